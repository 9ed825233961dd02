// The smoke simulator; simulator.h gives the model and the integrator.
#include <puff/sim/simulator.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include <puff/core/random.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include "curl_noise.h"

namespace puff::sim {

// ---- paths ---------------------------------------------------------------------------------------

namespace {

// The segment [i - 1, i] holding t, for times.front() < t < times.back(): compared in double, and
// clamped, so a t that rounds to the last key as a float still finds a segment.
std::size_t segmentOf(const std::vector<float>& times, double t) {
  const auto it = std::upper_bound(times.begin(), times.end(), t,
                                   [](double value, float key) { return value < static_cast<double>(key); });
  return std::clamp<std::size_t>(static_cast<std::size_t>(it - times.begin()), 1, times.size() - 1);
}

}  // namespace

glm::vec3 Path::at(double t) const {
  if (times.empty()) return glm::vec3(0.0f);
  if (t <= times.front()) return points.front();
  if (t >= times.back()) return points.back();
  const std::size_t i = segmentOf(times, t);
  const double t0 = times[i - 1], t1 = times[i];
  const float f = static_cast<float>(std::clamp((t - t0) / (t1 - t0), 0.0, 1.0));
  return glm::mix(points[i - 1], points[i], f);
}

glm::vec3 Path::velocityAt(double t) const {
  if (times.size() < 2 || t < times.front() || t >= times.back()) return glm::vec3(0.0f);
  const std::size_t i = segmentOf(times, t);
  return (points[i] - points[i - 1]) / (times[i] - times[i - 1]);
}

// ---- validation ----------------------------------------------------------------------------------

namespace {

struct Check {
  std::string error;
  bool ok() const { return error.empty(); }

  static std::string num(double d) {
    if (!std::isfinite(d)) return "a non-finite number";
    char b[32];
    std::snprintf(b, sizeof b, "%g", d);
    return b;
  }
  void fail(const std::string& ptr, const std::string& expected, double got) {
    if (error.empty()) error = ptr + ": expected " + expected + ", got " + num(got);
  }
  void finite(const std::string& ptr, float v, float limit = kMaxMagnitude) {
    if (!(std::isfinite(v) && std::abs(v) <= limit))
      fail(ptr, "a number in [-" + num(limit) + ", " + num(limit) + "]", v);
  }
  void range(const std::string& ptr, float v, float lo, float hi, bool loOpen = false) {
    const bool okLo = loOpen ? v > lo : v >= lo;
    if (!(std::isfinite(v) && okLo && v <= hi)) {
      fail(ptr, std::string("a number in ") + (loOpen ? "(" : "[") + num(lo) + ", " + num(hi) + "]", v);
    }
  }
  void vec(const std::string& ptr, const glm::vec3& v, float limit = kMaxMagnitude) {
    for (int i = 0; i < 3; ++i) finite(ptr + "/" + std::to_string(i), v[i], limit);
  }
  void direction(const std::string& ptr, const glm::vec3& v) {
    vec(ptr, v);
    if (ok() && !(glm::length(v) > 1e-12f)) error = ptr + ": expected a non-zero direction, got [0, 0, 0]";
  }
  void path(const std::string& ptr, const Path& p) {
    if (p.times.size() != p.points.size()) {
      if (error.empty()) error = ptr + ": expected as many times as points";
      return;
    }
    for (std::size_t i = 0; i < p.times.size(); ++i) {
      const std::string at = ptr + "/" + std::to_string(i);
      finite(at + "/time", p.times[i]);
      vec(at + "/position", p.points[i]);
      if (i > 0 && ok() && !(p.times[i] > p.times[i - 1])) {
        fail(at + "/time", "a time after the previous key (" + num(p.times[i - 1]) + ")", p.times[i]);
      }
    }
  }
};

void checkForces(Check& c, const Forces& f, const std::string& ptr) {
  c.vec(ptr + "/gravity", f.gravity);
  c.range(ptr + "/buoyancy", f.buoyancy, -kMaxMagnitude, kMaxMagnitude);
  c.direction(ptr + "/up", f.up);
  c.range(ptr + "/drag", f.drag, 0.0f, kMaxMagnitude);
  c.vec(ptr + "/wind", f.wind);
  for (std::size_t i = 0; i < f.windVolumes.size(); ++i) {
    const std::string p = ptr + "/windVolumes/" + std::to_string(i);
    const WindVolume& w = f.windVolumes[i];
    c.vec(p + "/center", w.center);
    for (int k = 0; k < 3; ++k) c.range(p + "/halfExtent/" + std::to_string(k), w.halfExtent[k], 0.0f, kMaxMagnitude);
    c.vec(p + "/velocity", w.velocity);
    c.range(p + "/feather", w.feather, 0.0f, kMaxMagnitude);
  }
  const Turbulence& t = f.turbulence;
  c.range(ptr + "/turbulence/strength", t.strength, 0.0f, kMaxMagnitude);
  c.range(ptr + "/turbulence/scale", t.scale, 1e-4f, kMaxMagnitude);
  c.range(ptr + "/turbulence/speed", t.speed, 0.0f, 1e3f);
  for (std::size_t i = 0; i < f.vortices.size(); ++i) {
    const std::string p = ptr + "/vortices/" + std::to_string(i);
    const Vortex& v = f.vortices[i];
    c.vec(p + "/position", v.position);
    c.direction(p + "/axis", v.axis);
    c.range(p + "/strength", v.strength, -kMaxMagnitude, kMaxMagnitude);
    c.range(p + "/radius", v.radius, 1e-4f, kMaxMagnitude);
    c.range(p + "/falloff", v.falloff, 0.0f, kMaxMagnitude);
    c.range(p + "/length", v.length, 0.0f, kMaxMagnitude);
    c.path(p + "/path", v.path);
    c.range(p + "/shedInterval", v.shedInterval, 0.0f, 1e4f);
    if (v.shedInterval > 0.0f) c.range(p + "/shedInterval", v.shedInterval, 1e-3f, 1e4f);
    c.range(p + "/shedLifetime", v.shedLifetime, 0.0f, 1e4f, true);
    // Each shed copy costs a pass over the particles: at most 1000 alive at once.
    if (c.ok() && v.shedInterval > 0.0f && v.shedLifetime / v.shedInterval > 1000.0f) {
      c.fail(p + "/shedLifetime",
             "at most 1000 shed copies alive at once (shedLifetime <= 1000 * shedInterval = " +
                 Check::num(1000.0 * v.shedInterval) + ")",
             v.shedLifetime);
    }
  }
}

void checkEmitter(Check& c, const Emitter& e, const std::string& p) {
  c.vec(p + "/position", e.position);
  c.range(p + "/radius", e.radius, 0.0f, kMaxMagnitude);
  if (e.shape == Emitter::Shape::kDisc) c.direction(p + "/normal", e.normal);
  c.path(p + "/path", e.path);
  c.range(p + "/rate", e.rate, 0.0f, 1e7f);
  c.finite(p + "/start", e.start);
  c.range(p + "/duration", e.duration, 0.0f, kMaxMagnitude);
  c.vec(p + "/velocity", e.velocity);
  c.range(p + "/spread", e.spreadDegrees, 0.0f, 180.0f);
  c.range(p + "/speedSpread", e.speedSpread, 0.0f, 1.0f);
  c.range(p + "/inheritVelocity", e.inheritVelocity, -10.0f, 10.0f);
  c.range(p + "/density", e.density, 0.0f, 1e3f, true);
  c.range(p + "/sizeMin", e.sizeMin, 0.0f, kMaxMagnitude);
  c.range(p + "/sizeMax", e.sizeMax, e.sizeMin, kMaxMagnitude);
  c.range(p + "/lifetime", e.lifetime, 0.0f, 1e6f, true);
  if (c.ok() && !(e.lifetimeSpread >= 0.0f && e.lifetimeSpread < 1.0f)) {
    c.fail(p + "/lifetimeSpread", "a number in [0, 1)", e.lifetimeSpread);
  }
  for (std::size_t i = 0; i < e.variations.size(); ++i) {
    const int v = e.variations[i];
    if (c.ok() && (v < 0 || v > 255)) c.fail(p + "/variations/" + std::to_string(i), "an integer in [0, 255]", v);
  }
  c.range(p + "/spin", e.spin, 0.0f, 1e3f);
}

void checkCollider(Check& c, const Collider& k, const std::string& p) {
  c.vec(p + "/center", k.center);
  for (int i = 0; i < 4; ++i) c.finite(p + "/rotation", k.rotation[i], 2.0f);
  if (c.ok() && !(glm::length(k.rotation) > 1e-3f))
    c.error = p + "/rotation: expected a rotation (a non-zero quaternion)";
  for (int i = 0; i < 3; ++i) c.range(p + "/halfExtent/" + std::to_string(i), k.halfExtent[i], 0.0f, kMaxMagnitude);
  c.range(p + "/friction", k.friction, 0.0f, 1.0f);
  c.path(p + "/path", k.path);
  if (k.type == Collider::Type::kMesh) {
    if (c.ok() && (k.indices.empty() || k.indices.size() % 3 != 0)) c.error = p + ": a mesh collider needs triangles";
    for (std::uint32_t i : k.indices) {
      if (c.ok() && i >= k.positions.size()) c.error = p + ": a triangle index is out of range";
    }
    for (const glm::vec3& v : k.positions) {
      if (c.ok()) c.vec(p + "/positions", v);
    }
  }
}

}  // namespace

Result<void> validate(const Forces& forces, const std::string& pointer) {
  Check c;
  checkForces(c, forces, pointer);
  if (!c.ok()) return Error{c.error};
  return {};
}

Result<void> validate(const Settings& s) {
  Check c;
  c.range("/fps", s.fps, 0.0f, 1e4f, true);
  if (c.ok() && (s.substeps < 1 || s.substeps > 1000)) c.fail("/substeps", "an integer in [1, 1000]", s.substeps);
  c.range("/preroll", s.preroll, 0.0f, 3600.0f);
  if (c.ok() && static_cast<double>(s.preroll) * s.fps * s.substeps > 1e6) {
    c.fail("/preroll", "at most 1e6 steps of preroll (preroll * fps * substeps)", s.preroll);
  }
  if (c.ok() && s.maxParticles > kMaxParticleBudget) {
    c.fail("/maxParticles",
           "at most " + std::to_string(kMaxParticleBudget) +
               " particles (about 64 bytes each; more would not fit in memory)",
           static_cast<double>(s.maxParticles));
  }
  c.range("/collisionRadius", s.collisionRadius, 0.0f, 1.0f);
  checkForces(c, s.forces, "/forces");
  for (std::size_t i = 0; i < s.emitters.size(); ++i) checkEmitter(c, s.emitters[i], "/emitters/" + std::to_string(i));
  for (std::size_t i = 0; i < s.colliders.size(); ++i) {
    checkCollider(c, s.colliders[i], "/colliders/" + std::to_string(i));
  }
  if (!c.ok()) return Error{c.error};
  return {};
}

// ---- the simulator -------------------------------------------------------------------------------

namespace {

constexpr float kLambOseenPeak = 0.638172f;  // max of (1 - exp(-s^2)) / s, at s = 1.12092

// Counter-based random numbers: the value for (seed, stream, index, k) never depends on order.
using core::mix64;

struct Rng {
  std::uint64_t state;
  Rng(std::uint32_t seed, std::uint64_t stream, std::uint64_t index)
      : state(mix64(mix64(seed * core::kGoldenGamma + stream) ^ (index + 0x632be59bd9b4e019ULL))) {}
  float uniform() {  // [0, 1)
    state += core::kGoldenGamma;
    return static_cast<float>(mix64(state) >> 40) / 16777216.0f;
  }
};

glm::vec3 anyPerpendicular(const glm::vec3& n) {
  const glm::vec3 a = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  return glm::normalize(glm::cross(n, a));
}

glm::vec3 randomUnit(Rng& r) {
  const float z = r.uniform() * 2.0f - 1.0f, phi = r.uniform() * 2.0f * std::numbers::pi_v<float>;
  const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

// A mesh collider: world-space triangles binned in a uniform grid.
struct MeshGrid {
  std::vector<glm::vec3> a, e1, e2, n;  // vertex 0, edges, unit normal
  glm::vec3 lo{0.0f}, hi{0.0f}, cell{1.0f};
  glm::ivec3 dims{1};
  std::vector<std::uint32_t> start, items;

  explicit MeshGrid(const Collider& c) {
    const std::size_t tris = c.indices.size() / 3;
    lo = glm::vec3(std::numeric_limits<float>::max());
    hi = -lo;
    for (const glm::vec3& p : c.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    for (std::size_t t = 0; t < tris; ++t) {
      const glm::vec3 p0 = c.positions[c.indices[3 * t]], p1 = c.positions[c.indices[3 * t + 1]],
                      p2 = c.positions[c.indices[3 * t + 2]];
      const glm::vec3 normal = glm::cross(p1 - p0, p2 - p0);
      const float len = glm::length(normal);
      if (!(len > 0.0f)) continue;  // degenerate: nothing to hit
      a.push_back(p0), e1.push_back(p1 - p0), e2.push_back(p2 - p0), n.push_back(normal / len);
    }
    const glm::vec3 extent = glm::max(hi - lo, glm::vec3(1e-4f));
    const int perAxis = std::clamp(static_cast<int>(std::cbrt(static_cast<double>(a.size())) * 1.5), 1, 64);
    const float side = std::max({extent.x, extent.y, extent.z}) / static_cast<float>(perAxis);
    dims = glm::clamp(glm::ivec3(glm::ceil(extent / side)), glm::ivec3(1), glm::ivec3(64));
    cell = extent / glm::vec3(dims);
    std::vector<std::vector<std::uint32_t>> bins(static_cast<std::size_t>(dims.x) * dims.y * dims.z);
    for (std::size_t t = 0; t < a.size(); ++t) {
      const glm::vec3 p1 = a[t] + e1[t], p2 = a[t] + e2[t];
      const glm::ivec3 c0 = cellOf(glm::min(a[t], glm::min(p1, p2))), c1 = cellOf(glm::max(a[t], glm::max(p1, p2)));
      for (int z = c0.z; z <= c1.z; ++z)
        for (int y = c0.y; y <= c1.y; ++y)
          for (int x = c0.x; x <= c1.x; ++x) bins[index(x, y, z)].push_back(static_cast<std::uint32_t>(t));
    }
    start.push_back(0);
    for (const auto& b : bins) {
      items.insert(items.end(), b.begin(), b.end());
      start.push_back(static_cast<std::uint32_t>(items.size()));
    }
  }
  glm::ivec3 cellOf(const glm::vec3& p) const {
    // Clamped while still float: a far-away point must not overflow the int conversion.
    return glm::ivec3(glm::clamp(glm::floor((p - lo) / cell), glm::vec3(0.0f), glm::vec3(dims - 1)));
  }
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * dims.y + static_cast<std::size_t>(y)) * dims.x + static_cast<std::size_t>(x);
  }

  // The first crossing of the segment p -> q with the surface: its parameter and the triangle.
  bool firstHit(const glm::vec3& p, const glm::vec3& q, float& tHit, std::uint32_t& triHit) const {
    if (!std::isfinite(p.x + p.y + p.z + q.x + q.y + q.z)) return false;
    const glm::vec3 sLo = glm::min(p, q), sHi = glm::max(p, q);
    if (glm::any(glm::lessThan(sHi, lo)) || glm::any(glm::greaterThan(sLo, hi))) return false;
    const glm::ivec3 c0 = cellOf(sLo), c1 = cellOf(sHi);
    const glm::vec3 d = q - p;
    bool hit = false;
    tHit = 2.0f;
    for (int z = c0.z; z <= c1.z; ++z) {
      for (int y = c0.y; y <= c1.y; ++y) {
        for (int x = c0.x; x <= c1.x; ++x) {
          const std::size_t b = index(x, y, z);
          for (std::uint32_t k = start[b]; k < start[b + 1]; ++k) {
            const std::uint32_t t = items[k];
            // Moller-Trumbore, both sides.
            const glm::vec3 pv = glm::cross(d, e2[t]);
            const float det = glm::dot(e1[t], pv);
            if (std::abs(det) < 1e-20f) continue;
            const float inv = 1.0f / det;
            const glm::vec3 tv = p - a[t];
            const float u = glm::dot(tv, pv) * inv;
            if (u < 0.0f || u > 1.0f) continue;
            const glm::vec3 qv = glm::cross(tv, e1[t]);
            const float v = glm::dot(d, qv) * inv;
            if (v < 0.0f || u + v > 1.0f) continue;
            const float s = glm::dot(e2[t], qv) * inv;
            if (s >= 0.0f && s <= 1.0f && s < tHit) tHit = s, triHit = t, hit = true;
          }
        }
      }
    }
    return hit;
  }
};

struct ShedVortex {
  glm::vec3 position, axis;
  float strength, radius, falloff, length;
  double born, lifetime;
};

// A vortex resolved for one step: where it is and how strong.
struct LiveVortex {
  glm::vec3 center, axis;
  float scale;        // strength / peak * radius
  float invRadius2;   // 1 / radius^2
  float invFalloff2;  // 0 = none
  float invHalfLength2;
  float cutoff2;  // beyond this squared distance it adds nothing worth computing
};

// The air one vortex adds to every particle: vortexVelocity written out in scalars over the arrays,
// in a free function so the compiler sees no aliasing and vectorizes it.
void addVortex(const LiveVortex& v, const float* __restrict X, const float* __restrict Y, const float* __restrict Z,
               float* __restrict UX, float* __restrict UY, float* __restrict UZ, std::size_t n) {
  const float cx = v.center.x, cy = v.center.y, cz = v.center.z;
  const float ax = v.axis.x, ay = v.axis.y, az = v.axis.z;
  const float scale = v.scale, ir2 = v.invRadius2, if2 = v.invFalloff2, ih2 = v.invHalfLength2, cutoff2 = v.cutoff2;
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = X[i] - cx, dy = Y[i] - cy, dz = Z[i] - cz;
    const float along = dx * ax + dy * ay + dz * az;
    const float rx = dx - along * ax, ry = dy - along * ay, rz = dz - along * az;
    const float r2 = rx * rx + ry * ry + rz * rz;
    const float inside = static_cast<float>(r2 >= 1e-12f) * static_cast<float>(r2 <= cutoff2);
    const float r2s = std::max(r2, 1e-12f);
    const float core = 1.0f - detail::fastExp(-r2s * ir2);
    const float k = inside * scale * core / r2s * detail::fastExp(-r2s * if2 - along * along * ih2);
    UX[i] += k * (ay * rz - az * ry);
    UY[i] += k * (az * rx - ax * rz);
    UZ[i] += k * (ax * ry - ay * rx);
  }
}

// One exponential-integrator step for every particle (see integrate); free, so it vectorizes.
// With e = exp(-k h), c1 = (1 - e) / k and c2 = (h - c1) / k (computed in double, by series for small
// k h, so nothing divides by a small drag):
//   v' = v e + u (1 - e) + a c1,   x' = x + v c1 + u (h - c1) + a c2
// the exact solution of dv/dt = a + k (u - v) with u and a held; k = 0 gives x + v h + a h^2 / 2.
void integrateExponential(float* __restrict X, float* __restrict Y, float* __restrict Z, float* __restrict VX,
                          float* __restrict VY, float* __restrict VZ, const float* __restrict UX,
                          const float* __restrict UY, const float* __restrict UZ, const float* __restrict A,
                          const float* __restrict L, const float* __restrict D0, std::size_t n, glm::vec3 g,
                          glm::vec3 b, float e, float oneMinusE, float c1, float hMinusC1, float c2) {
  for (std::size_t i = 0; i < n; ++i) {
    const float density = D0[i] * (1.0f - A[i] / L[i]);
    const float ax = g.x + b.x * density, ay = g.y + b.y * density, az = g.z + b.z * density;
    X[i] += VX[i] * c1 + UX[i] * hMinusC1 + ax * c2;
    Y[i] += VY[i] * c1 + UY[i] * hMinusC1 + ay * c2;
    Z[i] += VZ[i] * c1 + UZ[i] * hMinusC1 + az * c2;
    VX[i] = VX[i] * e + UX[i] * oneMinusE + ax * c1;
    VY[i] = VY[i] * e + UY[i] * oneMinusE + ay * c1;
    VZ[i] = VZ[i] * e + UZ[i] * oneMinusE + az * c1;
  }
}

// The air a wind volume adds (windWeight over the arrays), branch-free.
void addWindVolume(const WindVolume& w, const float* __restrict X, const float* __restrict Y, const float* __restrict Z,
                   float* __restrict UX, float* __restrict UY, float* __restrict UZ, std::size_t n) {
  const float cx = w.center.x, cy = w.center.y, cz = w.center.z;
  const float hx = w.halfExtent.x, hy = w.halfExtent.y, hz = w.halfExtent.z;
  const float invFeather = w.feather > 0.0f ? 1.0f / w.feather : 0.0f;
  const bool hard = !(w.feather > 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const float ox = std::max(std::abs(X[i] - cx) - hx, 0.0f), oy = std::max(std::abs(Y[i] - cy) - hy, 0.0f),
                oz = std::max(std::abs(Z[i] - cz) - hz, 0.0f);
    const float d = std::sqrt(ox * ox + oy * oy + oz * oz);
    const float x = std::max(0.0f, 1.0f - d * invFeather);
    float k = x * x * (3.0f - 2.0f * x);
    k = (d == 0.0f) ? 1.0f : (hard ? 0.0f : k);
    UX[i] += k * w.velocity.x, UY[i] += k * w.velocity.y, UZ[i] += k * w.velocity.z;
  }
}

// Plane and sphere contacts over the arrays, branch-free; returns the number of contacts.
std::size_t collidePlane(const glm::mat3& toLocal, const glm::vec3& center, const glm::vec3& halfExtent, float keep,
                         float* __restrict X, float* __restrict Y, float* __restrict Z, float* __restrict VX,
                         float* __restrict VY, float* __restrict VZ, const float* __restrict R, std::size_t n) {
  // toLocal rows: the plane's x, normal, z axes in world space.
  const glm::vec3 ex = glm::row(toLocal, 0), nrm = glm::row(toLocal, 1), ez = glm::row(toLocal, 2);
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = X[i] - center.x, dy = Y[i] - center.y, dz = Z[i] - center.z;
    const float lx = ex.x * dx + ex.y * dy + ex.z * dz, ly = nrm.x * dx + nrm.y * dy + nrm.z * dz,
                lz = ez.x * dx + ez.y * dy + ez.z * dz;
    const bool hit = (ly < R[i]) & (std::abs(lx) <= halfExtent.x) & (std::abs(lz) <= halfExtent.z);
    const float push = hit ? R[i] - ly : 0.0f;
    X[i] += push * nrm.x, Y[i] += push * nrm.y, Z[i] += push * nrm.z;
    const float vn = VX[i] * nrm.x + VY[i] * nrm.y + VZ[i] * nrm.z;
    const bool slide = hit & (vn < 0.0f);  // & not &&: no branch, so the loop vectorizes
    const float into = slide ? vn : 0.0f;
    const float scale = slide ? keep : 1.0f;
    VX[i] = (VX[i] - into * nrm.x) * scale, VY[i] = (VY[i] - into * nrm.y) * scale,
    VZ[i] = (VZ[i] - into * nrm.z) * scale;
    contacts += hit ? 1 : 0;
  }
  return contacts;
}

std::size_t collideSphere(const glm::vec3 center, float radius, const glm::vec3 up, float keep, float* __restrict X,
                          float* __restrict Y, float* __restrict Z, float* __restrict VX, float* __restrict VY,
                          float* __restrict VZ, const float* __restrict R, std::size_t n) {
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = X[i] - center.x, dy = Y[i] - center.y, dz = Z[i] - center.z;
    const float reach = radius + R[i];
    const float l2 = dx * dx + dy * dy + dz * dz;
    const bool hit = l2 < reach * reach;
    const float l = std::sqrt(l2);
    const float centred = static_cast<float>(!(l > 1e-12f));  // at the very centre: out along `up`
    const float inv = (1.0f - centred) / std::max(l, 1e-12f);
    const float nx = dx * inv + centred * up.x, ny = dy * inv + centred * up.y, nz = dz * inv + centred * up.z;
    const float move = static_cast<float>(hit);
    X[i] += move * (center.x + nx * reach - X[i]);
    Y[i] += move * (center.y + ny * reach - Y[i]);
    Z[i] += move * (center.z + nz * reach - Z[i]);
    const float vn = VX[i] * nx + VY[i] * ny + VZ[i] * nz;
    const bool slide = hit & (vn < 0.0f);  // & not &&: no branch, so the loop vectorizes
    const float into = slide ? vn : 0.0f;
    const float scale = slide ? keep : 1.0f;
    VX[i] = (VX[i] - into * nx) * scale, VY[i] = (VY[i] - into * ny) * scale, VZ[i] = (VZ[i] - into * nz) * scale;
    contacts += hit ? 1 : 0;
  }
  return contacts;
}

// Oriented-box contacts over the arrays, branch-free: a particle inside the box grown by its
// radius leaves through the nearest face.
std::size_t collideBox(const glm::mat3& toWorld, const glm::vec3& center, const glm::vec3& halfExtent, float keep,
                       float* __restrict X, float* __restrict Y, float* __restrict Z, float* __restrict VX,
                       float* __restrict VY, float* __restrict VZ, const float* __restrict R, std::size_t n) {
  const glm::vec3 ax = toWorld[0], ay = toWorld[1], az = toWorld[2];  // the box's axes in world space
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = X[i] - center.x, dy = Y[i] - center.y, dz = Z[i] - center.z;
    const float lx = ax.x * dx + ax.y * dy + ax.z * dz, ly = ay.x * dx + ay.y * dy + ay.z * dz,
                lz = az.x * dx + az.y * dy + az.z * dz;
    const float rx = halfExtent.x + R[i], ry = halfExtent.y + R[i], rz = halfExtent.z + R[i];
    const float px = rx - std::abs(lx), py = ry - std::abs(ly), pz = rz - std::abs(lz);
    const bool hit = (px > 0.0f) & (py > 0.0f) & (pz > 0.0f);
    const bool outX = (px < py) & (px < pz), outY = !outX & (py < pz), outZ = !outX & !outY;
    const float sx = lx < 0.0f ? -1.0f : 1.0f, sy = ly < 0.0f ? -1.0f : 1.0f, sz = lz < 0.0f ? -1.0f : 1.0f;
    // How far to move along the chosen face's normal (local), and that normal in world space.
    const float push = hit ? (outX ? px : (outY ? py : pz)) : 0.0f;
    const float nlx = outX ? sx : 0.0f, nly = outY ? sy : 0.0f, nlz = outZ ? sz : 0.0f;
    const float nx = ax.x * nlx + ay.x * nly + az.x * nlz, ny = ax.y * nlx + ay.y * nly + az.y * nlz,
                nz = ax.z * nlx + ay.z * nly + az.z * nlz;
    X[i] += push * nx, Y[i] += push * ny, Z[i] += push * nz;
    const float vn = VX[i] * nx + VY[i] * ny + VZ[i] * nz;
    const bool slide = hit & (vn < 0.0f);
    const float into = slide ? vn : 0.0f;
    const float scale = slide ? keep : 1.0f;
    VX[i] = (VX[i] - into * nx) * scale, VY[i] = (VY[i] - into * ny) * scale, VZ[i] = (VZ[i] - into * nz) * scale;
    contacts += hit ? 1 : 0;
  }
  return contacts;
}

}  // namespace

struct Simulator::Impl {
  Settings s;
  int variations = 1;
  double h = 0.0;
  std::int64_t prerollSteps = 0;
  std::int64_t step = 0;
  std::unique_ptr<detail::CurlField> curl;
  std::uint32_t curlSeed = 0;
  std::vector<MeshGrid> meshes;  // one per kMesh collider, in order
  std::vector<ShedVortex> shed;

  // Structure of arrays.
  std::vector<float> px, py, pz, vx, vy, vz, age, life, size0, density0;
  std::vector<float> qx, qy, qz, qw, wx, wy, wz;  // birth orientation, angular velocity
  std::vector<std::uint8_t> variation, oriented;
  std::vector<std::uint32_t> emitterOf, id;  // which emitter; a hash of (seed, emitter, birth index)
  // Scratch: air velocity, previous position.
  std::vector<float> ux, uy, uz, ox, oy, oz, radii;

  std::size_t size() const { return px.size(); }

  void clear() {
    for (auto* v : {&px, &py, &pz, &vx, &vy, &vz, &age, &life, &size0, &density0, &qx, &qy, &qz, &qw, &wx, &wy, &wz})
      v->clear();
    variation.clear(), oriented.clear(), emitterOf.clear(), id.clear();
    shed.clear();
  }

  void prepareTurbulence() {
    if (s.forces.turbulence.strength > 0.0f && (!curl || curlSeed != s.forces.turbulence.seed)) {
      curl = std::make_unique<detail::CurlField>(s.forces.turbulence.seed);
      curlSeed = s.forces.turbulence.seed;
    }
  }

  std::vector<LiveVortex> liveVortices(double t) const {
    std::vector<LiveVortex> out;
    auto add = [&](const glm::vec3& c, const glm::vec3& axis, float strength, float radius, float falloff,
                   float length) {
      if (strength == 0.0f) return;
      LiveVortex v;
      v.center = c;
      v.axis = glm::normalize(axis);
      v.scale = strength / kLambOseenPeak * radius;
      v.invRadius2 = 1.0f / (radius * radius);
      v.invFalloff2 = falloff > 0.0f ? 1.0f / (falloff * falloff) : 0.0f;
      v.invHalfLength2 = length > 0.0f ? 4.0f / (length * length) : 0.0f;
      // exp(-16) ~ 1e-7 of the speed: stop there. Without a falloff the 1/r tail never ends.
      v.cutoff2 = falloff > 0.0f ? 16.0f * falloff * falloff : std::numeric_limits<float>::infinity();
      out.push_back(v);
    };
    for (const Vortex& v : s.forces.vortices)
      add(v.position + v.path.at(t), v.axis, v.strength, v.radius, v.falloff, v.length);
    for (const ShedVortex& v : shed) {
      const float fade = static_cast<float>(std::max(0.0, 1.0 - (t - v.born) / v.lifetime));
      add(v.position, v.axis, v.strength * fade, v.radius, v.falloff, v.length);
    }
    return out;
  }

  // Turbulence lookups: the lattice tile holds 4 noise cells; one cell is `scale` world units (the
  // swirl size), and the frozen field drifts `speed` cells per second (Taylor's hypothesis: a
  // translated divergence-free field is still divergence-free), so the air at a point changes
  // over about 1 / speed seconds.
  static constexpr float kCellsPerTile = 4.0f;
  float turbulenceInvTile() const { return 1.0f / (s.forces.turbulence.scale * kCellsPerTile); }
  glm::vec3 turbulenceOffset(double t) const {
    const double d = static_cast<double>(s.forces.turbulence.speed) * t / kCellsPerTile;
    return glm::vec3(static_cast<float>(std::fmod(d * 0.8, 1.0)), static_cast<float>(std::fmod(d * 0.36, 1.0)),
                     static_cast<float>(std::fmod(d * 0.48, 1.0)));
  }

  // The air velocity at one point (the same sum airAll makes for every particle).
  glm::vec3 air(const glm::vec3& p, double t, const std::vector<LiveVortex>& vortices) const {
    const Forces& f = s.forces;
    glm::vec3 u = f.wind;
    for (const WindVolume& w : f.windVolumes) u += w.velocity * windWeight(p, w);
    for (const LiveVortex& v : vortices) u += vortexVelocity(p, v);
    const Turbulence& tb = f.turbulence;
    if (tb.strength > 0.0f && curl) u += tb.strength * curl->sample(p * turbulenceInvTile() + turbulenceOffset(t));
    return u;
  }

  static float windWeight(const glm::vec3& p, const WindVolume& w) {
    const glm::vec3 outside = glm::max(glm::abs(p - w.center) - w.halfExtent, glm::vec3(0.0f));
    const float d = std::sqrt(glm::dot(outside, outside));
    if (d == 0.0f) return 1.0f;
    if (!(d < w.feather)) return 0.0f;
    const float x = 1.0f - d / w.feather;
    return x * x * (3.0f - 2.0f * x);
  }

  static glm::vec3 vortexVelocity(const glm::vec3& p, const LiveVortex& v) {
    const glm::vec3 d = p - v.center;
    const float along = glm::dot(d, v.axis);
    const glm::vec3 radial = d - along * v.axis;
    const float r2 = glm::dot(radial, radial);
    // Branch-free (so the loop over particles vectorizes): on the axis and past the cutoff, zero.
    const float inside = (r2 >= 1e-12f && r2 <= v.cutoff2) ? 1.0f : 0.0f;
    const float r2s = std::max(r2, 1e-12f);
    // exp(-r^2/rc^2) for the core; one more exponential for the falloff and the length together.
    const float core = 1.0f - detail::fastExp(-r2s * v.invRadius2);
    const float k =
        inside * v.scale * core / r2s * detail::fastExp(-r2s * v.invFalloff2 - along * along * v.invHalfLength2);
    return k * glm::cross(v.axis, radial);
  }

  // Air velocity for every particle into ux/uy/uz, one field at a time over the arrays (the vortex
  // and wind-volume loops vectorize; the turbulence lookup is a gather).
  void airAll(double t) {
    const std::size_t n = size();
    ux.resize(n), uy.resize(n), uz.resize(n);
    const Forces& f = s.forces;
    std::fill(ux.begin(), ux.end(), f.wind.x);
    std::fill(uy.begin(), uy.end(), f.wind.y);
    std::fill(uz.begin(), uz.end(), f.wind.z);
    const float* __restrict X = px.data();
    const float* __restrict Y = py.data();
    const float* __restrict Z = pz.data();
    float* __restrict UX = ux.data();
    float* __restrict UY = uy.data();
    float* __restrict UZ = uz.data();
    for (const WindVolume& w : f.windVolumes) addWindVolume(w, X, Y, Z, UX, UY, UZ, n);
    for (const LiveVortex& v : liveVortices(t)) addVortex(v, X, Y, Z, UX, UY, UZ, n);
    const Turbulence& tb = f.turbulence;
    if (tb.strength > 0.0f && curl) {
      const float inv = turbulenceInvTile();
      const glm::vec3 offset = turbulenceOffset(t);
      for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 u = tb.strength * curl->sample(glm::vec3(X[i], Y[i], Z[i]) * inv + offset);
        UX[i] += u.x, UY[i] += u.y, UZ[i] += u.z;
      }
    }
  }

  void integrate() {
    const std::size_t n = size();
    const Forces& f = s.forces;
    const float hf = static_cast<float>(h);
    const glm::vec3 up = glm::normalize(f.up);
    const float bx = f.buoyancy * up.x, by = f.buoyancy * up.y, bz = f.buoyancy * up.z;
    const float gx = f.gravity.x, gy = f.gravity.y, gz = f.gravity.z;
    const float k = f.drag;
    float* __restrict X = px.data();
    float* __restrict Y = py.data();
    float* __restrict Z = pz.data();
    float* __restrict VX = vx.data();
    float* __restrict VY = vy.data();
    float* __restrict VZ = vz.data();
    const float* __restrict UX = ux.data();
    const float* __restrict UY = uy.data();
    const float* __restrict UZ = uz.data();
    const float* __restrict A = age.data();
    const float* __restrict L = life.data();
    const float* __restrict D0 = density0.data();
    if (s.integrator == Integrator::kForwardEuler) {
      for (std::size_t i = 0; i < n; ++i) {
        const float density = D0[i] * (1.0f - A[i] / L[i]);
        const float ax = gx + bx * density + k * (UX[i] - VX[i]);
        const float ay = gy + by * density + k * (UY[i] - VY[i]);
        const float az = gz + bz * density + k * (UZ[i] - VZ[i]);
        X[i] += hf * VX[i], Y[i] += hf * VY[i], Z[i] += hf * VZ[i];
        VX[i] += hf * ax, VY[i] += hf * ay, VZ[i] += hf * az;
      }
      return;
    }
    const double kh = static_cast<double>(k) * h;
    const double e = std::exp(-kh);
    const double oneMinusE = -std::expm1(-kh);
    // c1 = (1 - e) / k and c2 = (h - c1) / k; for small k h their series (no cancellation).
    const double c1 = kh < 1e-4 ? h * (1.0 - kh / 2.0 + kh * kh / 6.0) : oneMinusE / k;
    const double c2 = kh < 1e-4 ? h * h * (0.5 - kh / 6.0 + kh * kh / 24.0) : (h - c1) / k;
    integrateExponential(X, Y, Z, VX, VY, VZ, UX, UY, UZ, A, L, D0, n, glm::vec3(gx, gy, gz), glm::vec3(bx, by, bz),
                         static_cast<float>(e), static_cast<float>(oneMinusE), static_cast<float>(c1),
                         static_cast<float>(h - c1), static_cast<float>(c2));
  }

  // Puts particles [begin, end) back outside every collider; returns the number of contacts.
  // `prev` (x, y, z arrays indexed from `begin`) is where the particles were before they moved: mesh
  // colliders test the segment, so a fast particle cannot tunnel through a thin wall.
  std::size_t collide(std::size_t begin, std::size_t end, const float* const* prev, double t0, double t) {
    std::size_t contacts = 0;
    std::size_t meshIndex = 0;
    // Each particle's collision radius, once for all colliders.
    radii.resize(end - begin);
    for (std::size_t i = begin; i < end; ++i)
      radii[i - begin] = s.collisionRadius * 0.5f * size0[i] * std::max(0.0f, 1.0f - age[i] / life[i]);
    for (const Collider& collider : s.colliders) {
      Collider moved;  // a collider on a path, where it is now (meshes move by the same offset)
      const bool onPath = !collider.path.empty();
      if (onPath) {
        moved.type = collider.type, moved.rotation = collider.rotation, moved.halfExtent = collider.halfExtent;
        moved.friction = collider.friction, moved.center = collider.center + collider.path.at(t);
      }
      const Collider& c = onPath ? moved : collider;
      // A moving mesh: the particle's step is tested in the mesh's frame (start against where the
      // mesh was, end against where it is), so a sweeping mesh pushes smoke it passes through.
      const glm::vec3 meshOffset0 = onPath ? collider.path.at(t0) : glm::vec3(0.0f);
      const glm::vec3 meshOffset = onPath ? collider.path.at(t) : glm::vec3(0.0f);
      const glm::vec3 bodyVelocity = (meshOffset - meshOffset0) / static_cast<float>(t - t0);
      const float keep = 1.0f - c.friction;
      switch (c.type) {
        case Collider::Type::kPlane:
          contacts += collidePlane(glm::transpose(glm::mat3_cast(c.rotation)), c.center, c.halfExtent, keep,
                                   px.data() + begin, py.data() + begin, pz.data() + begin, vx.data() + begin,
                                   vy.data() + begin, vz.data() + begin, radii.data(), end - begin);
          break;
        case Collider::Type::kSphere:
          contacts += collideSphere(c.center, c.halfExtent.x, c.rotation * glm::vec3(0, 1, 0), keep, px.data() + begin,
                                    py.data() + begin, pz.data() + begin, vx.data() + begin, vy.data() + begin,
                                    vz.data() + begin, radii.data(), end - begin);
          break;
        case Collider::Type::kBox:
          contacts += collideBox(glm::mat3_cast(c.rotation), c.center, c.halfExtent, keep, px.data() + begin,
                                 py.data() + begin, pz.data() + begin, vx.data() + begin, vy.data() + begin,
                                 vz.data() + begin, radii.data(), end - begin);
          break;
        case Collider::Type::kMesh: {
          const MeshGrid& m = meshes[meshIndex++];
          const float* OX = prev[0];
          const float* OY = prev[1];
          const float* OZ = prev[2];
          for (std::size_t i = begin; i < end; ++i) {
            const glm::vec3 p = glm::vec3(OX[i - begin], OY[i - begin], OZ[i - begin]) - meshOffset0,
                            q = glm::vec3(px[i], py[i], pz[i]) - meshOffset;
            float along;
            std::uint32_t tri;
            if (!m.firstHit(p, q, along, tri)) continue;
            glm::vec3 n = m.n[tri];
            if (glm::dot(p - m.a[tri], n) < 0.0f) n = -n;  // the side it came from
            const glm::vec3 hit = p + (q - p) * along;
            const glm::vec3 at = hit + n * 1e-4f * std::max(1.0f, glm::length(m.hi - m.lo)) + meshOffset;
            px[i] = at.x, py[i] = at.y, pz[i] = at.z;
            // Lose the velocity into the surface relative to the moving body.
            glm::vec3 v = glm::vec3(vx[i], vy[i], vz[i]) - bodyVelocity;
            const float vn = glm::dot(v, n);
            if (vn < 0.0f) v = (v - vn * n) * keep;
            v += bodyVelocity;
            vx[i] = v.x, vy[i] = v.y, vz[i] = v.z;
            ++contacts;
          }
          break;
        }
      }
    }
    return contacts;
  }

  void spawn(double t0, double t1, StepStats& st) {
    for (std::size_t ei = 0; ei < s.emitters.size(); ++ei) {
      const Emitter& e = s.emitters[ei];
      if (!(e.rate > 0.0f)) continue;
      const double stop =
          e.duration > 0.0f ? static_cast<double>(e.start) + e.duration : std::numeric_limits<double>::infinity();
      // Particle k is born at start + (k + 1/2) / rate: E(t) counts those born before t. The half
      // keeps births off step boundaries, where rounding would move one to the next step.
      auto emitted = [&](double t) {
        const double tc = std::clamp(t, static_cast<double>(e.start), stop);
        return static_cast<std::int64_t>(std::floor((tc - e.start) * e.rate + 0.5));
      };
      std::int64_t k0 = emitted(t0);
      const std::int64_t k1 = emitted(t1);
      // Births before t1 - the longest lifetime die inside this step: skip them without a loop (a
      // huge rate with short lives must not cost a loop over every birth).
      const double longest = static_cast<double>(e.lifetime) * (1.0 + e.lifetimeSpread);
      k0 = std::max(k0, emitted(t1 - longest));
      for (std::int64_t k = k0; k < k1; ++k) {
        if (size() >= s.maxParticles) {
          st.dropped += static_cast<std::size_t>(k1 - k);
          break;
        }
        Rng r(e.seed, ei, static_cast<std::uint64_t>(k));
        // The instant of birth inside the step, and the time left to the step's end.
        const double tb = std::clamp(e.start + (static_cast<double>(k) + 0.5) / e.rate, t0, t1);
        const float remaining = static_cast<float>(t1 - tb);
        glm::vec3 offset(0.0f);
        switch (e.shape) {
          case Emitter::Shape::kPoint:
            break;
          case Emitter::Shape::kSphere:
            offset = randomUnit(r) * (e.radius * std::cbrt(r.uniform()));
            break;
          case Emitter::Shape::kDisc: {
            const glm::vec3 n = glm::normalize(e.normal), a = anyPerpendicular(n), b = glm::cross(n, a);
            const float rr = e.radius * std::sqrt(r.uniform()), phi = r.uniform() * 2.0f * std::numbers::pi_v<float>;
            offset = rr * (std::cos(phi) * a + std::sin(phi) * b);
            break;
          }
        }
        glm::vec3 v = e.velocity;
        const float speed = glm::length(v);
        if (speed > 0.0f) {
          const glm::vec3 dir = v / speed, a = anyPerpendicular(dir), b = glm::cross(dir, a);
          const float cosMax = std::cos(glm::radians(e.spreadDegrees));
          const float cz = 1.0f - r.uniform() * (1.0f - cosMax);
          const float sz = std::sqrt(std::max(0.0f, 1.0f - cz * cz));
          const float phi = r.uniform() * 2.0f * std::numbers::pi_v<float>;
          const float scale = 1.0f + e.speedSpread * (2.0f * r.uniform() - 1.0f);
          v = speed * scale * (cz * dir + sz * (std::cos(phi) * a + std::sin(phi) * b));
        }
        v += e.inheritVelocity * e.path.velocityAt(tb);
        const glm::vec3 p = e.position + e.path.at(tb) + offset + v * remaining;  // moved to the step's end
        const float lifetime = e.lifetime * (1.0f + e.lifetimeSpread * (2.0f * r.uniform() - 1.0f));
        const float size = e.sizeMin + (e.sizeMax - e.sizeMin) * r.uniform();
        const int var = e.variations.empty()
                            ? std::min(variations - 1, static_cast<int>(r.uniform() * static_cast<float>(variations)))
                            : e.variations[std::min(
                                  e.variations.size() - 1,
                                  static_cast<std::size_t>(r.uniform() * static_cast<float>(e.variations.size())))];
        glm::quat q(1.0f, 0.0f, 0.0f, 0.0f);
        glm::vec3 w(0.0f);
        if (e.oriented) {
          q = glm::angleAxis(r.uniform() * 2.0f * std::numbers::pi_v<float>, randomUnit(r));
          w = randomUnit(r) * (e.spin * r.uniform());
        }
        if (remaining >= lifetime) continue;  // born and dead inside one step
        if (!meshes.empty()) {                // where it was born, for the mesh colliders' segment test
          const glm::vec3 o = e.position + e.path.at(tb) + offset;
          ox.push_back(o.x), oy.push_back(o.y), oz.push_back(o.z);
        }
        px.push_back(p.x), py.push_back(p.y), pz.push_back(p.z);
        vx.push_back(v.x), vy.push_back(v.y), vz.push_back(v.z);
        age.push_back(remaining), life.push_back(lifetime), size0.push_back(size), density0.push_back(e.density);
        qx.push_back(q.x), qy.push_back(q.y), qz.push_back(q.z), qw.push_back(q.w);
        wx.push_back(w.x), wy.push_back(w.y), wz.push_back(w.z);
        variation.push_back(static_cast<std::uint8_t>(var)), oriented.push_back(e.oriented ? 1 : 0);
        emitterOf.push_back(static_cast<std::uint32_t>(ei));
        id.push_back(
            static_cast<std::uint32_t>(Rng(e.seed ^ 0x9e3779b9u, ei, static_cast<std::uint64_t>(k)).state >> 32));
        ++st.born;
      }
    }
  }

  void shedVortices(double t0, double t1) {
    for (const Vortex& v : s.forces.vortices) {
      if (!(v.shedInterval > 0.0f)) continue;
      const auto n0 = static_cast<std::int64_t>(std::floor(t0 / v.shedInterval));
      const auto n1 = static_cast<std::int64_t>(std::floor(t1 / v.shedInterval));
      for (std::int64_t k = n0 + 1; k <= n1; ++k) {
        const double at = static_cast<double>(k) * v.shedInterval;
        // Only a moving vortex leaves a wake: a still one would stack copies on itself.
        if (v.path.velocityAt(at) == glm::vec3(0.0f)) continue;
        shed.push_back(ShedVortex{v.position + v.path.at(at), glm::normalize(v.axis), v.strength, v.radius, v.falloff,
                                  v.length, at, v.shedLifetime});
      }
    }
    std::erase_if(shed, [&](const ShedVortex& v) { return t1 - v.born >= v.lifetime; });
  }

  void advance(StepStats& st) {
    // Scene time: frame 0 is at 0, the preroll before it.
    const double t0 = static_cast<double>(step - prerollSteps) * h,
                 t1 = static_cast<double>(step + 1 - prerollSteps) * h;
    const std::size_t n = size();
    airAll(t0);
    const bool haveMesh = !meshes.empty();
    if (haveMesh) ox = px, oy = py, oz = pz;
    integrate();
    const float* prev[3] = {ox.data(), oy.data(), oz.data()};
    if (!s.colliders.empty()) st.collisions += collide(0, n, prev, t0, t1);
    // Age, and remove the dead and the non-finite, keeping the order.
    const float hf = static_cast<float>(h);
    std::size_t out = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const float a = age[i] + hf;
      const bool finite = std::isfinite(px[i]) && std::isfinite(py[i]) && std::isfinite(pz[i]) &&
                          std::isfinite(vx[i]) && std::isfinite(vy[i]) && std::isfinite(vz[i]);
      if (!finite) ++st.nonFinite;
      if (a >= life[i] || !finite) {
        if (finite) ++st.died;
        continue;
      }
      if (out != i) move(i, out);
      age[out] = a;
      ++out;
    }
    resize(out);
    const std::size_t before = size();
    ox.clear(), oy.clear(), oz.clear();
    spawn(t0, t1, st);
    const float* born[3] = {ox.data(), oy.data(), oz.data()};
    if (!s.colliders.empty()) st.collisions += collide(before, size(), born, t0, t1);
    shedVortices(t0, t1);
    ++step;
  }

  void move(std::size_t from, std::size_t to) {
    for (auto* v : {&px, &py, &pz, &vx, &vy, &vz, &age, &life, &size0, &density0, &qx, &qy, &qz, &qw, &wx, &wy, &wz})
      (*v)[to] = (*v)[from];
    variation[to] = variation[from], oriented[to] = oriented[from];
    emitterOf[to] = emitterOf[from], id[to] = id[from];
  }
  void resize(std::size_t n) {
    for (auto* v : {&px, &py, &pz, &vx, &vy, &vz, &age, &life, &size0, &density0, &qx, &qy, &qz, &qw, &wx, &wy, &wz})
      v->resize(n);
    variation.resize(n), oriented.resize(n), emitterOf.resize(n), id.resize(n);
  }
};

Simulator::Simulator() : impl_(std::make_unique<Impl>()) {}
Simulator::~Simulator() = default;

Result<std::unique_ptr<Simulator>> Simulator::create(Settings settings, int variations) {
  if (auto ok = validate(settings); !ok) return ok.error();
  if (variations < 1 || variations > 256) return Error{"variations: expected an integer in [1, 256]"};
  std::unique_ptr<Simulator> sim(new Simulator());
  Impl& m = *sim->impl_;
  m.s = std::move(settings);
  m.variations = variations;
  m.h = 1.0 / (static_cast<double>(m.s.fps) * m.s.substeps);
  m.prerollSteps = static_cast<std::int64_t>(std::llround(m.s.preroll / m.h));
  for (Collider& c : m.s.colliders) {
    c.rotation = glm::normalize(c.rotation);  // the box and plane use it as a rotation
    if (c.type == Collider::Type::kMesh) m.meshes.emplace_back(c);
  }
  m.prepareTurbulence();
  sim->reset();
  return sim;
}

void Simulator::reset() {
  impl_->clear();
  impl_->step = 0;
  StepStats st;
  while (impl_->step < impl_->prerollSteps) impl_->advance(st);
}

void Simulator::step(StepStats* stats) {
  StepStats st;
  impl_->advance(stats ? *stats : st);
}

void Simulator::advanceToFrame(int frame, StepStats* stats) {
  PUFF_CHECK(frame >= 0);
  const std::int64_t target = impl_->prerollSteps + static_cast<std::int64_t>(frame) * impl_->s.substeps;
  if (target < impl_->step) reset();
  StepStats st;
  while (impl_->step < target) impl_->advance(stats ? *stats : st);
}

Result<void> Simulator::setForces(const Forces& forces) {
  if (auto ok = validate(forces); !ok) return ok.error();
  impl_->s.forces = forces;
  impl_->prepareTurbulence();
  return {};
}

const Settings& Simulator::settings() const { return impl_->s; }
double Simulator::time() const { return static_cast<double>(impl_->step - impl_->prerollSteps) * impl_->h; }
std::int64_t Simulator::stepIndex() const { return impl_->step; }

int Simulator::frame() const {
  const std::int64_t k = impl_->step - impl_->prerollSteps;
  if (k < 0 || k % impl_->s.substeps != 0) return -1;
  return static_cast<int>(k / impl_->s.substeps);
}

std::size_t Simulator::size() const { return impl_->size(); }

ParticleState Simulator::particle(std::size_t i) const {
  const Impl& m = *impl_;
  PUFF_CHECK(i < m.size());
  const float left = std::max(0.0f, 1.0f - m.age[i] / m.life[i]);
  ParticleState p;
  p.position = {m.px[i], m.py[i], m.pz[i]};
  p.velocity = {m.vx[i], m.vy[i], m.vz[i]};
  p.size = m.size0[i] * left;
  p.density = m.density0[i] * left;
  p.variation = m.variation[i];
  p.oriented = m.oriented[i] != 0;
  p.birthSize = m.size0[i];
  p.age = m.age[i];
  p.lifetime = m.life[i];
  p.emitter = static_cast<int>(m.emitterOf[i]);
  p.id = m.id[i];
  glm::quat q(m.qw[i], m.qx[i], m.qy[i], m.qz[i]);
  const glm::vec3 w(m.wx[i], m.wy[i], m.wz[i]);
  const float speed = glm::length(w);
  if (speed > 0.0f) q = glm::angleAxis(speed * m.age[i], w / speed) * q;
  p.orientation = q;
  return p;
}

glm::vec3 Simulator::airVelocity(const glm::vec3& p) const {
  const double t = time();
  return impl_->air(p, t, impl_->liveVortices(t));
}

std::size_t Simulator::liveVortices() const { return impl_->s.forces.vortices.size() + impl_->shed.size(); }

}  // namespace puff::sim
