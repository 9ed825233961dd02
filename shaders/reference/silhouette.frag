#version 450 core
// The cel reference's ink (silhouette.geom): the outline colour at the silhouette edge's depth, a
// hair behind it so the puff's own surface at the silhouette wins the tie.
#include "common/frame.glsl"

in float gDist;
uniform vec3 uInk;
layout(location = 0) out vec4 oColor;

void main() {
  gl_FragDepth = linearDepth(gDist) + 1e-5;
  oColor = vec4(uInk, 1.0);
}
