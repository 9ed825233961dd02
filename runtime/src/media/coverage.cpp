#include <puff/media/coverage.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include <puff/shader_blocks.h>

namespace puff::media {

PixelBox unite(const PixelBox& a, const PixelBox& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

PixelBox grow(const PixelBox& box, int pixels, int width, int height) {
  if (box.empty()) return box;
  PixelBox g{std::max(0, box.x0 - pixels), std::max(0, box.y0 - pixels), std::min(width, box.x1 + pixels),
             std::min(height, box.y1 + pixels)};
  return g.empty() ? PixelBox{} : g;
}

namespace {

// Screen extent (NDC) of points accumulated one at a time; `whole` once any bound is unbounded.
struct Extent {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  bool whole = false;
  void add(const glm::dmat4& proj, const glm::dvec3& p) {
    const glm::dvec4 c = proj * glm::dvec4(p, 1.0);
    if (!(c.w > 0.0)) {
      whole = true;
      return;
    }
    x0 = std::min(x0, c.x / c.w), x1 = std::max(x1, c.x / c.w);
    y0 = std::min(y0, c.y / c.w), y1 = std::max(y1, c.y / c.w);
  }
};

// A bound of the quads billboard.vert draws for a sphere at camera-space centre `c`, radius `r` (its
// four corners into `e`: the quad it draws for a projection of another form, holding the silhouette's
// box it draws for the usual one), or the whole frame where it reaches the camera's plane.
void addSphere(Extent& e, const glm::dmat4& proj, bool ortho, const glm::dvec3& c, double r) {
  const double dz = -c.z, zq = dz + r;
  glm::dvec2 centre{c.x, c.y};
  double h = r;
  if (!ortho) {
    if (dz - r < 0.05 * dz) {
      e.whole = true;
      return;
    }
    h = zq * r / (dz - r) * (1.0 + glm::length(glm::dvec2(c.x, c.y)) / dz);
    centre *= zq / dz;
  }
  for (const glm::dvec2 corner : {glm::dvec2(-1, -1), glm::dvec2(1, -1), glm::dvec2(-1, 1), glm::dvec2(1, 1)})
    e.add(proj, glm::dvec3(centre + h * corner, -zq));
}

}  // namespace

PixelBox coverage(const Frame& frame, std::span<const Particle> particles, std::span<const ExplosionLight> lights) {
  const glm::dmat4 view(frame.view), proj(frame.projection);
  Extent e;
  for (const Particle& p : particles) {
    const double r = p.radius;
    const glm::dvec3 c(view * glm::dvec4(glm::dvec3(p.position), 1.0));
    // billboard.vert draws nothing for these.
    if (!(r > 0.0) || -c.z + r < frame.nearPlane || -c.z - r > frame.farPlane) continue;
    addSphere(e, proj, frame.orthographic(), c, r);
    if (e.whole) break;
  }
  int shining = 0;
  for (const ExplosionLight& l : lights) {
    if (e.whole || shining == shader::kMaxLights) break;
    if (!(l.intensity > 0.0f) || !(l.radius > 0.0f)) continue;  // as the compose block takes them
    ++shining;
    addSphere(e, proj, frame.orthographic(), glm::dvec3(view * glm::dvec4(glm::dvec3(l.center), 1.0)), l.radius);
  }
  const int w = frame.viewport.width, h = frame.viewport.height;
  if (e.whole) return {0, 0, w, h};
  if (!(e.x0 <= e.x1) || !(e.y0 <= e.y1)) return {};
  // NDC to pixels, rounded out and grown by one (the rasterizer's and the float maths' slack).
  auto px = [](double ndc, int size) {
    return std::clamp((ndc * 0.5 + 0.5) * size, -1.0, static_cast<double>(size) + 1.0);
  };
  const PixelBox box{static_cast<int>(std::floor(px(e.x0, w))), static_cast<int>(std::floor(px(e.y0, h))),
                     static_cast<int>(std::ceil(px(e.x1, w))), static_cast<int>(std::ceil(px(e.y1, h)))};
  return grow(box, 1, w, h);
}

}  // namespace puff::media
