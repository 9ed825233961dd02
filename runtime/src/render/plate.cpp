// The plate (output.plate): read, decoded to scene-linear, and stretched to the frame.
#include <algorithm>
#include <cmath>
#include <vector>

#include <puff/core/colour.h>
#include <puff/render/plate.h>

namespace puff::render {

Result<core::Image> loadPlate(const scene::Scene& scene) {
  PUFF_CHECK(!scene.plate.empty());
  const auto wrap = [&](const std::string& message) {
    // readImage's errors already start with the plate's path.
    return Error::at(scene.file, "/output/plate: " + message);
  };
  auto image = core::readImage(scene.plate, nullptr, kPlateLimits);
  if (!image) return wrap(image.error().message);
  const core::Image& in = *image;
  core::Image out(in.width, in.height, 4, 1.0f);
  for (int y = 0; y < in.height; ++y) {
    for (int x = 0; x < in.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float v = in.at(x, y, in.channels >= 3 ? c : 0);
        if (!std::isfinite(v)) return wrap(scene.plate.string() + ": a non-finite value");
        out.at(x, y, c) = static_cast<float>(core::srgbToLinear(double{v}));
      }
    }
  }
  return out;
}

namespace {

// Tent weights of one axis: output pixel i (of n) from source pixels (of m).
struct Taps {
  std::vector<int> first;  // per output pixel: its first tap's offset into index/weight
  std::vector<int> index;
  std::vector<float> weight;
};

Taps taps(int m, int n) {
  Taps t;
  const double scale = static_cast<double>(m) / n;
  const double radius = std::max(1.0, scale);
  for (int i = 0; i < n; ++i) {
    t.first.push_back(static_cast<int>(t.index.size()));
    const double centre = (i + 0.5) * scale - 0.5;
    const int lo = static_cast<int>(std::ceil(centre - radius)), hi = static_cast<int>(std::floor(centre + radius));
    double total = 0.0;
    const std::size_t start = t.index.size();
    for (int k = lo; k <= hi; ++k) {
      const double w = 1.0 - std::abs(k - centre) / radius;
      if (w <= 0.0) continue;
      t.index.push_back(std::clamp(k, 0, m - 1));
      t.weight.push_back(static_cast<float>(w));
      total += w;
    }
    for (std::size_t k = start; k < t.weight.size(); ++k) t.weight[k] = static_cast<float>(t.weight[k] / total);
  }
  t.first.push_back(static_cast<int>(t.index.size()));
  return t;
}

}  // namespace

core::Image resizePlate(const core::Image& linear, int width, int height) {
  PUFF_CHECK(width > 0 && height > 0 && !linear.empty());
  if (linear.width == width && linear.height == height) return linear;
  const int ch = linear.channels;
  // Rows first (width), then columns (height): separable.
  const Taps tx = taps(linear.width, width), ty = taps(linear.height, height);
  core::Image rows(width, linear.height, ch);
  for (int y = 0; y < linear.height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < ch; ++c) {
        float v = 0.0f;
        for (int k = tx.first[x]; k < tx.first[x + 1]; ++k) v += tx.weight[k] * linear.at(tx.index[k], y, c);
        rows.at(x, y, c) = v;
      }
    }
  }
  core::Image out(width, height, ch);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < ch; ++c) {
        float v = 0.0f;
        for (int k = ty.first[y]; k < ty.first[y + 1]; ++k) v += ty.weight[k] * rows.at(x, ty.index[k], c);
        out.at(x, y, c) = v;
      }
    }
  }
  return out;
}

}  // namespace puff::render
