// Fixed-function against programmable: the art scenes, restricted to the fixed path's
// limits (eval::restrictToFixedLimits: no shadows, uniform ambient, view-plane billboards, one
// sample), drawn by both paths in one compatibility context. Per scene and path: 2 warm-up frames,
// then the median of --reps frames (SceneRenderer::renderFrame of frame 0: the draw and the
// read-back that waits for it, the same for both); the ratio is fixed / cel of the same run. The parity of the
// two images is reported beside it. Writes CSV (stdout, or --csv FILE). Not a test: nothing here
// fails on a time.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <puff/eval/compare.h>
#include <puff/io/openimageio.h>
#include <puff/platform/gl_context.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "bench_usage.h"
#include "harness.h"

namespace {

namespace fs = std::filesystem;
using namespace puff;

}  // namespace

int main(int argc, char** argv) {
  puff::io::useOpenImageIO();
  int reps = 7;
  std::string csvPath;
  fs::path artDir = PUFF_ART_DIR, sceneDir = fs::path(PUFF_SOURCE_DIR) / "art" / "scenes";
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
      reps = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc)
      csvPath = argv[++i];
    else if (!std::strcmp(argv[i], "--art-dir") && i + 1 < argc)
      artDir = argv[++i];
    else {
      std::fprintf(puff::bench::usageStream(argv[i]),
                   "usage: puff_bench_paths [--reps N] [--csv FILE] [--art-dir DIR]\n");
      return puff::bench::usageExit(argv[i]);
    }
  }
  core::GlContextOptions o;
  o.profile = core::GlProfile::kCompatibility;
  auto context = core::createGlContext(o);
  if (!context) {
    std::fprintf(stderr, "puff_bench_paths: error: %s\n", context.error().message.c_str());
    return 1;
  }
  std::fprintf(stderr, "puff_bench_paths: %s\n", (*context)->describe().c_str());

  std::string csv = "scene,width,height,particles,cel_ms,fixed_ms,ratio_fixed_to_cel,iou,tone_share_0.1\n";
  for (const char* name : {"cloud-fig8a", "magic-lamp", "missile-trail", "explosion", "lamp-plume", "cloud-50k"}) {
    auto loaded = scene::loadScene(sceneDir / (std::string(name) + ".json"), artDir);
    if (!loaded) {
      std::fprintf(stderr, "puff_bench_paths: error: %s\n", loaded.error().message.c_str());
      return 1;
    }
    const scene::Scene scene = eval::restrictToFixedLimits(*loaded);
    double ms[2] = {0, 0};
    core::Image images[2], bare[2];
    std::size_t particles = 0;
    for (int k = 0; k < 2; ++k) {
      const render::RenderPath path = k == 0 ? render::RenderPath::kCel : render::RenderPath::kFixed;
      auto r = render::SceneRenderer::create(scene, path);
      auto r0 = render::SceneRenderer::create(eval::withoutParticles(scene), path);
      if (!r || !r0) {
        std::fprintf(stderr, "puff_bench_paths: error: %s\n", (!r ? r.error() : r0.error()).message.c_str());
        return 1;
      }
      std::vector<double> times;
      for (int i = 0; i < reps + 2; ++i) {
        render::FrameStats stats;
        const auto t0 = bench::Clock::now();
        auto image = (*r)->renderFrame(0, &stats);
        const double t = bench::msSince(t0);
        if (!image) {
          std::fprintf(stderr, "puff_bench_paths: error: %s\n", image.error().message.c_str());
          return 1;
        }
        if (i >= 2) times.push_back(t);
        images[k] = std::move(*image);
        particles = stats.particles;
      }
      ms[k] = bench::median(times);
      auto b = (*r0)->renderFrame(0);
      if (!b) return 1;
      bare[k] = std::move(*b);
    }
    const eval::Parity p = eval::compareFrames(images[1], bare[1], images[0], bare[0], 0.1f);
    bench::appendf(csv, "%s,%d,%d,%zu,%.2f,%.2f,%.3f,%.3f,%.3f\n", name, scene.width, scene.height, particles, ms[0],
                   ms[1], ms[1] / ms[0], p.iou, p.toneShare);
    std::fprintf(stderr, "puff_bench_paths: %-14s cel %.2f ms, fixed %.2f ms (%.2fx), IoU %.3f\n", name, ms[0], ms[1],
                 ms[1] / ms[0], p.iou);
  }
  return bench::writeCsv("puff_bench_paths", csvPath, csv) ? 0 : 1;
}
