// Validation of the simulator's settings: every value checked, errors at the value's JSON pointer.
#include <cmath>
#include <cstdio>
#include <string>

#include <puff/core/number_text.h>
#include <puff/sim/simulator.h>
#include <glm/geometric.hpp>

#include "simulator_impl.h"

namespace puff::sim {

namespace {

struct Check {
  std::string error;
  bool ok() const { return error.empty(); }

  static std::string num(double d) { return std::isfinite(d) ? core::numberText(d) : "a non-finite number"; }
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
    if (!p.rotations.empty() && p.rotations.size() != p.times.size()) {
      if (error.empty()) error = ptr + ": expected a rotation for every key, or none";
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
    // A mesh follows its path's positions only (Simulator's mesh test is in the mesh's unturned frame).
    if (c.ok() && !k.path.rotations.empty())
      c.error = p + "/path: a mesh collider cannot turn (its path has rotations)";
    for (std::uint32_t i : k.indices) {
      if (c.ok() && i >= k.positions.size()) c.error = p + ": a triangle index is out of range";
    }
    for (const glm::vec3& v : k.positions) {
      if (c.ok()) c.vec(p + "/positions", v);
    }
  }
}

// A loop repeats only what stands still: nothing may follow a path.
void checkLoopForces(Check& c, const Forces& f, const std::string& ptr) {
  for (std::size_t i = 0; i < f.vortices.size() && c.ok(); ++i) {
    if (f.vortices[i].path.moves())
      c.error = ptr + "/vortices/" + std::to_string(i) +
                "/path: a vortex on a path (or attached to a moving object) does not repeat every period of a loop";
  }
}

void checkLoop(Check& c, const Settings& s) {
  if (c.ok() && (s.period < 0 || s.period > kMaxPeriod))
    c.fail("/period", "an integer in [0, " + std::to_string(kMaxPeriod) + "] (frames in a loop)", s.period);
  if (!c.ok() || s.period == 0) return;
  checkLoopForces(c, s.forces, "/forces");
  for (std::size_t i = 0; i < s.emitters.size() && c.ok(); ++i) {
    const Emitter& e = s.emitters[i];
    const std::string p = "/emitters/" + std::to_string(i);
    if (e.path.moves()) {
      c.error =
          p + "/path: an emitter on a path (or attached to a moving object) does not repeat every period of a loop";
    } else if (detail::longestLife(e) * s.fps * s.substeps > 1e6) {
      // A loop starts in its steady state: the preroll simulates the longest life first.
      c.fail(p + "/lifetime",
             "a life of at most 1e6 steps in a loop (lifetime * (1 + lifetimeSpread) * fps * substeps), which "
             "simulates one before frame 0",
             e.lifetime);
    }
  }
  for (std::size_t i = 0; i < s.colliders.size() && c.ok(); ++i) {
    if (s.colliders[i].path.moves())
      c.error = "/colliders/" + std::to_string(i) + " (" + s.colliders[i].name +
                "): a moving collider does not repeat every period of a loop";
  }
}

}  // namespace

std::size_t loopPeakParticles(const Settings& s) {
  if (s.period <= 0 || !(s.fps > 0.0f)) return 0;
  const double seconds = s.period / static_cast<double>(s.fps);
  double peak = 0.0;
  for (const Emitter& e : s.emitters) {
    const detail::LoopBirths b = detail::loopBirths(e, seconds);
    peak += static_cast<double>(b.perPeriod) * std::ceil(detail::longestLife(e) / seconds);
  }
  return static_cast<std::size_t>(std::min(peak, 1e18));
}

Result<void> validateLoopForces(const Forces& forces, const std::string& pointer) {
  Check c;
  checkLoopForces(c, forces, pointer);
  if (!c.ok()) return Error{c.error};
  return {};
}

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
  if (c.ok() && (s.threads < 0 || s.threads > kMaxThreads))
    c.fail("/threads", "an integer in [0, " + std::to_string(kMaxThreads) + "]", s.threads);
  checkForces(c, s.forces, "/forces");
  for (std::size_t i = 0; i < s.emitters.size(); ++i) checkEmitter(c, s.emitters[i], "/emitters/" + std::to_string(i));
  for (std::size_t i = 0; i < s.colliders.size(); ++i) {
    checkCollider(c, s.colliders[i], "/colliders/" + std::to_string(i));
  }
  checkLoop(c, s);
  if (!c.ok()) return Error{c.error};
  return {};
}

}  // namespace puff::sim
