// Image metrics (metrics.h): error, SSIM, coverage, second differences in time, jumps in space,
// and the media and clip-band masks.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include <puff/core/error.h>
#include <puff/reference/media_reference.h>
#include <puff/reference/metrics.h>

namespace puff::reference {

namespace {

void checkSameSize(const core::Image& a, const core::Image& b) {
  PUFF_CHECK(a.width == b.width && a.height == b.height);
  PUFF_CHECK(a.channels >= 3 && b.channels >= 3);
  PUFF_CHECK(a.pixels.size() == static_cast<std::size_t>(a.width) * a.height * a.channels);
  PUFF_CHECK(b.pixels.size() == static_cast<std::size_t>(b.width) * b.height * b.channels);
}

std::size_t pixelCount(const core::Image& a) { return static_cast<std::size_t>(a.width) * a.height; }

}  // namespace

ImageError imageError(const core::Image& a, const core::Image& b, const std::vector<bool>& mask) {
  checkSameSize(a, b);
  const std::size_t n = pixelCount(a);
  PUFF_CHECK(mask.empty() || mask.size() == n);
  double sum = 0.0, worst = 0.0;
  std::size_t counted = 0;
  for (std::size_t p = 0; p < n; ++p) {
    if (!mask.empty() && !mask[p]) continue;
    ++counted;
    for (std::size_t c = 0; c < 3; ++c) {
      const double d = static_cast<double>(a.pixels[p * a.channels + c]) - b.pixels[p * b.channels + c];
      sum += d * d;
      worst = std::max(worst, std::abs(d));
    }
  }
  ImageError e;
  const double mse = counted ? sum / static_cast<double>(3 * counted) : 0.0;
  e.rmse = std::sqrt(mse);
  e.psnr = mse > 0.0 ? -10.0 * std::log10(mse) : std::numeric_limits<double>::infinity();
  e.maxAbs = worst;
  return e;
}

std::vector<bool> coverageMask(const core::Image& image, const core::Image& background, double threshold) {
  checkSameSize(image, background);
  const std::size_t n = pixelCount(image);
  std::vector<bool> mask(n, false);
  for (std::size_t p = 0; p < n; ++p)
    for (std::size_t c = 0; c < 3; ++c)
      if (std::abs(static_cast<double>(image.pixels[p * image.channels + c]) -
                   background.pixels[p * background.channels + c]) > threshold)
        mask[p] = true;
  return mask;
}

std::vector<bool> inkMask(const core::Image& image, const core::Image& bare, const glm::vec3& ink, double tolerance) {
  checkSameSize(image, bare);
  auto isInk = [&](const core::Image& im, std::size_t p) {
    for (std::size_t c = 0; c < 3; ++c)
      if (std::abs(static_cast<double>(im.pixels[p * im.channels + c]) - ink[static_cast<int>(c)]) > tolerance)
        return false;
    return true;
  };
  const std::size_t n = pixelCount(image);
  std::vector<bool> mask(n, false);
  for (std::size_t p = 0; p < n; ++p) mask[p] = isInk(image, p) && !isInk(bare, p);
  return mask;
}

double maskIoU(const std::vector<bool>& a, const std::vector<bool>& b) {
  PUFF_CHECK(a.size() == b.size());
  std::size_t both = 0, either = 0;
  for (std::size_t i = 0; i < a.size(); ++i) both += a[i] && b[i], either += a[i] || b[i];
  return either ? static_cast<double>(both) / static_cast<double>(either) : 1.0;
}

double coverageIoU(const core::Image& a, const core::Image& b, const core::Image& background, double threshold) {
  return maskIoU(coverageMask(a, background, threshold), coverageMask(b, background, threshold));
}

namespace {

// Calls fn(|f[k+1] - 2 f[k] + f[k-1]|) for every interior frame, pixel and RGB channel.
template <class Fn>
void secondDifferences(std::span<const core::Image> frames, Fn&& fn) {
  for (const core::Image& f : frames) checkSameSize(f, frames.front());
  for (std::size_t k = 1; k + 1 < frames.size(); ++k) {
    const core::Image &a = frames[k - 1], &b = frames[k], &c = frames[k + 1];
    const std::size_t n = pixelCount(b);
    for (std::size_t p = 0; p < n; ++p)
      for (std::size_t ch = 0; ch < 3; ++ch)
        fn(std::abs(static_cast<double>(c.pixels[p * c.channels + ch]) - 2.0 * b.pixels[p * b.channels + ch] +
                    a.pixels[p * a.channels + ch]));
  }
}

}  // namespace

double largestSecondDifference(std::span<const core::Image> frames) {
  double worst = 0.0;
  secondDifferences(frames, [&](double d) { worst = std::max(worst, d); });
  return worst;
}

double meanSecondDifference(std::span<const core::Image> frames) {
  double sum = 0.0;
  std::size_t n = 0;
  secondDifferences(frames, [&](double d) { sum += d, ++n; });
  return n ? sum / static_cast<double>(n) : 0.0;
}

double largestJump(const core::Image& image, const std::vector<bool>& region) {
  checkSameSize(image, image);
  const int w = image.width, h = image.height;
  PUFF_CHECK(region.empty() || region.size() == pixelCount(image));
  auto in = [&](int x, int y) { return region.empty() || region[static_cast<std::size_t>(y) * w + x]; };
  double worst = 0.0;
  auto pair = [&](int x0, int y0, int x1, int y1) {
    if (!in(x0, y0) || !in(x1, y1)) return;
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(static_cast<double>(image.at(x0, y0, c)) - image.at(x1, y1, c)));
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (x + 1 < w) pair(x, y, x + 1, y);
      if (y + 1 < h) pair(x, y, x, y + 1);
    }
  }
  return worst;
}

namespace {

// The paper's window: 11 taps of a Gaussian of sigma 1.5 (not normalized: the cut windows at the
// edges are normalized by the taps they keep).
constexpr int kSsimRadius = 5;
std::array<double, 2 * kSsimRadius + 1> ssimTaps() {
  std::array<double, 2 * kSsimRadius + 1> g{};
  for (int i = -kSsimRadius; i <= kSsimRadius; ++i) g[i + kSsimRadius] = std::exp(-(i * i) / (2.0 * 1.5 * 1.5));
  return g;
}

// The window's weighted mean of `v` (w x h, row-major) at every pixel: the Gaussian is separable
// and a cut window is a rectangle, so rows then columns, each normalized by the taps inside.
std::vector<double> windowMean(const std::vector<double>& v, int w, int h) {
  const auto g = ssimTaps();
  std::vector<double> rows(v.size()), out(v.size());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double s = 0.0, n = 0.0;
      for (int k = std::max(-kSsimRadius, -x); k <= std::min(kSsimRadius, w - 1 - x); ++k) {
        s += g[k + kSsimRadius] * v[static_cast<std::size_t>(y) * w + x + k];
        n += g[k + kSsimRadius];
      }
      rows[static_cast<std::size_t>(y) * w + x] = s / n;
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double s = 0.0, n = 0.0;
      for (int k = std::max(-kSsimRadius, -y); k <= std::min(kSsimRadius, h - 1 - y); ++k) {
        s += g[k + kSsimRadius] * rows[static_cast<std::size_t>(y + k) * w + x];
        n += g[k + kSsimRadius];
      }
      out[static_cast<std::size_t>(y) * w + x] = s / n;
    }
  }
  return out;
}

}  // namespace

std::vector<double> ssimMap(const core::Image& a, const core::Image& b) {
  checkSameSize(a, b);
  const int w = a.width, h = a.height;
  const std::size_t n = pixelCount(a);
  constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;
  std::vector<double> map(n, 0.0);
  std::vector<double> va(n), vb(n), aa(n), bb(n), ab(n);
  for (std::size_t c = 0; c < 3; ++c) {
    for (std::size_t p = 0; p < n; ++p) {
      va[p] = a.pixels[p * a.channels + c];
      vb[p] = b.pixels[p * b.channels + c];
      aa[p] = va[p] * va[p], bb[p] = vb[p] * vb[p], ab[p] = va[p] * vb[p];
    }
    const auto ma = windowMean(va, w, h), mb = windowMean(vb, w, h);
    const auto maa = windowMean(aa, w, h), mbb = windowMean(bb, w, h), mab = windowMean(ab, w, h);
    for (std::size_t p = 0; p < n; ++p) {
      const double sa = maa[p] - ma[p] * ma[p], sb = mbb[p] - mb[p] * mb[p], sab = mab[p] - ma[p] * mb[p];
      map[p] += (2.0 * ma[p] * mb[p] + kC1) * (2.0 * sab + kC2) /
                ((ma[p] * ma[p] + mb[p] * mb[p] + kC1) * (sa + sb + kC2)) / 3.0;
    }
  }
  return map;
}

double ssim(const core::Image& a, const core::Image& b, const std::vector<bool>& mask) {
  const std::vector<double> map = ssimMap(a, b);
  PUFF_CHECK(mask.empty() || mask.size() == map.size());
  double sum = 0.0;
  std::size_t counted = 0;
  for (std::size_t p = 0; p < map.size(); ++p) {
    if (!mask.empty() && !mask[p]) continue;
    sum += map[p];
    ++counted;
  }
  return counted ? sum / static_cast<double>(counted) : 1.0;
}

std::vector<bool> mediaMask(const core::Image& layer, double epsilon) {
  PUFF_CHECK(layer.channels >= 4);
  PUFF_CHECK(layer.pixels.size() == pixelCount(layer) * layer.channels);
  const std::size_t n = pixelCount(layer);
  std::vector<bool> mask(n, false);
  for (std::size_t p = 0; p < n; ++p) {
    const float* v = &layer.pixels[p * layer.channels];
    mask[p] = v[3] < 1.0 - epsilon || v[0] > epsilon || v[1] > epsilon || v[2] > epsilon;
  }
  return mask;
}

ClipBand clipBand(std::span<const float> depth, std::span<const media::Particle> particles, const media::Frame& frame,
                  int width) {
  const int w = frame.viewport.width, h = frame.viewport.height;
  PUFF_CHECK(w >= 1 && h >= 1 && width >= 0);
  const std::size_t n = static_cast<std::size_t>(w) * h;
  PUFF_CHECK(depth.empty() || depth.size() == n);
  struct Sphere {
    glm::dvec3 centre;
    double r;
  };
  std::vector<Sphere> spheres;
  const glm::dmat4 view(frame.view);
  for (const media::Particle& p : particles)
    if (p.radius > 0.0f) spheres.push_back({glm::dvec3(view * glm::dvec4(glm::dvec3(p.position), 1.0)), p.radius});
  const double near = frame.nearPlane, range = static_cast<double>(frame.farPlane) - frame.nearPlane;
  ClipBand out;
  out.surface.assign(n, false);
  out.nearPlane.assign(n, false);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const std::size_t at = static_cast<std::size_t>(j) * w + i;           // row 0 at the bottom
      const std::size_t top = static_cast<std::size_t>(h - 1 - j) * w + i;  // row 0 at the top
      const Ray ray = pixelRay(frame, i, j);
      const double cosA = -ray.direction.z, oz = -ray.origin.z;
      const double lin = depth.empty() ? 1.0 : depth[at];
      const double tScene = lin >= 1.0 ? std::numeric_limits<double>::infinity() : (near + lin * range - oz) / cosA;
      const double tNear = (near - oz) / cosA;
      for (const Sphere& s : spheres) {
        const glm::dvec3 m = ray.origin - s.centre;
        const double b = glm::dot(m, ray.direction);
        const glm::dvec3 across = glm::cross(m, ray.direction);
        const double d2 = glm::dot(across, across);
        if (d2 >= s.r * s.r) continue;
        const double half = std::sqrt(s.r * s.r - d2), tF = -b - half, tB = -b + half;
        if (tF < tScene && tScene < tB) out.surface[top] = true;
        if (tF < tNear && tNear < tB) out.nearPlane[top] = true;
      }
    }
  }
  // The band: every pixel within `width` of a clipped one (rows, then columns: a square).
  std::vector<bool> rows(n, false);
  out.band.assign(n, false);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t at = static_cast<std::size_t>(y) * w + x;
      if (!out.surface[at] && !out.nearPlane[at]) continue;
      for (int k = std::max(0, x - width); k <= std::min(w - 1, x + width); ++k)
        rows[static_cast<std::size_t>(y) * w + k] = true;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!rows[static_cast<std::size_t>(y) * w + x]) continue;
      for (int k = std::max(0, y - width); k <= std::min(h - 1, y + width); ++k)
        out.band[static_cast<std::size_t>(k) * w + x] = true;
    }
  return out;
}

}  // namespace puff::reference
