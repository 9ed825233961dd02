#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include <puff/bake/baker.h>

namespace puff::bake {

namespace {

constexpr int kColumns = 6;  // preview, normal, depth, colour, coverage, distance
constexpr int kGap = 4;
const glm::vec3 kSheetBackground(0.18f, 0.18f, 0.2f);
const glm::vec3 kPreviewBackground(0.86f, 0.89f, 0.93f);
// Eq. 2 preview: a dusky ambient, white light from the upper left front, a two-tone ramp.
const glm::vec3 kAmbient(0.32f, 0.36f, 0.52f);
const glm::vec3 kLightDir = glm::normalize(glm::vec3(-0.5f, 0.6f, 0.65f));

glm::vec3 checker(int x, int y) { return ((x / 8 + y / 8) % 2) ? glm::vec3(0.75f) : glm::vec3(0.55f); }

// The colour a contact-sheet column shows for one level-0 texel.
glm::vec3 texelColor(const AtlasLevel& l, const core::AtlasDesc& desc, int column, int x, int y, int px, int py) {
  const glm::vec3 n(l.normalDepth.at(x, y, 0), l.normalDepth.at(x, y, 1), l.normalDepth.at(x, y, 2));
  const float d = l.normalDepth.at(x, y, 3);
  const glm::vec3 c(l.color.at(x, y, 0), l.color.at(x, y, 1), l.color.at(x, y, 2));
  const float alpha = l.color.at(x, y, 3);
  const float dist = l.distance.at(x, y);
  switch (column) {
    case 0: {
      const float q = glm::dot(n, kLightDir) >= 0.5f ? 1.0f : 0.0f;
      const float body = std::clamp(0.5f - dist, 0.0f, 1.0f);  // the flange shows black
      const glm::vec3 lit = body * (kAmbient + c * q);
      return glm::mix(kPreviewBackground, lit, alpha);
    }
    case 1:
      return 0.5f * (n + 1.0f);
    case 2:
      return glm::vec3(d + 0.5f);
    case 3:
      return glm::mix(checker(px, py), c, alpha);
    case 4:
      return glm::vec3(alpha);
    default: {
      // Distance: blue inside, orange outside, darker bands every 4 texels, white on the silhouette.
      const float t = std::clamp(std::abs(dist) / desc.distanceRange, 0.0f, 1.0f);
      const glm::vec3 base = dist < 0 ? glm::vec3(0.25f, 0.45f, 0.9f) : glm::vec3(0.95f, 0.6f, 0.2f);
      const float band = 0.8f + 0.2f * std::cos(dist * 3.14159265f / 2.0f);
      const float edge = std::clamp(1.0f - std::abs(dist), 0.0f, 1.0f);
      return glm::mix(base * (1.0f - 0.6f * t) * band, glm::vec3(1.0f), edge);
    }
  }
}

}  // namespace

core::Image contactSheet(const AtlasLevel& level0, const core::AtlasDesc& desc, int thumb, int maxCells) {
  const int rows = std::min(static_cast<int>(desc.cells.size()), maxCells);
  const int width = kGap + kColumns * (thumb + kGap), height = kGap + rows * (thumb + kGap);
  core::Image sheet(width, height, 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int ch = 0; ch < 3; ++ch) sheet.at(x, y, ch) = kSheetBackground[ch];
    }
  }
  // Each thumbnail pixel averages the block of texels it covers (cellSize / thumb on a side).
  const float scale = static_cast<float>(desc.cellSize) / static_cast<float>(thumb);
  const int block = std::max(1, static_cast<int>(std::ceil(scale)));
  for (int row = 0; row < rows; ++row) {
    const auto& rect = desc.cells[static_cast<std::size_t>(row)].rect;
    for (int col = 0; col < kColumns; ++col) {
      const int ox = kGap + col * (thumb + kGap), oy = kGap + row * (thumb + kGap);
      for (int py = 0; py < thumb; ++py) {
        for (int px = 0; px < thumb; ++px) {
          glm::vec3 sum(0.0f);
          const int x0 = rect[0] + static_cast<int>(static_cast<float>(px) * scale);
          const int y0 = rect[1] + static_cast<int>(static_cast<float>(py) * scale);
          int n = 0;
          for (int by = y0; by < std::min(y0 + block, rect[1] + rect[3]); ++by) {
            for (int bx = x0; bx < std::min(x0 + block, rect[0] + rect[2]); ++bx) {
              sum += texelColor(level0, desc, col, bx, by, px, py);
              ++n;
            }
          }
          sum /= static_cast<float>(std::max(n, 1));
          for (int ch = 0; ch < 3; ++ch) sheet.at(ox + px, oy + py, ch) = sum[ch];
        }
      }
    }
  }
  return sheet;
}

}  // namespace puff::bake
