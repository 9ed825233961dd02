// What the media cost against what they cover on screen (media::LayersBase::setCoverage): per case
// the cel path's frame with the media passes over the media's coverage (the default) and over the
// whole frame (SceneRenderer::setMediaOverWholeFrame, the passes before coverage), beside the same
// frame without the media (the scene's /media removed). Cases: magic-lamp with a small flame at its
// spout (tests/data/media/small-flame.json, under 2 % of the frame), and the media art scenes.
// Frame time: SceneRenderer::renderFrame (the draw and the read-back that waits for it) less the
// CPU time the simulators spent (FrameStats::simulateMs); the variants alternate frame by frame, 2
// warm-up rounds, then the median of --reps rounds. Writes CSV (stdout, or --csv FILE), the
// baseline (the frame without media) beside every row. Not a test: nothing here fails on a time.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <puff/io/openimageio.h>
#include <puff/platform/gl_context.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "bench_usage.h"
#include "harness.h"

namespace {

namespace fs = std::filesystem;
using namespace puff;

struct Case {
  std::string name;
  fs::path file;   // the scene
  fs::path patch;  // merged into it (JSON merge patch), or empty
  int frame;
};

enum Variant { kNoMedia, kCovered, kWholeFrame, kVariants };
constexpr const char* kVariantNames[kVariants] = {"no-media", "covered", "whole-frame"};

Result<scene::Scene> load(const Case& c, const fs::path& artDir) {
  std::ifstream in(c.file);
  if (!in) return Error::at(c.file, "cannot open");
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) return Error::at(c.file, "not JSON");
  if (!c.patch.empty()) {
    std::ifstream p(c.patch);
    nlohmann::json patch = nlohmann::json::parse(p, nullptr, false);
    if (patch.is_discarded()) return Error::at(c.patch, "not JSON");
    j.merge_patch(patch);
  }
  return scene::parseScene(j, c.file, artDir);
}

struct Timed {
  std::vector<double> ms;
  render::FrameStats stats;
};

}  // namespace

int main(int argc, char** argv) {
  puff::io::useOpenImageIO();
  int reps = 7;
  std::string csvPath;
  fs::path artDir = PUFF_ART_DIR, source = PUFF_SOURCE_DIR;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
      reps = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc)
      csvPath = argv[++i];
    else if (!std::strcmp(argv[i], "--art-dir") && i + 1 < argc)
      artDir = argv[++i];
    else {
      std::fprintf(puff::bench::usageStream(argv[i]),
                   "usage: puff_bench_coverage [--reps N] [--csv FILE] [--art-dir DIR]\n");
      return puff::bench::usageExit(argv[i]);
    }
  }
  auto context = core::createGlContext(core::GlContextOptions{});
  if (!context) {
    std::fprintf(stderr, "puff_bench_coverage: error: %s\n", context.error().message.c_str());
    return 1;
  }
  std::fprintf(stderr, "puff_bench_coverage: %s\n", (*context)->describe().c_str());
  const fs::path scenes = source / "art" / "scenes";
  const std::vector<Case> cases = {{"magic-lamp+small-flame", scenes / "magic-lamp.json",
                                    source / "tests" / "data" / "media" / "small-flame.json", 10},
                                   {"explosion-walls", scenes / "explosion-walls.json", {}, 20},
                                   {"explosion-walls-cartoon", scenes / "explosion-walls-cartoon.json", {}, 20},
                                   {"fire-to-smoke", scenes / "fire-to-smoke.json", {}, 48},
                                   {"smoke-flythrough", scenes / "smoke-flythrough.json", {}, 30}};

  std::string csv =
      "case,frame,width,height,samples,variant,media_particles,covered_share,ms,no_media_ms,ratio_to_no_media,"
      "whole_frame_ms,ratio_to_whole_frame\n";
  for (const Case& c : cases) {
    auto s = load(c, artDir);
    if (!s) {
      std::fprintf(stderr, "puff_bench_coverage: error: %s\n", s.error().message.c_str());
      return 1;
    }
    scene::Scene bare = *s;
    bare.media.reset();
    std::unique_ptr<render::SceneRenderer> r[kVariants];
    for (int v = 0; v < kVariants; ++v) {
      auto made = render::SceneRenderer::create(v == kNoMedia ? bare : *s);
      if (!made) {
        std::fprintf(stderr, "puff_bench_coverage: error: %s\n", made.error().message.c_str());
        return 1;
      }
      r[v] = std::move(*made);
      r[v]->setMediaOverWholeFrame(v == kWholeFrame);
    }
    Timed t[kVariants];
    for (int i = 0; i < reps + 2; ++i) {
      for (int v = 0; v < kVariants; ++v) {
        render::FrameStats stats;
        const auto t0 = bench::Clock::now();
        auto image = r[v]->renderFrame(c.frame, &stats);
        const double ms = bench::msSince(t0) - stats.simulateMs;
        if (!image) {
          std::fprintf(stderr, "puff_bench_coverage: error: %s\n", image.error().message.c_str());
          return 1;
        }
        if (i >= 2) t[v].ms.push_back(ms);
        t[v].stats = stats;
      }
    }
    double median[kVariants];
    for (int v = 0; v < kVariants; ++v) median[v] = bench::median(t[v].ms);
    const double pixels = static_cast<double>(s->width) * s->height;
    for (int v = 0; v < kVariants; ++v) {
      const double share = static_cast<double>(t[v].stats.mediaCoveredPixels) / pixels;
      bench::appendf(csv, "%s,%d,%d,%d,%d,%s,%zu,%.4f,%.2f,%.2f,%.3f,%.2f,%.3f\n", c.name.c_str(), c.frame, s->width,
                     s->height, s->samples, kVariantNames[v], t[v].stats.mediaParticles, share, median[v],
                     median[kNoMedia], median[v] / median[kNoMedia], median[kWholeFrame],
                     median[v] / median[kWholeFrame]);
    }
    std::fprintf(stderr,
                 "puff_bench_coverage: %-24s no media %.2f ms, covered %.2f ms (%.3fx, %.2f %% of the frame), whole "
                 "frame %.2f ms (%.3fx)\n",
                 c.name.c_str(), median[kNoMedia], median[kCovered], median[kCovered] / median[kNoMedia],
                 100.0 * static_cast<double>(t[kCovered].stats.mediaCoveredPixels) / pixels, median[kWholeFrame],
                 median[kWholeFrame] / median[kNoMedia]);
  }
  return bench::writeCsv("puff_bench_coverage", csvPath, csv) ? 0 : 1;
}
