// What the bake tests share: the sources of a unit sphere puff, and pi.
#pragma once

#include <cstddef>
#include <vector>

#include <puff/bake/baker.h>
#include <puff/mesh/mesh.h>

namespace puff::bake {

inline constexpr double kPi = 3.14159265358979323846;

inline std::vector<PuffSource> sphereSources(int count = 1, int subdivisions = 6) {
  std::vector<PuffSource> s(static_cast<std::size_t>(count));
  for (auto& src : s) {
    src.mesh = mesh::generateSphere({subdivisions});
    src.provenance.generator = "sphere";
    src.provenance.faces = src.mesh.faceCount();
  }
  return s;
}

}  // namespace puff::bake
