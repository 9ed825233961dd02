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
flat out float vTexelsPerPixel;  // level-0 atlas texels per screen pixel at the particle
flat out ivec4 vCell;
flat out vec4 vWeight;
flat out vec4 vMap[PUFF_VIEWS];        // billboard (x, y) -> cell (x, y): columns (m00, m10), (m01, m11)
flat out mat3 vNormalXf[PUFF_VIEWS];   // cell camera space -> camera (view) space

// Billboard (x, y) -> cell (x, y) as the columns (m00, m10), (m01, m11).
vec4 cellMap(int c, vec3 rP, vec3 uP) {
  vec3 right = cells[c].right.xyz, up = cells[c].up.xyz;
  return vec4(dot(rP, right), dot(rP, up), dot(uP, right), dot(uP, up));
}
mat3 cellAxes(int c) { return mat3(cells[c].right.xyz, cells[c].up.xyz, cells[c].dir.xyz); }

// The shadow map's caster pass (NailboardRenderer::drawShadowCasters, the light's frame bound):
// 1, with the eye's camera right and up (world), so an unoriented puff faces the light in
// lightFacingFrame. 0 in every other pass.
uniform int uCaster;
uniform vec3 uEyeRight;
uniform vec3 uEyeUp;

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
  uint index = uint(gl_VertexID) / 6u;
  vec2 corner = kCorners[gl_VertexID % 6];
  Particle p = unpackParticle(index);
  mat3 bb = uCaster == 1 ? lightFacingFrame(uInvView[2].xyz, uEyeRight, uEyeUp) : billboardFrame(p.position);
  mat3 puff = puffFrame(p, bb);
  mat3 puffT = transpose(puff);
  ivec4 cell;
  vec4 weight;
  selectViews(p, puffT * bb[2], cell, weight);
  vec3 rP = puffT * bb[0], uP = puffT * bb[1];
  mat3 toView = mat3(uView) * puff;
  vMap[0] = cellMap(cell.x, rP, uP);
  vNormalXf[0] = toView * cellAxes(cell.x);
#if PUFF_VIEWS == 4
  vMap[1] = cellMap(cell.y, rP, uP);
  vMap[2] = cellMap(cell.z, rP, uP);
  vMap[3] = cellMap(cell.w, rP, uP);
  vNormalXf[1] = toView * cellAxes(cell.y);
  vNormalXf[2] = toView * cellAxes(cell.z);
  vNormalXf[3] = toView * cellAxes(cell.w);
#endif
  vCell = cell;
  vWeight = weight;
  vSize = p.size;
  // The quad covers the whole cell (margin included) so the outline can reach past the silhouette.
  float halfCell = 0.5 * uAtlasGeom.z / uAtlasScale.x;  // cell half-width in puff diameters
  vPuff = corner * halfCell;
  vec3 world = p.position + p.size * (vPuff.x * bb[0] + vPuff.y * bb[1]);
  vec4 viewPos = uView * vec4(world, 1.0);
  vDist = -viewPos.z;
  vWorld = world;
  vId = index + 1u;
  // Pixels per world unit at the particle's distance (orthographic: everywhere the same).
  float centreDist = max(-(uView * vec4(p.position, 1.0)).z, uDepthRange.x);
  float pxPerUnit = 0.5 * uViewport.w * uProj[1][1] / (isOrthographic() ? 1.0 : centreDist);
  vTexelsPerPixel = uAtlasScale.x / max(1e-6, p.size * pxPerUnit);
  gl_Position = p.size > 0.0 ? uProj * viewPos : vec4(2.0, 2.0, 2.0, 1.0);
}
