#version 450 core
// Resolves the opaque pass's multisampled depth to one linear depth per pixel: the NEAREST of its
// samples, the same rule the layer's downsample uses (a blit would keep one sample of the
// driver's choosing, so edge pixels could read as background while their colour is half object).
#include "common/contract.glsl"
layout(binding = 0) uniform sampler2DMS uDepthMS;
layout(location = PUFF_LOC_RESOLVE_SAMPLES) uniform int uSamples;
layout(location = 0) out float outDepth;

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy);
  float nearest = 1.0;
  for (int i = 0; i < uSamples; ++i) nearest = min(nearest, texelFetch(uDepthMS, p, i).r);
  outDepth = nearest;
}
