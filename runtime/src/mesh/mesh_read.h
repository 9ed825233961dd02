// Puff's own readers of OBJ, OFF, PLY, STL and glTF (private to puff::mesh). OpenMesh's readers crash,
// hang or write out of bounds on malformed files (tests/fuzz/regressions: a normal given to a
// missing OBJ vertex, a PLY header that segfaults, an OFF file that never finishes), so the files are
// parsed here, with every count checked against the bytes that are left before anything is
// reserved; OpenMesh only builds the connectivity (mesh_io.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include <puff/core/error.h>
#include <puff/mesh/mesh.h>

namespace puff::mesh::detail {

enum class Format { Obj, Off, Ply, Stl, Gltf };

const char* formatName(Format f);

/// A file's vertices and polygons as it gives them, before any face is added to a mesh.
struct RawMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> colors;   ///< one per vertex, or none; [0, 1], or 0..255 in OBJ and OFF
  std::vector<glm::vec3> normals;  ///< one per vertex, or none
  /// Polygon i's corners are corners[faceStart[i] .. faceStart[i + 1]); a corner is a 0-based vertex
  /// index as the file gives it, which may be out of range (the face is then not added).
  std::vector<std::size_t> faceStart{0};
  std::vector<std::int64_t> corners;
  std::vector<std::size_t> faceLine;  ///< polygon i's line in a text file (1-based), 0 where not known
  std::size_t declaredFaces = 0;      ///< what the file says it holds (PLY strips: their triangles)
  int indexBase = 0;                  ///< how the file numbers its vertices in messages (OBJ: from 1)

  std::size_t faceCount() const { return faceStart.size() - 1; }
  void addCorner(std::int64_t v) { corners.push_back(v); }
  void endFace(std::size_t line = 0) {
    faceStart.push_back(corners.size());
    faceLine.push_back(line);
  }
};

/// validateMesh, naming triangle t's face in messages as `faceName(t)` does.
Result<void> validateMeshNamed(const TriMesh& mesh, const std::string& what,
                               const std::function<std::string(std::size_t)>& faceName);

/// Reads `path` as `format` (the caller has checked that it is a regular file within
/// kMaxMeshFileBytes). Errors are "PATH: problem", one line: "not a valid FORMAT file (detail)", or
/// a header that counts more than the file holds.
Result<RawMesh> readRawMesh(const std::filesystem::path& path, Format format);

}  // namespace puff::mesh::detail
