#version 450 core
// Composition (Umenhoffer §4): out = opaque(x + shimmer) * T + M, the media layer upsampled
// depth-aware, with the explosions' light on the opaque surfaces (volumetric-explosion-effects).
layout(binding = 0) uniform sampler2D uOpaqueColor;
#include "media/compose.glsl"
#include "media/lit.glsl"

layout(location = 0) out vec4 outColor;

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy - uViewport.xy);
  vec2 shimmer;
  const vec4 media = upsampledMedia(p, shimmer);
  outColor = vec4(litAt(vec2(p) + shimmer * uShimmer.x, ivec2(uViewport.zw)) * media.a + media.rgb, 1.0);
}
