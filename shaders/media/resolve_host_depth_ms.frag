#version 450 core
// A host's multisampled depth texture, in its convention, to one linear depth per pixel: the
// NEAREST of its samples (as resolve_depth.frag does for Puff's own opaque pass).
#include "media/host_depth.glsl"
layout(binding = 0) uniform sampler2DMS uHostDepth;
layout(location = PUFF_LOC_RESOLVE_SAMPLES) uniform int uSamples;
layout(location = 0) out float outDepth;

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy) + uOrigin;
  float nearest = 1.0;
  for (int i = 0; i < uSamples; ++i) nearest = min(nearest, linearFromStored(texelFetch(uHostDepth, p, i).r));
  outDepth = nearest;
}
