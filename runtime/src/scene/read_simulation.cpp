// The scene file's "simulation" (forces, vortices, emitters) and the forces media share.
#include <puff/core/number_text.h>
#include <puff/scene/read.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "read_detail.h"

namespace puff::scene::detail {

glm::vec3 readDirection(const json& v, const std::string& ptr) {
  const glm::vec3 d = readVec3(v, ptr, kMagnitude);
  if (!(glm::length(d) > 0.0f)) fail(ptr, "a non-zero direction", v);
  return d;
}

sim::Vortex readVortex(const json& j, const std::string& ptr) {
  requireObject(j, ptr,
                {"position", "axis", "strength", "radius", "falloff", "length", "path", "attach", "shedInterval",
                 "shedLifetime"});
  sim::Vortex v;
  if (auto* x = find(j, "position")) v.position = readVec3(*x, child(ptr, "position"), kMagnitude);
  if (auto* x = find(j, "axis")) v.axis = readDirection(*x, child(ptr, "axis"));
  if (auto* x = find(j, "strength")) v.strength = readFloat(*x, child(ptr, "strength"), kMagnitude);
  if (auto* x = find(j, "radius")) v.radius = readFloat(*x, child(ptr, "radius"), Range{1e-4, sim::kMaxMagnitude});
  if (auto* x = find(j, "falloff")) v.falloff = readFloat(*x, child(ptr, "falloff"), kNonNegativeMagnitude);
  if (auto* x = find(j, "length")) v.length = readFloat(*x, child(ptr, "length"), kNonNegativeMagnitude);
  if (auto* x = find(j, "path")) v.path = readPath3(*x, child(ptr, "path"));
  if (auto* x = find(j, "attach")) v.attach = readString(*x, child(ptr, "attach"), "the name of a scene object");
  if (auto* x = find(j, "shedInterval")) {
    v.shedInterval = readFloat(*x, child(ptr, "shedInterval"), Range{0.0, 1e4},
                               "0 (no shedding) or a number of seconds in [0.001, 10000]");
    if (v.shedInterval > 0.0f && v.shedInterval < 1e-3f)
      fail(child(ptr, "shedInterval"), "0 (no shedding) or a number of seconds in [0.001, 10000]", *x);
  }
  if (auto* x = find(j, "shedLifetime"))
    v.shedLifetime = readFloat(*x, child(ptr, "shedLifetime"), Range{0.0, 1e4, true, false});
  return v;
}

sim::Forces readForces(const json& j, const std::string& ptr) {
  requireObject(j, ptr, {"gravity", "buoyancy", "up", "drag", "wind", "windVolumes", "turbulence", "vortices"});
  sim::Forces f;
  if (auto* v = find(j, "gravity")) f.gravity = readVec3(*v, child(ptr, "gravity"), kMagnitude);
  if (auto* v = find(j, "buoyancy")) f.buoyancy = readFloat(*v, child(ptr, "buoyancy"), kMagnitude);
  if (auto* v = find(j, "up")) f.up = readDirection(*v, child(ptr, "up"));
  if (auto* v = find(j, "drag")) f.drag = readFloat(*v, child(ptr, "drag"), kNonNegativeMagnitude);
  if (auto* v = find(j, "wind")) f.wind = readVec3(*v, child(ptr, "wind"), kMagnitude);
  if (auto* v = find(j, "windVolumes")) {
    const std::string p = child(ptr, "windVolumes");
    if (!v->is_array()) fail(p, "an array of wind volumes", *v);
    for (std::size_t i = 0; i < v->size(); ++i) {
      const std::string q = child(p, i);
      const json& w = (*v)[i];
      requireObject(w, q, {"center", "halfExtent", "velocity", "feather"});
      sim::WindVolume vol;
      if (auto* x = find(w, "center")) vol.center = readVec3(*x, child(q, "center"), kMagnitude);
      if (auto* x = find(w, "halfExtent")) vol.halfExtent = readVec3(*x, child(q, "halfExtent"), kNonNegativeMagnitude);
      if (auto* x = find(w, "velocity")) vol.velocity = readVec3(*x, child(q, "velocity"), kMagnitude);
      if (auto* x = find(w, "feather")) vol.feather = readFloat(*x, child(q, "feather"), kNonNegativeMagnitude);
      f.windVolumes.push_back(vol);
    }
  }
  if (auto* v = find(j, "turbulence")) {
    const std::string p = child(ptr, "turbulence");
    requireObject(*v, p, {"strength", "scale", "speed", "seed"});
    sim::Turbulence& t = f.turbulence;
    if (auto* x = find(*v, "strength")) t.strength = readFloat(*x, child(p, "strength"), kNonNegativeMagnitude);
    if (auto* x = find(*v, "scale")) t.scale = readFloat(*x, child(p, "scale"), Range{1e-4, sim::kMaxMagnitude});
    if (auto* x = find(*v, "speed")) t.speed = readFloat(*x, child(p, "speed"), Range{0.0, 1e3});
    if (auto* x = find(*v, "seed"))
      t.seed = static_cast<std::uint32_t>(readInteger(*x, child(p, "seed"), 0, 0xffffffffLL));
  }
  if (auto* v = find(j, "vortices")) {
    const std::string p = child(ptr, "vortices");
    if (!v->is_array()) fail(p, "an array of vortices", *v);
    for (std::size_t i = 0; i < v->size(); ++i) f.vortices.push_back(readVortex((*v)[i], child(p, i)));
  }
  return f;
}

namespace {

// A curve's interpolation and keys [[age, value], ...]: `value` reads one key's value.
template <typename Curve, typename ReadValue>
Curve readCurveKeys(const json& j, const std::string& ptr, ReadValue value) {
  requireObject(j, ptr, {"keys", "interp"});
  Curve c;
  if (auto* v = find(j, "interp")) {
    c.interp = readEnum<sim::LifeCurve::Interp>(
        *v, child(ptr, "interp"),
        {{"linear", sim::LifeCurve::Interp::kLinear}, {"smooth", sim::LifeCurve::Interp::kSmooth}});
  }
  const json* keys = find(j, "keys");
  const std::string kp = child(ptr, "keys");
  if (!keys) failText(kp, "expected keys [[age, value], ...] (ages in [0, 1], increasing), got none");
  if (!keys->is_array() || keys->empty() || keys->size() > 64) {
    fail(kp, "1 to 64 keys [[age, value], ...] (ages in [0, 1], increasing)", *keys);
  }
  for (std::size_t i = 0; i < keys->size(); ++i) {
    const json& k = (*keys)[i];
    const std::string p = child(kp, i);
    if (!k.is_array() || k.size() != 2) fail(p, "a key [age, value]", k);
    const float age = readFloat(k[0], child(p, 0), Range{0.0, 1.0}, "an age in [0, 1] (0 birth, 1 death)");
    if (!c.ages.empty() && !(age > c.ages.back())) {
      fail(child(p, 0), "an age after the previous key's (" + core::numberText(c.ages.back()) + ")", k[0]);
    }
    c.ages.push_back(age);
    c.values.push_back(value(k[1], child(p, 1)));
  }
  return c;
}

sim::LifeCurve readLifeCurve(const json& j, const std::string& ptr, double minValue, double maxValue) {
  return readCurveKeys<sim::LifeCurve>(j, ptr, [&](const json& v, const std::string& p) {
    return readFloat(v, p, Range{minValue, maxValue});
  });
}

}  // namespace

sim::LifeCurves readLifeCurves(const json& j, const std::string& ptr, CurveOwner owner) {
  if (owner != CurveOwner::kMedia && j.is_object() && j.contains("temperature")) {
    failText(child(ptr, "temperature"),
             "cel puffs have no temperature: temperature curves are for media emitters (fire), under /media/emitters");
  }
  if (owner == CurveOwner::kCelEmitter) {
    requireObject(j, ptr, {"size", "color"});
  } else if (owner == CurveOwner::kCelSimulation) {
    requireObject(j, ptr, {"size", "density", "color"});
  } else {
    requireObject(j, ptr, {"size", "density", "color", "temperature"});
  }
  sim::LifeCurves c;
  // Multipliers of the birth size and density; a display colour; kelvin.
  if (auto* v = find(j, "size")) c.size = readLifeCurve(*v, child(ptr, "size"), 0.0, 100.0);
  if (auto* v = find(j, "density")) c.density = readLifeCurve(*v, child(ptr, "density"), 0.0, 1e3);
  if (auto* v = find(j, "color")) {
    c.color = readCurveKeys<sim::ColourCurve>(*v, child(ptr, "color"),
                                              [](const json& x, const std::string& p) { return readColor(x, p); });
  }
  if (auto* v = find(j, "temperature")) c.temperature = readLifeCurve(*v, child(ptr, "temperature"), 1.0, 1e5);
  return c;
}

sim::Emitter readSimEmitter(const json& j, const std::string& ptr, CurveOwner owner) {
  requireObject(j, ptr, {"shape",          "position",        "radius",   "normal",  "path",     "attach",
                         "rate",           "start",           "duration", "seed",    "velocity", "spread",
                         "speedSpread",    "inheritVelocity", "density",  "sizeMin", "sizeMax",  "lifetime",
                         "lifetimeSpread", "variations",      "oriented", "spin",    "overLife"});
  sim::Emitter e;
  using Shape = sim::Emitter::Shape;
  if (auto* v = find(j, "shape")) {
    e.shape = readEnum<Shape>(*v, child(ptr, "shape"),
                              {{"point", Shape::kPoint}, {"sphere", Shape::kSphere}, {"disc", Shape::kDisc}});
  }
  if (auto* v = find(j, "position")) e.position = readVec3(*v, child(ptr, "position"), kMagnitude);
  if (auto* v = find(j, "radius")) e.radius = readFloat(*v, child(ptr, "radius"), kNonNegativeMagnitude);
  if (auto* v = find(j, "normal")) e.normal = readDirection(*v, child(ptr, "normal"));
  if (auto* v = find(j, "path")) e.path = readPath3(*v, child(ptr, "path"));
  if (auto* v = find(j, "attach")) e.attach = readString(*v, child(ptr, "attach"), "the name of a scene object");
  if (auto* v = find(j, "rate"))
    e.rate = readFloat(*v, child(ptr, "rate"), Range{0.0, 1e7}, "particles per second in [0, 1e+07]");
  if (auto* v = find(j, "start")) e.start = readFloat(*v, child(ptr, "start"), kMagnitude);
  if (auto* v = find(j, "duration"))
    e.duration = readFloat(*v, child(ptr, "duration"), kNonNegativeMagnitude, "seconds >= 0 (0: never stops)");
  if (auto* v = find(j, "seed"))
    e.seed = static_cast<std::uint32_t>(readInteger(*v, child(ptr, "seed"), 0, 0xffffffffLL));
  if (auto* v = find(j, "velocity")) e.velocity = readVec3(*v, child(ptr, "velocity"), kMagnitude);
  if (auto* v = find(j, "spread")) e.spreadDegrees = readFloat(*v, child(ptr, "spread"), Range{0.0, 180.0});
  if (auto* v = find(j, "speedSpread")) e.speedSpread = readFloat(*v, child(ptr, "speedSpread"), kUnit);
  if (auto* v = find(j, "inheritVelocity"))
    e.inheritVelocity = readFloat(*v, child(ptr, "inheritVelocity"), Range{-10.0, 10.0});
  if (auto* v = find(j, "density")) e.density = readFloat(*v, child(ptr, "density"), Range{0.0, 1e3, true, false});
  if (auto* v = find(j, "sizeMin")) e.sizeMin = readFloat(*v, child(ptr, "sizeMin"), kNonNegativeMagnitude);
  if (auto* v = find(j, "sizeMax")) e.sizeMax = readFloat(*v, child(ptr, "sizeMax"), kNonNegativeMagnitude);
  if (e.sizeMin > e.sizeMax) {
    if (auto* v = find(j, "sizeMax"))
      fail(child(ptr, "sizeMax"), "a size >= sizeMin (" + core::numberText(e.sizeMin) + ")", *v);
    fail(child(ptr, "sizeMin"), "a size <= sizeMax (" + core::numberText(e.sizeMax) + ")", *find(j, "sizeMin"));
  }
  if (auto* v = find(j, "lifetime"))
    e.lifetime = readFloat(*v, child(ptr, "lifetime"), Range{0.0, 1e6, true, false}, "a lifetime in seconds > 0");
  if (auto* v = find(j, "lifetimeSpread"))
    e.lifetimeSpread = readFloat(*v, child(ptr, "lifetimeSpread"), Range{0.0, 1.0, false, true});
  if (auto* v = find(j, "variations")) {
    const std::string p = child(ptr, "variations");
    if (!v->is_array()) fail(p, "an array of variation numbers in [0, 255]", *v);
    for (std::size_t i = 0; i < v->size(); ++i) e.variations.push_back(readInt((*v)[i], child(p, i), 0, 255));
  }
  if (auto* v = find(j, "oriented")) e.oriented = readBool(*v, child(ptr, "oriented"));
  if (auto* v = find(j, "spin")) e.spin = readFloat(*v, child(ptr, "spin"), Range{0.0, 1e3});
  if (auto* v = find(j, "overLife")) e.overLife = readLifeCurves(*v, child(ptr, "overLife"), owner);
  return e;
}

sim::Settings readSimulation(const json& j, const std::string& ptr) {
  requireObject(j, ptr, {"substeps", "preroll", "maxParticles", "collisionRadius", "integrator", "forces", "emitters"});
  sim::Settings s;
  if (auto* v = find(j, "substeps")) s.substeps = readInt(*v, child(ptr, "substeps"), 1, 1000);
  if (auto* v = find(j, "preroll")) s.preroll = readFloat(*v, child(ptr, "preroll"), Range{0.0, 3600.0});
  if (auto* v = find(j, "maxParticles")) {
    s.maxParticles = static_cast<std::size_t>(
        readInteger(*v, child(ptr, "maxParticles"), 0, static_cast<long long>(sim::kMaxParticleBudget),
                    "a particle budget in [0, " + std::to_string(sim::kMaxParticleBudget) +
                        "] (about 64 bytes each; more would not fit in memory)"));
  }
  if (auto* v = find(j, "collisionRadius")) s.collisionRadius = readFloat(*v, child(ptr, "collisionRadius"), kUnit);
  if (auto* v = find(j, "integrator")) {
    s.integrator = readEnum<sim::Integrator>(
        *v, child(ptr, "integrator"),
        {{"exponential", sim::Integrator::kExponential}, {"forward-euler", sim::Integrator::kForwardEuler}});
  }
  if (auto* v = find(j, "forces")) s.forces = readForces(*v, child(ptr, "forces"));
  if (auto* v = find(j, "emitters")) {
    const std::string p = child(ptr, "emitters");
    if (!v->is_array()) fail(p, "an array of emitters", *v);
    for (std::size_t i = 0; i < v->size(); ++i) s.emitters.push_back(readSimEmitter((*v)[i], child(p, i)));
  }
  return s;
}

}  // namespace puff::scene::detail
