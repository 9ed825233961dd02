// The tumbling hull (style.tumble "hull"): an oriented puff's eye ray marched through the hull of its
// baked views. Part of the nailboards' fragment stage (nailboard_fs.glsl, PUFF_HULL): reads its maps,
// uniforms and varyings.

// The hull's field (NailboardRenderer::setAtlas, runtime/src/cel/hull_field.h): every baked view
// bounds the puff (it lies inside the view's silhouette swept along the view's direction, and before
// the view's far side), and so does its unit sphere (radius half a diameter). The intersection of all
// the views' bounds is a hull close to the puff where the views are many, and the same from wherever
// it is seen: sampled once per variation on a grid over the puff's cube, each point holding the
// largest of the bounds' distances there (diameters, > 0 outside; at most kHullFieldReach), the
// variations' grids stacked along z. The eye ray is marched through it, one filtered read a step:
// each value is about the distance to the hull, so steps of that size do not pass through it (sphere
// tracing). The ray hits where it reaches 0; a ray that misses passes the hull at its least distance,
// the ink band's distance to the silhouette.
//
// The hull decides coverage, ink and depth: the hit is the surface drawn, shaded by the four views
// nearest the eye's direction. A hemi-oct atlas seen from behind has no view of the side the eye
// sees: the field is exact there too (the far sides bound the near side), and the views from behind
// shade it, their normals reflected through their cell planes (side -1).
layout(binding = 4) uniform sampler3D uHull;

struct HullView {
  int cell;
  float side;           // +1 seen from its own side, -1 from behind (a hemi-oct back)
  vec3 right, up, dir;  // puff space; dir toward the baked view's viewer
};
const int kHullViews = 4;  // the four nearest the eye's direction (vCell): they shade the hit
HullView hullViews[kHullViews];
// This particle's grid in the field (core::HullFieldLayout): points a side, the texel where its
// variation's grid starts, and the texture's size.
float hullSide;
vec3 hullOrigin, hullTexels;

// The field at puff-space point `pt` (diameters, > 0 outside the hull). The grid holds the sphere's
// bound too, but its filtering rounds the sphere's rim by a fraction of a grid step; taken again here,
// exact, a sphere puff's rim and ink are the disc's (its ink edge's RMS against the disc 0.08, 0.18
// without it, seen from behind).
float hullField(vec3 pt) {
  vec3 g = clamp((pt + 0.5) * hullSide, vec3(0.5), vec3(hullSide - 0.5));
  return max(textureLod(uHull, (g + hullOrigin) / hullTexels, 0.0).r, length(pt) - 0.5);
}

// View k's maps at puff-space point `pt`: the packed texel (filtered; empty outside the cell) and where
// it was read.
struct HullLookup {
  vec4 texel;
  vec2 uv;
};
HullLookup hullLookup(int k, vec3 pt, float lod) {
  HullView v = hullViews[k];
  vec2 local = vec2(dot(pt, v.right), dot(pt, v.up));
  HullLookup l;
  l.uv = cellUv(v.cell, local);
  l.texel = insideCell(local, lod) ? textureLod(uPacked, l.uv, lod) : vec4(0.5, 0.5, 0.5, 1.0);
  return l;
}

struct HullHit {
  bool hit;
  bool behind;    // seen from behind on a hemi-oct atlas: the surface is an assumption (shaded as blended)
  float t;        // along the ray toward the eye, diameters from the billboard plane
  float nearest;  // a miss: least distance to the hull (diameters)
  float deepest;  // a hit: how far inside the hull the ray reaches (<= 0, diameters; probed to kBodyDepth)
  vec3 normal;    // a hit: camera space
  vec3 color;     // a hit: scene-linear
};

// Whether the eye ray through `origin` (puff space, on the billboard plane) hits the hull: the march
// below, without its probes.
// From `t` on (away from the eye) to the sphere's far side at -tMax.
bool hullHitsFrom(vec3 origin, float t, float tMax, float eps) {
  vec3 ray = vBillboardPuff[2];
  for (int i = 0; i < 64; ++i) {
    float f = hullField(origin + t * ray);
    if (f <= 0.0) return true;
    t -= max(f, eps);
    if (t < -tMax) break;
  }
  return false;
}

bool hullHits(vec3 origin, float eps) {
  float r2 = dot(origin, origin);
  if (r2 >= 0.25) return false;
  float tMax = sqrt(0.25 - r2);
  return hullHitsFrom(origin, tMax, tMax, eps);
}

// The views' frames for this fragment (hullViews) and its grid in the field; true when one of the
// views stands for the view from behind.
bool setUpHullViews() {
  bool behind = false;
  for (int k = 0; k < kHullViews; ++k) {
    HullView v;
    v.cell = vCell[k];
    v.right = cells[v.cell].right.xyz;
    v.up = cells[v.cell].up.xyz;
    v.dir = cells[v.cell].dir.xyz;
    // A hemi-oct cell whose viewer is on the far side stands for the view from behind.
    v.side = uAtlasLayout.w != 1 && dot(v.dir, vBillboardPuff[2]) < 0.0 ? -1.0 : 1.0;
    hullViews[k] = v;
    behind = behind || v.side < 0.0;
  }
  // The variations' grids: perColumn stacked along z, such columns side by side along x.
  hullTexels = vec3(textureSize(uHull, 0));
  hullSide = hullTexels.y;
  int side = int(hullSide), perColumn = max(1, int(hullTexels.z) / side);
  int variation = vCell[0] / max(1, uAtlasLayout.y);
  hullOrigin = vec3(float(variation / perColumn * side), 0.0, float(variation % perColumn * side));
  return behind;
}

// The hull along the eye ray from the sphere's near side (t = tMax) away from the eye: the first point
// inside it (h.hit, t, f the field there), or for a ray that misses its least distance (h.nearest, at
// tNearest).
void marchField(vec3 origin, float tMax, float eps, inout HullHit h, out float t, out float f, out float tNearest) {
  vec3 ray = vBillboardPuff[2];
  t = tMax;
  f = 1.0;
  tNearest = t;
  for (int i = 0; i < 64; ++i) {
    f = hullField(origin + t * ray);
    if (i == 0 || f < h.nearest) tNearest = t;
    h.nearest = i == 0 ? f : min(h.nearest, f);
    if (f <= 0.0) {
      h.hit = true;
      break;
    }
    t -= max(f, eps);
    if (t < -tMax) break;
  }
}

// Whether the eye ray through the billboard plane `s` diameters from this pixel's, toward `toward`
// (billboard axes), hits the hull.
bool hitsShifted(vec2 toward, float s, float eps) {
  return hullHits(vBillboardPuff * vec3(vPuff + s * toward, 0.0), eps);
}

// A miss's distance to the hull near the ink's outer edge, measured on the screen: the eye rays
// through the billboard plane stepped toward the hull hit it from some distance on, found by
// bisection along two directions (down the distance's gradient, and toward the puff's centre,
// where the gradient misleads: a bay), the nearer kept. `at`: the ray's closest approach;
// `nearest`: the field there; `ink`: the ink's width (diameters).
float screenDistance(vec3 at, float nearest, float ink, float pixel, float eps) {
  float delta = 0.5 * pixel;
  vec2 grad = (vec2(hullField(at + delta * vBillboardPuff[0]), hullField(at + delta * vBillboardPuff[1])) - nearest) /
              delta;
  vec2 towards[2] = vec2[2](dot(grad, grad) > 1e-12 ? -normalize(grad) : vec2(0.0),
                            dot(vPuff, vPuff) > 1e-12 ? -normalize(vPuff) : vec2(0.0));
  // What is drawn depends on the distance only within half a pixel of the ink's edges (the
  // antialiased edges; between them the pixel is ink whatever the distance): the bisection stops
  // once its interval lies between them, or is a quarter of a pixel wide.
  float solid = ink - 0.5 * pixel;  // nearer than this (and over half a pixel out): ink
  // The stepped rays only ask whether the hull is hit, not where: a pixel a step. (A ray that
  // crosses the hull within one step and misses every point it reads reaches less than 0.03 px into
  // a lump 10 px across, more at the hull's sharp edges, where two views' silhouettes meet.)
  float hitEps = max(eps, pixel);
  // Newton's guess down the gradient, where the field falls to 0 at its slope.
  float slope = length(grad);
  float guess = slope > 1e-6 ? nearest / slope : -1.0;
  float best = -1.0;
  for (int k = 0; k < 2; ++k) {
    vec2 toward = towards[k];
    if (dot(toward, toward) == 0.0 || (best >= 0.0 && best <= solid)) continue;
    // Toward the centre only where that is another way than the gradient's (a bay): within 20
    // degrees of it, rays less than a pixel from those already asked.
    if (k == 1 && dot(towards[0], toward) > 0.94) continue;
    float lo = 0.0, hi = ink + 0.5 * pixel;
    if (best >= 0.0) hi = min(hi, best);
    // The guess bracketed first: by the solid ink's bounds where it lies between them (both hold:
    // the pixel is ink), else by the quarter pixels counted from the ink's width (where the edge's
    // coverage is one half), the points the bisection below splits at. Where the guess is wrong,
    // the bisection goes on from what the two rays found. (At 0 the ray is the pixel's own, a miss.)
    bool hiHits = false;
    if (k == 0 && guess > 0.0 && guess < hi) {
      float quarter = 0.25 * pixel;
      bool inSolid = guess >= 0.5 * pixel && guess <= solid;
      float a = inSolid ? 0.5 * pixel : max(ink + quarter * floor((guess - ink) / quarter), 0.0);
      float b = inSolid ? solid : min(a + quarter, hi);
      if (hitsShifted(toward, b, hitEps)) {
        hi = b;
        hiHits = true;
        if (a > 0.0 && hitsShifted(toward, a, hitEps)) {
          hi = a;
        } else {
          lo = a;
        }
      } else if (b >= hi) {
        continue;  // the farthest ray asked, and missed: no ink this way
      } else {
        lo = b;
      }
    }
    if (!hiHits && !hitsShifted(toward, hi, hitEps)) continue;
    for (int i = 0; i < 4; ++i) {
      if ((lo >= 0.5 * pixel && hi <= solid) || hi - lo <= 0.25 * pixel) break;
      // Split first at the inner edge of the outer antialiased band, where most pixels of the ring
      // are decided, then at the ink's width, where an edge pixel's coverage is one half (so the
      // quarter-pixel intervals after it never straddle that line), else halfway.
      float mid = solid > lo && solid < hi ? solid : ink > lo && ink < hi ? ink : 0.5 * (lo + hi);
      if (hitsShifted(toward, mid, hitEps)) {
        hi = mid;
      } else {
        lo = mid;
      }
    }
    best = max(0.5 * (lo + hi), 1e-4);
  }
  return best >= 0.0 ? best : max(nearest, ink + 1.5 * pixel);
}

// How deep a ray must reach into the hull to be the body's alone (pixels): the body's antialiased
// edge is half a pixel wide (nailboard_fs.glsl: body = 0.5 - depth / pixel), so from half a pixel on
// the pixel is body however much deeper the ray reaches.
const float kBodyDepth = 0.5;

// How deep a ray that entered the hull at s = t (the field f there) reaches into it: on until
// kBodyDepth, or out (<= 0, diameters). A ray that grazes the hull's silhouette stays shallow: the
// antialiased edge of the body and the ink's inner edge. One that leaves the hull and enters it again
// farther on grazed a groove between two lumps, inside the silhouette: body, no ink.
float hullDepth(vec3 origin, float t, float f, float tMax, float pixel, float eps) {
  vec3 ray = vBillboardPuff[2];
  float body = -kBodyDepth * pixel;
  float deepest = f;
  float s = t;
  for (int i = 0; i < 8 && deepest > body; ++i) {
    s -= max(-f, eps);
    if (s < -tMax) break;
    f = hullField(origin + s * ray);
    if (f > 0.0) return hullHitsFrom(origin, s, tMax, eps) ? body : deepest;
    deepest = min(deepest, f);
  }
  return deepest;
}

// The hit's normal and colour: the views that see it (it lies on their front surface, not behind
// it) see the same point, their normals and colours blended as the views are.
void shadeHit(vec3 pt, float pixel, float lod, inout HullHit h) {
  vec3 n = vec3(0.0), color = vec3(0.0);
  float total = 0.0;
  for (int k = 0; k < 4; ++k) {
    HullView v = hullViews[k];
    HullLookup l = hullLookup(k, pt, lod);
    vec4 texel = l.texel;
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
    color += w * textureLod(uColor, l.uv, lod).rgb;
    total += w;
  }
  // (Every view weighs something; where none sees the point well, the least bad decide.)
  h.normal = vPuffToView * normalize(n);
  h.color = color / total;
}

// wantEdge: how deep a hit reaches (the antialiased edge and the ink's inner edge); wantShade: the
// normal and colour of a hit.
// reach: diameters past the silhouette where anything is drawn (the ink and its antialiased edge).
HullHit hullMarch(float lod, float tpp, float reach, bool wantEdge, bool wantShade) {
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
  float t, f, tNearest;
  marchField(origin, tMax, eps, h, t, f, tNearest);
  if (!h.hit) {
    // A miss: its least distance to the hull is the field's least along the ray, an estimate (short
    // where two bounds meet, long where a far side curves toward the ray), and the ink's outer edge
    // lies where it reaches the ink's width. Near that edge the distance is measured on the screen
    // instead. (The shadow map's casters draw no ink: their edge is the silhouette's, the estimate's.)
    float ink = reach - pixel;  // the ink's width (diameters); beyond `reach` nothing is drawn
    if (ink > 0.0 && h.nearest <= reach + pixel)
      h.nearest = screenDistance(origin + tNearest * ray, h.nearest, ink, pixel, eps);
    return h;
  }
  h.t = t;
  h.deepest = -kBodyDepth * pixel;
  if (wantEdge) h.deepest = hullDepth(origin, t, f, tMax, pixel, eps);
  if (wantShade) shadeHit(origin + h.t * ray, pixel, lod, h);
  return h;
}
