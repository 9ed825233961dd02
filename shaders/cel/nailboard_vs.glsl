// Nailboards (McGuire & Fein §4.1-4.2): each particle becomes a quad here, by vertex pulling from
// the 16-byte records (no per-vertex data leaves the CPU). 6 vertices per particle. Compiled with
// PUFF_VIEWS = 1 (one baked view per variation: nailboard.vert) or 4 (a multi-view atlas, the
// four nearest views blended: nailboard_views.vert), so every array index is a constant.
#include "common/frame.glsl"
#include "cel/particle.glsl"

out vec2 vPuff;     // position on the billboard, puff diameters from the centre (x right, y up)
out float vDist;    // camera-space distance along the view axis of the billboard plane here
out vec3 vWorld;    // world-space point of the billboard plane here (shadow-map receivers)
flat out uint vId;  // particle index + 1: the caster id of the shadow map (cel/shadow_map.glsl)
flat out float vSize;
flat out vec3 vTint;  // display multiplier of Eq. 2's C
flat out float vTexelsPerPixel;  // level-0 atlas texels per screen pixel at the particle
flat out ivec4 vCell;
flat out vec4 vWeight;
flat out vec4 vMap[PUFF_VIEWS];        // billboard (x, y) -> cell (x, y): columns (m00, m10), (m01, m11)
flat out mat3 vNormalXf[PUFF_VIEWS];   // cell camera space -> camera (view) space
#if PUFF_VIEWS == 4
// An oriented puff's surface is found by marching its eye ray through the hull of its four views
// (nailboard_fs.glsl, hullMarch): the billboard's right, up and normal (toward the eye) in puff
// space, and puff space -> camera space.
flat out int vHull;
flat out int vHullBehind;  // a hemi-oct atlas seen from behind: some of the four cells stand for back views
// The views nearest the billboard's right, up and the two diagonals between (every 45 degrees
// across the eye ray): their silhouettes bound the puff's depth, and together the width the four
// nearest views leave open (views that straddle the eye ray bound a lens wider than the puff).
flat out ivec4 vCellAcross;
flat out mat3 vBillboardPuff;
flat out mat3 vPuffToView;
#endif

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

// The shadow map's caster pass (NailboardRenderer::drawShadowCasters, the light's frame bound):
// 1, with the eye's camera right and up (world), so an unoriented puff faces the light in
// lightFacingFrame. 0 in every other pass.
uniform int uCaster;
uniform vec3 uEyeRight;
uniform vec3 uEyeUp;
// The fragment stage's outline switch and width (pixels): a small puff's quad grows to hold its band.
uniform int uOutlines;
uniform float uOutlineWidth;

#if PUFF_VIEWS == 4
// The atlas cell whose view is nearest puff-space direction `d` (or its opposite, on a hemi-oct
// atlas): seen across the eye ray, its silhouette bounds the puff's depth.
int nearestView(Particle p, vec3 d) {
  ivec4 cell;
  vec4 weight;
  selectViews(p, d, cell, weight);
  int best = 0;
  for (int k = 1; k < 4; ++k) {
    if (weight[k] > weight[best]) best = k;
  }
  return cell[best];
}
#endif

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
  uint index = uint(gl_VertexID) / 6u;
  vec2 corner = kCorners[gl_VertexID % 6];
  Particle p = unpackParticle(index);
  mat3 bb = uCaster == 1 ? lightFacingFrame(uInvView[2].xyz, uEyeRight, uEyeUp) : billboardFrame(p);
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
  vHull = p.oriented && uAtlasLayout.y > 1 ? 1 : 0;  // (read only by the hull's fragment stage)
  vCellAcross = ivec4(nearestView(p, rP), nearestView(p, uP), nearestView(p, normalize(rP + uP)),
                      nearestView(p, normalize(rP - uP)));
  vHullBehind = 0;
  for (int k = 0; k < 4; ++k) {
    if (uAtlasLayout.w != 1 && dot(cells[cell[k]].dir.xyz, toward) < 0.0) vHullBehind = 1;
  }
  vBillboardPuff = mat3(rP, uP, toward);
  vPuffToView = mat3(uView) * puff;
#endif
  vCell = cell;
  vWeight = weight;
  vSize = p.size;
  vTint = p.tint;
  // Pixels per world unit at the particle's distance (orthographic: everywhere the same).
  float centreDist = max(-(uView * vec4(p.position, 1.0)).z, uDepthRange.x);
  float pxPerUnit = 0.5 * uViewport.w * uProj[1][1] / (isOrthographic() ? 1.0 : centreDist);
  float pxPerDiameter = max(1e-6, p.size * pxPerUnit);
  vTexelsPerPixel = uAtlasScale.x / pxPerDiameter;
  // The quad covers the whole cell (margin included) so the outline can reach past the silhouette;
  // a puff so small that its band and antialiased edge (outline width + 1.5 pixels) reach past the
  // cell gets a quad that holds them: the silhouette lies within half a diameter of the centre.
  float halfCell = 0.5 * uAtlasGeom.z / uAtlasScale.x;  // cell half-width in puff diameters
  float band = (uOutlines == 1 ? max(0.0, uOutlineWidth) : 0.0) + 1.5;
  vPuff = corner * max(halfCell, 0.5 + band / pxPerDiameter);
  vec3 world = p.position + p.size * (vPuff.x * bb[0] + vPuff.y * bb[1]);
  vec4 viewPos = uView * vec4(world, 1.0);
  vDist = -viewPos.z;
  vWorld = world;
  vId = index + 1u;
  gl_Position = p.size > 0.0 ? uProj * viewPos : vec4(2.0, 2.0, 2.0, 1.0);
}
