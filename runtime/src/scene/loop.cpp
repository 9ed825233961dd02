// A scene as a loop (animation.period): what would change from one period to the next is refused
// (evaluate.h, checkLoop); the simulators repeat themselves (sim::Settings::period) and the media's
// detail videos play whole times a period (loopDetailSpeed).
#include <puff/scene/evaluate.h>

#include "sim_settings.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

namespace puff::scene {

namespace {

const std::string kRepeats = " does not repeat every period of a loop";
const std::string kRepeatPlural = " do not repeat every period of a loop";

std::string at(const char* list, std::size_t i) { return std::string(list) + "/" + std::to_string(i); }

std::optional<std::string> cameraRefusal(const Animation& a) {
  if (a.orbitDegreesPerSecond != 0.0f) return "/animation/orbit: a camera that orbits" + kRepeats;
  if (a.cameraPath.moves()) return "/animation/cameraPath: a camera that moves" + kRepeats;
  if (a.targetPath.moves()) return "/animation/targetPath: a camera target that moves" + kRepeats;
  return std::nullopt;
}

std::optional<std::string> placedRefusal(const Scene& s) {
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const ObjectSpec& o = s.objects[i];
    if (o.dynamic) return at("/objects", i) + "/dynamic: a rigid body (" + o.name + ") that falls" + kRepeats;
    if (o.path.moves()) return at("/objects", i) + "/path: an object (" + o.name + ") that moves" + kRepeats;
  }
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const ParticleSpec& p = s.particles[i];
    if (p.velocity != glm::vec3(0.0f) || p.angularVelocity != glm::vec3(0.0f))
      return at("/particles", i) + ": a listed particle that moves or turns" + kRepeats;
    if (p.birth > 0.0f || p.lifetime > 0.0f)
      return at("/particles", i) + ": a listed particle that is born or dies" + kRepeats;
  }
  for (std::size_t i = 0; i < s.emitters.size(); ++i) {
    const EmitterSpec& e = s.emitters[i];
    if (e.velocity != glm::vec3(0.0f) || e.speedSpread > 0.0f || e.spin > 0.0f)
      return at("/emitters", i) + ": placed particles that move or turn" + kRepeatPlural +
             " (a simulation's emitters loop: \"simulation\")";
    if (e.birthSpread > 0.0f || e.lifetime > 0.0f)
      return at("/emitters", i) + ": placed particles that are born or die" + kRepeatPlural +
             " (a simulation's emitters loop: \"simulation\")";
  }
  return std::nullopt;
}

std::optional<std::string> mediaRefusal(const Scene& s) {
  if (!s.media) return std::nullopt;
  const MediaSpec& m = *s.media;
  for (std::size_t i = 0; i < m.lights.size(); ++i) {
    const std::vector<float>& k = m.lights[i].intensities;
    if (std::any_of(k.begin(), k.end(), [&](float v) { return v != k.front(); }))
      return at("/media/lights", i) + "/intensity: a light whose intensity changes" + kRepeats;
  }
  return std::nullopt;
}

// What the simulators refuse in a loop (emitters and vortices that move), at the scene's pointers.
std::optional<std::string> simulationRefusal(const Scene& s) {
  auto check = [&](const sim::Settings& settings, const char* ptr) -> std::optional<std::string> {
    if (auto ok = sim::validate(settings); !ok) return std::string(ptr) + ok.error().message;
    return std::nullopt;
  };
  if (s.simulation) {
    if (auto refused = check(detail::smokeSettings(s), "/simulation")) return refused;
  }
  if (s.media && !s.media->emitters.empty()) {
    if (auto refused = check(detail::mediaSettings(s), "/media")) return refused;
  }
  return std::nullopt;
}

}  // namespace

float loopDetailSpeed(float speed, double periodSeconds, int videoFrames) {
  if (!(periodSeconds > 0.0) || videoFrames < 1) return speed;
  // Rounded to the nearest whole number of plays, or down where that would pass the most a material
  // may play (media::Material::detailSpeed's limit).
  double plays = std::round(speed * periodSeconds / videoFrames);
  if (plays * videoFrames / periodSeconds > media::kMaxDetailSpeed)
    plays = std::floor(speed * periodSeconds / videoFrames);
  return static_cast<float>(plays * videoFrames / periodSeconds);
}

std::optional<std::string> loopRefusal(const Scene& scene) {
  if (scene.animation.period <= 0) return std::nullopt;
  if (auto r = cameraRefusal(scene.animation)) return r;
  if (auto r = placedRefusal(scene)) return r;
  if (auto r = mediaRefusal(scene)) return r;
  return simulationRefusal(scene);
}

Result<void> checkLoop(const Scene& scene) {
  if (auto refused = loopRefusal(scene)) return Error::at(scene.file, *refused);
  return {};
}

}  // namespace puff::scene
