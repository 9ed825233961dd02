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
  void addBox(const glm::dvec4& box) {
    x0 = std::min(x0, box.x), y0 = std::min(y0, box.y), x1 = std::max(x1, box.z), y1 = std::max(y1, box.w);
  }
};

// billboard.vert's tangentSlopes in double: the extremes of x / dz over a sphere at (cx, dz), radius
// r, the eye outside it; false when a tangent line does not run forward.
bool tangentSlopes(double cx, double dz, double r, double& lo, double& hi) {
  const double t = std::sqrt(std::max(cx * cx + dz * dz - r * r, 0.0));
  const double a = dz * t + r * cx, b = dz * t - r * cx;
  if (!(a > 0.0) || !(b > 0.0)) return false;
  lo = (cx * t - r * dz) / a;
  hi = (cx * t + r * dz) / b;
  return true;
}

// billboard.vert's projectedSphereBox in double: the NDC box (x0, y0, x1, y1) a sphere projects
// into through a perspective projection of the usual form; false for another form or an unbounded
// silhouette.
bool projectedSphereBox(const glm::dmat4& p, const glm::dvec3& c, double r, glm::dvec4& box) {
  const bool usual = p[1][0] == 0.0 && p[3][0] == 0.0 && p[0][1] == 0.0 && p[3][1] == 0.0 && p[0][3] == 0.0 &&
                     p[1][3] == 0.0 && p[2][3] == -1.0 && p[3][3] == 0.0 && p[0][0] > 0.0 && p[1][1] > 0.0;
  double sx0 = 0, sx1 = 0, sy0 = 0, sy1 = 0;
  if (!usual || !tangentSlopes(c.x, -c.z, r, sx0, sx1) || !tangentSlopes(c.y, -c.z, r, sy0, sy1)) return false;
  box = {p[0][0] * sx0 - p[2][0], p[1][1] * sy0 - p[2][1], p[0][0] * sx1 - p[2][0], p[1][1] * sy1 - p[2][1]};
  return true;
}

// What the billboards can change for a sphere at camera-space centre `c`, radius `r`, into `e`: for a
// perspective projection of the usual form, the box its silhouette projects into (the spherical
// quad; every method's fragments outside the sphere's disc draw nothing, and the textured quad's x
// and y reach no further than the sphere's points at the centre's depth); for any other form the
// bound billboard.vert sizes its quads by; the whole frame where it reaches the camera's plane.
void addSphere(Extent& e, const glm::dmat4& proj, bool ortho, const glm::dvec3& c, double r) {
  const double dz = -c.z, zq = dz + r;
  glm::dvec2 centre{c.x, c.y};
  double h = r;
  if (!ortho) {
    if (dz - r < 0.05 * dz) {
      e.whole = true;
      return;
    }
    if (glm::dvec4 box; projectedSphereBox(proj, c, r, box)) {
      e.addBox(box);  // the spherical quad's box (its eighth of a pixel is in the grow below)
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
