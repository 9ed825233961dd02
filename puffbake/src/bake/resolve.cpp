#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <puff/bake/maps.h>
#include <puff/support/parallel.h>

namespace puff::bake {

namespace {
// Stand-in for "no silhouette anywhere" so averages stay finite.
constexpr float kFar = 1.0e6f;

// Distance from each sample centre to the nearest sample of the other kind, made into a
// signed distance to the boundary that lies half a sample before that neighbour.
std::vector<float> signedSampleDistances(const std::vector<std::uint8_t>& inside,
                                         const std::vector<std::uint8_t>& outside, int n) {
  const std::size_t count = static_cast<std::size_t>(n) * n;
  const std::vector<float> toInside = squaredDistanceTransform(inside, n, n);
  const std::vector<float> toOutside = squaredDistanceTransform(outside, n, n);
  std::vector<float> signedSamples(count);
  core::parallelFor(
      count,
      [&](std::size_t i) {
        const float sq = inside[i] ? toOutside[i] : toInside[i];
        const float dist = std::isfinite(sq) ? std::sqrt(sq) - 0.5f : kFar;
        signedSamples[i] = inside[i] ? -dist : dist;
      },
      1 << 16);
  return signedSamples;
}

// Carries the colour of the texels the puff covers out over the rest of the cell: each empty
// texel takes the colour of the covered texel nearest it (Euclidean; nearest positions propagated
// in two raster passes, as in 8SSEDT). A filtered read at the silhouette, at any mip level, then
// mixes the puff's own colour instead of the black around it, which darkened the body's edge by
// about a fifth of a pixel at every size. Coverage (alpha) is untouched.
void carryColourOut(core::Image& color, const std::vector<std::uint8_t>& covered) {
  const int w = color.width, h = color.height;
  constexpr int kNone = -1;
  std::vector<glm::ivec2> nearest(static_cast<std::size_t>(w) * h, glm::ivec2(kNone));
  auto at = [&](int x, int y) -> glm::ivec2& { return nearest[static_cast<std::size_t>(y) * w + x]; };
  bool any = false;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (covered[static_cast<std::size_t>(y) * w + x]) {
        at(x, y) = {x, y};
        any = true;
      }
    }
  }
  if (!any) return;
  auto d2 = [](glm::ivec2 a, int x, int y) {
    const long dx = a.x - x, dy = a.y - y;
    return dx * dx + dy * dy;
  };
  auto offer = [&](int x, int y, int nx, int ny) {
    if (nx < 0 || ny < 0 || nx >= w || ny >= h) return;
    const glm::ivec2 cand = at(nx, ny);
    if (cand.x == kNone) return;
    glm::ivec2& mine = at(x, y);
    if (mine.x == kNone || d2(cand, x, y) < d2(mine, x, y)) mine = cand;
  };
  for (int y = 0; y < h; ++y) {  // down: from above and the left, then from the right
    for (int x = 0; x < w; ++x) {
      offer(x, y, x - 1, y);
      offer(x, y, x - 1, y - 1);
      offer(x, y, x, y - 1);
      offer(x, y, x + 1, y - 1);
    }
    for (int x = w - 1; x >= 0; --x) offer(x, y, x + 1, y);
  }
  for (int y = h - 1; y >= 0; --y) {  // up: from below and the right, then from the left
    for (int x = w - 1; x >= 0; --x) {
      offer(x, y, x + 1, y);
      offer(x, y, x + 1, y + 1);
      offer(x, y, x, y + 1);
      offer(x, y, x - 1, y + 1);
    }
    for (int x = 0; x < w; ++x) offer(x, y, x - 1, y);
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (covered[static_cast<std::size_t>(y) * w + x]) continue;
      const glm::ivec2 src = at(x, y);
      for (int c = 0; c < 3; ++c) color.at(x, y, c) = color.at(src.x, src.y, c);
    }
  }
}

}  // namespace

CellMaps resolveCell(const SampleBuffer& samples, int supersample, float flangeTexels) {
  const int ss = supersample;
  const int n = samples.size;
  PUFF_CHECK(ss >= 1 && n % ss == 0);
  const int texels = n / ss;
  const std::size_t count = static_cast<std::size_t>(n) * n;

  std::vector<std::uint8_t> inside(count), outside(count);
  for (std::size_t i = 0; i < count; ++i) {
    inside[i] = samples.color[i].a > 0.5f;
    outside[i] = !inside[i];
  }
  const std::vector<float> signedSamples = signedSampleDistances(inside, outside, n);
  const float flangeSamples = flangeTexels * static_cast<float>(ss);

  CellMaps out;
  out.normalDepth = core::Image(texels, texels, 4);
  out.color = core::Image(texels, texels, 4);
  out.distance = core::Image(texels, texels, 1);
  out.body = core::Image(texels, texels, 1);
  const bool back = !samples.back.empty();
  if (back) out.back = core::Image(texels, texels, 1, kNoBack);
  const float perTexel = 1.0f / static_cast<float>(ss * ss);
  core::parallelFor(
      static_cast<std::size_t>(texels),
      [&](std::size_t row) {
        const int ty = static_cast<int>(row);
        for (int tx = 0; tx < texels; ++tx) {
          glm::vec3 normalSum(0.0f), colorSum(0.0f);
          float depthSum = 0.0f, distSum = 0.0f;
          int bodyCount = 0, dilatedCount = 0;
          // The back map: the farthest of the covered samples' farthest crossings (each the far side
          // of the last run of puff along its ray), so nothing of the puff lies beyond it.
          float farthest = 1.0f;
          for (int sy = 0; sy < ss; ++sy) {
            for (int sx = 0; sx < ss; ++sx) {
              const std::size_t i = static_cast<std::size_t>(ty * ss + sy) * n + (tx * ss + sx);
              distSum += signedSamples[i];
              if (inside[i]) {
                ++bodyCount;
                ++dilatedCount;
                const glm::vec4& nd = samples.normalDepth[i];
                normalSum += glm::vec3(nd);
                depthSum += nd.w * 0.5f;  // camera z in unit-sphere radii -> puff diameters
                colorSum += glm::vec3(samples.color[i]);
                if (back) farthest = std::min(farthest, samples.back[i] * 0.5f);  // radii -> diameters
              } else if (flangeSamples > 0.0f && signedSamples[i] <= flangeSamples) {
                ++dilatedCount;  // flange: d = 0, facing the viewer (its colour is carried out below)
                normalSum += glm::vec3(0.0f, 0.0f, 1.0f);
              }
            }
          }
          glm::vec3 normal(0.0f, 0.0f, 1.0f), color(0.0f);
          float depth = 0.0f;
          if (dilatedCount > 0) {
            const float inv = 1.0f / static_cast<float>(dilatedCount);
            if (glm::length(normalSum) > 1e-6f) normal = glm::normalize(normalSum);
            depth = depthSum * inv;
          }
          if (bodyCount > 0) color = colorSum / static_cast<float>(bodyCount);  // the puff's own colour
          out.normalDepth.at(tx, ty, 0) = normal.x;
          out.normalDepth.at(tx, ty, 1) = normal.y;
          out.normalDepth.at(tx, ty, 2) = normal.z;
          out.normalDepth.at(tx, ty, 3) = depth;
          out.color.at(tx, ty, 0) = color.r;
          out.color.at(tx, ty, 1) = color.g;
          out.color.at(tx, ty, 2) = color.b;
          out.color.at(tx, ty, 3) = static_cast<float>(dilatedCount) * perTexel;
          out.body.at(tx, ty) = static_cast<float>(bodyCount) * perTexel;
          out.distance.at(tx, ty) = distSum * perTexel / static_cast<float>(ss);
          if (back && bodyCount > 0) out.back.at(tx, ty) = farthest;
        }
      },
      4);
  std::vector<std::uint8_t> covered(static_cast<std::size_t>(texels) * texels);
  for (int y = 0; y < texels; ++y) {
    for (int x = 0; x < texels; ++x) covered[static_cast<std::size_t>(y) * texels + x] = out.body.at(x, y) > 0.0f;
  }
  carryColourOut(out.color, covered);
  return out;
}

}  // namespace puff::bake
