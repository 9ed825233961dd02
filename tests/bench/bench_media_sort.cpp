// The back-to-front sort key measured against the physical reference: for each art
// scene's frames, the media drawn by the GPU (SceneRenderer::renderFrame, scene-linear floats)
// with each media::SortKey, compared over the SAME opaque layer (SceneRenderer::lastMediaFrame)
// with
//  - the physical reference (reference::renderMediaPhysical: the particles as one continuous
//    medium; what the image should be),
//  - the model reference composited per ray (reference::renderMediaReference, viewAxisOrder off:
//    the model without any sort error),
//  - the model reference in the renderer's order with the same key (viewAxisOrder on).
// Per row: RMSE over R, G, B (linear, not clamped) over the whole frame and over the media pixels
// (reference::mediaMask of the physical reference's layer). The differences separate the errors:
// "order vs per ray" is the sort's error alone, "per ray vs physical" the model's alone, "gpu vs
// order" the GPU's arithmetic and layer. What the references do not model (explosion lights, heat
// shimmer, motion blur) is left out of the renders, as eval::measureMediaBudget does; the layer
// is at full resolution. Writes CSV (--csv FILE, atomically; else stdout) and prints a markdown
// summary to stderr. Not a test: nothing here fails on a time, and nothing is timed.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <puff/core/colour.h>
#include <puff/core/detail_video.h>
#include <puff/core/image.h>
#include <puff/io/openimageio.h>
#include <puff/platform/gl_context.h>
#include <puff/reference/media_physical.h>
#include <puff/reference/media_reference.h>
#include <puff/reference/metrics.h>
#include <puff/render/render.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>

#include "bench_usage.h"
#include "harness.h"

namespace {

namespace fs = std::filesystem;
using namespace puff;

constexpr media::SortKey kKeys[] = {media::SortKey::kViewDepth, media::SortKey::kPowerDistance};

struct Case {
  std::string scene;
  std::vector<int> frames;
};

struct Pair {
  double whole = 0.0, masked = 0.0;
};

Pair errors(const core::Image& a, const core::Image& b, const std::vector<bool>& mask) {
  return {reference::imageError(a, b).rmse, reference::imageError(a, b, mask).rmse};
}

struct Row {
  std::string scene, key;
  int frame = 0, width = 0, height = 0, samples = 0;
  std::size_t particles = 0, mediaPixels = 0;
  Pair gpuPhysical, gpuPerRay, orderPerRay, orderPhysical, perRayPhysical;
  double gpuOrder = 0.0;
};

// The scene as measured: lights, shimmer and motion blur off (no reference models them), the
// media layer at full resolution, the size and samples asked for.
scene::Scene asMeasured(scene::Scene s, double scale, int samples) {
  s.media->lights.clear();
  s.media->compose.shimmerPixels = 0.0f;
  s.media->motionBlurFrames = 0;
  s.media->resolution = 1.0f;
  s.width = std::max(16, static_cast<int>(s.width * scale + 0.5));
  s.height = std::max(16, static_cast<int>(s.height * scale + 0.5));
  s.samples = samples;
  return s;
}

std::optional<core::DetailVideo> loadVideo(const fs::path& path) {
  if (path.empty()) return std::nullopt;
  auto v = core::loadDetailVideo(path);
  if (!v) {
    std::fprintf(stderr, "puff_bench_media_sort: error: %s\n", v.error().message.c_str());
    std::exit(1);
  }
  return std::move(*v);
}

[[noreturn]] void die(const Error& e) {
  std::fprintf(stderr, "puff_bench_media_sort: error: %s\n", e.message.c_str());
  std::exit(1);
}

std::vector<Row> measureScene(const fs::path& sceneDir, const fs::path& artDir, const Case& c, double scale,
                              int samples, const reference::PhysicalOptions& physicalOptions) {
  auto loaded = scene::loadScene(sceneDir / (c.scene + ".json"), artDir);
  if (!loaded) die(loaded.error());
  if (!loaded->media) die(Error{c.scene + " has no media"});
  const scene::Scene base = asMeasured(*loaded, scale, samples);
  const std::optional<core::DetailVideo> temperature = loadVideo(base.media->temperatureDetail);
  const std::optional<core::DetailVideo> opacity = loadVideo(base.media->opacityDetail);
  const std::vector<media::Material> materials = scene::linearMediaMaterials(base);

  // One renderer per key, alive together.
  std::vector<std::unique_ptr<render::SceneRenderer>> renderers;
  for (media::SortKey key : kKeys) {
    scene::Scene s = base;
    s.media->settings.sort = key;
    auto r = render::SceneRenderer::create(s);
    if (!r) die(r.error());
    renderers.push_back(std::move(*r));
  }

  std::vector<Row> rows;
  for (int f : c.frames) {
    if (f < 0 || f >= base.animation.frames) die(Error{c.scene + ": no frame " + std::to_string(f)});
    std::vector<core::Image> gpu;
    std::vector<render::SceneRenderer::MediaFrameInputs> inputs;
    for (auto& r : renderers) {
      auto im = r->renderFrame(f);
      if (!im) die(im.error());
      gpu.push_back(std::move(*im));
      auto in = r->lastMediaFrame();
      if (!in) die(in.error());
      inputs.push_back(std::move(*in));
    }
    // The sort changes nothing but the media's order: both keys drew the same opaque layer and
    // the same particles, so one physical and one per-ray reference serve both.
    for (std::size_t k = 1; k < inputs.size(); ++k) {
      if (inputs[k].opaqueColor != inputs[0].opaqueColor || inputs[k].opaqueDepth != inputs[0].opaqueDepth ||
          inputs[k].particles.size() != inputs[0].particles.size())
        die(Error{c.scene + " frame " + std::to_string(f) + ": the keys' renders drew different opaque layers"});
    }
    reference::MediaReferenceInput ri;
    ri.frame = inputs[0].frame;
    ri.particles = inputs[0].particles;
    ri.materials = materials;
    ri.settings = base.media->settings;
    ri.temperatureDetail = temperature ? &*temperature : nullptr;
    ri.opacityDetail = opacity ? &*opacity : nullptr;
    ri.opaqueColor = inputs[0].opaqueColor;
    ri.opaqueDepth = inputs[0].opaqueDepth;
    ri.background = core::srgbToLinear(base.background);

    core::Image physicalLayer;
    reference::PhysicalReport report;
    const auto t0 = bench::Clock::now();
    auto physical = reference::renderMediaPhysical(ri, physicalOptions, &physicalLayer, &report);
    if (!physical) die(physical.error());
    std::fprintf(stderr, "%s frame %d: %zu particles, physical reference in %.1f s (step %.3g, %d halvings%s)\n",
                 c.scene.c_str(), f, inputs[0].particles.size(), bench::msSince(t0) / 1000.0, report.step,
                 report.halvings, report.converged ? "" : ", NOT converged");
    const std::vector<bool> mask = reference::mediaMask(physicalLayer);
    std::size_t mediaPixels = 0;
    for (bool m : mask) mediaPixels += m ? 1 : 0;
    auto perRay = reference::renderMediaReference(ri);
    if (!perRay) die(perRay.error());

    for (std::size_t k = 0; k < std::size(kKeys); ++k) {
      reference::MediaReferenceInput ordered = ri;
      ordered.settings.sort = kKeys[k];
      ordered.viewAxisOrder = true;
      auto order = reference::renderMediaReference(ordered);
      if (!order) die(order.error());
      Row r;
      r.scene = c.scene;
      r.key = std::string(media::toString(kKeys[k]));
      r.frame = f;
      r.width = base.width;
      r.height = base.height;
      r.samples = base.samples;
      r.particles = inputs[0].particles.size();
      r.mediaPixels = mediaPixels;
      r.gpuPhysical = errors(gpu[k], *physical, mask);
      r.gpuPerRay = errors(gpu[k], *perRay, mask);
      r.orderPerRay = errors(*order, *perRay, mask);
      r.orderPhysical = errors(*order, *physical, mask);
      r.perRayPhysical = errors(*perRay, *physical, mask);
      r.gpuOrder = reference::imageError(gpu[k], *order).rmse;
      rows.push_back(r);
    }
  }
  return rows;
}

std::vector<int> parseFrames(const char* text) {
  std::vector<int> frames;
  for (const char* p = text; *p;) {
    char* end = nullptr;
    frames.push_back(static_cast<int>(std::strtol(p, &end, 10)));
    if (end == p) break;
    p = *end == ',' ? end + 1 : end;
  }
  return frames;
}

}  // namespace

int main(int argc, char** argv) {
  puff::io::useOpenImageIO();
  fs::path artDir = PUFF_ART_DIR, sceneDir = fs::path(PUFF_SOURCE_DIR) / "art" / "scenes";
  std::string csvPath;
  double scale = 0.5;
  int samples = 4;
  reference::PhysicalOptions physical;
  std::vector<Case> cases = {
      {"explosion-walls", {5, 13, 20, 36}}, {"smoke-flythrough", {30, 48}}, {"fire-to-smoke", {48}}};
  bool ownCases = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) {
      csvPath = argv[++i];
    } else if (!std::strcmp(argv[i], "--art-dir") && i + 1 < argc) {
      artDir = argv[++i];
    } else if (!std::strcmp(argv[i], "--scale") && i + 1 < argc) {
      scale = std::clamp(std::atof(argv[++i]), 0.05, 4.0);
    } else if (!std::strcmp(argv[i], "--samples") && i + 1 < argc) {
      samples = std::clamp(std::atoi(argv[++i]), 1, 16);
    } else if (!std::strcmp(argv[i], "--tolerance") && i + 1 < argc) {
      physical.tolerance = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--scene") && i + 2 < argc) {
      if (!ownCases) cases.clear();
      ownCases = true;
      const std::string name = argv[++i];
      cases.push_back({name, parseFrames(argv[++i])});
    } else {
      std::fprintf(puff::bench::usageStream(argv[i]),
                   "usage: puff_bench_media_sort [--scale S (0.5: 320 x 240)] [--samples N (4)]\n"
                   "                             [--scene NAME FRAMES (e.g. explosion-walls 5,13) ...]\n"
                   "                             [--tolerance T (1e-4: the physical reference's)]\n"
                   "                             [--csv FILE] [--art-dir DIR]\n");
      return puff::bench::usageExit(argv[i]);
    }
  }
  auto context = core::createGlContext();
  if (!context) die(context.error());
  std::fprintf(stderr, "puff_bench_media_sort: %s\n", (*context)->describe().c_str());

  std::vector<Row> rows;
  for (const Case& c : cases) {
    std::vector<Row> r = measureScene(sceneDir, artDir, c, scale, samples, physical);
    rows.insert(rows.end(), r.begin(), r.end());
  }

  std::string csv =
      "scene,frame,width,height,samples,particles,media_pixels,key,"
      "gpu_vs_physical,gpu_vs_physical_masked,gpu_vs_per_ray,gpu_vs_per_ray_masked,"
      "order_vs_per_ray,order_vs_per_ray_masked,order_vs_physical,order_vs_physical_masked,"
      "per_ray_vs_physical,per_ray_vs_physical_masked,gpu_vs_order\n";
  for (const Row& r : rows) {
    bench::appendf(csv, "%s,%d,%d,%d,%d,%zu,%zu,%s,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n",
                   r.scene.c_str(), r.frame, r.width, r.height, r.samples, r.particles, r.mediaPixels, r.key.c_str(),
                   r.gpuPhysical.whole, r.gpuPhysical.masked, r.gpuPerRay.whole, r.gpuPerRay.masked,
                   r.orderPerRay.whole, r.orderPerRay.masked, r.orderPhysical.whole, r.orderPhysical.masked,
                   r.perRayPhysical.whole, r.perRayPhysical.masked, r.gpuOrder);
  }
  if (!bench::writeCsv("puff_bench_media_sort", csvPath, csv)) return 1;

  // The summary docs/media.md quotes: per frame, the GPU against the physical reference (whole
  // frame and media pixels) and the sort's own error (the model in the key's order against per ray,
  // media pixels), each key; and the model's own error (per ray against physical, media pixels).
  std::fprintf(stderr,
               "\n| scene, frame | media px | GPU vs physical, whole: view-depth | power-distance | media px: "
               "view-depth | power-distance | sort error, media px: view-depth | power-distance | model (per ray) vs "
               "physical, media px |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (std::size_t i = 0; i + 1 < rows.size(); i += 2) {
    const Row &a = rows[i], &b = rows[i + 1];
    std::fprintf(stderr, "| %s %d | %zu | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f |\n", a.scene.c_str(), a.frame,
                 a.mediaPixels, a.gpuPhysical.whole, b.gpuPhysical.whole, a.gpuPhysical.masked, b.gpuPhysical.masked,
                 a.orderPerRay.masked, b.orderPerRay.masked, a.perRayPhysical.masked);
  }
  return 0;
}
