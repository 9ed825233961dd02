// The primitive shapes scene objects are made of, shared by every path and the colliders.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include <puff/mesh/mesh.h>

namespace puff::mesh {

TriMesh makePlane() {
  TriMesh m;
  m.positions = {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}};
  m.normals.assign(4, glm::vec3(0, 1, 0));
  m.triangles = {{0, 1, 2}, {0, 2, 3}};  // counter-clockwise seen from +y
  return m;
}

TriMesh makeBox() {
  TriMesh m;
  // Per face: the outward normal n and two axes u, v with u x v = n, so the quad n + s u + t v
  // taken (s, t) = (-1,-1), (1,-1), (1,1), (-1,1) is counter-clockwise from outside.
  const glm::vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  const glm::vec3 faces[6][3] = {{x, y, z}, {-x, z, y}, {y, z, x}, {-y, x, z}, {z, x, y}, {-z, y, x}};
  const float st[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (const auto& [n, u, v] : faces) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (const auto& [s, t] : st) {
      m.positions.push_back(n + s * u + t * v);
      m.normals.push_back(n);
    }
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
  }
  return m;
}

TriMesh makeSphere(int segments) {
  segments = std::clamp(segments, 3, 4096);
  const int rings = std::max(2, segments / 2);
  TriMesh m;
  // Poles are single vertices; the rings in between hold `segments` vertices each (no seam
  // duplicates: the mesh has no texture coordinates).
  auto ring = [&](int i) {  // first vertex of ring i in [1, rings - 1]
    return static_cast<std::uint32_t>(1 + (i - 1) * segments);
  };
  m.positions.emplace_back(0, 1, 0);
  for (int i = 1; i < rings; ++i) {
    const double theta = std::numbers::pi * i / rings;  // from +y
    for (int j = 0; j < segments; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / segments;
      m.positions.emplace_back(static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
                               static_cast<float>(-std::sin(theta) * std::sin(phi)));
    }
  }
  m.positions.emplace_back(0, -1, 0);
  const auto south = static_cast<std::uint32_t>(m.positions.size() - 1);
  m.normals = m.positions;  // the unit sphere's normal is its position
  // phi grows counter-clockwise seen from +y (x toward -z), so seen from outside a quad
  // (i, j), (i+1, j), (i+1, j+1), (i, j+1) runs counter-clockwise.
  for (int j = 0; j < segments; ++j) {
    const auto j0 = static_cast<std::uint32_t>(j), j1 = static_cast<std::uint32_t>((j + 1) % segments);
    m.triangles.push_back({0u, ring(1) + j0, ring(1) + j1});
    for (int i = 1; i + 1 < rings; ++i) {
      const std::uint32_t a = ring(i), b = ring(i + 1);
      m.triangles.push_back({a + j0, b + j0, b + j1});
      m.triangles.push_back({a + j0, b + j1, a + j1});
    }
    m.triangles.push_back({ring(rings - 1) + j0, south, ring(rings - 1) + j1});
  }
  return m;
}

}  // namespace puff::mesh
