#version 450 core
// The cartoon style, pass 4: the flat fill and the ink (media/cartoon_cover.glsl) over Puff's own
// opaque scene, lit by the explosion lights and moved by the heat shimmer.
layout(binding = 0) uniform sampler2D uOpaqueColor;
#include "media/compose.glsl"
#include "media/lit.glsl"
#include "media/cartoon.glsl"
#include "media/cartoon_cover.glsl"

layout(location = 0) out vec4 outColor;

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy - uViewport.xy);
  vec2 shimmer;
  mediaTaps(p, shimmer);
  const vec3 scene = litAt(vec2(p) + shimmer * uShimmer.x, ivec2(uViewport.zw));
  const CartoonCover c = cartoonCover(p);
  outColor = vec4(scene * (1.0 - c.alpha - c.ink) + c.fill * c.alpha + uInk.rgb * c.ink, 1.0);
}
