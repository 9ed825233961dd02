#include <puffview/ramp_edit.h>

#include <algorithm>
#include <numeric>

#include <glm/common.hpp>

namespace puff::view {

namespace {
glm::vec3 texel(const core::Image& image, int x, int y) {
  if (image.channels >= 3) return {image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2)};
  return glm::vec3(image.at(x, y, 0));
}
}  // namespace

RampBands normalized(RampBands bands) {
  const std::size_t n = std::min(bands.starts.size(), bands.colors.size());
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return bands.starts[a] < bands.starts[b]; });
  RampBands out;
  out.starts.clear();
  out.colors.clear();
  for (std::size_t i : order) {
    if (out.starts.size() == static_cast<std::size_t>(kMaxRampBands)) break;
    out.starts.push_back(std::clamp(bands.starts[i], 0.0f, 1.0f));
    out.colors.push_back(glm::clamp(bands.colors[i], glm::vec3(0.0f), glm::vec3(1.0f)));
  }
  if (out.starts.empty()) {
    out.starts.push_back(0.0f);
    out.colors.push_back(glm::vec3(1.0f));
  }
  out.starts[0] = 0.0f;
  return out;
}

core::Image rampImage(const RampBands& input) {
  const RampBands bands = normalized(input);
  core::Image image(kRampWidth, 1, 3);
  for (int x = 0; x < kRampWidth; ++x) {
    const float u = (static_cast<float>(x) + 0.5f) / static_cast<float>(kRampWidth);
    std::size_t band = 0;
    for (std::size_t i = 0; i < bands.starts.size(); ++i) {
      if (bands.starts[i] <= u) band = i;
    }
    for (int c = 0; c < 3; ++c) image.at(x, 0, c) = bands.colors[band][c];
  }
  return image;
}

RampBands bandsFromImage(const core::Image& image) {
  RampBands bands;
  bands.starts.clear();
  bands.colors.clear();
  if (image.width < 1 || image.height < 1) return normalized(bands);
  const int row = image.height / 2, w = image.width;
  for (int x = 0; x < w; ++x) {
    const glm::vec3 c = texel(image, x, row);
    if (bands.colors.empty() || c != bands.colors.back()) {
      bands.starts.push_back(static_cast<float>(x) / static_cast<float>(w));
      bands.colors.push_back(c);
    }
  }
  if (bands.starts.size() > static_cast<std::size_t>(kMaxRampBands)) {
    // A smooth ramp: kMaxRampBands equal bands, each the colour at its middle.
    bands.starts.clear();
    bands.colors.clear();
    for (int i = 0; i < kMaxRampBands; ++i) {
      bands.starts.push_back(static_cast<float>(i) / kMaxRampBands);
      const int x =
          std::min(w - 1, static_cast<int>((static_cast<float>(i) + 0.5f) / kMaxRampBands * static_cast<float>(w)));
      bands.colors.push_back(texel(image, x, row));
    }
  }
  return normalized(bands);
}

core::Image gradientImage(const VerticalGradient& g) {
  core::Image image(kGradientSize, kGradientSize, 3);
  for (int y = 0; y < kGradientSize; ++y) {
    const float t = (static_cast<float>(y) + 0.5f) / static_cast<float>(kGradientSize);
    const glm::vec3 c = glm::clamp(g.top + (g.bottom - g.top) * t, glm::vec3(0.0f), glm::vec3(1.0f));
    for (int x = 0; x < kGradientSize; ++x) {
      for (int ch = 0; ch < 3; ++ch) image.at(x, y, ch) = c[ch];
    }
  }
  return image;
}

VerticalGradient gradientFromImage(const core::Image& image) {
  VerticalGradient g;
  if (image.width < 1 || image.height < 1) return g;
  auto rowMean = [&](int y) {
    glm::vec3 sum(0.0f);
    for (int x = 0; x < image.width; ++x) sum += texel(image, x, y);
    return sum / static_cast<float>(image.width);
  };
  g.top = rowMean(0);
  g.bottom = rowMean(image.height - 1);
  return g;
}

bool dropRefusedCurves(scene::Scene& scene) {
  if (!scene.media) return false;
  scene::MediaSpec& m = *scene.media;
  bool dropped = false;
  for (scene::MediaEmitterSpec& e : m.emitters) {
    if (e.emitter.overLife.temperature.empty()) continue;
    const auto material = [&](int i) -> const media::Material* {
      return i >= 0 && static_cast<std::size_t>(i) < m.materials.size() ? &m.materials[static_cast<std::size_t>(i)]
                                                                        : nullptr;
    };
    const media::Material* mt = material(e.materialIndex);
    const media::Material* next = mt ? material(mt->becomes) : nullptr;
    if (mt && (mt->emissive || (next && next->emissive))) continue;
    e.emitter.overLife.temperature = {};
    dropped = true;
  }
  return dropped;
}

}  // namespace puff::view
