// The cartoon style's flat fill and ink at a pixel, over whatever lies behind (cartoon_compose.frag
// over Puff's own opaque scene, cartoon_compose_over.frag over a host's). s, the signed distance
// from the pixel's centre to the iso-line A = threshold (negative inside), gives the fill's coverage
// clamp(0.5 - s) and the ink's, clamp(width + 0.5 - s) minus the fill's: a band `width` pixels wide
// outside the iso-line, antialiased on both edges. The ink lies at the medium's depth: a nearer
// opaque surface hides it, as the depth test hides a nailboard's. Needs media/compose.glsl and
// media/cartoon.glsl first.
layout(binding = 5) uniform sampler2D uFill;    // cartoonFill: colour, opacity tier
layout(binding = 6) uniform sampler2D uField;   // x: A, y: linear depth, z: A unclipped
layout(binding = 7) uniform usampler2D uSeeds;  // the nearest iso-line point (cartoon_seed.frag)

struct CartoonCover {
  vec3 fill;    // the fill's colour (scene-linear)
  float alpha;  // its coverage times its opacity tier
  float ink;    // the ink's coverage
};

CartoonCover cartoonCover(ivec2 p) {
  const bool inside = texelFetch(uField, p, 0).r >= uStyle.x;
  const uvec4 seed = texelFetch(uSeeds, p, 0);
  const bool seeded = seed.w != kNoSeed;
  // The distance to the iso-line: to the line through the nearest seed along the iso-line there
  // (the seeds are at most a pixel apart, so that line is the iso-line to a few hundredths of a
  // pixel), not to the seed itself, which would thin the ink by the seeds' spacing.
  const vec2 depthAngle = unpackUnorm2x16(seed.z);
  const float angle = (depthAngle.y - 0.5) * 6.28318530718;
  const vec2 v = vec2(p) + 0.5 - vec2(uintBitsToFloat(seed.x), uintBitsToFloat(seed.y));
  const float d = seeded ? abs(dot(v, vec2(cos(angle), sin(angle)))) : 3.0e38;
  const float s = inside ? -d : d;
  float fillCover = clamp(0.5 - s, 0.0, 1.0);
  float ink = uStyle.w > 0.0 ? clamp(uStyle.w + 0.5 - s, 0.0, 1.0) - fillCover : 0.0;
  // What lies outside the iso-line (the ink, and the fill's antialiased rim) is at the medium's
  // depth: a nearer opaque surface hides it.
  if (!seeded || texelFetch(uOpaqueDepth, p, 0).r < depthAngle.x) {
    ink = 0.0;
    if (!inside) fillCover = 0.0;
  }
  // Where a surface cuts the medium (cartoonCut) the iso-line is that surface's edge: the ink fades
  // out, and the fill ends at the pixels the surface leaves it, unantialiased as the surface is.
  if (seeded) {
    const float cut = float(seed.w) / 65535.0;
    ink *= 1.0 - cut;
    fillCover = mix(fillCover, inside ? 1.0 : 0.0, cut);
  }
  const vec4 fill = texelFetch(uFill, p, 0);
  return CartoonCover(fill.rgb, fillCover * fill.a, ink);
}
