// Puff meshes: loading (OBJ, OFF, PLY, STL, glTF by Puff's own readers; OpenMesh builds the
// connectivity), validation, normalization to the unit bounding sphere, built-in generators,
// writing, and quadric decimation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <puff/core/error.h>

namespace puff::mesh {

/// An indexed triangle mesh ready to bake. After load/generate it is centered on the origin and
/// scaled so every vertex lies within the unit sphere, with one vertex on it; normals are unit
/// per-vertex normals (area-weighted from faces unless the file supplied them).
struct TriMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  ///< one per position, unit length
  std::vector<glm::vec3> colors;   ///< per-vertex [0,1] RGB as the file stores it (usually sRGB-encoded); empty if none
  std::vector<glm::uvec3> triangles;  ///< counter-clockwise seen from outside

  std::size_t faceCount() const { return triangles.size(); }
  bool hasColors() const { return !colors.empty(); }
};

/// What loading found and fixed, for the user's log.
struct LoadInfo {
  std::size_t sourceFaces = 0;  ///< faces in the file (polygons count once)
  std::size_t sourceVertices = 0;
  bool flippedInward = false;  ///< the mesh was oriented inward; faces were reversed
  bool hadNormals = false;
  bool hadColors = false;
  /// Faces a halfedge mesh cannot hold where they are (around a non-manifold vertex or edge), put
  /// on their own copies of their vertices. The baker only rasterizes triangles, so they bake as
  /// any face does; only smooth normals do not cross the split.
  std::size_t separatedFaces = 0;
  /// The volume the faces enclose over the volume of the mesh's bounding sphere (about the bounding
  /// box's centre): 1 for a sphere, 0 for a flat card (see kFlatVolumeFraction).
  double volumeFraction = 0.0;
};

/// Below this LoadInfo::volumeFraction a mesh is flat: it bakes as a card, with depth and normals of
/// a puff only where the mesh has them (puffbake warns). The art's cluster puffs enclose about 0.3.
inline constexpr double kFlatVolumeFraction = 0.01;

/// Whether loading moves the mesh into the unit sphere (every file a user names) or keeps the file's
/// coordinates (a level of detail puffbake wrote in its source's normalized space, which must keep
/// that scale and centre, not take its own).
enum class Normalize { kYes, kNo };

/// The largest mesh file loadMesh reads: 1 GiB (a 10-million-triangle binary PLY is ~200 MB).
inline constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t{1} << 30;

/// The formats loadMesh reads, for messages and help.
inline constexpr const char* kMeshFormatsRead = "OBJ, OFF, PLY, STL or glTF 2.0 (.gltf, .glb)";

/// Reads OBJ, OFF, PLY, STL or glTF (by extension, case-insensitive), validates and normalizes it.
/// glTF: the triangles the default scene's nodes place, in their world transforms; vertices the
/// exporter split at UV seams merged; NORMAL kept where every vertex has one; buffers from the
/// .glb, data: URIs or files beside the .gltf (no other path).
/// Errors ("FILE: problem", one line): cannot open; not a regular file; larger than
/// kMaxMeshFileBytes; not a mesh of that format; no faces;
/// non-finite vertex (names the vertex); degenerate face (zero area, names the face);
/// faces declared but not added (the file declares N faces, only M could be added: a face that
/// repeats a vertex or refers to a missing one, or a header that counts more faces than the file
/// holds); unsupported extension. Non-manifold faces are not refused: they are split onto their own
/// vertices and counted (LoadInfo::separatedFaces).
Result<TriMesh> loadMesh(const std::filesystem::path& path, LoadInfo* info = nullptr,
                         Normalize normalize = Normalize::kYes);

/// Checks a mesh: non-empty, finite, no degenerate triangles, indices in range. `what` names the
/// source in the message.
Result<void> validateMesh(const TriMesh& mesh, const std::string& what);

/// As above, for a mesh triangulated from a file's polygons: triangle i came from the file's face
/// `sourceFace[i]` (0-based, file order), and messages name that face. Empty: names triangles.
Result<void> validateMesh(const TriMesh& mesh, const std::string& what, const std::vector<std::uint32_t>& sourceFace);

/// Centers the mesh on its bounding-box center and scales it so the farthest vertex is at 1.
void normalizeToUnitSphere(TriMesh& mesh);

/// Recomputes unit area-weighted vertex normals from the faces.
void computeNormals(TriMesh& mesh);

/// Whether saveMesh writes the vertex normals: kNo leaves them to be recomputed from the faces on
/// loading; kYes writes them (PLY and OBJ only), so loading gives back exactly these.
enum class SaveNormals { kNo, kYes };

/// Writes OBJ, OFF, PLY or STL (by extension) to a temporary file, then renames it over `path`.
/// Colors are written where the format carries them (PLY, OFF, OBJ); normals with SaveNormals::kYes
/// (an error for OFF and STL).
Result<void> saveMesh(const TriMesh& mesh, const std::filesystem::path& path, SaveNormals normals = SaveNormals::kNo);

// ---- primitives ------------------------------------------------------------------------------
// Scene objects' shapes, counter-clockwise from outside, in object space (not normalized).

/// The square [-1,1]^2 in y = 0, normal +y (4 vertices).
TriMesh makePlane();
/// [-1,1]^3 with flat face normals (24 vertices).
TriMesh makeBox();
/// Unit radius, normals = positions, `segments` around (clamped to [3, 4096]) and
/// max(2, segments/2) rings, one vertex per pole.
TriMesh makeSphere(int segments = 48);

// ---- generators -------------------------------------------------------------------------------
// All are deterministic for a given seed on every platform (own PRNG and noise, no std::
// distributions), and return normalized meshes with normals and no colors. Parameters must pass
// validate() first; generating from invalid ones is a broken promise (PUFF_CHECK).

struct SphereParams {
  int subdivisions = 4;  ///< icosphere subdivision level, 0..7 (20 * 4^n faces)
};
struct LumpyParams {
  int subdivisions = 5;     ///< icosphere level, 0..7
  float amplitude = 0.22f;  ///< radial displacement as a fraction of the radius, 0..0.9
  float frequency = 1.5f;   ///< noise frequency over the unit sphere, > 0
  int octaves = 3;          ///< fractal octaves, 1..8
  std::uint64_t seed = 1;
};
struct ClusterParams {
  int count = 6;            ///< spheres in the cluster, 1..64
  float radiusMin = 0.35f;  ///< sphere radii, relative to the cluster, 0 < min <= max
  float radiusMax = 0.6f;
  float spread = 0.55f;  ///< how far sphere centers scatter from the middle, >= 0
  int subdivisions = 3;  ///< icosphere level per sphere, 0..6
  std::uint64_t seed = 1;
};

TriMesh generateSphere(const SphereParams& p);
TriMesh generateLumpy(const LumpyParams& p);
TriMesh generateCluster(const ClusterParams& p);

/// Checks generator parameters; the error names the offending parameter and its range.
Result<void> validate(const SphereParams& p);
Result<void> validate(const LumpyParams& p);
Result<void> validate(const ClusterParams& p);

// ---- generator provenance ------------------------------------------------------------------
// An atlas sidecar records a generated puff as its generator's kind and parameters, so the puff can
// be made again (the cel reference draws it). These two functions are the one owner of that record.

/// A generated puff: the generator's kind and its parameters (only the kind's own are used).
struct Generator {
  std::string kind = "lumpy";  ///< "sphere", "lumpy" or "cluster"
  SphereParams sphere;
  LumpyParams lumpy;
  ClusterParams cluster;
};
/// Whether `kind` names a generator: "sphere", "lumpy" or "cluster".
bool isGeneratorKind(const std::string& kind);
/// The kind's parameters as a JSON object (the sidecar's "params").
nlohmann::json generatorToJson(const Generator& generator);
/// The generator of `kind` with `params` read back; absent keys keep their defaults. Errors read
/// "WHERE/params/KEY: ..." or, for an unknown kind, "WHERE/generator: ...".
Result<Generator> generatorFromJson(const std::string& kind, const nlohmann::json& params, const std::string& where);
/// Checks the parameters (validate) and generates the puff.
Result<TriMesh> generate(const Generator& generator);

// ---- level of detail ------------------------------------------------------------------------

/// Where a decimated mesh's normals come from: recomputed from its (coarser) faces, or the source's
/// own normal at each kept vertex (authored normals: a halfedge collapse keeps the surviving vertex
/// where it was, so its source normal is exact there).
enum class DecimatedNormals { kRecompute, kFromSource };

/// Decimates with OpenMesh's quadric decimater (collapses that would flip a normal are refused)
/// to at most `targetFaces` faces, or as close as it can get. Colors follow the kept vertices;
/// normals are recomputed or kept as `normals` says. The input is not modified.
TriMesh decimate(const TriMesh& mesh, std::size_t targetFaces, DecimatedNormals normals = DecimatedNormals::kRecompute);

}  // namespace puff::mesh
