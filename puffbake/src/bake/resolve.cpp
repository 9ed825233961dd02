#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include <puff/bake/maps.h>
#include <puff/core/parallel.h>

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
  const float perTexel = 1.0f / static_cast<float>(ss * ss);
  core::parallelFor(
      static_cast<std::size_t>(texels),
      [&](std::size_t row) {
        const int ty = static_cast<int>(row);
        for (int tx = 0; tx < texels; ++tx) {
          glm::vec3 normalSum(0.0f), colorSum(0.0f);
          float depthSum = 0.0f, distSum = 0.0f;
          int bodyCount = 0, dilatedCount = 0;
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
              } else if (flangeSamples > 0.0f && signedSamples[i] <= flangeSamples) {
                ++dilatedCount;  // flange: black, d = 0, facing the viewer
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
            color = colorSum * inv;
          }
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
        }
      },
      4);
  return out;
}

}  // namespace puff::bake
