#version 450 core
// Where this pixel's eye ray enters (uBackFace 0) or leaves (uBackFace 1) the particle's shadow
// volume, written as the face's depth. Which face this is comes from the draw, not from
// gl_FrontFacing: both faces are the same triangles in the same order (shadow.vert).
// In the light frame (x along e1, y along e2: the right and up of the atlas cell the light sees, in
// puff diameters; lambda along D, world units) the volume is
//   (x, y) inside the puff's silhouette,   s * (d(x, y) + bias) <= lambda <= lambda1
// where d is the puff's depth-map offset: the volume starts behind the puff's own far side, and
// its edge follows the silhouette (a polar table of its radius, 32 directions, made from the
// baked distance map), so shadow edges on the ground and on other puffs are wavy.
// Depths are clamped to the near plane, never negative.
#include "common/frame.glsl"
#include "cel/particle.glsl"

uniform float uShadowBias;
uniform int uBackFace;  // 0: the entry face (depth where the ray enters), 1: the exit face

noperspective in vec3 vC0;
noperspective in vec3 vC1;
flat in vec4 vExtent;

// The farthest a silhouette reaches from the puff's centre, diameters: the radius table
// (particle.glsl, silhouetteRadius) marches no farther than the cell's content plus its margin
// (NailboardRenderer::setAtlas).
#define kReach (0.5 + uAtlasGeom.w / uAtlasScale.x)
flat in int vCell;  // the atlas cell the light sees

// The atlas's packed maps (NailboardRenderer::setAtlas; nailboard_fs.glsl): .z is the depth offset
// toward the cell's viewer, (z - 0.5) * uAtlasScale.y puff diameters.
layout(binding = 2) uniform sampler2D uPacked;

// Where the shadow starts at cell point `xy` (puff diameters, x right, y up in the cell): the puff's
// far side as its depth map gives it (the near side seen by the light, mirrored through the
// billboard plane; never in front of the plane).
float farSideAt(vec2 xy) {
  return max(0.0, (textureLod(uPacked, cellUv(vCell, xy), 0.0).z - 0.5) * uAtlasScale.y);
}

// Intersects [t0, t1] with the ray parameters where lo <= c0 + t * c1 <= hi.
void clipSlab(float c0, float c1, float lo, float hi, inout float t0, inout float t1) {
  if (abs(c1) < 1e-12) {
    if (c0 < lo || c0 > hi) t1 = -1.0;
    return;
  }
  float ta = (lo - c0) / c1, tb = (hi - c0) / c1;
  t0 = max(t0, min(ta, tb));
  t1 = min(t1, max(ta, tb));
}

// The silhouette's radius of the light's cell in the direction of `p` (diameters).
float radiusToward(vec2 p) { return silhouetteRadius(vCell, p); }

// How far (diameters, along the unit direction `along`) from the closest approach `pc` (inside the
// silhouette) the line leaves it: first the one step that is exact for a round silhouette (the
// chord of the disc of the radius toward that estimate), checked to 0.02 diameters; where the silhouette is not round
// enough for it (a long puff), bisection between the closest approach (inside) and the table's reach
// (outside), 9 steps: 1/512 of the search span.
float leaves(vec2 pc, vec2 along, float h, float r) {
  float u = sqrt(max(0.0, r * r - h * h));
  vec2 q = pc + u * along;
  float rq = radiusToward(q);
  float est = sqrt(max(0.0, rq * rq - h * h));
  vec2 e = pc + est * along;
  if (abs(length(e) - radiusToward(e)) < 0.02) return est;
  float lo = 0.0, hi = sqrt(max(0.0, kReach * kReach - h * h));
  for (int i = 0; i < 9; ++i) {
    float mid = 0.5 * (lo + hi);
    vec2 m = pc + mid * along;
    if (length(m) < radiusToward(m)) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

void main() {
  vec3 c0 = vC0, c1 = vC1;
  float s = vExtent.x;
  float t0 = 0.0, t1 = 1.0;
  clipSlab(c0.x, c1.x, -0.5, 0.5, t0, t1);
  clipSlab(c0.y, c1.y, -0.5, 0.5, t0, t1);
  clipSlab(c0.z, c1.z, 0.0, vExtent.y, t0, t1);
  if (t1 <= t0) discard;

  // Where the ray's shadow line P(t) = c0 + t c1 (light frame, diameters) crosses the silhouette:
  // first the disc whose radius is the silhouette's toward the line's closest approach, then the
  // entry and exit moved to the radius toward themselves (one fixed-point step).
  float speed2 = dot(c1.xy, c1.xy);
  float tIn, tOut;
  vec2 pc;
  if (speed2 < 1e-14) {  // looking along the light: the line is a point
    pc = c0.xy + t0 * c1.xy;
    if (length(pc) > radiusToward(pc)) discard;
    tIn = t0;
    tOut = t1;
  } else {
    float tc = -dot(c0.xy, c1.xy) / speed2;
    pc = c0.xy + tc * c1.xy;
    float h = length(pc);
    vec2 across = h > 1e-6 ? pc : vec2(-c1.y, c1.x);
    float r = radiusToward(across);
    if (h >= r) discard;
    float invSpeed = inversesqrt(speed2);
    vec2 along = c1.xy * invSpeed;
    tIn = tc - leaves(pc, -along, h, r) * invSpeed;
    tOut = tc + leaves(pc, along, h, r) * invSpeed;
    tIn = max(tIn, t0);
    tOut = min(tOut, t1);
    if (tOut <= tIn) discard;
  }
  // The start cap follows the puff's far side, read from the depth map where the ray meets it: the
  // cap bounds the entry when the ray runs along D and the exit when it runs against it, so the
  // map is read at that end and the crossing found again (a fixed point; three steps).
  vec2 probe = c0.xy + 0.5 * (tIn + tOut) * c1.xy;
  float tA = tIn, tB = tOut;
  for (int i = 0; i < 3; ++i) {
    tA = tIn;
    tB = tOut;
    clipSlab(c0.z, c1.z, s * (farSideAt(probe) + uShadowBias), vExtent.y, tA, tB);
    if (tB <= tA) break;
    probe = c0.xy + (c1.z >= 0.0 ? tA : tB) * c1.xy;
  }
  tIn = tA;
  tOut = tB;
  if (tOut <= tIn) discard;
  // The ray runs from the near plane (t = 0) to the far plane (t = 1): t is the linear depth, stored
  // in the frame's convention.
  gl_FragDepth = storeDepth(clamp(uBackFace != 0 ? tOut : tIn, 0.0, 1.0));
}
