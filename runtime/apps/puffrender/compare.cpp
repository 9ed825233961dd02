// puffrender --compare A,B: the two render paths' parity, frame by frame.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include <cli/app.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/eval/cel_reference.h>
#include <puff/eval/compare.h>
#include <puff/render/render.h>

#include "commands.h"

namespace puff::app {

namespace fs = std::filesystem;

int compareFrames(const Options& o, const scene::Scene& scene, const Plan& plan) {
  const std::string first = o.compare.substr(0, o.compare.find(','));
  const std::string second = o.compare.substr(o.compare.find(',') + 1);
  const render::RenderPath pa = *render::parseRenderPath(first), pb = *render::parseRenderPath(second);
  std::vector<std::string> changes;
  const scene::Scene limited = eval::restrictToFixedLimits(scene, &changes);
  const scene::Scene bare = eval::withoutParticles(limited);
  if (!changes.empty() && !o.quiet) {
    std::string list;
    for (const std::string& c : changes) list += (list.empty() ? "" : ", ") + c;
    std::printf("%s: comparing within the fixed path's limits: %s\n", cli::name(), list.c_str());
  }
  std::unique_ptr<render::SceneRenderer> ra, rb, ra0, rb0;
  for (auto [slot, sc, p] : {std::tuple{&ra, &limited, pa}, std::tuple{&rb, &limited, pb}, std::tuple{&ra0, &bare, pa},
                             std::tuple{&rb0, &bare, pb}}) {
    auto r = eval::createRenderer(*sc, p);
    if (!r) {
      cli::printError(r.error());
      return 1;
    }
    *slot = std::move(*r);
  }
  double worstIou = 1.0, worstTone = 1.0;
  const int count = plan.last - plan.first + 1;
  for (int f = plan.first; f <= plan.last; ++f) {
    core::Image images[4];
    render::SceneRenderer* renderers[4] = {ra.get(), ra0.get(), rb.get(), rb0.get()};
    for (int i = 0; i < 4; ++i) {
      auto image = renderers[i]->renderFrame(f);
      if (!image) {
        cli::printError(image.error());
        return 1;
      }
      images[i] = std::move(*image);
    }
    core::Image side;
    const eval::Parity p = eval::compareFrames(images[0], images[1], images[2], images[3], o.toneTolerance, &side);
    worstIou = std::min(worstIou, p.iou);
    worstTone = std::min(worstTone, p.toneShare);
    const fs::path target = plan.pattern.name(f);
    core::OutputTransaction out;
    const fs::path temp = out.stage(target);
    if (auto r = core::writeImage(temp, side, core::PixelType::kUInt8, {}, "frame.png"); !r) {
      cli::printError(Error::at(target, r.error().message));
      return 1;
    }
    if (auto r = out.commit(); !r) {
      cli::printError(r.error());
      return 1;
    }
    char tone[96];
    if (p.both > 0) {
      std::snprintf(tone, sizeof tone, "tone within %.2f on %.1f%% of shared smoke pixels", o.toneTolerance,
                    100.0 * p.toneShare);
    } else {
      std::snprintf(tone, sizeof tone, "no shared smoke pixels to compare tones on");
    }
    std::printf(
        "%s: frame %d: smoke coverage IoU %.3f (%s %zu px, %s %zu px, both %zu); %s; mean |difference| %.3f "
        "over the smoke -> %s\n",
        cli::name(), f, p.iou, first.c_str(), p.maskA, second.c_str(), p.maskB, p.both, tone, p.meanAbsDiff,
        target.c_str());
  }
  if (count > 1) {
    std::printf("%s: %d frames: lowest IoU %.3f, lowest tone agreement %.1f%%\n", cli::name(), count, worstIou,
                100.0 * worstTone);
  }
  return 0;
}

}  // namespace puff::app
