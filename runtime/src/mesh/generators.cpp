// Built-in puff shapes: icosphere, lumpy (noise-displaced) sphere, cluster of spheres.
//
// Determinism: every generator must give bit-identical positions for a seed on every platform and
// compiler. So: our own PRNG (splitmix64) and noise, no std:: distributions, no libm calls other
// than sqrt and floor (both exact or correctly rounded by IEEE 754), arithmetic in double, and
// no fused multiply-adds (below).
#include <puff/mesh/mesh.h>

#include <puff/core/random.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace puff::mesh {
namespace {

struct DVec3 {
  double x = 0, y = 0, z = 0;
};
DVec3 operator+(const DVec3& a, const DVec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
DVec3 operator*(const DVec3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(const DVec3& a, const DVec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
DVec3 normalized(const DVec3& a) { return a * (1.0 / std::sqrt(dot(a, a))); }

using core::SplitMix64;

struct Icosphere {
  std::vector<DVec3> positions;  // unit length
  std::vector<glm::uvec3> triangles;
};

Icosphere makeIcosphere(int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  Icosphere s;
  // clang-format off
  const DVec3 base[12] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (const DVec3& v : base) s.positions.push_back(normalized(v));
  // Counter-clockwise seen from outside.
  s.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  // clang-format on

  for (int level = 0; level < subdivisions; ++level) {
    // One new vertex per edge, shared by the two triangles on it, so the result stays closed.
    std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
    midpoints.reserve(s.triangles.size() * 3 / 2);
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      auto [it, inserted] = midpoints.try_emplace(key, std::uint32_t(s.positions.size()));
      if (inserted) s.positions.push_back(normalized(s.positions[a] + s.positions[b]));
      return it->second;
    };
    std::vector<glm::uvec3> next;
    next.reserve(s.triangles.size() * 4);
    for (const glm::uvec3& tri : s.triangles) {
      const std::uint32_t ab = midpoint(tri[0], tri[1]);
      const std::uint32_t bc = midpoint(tri[1], tri[2]);
      const std::uint32_t ca = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], ab, ca});
      next.push_back({tri[1], bc, ab});
      next.push_back({tri[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    s.triangles = std::move(next);
  }
  return s;
}

TriMesh finish(const std::vector<DVec3>& positions, std::vector<glm::uvec3> triangles) {
  TriMesh m;
  m.positions.reserve(positions.size());
  for (const DVec3& p : positions) m.positions.emplace_back(float(p.x), float(p.y), float(p.z));
  m.triangles = std::move(triangles);
  normalizeToUnitSphere(m);
  computeNormals(m);
  return m;
}

// ---- value noise ------------------------------------------------------------------------------
// Value noise rather than gradient noise: it is a convex blend of lattice values in [-1, 1], so
// it provably stays in [-1, 1], and radius 1 + amplitude * noise stays > 0 for amplitude <= 0.9.

double latticeValue(std::int64_t x, std::int64_t y, std::int64_t z, std::uint64_t seed) {
  std::uint64_t h = seed;
  h = core::mix64(h ^ (std::uint64_t(x) * 0x9E3779B97F4A7C15ull));
  h = core::mix64(h ^ (std::uint64_t(y) * 0xC2B2AE3D27D4EB4Full));
  h = core::mix64(h ^ (std::uint64_t(z) * 0x165667B19E3779F9ull));
  return double(h >> 11) * 0x1.0p-52 - 1.0;  // [-1, 1)
}

double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }  // C2 quintic
double lerp(double a, double b, double t) { return a + (b - a) * t; }

double valueNoise(const DVec3& p, std::uint64_t seed) {
  const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
  const auto ix = std::int64_t(fx), iy = std::int64_t(fy), iz = std::int64_t(fz);
  const double u = fade(p.x - fx), v = fade(p.y - fy), w = fade(p.z - fz);
  auto at = [&](int dx, int dy, int dz) { return latticeValue(ix + dx, iy + dy, iz + dz, seed); };
  const double x00 = lerp(at(0, 0, 0), at(1, 0, 0), u), x10 = lerp(at(0, 1, 0), at(1, 1, 0), u);
  const double x01 = lerp(at(0, 0, 1), at(1, 0, 1), u), x11 = lerp(at(0, 1, 1), at(1, 1, 1), u);
  return lerp(lerp(x00, x10, v), lerp(x01, x11, v), w);
}

/// Fractal sum of octaves (frequency doubling, amplitude halving), rescaled to [-1, 1].
double fractalNoise(const DVec3& p, double frequency, int octaves, std::uint64_t seed) {
  SplitMix64 rng(seed);
  double sum = 0.0, norm = 0.0, amp = 1.0, freq = frequency;
  for (int o = 0; o < octaves; ++o) {
    // A per-octave seed and offset keep octaves from lining up on lattice points at the origin.
    const std::uint64_t octaveSeed = rng.next();
    const DVec3 offset{rng.unit() * 64.0, rng.unit() * 64.0, rng.unit() * 64.0};
    sum = sum + amp * valueNoise(p * freq + offset, octaveSeed);
    norm = norm + amp;
    amp = amp * 0.5;
    freq = freq * 2.0;
  }
  return sum / norm;
}

}  // namespace

TriMesh generateSphere(const SphereParams& p) {
  PUFF_CHECK(validate(p).ok());
  Icosphere s = makeIcosphere(p.subdivisions);
  return finish(s.positions, std::move(s.triangles));
}

TriMesh generateLumpy(const LumpyParams& p) {
  PUFF_CHECK(validate(p).ok());
  Icosphere s = makeIcosphere(p.subdivisions);
  // Radial displacement of a sphere keeps it star-shaped: it cannot fold over itself.
  for (DVec3& d : s.positions) {
    const double n = fractalNoise(d, double(p.frequency), p.octaves, p.seed);
    d = d * (1.0 + double(p.amplitude) * n);
  }
  return finish(s.positions, std::move(s.triangles));
}

TriMesh generateCluster(const ClusterParams& p) {
  PUFF_CHECK(validate(p).ok());
  const Icosphere unit = makeIcosphere(p.subdivisions);
  SplitMix64 rng(p.seed);
  std::vector<DVec3> positions;
  std::vector<glm::uvec3> triangles;
  positions.reserve(unit.positions.size() * std::size_t(p.count));
  triangles.reserve(unit.triangles.size() * std::size_t(p.count));
  double firstRadius = 0.0;
  for (int i = 0; i < p.count; ++i) {
    const double radius = double(p.radiusMin) + double(p.radiusMax - p.radiusMin) * rng.unit();
    DVec3 center;
    if (i == 0) {
      firstRadius = radius;  // at the origin, the sphere every other one overlaps
    } else {
      // Uniform in the ball of radius `spread`, by rejection from the cube (no cbrt needed).
      DVec3 q;
      do {
        q = {rng.unit() * 2.0 - 1.0, rng.unit() * 2.0 - 1.0, rng.unit() * 2.0 - 1.0};
      } while (dot(q, q) > 1.0);
      center = q * double(p.spread);
      // Pull a sphere that would float free in until it overlaps the first one, so the cluster
      // reads as one puff (its components still intersect rather than join; that is fine).
      const double dist = std::sqrt(dot(center, center));
      const double maxDist = 0.9 * (firstRadius + radius);
      if (dist > maxDist) center = center * (maxDist / dist);
    }
    const auto base = std::uint32_t(positions.size());
    for (const DVec3& d : unit.positions) positions.push_back(d * radius + center);
    for (const glm::uvec3& t : unit.triangles) triangles.push_back(t + glm::uvec3(base));
  }
  return finish(positions, std::move(triangles));
}

}  // namespace puff::mesh
