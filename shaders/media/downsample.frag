#version 450 core
// The media layer's opaque depth: the NEAREST linear depth in each layer texel's footprint of
// uFactor x uFactor full-resolution pixels, so a thin object in front keeps its own texels.
#include "common/contract.glsl"
layout(binding = 0) uniform sampler2D uDepthFull;  // linear depth, full resolution
layout(location = PUFF_LOC_DOWNSAMPLE_FACTOR) uniform int uFactor;          // 1, 2, 4 or 8
layout(location = 0) out float outDepth;

void main() {
  const ivec2 size = textureSize(uDepthFull, 0);
  const ivec2 base = ivec2(gl_FragCoord.xy) * uFactor;
  float nearest = 1.0;
  for (int y = 0; y < uFactor; ++y)
    for (int x = 0; x < uFactor; ++x)
      nearest = min(nearest, texelFetch(uDepthFull, min(base + ivec2(x, y), size - 1), 0).r);
  outDepth = nearest;
}
