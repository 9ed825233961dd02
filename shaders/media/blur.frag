#version 450 core
// Motion blur (Umenhoffer §4: the new frame fades into the previous ones): the weighted sum of
// the last frames, weights persistence^age normalized to 1 on the host.
#include "common/contract.glsl"
layout(binding = 0) uniform sampler2D uHistory[PUFF_MAX_BLUR_FRAMES];
layout(location = PUFF_LOC_BLUR_COUNT) uniform int uCount;
layout(location = PUFF_LOC_BLUR_WEIGHTS) uniform float uWeights[PUFF_MAX_BLUR_FRAMES];
layout(location = PUFF_LOC_BLUR_VIEWPORT) uniform vec4 uViewport;  // x, y of the output viewport
layout(location = 0) out vec4 outColor;

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy - uViewport.xy);
  vec3 sum = vec3(0.0);
  // Scene-linear frames (not clamped: a shutter integrates light, fire above 1 included); the view
  // transform comes after (docs/colour.md).
  for (int i = 0; i < uCount; ++i) sum += uWeights[i] * max(texelFetch(uHistory[i], p, 0).rgb, vec3(0.0));
  outColor = vec4(sum, 1.0);
}
