// Divergence-free turbulence: the curl of a periodic gradient-noise vector potential, sampled once
// onto a periodic lattice and read back by trilinear interpolation (fast enough for 50k particles
// per step on one core, which evaluating noise per particle is not).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace puff::sim::detail {

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
  /// The analytic curl at `p` (no lattice): the exact divergence-free field, for tests.
  glm::vec3 exact(const glm::vec3& p) const;
  int resolution() const { return n_; }

 private:
  int n_;
  float norm_ = 1.0f;
  GradientNoise a_, b_, c_;
  int noiseCells_;
  std::vector<float> v_;  // xyz interleaved, x fastest
};

}  // namespace puff::sim::detail
