#version 450 core
// Opaque objects' shadow volumes (z-fail, with caps). Every triangle is turned to face the light
// (one facing away is taken reversed) and swept along the direction D the light travels: a prism
// from the triangle (the light cap) to its copy moved by lambda along D (the far cap). The union of
// the prisms is the volume; where two neighbours' prisms share a side with opposite windings (both
// faced the light, or both were reversed) the sides cancel in the count and neither is drawn, so
// each triangle emits its caps and only the sides across edges where its neighbour's facing differs
// from its own: the silhouette as the light sees it, the open mesh's border (no neighbour), and
// edges next to triangles parallel to the light (which cast nothing).
//
// A closed mesh thus makes two nested volumes, from its light-facing and from its reversed far
// side; the count is 1 inside the object and 2 in its shadow: non-zero, which is all the shadowed
// pass asks. An open mesh (a plane, an open mesh file) is a shell of prisms and needs no inside.
//
// Facing is computed for a triangle's own prism and for each neighbour's by the same function of
// the same three points taken in a canonical order, so the two always agree bit for bit.
#include "common/frame.glsl"

layout(triangles_adjacency) in;
layout(triangle_strip, max_vertices = 18) out;

in vec3 vWorldPos[];  // 0, 2, 4: the triangle (counter-clockwise); 1, 3, 5: across edges 0-2, 2-4, 4-0

layout(location = PUFF_LOC_VOLUME_LENGTH) uniform float uShadowLength;  // world units
layout(location = PUFF_LOC_VOLUME_FLOOR) uniform vec4 uShadowFloor;     // world plane (n, w): volumes end just past it; n = 0: none

out float vDist;  // view-axis distance

// Rotates (a, b, c) so the lexicographically smallest point comes first; the winding is kept.
void canonical(inout vec3 a, inout vec3 b, inout vec3 c) {
  bool bFirst = b.x < a.x || (b.x == a.x && (b.y < a.y || (b.y == a.y && b.z < a.z)));
  if (bFirst) {
    vec3 t = a;
    a = b, b = c, c = t;
  }
  bool cFirst = c.x < a.x || (c.x == a.x && (c.y < a.y || (c.y == a.y && c.z < a.z)));
  if (cFirst) {
    vec3 t = c;
    c = b, b = a, a = t;
  }
}

// +1: the triangle (counter-clockwise) faces the light, -1: away, 0: parallel to it (casts nothing).
int facing(vec3 a, vec3 b, vec3 c) {
  canonical(a, b, c);
  precise vec3 n = cross(b - a, c - a);
  precise float d = dot(n, uLightDirWorld.xyz);
  precise float tol = 1e-5 * length(n);
  return d > tol ? 1 : d < -tol ? -1 : 0;
}

vec3 D;  // the direction the light travels

// Where a point's shadow ends: uShadowLength along D, or just past the floor when the floor is nearer.
vec3 extrude(vec3 p) {
  float lambda = uShadowLength;
  float dn = dot(uShadowFloor.xyz, D);
  if (dot(uShadowFloor.xyz, uShadowFloor.xyz) > 0.0 && dn < -1e-4) {
    float toFloor = (dot(uShadowFloor.xyz, p) + uShadowFloor.w) / -dn;
    lambda = clamp(toFloor + 0.01 * abs(toFloor) + 1e-3 * uShadowLength, 0.0, lambda);
  }
  return p + lambda * D;
}

void emit(vec3 p) {
  vec4 view = uView * vec4(p, 1.0);
  vDist = -view.z;
  gl_Position = uProj * view;
  EmitVertex();
}

void main() {
  D = -uLightDirWorld.xyz;
  vec3 v[3] = vec3[3](vWorldPos[0], vWorldPos[2], vWorldPos[4]);
  int f = facing(v[0], v[1], v[2]);
  if (f == 0) return;
  // Turned to face the light: counter-clockwise about the normal toward the light.
  if (f < 0) {
    vec3 t = v[1];
    v[1] = v[2], v[2] = t;
  }
  vec3 e[3] = vec3[3](extrude(v[0]), extrude(v[1]), extrude(v[2]));
  // The light cap faces the light, the far cap away: both outward.
  emit(v[0]), emit(v[1]), emit(v[2]);
  EndPrimitive();
  emit(e[0]), emit(e[2]), emit(e[1]);
  EndPrimitive();
  for (int k = 0; k < 3; ++k) {
    // Edge k of the original triangle runs from vertex k to k + 1; its neighbour is the mesh's
    // triangle (k + 1, k, across), counter-clockwise when the mesh is; no neighbour: the across
    // vertex is the triangle's own third vertex.
    vec3 a0 = vWorldPos[2 * k], a1 = vWorldPos[(2 * k + 2) % 6], across = vWorldPos[2 * k + 1];
    bool open = across == vWorldPos[(2 * k + 4) % 6];
    if (!open && facing(a1, a0, across) == f) continue;
    // The edge in the light-facing triangle's order, and its side outward.
    vec3 a = f > 0 ? a0 : a1, b = f > 0 ? a1 : a0;
    emit(a), emit(extrude(a)), emit(b), emit(extrude(b));
    EndPrimitive();
  }
}
