// puffbake's library entry points: bake puff meshes into an atlas (McGuire & Fein Fig. 3 / Eq. 1
// plus a signed distance map, mip levels, multi-view cells), its sidecar and a contact sheet.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <puff/bake/maps.h>
#include <puff/core/atlas.h>
#include <puff/core/error.h>
#include <puff/mesh/mesh.h>

namespace puff::bake {

inline constexpr int kMaxCellSize = 16384;  ///< GL_MAX_TEXTURE_SIZE on llvmpipe and most GPUs
inline constexpr int kMaxAtlasSize = core::kMaxAtlasSide;

/// Flange (outline) width: texels, or a fraction of the cell size.
struct FlangeWidth {
  float value = 0.03f;
  bool fractionOfCell = true;
  float texels(int cellSize) const { return fractionOfCell ? value * static_cast<float>(cellSize) : value; }
};

enum class MapFormat { kPng, kExr };

/// --lod auto's depth and colour tolerances (see BakeOptions). Depth: one step of the 8-bit packed
/// texture the renderer keeps d in (1/255 of a diameter); colour: one step of an 8-bit colour map.
inline constexpr float kDefaultLodDepthTolerance = 1.0f / 255.0f;
inline constexpr float kDefaultLodColorTolerance = 1.0f / 255.0f;

struct BakeOptions {
  int cellSize = 256;   ///< texels per cell side, 8..16384
  int supersample = 0;  ///< samples per texel side; 0 = auto (4, fewer above 1024^2 cells)
  FlangeWidth flange;   ///< outline flange; 0 disables it
  int viewGrid = 1;     ///< views per variation = viewGrid^2 (1: front view only)
  ViewLayout viewLayout = ViewLayout::kHemiOct;
  MapFormat format = MapFormat::kPng;
  glm::vec3 defaultColor{1.0f};  ///< diffuse colour of meshes without vertex colours
  bool mips = true;              ///< write coverage-preserving mip levels
  bool contactSheet = true;
  // Automatic level of detail: the fewest faces whose maps stay within these of the full mesh's.
  bool lodAuto = false;
  float lodNormalTolerance = 1.0f / 255.0f;             ///< mean |encoded normal| difference, per channel
  float lodSilhouetteTolerance = 1.0f;                  ///< texels between the two silhouettes
  float lodDepthTolerance = kDefaultLodDepthTolerance;  ///< mean |depth offset d| difference, puff diameters
  float lodColorTolerance = kDefaultLodColorTolerance;  ///< mean |colour| difference per channel (sRGB-encoded)
  std::filesystem::path outDir = "puff-out";
  std::string name = "puff";  ///< file prefix: NAME.json, NAME_color.HASH.png, ... (HASH: the content's)
};

/// Checks option ranges; the error names the flag, e.g. "--size must be in [8, 16384], got 0".
Result<void> validate(const BakeOptions& options, int variations);

/// One puff variation to bake, with where it came from (recorded in the sidecar).
struct PuffSource {
  mesh::TriMesh mesh;
  core::AtlasSource provenance;
  /// The mesh file gave its own vertex normals (mesh::LoadInfo::hadNormals): a level of detail keeps
  /// them (the source's normal at each kept vertex) rather than recomputing them from fewer faces.
  bool normalsAuthored = false;
  /// Non-manifold faces the mesh file's import put on their own vertices (mesh::LoadInfo).
  std::size_t separatedFaces = 0;
  /// The share of its bounding sphere the mesh file's faces enclose (mesh::LoadInfo::volumeFraction);
  /// generated puffs keep 1 (they are round).
  double volumeFraction = 1.0;
};

/// A generator and its parameters, producing `count` variations with seeds seed, seed+1, ...
struct GeneratorSpec {
  std::string kind = "lumpy";  ///< "sphere", "lumpy" or "cluster"
  mesh::SphereParams sphere;
  mesh::LumpyParams lumpy;
  mesh::ClusterParams cluster;
  int count = 4;
};

/// Progress: a stage name, steps done and total. Called from the baking thread.
using ProgressFn = std::function<void(std::string_view stage, int done, int total)>;

/// Loads mesh files (one variation each) or runs the generator. Errors name the file or flag.
/// `progress` hears "loading meshes" (files) and "generating puffs" (variations).
Result<std::vector<PuffSource>> loadSources(const std::vector<std::filesystem::path>& meshFiles,
                                            const std::optional<GeneratorSpec>& generator,
                                            const ProgressFn& progress = {});

/// What the automatic level of detail chose for one variation.
struct LodResult {
  std::size_t facesBefore = 0, facesAfter = 0;
  float normalError = 0.0f;      ///< mean |encoded normal difference| reached
  float silhouetteError = 0.0f;  ///< texels
  float depthError = 0.0f;       ///< mean |depth offset difference|, puff diameters
  float colorError = 0.0f;       ///< mean |colour difference| per channel, sRGB-encoded
  int evaluations = 0;           ///< decimate-and-compare steps the search took
};

struct BakeReport {
  core::AtlasDesc desc;
  std::filesystem::path sidecar, contactSheet;
  int contactSheetRows = 0;  ///< variations the contact sheet shows (it caps its height)
  /// Multi-view atlases: per variation, the sheet of its views (NAME_contact_vI.png, I from 0).
  std::vector<std::filesystem::path> viewSheets;
  std::vector<std::filesystem::path> files;   ///< every file written
  std::vector<std::optional<LodResult>> lod;  ///< per variation when the level of detail was automatic
  /// Per variation with --lod auto: the chosen mesh's file (the sidecar's sources[i].lodMesh).
  std::vector<std::filesystem::path> lodMeshes;
};

/// Bakes `sources` (one variation each) with the GL context that is current on this thread.
/// All outputs are staged and renamed into place only when every one is written: on failure
/// nothing in options.outDir changes.
Result<BakeReport> bakeAtlas(const std::vector<PuffSource>& sources, const BakeOptions& options,
                             const ProgressFn& progress = {});

/// Compares two cells' maps for the automatic level of detail. Over texels both cover: the mean
/// encoded-normal error per channel, the mean depth-offset error (puff diameters) and the mean
/// colour error per channel (the maps' sRGB-encoded values); and the largest difference of the two
/// distance maps near either silhouette (texels within 1 of it): how far the silhouette moved.
struct MapDifference {
  float meanNormalError = 0.0f;
  float silhouetteTexels = 0.0f;
  float meanDepthError = 0.0f;
  float meanColorError = 0.0f;
};
MapDifference compareCells(const CellMaps& reference, const CellMaps& candidate);

/// What a level of detail may change, each the largest MapDifference term allowed in any view.
struct LodTolerances {
  float normal = 1.0f / 255.0f;             ///< meanNormalError
  float silhouette = 1.0f;                  ///< silhouetteTexels
  float depth = kDefaultLodDepthTolerance;  ///< meanDepthError
  float color = kDefaultLodColorTolerance;  ///< meanColorError
};

/// Finds the fewest faces whose maps stay within the tolerances in every view (binary search over
/// the face count with OpenMesh's quadric decimater; assumes error grows as faces fall, which
/// holds for quadric decimation in practice but is not guaranteed). `rasterize` turns a mesh
/// into the cell maps of each view, without flange. `normals` says whether the candidates keep the
/// source's normals (authored ones) or recompute them. `chosen` receives the mesh picked.
LodResult chooseLod(const mesh::TriMesh& full,
                    const std::function<std::vector<CellMaps>(const mesh::TriMesh&)>& rasterize,
                    const LodTolerances& tolerances, mesh::DecimatedNormals normals, mesh::TriMesh* chosen,
                    const std::function<void(int step, int maxSteps)>& onStep = {});

/// The cell of `variation` whose view is nearest the front (+z), or -1 if it has none.
int frontCell(const core::AtlasDesc& desc, int variation);

/// The contact sheet: a row of column titles (PREVIEW: shaded with Eq. 2 and a two-tone ramp,
/// NORMALS, DEPTH, COLOUR, COVERAGE, DISTANCE), then one row per variation (the first `maxRows`),
/// named V0, V1, ... on the left (numbered from 0, as a scene's "variations" count them),
/// showing its view nearest the front. `thumb`: thumbnail pixels.
core::Image contactSheet(const AtlasLevel& level0, const core::AtlasDesc& desc, int thumb, int maxRows);

/// A multi-view atlas's `variation` as the grid of its views (view i at column i % viewGrid, row
/// i / viewGrid, as the atlas lays them out), each the shaded preview with its number and
/// direction under it, under a title; thumbnails sized so that the grid is at most about `maxSide`
/// pixels on a side.
core::Image viewSheet(const AtlasLevel& level0, const core::AtlasDesc& desc, int variation, int maxSide);

}  // namespace puff::bake
