#version 450 core
// Billboard shadow volumes (McGuire & Fein §4.3): per particle, one front-facing and one
// back-facing face that cover exactly the same pixels; the billboard is the third polygon.
//
// The proxy is the puff's silhouette seen from the light (its distance map) swept along the
// direction D the light travels: a prism with cross-section perpendicular to D. The paper's proxy,
// a square containing the view direction, collapses to a sliver when the light is near the view
// axis (a back-lit cloud) and can never contain the eye; this one stays a full shadow from any
// side, and the camera can stand inside it. docs/cel-rendering.md has the comparison.
//
// The faces are drawn over a conservative footprint (the convex hull of the prism on screen, or
// the whole screen when the prism reaches the eye); the fragment shader finds where the eye ray
// enters and leaves the volume and writes that depth, so both faces always cover the same pixels
// and the depth-fail count is exact with the camera inside a volume or a volume through the near
// plane. 12 vertices per particle: the footprint as a counter-clockwise fan of four triangles. The
// renderer draws it twice, with the SAME vertices in the same order: once as the entry face
// (uBackFace 0: depth where the eye ray enters, stencil decremented on depth fail) and once as the
// exit face (uBackFace 1: where it leaves, incremented). Both draws rasterize and interpolate
// identically, so the two faces cover the same samples with the same ray, whatever the winding.
#include "common/frame.glsl"
#include "cel/particle.glsl"

uniform float uShadowBias;    // volume starts this many diameters past the puff's far side
uniform float uShadowLength;  // world units
uniform vec4 uShadowFloor;    // world plane (n, w): volumes end a diameter past it; n = 0: none

// The eye ray through this pixel in the volume's light frame: P(t) = vC0 + t vC1 (x, y in puff
// diameters, z = lambda in world units), t from the near plane (0) to the far plane (1). Both are
// affine in screen position, so they interpolate without perspective; t is then the linear depth
// (whatever the depth convention: rayPoint finds the planes from the projection's x, y and w rows).
noperspective out vec3 vC0;
noperspective out vec3 vC1;
flat out vec4 vExtent;  // size, lambda end (world), 0, 0
flat out int vCell;          // the atlas cell the light sees: its depth map gives the start cap

// The world point at view-axis distance `dist` on the eye ray through `ndc` (x, y): uProj's x, y and
// w rows put a camera point (x, y, -dist, 1) there when (row0 - ndc.x row3) . p = 0 and (row1 -
// ndc.y row3) . p = 0, two linear equations in x and y. Its z row is not used, so this holds for
// any depth convention and clip z range, an infinite far plane included (the near and far planes
// of linear depth are uDepthRange's, finite).
vec3 rayPoint(vec2 ndc, float dist) {
  mat4 rows = transpose(uProj);
  vec4 a = rows[0] - ndc.x * rows[3], b = rows[1] - ndc.y * rows[3];
  vec2 rhs = vec2(a.z * dist - a.w, b.z * dist - b.w);
  float det = a.x * b.y - a.y * b.x;
  vec2 xy = vec2(rhs.x * b.y - a.y * rhs.y, a.x * rhs.y - rhs.x * b.x) / det;
  return (uInvView * vec4(xy, -dist, 1.0)).xyz;
}

// The volume's far end, lambda1 (world units along D from the puff's centre): the shadow's length,
// or, where the light travels into the floor, a diameter past the floor when that is shorter (and
// never below 0).
float volumeEnd(vec3 position, float s, vec3 D) {
  float lambda1 = uShadowLength;
  float dn = dot(uShadowFloor.xyz, D);
  if (dot(uShadowFloor.xyz, uShadowFloor.xyz) > 0.0 && dn < -1e-4) {
    float toFloor = (dot(uShadowFloor.xyz, position) + uShadowFloor.w) / -dn;
    lambda1 = clamp(toFloor + s, 0.0, lambda1);
  }
  return lambda1;
}

// The atlas cell whose view is nearest the light's: the silhouette the light sees. `puff`: the puff's
// frame (puff space -> world) as the light sees it. An oriented puff turns with its own frame; an
// unoriented one shows the light its front view in lightFacingFrame (as the shadow map draws it).
int lightCell(Particle p, vec3 D, out mat3 puff) {
  puff = p.oriented ? quatToMat3(p.orientation)
                    : lightFacingFrame(-D, normalize(uInvView[0].xyz), normalize(uInvView[1].xyz));
  ivec4 cell;
  vec4 weight;
  selectViews(p, transpose(puff) * uLightDirWorld.xyz, cell, weight);
  int best = 0;
  for (int k = 1; k < 4; ++k) {
    if (weight[k] > weight[best]) best = k;
  }
  return cell[best];
}

// The light frame (e1, e2) is the cell's right and up in world space, projected across the light
// and made orthonormal: the silhouette table (in the cell's right / up) turns with the puff.
void lightFrame(mat3 puff, int cell, vec3 D, out vec3 e1, out vec3 e2) {
  vec3 cr = puff * cells[cell].right.xyz, cu = puff * cells[cell].up.xyz;
  e1 = cr - dot(cr, D) * D;
  e2 = cu - dot(cu, D) * D;
  if (dot(e1, e1) < 1e-6) e1 = cross(D, e2);  // the cell's right along the light: up alone decides
  e1 = normalize(e1);
  e2 -= dot(e2, e1) * e1;
  e2 = dot(e2, e2) < 1e-12 ? cross(e1, D) : normalize(e2);
}

// The prism's eight corners on screen (pts, normalized device x, y): the square of side s across
// the light (e1, e2) about the puff's centre, from half a diameter before it to lambda1 past it
// along D. True when the prism reaches the eye (a corner nearer than the near plane, in perspective).
bool prismCorners(vec3 position, float s, vec3 e1, vec3 e2, vec3 D, float lambda1, out vec2 pts[8]) {
  bool reachesEye = false;
  for (int i = 0; i < 8; ++i) {
    vec3 corner = position + 0.5 * s * ((i & 1) != 0 ? e1 : -e1) + 0.5 * s * ((i & 2) != 0 ? e2 : -e2) +
                  ((i & 4) != 0 ? lambda1 : -0.5 * s) * D;
    vec4 clip = uViewProj * vec4(corner, 1.0);
    if (!isOrthographic() && clip.w < uDepthRange.x * 1.01) reachesEye = true;
    pts[i] = clip.xy / max(clip.w, 1e-6);
  }
  return reachesEye;
}

// The whole screen as the footprint: its corners, counter-clockwise, in pts[0..3] and hull[0..3];
// returns their count.
int wholeScreen(inout vec2 pts[8], out int hull[8]) {
  pts[0] = vec2(-1.0, -1.0);
  pts[1] = vec2(1.0, -1.0);
  pts[2] = vec2(1.0, 1.0);
  pts[3] = vec2(-1.0, 1.0);
  hull[0] = 0, hull[1] = 1, hull[2] = 2, hull[3] = 3;
  return 4;
}

// The convex hull of the eight points (Jarvis march): indices into pts, counter-clockwise from the
// leftmost (the lowest of those), in hull; returns their count.
int convexHull(vec2 pts[8], out int hull[8]) {
  int n = 0;
  int start = 0;
  for (int i = 1; i < 8; ++i) {
    if (pts[i].x < pts[start].x || (pts[i].x == pts[start].x && pts[i].y < pts[start].y)) start = i;
  }
  int cur = start;
  for (int iter = 0; iter < 8; ++iter) {
    hull[n++] = cur;
    int next = (cur + 1) % 8;
    for (int j = 0; j < 8; ++j) {
      vec2 a = pts[next] - pts[cur], b = pts[j] - pts[cur];
      float c = a.x * b.y - a.y * b.x;
      // Keep every other point on the left: counter-clockwise.
      if (c < 0.0 || (c == 0.0 && dot(b, b) > dot(a, a))) next = j;
    }
    cur = next;
    if (cur == start) break;
  }
  return n;
}

void main() {
  uint index = uint(gl_VertexID) / 12u;
  int local = gl_VertexID % 12;
  Particle p = unpackParticle(index);
  float s = p.size;
  if (s <= 0.0) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  vec3 D = -uLightDirWorld.xyz;
  float lambda1 = volumeEnd(p.position, s, D);
  vExtent = vec4(s, lambda1, 0.0, 0.0);
  mat3 puff;
  int cell = lightCell(p, D, puff);
  vec3 e1, e2;
  lightFrame(puff, cell, D, e1, e2);
  vCell = cell;

  // Footprint: the convex hull of the prism's eight corners on screen (Jarvis march), as a fan
  // of four triangles; or the whole screen when the prism reaches the eye.
  vec2 pts[8];
  bool reachesEye = prismCorners(p.position, s, e1, e2, D, lambda1, pts);
  int hull[8];
  int n;
  if (reachesEye) {
    n = wholeScreen(pts, hull);
  } else {
    n = convexHull(pts, hull);
  }
  int tri = local / 3, vtx = local % 3;
  int k = vtx == 0 ? 0 : min(tri + vtx, n - 1);
  vec2 ndc = pts[hull[k]];
  vec3 origin = rayPoint(ndc, uDepthRange.x), dir = rayPoint(ndc, uDepthRange.y) - origin;
  mat3 toLight = transpose(mat3(e1, e2, D));
  vec3 scale = vec3(1.0 / s, 1.0 / s, 1.0);
  vC0 = scale * (toLight * (origin - p.position));
  vC1 = scale * (toLight * dir);
  gl_Position = vec4(ndc, 0.0, 1.0);
}
