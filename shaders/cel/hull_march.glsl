// The tumbling hull (style.tumble "hull"): an oriented puff's eye ray marched through the hull of its
// baked views. Part of the nailboards' fragment stage (nailboard_fs.glsl, PUFF_HULL): reads its maps,
// uniforms and varyings.

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
