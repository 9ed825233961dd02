#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include <puff/bake/maps.h>

namespace puff::bake {

glm::vec3 viewDirection(ViewLayout layout, int grid, int index) {
  PUFF_CHECK(grid >= 1 && index >= 0 && index < grid * grid);
  const int col = index % grid, row = index / grid;
  // Cell centres of the grid, in [-1, 1]^2.
  const float u = (2.0f * (static_cast<float>(col) + 0.5f) / static_cast<float>(grid)) - 1.0f;
  const float v = (2.0f * (static_cast<float>(row) + 0.5f) / static_cast<float>(grid)) - 1.0f;
  glm::vec3 p;
  if (layout == ViewLayout::kHemiOct) {
    // Hemi-octahedral: the square rotated 45 degrees onto the upper half of the octahedron.
    const float x = 0.5f * (u + v), y = 0.5f * (u - v);
    p = glm::vec3(x, y, 1.0f - std::abs(x) - std::abs(y));
  } else {
    p = glm::vec3(u, v, 1.0f - std::abs(u) - std::abs(v));
    if (p.z < 0.0f) {
      const float x = p.x, y = p.y;
      p.x = (1.0f - std::abs(y)) * (x >= 0.0f ? 1.0f : -1.0f);
      p.y = (1.0f - std::abs(x)) * (y >= 0.0f ? 1.0f : -1.0f);
    }
  }
  return glm::normalize(p);
}

glm::mat3 viewRotation(const glm::vec3& dir) {
  const glm::vec3 w = glm::normalize(dir);
  glm::vec3 up(0.0f, 1.0f, 0.0f);
  if (1.0f - std::abs(glm::dot(up, w)) < 1e-6f) up = glm::vec3(0.0f, 0.0f, w.y > 0.0f ? -1.0f : 1.0f);
  up = glm::normalize(up - glm::dot(up, w) * w);
  const glm::vec3 right = glm::cross(up, w);
  // glm is column-major: build the columns, transpose so the rows are the camera axes.
  return glm::transpose(glm::mat3(right, up, w));
}

void placeCell(AtlasLevel& atlas, const CellMaps& cell, int x0, int y0) {
  auto copy = [&](core::Image& dst, const core::Image& src) {
    PUFF_CHECK(dst.channels == src.channels && x0 + src.width <= dst.width && y0 + src.height <= dst.height);
    for (int y = 0; y < src.height; ++y) {
      std::copy_n(&src.pixels[src.index(0, y)], static_cast<std::size_t>(src.width) * src.channels,
                  &dst.pixels[dst.index(x0, y0 + y)]);
    }
  };
  copy(atlas.normalDepth, cell.normalDepth);
  copy(atlas.color, cell.color);
  copy(atlas.distance, cell.distance);
  if (!atlas.back.pixels.empty()) copy(atlas.back, cell.back);
}

int mipLevelCount(int cellSize) {
  int levels = 1;
  while (cellSize % 2 == 0 && cellSize / 2 >= 8) {
    cellSize /= 2;
    ++levels;
  }
  return levels;
}

core::Image encodeNormalDepth(const core::Image& decoded) {
  core::Image out = decoded;
  for (std::size_t i = 0; i < out.pixels.size(); i += 4) {
    for (int c = 0; c < 3; ++c) out.pixels[i + c] = 0.5f * (decoded.pixels[i + c] + 1.0f);
    out.pixels[i + 3] = decoded.pixels[i + 3] + 0.5f;
  }
  return out;
}

core::Image encodeBack(const core::Image& decoded) {
  core::Image out = decoded;
  for (float& v : out.pixels) v = std::clamp(v + 0.5f, 0.0f, 1.0f);
  return out;
}

core::Image encodeDistance(const core::Image& decoded, float range) {
  core::Image out = decoded;
  for (float& v : out.pixels) v = std::clamp(0.5f + v / (2.0f * range), 0.0f, 1.0f);
  return out;
}

}  // namespace puff::bake
