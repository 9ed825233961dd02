// The opaque scene with the explosions' light (compose.glsl's lightTerms), for the passes that
// read Puff's own opaque colour: compose.frag and cartoon_compose.frag. Needs uOpaqueColor.
vec3 lit(ivec2 p) {
  vec3 mul, add;
  lightTerms(p, mul, add);
  return texelFetch(uOpaqueColor, p, 0).rgb * mul + add;
}

// The opaque scene lit, at a continuous pixel position (pixel centres at whole numbers): the
// bilinear mix of the four pixels around it, clamped to the image's edge. Heat shimmer moves the
// scene by fractions of a pixel; snapping them to whole pixels made the image jump in 1 px steps.
vec3 litAt(vec2 pos, ivec2 full) {
  pos = clamp(pos, vec2(0.0), vec2(full - 1));
  const ivec2 i0 = ivec2(floor(pos));
  const ivec2 i1 = min(i0 + 1, full - 1);
  const vec2 f = pos - vec2(i0);
  if (f == vec2(0.0)) return lit(i0);  // no offset: the pixel itself, exactly
  return mix(mix(lit(i0), lit(ivec2(i1.x, i0.y)), f.x), mix(lit(ivec2(i0.x, i1.y)), lit(i1), f.x), f.y);
}
