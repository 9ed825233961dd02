#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "shadow_profiles.h"

namespace puff::cel::detail {

namespace {

float bilinear(const core::Image& im, float x, float y, int c) {
  // Continuous texel coordinates: texel i's centre is at i + 0.5.
  x = std::clamp(x - 0.5f, 0.0f, static_cast<float>(im.width - 1));
  y = std::clamp(y - 0.5f, 0.0f, static_cast<float>(im.height - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, im.width - 1), y1 = std::min(y0 + 1, im.height - 1);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const float top = im.at(x0, y0, c) * (1 - fx) + im.at(x1, y0, c) * fx;
  const float bottom = im.at(x0, y1, c) * (1 - fx) + im.at(x1, y1, c) * fx;
  return top * (1 - fy) + bottom * fy;
}

}  // namespace

ShadowProfiles shadowProfiles(const core::Atlas& atlas) {
  const core::AtlasDesc& d = atlas.desc;
  const core::Image& dist = atlas.maps.at("distance").front();
  const float content = static_cast<float>(d.contentSize);
  const float reach = 0.5f * content + static_cast<float>(d.margin) - 1.0f;
  ShadowProfiles out;
  for (const core::AtlasCell& c : d.cells) {
    const float cx = static_cast<float>(c.rect[0] + d.margin) + 0.5f * content;
    const float cy = static_cast<float>(c.rect[1] + d.margin) + 0.5f * content;
    for (int i = 0; i < kPolar; ++i) {
      // Evenly spaced in diamond angle q in [0, 4) (shaders/cel/shadow.frag, radiusToward).
      const float q = 4.0f * static_cast<float>(i) / kPolar;
      const float u = q - std::floor(q);
      glm::vec2 dir = q < 1   ? glm::vec2(1 - u, u)
                      : q < 2 ? glm::vec2(-u, 1 - u)
                      : q < 3 ? glm::vec2(u - 1, -u)
                              : glm::vec2(u, u - 1);
      dir = glm::normalize(dir);
      const float dx = dir.x, dy = -dir.y;  // image rows go down
      auto signedDist = [&](float r) {
        return (bilinear(dist, cx + r * dx, cy + r * dy, 0) - 0.5f) * 2.0f * d.distanceRange;
      };
      float radius = 0.0f, prev = signedDist(0.0f);
      for (float r = 0.25f; r <= reach; r += 0.25f) {
        const float cur = signedDist(r);
        if (prev <= 0.0f && cur > 0.0f) radius = r - 0.25f + 0.25f * (-prev) / (cur - prev);
        prev = cur;
      }
      out.radii.push_back(radius / content);
    }
  }
  return out;
}

}  // namespace puff::cel::detail
