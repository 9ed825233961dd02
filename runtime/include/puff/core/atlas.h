// The puff atlas: the baked maps of McGuire & Fein Fig. 3 plus a signed distance map, and the
// JSON sidecar that describes them. puffbake writes it; the runtime loads atlases only through
// the sidecar, never by guessing file names.
//
// Encoding (level 0 of each map, top row first):
//   normalDepth RGBA: ((N+1)/2, d+0.5). N is the camera-space unit normal of the puff surface
//     (x right, y up, z toward the viewer). d is the surface's offset from the billboard plane,
//     toward the viewer positive, in units of the puff's diameter (the content square's width),
//     so d lies in [-0.5, 0.5]. Flange and empty texels hold N=(0,0,1), d=0.
//   color RGBA: diffuse colour C (as authored, sRGB-encoded) and coverage alpha, dilated by the
//     flange. Straight (not premultiplied) alpha. Past the silhouette, C is the colour of the
//     nearest covered texel (flange and empty texels alike, every mip level), so a filtered read at
//     the rim sees the puff's colour; the paper's Fig. 3 bakes the flange black instead, and Puff
//     draws the ink from the distance map. (An atlas whose flange texels hold black loads and
//     draws, with a slightly dark rim.)
//   distance (one channel): signed distance from the texel center to the puff's silhouette
//     (without the flange), in level-0 texels, outside positive: dist = (v - 0.5) * 2 * range.
//   back (one channel; optional: puffbake writes it for multi-view atlases): v = b + 0.5, b the offset
//     from the billboard plane (as d) of the farthest point where the texel's rays (its covered
//     samples') cross the puff's surface: the far side of the last run of puff along them, a bound
//     (nothing of the puff lies beyond it). Outside the silhouette v = 0: no bound. Each mip level
//     keeps the least of its block. The tumbling hull (docs/cel-rendering.md) reads it; it is what
//     makes a hemi-oct atlas seen from behind bound the side it faces.
// A cell is one (variation, view); the puff's unit bounding sphere projects onto the cell's
// content square, centred in the cell with `margin` texels on each side.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <puff/core/error.h>
#include <puff/core/image.h>

namespace puff::core {

inline constexpr int kAtlasFormatVersion = 1;

struct AtlasCell {
  int variation = 0;
  int view = 0;
  std::array<int, 4> rect{};   ///< x, y, width, height of the whole cell in level-0 texels (y down)
  glm::vec3 viewDir{0, 0, 1};  ///< puff-space direction from the puff toward the camera
  glm::vec3 viewUp{0, 1, 0};   ///< puff-space direction that is "up" in the cell
};

struct AtlasSource {
  /// The mesh file: absolute as given to puffbake, else relative to the sidecar's directory; empty
  /// for a generator.
  std::string path;
  std::string hash;            ///< "fnv1a64:<hex>" of the file's bytes; empty for a generator
  std::string generator;       ///< "sphere", "lumpy", "cluster", or empty for a file
  nlohmann::json params;       ///< generator parameters (seed included)
  std::size_t faces = 0;       ///< faces of the normalized source mesh
  std::size_t facesBaked = 0;  ///< faces actually rasterized (fewer when the bake decimated)
  /// Diffuse colour baked where the mesh has no vertex colours (the bake's default colour; sRGB-encoded as
  /// authored). A sidecar without it reads as white, puffbake's default.
  glm::vec3 defaultColor{1.0f};
  /// The mesh the atlas was baked from when puffbake --lod auto decimated it (fewer faces than the
  /// source): a mesh file relative to the sidecar, in the source's normalized space (unit sphere),
  /// with the normals the bake used. Empty when the bake kept the source mesh (no --lod auto).
  std::string lodMesh;
};

struct AtlasMap {
  std::vector<std::string> levels;  ///< file per mip level, level 0 first, relative to the sidecar
};

/// Limits on an atlas, checked before anything is decoded: each side of level 0 at most 16384
/// texels (GL_MAX_TEXTURE_SIZE on most GPUs, and the most puffbake bakes); each map level's file
/// exactly the size the sidecar gives that level (a file that claims more is refused from its
/// header) and at most 1 GiB.
inline constexpr int kMaxAtlasSide = 16384;
inline constexpr std::uintmax_t kMaxAtlasMapFileBytes = std::uintmax_t{1} << 30;

struct AtlasDesc {
  int formatVersion = kAtlasFormatVersion;
  /// "png" (8-bit maps, 16-bit distance) or "exr" (half float): the maps' precision. A cooked atlas
  /// (`puffbake cook`) keeps its source's value; its level files are .puffimg of the same types.
  std::string fileFormat = "png";
  int width = 0, height = 0;    ///< level-0 atlas size in texels
  int columns = 0, rows = 0;    ///< cells per row / column
  int cellSize = 0;             ///< texels per cell side
  int margin = 0;               ///< texels between the cell edge and the content square
  int contentSize = 0;          ///< cellSize - 2 * margin: texels across the puff's diameter
  int supersample = 1;          ///< samples per texel side used when rasterizing
  float depthScale = 1.0f;      ///< d in units of the puff diameter: d = (a - 0.5) * depthScale
  float flangeTexels = 0.0f;    ///< outline flange width, level-0 texels
  float distanceRange = 1.0f;   ///< distance map covers [-range, +range] level-0 texels
  float alphaThreshold = 0.5f;  ///< coverage test the mip levels preserve
  int mipLevels = 1;            ///< stored levels; cells stay apart at every one of them
  int variations = 0;
  int views = 1;                         ///< views per variation (viewGrid^2)
  int viewGrid = 1;                      ///< views form a viewGrid x viewGrid (hemi-)octahedral grid
  std::string viewLayout = "hemioct";    ///< "hemioct" (front hemisphere) or "oct" (full sphere)
  std::vector<AtlasCell> cells;          ///< variation-major: cell index = variation * views + view
  std::vector<AtlasSource> sources;      ///< one per variation
  std::map<std::string, AtlasMap> maps;  ///< "normalDepth", "color", "distance", and optionally "back"

  const AtlasCell& cell(int variation, int view) const {
    return cells.at(static_cast<std::size_t>(variation * views + view));
  }
};

nlohmann::json toJson(const AtlasDesc& desc);
/// Validates every field (sizes positive and consistent, cells inside the atlas, maps present);
/// errors name `file` and the JSON pointer of the offending field.
Result<AtlasDesc> atlasFromJson(const nlohmann::json& j, const std::filesystem::path& file = {});
/// Reads and validates a sidecar file (a source's lodMesh is checked where it is drawn: lodMeshFile).
Result<AtlasDesc> loadAtlasDesc(const std::filesystem::path& sidecar);

/// An atlas in memory: its description and every map level as float images.
struct Atlas {
  AtlasDesc desc;
  std::map<std::string, std::vector<Image>> maps;  ///< same keys as desc.maps, level 0 first
};

/// Loads the sidecar and every image it names, checking each level's size against the desc.
Result<Atlas> loadAtlas(const std::filesystem::path& sidecar);

/// The deepest level atlasFromLevel accepts: cells and margins stay whole texels (the cell size and
/// the margin divisible by 2^level) and within the stored mip levels.
int deepestAtlasLevel(const AtlasDesc& desc);

/// The atlas as it would be shipped without its `level` finest mip levels: level `level` becomes
/// level 0, and every size in texels (atlas, cells, margin, content, flange, distance range) shrinks
/// by 2^level. Same puffs, same encoding; a smaller atlas (just enough model, eval/budget.h). Level 0 is
/// the atlas itself. Errors: level outside [0, deepestAtlasLevel(desc)].
Result<Atlas> atlasFromLevel(const Atlas& atlas, int level);

/// Bytes of GL texture memory the atlas's maps take once the nailboard renderer uploads them, every
/// mip level: the packed normal, depth and distance map (RGBA8, 4 bytes a texel; the distance map has
/// no texture of its own) and the colour map (SRGB8_ALPHA8, 4 bytes, for a png atlas; RGBA16F, 8
/// bytes, for an exr one); and for a multi-view atlas the tumbling hull's field (R16F, 2 bytes a
/// point of its 3D texture, hullFieldLayout).
/// cel::NailboardRenderer::textureBytes() measures the same from the GL.
std::size_t atlasTextureBytes(const AtlasDesc& desc);

/// The tumbling hull's field of a multi-view atlas (cel::NailboardRenderer; docs/cel-rendering.md,
/// "Tumbling puffs"): a grid of `side` points a side per variation, one for every two texels across
/// the puff within [32, 96], and how the variations' grids tile one 3D texture within the 2048
/// texels a side every GL 4.5 holds: `perColumn` stacked along z, `columns` such stacks along x (the
/// last one's unused places padded). Past 441 variations the grid is coarser, to fit.
struct HullFieldLayout {
  int side = 0, perColumn = 0, columns = 0;
  int width() const { return side * columns; }
  int depth() const { return side * perColumn; }
};
HullFieldLayout hullFieldLayout(const AtlasDesc& desc);

/// The absolute (or working-directory-relative) path of a source's lodMesh: beside `sidecar`.
/// Empty when the source has none.
std::filesystem::path lodMeshPath(const AtlasSource& source, const std::filesystem::path& sidecar);

/// Source `i`'s LOD mesh file (it must have one), checked to exist: the error names the sidecar and
/// /sources/i/lodMesh. Only the fixed path draws it, so loading an atlas does not ask for it.
Result<std::filesystem::path> lodMeshFile(const AtlasDesc& desc, std::size_t i, const std::filesystem::path& sidecar);

}  // namespace puff::core
