// Divergence-free turbulence: the curl of a periodic gradient-noise vector potential, sampled once
// onto a periodic lattice and read back by trilinear interpolation (fast enough for 50k particles
// per step on one core, which evaluating noise per particle is not).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

// The per-particle loops are compiled twice on x86-64: for the baseline (SSE2) and for AVX2, picked
// when the program loads where the CPU has it. Neither contracts a multiply and an add into an FMA
// (AVX2 does not include FMA), and every operation is IEEE-exact per lane, so both give the same bits.
// GCC only: clang (the fuzzing build's compiler) does not link a call from another translation unit
// to a member function whose clones are declared on its definition alone (CurlField::addSamples),
// so its builds take the baseline loops.
#if defined(__x86_64__) && defined(__ELF__) && defined(__GNUC__) && !defined(__clang__)
#define PUFF_SIM_KERNEL [[gnu::target_clones("avx2", "default")]]
#else
#define PUFF_SIM_KERNEL
#endif

namespace puff::sim::detail {

/// exp(x) for x <= 0, to a few 1e-6 relative error (2e-7 near 0): 2^x split into a power of two (exponent bits)
/// and 2^f for f in [-1/2, 1/2] (Taylor to degree 6). Branch-free, so loops over particles
/// vectorize, and the same on every machine; 0 below -87.
inline float fastExp(float x) {
  const float xc = x < -87.0f ? -87.0f : (x > 0.0f ? 0.0f : x);
  const float t = xc * 1.44269504f;  // log2(e)
  const float a = t + 0.5f;          // fi = round(t) = floor(t + 1/2), so f = t - fi lies in [-1/2, 1/2]
  const float truncated = static_cast<float>(static_cast<int>(a));
  const float fi = truncated - (truncated > a ? 1.0f : 0.0f);
  const float f = t - fi;
  float p = 1.5403530e-4f;
  p = p * f + 1.3333558e-3f;
  p = p * f + 9.6181291e-3f;
  p = p * f + 5.5504109e-2f;
  p = p * f + 2.4022651e-1f;
  p = p * f + 6.9314718e-1f;
  p = p * f + 1.0f;
  const float out = std::bit_cast<float>(std::bit_cast<int>(p) + (static_cast<int>(fi) << 23));
  return x <= -87.0f ? 0.0f : out;
}

/// Periodic 3D gradient noise (Perlin 2002, quintic fade) with its analytic gradient. The lattice
/// period is `period` cells in each axis.
class GradientNoise {
 public:
  GradientNoise(std::uint32_t seed, int period);
  /// Value in about [-1, 1]; `gradient` receives d/dx, d/dy, d/dz.
  float eval(const glm::vec3& p, glm::vec3* gradient) const;

 private:
  glm::vec3 grad(int x, int y, int z) const;
  std::uint32_t seed_;
  int period_;
};

/// A periodic lattice of `n`^3 velocity samples, one tile per unit of lookup space, holding the curl
/// of three noise potentials (each of `noiseCells` cells per tile), normalized to unit RMS speed.
class CurlField {
 public:
  CurlField(std::uint32_t seed, int n = 32, int noiseCells = 4);
  /// The field at `p` (tile space, any real value: the field repeats every 1), trilinear.
  glm::vec3 sample(const glm::vec3& p) const;
  /// For i in [0, n): U[i] += strength * sample((X, Y, Z)[i] * scale + offset), the same arithmetic
  /// as sample and so the same bits, with the lattice addressing done four points at a time.
  void addSamples(const float* X, const float* Y, const float* Z, std::size_t n, float scale, const glm::vec3& offset,
                  float strength, float* UX, float* UY, float* UZ) const;
  /// The analytic curl at `p` (no lattice): the exact divergence-free field, for tests.
  glm::vec3 exact(const glm::vec3& p) const;
  int resolution() const { return n_; }

 private:
  int n_;
  float norm_ = 1.0f;
  float top_ = 0.0f;  // the largest float below n
  GradientNoise a_, b_, c_;
  int noiseCells_;
  std::vector<float> v_;  // xyz0 per sample, x fastest, (n + 1)^3: the last layer repeats the first
};

}  // namespace puff::sim::detail
