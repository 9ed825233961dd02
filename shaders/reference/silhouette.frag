#version 450 core
// The cel reference's ink (silhouette.geom): the outline colour at the silhouette edge's depth (a
// hair behind it), except over the puff's own pixels.
#include "common/frame.glsl"

in float gDist;
flat in uint gId;
layout(binding = 3) uniform usampler2D uIds;  // a copy of the frame's puff ids
uniform vec3 uInk;  // display value
layout(location = 0) out vec4 oColor;

void main() {
  if (texelFetch(uIds, ivec2(gl_FragCoord.xy), 0).r == gId) discard;  // over the puff itself
  gl_FragDepth = linearDepth(gDist) + 1e-5;
  oColor = vec4(srgbToLinear(clamp(uInk, 0.0, 1.0)), 1.0);  // the target holds scene-linear colour
}
