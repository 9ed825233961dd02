// What a scene holds that is valid but likely not what its author meant (evaluate.h, sceneWarnings).
#include <puff/core/number_text.h>
#include <puff/scene/evaluate.h>

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

}  // namespace

std::vector<std::string> sceneWarnings(const Scene& scene) {
  std::vector<std::string> out;
  if (scene.animation.period > 0) return out;  // a loop fills its own preroll
  if (scene.simulation) {
    prerollFillsNothing(
        "/simulation/preroll", scene.simulation->preroll, scene.simulation->emitters,
        [](const sim::Emitter& e) { return e.start; }, out);
  }
  if (scene.media) {
    prerollFillsNothing(
        "/media/preroll", scene.media->preroll, scene.media->emitters,
        [](const MediaEmitterSpec& e) { return e.emitter.start; }, out);
  }
  return out;
}

}  // namespace puff::scene
