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

// What a texel is resolved from: the samples, which the puff covers, and their signed distances.
struct SampleView {
  const SampleBuffer& samples;
  const std::vector<std::uint8_t>& inside;
  const std::vector<float>& signedSamples;
  int n, ss;
  float flangeSamples;
  bool back;
};

// The sums over one texel's samples that its values in the maps are made of.
struct TexelSums {
  glm::vec3 normalSum{0.0f}, colorSum{0.0f};
  float depthSum = 0.0f, distSum = 0.0f;
  int bodyCount = 0, dilatedCount = 0;
  // The back map: the farthest of the covered samples' farthest crossings (each the far side
  // of the last run of puff along its ray), so nothing of the puff lies beyond it.
  float farthest = 1.0f;
};

// Sums texel (tx, ty)'s ss x ss samples: the body's and the flange's, each into what it adds to.
TexelSums sumTexel(const SampleView& v, int tx, int ty) {
  TexelSums s;
  for (int sy = 0; sy < v.ss; ++sy) {
    for (int sx = 0; sx < v.ss; ++sx) {
      const std::size_t i = static_cast<std::size_t>(ty * v.ss + sy) * v.n + (tx * v.ss + sx);
      s.distSum += v.signedSamples[i];
      if (v.inside[i]) {
        ++s.bodyCount;
        ++s.dilatedCount;
        const glm::vec4& nd = v.samples.normalDepth[i];
        s.normalSum += glm::vec3(nd);
        s.depthSum += nd.w * 0.5f;  // camera z in unit-sphere radii -> puff diameters
        s.colorSum += glm::vec3(v.samples.color[i]);
        if (v.back) s.farthest = std::min(s.farthest, v.samples.back[i] * 0.5f);  // radii -> diameters
      } else if (v.flangeSamples > 0.0f && v.signedSamples[i] <= v.flangeSamples) {
        ++s.dilatedCount;  // flange: d = 0, facing the viewer (its colour is carried out by carryColourOut)
        s.normalSum += glm::vec3(0.0f, 0.0f, 1.0f);
      }
    }
  }
  return s;
}

// Writes texel (tx, ty) of each map from its sums; perTexel is 1 over its samples.
void writeTexel(const TexelSums& s, int tx, int ty, float perTexel, const SampleView& v, CellMaps& out) {
  glm::vec3 normal(0.0f, 0.0f, 1.0f), color(0.0f);
  float depth = 0.0f;
  if (s.dilatedCount > 0) {
    const float inv = 1.0f / static_cast<float>(s.dilatedCount);
    if (glm::length(s.normalSum) > 1e-6f) normal = glm::normalize(s.normalSum);
    depth = s.depthSum * inv;
  }
  if (s.bodyCount > 0) color = s.colorSum / static_cast<float>(s.bodyCount);  // the puff's own colour
  out.normalDepth.at(tx, ty, 0) = normal.x;
  out.normalDepth.at(tx, ty, 1) = normal.y;
  out.normalDepth.at(tx, ty, 2) = normal.z;
  out.normalDepth.at(tx, ty, 3) = depth;
  out.color.at(tx, ty, 0) = color.r;
  out.color.at(tx, ty, 1) = color.g;
  out.color.at(tx, ty, 2) = color.b;
  out.color.at(tx, ty, 3) = static_cast<float>(s.dilatedCount) * perTexel;
  out.body.at(tx, ty) = static_cast<float>(s.bodyCount) * perTexel;
  out.distance.at(tx, ty) = s.distSum * perTexel / static_cast<float>(v.ss);
  if (v.back && s.bodyCount > 0) out.back.at(tx, ty) = s.farthest;
}

// The cell's maps, texels x texels, all zero; the back map (kNoBack) only when `back`.
CellMaps makeCellMaps(int texels, bool back) {
  CellMaps out;
  out.normalDepth = core::Image(texels, texels, 4);
  out.color = core::Image(texels, texels, 4);
  out.distance = core::Image(texels, texels, 1);
  out.body = core::Image(texels, texels, 1);
  if (back) out.back = core::Image(texels, texels, 1, kNoBack);
  return out;
}

// Which texels of the body map the puff covers at all.
std::vector<std::uint8_t> coveredTexels(const core::Image& body, int texels) {
  std::vector<std::uint8_t> covered(static_cast<std::size_t>(texels) * texels);
  for (int y = 0; y < texels; ++y) {
    for (int x = 0; x < texels; ++x) covered[static_cast<std::size_t>(y) * texels + x] = body.at(x, y) > 0.0f;
  }
  return covered;
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

  const bool back = !samples.back.empty();
  CellMaps out = makeCellMaps(texels, back);
  const SampleView view{samples, inside, signedSamples, n, ss, flangeSamples, back};
  const float perTexel = 1.0f / static_cast<float>(ss * ss);
  core::parallelFor(
      static_cast<std::size_t>(texels),
      [&](std::size_t row) {
        const int ty = static_cast<int>(row);
        for (int tx = 0; tx < texels; ++tx) writeTexel(sumTexel(view, tx, ty), tx, ty, perTexel, view, out);
      },
      4);
  carryColourOut(out.color, coveredTexels(out.body, texels));
  return out;
}

}  // namespace puff::bake
