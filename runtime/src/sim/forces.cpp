// The air (wind, wind volumes, vortices, turbulence) and the integrator that moves the particles
// through it.
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "simulator_impl.h"

namespace puff::sim {

using detail::LiveVortex;

namespace {

constexpr float kLambOseenPeak = 0.638172f;  // max of (1 - exp(-s^2)) / s, at s = 1.12092

// Turbulence lookups: the lattice tile holds 4 noise cells; one cell is `scale` world units (the
// swirl size), and the frozen field drifts `speed` cells per second (Taylor's hypothesis: a
// translated divergence-free field is still divergence-free), so the air at a point changes
// over about 1 / speed seconds.
constexpr float kCellsPerTile = 4.0f;
// The way the field drifts through its lattice (a unit vector off every lattice axis and diagonal).
constexpr glm::dvec3 kDriftDirection{0.8, 0.36, 0.48};

// The air one vortex adds to particles [begin, n): vortexVelocity written out in scalars over the
// arrays, in a free function so the compiler sees no aliasing and vectorizes it (SSE2).
void addVortexFrom(const LiveVortex& v, const float* __restrict X, const float* __restrict Y, const float* __restrict Z,
                   float* __restrict UX, float* __restrict UY, float* __restrict UZ, std::size_t begin, std::size_t n) {
  const float cx = v.center.x, cy = v.center.y, cz = v.center.z;
  const float ax = v.axis.x, ay = v.axis.y, az = v.axis.z;
  const float scale = v.scale, ir2 = v.invRadius2, if2 = v.invFalloff2, ih2 = v.invHalfLength2, cutoff2 = v.cutoff2;
  for (std::size_t i = begin; i < n; ++i) {
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

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define PUFF_SIM_VORTEX_AVX2 1

[[gnu::target("avx2")]] inline __m256 mul(__m256 a, __m256 b) { return _mm256_mul_ps(a, b); }
[[gnu::target("avx2")]] inline __m256 add(__m256 a, __m256 b) { return _mm256_add_ps(a, b); }
[[gnu::target("avx2")]] inline __m256 sub(__m256 a, __m256 b) { return _mm256_sub_ps(a, b); }

// detail::fastExp on eight lanes, operation for operation (selects as blends, so NaN and the
// clamps behave as the scalar ternaries do): the same bits.
[[gnu::target("avx2")]] inline __m256 fastExp8(__m256 x) {
  const __m256 lo = _mm256_set1_ps(-87.0f), zero = _mm256_setzero_ps();
  // x < -87 ? -87 : (x > 0 ? 0 : x)
  const __m256 xc = _mm256_blendv_ps(_mm256_blendv_ps(x, zero, _mm256_cmp_ps(x, zero, _CMP_GT_OQ)), lo,
                                     _mm256_cmp_ps(x, lo, _CMP_LT_OQ));
  const __m256 t = _mm256_mul_ps(xc, _mm256_set1_ps(1.44269504f));
  const __m256 a = _mm256_add_ps(t, _mm256_set1_ps(0.5f));
  const __m256 truncated = _mm256_cvtepi32_ps(_mm256_cvttps_epi32(a));
  const __m256 fi =
      _mm256_sub_ps(truncated, _mm256_and_ps(_mm256_cmp_ps(truncated, a, _CMP_GT_OQ), _mm256_set1_ps(1.0f)));
  const __m256 f = _mm256_sub_ps(t, fi);
  __m256 p = _mm256_set1_ps(1.5403530e-4f);
  p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(1.3333558e-3f));
  p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(9.6181291e-3f));
  p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(5.5504109e-2f));
  p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(2.4022651e-1f));
  p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(6.9314718e-1f));
  p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(1.0f));
  const __m256 out =
      _mm256_castsi256_ps(_mm256_add_epi32(_mm256_castps_si256(p), _mm256_slli_epi32(_mm256_cvttps_epi32(fi), 23)));
  return _mm256_blendv_ps(out, zero, _mm256_cmp_ps(x, lo, _CMP_LE_OQ));
}

// addVortexFrom on eight particles at a time, operation for operation; returns how many it did
// (a multiple of 8). GCC 12 does not vectorize fastExp's selects for AVX2 by itself.
[[gnu::target("avx2")]] std::size_t addVortexAvx2(const LiveVortex& v, const float* X, const float* Y, const float* Z,
                                                  float* UX, float* UY, float* UZ, std::size_t n) {
  const __m256 cx = _mm256_set1_ps(v.center.x), cy = _mm256_set1_ps(v.center.y), cz = _mm256_set1_ps(v.center.z);
  const __m256 ax = _mm256_set1_ps(v.axis.x), ay = _mm256_set1_ps(v.axis.y), az = _mm256_set1_ps(v.axis.z);
  const __m256 scale = _mm256_set1_ps(v.scale), ir2 = _mm256_set1_ps(v.invRadius2), if2 = _mm256_set1_ps(v.invFalloff2),
               ih2 = _mm256_set1_ps(v.invHalfLength2), cutoff2 = _mm256_set1_ps(v.cutoff2);
  const __m256 tiny = _mm256_set1_ps(1e-12f), one = _mm256_set1_ps(1.0f), sign = _mm256_set1_ps(-0.0f);
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    const __m256 dx = sub(_mm256_loadu_ps(X + i), cx), dy = sub(_mm256_loadu_ps(Y + i), cy),
                 dz = sub(_mm256_loadu_ps(Z + i), cz);
    const __m256 along = add(add(mul(dx, ax), mul(dy, ay)), mul(dz, az));
    const __m256 rx = sub(dx, mul(along, ax)), ry = sub(dy, mul(along, ay)), rz = sub(dz, mul(along, az));
    const __m256 r2 = add(add(mul(rx, rx), mul(ry, ry)), mul(rz, rz));
    const __m256 inside = mul(_mm256_and_ps(_mm256_cmp_ps(r2, tiny, _CMP_GE_OQ), one),
                              _mm256_and_ps(_mm256_cmp_ps(r2, cutoff2, _CMP_LE_OQ), one));
    const __m256 r2s = _mm256_blendv_ps(r2, tiny, _mm256_cmp_ps(r2, tiny, _CMP_LT_OQ));  // std::max(r2, tiny)
    const __m256 negR2s = _mm256_xor_ps(r2s, sign);
    const __m256 core = sub(one, fastExp8(mul(negR2s, ir2)));
    const __m256 k = mul(_mm256_div_ps(mul(mul(inside, scale), core), r2s),
                         fastExp8(sub(mul(negR2s, if2), mul(mul(along, along), ih2))));
    _mm256_storeu_ps(UX + i, add(_mm256_loadu_ps(UX + i), mul(k, sub(mul(ay, rz), mul(az, ry)))));
    _mm256_storeu_ps(UY + i, add(_mm256_loadu_ps(UY + i), mul(k, sub(mul(az, rx), mul(ax, rz)))));
    _mm256_storeu_ps(UZ + i, add(_mm256_loadu_ps(UZ + i), mul(k, sub(mul(ax, ry), mul(ay, rx)))));
  }
  return i;
}
#endif

// The air one vortex adds to every particle: eight at a time where the CPU has AVX2, the rest
// (and everything elsewhere) four at a time; both give the same bits.
void addVortex(const LiveVortex& v, const float* X, const float* Y, const float* Z, float* UX, float* UY, float* UZ,
               std::size_t n) {
  std::size_t done = 0;
#if defined(PUFF_SIM_VORTEX_AVX2)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) done = addVortexAvx2(v, X, Y, Z, UX, UY, UZ, n);
#endif
  addVortexFrom(v, X, Y, Z, UX, UY, UZ, done, n);
}

// One exponential-integrator step for every particle (see integrate); free, so it vectorizes.
// With e = exp(-k h), c1 = (1 - e) / k and c2 = (h - c1) / k (computed in double, by series for small
// k h, so nothing divides by a small drag):
//   v' = v e + u (1 - e) + a c1,   x' = x + v c1 + u (h - c1) + a c2
// the exact solution of dv/dt = a + k (u - v) with u and a held; k = 0 gives x + v h + a h^2 / 2.
PUFF_SIM_KERNEL void integrateExponential(float* __restrict X, float* __restrict Y, float* __restrict Z,
                                          float* __restrict VX, float* __restrict VY, float* __restrict VZ,
                                          const float* __restrict UX, const float* __restrict UY,
                                          const float* __restrict UZ, const float* __restrict A,
                                          const float* __restrict L, const float* __restrict D0, std::size_t n,
                                          glm::vec3 g, glm::vec3 b, float e, float oneMinusE, float c1, float hMinusC1,
                                          float c2) {
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

// The paper's forward Euler step for every particle: v' = v + h (g + b density + k (u - v)),
// x' = x + h v. Free, so it vectorizes.
PUFF_SIM_KERNEL void integrateForwardEuler(float* __restrict X, float* __restrict Y, float* __restrict Z,
                                           float* __restrict VX, float* __restrict VY, float* __restrict VZ,
                                           const float* __restrict UX, const float* __restrict UY,
                                           const float* __restrict UZ, const float* __restrict A,
                                           const float* __restrict L, const float* __restrict D0, std::size_t n,
                                           float gx, float gy, float gz, float bx, float by, float bz, float k,
                                           float hf) {
  for (std::size_t i = 0; i < n; ++i) {
    const float density = D0[i] * (1.0f - A[i] / L[i]);
    const float ax = gx + bx * density + k * (UX[i] - VX[i]);
    const float ay = gy + by * density + k * (UY[i] - VY[i]);
    const float az = gz + bz * density + k * (UZ[i] - VZ[i]);
    X[i] += hf * VX[i], Y[i] += hf * VY[i], Z[i] += hf * VZ[i];
    VX[i] += hf * ax, VY[i] += hf * ay, VZ[i] += hf * az;
  }
}

// The air a wind volume adds (windWeight over the arrays), branch-free.
PUFF_SIM_KERNEL void addWindVolume(const WindVolume& w, const float* __restrict X, const float* __restrict Y,
                                   const float* __restrict Z, float* __restrict UX, float* __restrict UY,
                                   float* __restrict UZ, std::size_t n) {
  const float cx = w.center.x, cy = w.center.y, cz = w.center.z;
  const float hx = w.halfExtent.x, hy = w.halfExtent.y, hz = w.halfExtent.z;
  const float invFeather = w.feather > 0.0f ? 1.0f / w.feather : 0.0f;
  const bool hard = !(w.feather > 0.0f);
  const float wx = w.velocity.x, wy = w.velocity.y, wz = w.velocity.z;
  for (std::size_t i = 0; i < n; ++i) {
    const float ox = std::max(std::abs(X[i] - cx) - hx, 0.0f), oy = std::max(std::abs(Y[i] - cy) - hy, 0.0f),
                oz = std::max(std::abs(Z[i] - cz) - hz, 0.0f);
    const float d = std::sqrt(ox * ox + oy * oy + oz * oz);
    const float x = std::max(0.0f, 1.0f - d * invFeather);
    float k = x * x * (3.0f - 2.0f * x);
    k = (d == 0.0f) ? 1.0f : (hard ? 0.0f : k);
    UX[i] += k * wx, UY[i] += k * wy, UZ[i] += k * wz;
  }
}

float windWeight(const glm::vec3& p, const WindVolume& w) {
  const glm::vec3 outside = glm::max(glm::abs(p - w.center) - w.halfExtent, glm::vec3(0.0f));
  const float d = std::sqrt(glm::dot(outside, outside));
  if (d == 0.0f) return 1.0f;
  if (!(d < w.feather)) return 0.0f;
  const float x = 1.0f - d / w.feather;
  return x * x * (3.0f - 2.0f * x);
}

glm::vec3 vortexVelocity(const glm::vec3& p, const LiveVortex& v) {
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

}  // namespace

void Simulator::Impl::prepareTurbulence() {
  if (s.forces.turbulence.strength > 0.0f && (!curl || curlSeed != s.forces.turbulence.seed)) {
    curl = std::make_unique<detail::CurlField>(s.forces.turbulence.seed);
    curlSeed = s.forces.turbulence.seed;
  }
  // A loop drifts whole tiles a period (the field repeats every tile), the nearest to its speed.
  const double tiles = s.period > 0 ? s.forces.turbulence.speed * loopSeconds() / kCellsPerTile : 0.0;
  loopDrift = glm::vec3(glm::round(tiles * kDriftDirection));
}

double Simulator::Impl::loopSeconds() const { return s.period / static_cast<double>(s.fps); }

std::vector<LiveVortex> Simulator::Impl::liveVortices(double t) const {
  std::vector<LiveVortex> out;
  auto add = [&](const glm::vec3& c, const glm::vec3& axis, float strength, float radius, float falloff, float length) {
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
  for (const detail::ShedVortex& v : shed) {
    const float fade = static_cast<float>(std::max(0.0, 1.0 - (t - v.born) / v.lifetime));
    add(v.position, v.axis, v.strength * fade, v.radius, v.falloff, v.length);
  }
  return out;
}

float Simulator::Impl::turbulenceInvTile() const { return 1.0f / (s.forces.turbulence.scale * kCellsPerTile); }
glm::vec3 Simulator::Impl::turbulenceOffset(std::int64_t b) const {
  const double t = static_cast<double>(b) * h;
  if (s.period > 0) {  // a whole number of tiles a period: the same offset at b and b + a period of steps
    const std::int64_t steps = static_cast<std::int64_t>(s.period) * s.substeps;
    const double phase = static_cast<double>(((b % steps) + steps) % steps) / static_cast<double>(steps);
    auto at = [&](float drift) {
      const double d = drift * phase;
      return static_cast<float>(d - std::floor(d));
    };
    return {at(loopDrift.x), at(loopDrift.y), at(loopDrift.z)};
  }
  const double d = static_cast<double>(s.forces.turbulence.speed) * t / kCellsPerTile;
  return glm::vec3(static_cast<float>(std::fmod(d * kDriftDirection.x, 1.0)),
                   static_cast<float>(std::fmod(d * kDriftDirection.y, 1.0)),
                   static_cast<float>(std::fmod(d * kDriftDirection.z, 1.0)));
}

// The air velocity at one point (the same sum airAll makes for every particle).
glm::vec3 Simulator::Impl::air(const glm::vec3& p, std::int64_t b, const std::vector<LiveVortex>& vortices) const {
  const Forces& f = s.forces;
  glm::vec3 u = f.wind;
  for (const WindVolume& w : f.windVolumes) u += w.velocity * windWeight(p, w);
  for (const LiveVortex& v : vortices) u += vortexVelocity(p, v);
  const Turbulence& tb = f.turbulence;
  if (tb.strength > 0.0f && curl) u += tb.strength * curl->sample(p * turbulenceInvTile() + turbulenceOffset(b));
  return u;
}

// Air velocity for particles [begin, end) into ux/uy/uz, one field at a time over the arrays (the
// vortex and wind-volume loops vectorize; the turbulence lookup gathers lattice corners).
void Simulator::Impl::airRange(std::size_t begin, std::size_t end) {
  const std::size_t n = end - begin;
  const Forces& f = s.forces;
  const float* X = px.data() + begin;
  const float* Y = py.data() + begin;
  const float* Z = pz.data() + begin;
  float* UX = ux.data() + begin;
  float* UY = uy.data() + begin;
  float* UZ = uz.data() + begin;
  std::fill(UX, UX + n, f.wind.x);
  std::fill(UY, UY + n, f.wind.y);
  std::fill(UZ, UZ + n, f.wind.z);
  for (const WindVolume& w : f.windVolumes) addWindVolume(w, X, Y, Z, UX, UY, UZ, n);
  for (const LiveVortex& v : stepVortices) addVortex(v, X, Y, Z, UX, UY, UZ, n);
  const Turbulence& tb = f.turbulence;
  if (tb.strength > 0.0f && curl)
    curl->addSamples(X, Y, Z, n, turbulenceInvTile(), stepTurbulenceOffset, tb.strength, UX, UY, UZ);
}

void Simulator::Impl::integrateRange(std::size_t begin, std::size_t end) {
  const std::size_t n = end - begin;
  const Forces& f = s.forces;
  const float hf = static_cast<float>(h);
  const glm::vec3 up = glm::normalize(f.up);
  const float bx = f.buoyancy * up.x, by = f.buoyancy * up.y, bz = f.buoyancy * up.z;
  const float gx = f.gravity.x, gy = f.gravity.y, gz = f.gravity.z;
  const float k = f.drag;
  float* X = px.data() + begin;
  float* Y = py.data() + begin;
  float* Z = pz.data() + begin;
  float* VX = vx.data() + begin;
  float* VY = vy.data() + begin;
  float* VZ = vz.data() + begin;
  const float* UX = ux.data() + begin;
  const float* UY = uy.data() + begin;
  const float* UZ = uz.data() + begin;
  const float* A = age.data() + begin;
  const float* L = life.data() + begin;
  const float* D0 = density0.data() + begin;
  if (s.integrator == Integrator::kForwardEuler) {
    integrateForwardEuler(X, Y, Z, VX, VY, VZ, UX, UY, UZ, A, L, D0, n, gx, gy, gz, bx, by, bz, k, hf);
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

}  // namespace puff::sim
