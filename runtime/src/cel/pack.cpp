// The 16-byte particle record (nailboards.h) and its inverse, the same arithmetic as
// shaders/cel/particle.glsl's unpackParticle.
#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/packing.hpp>

#include <puff/cel/nailboards.h>
#include <puff/core/colour.h>

namespace puff::cel {

namespace {

constexpr float kQuatRange = 0.70710678f;  // the three smallest components lie in [-1/sqrt2, 1/sqrt2]

// Positions lie on a fixed world-space grid per axis (PackBounds): the step is a power of two, the
// smallest with the batch's extent <= kGridSpan steps, and the origin a multiple of the step. A
// still particle rounds to the same grid point whatever the rest of the batch does, as long as the
// batch's extent on that axis stays between the same two thresholds (kGridSpan * 2^k, roughly powers
// of two). Not camera-relative: that grid would move with every camera move (a still scene would
// shimmer under a panning camera), and packing happens at upload, before any camera is known.
//   kGridSpan: 65535 steps fit 16 bits; snapping the origin down to the grid costs up to one.
//   kMinStepExponent: the finest step, 2^-24 world units, for a batch of one point (extent 0).
//   kMaxCoordinate: 2^125; beyond it the grid's corner and q * step could overflow a float.
constexpr double kGridSpan = 65534.0;
constexpr int kMinStepExponent = -24;
constexpr float kMaxCoordinate = 0x1.0p125f;

// The exponent k of the grid step 2^k for an extent (world units): the smallest k >=
// kMinStepExponent with extent <= kGridSpan * 2^k.
int stepExponent(double extent) {
  if (!(extent > std::ldexp(kGridSpan, kMinStepExponent))) return kMinStepExponent;
  int k = std::ilogb(extent / kGridSpan);  // 2^k <= extent / kGridSpan (rounded) < 2^(k + 1)
  if (std::ldexp(kGridSpan, k) < extent) ++k;
  return k;
}

bool drawable(const glm::vec3& v) {
  for (int a = 0; a < 3; ++a) {
    if (!(std::abs(v[a]) <= kMaxCoordinate)) return false;  // NaN fails too
  }
  return true;
}

std::uint32_t packQuat(glm::quat q) {
  const float len = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!(len > 0.0f) || !std::isfinite(len)) return 0u | (0u << 30);  // identity below
  const float c[4] = {q.x / len, q.y / len, q.z / len, q.w / len};
  int largest = 0;
  for (int i = 1; i < 4; ++i) {
    if (std::abs(c[i]) > std::abs(c[largest])) largest = i;
  }
  const float sign = c[largest] < 0.0f ? -1.0f : 1.0f;  // q and -q are the same rotation
  std::uint32_t bits = static_cast<std::uint32_t>(largest) << 30;
  int shift = 20;
  for (int i = 0; i < 4; ++i) {
    if (i == largest) continue;
    const float t = std::clamp((sign * c[i] + kQuatRange) / (2.0f * kQuatRange), 0.0f, 1.0f);
    bits |= static_cast<std::uint32_t>(std::lround(t * 1023.0f)) << shift;
    shift -= 10;
  }
  return bits;
}

glm::quat unpackQuat(std::uint32_t bits) {
  const int largest = static_cast<int>(bits >> 30);
  float c[4];
  float sum = 0.0f;
  int shift = 20;
  for (int i = 0; i < 4; ++i) {
    if (i == largest) continue;
    const float t = static_cast<float>((bits >> shift) & 1023u) / 1023.0f;
    c[i] = t * 2.0f * kQuatRange - kQuatRange;
    sum += c[i] * c[i];
    shift -= 10;
  }
  c[largest] = std::sqrt(std::max(0.0f, 1.0f - sum));
  return glm::normalize(glm::quat(c[3], c[0], c[1], c[2]));
}

// Tint: the display value of each scene-linear channel (Eq. 2 multiplies display values), 7 bits a
// channel at bits 9, 16 and 23 (white 127, 127, 127 is exactly 1). A channel that is not a number
// draws untinted.
std::uint32_t tintCode(float linear) {
  // round(linearToSrgb(v) * 127) without a power per particle: the count of the codes' midpoints,
  // decoded to linear, at or below v.
  static const std::array<float, 127> midpoints = [] {
    std::array<float, 127> m{};
    for (int k = 0; k < 127; ++k) m[k] = static_cast<float>(core::srgbToLinear((k + 0.5) / 127.0));
    return m;
  }();
  if (std::isnan(linear)) return 127u;
  return static_cast<std::uint32_t>(std::upper_bound(midpoints.begin(), midpoints.end(), linear) - midpoints.begin());
}

std::uint32_t packTint(const glm::vec3& tint) {
  std::uint32_t bits = 0;
  for (int c = 0; c < 3; ++c) bits |= tintCode(tint[c]) << (9 + 7 * c);
  return bits;
}

glm::vec3 unpackTint(std::uint32_t w) {
  return core::srgbToLinear(glm::vec3(static_cast<float>((w >> 9) & 127u), static_cast<float>((w >> 16) & 127u),
                                      static_cast<float>((w >> 23) & 127u)) /
                            127.0f);
}

}  // namespace

PackBounds packParticles(std::span<const Particle> particles, std::vector<PackedParticle>& out) {
  // A particle whose position is not finite (or beyond kMaxCoordinate) is not drawn (size 0) and
  // does not widen the grid: one bad position must not take the batch with it.
  glm::vec3 lo(0.0f), hi(0.0f);
  bool any = false;
  for (const Particle& p : particles) {
    if (!drawable(p.position)) continue;
    lo = any ? glm::min(lo, p.position) : p.position;
    hi = any ? glm::max(hi, p.position) : p.position;
    any = true;
  }
  // Per axis, in doubles (exact here: a float over a power of two, integers below 2^53 or of one
  // binade): the step, and the grid index of the origin.
  PackBounds b;
  double step[3], first[3];
  for (int a = 0; a < 3; ++a) {
    step[a] = std::ldexp(1.0, stepExponent(static_cast<double>(hi[a]) - static_cast<double>(lo[a])));
    first[a] = std::floor(static_cast<double>(lo[a]) / step[a]);
    b.min[a] = static_cast<float>(first[a] * step[a]);  // exact: a multiple of the step near lo
    b.step[a] = static_cast<float>(step[a]);
    b.max[a] = static_cast<float>((first[a] + 65535.0) * step[a]);
  }
  // The index of the grid point nearest v: round(v / step) - first, the same integer for a still
  // point whichever origin the batch gives (the origin moves by whole steps).
  auto index = [&](float v, int a) {
    const double i = std::round(static_cast<double>(v) / step[a]) - first[a];
    return static_cast<std::uint32_t>(std::clamp(i, 0.0, 65535.0));
  };
  out.resize(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Particle& p = particles[i];
    const bool draw = drawable(p.position);
    const float size = std::isfinite(p.size) && draw ? std::clamp(p.size, 0.0f, 65504.0f) : 0.0f;
    PackedParticle& o = out[i];
    o.x = draw ? index(p.position.x, 0) | (index(p.position.y, 1) << 16) : 0u;
    o.y = (draw ? index(p.position.z, 2) : 0u) | (static_cast<std::uint32_t>(glm::packHalf1x16(size)) << 16);
    o.z = p.oriented ? packQuat(p.orientation) : packQuat(glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
    o.w = (static_cast<std::uint32_t>(p.variation) & 0xFFu) | (p.oriented ? 0x100u : 0u) | packTint(p.tint);
  }
  return b;
}

Particle unpackParticle(const PackedParticle& packed, const PackBounds& b) {
  // min + q * step: q * step is exact (16 bits times a power of two) and so is the sum (a multiple
  // of the step that a float holds), so the GPU's float arithmetic, fused or not, gives these bits.
  auto axis = [&](std::uint32_t q, int a) { return b.min[a] + static_cast<float>(q & 0xFFFFu) * b.step[a]; };
  Particle p;
  p.position = glm::vec3(axis(packed.x, 0), axis(packed.x >> 16, 1), axis(packed.y, 2));
  p.size = glm::unpackHalf1x16(static_cast<glm::uint16>(packed.y >> 16));
  p.orientation = unpackQuat(packed.z);
  p.variation = static_cast<int>(packed.w & 0xFFu);
  p.oriented = (packed.w & 0x100u) != 0;
  p.tint = unpackTint(packed.w);
  return p;
}

std::string_view toString(Alignment a) {
  switch (a) {
    case Alignment::kViewPlane:
      return "view-plane";
    case Alignment::kViewpoint:
      return "viewpoint";
    case Alignment::kAxial:
      return "axial";
  }
  return "view-plane";
}

std::string_view toString(ShadowMethod m) { return m == ShadowMethod::kMap ? "map" : "volumes"; }

std::string_view toString(TumbleMethod m) { return m == TumbleMethod::kBlend ? "blend" : "hull"; }

}  // namespace puff::cel
