// The 16-byte particle record (nailboards.h) and its inverse, the same arithmetic as
// shaders/cel/particle.glsl's unpackParticle.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/packing.hpp>

#include <puff/cel/nailboards.h>

namespace puff::cel {

namespace {

constexpr float kQuatRange = 0.70710678f;  // the three smallest components lie in [-1/sqrt2, 1/sqrt2]

std::uint32_t quantize16(float v, float lo, float hi) {
  float t = (v - lo) / (hi - lo);
  t = t >= 0.0f ? std::min(t, 1.0f) : 0.0f;  // NaN (a position not drawn) goes to 0 too
  return static_cast<std::uint32_t>(std::lround(t * 65535.0f));
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

}  // namespace

PackBounds packParticles(std::span<const Particle> particles, std::vector<PackedParticle>& out) {
  // A particle whose position is not finite is not drawn (size 0) and does not widen the bounds:
  // one bad position must not take the batch with it.
  auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  PackBounds b;
  bool any = false;
  for (const Particle& p : particles) {
    if (!finite(p.position)) continue;
    b.min = any ? glm::min(b.min, p.position) : p.position;
    b.max = any ? glm::max(b.max, p.position) : p.position;
    any = true;
  }
  for (int a = 0; a < 3; ++a) {
    if (!(b.max[a] > b.min[a])) b.max[a] = b.min[a] + 1.0f;
  }
  out.resize(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Particle& p = particles[i];
    const float size = std::isfinite(p.size) && finite(p.position) ? std::clamp(p.size, 0.0f, 65504.0f) : 0.0f;
    PackedParticle& o = out[i];
    o.x = quantize16(p.position.x, b.min.x, b.max.x) | (quantize16(p.position.y, b.min.y, b.max.y) << 16);
    o.y = quantize16(p.position.z, b.min.z, b.max.z) | (static_cast<std::uint32_t>(glm::packHalf1x16(size)) << 16);
    o.z = p.oriented ? packQuat(p.orientation) : packQuat(glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
    o.w = (static_cast<std::uint32_t>(p.variation) & 0xFFu) | (p.oriented ? 0x100u : 0u);
  }
  return b;
}

Particle unpackParticle(const PackedParticle& packed, const PackBounds& b) {
  auto axis = [&](std::uint32_t q, int a) {
    return b.min[a] + (b.max[a] - b.min[a]) * (static_cast<float>(q & 0xFFFFu) / 65535.0f);
  };
  Particle p;
  p.position = glm::vec3(axis(packed.x, 0), axis(packed.x >> 16, 1), axis(packed.y, 2));
  p.size = glm::unpackHalf1x16(static_cast<glm::uint16>(packed.y >> 16));
  p.orientation = unpackQuat(packed.z);
  p.variation = static_cast<int>(packed.w & 0xFFu);
  p.oriented = (packed.w & 0x100u) != 0;
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

Result<Alignment> parseAlignment(std::string_view name) {
  for (Alignment a : {Alignment::kViewPlane, Alignment::kViewpoint, Alignment::kAxial}) {
    if (name == toString(a)) return a;
  }
  return Error{"unknown alignment \"" + std::string(name) + "\" (expected view-plane, viewpoint or axial)"};
}

std::string_view toString(ShadowMethod m) { return m == ShadowMethod::kMap ? "map" : "volumes"; }

Result<ShadowMethod> parseShadowMethod(std::string_view name) {
  for (ShadowMethod m : {ShadowMethod::kVolumes, ShadowMethod::kMap}) {
    if (name == toString(m)) return m;
  }
  return Error{"unknown shadow method \"" + std::string(name) + "\" (expected volumes or map)"};
}

}  // namespace puff::cel
