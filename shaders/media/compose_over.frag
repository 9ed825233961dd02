#version 450 core
// Composition over a host's frame (media/layers.h, Layers::composeOver): the host's colour stays in
// its framebuffer and the blend unit computes dst * (mul * T) + (add * T + M) with dual-source
// blending (glBlendFunc(GL_ONE, GL_SRC1_COLOR)): the same image as compose.frag without shimmer,
// without reading the host's colour. Alpha: (GL_ZERO, GL_ONE) keeps the host's.
#include "media/compose.glsl"

layout(location = 0, index = 0) out vec4 outColor;
layout(location = 0, index = 1) out vec4 outFactor;

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy - uViewport.xy);
  vec2 shimmer;
  const vec4 media = upsampledMedia(p, shimmer);
  vec3 mul, add;
  lightTerms(p, mul, add);
  outColor = vec4(add * media.a + media.rgb, 0.0);
  outFactor = vec4(mul * media.a, 1.0);
}
