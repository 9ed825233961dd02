#version 450 core
// The cartoon style over a host's frame (HostLayers::composeOver with a CartoonCompose): the fill
// and the ink of cartoon_compose.frag, with the host's colour left in its framebuffer. With
// k = 1 - alpha - ink, the blend unit computes dst * (mul * k) + (add * k + fill * alpha + ink colour
// * ink) by dual-source blending (glBlendFunc(GL_ONE, GL_SRC1_COLOR)): cartoon_compose.frag's image
// without shimmer, without reading the host's colour. Alpha: (GL_ZERO, GL_ONE) keeps the host's.
#include "media/compose.glsl"
#include "media/cartoon.glsl"
#include "media/cartoon_cover.glsl"

layout(location = 0, index = 0) out vec4 outColor;
layout(location = 0, index = 1) out vec4 outFactor;

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy - uViewport.xy);
  vec3 mul, add;
  lightTerms(p, mul, add);
  const CartoonCover c = cartoonCover(p);
  const float k = 1.0 - c.alpha - c.ink;
  outColor = vec4(add * k + c.fill * c.alpha + uInk.rgb * c.ink, 0.0);
  outFactor = vec4(mul * k, 1.0);
}
