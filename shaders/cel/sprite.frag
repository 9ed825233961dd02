#version 450 core
// The nailboards' fill-rate floor (sprite.vert): the colour map alpha-tested, and the quad plane's
// depth written as the nailboards write theirs (gl_FragDepth = storeDepth(linearDepth(distance))).
#include "common/frame.glsl"

in vec2 vUv;
in float vDist;
layout(binding = 3) uniform sampler2D uColor;
out vec4 fragColor;

void main() {
  vec4 c = texture(uColor, vUv);
  if (c.a < 0.5) discard;
  fragColor = c;
  gl_FragDepth = storeDepth(linearDepth(vDist));
}
