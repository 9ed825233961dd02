// What a scene holds that is valid but likely not what its author meant (evaluate.h, sceneWarnings).
#include <puff/core/number_text.h>
#include <puff/scene/evaluate.h>

#include "sim_settings.h"

#include <algorithm>
#include <string>
#include <vector>

namespace puff::scene {

namespace {

// A preroll simulates seconds before frame 0; only emitters that start before 0 put anything there.
template <class Emitters, class Start>
void prerollFillsNothing(const char* ptr, float preroll, const Emitters& emitters, Start start,
                         std::vector<std::string>& out) {
  if (preroll <= 0.0f) return;
  if (std::any_of(emitters.begin(), emitters.end(), [&](const auto& e) { return start(e) < 0.0f; })) return;
  out.push_back(std::string(ptr) + ": " + core::numberText(preroll) +
                " s are simulated before frame 0, but no emitter starts before 0, so they fill nothing (an emitter "
                "meant to fill them starts at -" +
                core::numberText(preroll) + ")");
}

// A loop that may reach its particle budget: the births dropped differ from period to period.
void loopOverBudget(const char* ptr, const sim::Settings& settings, std::vector<std::string>& out) {
  const std::size_t peak = sim::loopPeakParticles(settings);
  if (peak <= settings.maxParticles) return;
  out.push_back(std::string(ptr) + ": the loop's emitters may hold up to " + std::to_string(peak) +
                " particles at once, more than this budget (" + std::to_string(settings.maxParticles) +
                "): the births it drops fall differently each period, so the loop does not repeat");
}

}  // namespace

std::vector<std::string> sceneWarnings(const Scene& scene) {
  std::vector<std::string> out;
  const bool loop = scene.animation.period > 0;  // a loop fills its own preroll
  if (scene.simulation) {
    if (!loop) {
      prerollFillsNothing(
          "/simulation/preroll", scene.simulation->preroll, scene.simulation->emitters,
          [](const sim::Emitter& e) { return e.start; }, out);
    }
    loopOverBudget("/simulation/maxParticles", detail::smokeSettings(scene), out);
  }
  if (scene.media) {
    if (!loop) {
      prerollFillsNothing(
          "/media/preroll", scene.media->preroll, scene.media->emitters,
          [](const MediaEmitterSpec& e) { return e.emitter.start; }, out);
    }
    loopOverBudget("/media/maxParticles", detail::mediaSettings(scene), out);
  }
  return out;
}

}  // namespace puff::scene
