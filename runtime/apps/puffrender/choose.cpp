// puffrender --max-error: just enough model, measured against the references (render/budget.h).
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <cli/app.h>
#include <cli/progress.h>
#include <puff/core/image.h>
#include <puff/core/number_text.h>
#include <puff/eval/budget.h>
#include <puff/scene/evaluate.h>

#include "commands.h"

namespace puff::app {

namespace {

// Measures every media layer resolution at up to three of the frames to render, against the exact
// reference, and sets the cheapest within the budget on `scene`. Returns 0, or the exit code of a
// failure (after saying why).
int chooseMediaResolution(const Options& o, scene::Scene& scene, const Plan& plan) {
  const std::vector<int> frames = eval::budgetFrames(plan.first, plan.last);
  if (!o.quiet) {
    std::string list;
    for (int f : frames) list += (list.empty() ? "" : ", ") + std::to_string(f);
    std::fprintf(stderr, "%s: --max-error %g: measuring media resolutions 0.125 to 1 against the reference at %s %s\n",
                 cli::name(), *o.maxError, frames.size() == 1 ? "frame" : "frames", list.c_str());
    std::fflush(stderr);
  }
  cli::Progress progress(o.quiet);
  eval::MediaBudgetOptions options;
  options.progress = [&](int done, int total) { progress("measuring frames", done, total); };
  auto budget = eval::measureMediaBudget(scene, frames, options);
  progress.finish();
  if (!budget) {
    cli::printError(budget.error());
    return 1;
  }
  auto choice = eval::chooseMediaResolution(*budget, *o.maxError);
  if (!choice) {  // parse() checked the value
    cli::printError("--max-error: " + choice.error().message);
    return 2;
  }
  if (!o.quiet) {
    std::fprintf(stderr, "%s", eval::budgetTable(*budget, *choice).c_str());
    if (!choice->met) {
      std::fprintf(stderr, "%s: warning: %s\n", cli::name(), eval::budgetWarning(*budget, *choice).c_str());
    }
  }
  std::fprintf(stderr, "%s: %s\n", cli::name(), eval::budgetSummary(*budget, *choice).c_str());
  std::fflush(stderr);
  scene.media->resolution = budget->candidates[choice->chosen].resolution;
  return 0;
}

// On a scene with cel particles: measures one of the nailboards' run-time parameters (the share of
// the emitters' particles, the atlas level, or the shadow method and map scale) against the cel reference of the full
// model and sets the cheapest within the budget on `scene`.
int chooseCelModel(const Options& o, scene::Scene& scene, const Plan& plan, eval::CelKnob knob,
                   std::vector<core::Image>* references) {
  const std::vector<int> frames = eval::budgetFrames(plan.first, plan.last);
  const bool atlas = knob == eval::CelKnob::kAtlasLevel, shadows = knob == eval::CelKnob::kShadows;
  const bool tumble = knob == eval::CelKnob::kTumble;
  if (!o.quiet) {
    std::string list, sizes;
    for (int f : frames) list += (list.empty() ? "" : ", ") + std::to_string(f);
    for (float px : eval::kHullFromPixels) sizes += (sizes.empty() ? "" : ", ") + core::numberText(px);
    const std::string tumbles = "oriented puffs by the blend, by the hull from " + sizes + " px and by the hull";
    std::fprintf(stderr, "%s: --max-error %g: measuring %s against the cel reference at %s %s\n", cli::name(),
                 *o.maxError,
                 shadows  ? "the shadow map at scales 0.25, 0.5, 1 and 2 and the shadow volumes"
                 : tumble ? tumbles.c_str()
                 : atlas  ? "the atlas at each mip level"
                          : "1/8, 1/4, 1/2 and all of the emitters' particles",
                 frames.size() == 1 ? "frame" : "frames", list.c_str());
    std::fflush(stderr);
  }
  cli::Progress progress(o.quiet);
  eval::CelBudgetOptions options;
  options.progress = [&](int done, int total) { progress("measuring (references, then candidates)", done, total); };
  auto budget = eval::measureCelBudget(scene, frames, options, knob, *references);
  progress.finish();
  if (!budget) {
    cli::printError(budget.error());
    return 1;
  }
  auto choice = eval::chooseCelBudget(*budget, *o.maxError);
  if (!choice) {
    cli::printError("--max-error: " + choice.error().message);
    return 2;
  }
  if (!o.quiet) {
    std::fprintf(stderr, "%s", eval::celBudgetTable(*budget, *choice).c_str());
    if (!choice->met) {
      std::fprintf(stderr, "%s: warning: %s\n", cli::name(), eval::celBudgetWarning(*budget, *choice).c_str());
    }
  }
  std::fprintf(stderr, "%s: %s\n", cli::name(), eval::celBudgetSummary(*budget, *choice).c_str());
  std::fflush(stderr);
  *references = std::move(budget->references);  // the next parameter measures against the same
  const eval::CelCandidate& c = budget->candidates[choice->chosen];
  if (shadows) {
    scene.style.shadowMethod = c.shadowMethod;
    scene.style.shadowMapScale = c.shadowMapScale;
  } else if (tumble) {
    scene.style.tumble = c.tumble;
    scene.style.hullFromPixels = c.hullFromPixels;
  } else if (atlas) {
    scene.atlasLevel = c.atlasLevel;
  } else {
    scene.particleFraction = c.particleFraction;
  }
  return 0;
}

}  // namespace

bool hasCelParticles(const scene::Scene& scene) {
  return !scene.atlas.empty() && (!scene.particles.empty() || !scene.emitters.empty() ||
                                  (scene.simulation && !scene.simulation->emitters.empty()));
}

int chooseModel(const Options& o, scene::Scene& scene, const Plan& plan) {
  // run() made sure the path is cel and there is something to choose.
  if (hasCelParticles(scene)) {
    // Fewer particles first (the frame time), then the smallest atlas for them (the memory), both
    // against the same references of the full model.
    std::vector<core::Image> references;
    if (!scene.emitters.empty()) {
      if (const int code = chooseCelModel(o, scene, plan, eval::CelKnob::kParticleFraction, &references); code != 0)
        return code;
    }
    if (const int code = chooseCelModel(o, scene, plan, eval::CelKnob::kAtlasLevel, &references); code != 0)
      return code;
    // How the oriented ones turn: the blend, or the hull from a size on.
    if (!scene::orientedPuffs(scene).empty()) {
      if (const int code = chooseCelModel(o, scene, plan, eval::CelKnob::kTumble, &references); code != 0) return code;
    }
    // Then the shadows those particles cast: the method and the map's resolution.
    if (scene.style.shadows) {
      if (const int code = chooseCelModel(o, scene, plan, eval::CelKnob::kShadows, &references); code != 0) return code;
    }
  }
  if (scene.media) {
    if (const int code = chooseMediaResolution(o, scene, plan); code != 0) return code;
  }
  return 0;
}

}  // namespace puff::app
