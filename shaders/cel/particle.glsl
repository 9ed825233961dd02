// Particles as the GPU receives them (16 bytes each, puff::cel::PackedParticle), the billboard
// frame of each alignment, and the atlas cells a particle's view picks. Shared by the nailboard
// and shadow-volume programs so a shadow is cast by exactly the billboard that is drawn.

layout(std430, binding = 0) readonly buffer ParticleBuffer { uvec4 particles[]; };

// One atlas cell: rect (x, y, w, h; level-0 texels, y down), the puff-space axes of the view it was
// baked from (right, up, toward the viewer), and its variation's core: a ball inside the tumbling
// hull (puff-space centre and radius, diameters; radius 0: none. runtime/src/cel/hull_field.h).
struct AtlasCell {
  vec4 rect;
  vec4 right;
  vec4 up;
  vec4 dir;
  vec4 core;
};
layout(std430, binding = 1) readonly buffer AtlasCells { AtlasCell cells[]; };

uniform vec3 uGridOrigin;    // PackBounds::min: world position of grid point 0, a multiple of uGridStep
uniform vec3 uGridStep;      // PackBounds::step: a power of two per axis (world units)
uniform int uAlignment;      // 0 view-plane, 1 viewpoint, 2 axial
uniform ivec4 uAtlasLayout;  // variations, views, view grid, 1 if the layout is octahedral (else hemi-oct)
uniform vec4 uAtlasGeom;     // atlas width, height (texels), cell size, margin
uniform vec4 uAtlasScale;    // content size, depth scale, distance range, 0

struct Particle {
  vec3 position;
  float size;
  vec4 orientation;  // quaternion x, y, z, w
  int variation;
  bool oriented;
  vec3 tint;  // display multiplier of Eq. 2's C (7 bits a channel; puff::cel::PackedParticle)
};

vec4 unpackQuat(uint bits) {
  const float kRange = 0.70710678;
  int largest = int(bits >> 30u);
  float c[4];
  float sum = 0.0;
  int shift = 20;
  for (int i = 0; i < 4; ++i) {
    if (i == largest) continue;
    c[i] = float((bits >> uint(shift)) & 1023u) / 1023.0 * 2.0 * kRange - kRange;
    sum += c[i] * c[i];
    shift -= 10;
  }
  c[largest] = sqrt(max(0.0, 1.0 - sum));
  return normalize(vec4(c[0], c[1], c[2], c[3]));
}

Particle unpackParticle(uint index) {
  uvec4 d = particles[index];
  Particle p;
  // Exact in floats (fused or not): q * step is 16 bits times a power of two, and the sum a grid
  // point a float holds. So the position is bit for bit puff::cel::unpackParticle's.
  vec3 q = vec3(float(d.x & 0xFFFFu), float(d.x >> 16u), float(d.y & 0xFFFFu));
  p.position = uGridOrigin + q * uGridStep;
  p.size = unpackHalf2x16(d.y >> 16u).x;
  p.orientation = unpackQuat(d.z);
  p.variation = int(d.w & 0xFFu) % max(1, uAtlasLayout.x);
  p.oriented = (d.w & 0x100u) != 0u;
  p.tint = vec3(float((d.w >> 9u) & 127u), float((d.w >> 16u) & 127u), float((d.w >> 23u) & 127u)) / 127.0;
  return p;
}

mat3 quatToMat3(vec4 q) {
  float x = q.x, y = q.y, z = q.z, w = q.w;
  return mat3(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y),
              2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x),
              2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y));
}

bool isOrthographic() { return uDepthRange.w > 0.5; }

// Unit world-space direction from `p` toward the camera.
vec3 towardCamera(vec3 p) {
  if (isOrthographic()) return normalize(uInvView[2].xyz);
  return normalize(uCameraWorld.xyz - p);
}

// The billboard's world-space frame for `alignment` (0 view-plane, 1 viewpoint, 2 axial): columns
// right, up, normal (toward the viewer).
mat3 billboardFrame(vec3 p, int alignment) {
  vec3 camRight = normalize(uInvView[0].xyz), camUp = normalize(uInvView[1].xyz), camBack = normalize(uInvView[2].xyz);
  if (alignment == 1) {  // viewpoint-oriented: faces the eye, upright against the camera's up
    vec3 w = towardCamera(p);
    vec3 r = cross(camUp, w);
    if (dot(r, r) > 1e-8) {
      r = normalize(r);
      return mat3(r, cross(w, r), w);
    }
  } else if (alignment == 2) {  // axial: turns only about world up
    vec3 u = vec3(0.0, 1.0, 0.0);
    vec3 w = towardCamera(p);
    w -= dot(w, u) * u;
    if (dot(w, w) > 1e-8) {
      w = normalize(w);
      return mat3(cross(u, w), u, w);
    }
  }
  return mat3(camRight, camUp, camBack);
}

// The frame particle `p`'s billboard wears: the style's alignment (Style::alignment), but an
// oriented puff (turned by its own rotation, drawn from a multi-view atlas) faces the eye whatever
// the style says: its billboard only carries the rays it marches (or the views it blends) along its
// normal, and the puff itself does not wear the billboard's frame. Under perspective a view-plane
// normal is off the eye ray by the puff's angle off the view axis (TumbleCases.AnOffAxisPuff...:
// coverage IoU 0.819 at puffs 20-25 degrees off, 0.973 facing the eye); orthographic, both are one.
mat3 billboardFrame(Particle p) { return billboardFrame(p.position, p.oriented ? 1 : uAlignment); }

// The frame an UNORIENTED puff shows the light (the shadow map's casters and the shadow volumes
// both use it): facing the light, its right the eye's right carried across the light (or, with the
// eye's right along the light, its up), so a long puff's shadow lies along the puff the eye sees, as
// the cel reference's mesh (which wears the eye's billboard frame) casts it. Columns right, up, normal.
mat3 lightFacingFrame(vec3 towardLight, vec3 eyeRight, vec3 eyeUp) {
  vec3 l = normalize(towardLight);
  vec3 r = eyeRight - dot(eyeRight, l) * l;
  if (dot(r, r) < 1e-6) {
    vec3 u = eyeUp - dot(eyeUp, l) * l;
    r = cross(u, l);
  }
  r = normalize(r);
  return mat3(r, cross(l, r), l);
}

// The puff's frame: puff space -> world. An unoriented puff wears the billboard's frame, so it
// always shows its front view upright.
mat3 puffFrame(Particle p, mat3 billboard) { return p.oriented ? quatToMat3(p.orientation) : billboard; }

// The view grid's cell (column, row) one step past an edge, as the sphere continues there: the
// octahedral square folds along its edges ((1 + e, v) is (1 - e, -v)); past the hemi-oct square's
// edge (the equator) lies the back, whose cells are the front ones opposite ((1 + e, v) is
// (-1 + e, -v), seen from behind). Bilinear blending then runs on around the sphere instead of
// clamping to the edge views.
int wrapView(ivec2 c, int grid) {
  bool oct = uAtlasLayout.w == 1;
  if (c.x < 0 || c.x >= grid) {
    c.y = grid - 1 - c.y;
    c.x = oct ? clamp(c.x, 0, grid - 1) : (c.x < 0 ? grid - 1 : 0);
  }
  if (c.y < 0 || c.y >= grid) {
    c.x = grid - 1 - c.x;
    c.y = oct ? clamp(c.y, 0, grid - 1) : (c.y < 0 ? grid - 1 : 0);
  }
  return clamp(c.y, 0, grid - 1) * grid + clamp(c.x, 0, grid - 1);
}

// Up to four atlas cells for a puff-space direction toward the camera, with bilinear weights over
// the (hemi-)octahedral view grid. A one-view atlas gives its only view with weight 1.
void selectViews(Particle p, vec3 dirPuff, out ivec4 cellIndex, out vec4 weight) {
  int views = max(1, uAtlasLayout.y), grid = max(1, uAtlasLayout.z);
  int base = p.variation * views;
  if (views == 1) {
    cellIndex = ivec4(base);
    weight = vec4(1.0, 0.0, 0.0, 0.0);
    return;
  }
  vec3 d = dirPuff / max(1e-6, abs(dirPuff.x) + abs(dirPuff.y) + abs(dirPuff.z));
  vec2 uv;
  if (uAtlasLayout.w == 1) {
    uv = d.xy;
    if (d.z < 0.0) uv = (1.0 - abs(d.yx)) * vec2(d.x >= 0.0 ? 1.0 : -1.0, d.y >= 0.0 ? 1.0 : -1.0);
  } else {
    // Hemi-octahedral covers the front half only. A view from behind takes the cells around the
    // OPPOSITE direction: an orthographic silhouette seen from -d is the one seen from d, so the
    // outline stays exact; the surface is that cell's front reflected through its plane (cellAxes).
    if (d.z < 0.0) d = -d;
    uv = vec2(d.x + d.y, d.x - d.y);
  }
  vec2 g = (uv * 0.5 + 0.5) * float(grid) - 0.5;
  vec2 g0 = floor(g), f = g - g0;
  ivec2 c0 = ivec2(g0), c1 = c0 + 1;
  cellIndex = ivec4(base + wrapView(ivec2(c0.x, c0.y), grid), base + wrapView(ivec2(c1.x, c0.y), grid),
                    base + wrapView(ivec2(c0.x, c1.y), grid), base + wrapView(ivec2(c1.x, c1.y), grid));
  weight = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
}

// Atlas texture coordinate of a point of cell `c` given in puff diameters from the puff's centre
// (x right, y up in the cell's view).
vec2 cellUv(int c, vec2 puff) {
  vec4 rect = cells[c].rect;
  float margin = uAtlasGeom.w, content = uAtlasScale.x;
  vec2 texel = rect.xy + vec2(margin + (puff.x + 0.5) * content, margin + (0.5 - puff.y) * content);
  return texel / uAtlasGeom.xy;
}

// Whether a point of a cell (puff diameters from the centre, as cellUv takes it) is read from inside
// the cell at mip level `lod`: its bilinear taps at the coarser level used stay off the neighbour
// cells (a rolled or foreshortened quad reaches past its cell's corners; outside is empty).
bool insideCell(vec2 puff, float lod) {
  float halfTexels = 0.5 * uAtlasGeom.z - 0.5 * exp2(ceil(lod));
  return all(lessThanEqual(abs(puff) * uAtlasScale.x, vec2(halfTexels)));
}

// Per atlas cell, from the CPU (NailboardRenderer::setAtlas): row `cell` of this texture holds the
// silhouette's radius (diameters) in kPolar directions from the puff's centre, counter-clockwise
// from +x of the cell, evenly spaced in diamond angle; linear filtering with wrap-around
// interpolates between directions. Marched outward from the centre, the radius is the last crossing
// of the silhouette: the star-shaped hull. The shadow volumes cut their sides along it; small
// nailboards draw their silhouette and ink band from it where the distance map runs out.
const int kPolar = 32;
layout(binding = 5) uniform sampler2D uShadowProfile;

// The silhouette's radius of cell `c` in the direction of `p` (diameters), interpolated between
// directions. Directions are indexed by the "diamond angle" (0..4 around the square |x| + |y| = 1),
// which needs one division where an angle needs atan; the CPU builds the table the same way.
float silhouetteRadius(int c, vec2 p) {
  float q;
  if (p.y >= 0.0) {
    q = p.x >= 0.0 ? p.y / (p.x + p.y + 1e-20) : 1.0 - p.x / (p.y - p.x);
  } else {
    q = p.x < 0.0 ? 2.0 - p.y / (-p.x - p.y) : 3.0 + p.x / (p.x - p.y);
  }
  float row = (float(c) + 0.5) / float(max(1, uAtlasLayout.x * uAtlasLayout.y));
  return texture(uShadowProfile, vec2(q * 0.25 + 0.5 / float(kPolar), row)).r;
}
