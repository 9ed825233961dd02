// Nailboard shading (McGuire & Fein Eq. 2) with a per-pixel depth offset (§4.2) and outlines drawn
// from the baked signed distance to the silhouette, so their width is a run-time choice and both
// edges are antialiased (alpha-to-coverage when the target is multisampled).
// Compiled with PUFF_CASTER for the shadow map's caster pass (drawn from the light: depth and id only),
// and with PUFF_HULL (four views, nailboard_hull*.frag) to draw oriented puffs by marching the hull of
// their views (style.tumble "hull"); without it, oriented puffs blend four views and the program
// carries none of the hull's code (its registers would slow every puff drawn with it).
// Every other variant is compiled once per shade pass, PUFF_SHADE_PASS (PUFF_PASS_LIT, _SHADOWED or
// _DEPTH_ONLY, common/contract.glsl): a pass carries none of the code it does not run, since a
// uniform's branch still costs what it skips on a rasterizer that runs both sides under a mask.
// The lit and shadowed passes shade each pixel once (cel::LitShading, nailboards.h): PUFF_VISIBILITY
// compiles the pre-pass (the quads' depth and particle id into Puff's own target), PUFF_DEFERRED the
// screen pass that shades each pixel's particles from it (PUFF_DEFERRED_MS: multisampled), the
// quads' varyings computed per pixel (nailboard_setup.glsl).
#include "common/frame.glsl"
#include "cel/particle.glsl"
#include "cel/shadow_map.glsl"

#include "cel/nailboard_io.glsl"
#ifdef PUFF_DEFERRED
#include "cel/nailboard_setup.glsl"
#endif

// Two reads per pixel, as in the paper: normal x, y (z rebuilt), depth offset and distance to the
// silhouette packed by NailboardRenderer::setAtlas; and the colour.
layout(binding = 2) uniform sampler2D uPacked;
layout(binding = 3) uniform sampler2D uColor;  // scene-linear (an sRGB texture decodes the atlas's display values)

uniform int uShading;       // 1: q(N.L); 0: flat
uniform vec3 uOutlineColor;   // display value
uniform int uMultisample;   // 1: alpha-to-coverage resolves the edge; 0: hard edge at half coverage

#if defined(PUFF_DEFERRED) && defined(PUFF_HULL)
#error "the tumbling hull is drawn forward: no deferred variant"
#endif
#if !defined(PUFF_CASTER) && !defined(PUFF_SHADE_PASS)
#error "a nailboard program that is not a caster names its PUFF_SHADE_PASS"
#endif
#ifdef PUFF_CASTER
uniform float uShadowBias;  // diameters past the puff's far side where its shadow starts
layout(location = 0) out uint oId;
#elif defined(PUFF_VISIBILITY)
// The visibility pre-pass (a depth-only pass into Puff's own target): the nearest particle's id and
// the depth it stores, per pixel, for the deferred shading pass.
layout(location = 0) out uvec2 oVisible;
#else
out vec4 fragColor;
#endif

// Samples per pixel of the target (multisampled: the visibility pre-pass's sample mask, the
// deferred pass's loop).
uniform int uSamples;

#ifdef PUFF_DEFERRED
// The pixel's clip-space x, y (cel/screen_rect.vert): from it, not from gl_FragCoord, whose y runs
// down the clip space's under glClipControl(GL_UPPER_LEFT, ...).
in vec2 vScreenNdc;
// The visibility pre-pass's target: x the particle id (0: none), y the bits of the depth stored.
#ifdef PUFF_DEFERRED_MS
layout(binding = 8) uniform usampler2DMS uVisible;
#else
layout(binding = 8) uniform usampler2D uVisible;
#endif

// The varyings the vertex stage would have given the nailboard of particle `id` at this pixel: its
// per-particle values (setUpParticle), and where the pixel's eye ray meets its billboard plane.
void loadVarying(uint id) {
  Particle p = unpackParticle(id - 1u);
  mat3 bb = billboardFrame(p);
  setUpParticle(id - 1u, p, bb);
  vec4 onRay = uInvViewProj * vec4(vScreenNdc, 0.5, 1.0);
  vec3 origin = onRay.xyz / onRay.w;
  vec3 dir = isOrthographic() ? -uInvView[2].xyz : origin - uCameraWorld.xyz;
  vec3 world = origin + dir * (dot(p.position - origin, bb[2]) / dot(dir, bb[2]));
  vPuff = vec2(dot(world - p.position, bb[0]), dot(world - p.position, bb[1])) / p.size;
  vWorld = world;
  vDist = -(uView * vec4(world, 1.0)).z;
}
#endif

#ifdef PUFF_HULL
// The back map (puff/core/atlas.h), level 0 only: where each ray through a texel last leaves the puff;
// 0, no bound (an atlas without one reads the renderer's texel of 0).
layout(binding = 4) uniform sampler2D uBack;

// An oriented puff between its baked views. Each view's maps bound the puff: it lies
// inside the view's silhouette swept along the view's direction (the distance map), and behind the
// view's front surface (the depth map). The puff lies inside the intersection of its views' bounds
// and its unit sphere (radius half a diameter): a depth hull, close to the puff itself where the
// views are near each other. The views: the four nearest the eye's direction (silhouette and front
// surface), and the four nearest the directions across the eye ray every 45 degrees (silhouette:
// they bound the depth, and the width of the lens that four near views straddling the ray leave;
// with two, right and up only, coverage IoU over the tumble sweep is up to 0.008 lower and outline
// IoU up to 0.08). The eye ray is marched through that hull. Each bound
// gives a distance (the silhouette's, or the height over the front surface times the surface normal's z:
// the distance to its tangent plane), and the largest is about the distance to the hull: steps of
// that size do not pass through it (sphere tracing). The ray hits where it reaches 0; a ray that
// misses passes the hull at its least distance, the ink band's distance to the silhouette.
//
// A hemi-oct atlas seen from behind has no view of the side the eye sees: its cells give exact
// bounds (silhouette, and their front surface on the far side), which decide coverage and ink;
// the surface drawn is their front reflected through the cell plane (side -1), an assumption that
// only places the depth and shading, after the exact hull is hit.
struct HullView {
  int cell;
  float side;           // +1 seen from its own side, -1 from behind (a hemi-oct back)
  vec3 right, up, dir;  // puff space; dir toward the baked view's viewer
  float across;         // the sine between the eye ray and dir: how fast the ray crosses the view
};
const int kHullViews = 8;
HullView hullViews[kHullViews];

struct HullBound {
  float exact;    // > 0: outside what the view's maps bound (about the distance, diameters)
  float wallDist; // the swept silhouette's part of it (> 0: outside the wall)
  float assumed;  // with a view from behind, also outside its reflected front
  bool wall;      // `exact` is the silhouette's (the swept silhouette's wall), not the front surface's
  vec4 texel;     // the packed texel read (filtered)
  vec2 uv;
};

// The bound of view k at puff-space point `pt`.
HullBound hullBound(int k, vec3 pt, float lod, bool fromTable, float trusted) {
  HullView v = hullViews[k];
  HullBound b;
  vec2 local = vec2(dot(pt, v.right), dot(pt, v.up));
  b.uv = cellUv(v.cell, local);
  bool inside = insideCell(local, lod);
  b.texel = inside ? textureLod(uPacked, b.uv, lod) : vec4(0.5, 0.5, 0.5, 1.0);
  float range = uAtlasScale.z;
  float dist = (b.texel.w - 0.5) * 2.0 * range;  // level-0 texels, > 0 outside the silhouette
  // Past the map's range (or where it is not trusted) the radius table's star-shaped hull holds the
  // silhouette: the distance to it is at most the distance to the silhouette, and is not cut off at
  // the range, so a ray far from the puff takes long steps.
  if (dist >= trusted) dist = max((length(local) - silhouetteRadius(v.cell, local)) * uAtlasScale.x, fromTable ? trusted : dist);
  b.exact = dist / uAtlasScale.x;
  b.wallDist = b.exact;
  b.assumed = b.exact;
  b.wall = true;
  if (dist <= 0.0 && k < 4) {
    // The front surface's height is the largest of the four level-0 texels around the point that
    // lie inside the silhouette (outside, no depth is baked): a filtered read across an occluding
    // edge, or a coarse mip's, would cut away the nearer lump (a texel astride an occluding edge
    // holds the mean of the near and the far lump; the largest of four holds the near one). Less
    // what the map cannot tell: a step of its 8 bits. (A texel and a half more draws the puffs up to
    // a pixel large where the nearest views bound them, and their ink thin: outline IoU 0.02-0.05
    // lower over the tumble sweep, coverage no better.)
    vec4 heights = textureGather(uPacked, b.uv, 2);
    vec4 outside = step(0.5 + 0.5 / 255.0, textureGather(uPacked, b.uv, 3));
    heights = mix(heights, vec4(-1.0), outside);
    float top = max(max(heights.x, heights.y), max(heights.z, heights.w));
    if (top >= 0.0) {
      float front = (top - 0.5) * uAtlasScale.y + uAtlasScale.y / 255.0;
      vec2 n = b.texel.xy * 2.0 - 1.0;
      float slope = max(sqrt(max(0.0, 1.0 - dot(n, n))), 0.1);
      float h = dot(pt, v.dir);
      float above = h - front;
      float depthBound = above > 0.0 ? above * slope : above;
      b.wall = b.exact >= depthBound;
      b.exact = max(b.exact, depthBound);
      // The far side (where each ray last leaves the puff), where the four texels around the point
      // all hold one (inside the silhouette): the farthest of the four, less a step of its 8 bits. A
      // point beyond it lies outside, about the height under it times the far side's normal z away;
      // no map holds that normal, so a tenth of the height is taken (the front's least slope): short
      // steps, that never pass the far side.
      // (The slope of the four texels overshoots where the far side curves: oct 3x3's worst pose
      // 0.954 with it, against 0.962 without the back map and 0.962 with a tenth.)
      vec4 backs = textureGather(uBack, b.uv, 0);
      float least = min(min(backs.x, backs.y), min(backs.z, backs.w));
      if (least > 0.0) {
        float below = (least - 0.5) * uAtlasScale.y - uAtlasScale.y / 255.0 - h;
        float backBound = below > 0.0 ? 0.1 * below : below;
        b.wall = b.wall && b.exact >= backBound;
        b.exact = max(b.exact, backBound);
      }
      float reflected = -h - front;
      b.assumed = v.side > 0.0 ? b.exact : max(b.exact, reflected > 0.0 ? reflected * slope : reflected);
    }
  }
  return b;
}

struct HullHit {
  bool hit;
  bool behind;    // seen from behind on a hemi-oct atlas: the surface is an assumption (shaded as blended)
  float t;        // along the ray toward the eye, diameters from the billboard plane
  float nearest;  // a miss: least distance to the hull (diameters)
  float deepest;  // a hit: how far inside the hull the ray reaches (<= 0, diameters; probed to 2 px)
  vec3 normal;    // a hit: camera space
  vec3 color;     // a hit: scene-linear
};

// Every view's bound at `pt`, and the hull's: x exact, y with the reflected fronts assumed, z the step
// the march may take along the eye ray from `pt` (> 0 exactly where x is). `wall`: the exact bound
// that decides is a silhouette's (or the sphere's), not a front surface's.
// The step: each bound is about a distance, so the ray stays outside for x (sphere tracing). A swept
// silhouette's is measured across its view's direction, and the ray nears that wall only as fast as
// it crosses the direction (`across`, the sine between them): it stays farther than `keep` from it
// for its distance less `keep` over that sine, for a view near the eye's direction many times x.
// (`keep`: the least distance the march must see to within the step's own error, the ink's reach.)
vec3 hullAt(vec3 pt, float lod, bool fromTable, float trusted, float keep, out HullBound b[kHullViews],
            out bool wall) {
  vec2 f = vec2(length(pt) - 0.5);
  float step = f.x;
  wall = true;
  for (int k = 0; k < kHullViews; ++k) {
    b[k] = hullBound(k, pt, lod, fromTable, trusted);
    if (b[k].exact > f.x) wall = b[k].wall;
    f = max(f, vec2(b[k].exact, b[k].assumed));
    if (b[k].wallDist > keep) step = max(step, (b[k].wallDist - keep) / hullViews[k].across);
  }
  return vec3(f, max(step, f.x));
}

// Whether the eye ray through `origin` (puff space, on the billboard plane) hits the hull: the march
// below, without its probes.
bool hullHits(vec3 origin, float eps, float lod, bool fromTable, float trusted) {
  float r2 = dot(origin, origin);
  if (r2 >= 0.25) return false;
  vec3 ray = vBillboardPuff[2];
  float tMax = sqrt(0.25 - r2);
  HullBound b[kHullViews];
  bool wall;
  float t = tMax;
  for (int i = 0; i < 64; ++i) {
    vec3 f = hullAt(origin + t * ray, lod, fromTable, trusted, 0.0, b, wall);
    if (f.x <= 0.0) return true;
    t -= max(f.z, eps);
    if (t < -tMax) break;
  }
  return false;
}

// The views' frames for this fragment (hullViews); true when one of them stands for the view from
// behind.
bool setUpHullViews() {
  bool behind = false;
  for (int k = 0; k < kHullViews; ++k) {
    HullView v;
    v.cell = k < 4 ? vCell[k] : vCellAcross[k - 4];
    v.right = cells[v.cell].right.xyz;
    v.up = cells[v.cell].up.xyz;
    v.dir = cells[v.cell].dir.xyz;
    // A hemi-oct cell whose viewer is on the far side stands for the view from behind.
    // (The views across the ray bound only: their own sides.)
    v.side = k < 4 && uAtlasLayout.w != 1 && dot(v.dir, vBillboardPuff[2]) < 0.0 ? -1.0 : 1.0;
    v.across = max(length(cross(v.dir, vBillboardPuff[2])), 1e-3);
    hullViews[k] = v;
    behind = behind || v.side < 0.0;
  }
  return behind;
}

// The exact hull along the eye ray from the sphere's far side (t = tMax) toward the eye: the first
// point inside it (h.hit, t, f its bounds there, b the views' bounds, throughWall whether it entered
// through a silhouette's wall), or for a ray that misses its least distance (h.nearest, at
// tNearest).
void marchExact(vec3 origin, float tMax, float eps, float lod, bool fromTable, float trusted, float keep,
                inout HullHit h, out float t, out vec2 f, out bool throughWall, out float tNearest,
                out HullBound b[kHullViews]) {
  vec3 ray = vBillboardPuff[2];
  t = tMax;
  bool wall = true;
  throughWall = true;
  tNearest = t;
  for (int i = 0; i < 64; ++i) {
    vec3 g = hullAt(origin + t * ray, lod, fromTable, trusted, keep, b, wall);
    f = g.xy;
    if (i == 0 || f.x < h.nearest) tNearest = t;
    h.nearest = i == 0 ? f.x : min(h.nearest, f.x);
    if (f.x <= 0.0) {
      h.hit = true;
      break;
    }
    throughWall = wall;
    t -= max(g.z, eps);
    if (t < -tMax) break;
  }
}

// A miss's distance to the hull near the ink's outer edge, measured on the screen: the eye rays
// through the billboard plane stepped toward the hull hit it from some distance on, found by
// bisection along two directions (down the distance's gradient, and toward the puff's centre,
// where the gradient misleads: a bay), the nearer kept. `at`: the ray's closest approach;
// `nearest`: the bounds' estimate there; `ink`: the ink's width (diameters).
float screenDistance(vec3 at, float nearest, float ink, float pixel, float eps, float lod, bool fromTable,
                     float trusted) {
  float delta = 0.5 * pixel;
  HullBound g[kHullViews];
  bool gw;
  vec2 grad = vec2(hullAt(at + delta * vBillboardPuff[0], lod, fromTable, trusted, 0.0, g, gw).x,
                   hullAt(at + delta * vBillboardPuff[1], lod, fromTable, trusted, 0.0, g, gw).x) -
              nearest;
  vec2 towards[2] = vec2[2](dot(grad, grad) > 1e-12 ? -normalize(grad) : vec2(0.0),
                            dot(vPuff, vPuff) > 1e-12 ? -normalize(vPuff) : vec2(0.0));
  // What is drawn depends on the distance only within half a pixel of the ink's edges (the
  // antialiased edges; between them the pixel is ink whatever the distance): the bisection stops
  // once its interval lies between them, or is a quarter of a pixel wide.
  float solid = ink - 0.5 * pixel;  // nearer than this (and over half a pixel out): ink
  float best = -1.0;
  for (int k = 0; k < 2; ++k) {
    vec2 toward = towards[k];
    if (dot(toward, toward) == 0.0 || (best >= 0.0 && best <= solid)) continue;
    if (k == 1 && dot(towards[0], toward) > 0.95) continue;
    float lo = 0.0, hi = ink + 0.5 * pixel;
    if (best >= 0.0) hi = min(hi, best);
    if (!hullHits(vBillboardPuff * vec3(vPuff + hi * toward, 0.0), eps, lod, fromTable, trusted)) continue;
    for (int i = 0; i < 4; ++i) {
      if ((lo >= 0.5 * pixel && hi <= solid) || hi - lo <= 0.25 * pixel) break;
      // The first split at the inner edge of the outer antialiased band, where most pixels of
      // the ring are decided.
      float mid = i == 0 && solid > lo && solid < hi ? solid : 0.5 * (lo + hi);
      if (hullHits(vBillboardPuff * vec3(vPuff + mid * toward, 0.0), eps, lod, fromTable, trusted)) {
        hi = mid;
      } else {
        lo = mid;
      }
    }
    best = max(0.5 * (lo + hi), 1e-4);
  }
  return best >= 0.0 ? best : max(nearest, ink + 1.5 * pixel);
}

// How deep a ray that entered at s = t through a silhouette's wall (bounds f there) reaches into
// the hull: on into it until 2 px deep, or out (<= 0, diameters).
float wallDepth(vec3 origin, float t, vec2 f, float tMax, float pixel, float eps, float lod, bool fromTable,
                float trusted) {
  vec3 ray = vBillboardPuff[2];
  float deepest = f.x;
  float s = t;
  HullBound probe[kHullViews];
  bool wall;
  for (int i = 0; i < 8 && deepest > -2.0 * pixel; ++i) {
    s -= max(-f.x, eps);
    if (s < -tMax) break;
    f = hullAt(origin + s * ray, lod, fromTable, trusted, 0.0, probe, wall).xy;
    if (f.x > 0.0) break;
    deepest = min(deepest, f.x);
  }
  return deepest;
}

// Seen from behind, the surface drawn: on from the hit at `t` to the first point behind every
// reflected front too (t and b move there; if the ray finds none, the hit itself).
void surfaceBehind(vec3 origin, float tMax, float eps, float lod, bool fromTable, float trusted, inout float t,
                   inout HullBound b[kHullViews]) {
  vec3 ray = vBillboardPuff[2];
  float s = t;
  HullBound at[kHullViews];
  bool wall;
  for (int i = 0; i < 32; ++i) {
    vec2 f = hullAt(origin + s * ray, lod, fromTable, trusted, 0.0, at, wall).xy;
    if (f.y <= 0.0) {
      t = s;
      b = at;
      break;
    }
    s -= max(f.y, eps);
    if (s < -tMax) break;
  }
}

// The hit's normal and colour: the views that see it (it lies on their front surface, not behind
// it) see the same point, their normals and colours blended as the views are.
void shadeHit(vec3 pt, float pixel, float lod, HullBound b[kHullViews], inout HullHit h) {
  vec3 n = vec3(0.0), color = vec3(0.0);
  float total = 0.0;
  for (int k = 0; k < 4; ++k) {
    HullView v = hullViews[k];
    vec4 texel = b[k].texel;
    vec2 nxy = texel.xy * 2.0 - 1.0;
    float nz = sqrt(max(0.0, 1.0 - dot(nxy, nxy)));
    // How far the hit lies off this view's surface along its direction: a view that sees another
    // lump there (the hit lies behind it) or none at all (in front of it) fades out.
    // (In pixels or texels, whichever is larger: a magnified map is as exact as its texels.)
    float off = abs((texel.z - 0.5) * uAtlasScale.y - v.side * dot(pt, v.dir)) * max(nz, 0.25) /
                max(pixel, 1.0 / uAtlasScale.x);
    // Near a view's silhouette its filtered normal is mixed with the empty texels outside (no
    // normal): that view's rim may cross the middle of the puff the eye sees. It fades out there.
    float rim = (0.5 - texel.w) * 2.0 * uAtlasScale.z / exp2(ceil(lod));  // texels of the level read
    // A view that faces the surface there sees it best (its normal's z: the cosine).
    float w = (vWeight[k] + 0.05) * (nz * nz + 1e-3) * (smoothstep(0.5, 2.5, rim) + 1e-4) *
              (1.0 - smoothstep(2.0, 4.0, off) + 1e-4);
    n += w * (nxy.x * v.right + nxy.y * v.up + v.side * nz * v.dir);
    color += w * textureLod(uColor, b[k].uv, lod).rgb;
    total += w;
  }
  // (Every view weighs something; where none sees the point well, the least bad decide.)
  h.normal = vPuffToView * normalize(n);
  h.color = color / total;
}

// wantEdge: how deep a hit reaches (the antialiased edge and the ink's inner edge); wantShade: the
// normal and colour of a hit.
// reach: diameters past the silhouette where anything is drawn (the ink and its antialiased edge).
HullHit hullMarch(float lod, float tpp, bool fromTable, float trusted, float reach, bool wantEdge, bool wantShade) {
  bool behind = setUpHullViews();
  vec3 origin = vBillboardPuff * vec3(vPuff, 0.0);
  vec3 ray = vBillboardPuff[2];
  float pixel = tpp / uAtlasScale.x;  // a screen pixel in diameters
  float eps = 0.25 * pixel;
  // The unit sphere holds the puff: the ray's chord through it, or its point nearest the centre
  // for a ray that misses (whose least distance is then measured there).
  float tMax = sqrt(max(0.25 - dot(origin, origin), 0.0));
  HullHit h;
  h.hit = false;
  h.behind = behind;
  h.t = 0.0;
  h.nearest = length(origin) - 0.5;
  h.deepest = 0.0;
  if (h.nearest > reach) return h;  // farther from the sphere than any ink reaches: nothing to read
  HullBound b[kHullViews];
  float t, tNearest;
  vec2 f;
  bool throughWall;
  marchExact(origin, tMax, eps, lod, fromTable, trusted, reach + pixel, h, t, f, throughWall, tNearest, b);
  if (!h.hit) {
    // A miss: its least distance to the hull is the largest of the bounds' distances at the ray's
    // closest approach, an estimate (short where two bounds meet, long where a front surface curves
    // up toward the ray), and the ink's outer edge lies where it reaches the ink's width. Near that
    // edge the distance is measured on the screen instead.
    float ink = reach - pixel;  // the ink's width (diameters); beyond `reach` nothing is drawn
    if (ink > 0.0 && h.nearest <= reach + pixel)
      h.nearest = screenDistance(origin + tNearest * ray, h.nearest, ink, pixel, eps, lod, fromTable, trusted);
    return h;
  }
  h.t = t;
  // A ray that enters through a front surface is inside the silhouette: its pixel is body. One that
  // enters through a silhouette's wall may graze it: on into the hull until 2 px deep (or out).
  h.deepest = -2.0 * pixel;
  if (wantEdge && throughWall) h.deepest = wallDepth(origin, t, f, tMax, pixel, eps, lod, fromTable, trusted);
  if (behind && wantShade) surfaceBehind(origin, tMax, eps, lod, fromTable, trusted, h.t, b);
  if (h.hit && wantShade) shadeHit(origin + h.t * ray, pixel, lod, b, h);
  return h;
}
#endif

// The blend of the views' packed maps at this fragment: each view's lookup (uv, inside its cell)
// and normal, and the weighted depth offset and silhouette distance (texels; tableDist the radius
// table's, read only when fromTable). All zero where the blend does not shade (`shades` false).
struct ViewBlend {
  vec2 uv[PUFF_VIEWS];
  vec2 nxy[PUFF_VIEWS];
  bool inside[PUFF_VIEWS];
  float depth, dist, tableDist;
};

ViewBlend blendViews(float lod, float range, bool fromTable, bool shades) {
  ViewBlend v;
  v.depth = 0.0;
  v.dist = 0.0;
  v.tableDist = 0.0;
  for (int k = 0; k < PUFF_VIEWS; ++k) {  // a constant bound: unrolled
    v.uv[k] = vec2(0.0);
    v.nxy[k] = vec2(0.0);
    v.inside[k] = false;
    if (!shades) continue;
    vec2 local = mat2(vMap[k].xy, vMap[k].zw) * vPuff;  // the cell's view, puff diameters
    v.uv[k] = cellUv(vCell[k], local);
    // Lookups stay inside their cell: a rolled or foreshortened quad reaches past the cell's
    // corners, into other variations and views. Outside is empty.
    v.inside[k] = insideCell(local, lod);
    vec4 pk = v.inside[k] ? textureLod(uPacked, v.uv[k], lod) : vec4(0.5, 0.5, 0.5, 1.0);
    v.nxy[k] = pk.xy * 2.0 - 1.0;
    float w = vWeight[k];
    v.depth += w * (pk.z - 0.5) * uAtlasScale.y * vNormalXf[k][2].z;
    v.dist += w * ((pk.w - 0.5) * 2.0 * range);
    if (fromTable) v.tableDist += w * (length(local) - silhouetteRadius(vCell[k], local)) * uAtlasScale.x;
  }
  return v;
}

#ifndef PUFF_CASTER
// The blend's normal (camera space, unnormalized) and colour (scene-linear: views blended in linear
// light; the colour map is the second read, the lit pass's alone).
void blendedSurface(ViewBlend v, float lod, out vec3 n, out vec3 color) {
  n = vec3(0.0);
  color = vec3(0.0);
  for (int k = 0; k < PUFF_VIEWS; ++k) {
    float w = vWeight[k];
    n += w * (vNormalXf[k] * vec3(v.nxy[k], sqrt(max(0.0, 1.0 - dot(v.nxy[k], v.nxy[k])))));
    if (v.inside[k]) color += w * textureLod(uColor, v.uv[k], lod).rgb;
  }
}

// The world point this fragment shades: on its eye ray at the offset depth `d` (diameters toward
// the eye).
vec3 pointAtOffset(float d) {
  if (isOrthographic()) return vWorld + normalize(uInvView[2].xyz) * (d * vSize);
  return uCameraWorld.xyz + (vWorld - uCameraWorld.xyz) * ((vDist - d * vSize) / vDist);
}
#endif

// The outline band: 0 < dist <= width (texels), the width returned. From the map, the band and its
// antialiased edge (half a pixel) must end inside its range; beyond is empty (dist made so far that
// nothing covers the pixel). With
// `fromTable`, a blended distance past what the map holds is the radius table's (`tableDist`).
float outlineBand(bool fromTable, bool blended, float tableDist, float trusted, float range, float wantTexels,
                  float tpp, inout float dist) {
  if (fromTable) {
    if (blended) dist = dist < trusted ? dist : max(tableDist, trusted);
    return wantTexels;
  }
  if (dist >= range - 0.5) dist = 1e30;  // nothing drawn: no coverage
  return max(0.0, min(wantTexels, range - 1.0 - 0.5 * tpp));
}

#ifdef PUFF_HULL
// An oriented puff: the hull marched (hullMarch) in place of the blend, whose depth offset and
// silhouette distance (texels: outside, the least distance to the hull; inside, how deep the ray
// reaches into it) replace the blend's.
HullHit marchHull(float lod, float tpp, bool fromTable, float trusted, float wantTexels, inout float depth,
                  inout float dist) {
  float reach = (wantTexels + tpp) / uAtlasScale.x;
#ifdef PUFF_CASTER
  HullHit hull = hullMarch(lod, tpp, fromTable, trusted, reach, false, false);
#else
  const bool wantEdge = PUFF_SHADE_PASS != PUFF_PASS_DEPTH_ONLY, wantShade = PUFF_SHADE_PASS == PUFF_PASS_LIT;
  HullHit hull = hullMarch(lod, tpp, fromTable, trusted, reach, wantEdge, wantShade);
#endif
  depth = hull.t * vNormalXf[0][2].z;
  dist = hull.hit ? min(hull.deepest * uAtlasScale.x, -1e-3) : max(hull.nearest * uAtlasScale.x, 1e-3);
  return hull;
}
#endif

#ifndef PUFF_CASTER
// Eq. 2, K_a + C K_L q(N . L), in display values: the surface's colour (scene-linear) is encoded and
// the particle's tint multiplies it. A shadow-map receiver in another caster's shadow keeps the
// ambient term only, as the volumes' shadowed pass draws it.
vec3 litColor(vec3 ka, vec3 n, vec3 color, float d) {
  color = linearToSrgb(color) * vTint;
  vec3 q = uShading == 1 ? quantize(dot(normalize(n), uLightDirView.xyz)) : vec3(1.0);
  vec3 rgb = ka + color * uLightColor.rgb * q;
  if (shadowMapEnabled() && inShadowMap(pointAtOffset(d), vId)) rgb = ka;
  return rgb;
}
#endif

// A nailboard fragment as every pass sees it (evaluateFragment).
struct NailboardFragment {
  float coverage;  // of the pixel, the ink's outer edge antialiased (0: nothing drawn)
  float body;      // the body's share of it (the rest is ink)
  float d;         // depth offset, diameters toward the eye (0 on the ink and flange)
  float lod;
  ViewBlend views;
#ifdef PUFF_HULL
  bool marched;
  float blendDist;  // the blend's distance to its silhouette (when it shades)
  HullHit hull;
#endif
};

// First what every pass needs: depth offset and distance to the silhouette (one read per view).
// The mip level comes from the particle's projected size, like the texel-to-pixel scale below:
// no derivatives, so the colour can be read after the discards.
NailboardFragment evaluateFragment() {
  NailboardFragment f;
  float lod = max(0.0, log2(max(1e-4, vTexelsPerPixel)));
  f.lod = lod;
  // From the particle's projected size, not from derivatives: those break down along the quad's
  // diagonal on some rasterizers, and the size is known anyway.
  float tpp = max(1e-4, vTexelsPerPixel);
  // The distance map holds the distance to the silhouette (texels) up to its range, and a coarse
  // mip blurs it over 2^lod texels: it is trusted below `trusted`. A puff so small that its band
  // and antialiased edge reach past that (puffs a few dozen pixels wide and less) takes its
  // silhouette and band from the radius table instead (particle.glsl, silhouetteRadius), which
  // reaches any distance: outlines never thin away, and silhouettes are not eroded.
  float range = uAtlasScale.z;
  float trusted = range - 1.0 - 0.5 * tpp;
  float wantTexels = uOutlines == 1 ? max(0.0, uOutlineWidth) * tpp : 0.0;
  bool fromTable = wantTexels > trusted;  // the same for the whole puff
#ifdef PUFF_HULL
  bool marched = vHull == 1;  // an oriented puff: hullMarch below, not the blend of four views
  bool blendShades = !marched || vHullBehind == 1;  // from behind, the blend shades the hull (below)
  f.marched = marched;
#else
  const bool marched = false, blendShades = true;
#endif
  f.views = blendViews(lod, range, fromTable, blendShades);
  float depth = f.views.depth, dist = f.views.dist;
#ifdef PUFF_HULL
  f.blendDist = dist;
  if (marched) f.hull = marchHull(lod, tpp, fromTable, trusted, wantTexels, depth, dist);
#endif
  float widthTexels = outlineBand(fromTable, !marched, f.views.tableDist, trusted, range, wantTexels, tpp, dist);
  f.coverage = clamp(0.5 - (dist - widthTexels) / tpp, 0.0, 1.0);
  f.body = clamp(0.5 - dist / tpp, 0.0, 1.0);
  // Outline and flange texels hold d = 0: they sit on the billboard plane, behind the bodies of
  // nearer particles, which is what hides outlines inside a cloud (Fig. 5).
  f.d = dist > 0.0 ? 0.0 : depth;
  return f;
}

#if !defined(PUFF_CASTER) && !defined(PUFF_VISIBILITY)
// The colour of a lit (or shadowed) fragment, scene-linear.
vec3 shadeFragment(NailboardFragment f) {
  vec3 ka = ambientAt(gl_FragCoord.xy);
  vec3 rgb = ka;
  if (PUFF_SHADE_PASS == PUFF_PASS_LIT) {  // the lit pass alone needs the normal and the colour (the second read)
    vec3 n, color;
    blendedSurface(f.views, f.lod, n, color);
#ifdef PUFF_HULL
    if (f.marched && f.hull.hit) {
      // Seen from behind, the hull's surface is an assumption that differs from view to view: the
      // blend's turned normals shade it (coherent, as the blend draws backs) where the blend covers
      // the pixel; the colour is the hull's.
      if (!f.hull.behind || f.blendDist > 0.0) n = f.hull.normal;
      color = f.hull.color;
    }
#endif
    rgb = litColor(ka, n, color, f.d);
  }
  // Eq. 2's result is a display value, limited to the display's range as the paper's 8-bit frame
  // buffer limited it (K_a + C K_L q may exceed 1), then to scene-linear; the outline's antialiased
  // edge blends in linear light.
  rgb = srgbToLinear(clamp(rgb, 0.0, 1.0));
  if (uOutlines == 1) rgb = mix(srgbToLinear(clamp(uOutlineColor, 0.0, 1.0)), rgb, f.body);
  return rgb;
}
#endif

#ifdef PUFF_DEFERRED
// Each pixel's particles, as the pre-pass left them (one per sample), shaded once each at the
// pixel's centre, as the nailboards' quads would have shaded them there. The pre-pass kept them: none
// is discarded. Single-sampled, exactly what the quads draw. Multisampled, the samples' colours
// averaged over the samples the particles cover (what the resolve makes of them) and written to
// those samples at the depth of the particle that covers most of them: a sample of another particle
// at the pixel (only along silhouettes) takes that depth.
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);  // (the target spans the viewport's origin)
#ifdef PUFF_DEFERRED_MS
  uvec2 samples[PUFF_MAX_DEFERRED_SAMPLES];
  int count = clamp(uSamples, 1, PUFF_MAX_DEFERRED_SAMPLES);
  int mask = 0;
  for (int i = 0; i < count; ++i) {
    samples[i] = texelFetch(uVisible, px, i).xy;
    if (samples[i].x != 0u) mask |= 1 << i;
  }
  if (mask == 0) discard;
  vec3 sum = vec3(0.0);
  int covered = 0, most = 0;
  float depth = 0.0;
  for (int i = 0; i < count; ++i) {
    uint id = samples[i].x;
    bool first = id != 0u;
    int n = 0;
    for (int j = 0; j < count; ++j) {
      first = first && !(j < i && samples[j].x == id);
      n += samples[j].x == id ? 1 : 0;
    }
    if (!first) continue;
    loadVarying(id);
    sum += float(n) * shadeFragment(evaluateFragment());
    covered += n;
    if (n > most) {
      most = n;
      depth = uintBitsToFloat(samples[i].y);
    }
  }
  gl_SampleMask[0] = mask;
  gl_FragDepth = depth;
  fragColor = vec4(sum / float(covered), 1.0);
#else
  uvec2 visible = texelFetch(uVisible, px, 0).xy;
  if (visible.x == 0u) discard;
  loadVarying(visible.x);
  gl_FragDepth = uintBitsToFloat(visible.y);
  fragColor = vec4(shadeFragment(evaluateFragment()), 1.0);
#endif
}
#else
void main() {
  NailboardFragment f = evaluateFragment();
  if (uMultisample == 1 ? f.coverage <= 0.0 : f.coverage < 0.5) discard;
#ifdef PUFF_CASTER
  // Drawn from the light, the map keeps where this puff's shadow starts: behind its far side, taken
  // as its near side's depth-map offset mirrored through the billboard plane (as the shadow volumes
  // take it), plus the bias. Its own near side lies before that, so it does not shadow itself even
  // where the map saw only it.
  gl_FragDepth = storeDepth(linearDepth(vDist + (max(f.d, 0.0) + uShadowBias) * vSize));
  oId = vId;
#elif defined(PUFF_VISIBILITY)
  gl_FragDepth = storeDepth(linearDepth(vDist - f.d * vSize));
  // Multisampled, the coverage goes to the sample mask (an integer target has no alpha for
  // alpha-to-coverage): sample s where coverage > s / samples, the rule Mesa's rasterizers spend
  // alpha-to-coverage's alpha by, so the quads drawn forward there cover the same samples. (A GPU
  // may dither its own; the count of samples is the same on average.)
  if (uMultisample == 1) {
    int mask = 0;
    for (int s = 0; s < uSamples; ++s) mask |= f.coverage > float(s) / float(uSamples) ? 1 << s : 0;
    gl_SampleMask[0] = mask;
  }
  oVisible = uvec2(vId, floatBitsToUint(clamp(gl_FragDepth, 0.0, 1.0)));
#else
  gl_FragDepth = storeDepth(linearDepth(vDist - f.d * vSize));
  if (PUFF_SHADE_PASS == PUFF_PASS_DEPTH_ONLY) {
    fragColor = vec4(0.0);
    return;
  }
  fragColor = vec4(shadeFragment(f), uMultisample == 1 ? f.coverage : 1.0);
#endif
}
#endif
