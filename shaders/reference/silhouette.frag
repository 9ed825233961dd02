#version 450 core
// The cel reference's ink (silhouette.geom): the outline colour at the silhouette edge's depth (a
// hair behind it) on every pixel whose centre lies within uWidth pixels of the edge, except over the
// puff's own pixels.
#include "common/frame.glsl"

flat in uint gId;
flat in vec4 gSegment;  // the edge's ends, pixels of the target viewport
flat in vec2 gEndDist;  // their view-axis distances
uniform float uWidth;   // pixels of the (supersampled) target
layout(binding = 3) uniform usampler2D uIds;  // a copy of the frame's puff ids
uniform vec3 uInk;  // display value
layout(location = 0) out vec4 oColor;

void main() {
  vec2 p = gl_FragCoord.xy - uViewport.xy, a = gSegment.xy, ab = gSegment.zw - gSegment.xy;
  float t = clamp(dot(p - a, ab) / max(dot(ab, ab), 1e-12), 0.0, 1.0);
  if (distance(p, a + t * ab) > uWidth) discard;  // farther from the edge than the outline's width
  if (texelFetch(uIds, ivec2(gl_FragCoord.xy), 0).r == gId) discard;  // over the puff itself
  // The depth of the edge's point nearest the pixel (its reciprocal is linear on screen in a
  // perspective view), not of the box drawn around the edge, whose padding would stretch it.
  float dist = uDepthRange.w > 0.5 ? mix(gEndDist.x, gEndDist.y, t) : 1.0 / mix(1.0 / gEndDist.x, 1.0 / gEndDist.y, t);
  gl_FragDepth = linearDepth(dist) + 1e-5;
  oColor = vec4(srgbToLinear(clamp(uInk, 0.0, 1.0)), 1.0);  // the target holds scene-linear colour
}
