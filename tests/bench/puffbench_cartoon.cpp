// puffbench's cartoon part: the cartoon media style against the photoreal one on the same
// scenes. Per scene and style:
//  - cost: the median frame time over the budget's frames, and the frame without media particles
//    (what both pay before the media): the media's own cost is ms - bareMs;
//  - stability: second differences of consecutive display frames (bands and ink must not flicker);
//  - the ink against the references: the GPU's fill mask (A >= threshold at the output's size, the
//    field the ink is drawn from) against the model reference's (reference::renderMediaReference:
//    the renderer's per-sphere model, computed independently on the CPU) and the physical
//    reference's (reference::renderMediaPhysical: the summed density fields) opacity masks at the
//    same threshold, with every material's burn set to 0 (the cartoon ignores burn).
// Not a test: nothing fails here. Frame times are wall-clock medians after an untimed render.
#include "puffbench_cartoon.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <puff/core/colour.h>
#include <puff/core/detail_video.h>
#include <puff/reference/media_physical.h>
#include <puff/reference/media_reference.h>
#include <puff/render/render.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>

#include "harness.h"
#include "puffbench_cel.h"

namespace puffbench {

namespace {

namespace fs = std::filesystem;
using namespace puff;
using bench::Clock;

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// Second differences of a display sequence (each image RGBA, same size): mean, 99th percentile of
// the largest channel's |x(t+1) - 2 x(t) + x(t-1)|, and the share of flickers.
void stability(const std::vector<core::Image>& seq, CartoonRow& row) {
  std::vector<double> d2;
  std::size_t flickers = 0, samples = 0;
  for (std::size_t t = 1; t + 1 < seq.size(); ++t) {
    const core::Image &a = seq[t - 1], &b = seq[t], &c = seq[t + 1];
    for (int y = 0; y < b.height; ++y) {
      for (int x = 0; x < b.width; ++x) {
        double worst = 0.0;
        bool step = false, undone = true;
        for (int ch = 0; ch < 3; ++ch) {
          const double s1 = b.at(x, y, ch) - a.at(x, y, ch), s2 = c.at(x, y, ch) - b.at(x, y, ch);
          worst = std::max(worst, std::abs(s2 - s1));
          // A blip: a step of more than 0.1 that the next frame undoes, every channel back within
          // 0.02. An edge passing (scene, then ink, then fill) changes a pixel twice, but the fill
          // is not the scene it covered.
          step = step || std::abs(s1) > 0.1;
          undone = undone && std::abs(s1 + s2) <= 0.02;
        }
        const bool flicker = step && undone;
        d2.push_back(worst);
        flickers += flicker;
        ++samples;
      }
    }
  }
  double sum = 0.0;
  for (double v : d2) sum += v;
  row.d2Mean = d2.empty() ? 0.0 : sum / static_cast<double>(d2.size());
  row.d2P99 = percentile(d2, 0.99);
  row.flickerShare = samples ? static_cast<double>(flickers) / static_cast<double>(samples) : 0.0;
}

// The mask's iso-line pixels: inside pixels with an outside 4-neighbour.
std::vector<glm::ivec2> edgePixels(const std::vector<bool>& mask, int w, int h) {
  std::vector<glm::ivec2> out;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!mask[static_cast<std::size_t>(y) * w + x]) continue;
      const bool edge = (x > 0 && !mask[static_cast<std::size_t>(y) * w + x - 1]) ||
                        (x + 1 < w && !mask[static_cast<std::size_t>(y) * w + x + 1]) ||
                        (y > 0 && !mask[static_cast<std::size_t>(y - 1) * w + x]) ||
                        (y + 1 < h && !mask[static_cast<std::size_t>(y + 1) * w + x]);
      if (edge) out.push_back({x, y});
    }
  }
  return out;
}

// Distances from each of `from`'s points to the nearest of `to`'s (brute force: the iso-lines are a
// few thousand pixels at the bench's sizes).
std::vector<double> nearestDistances(const std::vector<glm::ivec2>& from, const std::vector<glm::ivec2>& to) {
  std::vector<double> out;
  for (const glm::ivec2& p : from) {
    double best = std::numeric_limits<double>::infinity();
    for (const glm::ivec2& q : to) best = std::min(best, glm::length(glm::dvec2(p - q)));
    out.push_back(best);
  }
  return out;
}

struct IsoAgreement {
  double iou = 0.0, meanPx = 0.0, p95Px = 0.0;
};

IsoAgreement agreement(const std::vector<bool>& a, const std::vector<bool>& b, int w, int h) {
  IsoAgreement r;
  std::size_t both = 0, either = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    both += a[i] && b[i];
    either += a[i] || b[i];
  }
  r.iou = either ? static_cast<double>(both) / static_cast<double>(either) : 1.0;
  const auto ea = edgePixels(a, w, h), eb = edgePixels(b, w, h);
  std::vector<double> d = nearestDistances(ea, eb);
  const std::vector<double> back = nearestDistances(eb, ea);
  d.insert(d.end(), back.begin(), back.end());
  double sum = 0.0;
  for (double v : d) sum += v;
  r.meanPx = d.empty() ? 0.0 : sum / static_cast<double>(d.size());
  r.p95Px = percentile(d, 0.95);
  return r;
}

// The reference's opacity mask at `threshold` from its layer (alpha = T), flipped to row 0 at the
// bottom as the GPU's field is.
std::vector<bool> referenceMask(const core::Image& layer, double threshold) {
  std::vector<bool> m(static_cast<std::size_t>(layer.width) * layer.height);
  for (int y = 0; y < layer.height; ++y)
    for (int x = 0; x < layer.width; ++x)
      m[static_cast<std::size_t>(layer.height - 1 - y) * layer.width + x] = 1.0 - layer.at(x, y, 3) >= threshold;
  return m;
}

Result<void> measureIso(const scene::Scene& s, std::span<const int> frames, CartoonRow& row) {
  PUFF_TRY_ASSIGN(auto r, render::SceneRenderer::create(s));
  std::optional<core::DetailVideo> temperature, opacity;
  if (!s.media->temperatureDetail.empty()) {
    PUFF_TRY_ASSIGN(auto v, core::loadDetailVideo(s.media->temperatureDetail));
    temperature = std::move(v);
  }
  if (!s.media->opacityDetail.empty()) {
    PUFF_TRY_ASSIGN(auto v, core::loadDetailVideo(s.media->opacityDetail));
    opacity = std::move(v);
  }
  std::vector<media::Material> materials = scene::linearMediaMaterials(s);
  for (media::Material& m : materials) m.burn = 0.0f;  // the cartoon's A ignores burn
  const double theta = s.media->settings.cartoon.threshold;
  IsoAgreement model, physical;
  for (int f : frames) {
    if (auto im = (r)->renderFrame(f); !im) return im.error();
    PUFF_TRY_ASSIGN(auto in, (r)->lastMediaFrame());
    if (in.cartoonOpacity.empty()) return Error{s.file.string() + ": no cartoon field was read back"};
    std::vector<bool> gpu(in.cartoonOpacity.size());
    for (std::size_t i = 0; i < gpu.size(); ++i) gpu[i] = in.cartoonOpacity[i] >= theta;
    reference::MediaReferenceInput ri;
    ri.frame = in.frame;
    ri.particles = in.particles;
    ri.materials = materials;
    ri.settings = s.media->settings;
    ri.temperatureDetail = temperature ? &*temperature : nullptr;
    ri.opacityDetail = opacity ? &*opacity : nullptr;
    ri.opaqueColor = in.opaqueColor;
    ri.opaqueDepth = in.opaqueDepth;
    core::Image layer, physicalLayer;
    if (auto m = reference::renderMediaReference(ri, &layer); !m) return m.error();
    if (auto p = reference::renderMediaPhysical(ri, reference::PhysicalOptions{}, &physicalLayer); !p) return p.error();
    const IsoAgreement a = agreement(gpu, referenceMask(layer, theta), s.width, s.height);
    const IsoAgreement b = agreement(gpu, referenceMask(physicalLayer, theta), s.width, s.height);
    // The worst frame's IoU, and the distances' largest mean and 95th percentile.
    const bool first = f == frames.front();
    model.iou = first ? a.iou : std::min(model.iou, a.iou);
    model.meanPx = std::max(model.meanPx, a.meanPx);
    model.p95Px = std::max(model.p95Px, a.p95Px);
    physical.iou = first ? b.iou : std::min(physical.iou, b.iou);
    physical.meanPx = std::max(physical.meanPx, b.meanPx);
    physical.p95Px = std::max(physical.p95Px, b.p95Px);
  }
  row.iouModel = model.iou, row.meanPxModel = model.meanPx, row.p95PxModel = model.p95Px;
  row.iouPhysical = physical.iou, row.meanPxPhysical = physical.meanPx, row.p95PxPhysical = physical.p95Px;
  return {};
}

}  // namespace

Result<std::vector<CartoonRow>> runCartoonBench(const CartoonBenchOptions& opt) {
  std::vector<CartoonRow> rows;
  const auto start = Clock::now();
  auto log = [&](const std::string& what) {
    std::fprintf(stderr, "puffbench: cartoon: %s (%.1f s)\n", what.c_str(),
                 std::chrono::duration<double>(Clock::now() - start).count());
  };
  for (const std::string& name : opt.scenes) {
    PUFF_TRY_ASSIGN(auto loaded, scene::loadScene(opt.sceneDir / (name + ".json"), opt.artDir));
    if (!loaded.media || loaded.media->settings.style != media::Style::kCartoon)
      return Error{name + ": not a cartoon media scene (media.style \"cartoon\")"};
    scene::Scene cartoon = loaded;
    cartoon.width = opt.width;
    cartoon.height = opt.height;
    cartoon.media->motionBlurFrames = 0;
    const int last = cartoon.animation.frames - 1;
    const std::vector<int> timed = {last / 4, last / 2, 3 * last / 4};
    double photorealBare = 0.0;
    for (media::Style style : {media::Style::kPhotoreal, media::Style::kCartoon}) {
      scene::Scene s = cartoon;
      s.media->settings.style = style;
      CartoonRow row;
      row.scene = name;
      row.style = std::string(media::toString(style));
      row.width = opt.width;
      row.height = opt.height;
      PUFF_TRY_ASSIGN(auto timedFrames, renderFrames(s, render::RenderPath::kCel, timed, opt.reps));
      row.ms = timedFrames.ms;
      scene::Scene bare = s;
      bare.media->particles.clear();
      bare.media->emitters.clear();
      PUFF_TRY_ASSIGN(auto bareFrames, renderFrames(bare, render::RenderPath::kCel, timed, opt.reps));
      row.emptyMs = bareFrames.ms;
      if (style == media::Style::kPhotoreal) photorealBare = bareFrames.ms;
      row.bareMs = photorealBare;
      log(name + ", " + row.style + ": timed");
      // Stability: consecutive frames around the middle, display values.
      std::vector<int> seq;
      const int from = std::max(0, last / 2 - opt.sequenceFrames / 2);
      for (int f = from; f <= std::min(last, from + opt.sequenceFrames - 1); ++f) seq.push_back(f);
      PUFF_TRY_ASSIGN(auto frames, renderFrames(s, render::RenderPath::kCel, seq, 0));
      std::vector<core::Image> display;
      for (const core::Image& im : frames.images)
        display.push_back(core::viewTransform(im, scene::viewTransformFor(s)));
      stability(display, row);
      log(name + ", " + row.style + ": " + std::to_string(seq.size()) + " frames' stability");
      if (style == media::Style::kCartoon) {
        const std::vector<int> iso(timed.begin(), timed.begin() + std::min<std::size_t>(timed.size(), opt.isoFrames));
        PUFF_TRY(measureIso(s, iso, row));
        log(name + ": the ink against the references");
      } else {
        row.iouModel = row.meanPxModel = row.p95PxModel = std::numeric_limits<double>::quiet_NaN();
        row.iouPhysical = row.meanPxPhysical = row.p95PxPhysical = std::numeric_limits<double>::quiet_NaN();
      }
      rows.push_back(row);
    }
  }
  return rows;
}

std::string cartoonCsv(const std::vector<CartoonRow>& rows) {
  std::string csv =
      "scene,style,width,height,median_ms,bare_ms,empty_ms,media_ms,media_ratio_to_photoreal,d2_mean,d2_p99,"
      "flicker_share,"
      "iou_model,iso_mean_px_model,iso_p95_px_model,iou_physical,iso_mean_px_physical,iso_p95_px_physical\n";
  for (const CartoonRow& r : rows) {
    double photoreal = 0.0;
    for (const CartoonRow& o : rows)
      if (o.scene == r.scene && o.style == "photoreal") photoreal = o.ms - o.bareMs;
    const double media = r.ms - r.bareMs;
    auto num = [](double v) {
      if (std::isnan(v)) return std::string();
      char b[32];
      std::snprintf(b, sizeof b, "%.4f", v);
      return std::string(b);
    };
    bench::appendf(csv, "%s,%s,%d,%d,%.3f,%.3f,%.3f,%.3f,%s,%.5f,%.5f,%.6f,%s,%s,%s,%s,%s,%s\n", r.scene.c_str(),
                   r.style.c_str(), r.width, r.height, r.ms, r.bareMs, r.emptyMs, media,
                   photoreal > 0.0 ? num(media / photoreal).c_str() : "", r.d2Mean, r.d2P99, r.flickerShare,
                   num(r.iouModel).c_str(), num(r.meanPxModel).c_str(), num(r.p95PxModel).c_str(),
                   num(r.iouPhysical).c_str(), num(r.meanPxPhysical).c_str(), num(r.p95PxPhysical).c_str());
  }
  return csv;
}

}  // namespace puffbench
