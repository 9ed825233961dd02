#version 450 core
// The cartoon style, pass 3 (repeated): one jump-flooding step (Rong & Tan 2006). Each pixel keeps,
// of its own seed and the seeds `uStep` pixels away in the 8 directions, the one nearest its centre.
#include "media/cartoon.glsl"

layout(binding = 7) uniform usampler2D uSeeds;
layout(location = PUFF_LOC_FLOOD_STEP) uniform int uStep;

layout(location = 0) out uvec4 outSeed;

float seedDistance(uvec4 s, vec2 centre) {
  return s.w == kNoSeed ? 3.0e38 : distance(centre, vec2(uintBitsToFloat(s.x), uintBitsToFloat(s.y)));
}

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy);
  const ivec2 size = textureSize(uSeeds, 0);
  const vec2 centre = vec2(p) + 0.5;
  uvec4 best = texelFetch(uSeeds, p, 0);
  float bestDistance = seedDistance(best, centre);
  for (int y = -1; y <= 1; ++y) {
    for (int x = -1; x <= 1; ++x) {
      const ivec2 q = p + uStep * ivec2(x, y);
      if ((x == 0 && y == 0) || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      const uvec4 s = texelFetch(uSeeds, q, 0);
      const float d = seedDistance(s, centre);
      if (d < bestDistance) {
        bestDistance = d;
        best = s;
      }
    }
  }
  outSeed = best;
}
