#version 450 core
// The cartoon style, pass 2: where the iso-line A = threshold crosses the segments from this pixel's
// centre to its four neighbours' (A linear between them), the nearest crossing: the distance field's
// seed. Sub-pixel, so the ink moves smoothly as the medium does.
#include "media/cartoon.glsl"

layout(binding = 6) uniform sampler2D uField;  // x: A, y: linear depth, z: A without the surfaces' clipping

// x, y: the point (pixels, float bits); z: packUnorm2x16(the medium's depth at its inside end, the
// iso-line's normal angle / 2 pi); w: how much an opaque surface cuts the medium there, 0 ..
// 65535 (cartoonCut), or kNoSeed.
layout(location = 0) out uvec4 outSeed;

float fieldAt(ivec2 q, ivec2 size) { return texelFetch(uField, clamp(q, ivec2(0), size - 1), 0).r; }

// A's gradient at pixel q by central differences (one-sided at the frame's edge).
vec2 gradientAt(ivec2 q, ivec2 size) {
  return vec2(fieldAt(q + ivec2(1, 0), size) - fieldAt(q - ivec2(1, 0), size),
              fieldAt(q + ivec2(0, 1), size) - fieldAt(q - ivec2(0, 1), size));
}

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy);
  const ivec2 size = textureSize(uField, 0);
  const float theta = uStyle.x;
  const vec3 here = texelFetch(uField, p, 0).rgb;
  const bool inside = here.r >= theta;
  const ivec2 steps[4] = ivec2[](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
  float best = 2.0;
  outSeed = uvec4(0u, 0u, 0u, kNoSeed);
  for (int i = 0; i < 4; ++i) {
    const ivec2 q = p + steps[i];
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;  // the frame's edge is no edge
    const vec3 there = texelFetch(uField, q, 0).rgb;
    if ((there.r >= theta) == inside) continue;
    const float t = clamp((here.r - theta) / (here.r - there.r), 0.0, 1.0);
    if (t >= best) continue;
    best = t;
    const vec2 point = vec2(p) + 0.5 + t * vec2(steps[i]);
    const float depth = inside ? here.g : there.g;
    // The iso-line's normal there: A's gradient at the two pixels, mixed as the crossing lies; the
    // segment's own direction where A is flat across it (cannot happen at a crossing, but be safe).
    vec2 g = mix(gradientAt(p, size), gradientAt(q, size), t);
    if (!(dot(g, g) > 0.0)) g = inside ? -vec2(steps[i]) : vec2(steps[i]);
    const float angle = atan(g.y, g.x) / 6.28318530718 + 0.5;  // [0, 1]
    outSeed = uvec4(floatBitsToUint(point.x), floatBitsToUint(point.y), packUnorm2x16(vec2(depth, angle)),
                    uint(round(cartoonCut(inside ? there.b : here.b) * 65535.0)));
  }
}
