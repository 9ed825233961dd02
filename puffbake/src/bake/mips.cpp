#include <algorithm>
#include <cmath>
#include <functional>

#include <glm/geometric.hpp>

#include <puff/bake/maps.h>
#include <puff/core/colour.h>
#include <puff/support/parallel.h>

namespace puff::bake {

double coverageFraction(const core::Image& color, int cellX, int cellY, int cellSize, float threshold) {
  std::size_t passing = 0;
  for (int y = cellY; y < cellY + cellSize; ++y) {
    for (int x = cellX; x < cellX + cellSize; ++x) passing += color.at(x, y, 3) >= threshold;
  }
  return static_cast<double>(passing) / (static_cast<double>(cellSize) * cellSize);
}

namespace {

// No coverage: facing the viewer at the billboard plane. The colour stays: level 0 holds the puff's
// colour carried out past its silhouette (resolveCell), and a filtered read at the silhouette must
// find that, not black.
void emptyTexel(AtlasLevel& l, int x, int y) {
  const float nd[4] = {0, 0, 1, 0};
  for (int c = 0; c < 4; ++c) l.normalDepth.at(x, y, c) = nd[c];
  l.color.at(x, y, 3) = 0.0f;
}

// Scales the alpha of one cell so the share of texels at or above `threshold` matches `target`:
// the texel that should be the last to pass is lifted exactly onto the threshold.
void preserveCoverage(core::Image& color, int cx, int cy, int cellSize, float threshold, double target) {
  std::vector<float> alphas;
  alphas.reserve(static_cast<std::size_t>(cellSize) * cellSize);
  for (int y = cy; y < cy + cellSize; ++y) {
    for (int x = cx; x < cx + cellSize; ++x) {
      if (color.at(x, y, 3) > 0.0f) alphas.push_back(color.at(x, y, 3));
    }
  }
  const auto want = static_cast<std::size_t>(std::llround(target * cellSize * cellSize));
  if (want == 0 || alphas.empty()) return;
  const std::size_t m = std::min(want, alphas.size());
  std::sort(alphas.begin(), alphas.end(), std::greater<>());
  float pivot = alphas[m - 1];
  // Texels of equal alpha pass or fail together: when lifting the whole tie overshoots the
  // target by more than leaving it out undershoots, lift only what lies above it.
  const auto tieEnd = std::upper_bound(alphas.begin(), alphas.end(), pivot, std::greater<>()) - alphas.begin();
  const auto tieBegin = std::lower_bound(alphas.begin(), alphas.end(), pivot, std::greater<>()) - alphas.begin();
  if (m == want && tieBegin > 0 &&
      static_cast<std::size_t>(tieEnd) - want > want - static_cast<std::size_t>(tieBegin)) {
    pivot = alphas[static_cast<std::size_t>(tieBegin) - 1];
  }
  float scale = std::clamp(threshold / pivot, 0.25f, 64.0f);
  // Rounding may leave pivot * scale a hair under the threshold; the pivot must pass.
  while (pivot * scale < threshold && scale < 64.0f) scale = std::nextafter(scale, 64.0f);
  for (int y = cy; y < cy + cellSize; ++y) {
    for (int x = cx; x < cx + cellSize; ++x) color.at(x, y, 3) = std::min(1.0f, color.at(x, y, 3) * scale);
  }
}

}  // namespace

AtlasLevel buildMipLevel(const AtlasLevel& level0, int cellSize, int level, float alphaThreshold) {
  PUFF_CHECK(level >= 1);
  const int f = 1 << level;
  PUFF_CHECK(cellSize % f == 0 && level0.color.width % f == 0 && level0.color.height % f == 0);
  const int w = level0.color.width / f, h = level0.color.height / f, cell = cellSize / f;
  AtlasLevel out{core::Image(w, h, 4), core::Image(w, h, 4), core::Image(w, h, 1), {}};
  const bool back = !level0.back.pixels.empty();
  if (back) out.back = core::Image(w, h, 1, kNoBack);
  const float perBlock = 1.0f / static_cast<float>(f * f);
  core::parallelFor(
      static_cast<std::size_t>(h),
      [&](std::size_t row) {
        const int y = static_cast<int>(row);
        for (int x = 0; x < w; ++x) {
          float alpha = 0.0f, depth = 0.0f, dist = 0.0f;
          glm::vec3 normal(0.0f), color(0.0f), plain(0.0f);
          for (int by = y * f; by < (y + 1) * f; ++by) {
            for (int bx = x * f; bx < (x + 1) * f; ++bx) {
              const float a = level0.color.at(bx, by, 3);
              alpha += a;
              normal += a * glm::vec3(level0.normalDepth.at(bx, by, 0), level0.normalDepth.at(bx, by, 1),
                                      level0.normalDepth.at(bx, by, 2));
              depth += a * level0.normalDepth.at(bx, by, 3);
              // The map holds display values; a mip averages light (docs/colour.md).
              const glm::vec3 linear = core::srgbToLinear(
                  glm::vec3(level0.color.at(bx, by, 0), level0.color.at(bx, by, 1), level0.color.at(bx, by, 2)));
              color += a * linear;
              plain += linear;
              dist += level0.distance.at(bx, by);
            }
          }
          out.distance.at(x, y) = dist * perBlock;
          if (back) {
            // A bound: the farthest of the block's (kNoBack, the least, where any has none).
            float farthest = level0.back.at(x * f, y * f);
            for (int by = y * f; by < (y + 1) * f; ++by)
              for (int bx = x * f; bx < (x + 1) * f; ++bx) farthest = std::min(farthest, level0.back.at(bx, by));
            out.back.at(x, y) = farthest;
          }
          if (alpha <= 0.0f) {
            const glm::vec3 display = core::linearToSrgb(plain * perBlock);  // the carried-out colour
            for (int c = 0; c < 3; ++c) out.color.at(x, y, c) = display[c];
            emptyTexel(out, x, y);
            continue;
          }
          normal = glm::length(normal) > 1e-6f ? glm::normalize(normal) : glm::vec3(0, 0, 1);
          const glm::vec3 display = core::linearToSrgb(color / alpha);
          for (int c = 0; c < 3; ++c) {
            out.normalDepth.at(x, y, c) = normal[c];
            out.color.at(x, y, c) = display[c];
          }
          out.normalDepth.at(x, y, 3) = depth / alpha;
          out.color.at(x, y, 3) = alpha * perBlock;
        }
      },
      4);
  for (int cy = 0; cy < h; cy += cell) {
    for (int cx = 0; cx < w; cx += cell) {
      // The outer ring stays empty so bilinear taps at a cell's edge never reach its neighbour.
      for (int i = 0; i < cell; ++i) {
        emptyTexel(out, cx + i, cy);
        emptyTexel(out, cx + i, cy + cell - 1);
        emptyTexel(out, cx, cy + i);
        emptyTexel(out, cx + cell - 1, cy + i);
      }
      const double target = coverageFraction(level0.color, cx * f, cy * f, cellSize, alphaThreshold);
      preserveCoverage(out.color, cx, cy, cell, alphaThreshold, target);
    }
  }
  return out;
}

}  // namespace puff::bake
