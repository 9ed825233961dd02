// puffbench's shadow part: both shadow methods against the cel reference's exact shadows,
// speed against accuracy. Per scene (cloud-fig8c, explosion, magic-lamp with shadows on, and
// cloud-50k's emitters scaled to 10,000 particles) and per method (volumes; the map at
// Style::shadowMapScale 0.25, 0.5, 1 and 2): the median frame time, its ratio to the fill-rate floor
// of the same particles, and against the reference (3x3 supersampled meshes, a 4096-texel map over the
// casters) at the first, middle and last frame:
//   - shadow-mask IoU: the pixels a frame's shadows darken (a channel 0.02 darker than the same
//     frame drawn without shadows by the same path), the method's mask against the reference's;
//   - RMSE of the frames (display values, as --max-error measures the cel path).
// Each the worst over the frames.
#include "puffbench_shadows.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <puff/core/colour.h>
#include <puff/eval/budget.h>
#include <puff/eval/cel_reference.h>
#include <puff/reference/metrics.h>
#include <puff/scene/read.h>

#include "harness.h"
#include "puffbench_cel.h"

namespace puffbench {

namespace fs = std::filesystem;
using namespace puff;
using bench::Clock;

namespace {

// A configuration's frames in display values (standard view), as the cel budget compares them.
Result<Frames> render(const scene::Scene& scene, render::RenderPath path, std::span<const int> frames, int reps,
                      bool fillRateFloor = false) {
  PUFF_TRY_ASSIGN(auto f, renderFrames(scene, path, frames, reps, fillRateFloor));
  for (core::Image& im : f.images) im = core::viewTransform(im, core::ViewTransform::kStandard);
  return f;
}

// The pixels `shadowed` shows darker than `unshadowed` (the same path without shadows) by 0.02 in a channel.
std::vector<bool> shadowMask(const core::Image& shadowed, const core::Image& unshadowed) {
  std::vector<bool> m(static_cast<std::size_t>(shadowed.width) * shadowed.height);
  for (int y = 0; y < shadowed.height; ++y) {
    for (int x = 0; x < shadowed.width; ++x) {
      bool dark = false;
      for (int c = 0; c < 3; ++c) dark = dark || shadowed.at(x, y, c) < unshadowed.at(x, y, c) - 0.02f;
      m[static_cast<std::size_t>(y) * shadowed.width + x] = dark;
    }
  }
  return m;
}

}  // namespace

Result<std::vector<ShadowRow>> runShadowBench(const CelBenchOptions& opt, std::span<const std::string> scenes) {
  std::vector<ShadowRow> rows;
  for (const std::string& name : scenes) {
    const auto t0 = Clock::now();
    const bool cloud10k = name == "cloud-10k";
    PUFF_TRY_ASSIGN(
        auto loaded,
        scene::loadScene(opt.sceneDir / ((cloud10k ? std::string("cloud-50k") : name) + ".json"), opt.artDir));
    scene::Scene scene = loaded;
    if (scene.atlas.empty()) return Error{name + ": not a cel scene (no atlas)"};
    scene.width = opt.width;
    scene.height = opt.height;
    scene.media.reset();
    scene.style.shadows = true;
    if (cloud10k) {
      // cloud-50k's emitters scaled to 10,000 particles in all, in proportion.
      std::size_t total = 0;
      for (const scene::EmitterSpec& e : scene.emitters) total += static_cast<std::size_t>(e.count);
      for (scene::EmitterSpec& e : scene.emitters) {
        e.count = static_cast<int>(std::llround(10000.0 * e.count / static_cast<double>(total)));
      }
    }
    const std::vector<int> frames = eval::budgetFrames(0, scene.animation.frames - 1);
    scene::Scene unshadowedScene = scene;
    unshadowedScene.style.shadows = false;
    PUFF_TRY_ASSIGN(auto ref, render(scene, render::RenderPath::kReference, frames, 0));
    PUFF_TRY_ASSIGN(auto refNoShadow, render(unshadowedScene, render::RenderPath::kReference, frames, 0));
    PUFF_TRY_ASSIGN(auto noShadow, render(unshadowedScene, render::RenderPath::kCel, frames, opt.reps));
    PUFF_TRY_ASSIGN(auto floor, render(scene, render::RenderPath::kCel, frames, opt.reps, true));
    std::fprintf(stderr, "puffbench: %s: reference and floors (%.1f s)\n", name.c_str(),
                 std::chrono::duration<double>(Clock::now() - t0).count());

    auto measure = [&](cel::ShadowMethod method, float mapScale) -> Result<void> {
      const auto t1 = Clock::now();
      scene::Scene s = scene;
      s.style.shadowMethod = method;
      s.style.shadowMapScale = mapScale;
      PUFF_TRY_ASSIGN(auto f, render(s, render::RenderPath::kCel, frames, opt.reps));
      ShadowRow r;
      r.scene = name;
      r.method = std::string(cel::toString(method));
      r.mapScale = method == cel::ShadowMethod::kMap ? mapScale : 0.0f;
      r.particles = f.particles;
      r.width = opt.width;
      r.height = opt.height;
      r.ms = f.ms;
      r.floorMs = floor.ms;
      r.noShadowMs = noShadow.ms;
      r.shadowIoU = 1.0;
      for (std::size_t i = 0; i < frames.size(); ++i) {
        const std::vector<bool> mine = shadowMask(f.images[i], noShadow.images[i]);
        const std::vector<bool> exact = shadowMask(ref.images[i], refNoShadow.images[i]);
        r.shadowIoU = std::min(r.shadowIoU, reference::maskIoU(mine, exact));
        std::size_t n = 0;
        for (bool b : exact) n += b;
        r.referenceShadowFraction = std::max(r.referenceShadowFraction, static_cast<double>(n) / exact.size());
        r.rmse = std::max(r.rmse, reference::imageError(f.images[i], ref.images[i]).rmse);
      }
      rows.push_back(r);
      std::fprintf(stderr, "puffbench: %s: %s%s (%.1f s)\n", name.c_str(), r.method.c_str(),
                   method == cel::ShadowMethod::kMap ? (" x" + std::to_string(mapScale)).c_str() : "",
                   std::chrono::duration<double>(Clock::now() - t1).count());
      return {};
    };
    PUFF_TRY(measure(cel::ShadowMethod::kVolumes, 1.0f));
    for (float scale : {0.25f, 0.5f, 1.0f, 2.0f}) PUFF_TRY(measure(cel::ShadowMethod::kMap, scale));
  }
  return rows;
}

std::string shadowCsv(const std::vector<ShadowRow>& rows) {
  std::string csv =
      "scene,method,map_scale,particles,width,height,median_ms,floor_ms,ratio_to_floor,no_shadow_ms,shadow_iou,rmse,"
      "reference_shadow_fraction,valid\n";
  for (const ShadowRow& r : rows) {
    bench::appendf(csv, "%s,%s,%g,%zu,%d,%d,%.3f,%.3f,%s,%.3f,%.4f,%.6f,%.4f,%d\n", r.scene.c_str(), r.method.c_str(),
                   r.mapScale, r.particles, r.width, r.height, r.ms, r.floorMs,
                   bench::ratioToFloor(r.ms, r.floorMs).c_str(), r.noShadowMs, r.shadowIoU, r.rmse,
                   r.referenceShadowFraction, bench::validAgainstFloor(r.ms, r.floorMs) ? 1 : 0);
  }
  return csv;
}

}  // namespace puffbench
