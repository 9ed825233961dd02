// Births (emitters) and the wakes moving vortices shed.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include <puff/core/random.h>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "simulator_impl.h"

namespace puff::sim {

namespace {

// Counter-based random numbers: the value for (seed, stream, index, k) never depends on the order
// particles are born in; within one particle, the draws are taken one a statement (birthOffset).
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

// Where in the emitter's shape a particle is born, from its centre.
glm::vec3 birthOffset(const Emitter& e, Rng& r) {
  glm::vec3 offset(0.0f);
  switch (e.shape) {
    case Emitter::Shape::kPoint:
      break;
    case Emitter::Shape::kSphere: {
      // Each draw its own statement: the operands of one expression are evaluated in an order the
      // compiler picks, and a seed must give the same smoke whatever compiled it.
      const float depth = std::cbrt(r.uniform());
      offset = randomUnit(r) * (e.radius * depth);
      break;
    }
    case Emitter::Shape::kDisc: {
      const glm::vec3 n = glm::normalize(e.normal), a = anyPerpendicular(n), b = glm::cross(n, a);
      const float rr = e.radius * std::sqrt(r.uniform()), phi = r.uniform() * 2.0f * std::numbers::pi_v<float>;
      offset = rr * (std::cos(phi) * a + std::sin(phi) * b);
      break;
    }
  }
  return offset;
}

// The emitter's velocity, spread over a cone of spreadDegrees and in speed by speedSpread (without
// the velocity inherited from the path).
glm::vec3 birthVelocity(const Emitter& e, Rng& r) {
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
  return v;
}

// The atlas variation: any of `variations`, or one of the emitter's list.
int birthVariation(const Emitter& e, Rng& r, int variations) {
  return e.variations.empty()
             ? std::min(variations - 1, static_cast<int>(r.uniform() * static_cast<float>(variations)))
             : e.variations[std::min(e.variations.size() - 1,
                                     static_cast<std::size_t>(r.uniform() * static_cast<float>(e.variations.size())))];
}

// When an emitter's births come: which births fall in a step, when in it, and the index each draws
// its random numbers with. Birth k is at start + (k + 1/2) / rate (the half keeps births off step
// boundaries, where rounding would move one to the next step).
//
// A loop's births (LoopBirths) are counted in steps, with the period (a whole number of steps)
// taken off in integers: births of period J are at x_i + J * period steps, x_i = phase + (i + 1/2) *
// window / perPeriod, so every period splits its births between steps alike (a birth on a step
// boundary included) and birth k draws the numbers of k mod perPeriod.
struct Schedule {
  double start, stop, rate, h;
  std::optional<detail::LoopBirths> loop;
  std::int64_t periodSteps = 0;
  double phase = 0.0, spacing = 0.0;  // in steps: the first period's start in [0, periodSteps), the births' spacing

  Schedule(const Emitter& e, const Settings& s, double stepSeconds) : start(e.start), rate(e.rate), h(stepSeconds) {
    stop = e.duration > 0.0f ? start + e.duration : std::numeric_limits<double>::infinity();
    if (s.period > 0) {
      loop = detail::loopBirths(e, s.period / static_cast<double>(s.fps));
      periodSteps = static_cast<std::int64_t>(s.period) * s.substeps;
      phase = std::fmod(start / h, static_cast<double>(periodSteps));  // exact, however far `start` lies
      if (phase < 0.0) phase += static_cast<double>(periodSteps);
      spacing = loop->window / h / static_cast<double>(loop->perPeriod);
    }
  }
  // Births before step boundary b (time b * h): an index, counted from an origin of its own.
  std::int64_t before(std::int64_t b) const {
    if (!loop) return beforeTime(static_cast<double>(b) * h);
    const std::int64_t n = loop->perPeriod, jb = floorDiv(b, periodSteps), bm = b - jb * periodSteps;
    // Of period jb - 1 (all of jb - 2 and before lie before b), then of jb.
    const std::int64_t late = below(static_cast<double>(bm + periodSteps));
    return late < n ? (jb - 1) * n + late : jb * n + below(static_cast<double>(bm));
  }
  // Births before time t, no loop.
  std::int64_t beforeTime(double t) const {
    const double tc = std::clamp(t, start, stop);
    return static_cast<std::int64_t>(std::floor((tc - start) * rate + 0.5));
  }
  // A loop's births with x_i < y steps.
  std::int64_t below(double y) const {
    return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::ceil((y - phase) / spacing - 0.5)), 0,
                                    loop->perPeriod);
  }
  // Birth k's instant, seconds (no loop).
  double at(std::int64_t k) const { return start + (static_cast<double>(k) + 0.5) / rate; }
  // Seconds from a loop's birth k to boundary b, the period taken off in whole steps.
  double loopAge(std::int64_t k, std::int64_t b) const {
    const std::int64_t n = loop->perPeriod, j = floorDiv(k, n);
    return (static_cast<double>(b - j * periodSteps) - (phase + (static_cast<double>(k - j * n) + 0.5) * spacing)) * h;
  }
  std::uint64_t draws(std::int64_t k) const {
    return static_cast<std::uint64_t>(loop ? k - floorDiv(k, loop->perPeriod) * loop->perPeriod : k);
  }
  static std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
    return a / b - ((a % b != 0) && ((a < 0) != (b < 0)));
  }
};

}  // namespace

void Simulator::Impl::spawn(std::int64_t b0, StepStats& st) {
  const double t0 = static_cast<double>(b0) * h, t1 = static_cast<double>(b0 + 1) * h;
  for (std::size_t ei = 0; ei < s.emitters.size(); ++ei) {
    const Emitter& e = s.emitters[ei];
    if (!(e.rate > 0.0f)) continue;
    const Schedule births(e, s, h);
    std::int64_t k0 = births.before(b0);
    const std::int64_t k1 = births.before(b0 + 1);
    // Births before the step's end less the longest lifetime die inside this step: skip them
    // without a loop (a huge rate with short lives must not cost a loop over every birth). A loop
    // counts its births in whole steps and cannot skip part of one: a birth that dies inside its
    // step is dropped below.
    if (!births.loop) k0 = std::max(k0, births.beforeTime(t1 - detail::longestLife(e)));
    for (std::int64_t k = k0; k < k1; ++k) {
      if (size() >= s.maxParticles) {
        st.dropped += static_cast<std::size_t>(k1 - k);
        break;
      }
      Rng r(e.seed, ei, births.draws(k));
      // The instant of birth inside the step, and the time left to the step's end.
      double tb = 0.0, left = 0.0;
      if (births.loop) {
        left = std::clamp(births.loopAge(k, b0 + 1), 0.0, t1 - t0);
        tb = t1 - left;
      } else {
        tb = std::clamp(births.at(k), t0, t1);
        left = t1 - tb;
      }
      const float remaining = static_cast<float>(left);
      const glm::vec3 offset = birthOffset(e, r);
      glm::vec3 v = birthVelocity(e, r);
      v += e.inheritVelocity * e.path.velocityAt(tb);
      const glm::vec3 p = e.position + e.path.at(tb) + offset + v * remaining;  // moved to the step's end
      const float lifetime = e.lifetime * (1.0f + e.lifetimeSpread * (2.0f * r.uniform() - 1.0f));
      const float size = e.sizeMin + (e.sizeMax - e.sizeMin) * r.uniform();
      const int var = birthVariation(e, r, variations);
      glm::quat q(1.0f, 0.0f, 0.0f, 0.0f);
      glm::vec3 w(0.0f);
      if (e.oriented) {
        // One draw a statement (see birthOffset), in the order the seeds' smoke was first drawn in.
        const glm::vec3 axis = randomUnit(r);
        q = glm::angleAxis(r.uniform() * 2.0f * std::numbers::pi_v<float>, axis);
        const float spin = e.spin * r.uniform();
        w = randomUnit(r) * spin;
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
      id.push_back(static_cast<std::uint32_t>(Rng(e.seed ^ 0x9e3779b9u, ei, births.draws(k)).state >> 32));
      ++st.born;
    }
  }
}

void Simulator::Impl::shedVortices(double t0, double t1) {
  for (const Vortex& v : s.forces.vortices) {
    if (!(v.shedInterval > 0.0f)) continue;
    const auto n0 = static_cast<std::int64_t>(std::floor(t0 / v.shedInterval));
    const auto n1 = static_cast<std::int64_t>(std::floor(t1 / v.shedInterval));
    for (std::int64_t k = n0 + 1; k <= n1; ++k) {
      const double at = static_cast<double>(k) * v.shedInterval;
      // Only a moving vortex leaves a wake: a still one would stack copies on itself.
      if (v.path.velocityAt(at) == glm::vec3(0.0f)) continue;
      shed.push_back(detail::ShedVortex{v.position + v.path.at(at), glm::normalize(v.axis), v.strength, v.radius,
                                        v.falloff, v.length, at, v.shedLifetime});
    }
  }
  std::erase_if(shed, [&](const detail::ShedVortex& v) { return t1 - v.born >= v.lifetime; });
}

}  // namespace puff::sim
