// Random numbers that are the same on every machine and standard library: splitmix64 (Steele, Lea &
// Flood 2014) for streams, its finalizer for hashing, lowbias32 (Wellons) for 32-bit hashes (the
// media shader has the same one in GLSL), and unit directions from two uniforms. std::
// distributions promise no such thing, so Puff's generators, emitters and simulators use these.
// Header-only, no GL: the simulator (which links nothing of Puff's) uses it too.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include <glm/vec3.hpp>

namespace puff::core {

/// splitmix64's increment (the golden ratio in 64 bits).
inline constexpr std::uint64_t kGoldenGamma = 0x9E3779B97F4A7C15ull;

/// splitmix64's finalizer: a bijective 64-bit mix, good as a hash.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// lowbias32 (Chris Wellons' hash prospector): a 32-bit integer hash.
constexpr std::uint32_t lowbias32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

/// A splitmix64 stream from a raw state (seed it with mix64(seed) to decorrelate nearby seeds).
class SplitMix64 {
 public:
  explicit constexpr SplitMix64(std::uint64_t state) : state_(state) {}
  constexpr std::uint64_t next() {
    state_ += kGoldenGamma;
    return mix64(state_);
  }
  /// Uniform in [0, 1) with 24 random bits, exact in a float.
  constexpr float uniform() { return static_cast<float>(next() >> 40) * 0x1.0p-24f; }
  /// Uniform in [0, 1) with 53 random bits, exact in a double.
  constexpr double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

/// The unit vector at (z = 1 - 2 u1, phi = 2 pi u2): uniform on the sphere for uniform u1, u2 in [0, 1).
inline glm::vec3 unitDirection(float u1, float u2) {
  const float z = 1.0f - 2.0f * u1;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * std::numbers::pi_v<float> * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace puff::core
