// What the mesh tests (mesh_test.cpp, mesh_io_test.cpp) share: a mesh's signed volume, whether it is
// closed and consistently oriented, and a mesh coloured by its positions.
#pragma once

#include <puff/mesh/mesh.h>

#include <cstdint>
#include <map>
#include <utility>

#include <glm/glm.hpp>

namespace puff::test {

inline double signedVolume(const mesh::TriMesh& m) {
  double v = 0.0;
  for (const glm::uvec3& t : m.triangles)
    v += glm::dot(glm::dvec3(m.positions[t[0]]),
                  glm::cross(glm::dvec3(m.positions[t[1]]), glm::dvec3(m.positions[t[2]])));
  return v / 6.0;
}

/// Every directed edge once and its reverse once: a closed, consistently oriented 2-manifold.
inline bool closedAndOriented(const mesh::TriMesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const glm::uvec3& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : directed) {
    if (n != 1) return false;
    auto rev = directed.find({e.second, e.first});
    if (rev == directed.end() || rev->second != 1) return false;
  }
  return true;
}

/// `m` with one colour per vertex, its position mapped from [-1, 1] to [0, 1].
inline mesh::TriMesh colored(mesh::TriMesh m) {
  m.colors.clear();
  for (const glm::vec3& p : m.positions) m.colors.push_back(glm::clamp(p * 0.5f + 0.5f, 0.0f, 1.0f));
  return m;
}

}  // namespace puff::test
