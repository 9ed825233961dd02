#include "curl_noise.h"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <puff/core/random.h>
#include <glm/geometric.hpp>

namespace puff::sim::detail {

namespace {

constexpr std::uint32_t hash(std::uint32_t x) { return core::lowbias32(x); }

int wrap(int i, int n) {
  const int r = i % n;
  return r < 0 ? r + n : r;
}

float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
float fadeDerivative(float t) { return 30.0f * t * t * (t * (t - 2.0f) + 1.0f); }

}  // namespace

GradientNoise::GradientNoise(std::uint32_t seed, int period) : seed_(seed), period_(period) {}

glm::vec3 GradientNoise::grad(int x, int y, int z) const {
  x = wrap(x, period_), y = wrap(y, period_), z = wrap(z, period_);
  std::uint32_t h = hash(seed_ ^ hash(static_cast<std::uint32_t>(x) +
                                      hash(static_cast<std::uint32_t>(y) + hash(static_cast<std::uint32_t>(z)))));
  // A uniform direction from two hashed numbers.
  const float u = static_cast<float>(h & 0xffffU) / 65535.0f * 2.0f - 1.0f;
  const float phi = static_cast<float>(h >> 16) / 65536.0f * 6.28318530718f;
  const float s = std::sqrt(std::max(0.0f, 1.0f - u * u));
  return {s * std::cos(phi), s * std::sin(phi), u};
}

float GradientNoise::eval(const glm::vec3& p, glm::vec3* gradient) const {
  const glm::vec3 fl = glm::floor(p);
  const int x0 = static_cast<int>(fl.x), y0 = static_cast<int>(fl.y), z0 = static_cast<int>(fl.z);
  const glm::vec3 f = p - fl;
  const glm::vec3 w{fade(f.x), fade(f.y), fade(f.z)};
  const glm::vec3 dw{fadeDerivative(f.x), fadeDerivative(f.y), fadeDerivative(f.z)};
  float value = 0.0f;
  glm::vec3 g(0.0f);
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const glm::vec3 gr = grad(x0 + dx, y0 + dy, z0 + dz);
    const glm::vec3 d = f - glm::vec3(dx, dy, dz);
    const float n = glm::dot(gr, d);
    const float wx = dx ? w.x : 1.0f - w.x, wy = dy ? w.y : 1.0f - w.y, wz = dz ? w.z : 1.0f - w.z;
    const float sx = dx ? dw.x : -dw.x, sy = dy ? dw.y : -dw.y, sz = dz ? dw.z : -dw.z;
    value += wx * wy * wz * n;
    g += wx * wy * wz * gr + glm::vec3(sx * wy * wz, wx * sy * wz, wx * wy * sz) * n;
  }
  if (gradient) *gradient = g;
  return value;
}

CurlField::CurlField(std::uint32_t seed, int n, int noiseCells)
    : n_(n),
      a_(seed * 3U + 1U, noiseCells),
      b_(seed * 3U + 2U, noiseCells),
      c_(seed * 3U + 3U, noiseCells),
      noiseCells_(noiseCells) {
  top_ = std::nextafter(static_cast<float>(n), 0.0f);
  const std::size_t m = static_cast<std::size_t>(n) + 1;
  v_.resize(m * m * m * 4);  // xyz + padding: one 16-byte load per corner
  double sumSquares = 0.0;
  for (std::size_t z = 0; z < m; ++z) {
    for (std::size_t y = 0; y < m; ++y) {
      for (std::size_t x = 0; x < m; ++x) {
        // The padding layer x, y or z = n holds the samples at 0: the field is periodic.
        const glm::vec3 cell(static_cast<float>(x % static_cast<std::size_t>(n)),
                             static_cast<float>(y % static_cast<std::size_t>(n)),
                             static_cast<float>(z % static_cast<std::size_t>(n)));
        const glm::vec3 v = exact(cell / static_cast<float>(n));
        const std::size_t i = ((z * m + y) * m + x) * 4;
        v_[i] = v.x, v_[i + 1] = v.y, v_[i + 2] = v.z, v_[i + 3] = 0.0f;
        if (x < m - 1 && y < m - 1 && z < m - 1) sumSquares += glm::dot(v, v);
      }
    }
  }
  const double rms = std::sqrt(sumSquares / (static_cast<double>(n) * n * n));
  norm_ = rms > 0.0 ? static_cast<float>(1.0 / rms) : 1.0f;
  for (float& c : v_) c *= norm_;
}

glm::vec3 CurlField::exact(const glm::vec3& p) const {
  // curl (A, B, C) = (dC/dy - dB/dz, dA/dz - dC/dx, dB/dx - dA/dy), in tile units.
  const glm::vec3 q = p * static_cast<float>(noiseCells_);
  glm::vec3 ga, gb, gc;
  a_.eval(q, &ga);
  b_.eval(q, &gb);
  c_.eval(q, &gc);
  const float s = static_cast<float>(noiseCells_) * norm_;
  return glm::vec3(gc.y - gb.z, ga.z - gc.x, gb.x - ga.y) * s;
}

glm::vec3 CurlField::sample(const glm::vec3& p) const {
  const float nf = static_cast<float>(n_);
  // Into the tile first (the field repeats every 1), so no float -> int conversion can overflow;
  // p - floor(p) can round up to 1, hence the clamp below n.
  const float top = top_;
  const glm::vec3 q = glm::clamp((p - glm::floor(p)) * nf, glm::vec3(0.0f), glm::vec3(top));
  const int x0 = static_cast<int>(q.x), y0 = static_cast<int>(q.y), z0 = static_cast<int>(q.z);
  const glm::vec3 f = q - glm::vec3(x0, y0, z0);
  const std::size_t m = static_cast<std::size_t>(n_) + 1;
  const float* c =
      &v_[((static_cast<std::size_t>(z0) * m + static_cast<std::size_t>(y0)) * m + static_cast<std::size_t>(x0)) * 4];
  const std::size_t dy = m * 4, dz = m * m * 4;
#if defined(__SSE2__)
  // The eight corners as four-float vectors: the trilinear blend in 7 vector lerps.
  auto lerp = [](__m128 a, __m128 b, __m128 t) { return _mm_add_ps(a, _mm_mul_ps(_mm_sub_ps(b, a), t)); };
  const __m128 fx = _mm_set1_ps(f.x), fy = _mm_set1_ps(f.y), fz = _mm_set1_ps(f.z);
  const __m128 c00 = lerp(_mm_loadu_ps(c), _mm_loadu_ps(c + 4), fx);
  const __m128 c10 = lerp(_mm_loadu_ps(c + dy), _mm_loadu_ps(c + dy + 4), fx);
  const __m128 c01 = lerp(_mm_loadu_ps(c + dz), _mm_loadu_ps(c + dz + 4), fx);
  const __m128 c11 = lerp(_mm_loadu_ps(c + dz + dy), _mm_loadu_ps(c + dz + dy + 4), fx);
  alignas(16) float out[4];
  _mm_store_ps(out, lerp(lerp(c00, c10, fy), lerp(c01, c11, fy), fz));
  return glm::vec3(out[0], out[1], out[2]);
#else
  glm::vec3 out;
  for (int k = 0; k < 3; ++k) {
    const float c00 = c[k] + (c[4 + k] - c[k]) * f.x;
    const float c10 = c[dy + k] + (c[dy + 4 + k] - c[dy + k]) * f.x;
    const float c01 = c[dz + k] + (c[dz + 4 + k] - c[dz + k]) * f.x;
    const float c11 = c[dz + dy + k] + (c[dz + dy + 4 + k] - c[dz + dy + k]) * f.x;
    const float c0 = c00 + (c10 - c00) * f.y, c1 = c01 + (c11 - c01) * f.y;
    out[k] = c0 + (c1 - c0) * f.z;
  }
  return out;
#endif
}

PUFF_SIM_KERNEL void CurlField::addSamples(const float* X, const float* Y, const float* Z, std::size_t n, float scale,
                                           const glm::vec3& offset, float strength, float* UX, float* UY,
                                           float* UZ) const {
  std::size_t i = 0;
#if defined(__SSE2__)
  const int m = n_ + 1;
  const std::size_t dy = static_cast<std::size_t>(m) * 4, dz = static_cast<std::size_t>(m) * m * 4;
  const __m128 vscale = _mm_set1_ps(scale), vstrength = _mm_set1_ps(strength);
  const __m128 ox = _mm_set1_ps(offset.x), oy = _mm_set1_ps(offset.y), oz = _mm_set1_ps(offset.z);
  const __m128 nf = _mm_set1_ps(static_cast<float>(n_)), top = _mm_set1_ps(top_), zero = _mm_setzero_ps();
  const __m128 one = _mm_set1_ps(1.0f), mf = _mm_set1_ps(static_cast<float>(m));
  const __m128 sign = _mm_set1_ps(-0.0f), two23 = _mm_set1_ps(8388608.0f);
  // floor(x) as std::floor gives it: truncate, step down where that rounded up, keep x where it is
  // already an integer (|x| >= 2^23, beyond the int range too), and keep x's sign (floor(-0) = -0).
  auto floor4 = [&](__m128 x) {
    const __m128 t = _mm_cvtepi32_ps(_mm_cvttps_epi32(x));
    const __m128 down = _mm_sub_ps(t, _mm_and_ps(_mm_cmpgt_ps(t, x), one));
    const __m128 big = _mm_cmpge_ps(_mm_andnot_ps(sign, x), two23);
    const __m128 r = _mm_or_ps(_mm_and_ps(big, x), _mm_andnot_ps(big, down));
    return _mm_or_ps(_mm_andnot_ps(sign, r), _mm_and_ps(sign, x));
  };
  // Into the tile, scaled to lattice cells and clamped below n, as sample does.
  auto cells = [&](__m128 p) { return _mm_min_ps(_mm_max_ps(_mm_mul_ps(_mm_sub_ps(p, floor4(p)), nf), zero), top); };
  auto lerp = [](__m128 a, __m128 b, __m128 t) { return _mm_add_ps(a, _mm_mul_ps(_mm_sub_ps(b, a), t)); };
  // In chunks: first every point's corner index and fractions (vectorized), then the corner loads,
  // prefetched a few points ahead (the lattice does not fit the first-level cache and the points
  // jump about in it).
  constexpr std::size_t kChunk = 256, kAhead = 8;
  alignas(16) float fx[kChunk], fy[kChunk], fz[kChunk];
  alignas(16) std::int32_t at[kChunk];
  while (i + 4 <= n) {
    const std::size_t count = std::min(kChunk, (n - i) / 4 * 4);
    for (std::size_t j = 0; j < count; j += 4) {
      const __m128 qx = cells(_mm_add_ps(_mm_mul_ps(_mm_loadu_ps(X + i + j), vscale), ox));
      const __m128 qy = cells(_mm_add_ps(_mm_mul_ps(_mm_loadu_ps(Y + i + j), vscale), oy));
      const __m128 qz = cells(_mm_add_ps(_mm_mul_ps(_mm_loadu_ps(Z + i + j), vscale), oz));
      const __m128 x0 = _mm_cvtepi32_ps(_mm_cvttps_epi32(qx)), y0 = _mm_cvtepi32_ps(_mm_cvttps_epi32(qy)),
                   z0 = _mm_cvtepi32_ps(_mm_cvttps_epi32(qz));
      _mm_store_ps(fx + j, _mm_sub_ps(qx, x0));
      _mm_store_ps(fy + j, _mm_sub_ps(qy, y0));
      _mm_store_ps(fz + j, _mm_sub_ps(qz, z0));
      // The corner's sample index, exact in float (at most 33^3).
      _mm_store_si128(reinterpret_cast<__m128i*>(at + j),
                      _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(_mm_add_ps(_mm_mul_ps(z0, mf), y0), mf), x0)));
    }
    for (std::size_t j = 0; j < count; j += 4) {
      for (std::size_t k = j + kAhead; k < std::min(count, j + kAhead + 4); ++k) {
        const char* c = reinterpret_cast<const char*>(&v_[static_cast<std::size_t>(at[k]) * 4]);
        _mm_prefetch(c, _MM_HINT_T0);
        _mm_prefetch(c + dy * sizeof(float), _MM_HINT_T0);
        _mm_prefetch(c + dz * sizeof(float), _MM_HINT_T0);
        _mm_prefetch(c + (dz + dy) * sizeof(float), _MM_HINT_T0);
      }
      __m128 r[4];
      for (std::size_t k = 0; k < 4; ++k) {
        const float* c = &v_[static_cast<std::size_t>(at[j + k]) * 4];
        const __m128 tx = _mm_set1_ps(fx[j + k]), ty = _mm_set1_ps(fy[j + k]), tz = _mm_set1_ps(fz[j + k]);
        const __m128 c00 = lerp(_mm_loadu_ps(c), _mm_loadu_ps(c + 4), tx);
        const __m128 c10 = lerp(_mm_loadu_ps(c + dy), _mm_loadu_ps(c + dy + 4), tx);
        const __m128 c01 = lerp(_mm_loadu_ps(c + dz), _mm_loadu_ps(c + dz + 4), tx);
        const __m128 c11 = lerp(_mm_loadu_ps(c + dz + dy), _mm_loadu_ps(c + dz + dy + 4), tx);
        r[k] = _mm_mul_ps(vstrength, lerp(lerp(c00, c10, ty), lerp(c01, c11, ty), tz));
      }
      // Four (x, y, z, 0) rows into x, y and z columns.
      _MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
      float* ux = UX + i + j;
      float* uy = UY + i + j;
      float* uz = UZ + i + j;
      _mm_storeu_ps(ux, _mm_add_ps(_mm_loadu_ps(ux), r[0]));
      _mm_storeu_ps(uy, _mm_add_ps(_mm_loadu_ps(uy), r[1]));
      _mm_storeu_ps(uz, _mm_add_ps(_mm_loadu_ps(uz), r[2]));
    }
    i += count;
  }
#endif
  for (; i < n; ++i) {
    const glm::vec3 u = strength * sample(glm::vec3(X[i], Y[i], Z[i]) * scale + offset);
    UX[i] += u.x, UY[i] += u.y, UZ[i] += u.z;
  }
}

}  // namespace puff::sim::detail
