#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>

#include <puff/bake/baker.h>
#include <puff/support/label.h>

namespace puff::bake {

namespace {

constexpr int kColumns = 6;
constexpr const char* kColumnTitles[kColumns] = {"PREVIEW", "NORMALS", "DEPTH", "COLOUR", "COVERAGE", "DISTANCE"};
constexpr int kGap = 4;
const glm::vec3 kLabelColor(0.9f, 0.9f, 0.86f);
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
      const float band = 0.8f + 0.2f * std::cos(dist * std::numbers::pi_v<float> / 2.0f);
      const float edge = std::clamp(1.0f - std::abs(dist), 0.0f, 1.0f);
      return glm::mix(base * (1.0f - 0.6f * t) * band, glm::vec3(1.0f), edge);
    }
  }
}

// A thumbnail of one map (`column`) of the cell at `rect`, its top-left at (ox, oy). Each thumbnail
// pixel averages the block of texels it covers (cellSize / thumb on a side).
void drawThumb(core::Image& sheet, const AtlasLevel& level0, const core::AtlasDesc& desc,
               const std::array<int, 4>& rect, int column, int thumb, int ox, int oy) {
  const float scale = static_cast<float>(desc.cellSize) / static_cast<float>(thumb);
  const int block = std::max(1, static_cast<int>(std::ceil(scale)));
  for (int py = 0; py < thumb; ++py) {
    for (int px = 0; px < thumb; ++px) {
      glm::vec3 sum(0.0f);
      const int x0 = rect[0] + static_cast<int>(static_cast<float>(px) * scale);
      const int y0 = rect[1] + static_cast<int>(static_cast<float>(py) * scale);
      int n = 0;
      for (int by = y0; by < std::min(y0 + block, rect[1] + rect[3]); ++by) {
        for (int bx = x0; bx < std::min(x0 + block, rect[0] + rect[2]); ++bx) {
          sum += texelColor(level0, desc, column, bx, by, px, py);
          ++n;
        }
      }
      sum /= static_cast<float>(std::max(n, 1));
      for (int ch = 0; ch < 3; ++ch) sheet.at(ox + px, oy + py, ch) = sum[ch];
    }
  }
}

core::Image blankSheet(int width, int height) {
  core::Image sheet(width, height, 3);
  for (std::size_t i = 0; i < sheet.pixels.size(); i += 3) {
    for (int ch = 0; ch < 3; ++ch) sheet.pixels[i + static_cast<std::size_t>(ch)] = kSheetBackground[ch];
  }
  return sheet;
}

}  // namespace

int frontCell(const core::AtlasDesc& desc, int variation) {
  int best = -1;
  for (std::size_t i = 0; i < desc.cells.size(); ++i) {
    const core::AtlasCell& c = desc.cells[i];
    if (c.variation != variation) continue;
    if (best < 0 || c.viewDir.z > desc.cells[static_cast<std::size_t>(best)].viewDir.z) best = static_cast<int>(i);
  }
  return best;
}

core::Image contactSheet(const AtlasLevel& level0, const core::AtlasDesc& desc, int thumb, int maxRows) {
  const int rows = std::min(desc.variations, maxRows);
  // Columns at least as wide as their titles; a margin on the left for the rows' names.
  const int pitch = std::max(thumb, core::textWidth("DISTANCE")) + 2 * kGap;
  const int margin = kGap + core::textWidth("V" + std::to_string(desc.variations - 1));
  const int header = kGap + core::textHeight() + kGap;
  const int width = margin + kGap + kColumns * pitch, height = header + rows * (thumb + kGap);
  core::Image sheet = blankSheet(width, height);
  for (int col = 0; col < kColumns; ++col) {
    core::drawText(sheet, margin + kGap + col * pitch, kGap, kColumnTitles[col], kLabelColor);
  }
  for (int row = 0; row < rows; ++row) {
    const int oy = header + row * (thumb + kGap);
    core::drawText(sheet, kGap / 2, oy + (thumb - core::textHeight()) / 2, "V" + std::to_string(row), kLabelColor);
    const int cell = frontCell(desc, row);
    if (cell < 0) continue;
    for (int col = 0; col < kColumns; ++col) {
      drawThumb(sheet, level0, desc, desc.cells[static_cast<std::size_t>(cell)].rect, col, thumb,
                margin + kGap + col * pitch, oy);
    }
  }
  return sheet;
}

core::Image viewSheet(const AtlasLevel& level0, const core::AtlasDesc& desc, int variation, int maxSide) {
  const int n = std::max(1, desc.viewGrid);
  const int label = core::textHeight() + kGap;  // the view's number (and direction) under each thumbnail
  const int thumb = std::clamp((maxSide - kGap) / n - kGap - label, 8, std::min(desc.cellSize, 256));
  const std::string title = "VARIATION " + std::to_string(variation) + ": " + std::to_string(desc.views) + " VIEWS, " +
                            desc.viewLayout + " " + std::to_string(n) + "x" + std::to_string(n) + ", SHADED PREVIEW";
  const int header = kGap + core::textHeight() + kGap;
  const int pitchX = std::max(thumb, core::textWidth("000")) + kGap, pitchY = thumb + label + kGap;
  const int width = std::max(kGap + n * pitchX, 2 * kGap + core::textWidth(title)), height = header + n * pitchY;
  core::Image sheet = blankSheet(width, height);
  core::drawText(sheet, kGap, kGap, title, kLabelColor);
  for (const core::AtlasCell& c : desc.cells) {
    if (c.variation != variation) continue;
    const int ox = kGap + (c.view % n) * pitchX, oy = header + (c.view / n) * pitchY;
    drawThumb(sheet, level0, desc, c.rect, 0, thumb, ox, oy);
    // The view's number, and where it looks from when there is room: "12 +0.71 +0.00 +0.71".
    char dir[64];
    std::snprintf(dir, sizeof dir, "%d %+.2f %+.2f %+.2f", c.view, static_cast<double>(c.viewDir.x),
                  static_cast<double>(c.viewDir.y), static_cast<double>(c.viewDir.z));
    const std::string text = core::textWidth(dir) <= pitchX - kGap ? dir : std::to_string(c.view);
    core::drawText(sheet, ox, oy + thumb + kGap / 2, text, kLabelColor);
  }
  return sheet;
}

}  // namespace puff::bake
