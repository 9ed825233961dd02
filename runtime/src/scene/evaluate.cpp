// What a frame draws: listed and placed particles, the camera, object transforms, the simulators'
// settings. Pure functions of the scene and the frame number.
#include <puff/scene/evaluate.h>

#include "sim_settings.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <puff/core/colour.h>
#include <puff/core/detail_video.h>
#include <puff/core/random.h>
#include <puff/scene/geometry.h>

namespace puff::scene {

namespace {

// Emitters draw from splitmix64 (core/random.h), seeded through its finalizer.
struct Rng : core::SplitMix64 {
  explicit Rng(std::uint64_t seed) : core::SplitMix64(core::mix64(seed)) {}
};

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

using core::unitDirection;

// Uniform in the unit ball (three draws, no rejection, so every particle uses the same count).
glm::vec3 unitBall(Rng& rng) {
  const float u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
  return unitDirection(u1, u2) * std::cbrt(u3);
}

// Moves, spins and shrinks a particle to time t (its size over its life from `curves.size` when that
// is not empty, its tint from `curves.color`); false when it is not alive then.
bool evolve(const ParticleSpec& p, float t, cel::Particle& out, const sim::LifeCurves& curves = {}) {
  const sim::LifeCurve& sizeCurve = curves.size;
  if (t < p.birth) return false;
  const float age = t - p.birth;
  float size = p.size;
  if (p.lifetime > 0.0f) {
    if (age >= p.lifetime) return false;
    const float life = age / p.lifetime;
    size *= sizeCurve.empty() ? std::max(0.0f, 1.0f - life) * celBirthGrowth(life) : sizeCurve.at(life);
    // The curve's display value decoded (white without a curve).
    out.tint = curves.color.empty() ? glm::vec3(1.0f) : core::srgbToLinear(curves.color.at(life));
  } else {
    out.tint = glm::vec3(1.0f);
  }
  out.position = p.position + p.velocity * age;
  out.size = size;
  out.variation = p.variation;
  out.oriented = p.oriented;
  const float speed = glm::length(p.angularVelocity);
  glm::quat q = p.orientation;
  if (speed > 0.0f && age > 0.0f) q = glm::angleAxis(speed * age, p.angularVelocity / speed) * q;
  out.orientation = glm::normalize(q);
  return true;
}

// Particle `index` of emitter `e`, at birth. Its numbers come from its own stream, seeded from the
// emitter's seed and the index only, so it never depends on the other particles or on the frame.
// Every particle draws the same numbers in the same order, whatever the options.
ParticleSpec emit(const EmitterSpec& e, int index, int variations) {
  Rng rng((static_cast<std::uint64_t>(e.seed) << 32) | static_cast<std::uint32_t>(index));
  ParticleSpec p;
  // Position (3 draws) and how far out in the shape it lies, r/R in [0, 1].
  const float u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
  float edge = 0.0f;
  float along = 0.0f;  // cone: the parameter s along the segment
  switch (e.shape) {
    case EmitterSpec::Shape::kSphere:
      edge = std::cbrt(u3);
      p.position = e.center + e.radius * edge * unitDirection(u1, u2);
      break;
    case EmitterSpec::Shape::kBox: {
      const glm::vec3 q = 2.0f * glm::vec3(u1, u2, u3) - 1.0f;
      edge = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
      p.position = e.center + e.halfExtent * q;
      break;
    }
    case EmitterSpec::Shape::kCone: {
      along = u1;
      const glm::vec3 axis = e.end - e.center;
      const float length = glm::length(axis);
      const glm::vec3 n = length > 0.0f ? axis / length : glm::vec3(0.0f, 1.0f, 0.0f);
      const glm::vec3 helper = std::abs(n.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
      const glm::vec3 b1 = glm::normalize(glm::cross(n, helper)), b2 = glm::cross(n, b1);
      edge = std::sqrt(u2);  // uniform over the disc
      const float radius = e.radius + (e.endRadius - e.radius) * along;
      const float phi = kTwoPi * u3;
      p.position = e.center + axis * along + radius * edge * (std::cos(phi) * b1 + std::sin(phi) * b2);
      break;
    }
  }
  p.size = (e.sizeMin + (e.sizeMax - e.sizeMin) * rng.uniform()) * (1.0f - e.sizeFalloff * edge);
  const float v = rng.uniform();
  if (e.variations.empty()) {
    p.variation = std::min(static_cast<int>(v * static_cast<float>(variations)), variations - 1);
  } else {
    const int n = static_cast<int>(e.variations.size());
    p.variation = e.variations[static_cast<std::size_t>(std::min(static_cast<int>(v * static_cast<float>(n)), n - 1))];
  }
  p.variation = std::clamp(p.variation, 0, 255);
  p.velocity = e.velocity + e.speedSpread * unitBall(rng);
  const float b = rng.uniform();
  p.birth = (e.shape == EmitterSpec::Shape::kCone ? along : b) * e.birthSpread;
  // A uniformly random rotation (Shoemake 1992).
  const float q1 = rng.uniform(), q2 = kTwoPi * rng.uniform(), q3 = kTwoPi * rng.uniform();
  const float a = std::sqrt(1.0f - q1), c = std::sqrt(q1);
  const glm::quat random(c * std::cos(q3), a * std::sin(q2), a * std::cos(q2), c * std::sin(q3));
  const glm::vec3 spin = e.spin * unitBall(rng);
  p.oriented = e.oriented;
  if (e.oriented) {
    p.orientation = glm::normalize(random);
    p.angularVelocity = spin;
  }
  p.lifetime = e.lifetime;
  return p;
}

}  // namespace

std::string orientedPuffs(const Scene& s) {
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    if (s.particles[i].oriented) return "/particles/" + std::to_string(i) + "/oriented";
  for (std::size_t i = 0; i < s.emitters.size(); ++i)
    if (s.emitters[i].oriented) return "/emitters/" + std::to_string(i) + "/oriented";
  if (s.simulation) {
    for (std::size_t i = 0; i < s.simulation->emitters.size(); ++i)
      if (s.simulation->emitters[i].oriented) return "/simulation/emitters/" + std::to_string(i) + "/oriented";
  }
  return {};
}

bool hasParticles(const Scene& s) {
  return !s.particles.empty() || !s.emitters.empty() || (s.simulation && !s.simulation->emitters.empty());
}

float frameTime(const Scene& scene, int frame) {
  return static_cast<float>(static_cast<double>(frame) / static_cast<double>(scene.animation.fps));
}

std::vector<cel::Particle> particlesAt(const Scene& scene, int frame, int variations,
                                       std::vector<std::uint64_t>* keys) {
  variations = std::clamp(variations, 1, 256);
  const float t = frameTime(scene, frame);
  std::size_t capacity = scene.particles.size();
  for (const EmitterSpec& e : scene.emitters) capacity += static_cast<std::size_t>(std::max(0, e.count));
  std::vector<cel::Particle> out;
  out.reserve(capacity);
  if (keys) keys->clear();
  cel::Particle p;
  for (std::size_t i = 0; i < scene.particles.size(); ++i) {
    if (!evolve(scene.particles[i], t, p)) continue;
    out.push_back(p);
    if (keys) keys->push_back(particleKey(ParticleSource::kListed, static_cast<std::uint32_t>(i)));
  }
  const float f = scene.particleFraction;
  const float grow = f < 1.0f ? std::cbrt(1.0f / f) : 1.0f;
  for (std::size_t k = 0; k < scene.emitters.size(); ++k) {
    const EmitterSpec& e = scene.emitters[k];
    const int count = f < 1.0f && e.count > 0 ? std::max(1, static_cast<int>(std::lround(e.count * f))) : e.count;
    for (int i = 0; i < count; ++i) {
      ParticleSpec spec = emit(e, i, variations);
      spec.size *= grow;
      if (!evolve(spec, t, p, e.overLife)) continue;
      out.push_back(p);
      if (keys) {
        keys->push_back(
            particleKey(ParticleSource::kEmitted, static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(i)));
      }
    }
  }
  return out;
}

glm::mat4 objectTransform(const ObjectSpec& o, double t) {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), o.translate + o.path.at(t));
  // A dynamic body's simulated turn (identity for a keyframed or still object), then its own.
  if (!o.path.rotations.empty()) m = m * glm::mat4_cast(o.path.rotationAt(t));
  // XYZ Euler angles applied X first: M = T * Rz * Ry * Rx * S.
  m = glm::rotate(m, glm::radians(o.rotateDegrees.z), glm::vec3(0, 0, 1));
  m = glm::rotate(m, glm::radians(o.rotateDegrees.y), glm::vec3(0, 1, 0));
  m = glm::rotate(m, glm::radians(o.rotateDegrees.x), glm::vec3(1, 0, 0));
  return glm::scale(m, o.scale);
}

namespace {

// The scene's colliding objects as colliders of `s` (checked, named by their object).
Result<void> addColliders(const Scene& scene, const SceneGeometry& geometry, sim::Settings& s) {
  s.colliders.clear();
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const ObjectSpec& o = scene.objects[i];
    if (!o.collide) continue;
    sim::Collider c;
    c.name = o.name;
    c.center = o.translate;
    c.rotation = glm::angleAxis(glm::radians(o.rotateDegrees.z), glm::vec3(0, 0, 1)) *
                 glm::angleAxis(glm::radians(o.rotateDegrees.y), glm::vec3(0, 1, 0)) *
                 glm::angleAxis(glm::radians(o.rotateDegrees.x), glm::vec3(1, 0, 0));
    c.friction = o.friction;
    c.path = o.path;
    switch (o.type) {
      case ObjectSpec::Type::kPlane:
        c.type = sim::Collider::Type::kPlane;
        c.halfExtent = glm::vec3(o.scale.x, 0.0f, o.scale.z);
        break;
      case ObjectSpec::Type::kBox:
        c.type = sim::Collider::Type::kBox;
        c.halfExtent = o.scale;
        break;
      case ObjectSpec::Type::kSphere:
        // A stretched sphere collides as the sphere around it.
        c.type = sim::Collider::Type::kSphere;
        c.halfExtent = glm::vec3(std::max({o.scale.x, o.scale.y, o.scale.z}));
        break;
      case ObjectSpec::Type::kMesh: {
        const mesh::TriMesh* loaded = geometry.shapes[i].get();
        c.type = sim::Collider::Type::kMesh;
        ObjectSpec still = o;  // the vertices where the object stands; the collider's path moves them
        still.path = {};
        const glm::mat4 m = objectTransform(still);
        c.center = glm::vec3(0.0f);
        c.positions.reserve(loaded->positions.size());
        for (const glm::vec3& v : loaded->positions) c.positions.push_back(glm::vec3(m * glm::vec4(v, 1.0f)));
        for (const glm::uvec3& t : loaded->triangles) c.indices.insert(c.indices.end(), {t.x, t.y, t.z});
        break;
      }
    }
    s.colliders.push_back(std::move(c));
  }
  // A collider that fails the simulator's checks is named by the object it came from.
  std::size_t k = 0;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (!scene.objects[i].collide) continue;
    sim::Settings one;
    one.colliders = {s.colliders[k++]};
    if (auto ok = sim::validate(one); !ok) {
      std::string what = ok.error().message;
      what = what.substr(std::min(what.find(':'), what.size()));  // drop "/colliders/0/field"
      return Error::at(scene.file, "/objects/" + std::to_string(i) + " (as a collider)" + what);
    }
  }
  return {};
}

}  // namespace

sim::Settings detail::smokeSettings(const Scene& scene) {
  sim::Settings s = *scene.simulation;
  s.fps = scene.animation.fps;
  s.period = scene.animation.period;
  return s;
}

sim::Settings detail::mediaSettings(const Scene& scene) {
  const MediaSpec& m = *scene.media;
  sim::Settings s;
  s.fps = scene.animation.fps;
  s.period = scene.animation.period;
  s.substeps = m.substeps;
  s.preroll = m.preroll;
  s.maxParticles = m.maxParticles;
  s.collisionRadius = m.collisionRadius;
  s.forces = m.forces;
  for (const MediaEmitterSpec& e : m.emitters) s.emitters.push_back(e.emitter);
  return s;
}

Result<std::optional<sim::Settings>> simulationSettings(const Scene& scene, const SceneGeometry& geometry) {
  if (!scene.simulation) return std::optional<sim::Settings>{};
  sim::Settings s = detail::smokeSettings(scene);
  if (auto ok = addColliders(scene, geometry, s); !ok) return ok.error();
  if (auto ok = sim::validate(s); !ok) return Error::at(scene.file, "/simulation" + ok.error().message);
  return std::optional<sim::Settings>(std::move(s));
}

Result<std::optional<sim::Settings>> mediaSimulationSettings(const Scene& scene, const SceneGeometry& geometry) {
  if (!scene.media || scene.media->emitters.empty()) return std::optional<sim::Settings>{};
  sim::Settings s = detail::mediaSettings(scene);
  if (auto ok = addColliders(scene, geometry, s); !ok) return ok.error();
  if (auto ok = sim::validate(s); !ok) return Error::at(scene.file, "/media" + ok.error().message);
  return std::optional<sim::Settings>(std::move(s));
}

float MediaLightSpec::intensityAt(double t) const {
  if (intensities.empty()) return 0.0f;
  if (t <= times.front()) return intensities.front();
  if (t >= times.back()) return intensities.back();
  const auto it = std::upper_bound(times.begin(), times.end(), static_cast<float>(t));
  const std::size_t k = static_cast<std::size_t>(it - times.begin());
  const double f = (t - times[k - 1]) / (times[k] - times[k - 1]);
  return static_cast<float>(intensities[k - 1] + f * (intensities[k] - intensities[k - 1]));
}

cel::Camera cameraAt(const Scene& scene, int frame) {
  cel::Camera c = scene.camera;
  const double t = frameTime(scene, frame);
  if (!scene.animation.cameraPath.empty()) c.position = scene.animation.cameraPath.at(t);
  if (!scene.animation.targetPath.empty()) c.target = scene.animation.targetPath.at(t);
  if (!(glm::length(c.target - c.position) > 0.0f)) c.target = c.position + glm::vec3(0.0f, 0.0f, -1.0f);
  const float degrees = scene.animation.orbitDegreesPerSecond * frameTime(scene, frame);
  if (degrees == 0.0f) return c;
  // Turn about the vertical (world y) axis through the target; up turns with the camera.
  const glm::quat turn = glm::angleAxis(glm::radians(std::fmod(degrees, 360.0f)), glm::vec3(0.0f, 1.0f, 0.0f));
  c.position = c.target + turn * (c.position - c.target);
  c.up = turn * c.up;
  return c;
}

std::vector<media::Material> linearMediaMaterials(const Scene& scene, const core::DetailVideo* temperature,
                                                  const core::DetailVideo* opacity) {
  std::vector<media::Material> out = scene.media->materials;
  for (media::Material& m : out) m.color = core::srgbToLinear(m.color);
  if (scene.animation.period > 0) {  // the videos play whole times a loop
    const int frames = std::lcm(temperature ? temperature->frames : 1, opacity ? opacity->frames : 1);
    const double seconds = scene.animation.period / static_cast<double>(scene.animation.fps);
    for (media::Material& m : out) m.detailSpeed = loopDetailSpeed(m.detailSpeed, seconds, frames);
  }
  return out;
}

core::SharedFrame sharedFrameFor(const Scene& s, const cel::Camera& cam, int width, int height) {
  core::SharedFrame f;
  f.view = cam.view();
  f.projection = cam.projection(static_cast<float>(width) / static_cast<float>(std::max(1, height)));
  f.nearPlane = cam.nearPlane;
  f.farPlane = cam.farPlane;
  f.depth = core::DepthConvention::kLinear;
  f.viewport = {0, 0, width, height};
  f.light = {s.light.direction, core::srgbToLinear(s.light.color)};
  f.ambient = core::srgbToLinear(s.ambientColor);
  return f;
}

media::Frame mediaFrameFor(const Scene& s, const cel::Camera& cam, float time, int width, int height) {
  media::Frame mf{sharedFrameFor(s, cam, width, height)};
  mf.time = time;
  return mf;
}

cel::Style celStyleFor(const Scene& s) {
  cel::Style style = s.style;
  style.outlineColor = core::srgbToLinear(s.style.outlineColor);
  return style;
}

glm::vec3 linearAlbedo(const ObjectSpec& object) { return core::srgbToLinear(object.albedo); }

bool hasFire(const Scene& scene) {
  if (!scene.media) return false;
  const std::vector<media::Material>& mats = scene.media->materials;
  auto fiery = [&](int index) {
    if (index < 0 || index >= static_cast<int>(mats.size())) return false;
    const media::Material& m = mats[static_cast<std::size_t>(index)];
    const int next = m.becomes;
    return m.emissive ||
           (next >= 0 && next < static_cast<int>(mats.size()) && mats[static_cast<std::size_t>(next)].emissive);
  };
  for (const MediaParticleSpec& p : scene.media->particles) {
    if (fiery(p.materialIndex)) return true;
  }
  for (const MediaEmitterSpec& e : scene.media->emitters) {
    if (fiery(e.materialIndex)) return true;
  }
  return false;
}

core::ViewTransform viewTransformFor(const Scene& scene) {
  if (scene.view) return *scene.view;
  return hasFire(scene) ? core::ViewTransform::kFilmic : core::ViewTransform::kStandard;
}

}  // namespace puff::scene
