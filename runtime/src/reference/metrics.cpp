// Image metrics (metrics.h): error, coverage, second differences in time, jumps in space.
#include <algorithm>
#include <cmath>
#include <limits>

#include <puff/core/error.h>
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

}  // namespace puff::reference
