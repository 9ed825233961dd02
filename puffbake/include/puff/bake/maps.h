// The CPU half of baking, exposed so tests and tools can check each step on its own:
// supersampled samples -> resolved cell maps (coverage, flange, signed distance) -> atlas ->
// coverage-preserving mip levels. The GL half (rasterizing a mesh into samples) is raster.h.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <puff/core/image.h>

namespace puff::bake {

// ---- views ------------------------------------------------------------------------------------

enum class ViewLayout { kHemiOct, kOct };

/// Direction from the puff toward the camera for cell `index` (row-major) of a grid x grid
/// hemi-octahedral (front hemisphere, z >= 0) or octahedral (whole sphere) map. A 1x1 grid of
/// either layout is the front view (0, 0, 1). Unit length.
glm::vec3 viewDirection(ViewLayout layout, int grid, int index);

/// The rotation into a view's camera space: rows are camera right, up and `dir` (toward the
/// viewer). Up is world +y made orthogonal to dir, or -z*sign(dir.y) when dir is (anti)parallel
/// to +y.
glm::mat3 viewRotation(const glm::vec3& dir);

// ---- samples and cell maps ----------------------------------------------------------------------

/// Rasterized samples of one cell, `size` x `size`, row 0 at the top. Empty samples are all zero.
struct SampleBuffer {
  int size = 0;
  std::vector<glm::vec4> normalDepth;  ///< camera-space unit normal, camera-space z (unit-sphere radii)
  std::vector<glm::vec4> color;        ///< diffuse rgb, a = 1 where the puff covers the sample
  /// Only when rendered with the back surface (PuffRasterizer::render's `back`), else empty: the
  /// camera-space z (radii) of the farthest point where the sample's ray crosses the mesh (any
  /// surface, every run of puff along the ray: nothing of the mesh lies beyond it).
  std::vector<float> back;
};

/// A back map's value where it bounds nothing (decoded, puff diameters): beyond the unit sphere's
/// far side, so it encodes to 0.
inline constexpr float kNoBack = -1.0f;

/// One cell's maps before encoding, `size` x `size` texels, row 0 at the top.
struct CellMaps {
  core::Image normalDepth;  ///< 4 channels: N (unit, camera space), d (puff diameters, toward viewer)
  core::Image color;        ///< 4 channels: C, alpha = coverage dilated by the flange
  core::Image distance;     ///< 1 channel: signed distance to the silhouette, texels, outside > 0
  core::Image body;         ///< 1 channel: coverage of the puff itself (no flange), [0,1]
  /// 1 channel, only when the samples hold the back surface (else empty): the back map (puff/core/atlas.h).
  /// Where the texel holds the puff, the farthest of its covered samples' farthest crossings (d, puff
  /// diameters toward the viewer); elsewhere kNoBack.
  core::Image back;
};

/// Squared Euclidean distance, in samples, from each sample to the nearest sample where
/// `feature` is non-zero (Felzenszwalb & Huttenlocher's exact two-pass transform). With no
/// feature at all every value is +infinity.
std::vector<float> squaredDistanceTransform(const std::vector<std::uint8_t>& feature, int width, int height);

/// Box-filters `samples` (supersample x supersample samples per texel) into texel maps. The
/// flange dilates coverage by `flangeTexels` around the silhouette: flange samples have alpha 1,
/// C black, d 0 and N (0,0,1). Attributes are averaged over the samples inside the dilated shape;
/// the back map (when the samples hold one) takes the farthest.
CellMaps resolveCell(const SampleBuffer& samples, int supersample, float flangeTexels);

// ---- atlas and mips -----------------------------------------------------------------------------

/// Decoded atlas maps at one mip level (same channel meaning as CellMaps). `back` is empty when the
/// atlas has no back map (one view).
struct AtlasLevel {
  core::Image normalDepth, color, distance, back;
};

/// Copies a cell's maps into the atlas at texel offset (x, y).
void placeCell(AtlasLevel& atlas, const CellMaps& cell, int x, int y);

/// How many mip levels (level 0 included) a cell of `cellSize` texels gets: halving while the
/// cell size stays even and at least 8 texels.
int mipLevelCount(int cellSize);

/// Level `level` (>= 1) from level 0: coverage-weighted box filter over 2^level texels (normals
/// renormalized, distances averaged, the back map's farthest kept), then per cell the alpha is scaled so the share of
/// texels passing `alphaThreshold` matches level 0's (Castaño's coverage-preserving mipmaps), and each cell's outer
/// ring of texels is emptied so bilinear filtering never mixes two cells.
AtlasLevel buildMipLevel(const AtlasLevel& level0, int cellSize, int level, float alphaThreshold);

/// Fraction of a cell's texels whose alpha is at least `threshold`.
double coverageFraction(const core::Image& color, int cellX, int cellY, int cellSize, float threshold);

/// Encodes decoded maps for files (see puff/core/atlas.h): ((N+1)/2, d+0.5); colour unchanged;
/// distance 0.5 + dist / (2 * range).
core::Image encodeNormalDepth(const core::Image& decoded);
core::Image encodeDistance(const core::Image& decoded, float range);
/// The back map: d + 0.5, clamped to [0, 1] (kNoBack: 0).
core::Image encodeBack(const core::Image& decoded);

}  // namespace puff::bake
