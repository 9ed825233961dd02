// puffbench: speed against accuracy on the art scenes. The cel part (nailboards and the
// fixed-function path against the cel reference over atlas size, mesh detail and particle count) is
// in puffbench_cel.cpp and writes --cel-csv; the shadow part is puffbench_shadows.cpp (--shadow-csv);
// the tumble part (multi-view atlases' memory against their error over a sweep of orientations) is
// puffbench_tumble.cpp (--tumble-csv). The media part: for every scene, method (planar,
// planar-textured, soft-linear, soft-scurve, spherical) and media layer resolution (1/8 ..
// 1), the median frame time and the worst error against the exact reference over three frames of
// the scene's camera path (eval::measureMediaBudget: reference::renderMediaReference over the
// same opaque layer, RMSE in scene-linear colour; also over the media pixels, in the clip band, and
// SSIM; with --physical the same against reference::renderMediaPhysical, the particles as one
// continuous medium), and the scene's frame without media particles (the
// baseline: opaque pass, resolve and compose) measured in the same run. Marks the Pareto front per
// scene: the configurations no other one beats on both time and error. Writes CSV (--csv FILE,
// atomically; else stdout) for tests/bench/report.sh, which draws the charts. Not a test: nothing
// here fails on a time.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <puff/core/image.h>
#include <puff/eval/budget.h>
#include <puff/io/openimageio.h>
#include <puff/platform/gl_context.h>
#include <puff/reference/metrics.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "bench_usage.h"
#include "harness.h"
#include "puffbench_cartoon.h"
#include "puffbench_cel.h"
#include "puffbench_shadows.h"
#include "puffbench_tumble.h"

namespace {

namespace fs = std::filesystem;
using namespace puff;
using bench::Clock;

// Every media method, the paper's classic textured billboard included.
constexpr media::Method kMethods[] = {media::Method::kPlanar, media::Method::kPlanarTextured,
                                      media::Method::kSoftLinear, media::Method::kSoftSCurve,
                                      media::Method::kSpherical};

struct Row {
  std::string scene, method;
  float resolution = 1.0f;
  int width = 0, height = 0;
  std::size_t particles = 0;
  double ms = 0.0, baselineMs = 0.0, rmse = 0.0;
  double floorMs = 0.0;  ///< the fill-rate floor: the same particles' quads computing nothing
  bool pareto = false;
  bool sceneMethod = false;            ///< the scene's own method (what puffrender --max-error measures)
  eval::RegionErrors regions;          ///< against the model reference (worst fields used)
  bool physical = false;               ///< measured against the physical reference too
  double rmsePhysical = 0.0;           ///< worst whole-frame RMSE against it
  eval::RegionErrors regionsPhysical;  ///< against it (worst fields used)
};

// A CSV field: the figure, or empty where it was not measured.
std::string field(bool measured, double v, const char* format = "%.6f") {
  if (!measured) return {};
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// The scene as eval::measureMediaBudget renders the frames it times: without what the reference
// does not model (explosion lights, heat shimmer, motion blur; budget.cpp does the same). The
// baseline and every floor are measured on it, so they pay what the measured rows pay.
scene::Scene asMeasured(scene::Scene s) {
  s.media->lights.clear();
  s.media->compose.shimmerPixels = 0.0f;
  s.media->motionBlurFrames = 0;
  return s;
}

// The frame without media particles (what every configuration pays before the media), or with
// `fillRateFloor` the frame with the media particles drawn by the scene's method and layer
// resolution computing nothing (SceneRenderer::setFillRateFloor: that method's quads, depth test
// and blending with media::Renderer's floor program for it): the method's fill-rate floor. Both on
// asMeasured(s).
Result<double> baselineMs(scene::Scene s, std::span<const int> frames, int reps, bool fillRateFloor = false) {
  s = asMeasured(std::move(s));
  if (!fillRateFloor) {
    s.media->particles.clear();
    s.media->emitters.clear();
  }
  PUFF_TRY_ASSIGN(auto r, render::SceneRenderer::create(s));
  (r)->setFillRateFloor(fillRateFloor);
  std::vector<double> times;
  for (int f : frames) {
    if (auto first = (r)->renderFrame(f); !first) return first.error();
    PUFF_TRY(puffbench::timeFrame(*r, f, reps, times));
  }
  return bench::median(times);
}

// The places media methods break, measured: per method,
//  - temporal: smoke-flythrough's camera flying into the smoke (its pillar taken out, so only the
//    media change), every frame in order; the largest and the mean second difference of consecutive
//    frames (reference::largestSecondDifference: popping shows as spikes);
//  - spatial: explosion-walls at its fireball frames (explosion lights and shimmer off), the largest
//    jump between neighbouring pixels of the ERROR image, frame minus exact reference
//    (eval::mediaReference), over the pixels either shows media on, away from the bare frame's own
//    edges: the fire's texture is in both and cancels, a billboard cut by a wall is a hard step in
//    the error that the reference does not have.
// The largest step between neighbouring pixels of the error image (frame minus its exact reference)
// over the pixels either shows media on, away from the bare frame's own edges: the medium's own
// gradients are in both and cancel; a billboard cut by a wall is a hard step the reference has not.
double largestErrorJump(const core::Image& im, const core::Image& ref, const core::Image& b) {
  const int width = im.width, height = im.height;
  const std::vector<bool> shown = reference::coverageMask(im, b), exact = reference::coverageMask(ref, b);
  core::Image error(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) error.at(x, y, c) = im.at(x, y, c) - ref.at(x, y, c);
  std::vector<bool> region(shown.size(), false);
  for (int y = 1; y + 1 < height; ++y) {
    for (int x = 1; x + 1 < width; ++x) {
      bool flat = true;  // the bare frame has no edge of its own here
      for (int c = 0; c < 3 && flat; ++c) {
        const float v = b.at(x, y, c);
        flat = std::abs(v - b.at(x + 1, y, c)) < 1.0f / 64 && std::abs(v - b.at(x - 1, y, c)) < 1.0f / 64 &&
               std::abs(v - b.at(x, y + 1, c)) < 1.0f / 64 && std::abs(v - b.at(x, y - 1, c)) < 1.0f / 64;
      }
      const std::size_t k = static_cast<std::size_t>(y) * width + x;
      region[k] = flat && (shown[k] || exact[k]);
    }
  }
  return reference::largestJump(error, region);
}

struct StabilityRow {
  std::string scene, method, metric;
  double value = 0.0;
  int frames = 0, width = 0, height = 0;
};

Result<std::vector<StabilityRow>> stability(const fs::path& sceneDir, const fs::path& artDir, int width, int height) {
  std::vector<StabilityRow> rows;
  const auto& methods = kMethods;
  {
    PUFF_TRY_ASSIGN(auto loaded, scene::loadScene(sceneDir / "smoke-flythrough.json", artDir));
    // The smoke frozen as it is at frame 0 (births pop in whatever the method; that is the
    // simulator's, not the billboards'), listed as particles; the pillar taken out.
    scene::Scene frozen = loaded;
    frozen.width = width;
    frozen.height = height;
    frozen.objects.clear();
    {
      PUFF_TRY_ASSIGN(auto r, render::SceneRenderer::create(frozen));
      if (auto im = (r)->renderFrame(0); !im) return im.error();
      PUFF_TRY_ASSIGN(auto in, (r)->lastMediaFrame());
      frozen.media->emitters.clear();
      frozen.media->particles.clear();
      for (const media::Particle& p : in.particles) {
        // A listed media particle has no tint or temperature of its own (curves over life belong to
        // emitters): freezing one that has them would measure another picture.
        if (p.tint != glm::vec3(1.0f) || p.temperature > 0.0f) {
          return Error{
              "puffbench: the media particles of this scene have curves over life (tint or temperature), "
              "which frozen particles cannot keep"};
        }
        scene::MediaParticleSpec spec;
        spec.position = p.position;
        spec.radius = p.radius;
        spec.materialIndex = static_cast<int>(p.material);
        spec.life = p.life;
        spec.density = p.density;
        spec.seed = p.seed;
        frozen.media->particles.push_back(spec);
      }
    }
    for (media::Method m : methods) {
      scene::Scene s = frozen;
      s.media->method = m;
      PUFF_TRY_ASSIGN(auto r, render::SceneRenderer::create(s));
      std::vector<core::Image> frames;
      for (int f = 0; f < s.animation.frames; ++f) {
        PUFF_TRY_ASSIGN(auto im, (r)->renderFrame(f));
        frames.push_back(std::move(im));
      }
      const std::string method(media::toString(m));
      rows.push_back({"smoke-flythrough", method, "largest_second_difference",
                      reference::largestSecondDifference(frames), s.animation.frames, width, height});
      rows.push_back({"smoke-flythrough", method, "mean_second_difference", reference::meanSecondDifference(frames),
                      s.animation.frames, width, height});
    }
  }
  {
    PUFF_TRY_ASSIGN(auto loaded, scene::loadScene(sceneDir / "explosion-walls.json", artDir));
    scene::Scene bareScene = loaded;
    bareScene.width = width;
    bareScene.height = height;
    bareScene.media->particles.clear();
    bareScene.media->emitters.clear();
    bareScene.media->lights.clear();
    PUFF_TRY_ASSIGN(auto bare, render::SceneRenderer::create(bareScene));
    const int fireFrames[] = {5, 20};
    std::vector<core::Image> bareFrames;
    for (int f : fireFrames) {
      PUFF_TRY_ASSIGN(auto im, (bare)->renderFrame(f));
      bareFrames.push_back(std::move(im));
    }
    for (media::Method m : methods) {
      scene::Scene s = loaded;
      s.width = width;
      s.height = height;
      s.media->method = m;
      s.media->lights.clear();  // their light is not the media's: leave the walls as the bare frame has them
      s.media->compose.shimmerPixels = 0.0f;
      s.media->resolution = 1.0f;  // no upsampling error: what is left at the walls is the method's
      PUFF_TRY_ASSIGN(auto r, render::SceneRenderer::create(s));
      double worst = 0.0;
      for (std::size_t i = 0; i < std::size(fireFrames); ++i) {
        PUFF_TRY_ASSIGN(auto im, (r)->renderFrame(fireFrames[i]));
        PUFF_TRY_ASSIGN(auto ref, eval::mediaReference(s, *r));
        worst = std::max(worst, largestErrorJump(im, ref, bareFrames[i]));
      }
      rows.push_back({"explosion-walls", std::string(media::toString(m)), "largest_error_jump", worst,
                      static_cast<int>(std::size(fireFrames)), width, height});
    }
  }
  {
    // The same spatial metric where the clipping can be isolated: one dense smoke sphere, no detail
    // video, a slanted wall through its centre (the ball of media_test's slanted-wall test), the
    // layer at full resolution.
    const nlohmann::json j = {
        {"output", {{"width", width}, {"height", height}, {"samples", 1}, {"background", {0.6, 0.7, 0.85}}}},
        {"camera", {{"position", {0, 0, 6}}, {"target", {0, 0, 0}}, {"fovY", 40}, {"near", 0.5}, {"far", 30}}},
        {"objects", {{{"type", "plane"}, {"rotate", {70, 25, 0}}, {"scale", {4, 1, 4}}, {"albedo", {0.7, 0.5, 0.4}}}}},
        {"media", {{"resolution", 1}, {"particles", {{{"position", {0, 0, 0}}, {"radius", 1.6}, {"density", 3}}}}}}};
    PUFF_TRY_ASSIGN(auto wall, scene::parseScene(j, sceneDir / "wall-through-smoke.json"));
    scene::Scene bareScene = wall;
    bareScene.media->particles.clear();
    PUFF_TRY_ASSIGN(auto bare, render::SceneRenderer::create(bareScene));
    PUFF_TRY_ASSIGN(auto b, (bare)->renderFrame(0));
    for (media::Method m : methods) {
      scene::Scene s = wall;
      s.media->method = m;
      PUFF_TRY_ASSIGN(auto r, render::SceneRenderer::create(s));
      PUFF_TRY_ASSIGN(auto im, (r)->renderFrame(0));
      PUFF_TRY_ASSIGN(auto ref, eval::mediaReference(s, *r));
      rows.push_back({"wall-through-smoke", std::string(media::toString(m)), "largest_error_jump",
                      largestErrorJump(im, ref, b), 1, width, height});
    }
  }
  return rows;
}

}  // namespace

int main(int argc, char** argv) {
  puff::io::useOpenImageIO();
  int reps = 3, width = 320, height = 240;
  bool physical = false;
  std::string csvPath, celCsvPath, stabilityCsvPath, shadowCsvPath, tumbleCsvPath, cartoonCsvPath, part = "all";
  std::vector<std::string> shadowScenes = {"cloud-fig8c", "explosion", "magic-lamp", "cloud-10k"};
  puffbench::CelBenchOptions cel;
  puffbench::TumbleBenchOptions tumble;
  tumble.puffDir = fs::path(PUFF_SOURCE_DIR) / "art" / "puffs";
  fs::path artDir = PUFF_ART_DIR, sceneDir = fs::path(PUFF_SOURCE_DIR) / "art" / "scenes";
  std::vector<std::string> scenes = {"explosion-walls", "smoke-flythrough", "fire-to-smoke"};
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc) {
      reps = std::clamp(std::atoi(argv[++i]), 1, 100);
    } else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) {
      csvPath = argv[++i];
    } else if (!std::strcmp(argv[i], "--art-dir") && i + 1 < argc) {
      artDir = argv[++i];
    } else if (!std::strcmp(argv[i], "--size") && i + 2 < argc) {
      width = std::clamp(std::atoi(argv[++i]), 16, 4096);
      height = std::clamp(std::atoi(argv[++i]), 16, 4096);
    } else if (!std::strcmp(argv[i], "--stability-csv") && i + 1 < argc) {
      stabilityCsvPath = argv[++i];
    } else if (!std::strcmp(argv[i], "--cel-csv") && i + 1 < argc) {
      celCsvPath = argv[++i];
    } else if (!std::strcmp(argv[i], "--shadow-csv") && i + 1 < argc) {
      shadowCsvPath = argv[++i];
    } else if ((!std::strcmp(argv[i], "--shadow-scenes") || !std::strcmp(argv[i], "--cel-scenes") ||
                !std::strcmp(argv[i], "--tumble-scenes")) &&
               i + 1 < argc) {
      std::vector<std::string>& into = !std::strcmp(argv[i], "--shadow-scenes") ? shadowScenes
                                       : !std::strcmp(argv[i], "--cel-scenes")  ? cel.scenes
                                                                                : cel.tumbleScenes;
      into.clear();  // (an empty LIST: none)
      std::string list = argv[++i];
      for (std::size_t at = 0; at <= list.size();) {
        const std::size_t comma = std::min(list.find(',', at), list.size());
        if (comma > at) into.push_back(list.substr(at, comma - at));
        at = comma + 1;
      }
    } else if (!std::strcmp(argv[i], "--cartoon-csv") && i + 1 < argc) {
      cartoonCsvPath = argv[++i];
    } else if (!std::strcmp(argv[i], "--tumble-csv") && i + 1 < argc) {
      tumbleCsvPath = argv[++i];
    } else if (!std::strcmp(argv[i], "--tumble-atlases") && i + 1 < argc) {
      auto atlases = puffbench::parseTumbleAtlases(argv[++i]);
      if (!atlases) {
        std::fprintf(stderr, "puffbench: error: %s\n", atlases.error().message.c_str());
        return 2;
      }
      tumble.atlases = *atlases;
    } else if (!std::strcmp(argv[i], "--tumble-cells") && i + 1 < argc) {
      tumble.cellSizes.clear();
      const std::string list = argv[++i];
      for (std::size_t at = 0; at <= list.size();) {
        const std::size_t comma = std::min(list.find(',', at), list.size());
        if (comma > at)
          tumble.cellSizes.push_back(std::atoi(list.substr(at, comma - at).c_str()));  // bake::validate checks it
        at = comma + 1;
      }
    } else if (!std::strcmp(argv[i], "--tumble-step") && i + 1 < argc) {
      tumble.stepDegrees = std::atoi(argv[++i]);  // eval::measureTumble refuses a step that does not divide 90
    } else if (!std::strcmp(argv[i], "--part") && i + 1 < argc &&
               (!std::strcmp(argv[i + 1], "media") || !std::strcmp(argv[i + 1], "cel") ||
                !std::strcmp(argv[i + 1], "shadows") || !std::strcmp(argv[i + 1], "tumble") ||
                !std::strcmp(argv[i + 1], "cartoon") || !std::strcmp(argv[i + 1], "all"))) {
      part = argv[++i];
    } else if (!std::strcmp(argv[i], "--reference-limit") && i + 1 < argc) {
      cel.referenceLimit = static_cast<std::size_t>(std::max(0, std::atoi(argv[++i])));
    } else if (!std::strcmp(argv[i], "--physical")) {
      physical = true;
    } else if (!std::strcmp(argv[i], "--no-counts")) {
      cel.counts.clear();
    } else if (!std::strcmp(argv[i], "--scene") && i + 1 < argc) {
      if (scenes.size() == 3 && scenes[0] == "explosion-walls") scenes.clear();
      scenes.push_back(argv[++i]);
    } else {
      std::fprintf(
          puff::bench::usageStream(argv[i]),
          "usage: puffbench [--part media|cel|shadows|tumble|cartoon|all (all: media and cel)] [--reps N (3)]\n"
          "                 [--size W H (320 240)] [--shadow-csv FILE] [--shadow-scenes A,B (cloud-fig8c,\n"
          "                 explosion,magic-lamp,cloud-10k)]\n"
          "                 [--scene NAME ... (media scenes)] [--csv FILE (media)] [--cel-csv FILE]\n"
          "                 [--stability-csv FILE (media methods where they break)]\n"
          "                 [--physical: media errors against the physical reference too]\n"
          "                 [--reference-limit N (12500): no cel reference above N particles]\n"
          "                 [--no-counts: skip the particle-count sweep] [--art-dir DIR]\n"
          "                 [--cel-scenes A,B (explosion,cloud-fig8c): cel's atlas and mesh-detail sweeps]\n"
          "                 [--tumble-scenes A,B (dust-roll): cel's oriented puffs by the blend, by the hull\n"
          "                 from each size --max-error tries and by the hull, at the scene's own size]\n"
          "                 [--tumble-csv FILE] [--tumble-atlases LIST (oct3,oct5,oct7,oct9,hemioct3,\n"
          "                 hemioct5,hemioct7)] [--tumble-cells LIST (64,128,256)] [--tumble-step DEG (15)]\n"
          "                 (tumble: each atlas drawn by both tumble methods, hull and blend; frame times are\n"
          "                 eval::measureTumble's, 3 renders a roll; --reps is not used)\n"
          "                 [--cartoon-csv FILE] (cartoon: explosion-walls-cartoon and fire-to-smoke-cartoon\n"
          "                 against their photoreal selves: cost, stability, the ink against the references)\n");
      return puff::bench::usageExit(argv[i]);
    }
  }
  // Compatibility profile: the fixed-function path (GL 1.x calls) runs beside the programmable ones.
  core::GlContextOptions glOptions;
  glOptions.profile = core::GlProfile::kCompatibility;
  auto context = core::createGlContext(glOptions);
  if (!context) {
    std::fprintf(stderr, "puffbench: error: %s\n", context.error().message.c_str());
    return 1;
  }
  std::fprintf(stderr, "puffbench: %s\n", (*context)->describe().c_str());

  if (part == "tumble") {
    auto rows = puffbench::runTumbleBench(tumble);
    if (!rows) {
      std::fprintf(stderr, "puffbench: error: %s\n", rows.error().message.c_str());
      return 1;
    }
    for (const puffbench::TumbleRow& r : *rows) {
      std::fprintf(stderr,
                   "%-8s %dx%d views, %4d texels, %-5s: %9zu bytes, %zu poses: coverage IoU min %.4f mean %.4f (%.1f%% "
                   ">= 0.95), outline IoU min %.4f mean %.4f (%.1f%% >= 0.5), %.1f ms\n",
                   r.layout.c_str(), r.grid, r.grid, r.cellSize, r.method.c_str(), r.atlasBytes, r.poses,
                   r.minCoverageIoU, r.meanCoverageIoU, 100.0 * r.coverageShare, r.minOutlineIoU, r.meanOutlineIoU,
                   100.0 * r.outlineShare, r.ms);
    }
    return bench::writeCsv("puffbench", tumbleCsvPath, puffbench::tumbleCsv(*rows)) ? 0 : 1;
  }
  if (part == "cartoon") {
    puffbench::CartoonBenchOptions c;
    c.sceneDir = sceneDir;
    c.artDir = artDir;
    c.width = width;
    c.height = height;
    c.reps = reps;
    auto rows = puffbench::runCartoonBench(c);
    if (!rows) {
      std::fprintf(stderr, "puffbench: error: %s\n", rows.error().message.c_str());
      return 1;
    }
    for (const puffbench::CartoonRow& r : *rows) {
      std::fprintf(
          stderr,
          "%-24s %-9s %8.2f ms (bare %.2f, empty %.2f)  d2 mean %.5f p99 %.4f flicker %.5f%%  iso: model IoU %.4f "
          "mean %.2f px p95 %.2f px, physical IoU %.4f mean %.2f px p95 %.2f px\n",
          r.scene.c_str(), r.style.c_str(), r.ms, r.bareMs, r.emptyMs, r.d2Mean, r.d2P99, 100.0 * r.flickerShare,
          r.iouModel, r.meanPxModel, r.p95PxModel, r.iouPhysical, r.meanPxPhysical, r.p95PxPhysical);
    }
    return bench::writeCsv("puffbench", cartoonCsvPath, puffbench::cartoonCsv(*rows)) ? 0 : 1;
  }
  if (part == "shadows") {
    cel.sceneDir = sceneDir;
    cel.artDir = artDir;
    cel.width = width;
    cel.height = height;
    cel.reps = reps;
    auto shadowRows = puffbench::runShadowBench(cel, shadowScenes);
    if (!shadowRows) {
      std::fprintf(stderr, "puffbench: error: %s\n", shadowRows.error().message.c_str());
      return 1;
    }
    for (const puffbench::ShadowRow& r : *shadowRows) {
      std::fprintf(stderr, "%-12s %-8s x%-5g %8.2f ms (%s floor)  shadow IoU %.3f  rmse %.5f\n", r.scene.c_str(),
                   r.method.c_str(), r.mapScale, r.ms, bench::ratioToFloor(r.ms, r.floorMs).c_str(), r.shadowIoU,
                   r.rmse);
    }
    return bench::writeCsv("puffbench", shadowCsvPath, puffbench::shadowCsv(*shadowRows)) ? 0 : 1;
  }
  if (part != "media") {
    cel.sceneDir = sceneDir;
    cel.artDir = artDir;
    cel.width = width;
    cel.height = height;
    cel.reps = reps;
    auto celRows = puffbench::runCelBench(cel);
    if (!celRows) {
      std::fprintf(stderr, "puffbench: error: %s\n", celRows.error().message.c_str());
      return 1;
    }
    for (const puffbench::CelRow& r : *celRows) {
      const std::string ratio = bench::ratioToFloor(r.ms, r.floorMs);
      std::fprintf(stderr, "%-12s %-16s %-6s %7s  %8.2f ms (%s floor)  rmse %.5f  cov %.3f  ink %.3f%s\n",
                   r.scene.c_str(), r.path.c_str(), r.parameter.c_str(), r.label.c_str(), r.ms,
                   bench::validAgainstFloor(r.ms, r.floorMs) ? (ratio + "x").c_str() : "INVALID: below its", r.rmse,
                   r.coverageIoU, r.outlineIoU, r.pareto ? "  pareto" : "");
    }
    if (!bench::writeCsv("puffbench", celCsvPath, puffbench::celCsv(*celRows))) return 1;
    if (part == "cel") return 0;
  }

  std::vector<Row> rows;
  for (const std::string& name : scenes) {
    auto loaded = scene::loadScene(sceneDir / (name + ".json"), artDir);
    if (!loaded) {
      std::fprintf(stderr, "puffbench: error: %s\n", loaded.error().message.c_str());
      return 1;
    }
    scene::Scene scene = *loaded;
    if (!scene.media) {
      std::fprintf(stderr, "puffbench: error: %s has no media\n", name.c_str());
      return 1;
    }
    scene.width = width;
    scene.height = height;
    const std::vector<int> frames = eval::budgetFrames(0, scene.animation.frames - 1);
    auto base = baselineMs(scene, frames, reps);
    if (!base) {
      std::fprintf(stderr, "puffbench: error: %s\n", base.error().message.c_str());
      return 1;
    }
    const std::size_t first = rows.size();
    for (media::Method m : kMethods) {
      scene::Scene s = scene;
      s.media->method = m;
      // This method's fill-rate floor at each layer resolution (the quads' pixels scale with it).
      std::map<float, double> floors;
      for (float res : eval::kMediaResolutions) {
        scene::Scene fs = s;
        fs.media->resolution = res;
        auto fl = baselineMs(fs, frames, reps, true);
        if (!fl) {
          std::fprintf(stderr, "puffbench: error: %s\n", fl.error().message.c_str());
          return 1;
        }
        floors[res] = *fl;
      }
      eval::MediaBudgetOptions o;
      o.timedRenders = reps;
      o.physical = physical;
      const auto t0 = Clock::now();
      auto budget = eval::measureMediaBudget(s, frames, o);
      if (!budget) {
        std::fprintf(stderr, "puffbench: error: %s\n", budget.error().message.c_str());
        return 1;
      }
      std::fprintf(stderr, "puffbench: %s, %s: measured in %.1f s\n", name.c_str(),
                   std::string(media::toString(m)).c_str(), std::chrono::duration<double>(Clock::now() - t0).count());
      for (const eval::MediaCandidate& c : budget->candidates) {
        Row r;
        r.scene = name;
        r.method = std::string(media::toString(m));
        r.resolution = c.resolution;
        r.width = width;
        r.height = height;
        r.ms = c.medianMs;
        r.baselineMs = *base;
        r.floorMs = floors[c.resolution];
        r.rmse = c.worstRmse;
        r.sceneMethod = m == scene.media->method;
        r.regions = c.regions;
        r.physical = physical;
        r.rmsePhysical = c.worstRmsePhysical;
        r.regionsPhysical = c.regionsPhysical;
        rows.push_back(r);
      }
    }
    // The Pareto front of this scene: nothing else both as fast and as close, and better in one.
    for (std::size_t i = first; i < rows.size(); ++i) {
      bool beaten = false;
      for (std::size_t j = first; j < rows.size() && !beaten; ++j) {
        beaten = j != i && rows[j].ms <= rows[i].ms && rows[j].rmse <= rows[i].rmse &&
                 (rows[j].ms < rows[i].ms || rows[j].rmse < rows[i].rmse);
      }
      rows[i].pareto = !beaten;
    }
  }

  std::string csv =
      "scene,method,resolution,width,height,median_ms,baseline_ms,ratio_to_baseline,worst_rmse,psnr_db,"
      "pareto,floor_ms,ratio_to_floor,valid,scene_method,worst_rmse_media,worst_rmse_band,worst_ssim,"
      "worst_rmse_physical,worst_rmse_media_physical,worst_rmse_band_physical,worst_ssim_physical\n";
  for (const Row& r : rows) {
    const double psnr = r.rmse > 0.0 ? -20.0 * std::log10(r.rmse) : 999.0;
    // A row faster than its own floor measured noise or a floor that is not one: invalid, no ratio.
    const bool valid = bench::validAgainstFloor(r.ms, r.floorMs);
    bench::appendf(csv, "%s,%s,%g,%d,%d,%.3f,%.3f,%.3f,%.6f,%.2f,%d,%.3f,%s,%d,", r.scene.c_str(), r.method.c_str(),
                   static_cast<double>(r.resolution), r.width, r.height, r.ms, r.baselineMs,
                   r.baselineMs > 0.0 ? r.ms / r.baselineMs : 0.0, r.rmse, psnr, r.pareto ? 1 : 0, r.floorMs,
                   bench::ratioToFloor(r.ms, r.floorMs).c_str(), valid ? 1 : 0);
    bench::appendf(csv, "%d,%.6f,%.6f,%.6f,%s,%s,%s,%s\n", r.sceneMethod ? 1 : 0, r.regions.worstRmseMedia,
                   r.regions.worstRmseBand, r.regions.worstSsim, field(r.physical, r.rmsePhysical).c_str(),
                   field(r.physical, r.regionsPhysical.worstRmseMedia).c_str(),
                   field(r.physical, r.regionsPhysical.worstRmseBand).c_str(),
                   field(r.physical, r.regionsPhysical.worstSsim).c_str());
    std::fprintf(
        stderr,
        "%-17s %-15s %5g  %8.2f ms (%5.2fx)  floor %8.2f ms%s  rmse %.5f (media %.5f, band %.5f, ssim %.4f)%s%s\n",
        r.scene.c_str(), r.method.c_str(), static_cast<double>(r.resolution), r.ms,
        r.baselineMs > 0.0 ? r.ms / r.baselineMs : 0.0, r.floorMs, valid ? "" : " (INVALID: below its floor)", r.rmse,
        r.regions.worstRmseMedia, r.regions.worstRmseBand, r.regions.worstSsim,
        r.physical ? ("  physical " + field(true, r.rmsePhysical, "%.5f")).c_str() : "", r.pareto ? "  pareto" : "");
  }
  {
    // Where the media methods break, at a small size (every frame of the flight is drawn).
    auto st = stability(sceneDir, artDir, 160, 120);
    if (!st) {
      std::fprintf(stderr, "puffbench: error: %s\n", st.error().message.c_str());
      return 1;
    }
    std::string stCsv = "scene,method,metric,value,frames,width,height\n";
    for (const StabilityRow& r : *st) {
      bench::appendf(stCsv, "%s,%s,%s,%.6f,%d,%d,%d\n", r.scene.c_str(), r.method.c_str(), r.metric.c_str(), r.value,
                     r.frames, r.width, r.height);
      std::fprintf(stderr, "%-17s %-12s %-26s %.4f\n", r.scene.c_str(), r.method.c_str(), r.metric.c_str(), r.value);
    }
    if (!bench::writeCsv("puffbench", stabilityCsvPath, stCsv)) return 1;
  }
  return bench::writeCsv("puffbench", csvPath, csv) ? 0 : 1;
}
