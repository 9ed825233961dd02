// What the nailboards compute once per particle (the views it shows, their turns, its size on
// screen): in the vertex stage for the quads (nailboard_vs.glsl), and per pixel in the deferred
// shading pass for the particle the visibility pre-pass left there (nailboard_fs.glsl,
// PUFF_DEFERRED). Needs cel/particle.glsl and cel/nailboard_io.glsl.

// Billboard (x, y) -> cell (x, y), as the columns (m00, m10), (m01, m11): the billboard's axes
// projected on the cell's, made the nearest rotation (or, for a cell seen from behind, reflection).
// A puff is a round lump, not a card: seen from a direction between the baked views, it shows
// about the silhouette of the nearest view, turned, at its own size, not foreshortened as a flat
// card would be. A view from behind mirrors the cell: the silhouette seen from -d is the one seen
// from d.
vec4 cellMap(int c, vec3 rP, vec3 uP) {
  vec3 right = cells[c].right.xyz, up = cells[c].up.xyz;
  vec4 m = vec4(dot(rP, right), dot(rP, up), dot(uP, right), dot(uP, up));
  // The nearest orthogonal 2 x 2 matrix: M plus (det > 0) or minus (det < 0) its cofactor matrix,
  // normalized; the larger of the two is the one of det's sign.
  vec4 turn = vec4(m.x + m.w, m.y - m.z, m.z - m.y, m.x + m.w);
  vec4 mirror = vec4(m.x - m.w, m.y + m.z, m.z + m.y, m.w - m.x);
  float t = dot(turn.xy, turn.xy), r = dot(mirror.xy, mirror.xy);
  return t >= r ? turn * inversesqrt(max(t, 1e-20)) : mirror * inversesqrt(max(r, 1e-20));
}

// A cell's camera-space normal (x, y in the cell, z toward its viewer) -> the billboard's frame,
// through the same turn as cellMap (its transpose: the inverse): the puff shows the shading the
// view baked, turned with its silhouette, its bulge toward the camera.
mat3 cellToBillboard(vec4 m) { return mat3(vec3(m.x, m.z, 0.0), vec3(m.y, m.w, 0.0), vec3(0.0, 0.0, 1.0)); }

#if PUFF_VIEWS == 4
// Oriented puffs at least this many pixels across (one diameter at the centre) take the hull, smaller
// ones the blend (cel::Style::hullFromPixels; 0: all take the hull).
uniform float uHullFromPixels;
#endif

// Sets the per-particle values (vId, vSize, vTint, vTexelsPerPixel, vCell, vWeight, vMap,
// vNormalXf and the hull's) for particle `index`, `p`, wearing billboard frame `bb` (world: right,
// up, normal toward the viewer). Returns the screen pixels one puff diameter covers at the particle.
float setUpParticle(uint index, Particle p, mat3 bb) {
  mat3 puff = puffFrame(p, bb);
  mat3 puffT = transpose(puff);
  ivec4 cell;
  vec4 weight;
  vec3 toward = puffT * bb[2];  // toward the camera (the light, drawing casters), puff space
  selectViews(p, toward, cell, weight);
  vec3 rP = puffT * bb[0], uP = puffT * bb[1];
  mat3 toView = mat3(uView) * bb;
  vMap[0] = cellMap(cell.x, rP, uP);
  vNormalXf[0] = toView * cellToBillboard(vMap[0]);
#if PUFF_VIEWS == 4
  vMap[1] = cellMap(cell.y, rP, uP);
  vMap[2] = cellMap(cell.z, rP, uP);
  vMap[3] = cellMap(cell.w, rP, uP);
  vNormalXf[1] = toView * cellToBillboard(vMap[1]);
  vNormalXf[2] = toView * cellToBillboard(vMap[2]);
  vNormalXf[3] = toView * cellToBillboard(vMap[3]);
#ifndef PUFF_DEFERRED
  // (The deferred pass shades the blend only: the hull is drawn forward, nailboards.h.)
  vHullBehind = 0;
  for (int k = 0; k < 4; ++k) {
    if (uAtlasLayout.w != 1 && dot(cells[cell[k]].dir.xyz, toward) < 0.0) vHullBehind = 1;
  }
  vBillboardPuff = mat3(rP, uP, toward);
  vPuffToView = mat3(uView) * puff;
#endif
#endif
  vCell = cell;
  vWeight = weight;
  vSize = p.size;
  vTint = p.tint;
  vId = index + 1u;
  // Pixels per world unit at the particle's distance (orthographic: everywhere the same).
  // (precise: the hull's program and the blend's split the particles by it, and must agree.)
  precise float centreDist = max(-(uView * vec4(p.position, 1.0)).z, uDepthRange.x);
  precise float pxPerUnit = 0.5 * uViewport.w * uProj[1][1] / (isOrthographic() ? 1.0 : centreDist);
  precise float pxPerDiameter = max(1e-6, p.size * pxPerUnit);
  vTexelsPerPixel = uAtlasScale.x / pxPerDiameter;
#if PUFF_VIEWS == 4
  // (Read by the hull's fragment stage, and by the vertex stage to split the particles between the
  // hull's program and the blend's.)
  vHull = p.oriented && uAtlasLayout.y > 1 && pxPerDiameter >= uHullFromPixels ? 1 : 0;
#endif
  return pxPerDiameter;
}
