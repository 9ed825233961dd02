#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include <puff/core/atlas.h>
#include <puff/core/colour.h>
#include <puff/core/detail_video.h>
#include <puff/core/number_text.h>
#include <puff/core/stopwatch.h>
#include <puff/eval/budget.h>
#include <puff/eval/cel_reference.h>
#include <puff/reference/media_physical.h>
#include <puff/reference/media_reference.h>
#include <puff/reference/metrics.h>
#include <puff/render/render.h>
#include <puff/scene/evaluate.h>
#include <puff/support/statistics.h>

namespace puff::eval {

using render::FrameStats;
using render::RenderPath;
using render::SceneRenderer;
using scene::MediaSpec;
using scene::Scene;

namespace {

using core::Clock;

using core::median;

// A resolution as the scene file writes it: 0.125, 0.25, 0.5, 1.
std::string resolutionText(float r) { return core::numberText(r); }

// An RMSE: four decimals like the other reports, two significant digits below 0.001.
std::string errorText(double e) {
  char buf[32];
  if (e >= 0.001 || e == 0.0) {
    std::snprintf(buf, sizeof buf, "%.4f", e);
  } else {
    std::snprintf(buf, sizeof buf, "%.2g", e);
  }
  return buf;
}

std::string framesText(const std::vector<int>& frames) {
  std::string s;
  for (int f : frames) s += (s.empty() ? "" : ", ") + std::to_string(f);
  return s;
}

// The cheapest candidate within the budget (candidates cheapest first), else the dearest.
template <class Candidates>
Result<MediaChoice> chooseWithin(const Candidates& candidates, double maxError, const char* what) {
  if (!(maxError > 0.0 && maxError <= 1.0)) {
    return Error{"the error budget must be an RMSE in (0, 1], got " + core::numberText(maxError)};
  }
  if (candidates.empty()) return Error{std::string("the ") + what + " budget has no measured candidates"};
  MediaChoice c;
  c.maxError = maxError;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (candidates[i].worstRmse < candidates[c.best].worstRmse) c.best = i;
  }
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (candidates[i].worstRmse <= maxError) {
      c.chosen = i;
      c.met = true;
      return c;
    }
  }
  c.chosen = candidates.size() - 1;
  return c;
}

// The scene's detail videos, loaded (none: a constant, as media::Renderer::setDetail takes nullptr).
struct Detail {
  std::optional<core::DetailVideo> temperatureVideo, opacityVideo;
  const core::DetailVideo* temperature() const { return temperatureVideo ? &*temperatureVideo : nullptr; }
  const core::DetailVideo* opacity() const { return opacityVideo ? &*opacityVideo : nullptr; }
};

Result<Detail> loadDetail(const MediaSpec& spec) {
  Detail d;
  for (auto [path, video] :
       {std::pair{&spec.temperatureDetail, &d.temperatureVideo}, std::pair{&spec.opacityDetail, &d.opacityVideo}}) {
    if (path->empty()) continue;
    PUFF_TRY_ASSIGN(*video, core::loadDetailVideo(*path));
  }
  return d;
}

// The reference of one frame: what the GPU drew it from, and the exact image in scene-linear, not
// clamped (the frames it is compared with are the renderer's scene-linear float read-back).
struct FrameReference {
  std::vector<glm::vec3> opaqueColor;
  std::vector<float> opaqueDepth;
  std::size_t particles = 0;
  core::Image image;
  core::Image physical;  // empty unless asked for
  // Where the error is counted (RegionErrors): each reference's media pixels, and the clip band of
  // the frame (the same for both: it depends on the particles, the camera and the opaque depth).
  std::vector<bool> media, mediaPhysical, band;
};

Result<FrameReference> makeReference(const Scene& scene, const SceneRenderer::MediaFrameInputs& in,
                                     const core::DetailVideo* temperature, const core::DetailVideo* opacity,
                                     bool physical = false, double* physicalMs = nullptr, bool regions = false) {
  const MediaSpec& spec = *scene.media;
  reference::MediaReferenceInput ri;
  ri.frame = in.frame;
  ri.particles = in.particles;
  const std::vector<media::Material> materials = scene::linearMediaMaterials(scene, temperature, opacity);
  ri.materials = materials;
  ri.settings = spec.settings;
  ri.temperatureDetail = temperature;
  ri.opacityDetail = opacity;
  ri.opaqueColor = in.opaqueColor;
  ri.opaqueDepth = in.opaqueDepth;
  ri.background = core::srgbToLinear(scene.background);
  core::Image layer;
  auto image = reference::renderMediaReference(ri, &layer);
  if (!image) return Error::at(scene.file, "the media reference: " + image.error().message);
  FrameReference r;
  if (regions) {
    r.media = reference::mediaMask(layer);
    r.band = reference::clipBand(in.opaqueDepth, in.particles, in.frame).band;
  }
  if (physical) {
    const auto t0 = Clock::now();
    core::Image physicalLayer;
    auto p = reference::renderMediaPhysical(ri, reference::PhysicalOptions{}, &physicalLayer);
    if (physicalMs) *physicalMs += core::millisecondsSince(t0);
    if (!p) return Error::at(scene.file, "the physical media reference: " + p.error().message);
    r.physical = std::move(*p);
    if (regions) r.mediaPhysical = reference::mediaMask(physicalLayer);
  }
  r.opaqueColor = in.opaqueColor;
  r.opaqueDepth = in.opaqueDepth;
  r.particles = in.particles.size();
  r.image = std::move(*image);
  return r;
}

bool sameInputs(const FrameReference& r, const SceneRenderer::MediaFrameInputs& in) {
  return r.particles == in.particles.size() && r.opaqueColor == in.opaqueColor && r.opaqueDepth == in.opaqueDepth;
}

Result<void> checkMediaBudget(const Scene& scene, std::span<const int> frames, const MediaBudgetOptions& options) {
  if (!scene.media) return Error::at(scene.file, "/media: the scene has no media, so no media resolution to choose");
  if (scene.media->settings.style == media::Style::kCartoon) {
    // The references are the photoreal image: a cartoon frame's distance from it measures the style.
    return Error::at(scene.file,
                     "/media/style: the media budget measures the layer against the photoreal references, which a "
                     "cartoon frame is not drawn to match; choose its resolution with \"style\": \"photoreal\" (the "
                     "cartoon's iso-line follows the same layer), or set /media/resolution by hand");
  }
  if (frames.empty() || frames.size() > 16) {
    return Error{"measuring the media budget: expected 1 to 16 frames, got " + std::to_string(frames.size())};
  }
  for (int f : frames) {
    if (f < 0 || f >= scene.animation.frames) {
      return Error::at(scene.file, "frame " + std::to_string(f) + " is outside the scene's frames 0 to " +
                                       std::to_string(scene.animation.frames - 1) + " (/animation/frames)");
    }
  }
  if (options.timedRenders < 1 || options.timedRenders > 100) {
    return Error{"measuring the media budget: timedRenders must be 1 to 100, got " +
                 std::to_string(options.timedRenders)};
  }
  return {};
}

// A frame's errors in the regions that matter, against one reference.
void addRegionErrors(const core::Image& image, const core::Image& ref, const std::vector<bool>& media,
                     const std::vector<bool>& band, RegionErrors& e) {
  e.rmseMedia.push_back(reference::imageError(image, ref, media).rmse);
  e.rmseBand.push_back(reference::imageError(image, ref, band).rmse);
  e.ssim.push_back(reference::ssim(image, ref));
}

void finishRegionErrors(RegionErrors& e) {
  if (e.ssim.empty()) return;
  e.worstRmseMedia = *std::max_element(e.rmseMedia.begin(), e.rmseMedia.end());
  e.worstRmseBand = *std::max_element(e.rmseBand.begin(), e.rmseBand.end());
  e.worstSsim = *std::min_element(e.ssim.begin(), e.ssim.end());
}

std::size_t countSet(const std::vector<bool>& mask) {
  return static_cast<std::size_t>(std::count(mask.begin(), mask.end(), true));
}

// Every resolution's error at frame f against the exact media reference, made once for all of them
// while they draw the same opaque pass.
Result<void> measureMediaErrors(const Scene& scene, const Scene& measured, int f,
                                const std::vector<std::unique_ptr<SceneRenderer>>& renderers, const Detail& detail,
                                bool physical, MediaBudget& budget) {
  std::optional<FrameReference> shared;
  for (std::size_t i = 0; i < renderers.size(); ++i) {
    PUFF_TRY_ASSIGN(auto image, renderers[i]->renderFrame(f));
    auto inputs = renderers[i]->lastMediaFrame();
    if (!inputs) return Error::at(scene.file, "frame " + std::to_string(f) + ": " + inputs.error().message);
    // Every resolution draws the same opaque pass; should one ever differ, it gets its own reference.
    std::optional<FrameReference> own;
    if (!shared || !sameInputs(*shared, *inputs)) {
      const auto t0 = Clock::now();
      auto ref = makeReference(measured, *inputs, detail.temperature(), detail.opacity(), physical, &budget.physicalMs,
                               /*regions=*/true);
      budget.referenceMs += core::millisecondsSince(t0);
      if (!ref) return ref.error();
      if (!shared) {
        shared = std::move(*ref);
        budget.mediaPixels.push_back(countSet(shared->media));
        budget.bandPixels.push_back(countSet(shared->band));
        if (physical) budget.mediaPixelsPhysical.push_back(countSet(shared->mediaPhysical));
      } else {
        own = std::move(*ref);
      }
    }
    const FrameReference& ref = own ? *own : *shared;
    MediaCandidate& c = budget.candidates[i];
    c.rmse.push_back(reference::imageError(image, ref.image).rmse);
    addRegionErrors(image, ref.image, ref.media, ref.band, c.regions);
    if (physical) {
      c.rmsePhysical.push_back(reference::imageError(image, ref.physical).rmse);
      addRegionErrors(image, ref.physical, ref.mediaPhysical, ref.band, c.regionsPhysical);
    }
  }
  return {};
}

}  // namespace

Result<core::Image> mediaReference(const Scene& scene, const SceneRenderer& renderer) {
  if (!scene.media) return Error::at(scene.file, "/media: the scene has no media");
  PUFF_TRY_ASSIGN(auto in, renderer.lastMediaFrame());
  PUFF_TRY_ASSIGN(auto detail, loadDetail(*scene.media));
  PUFF_TRY_ASSIGN(auto ref, makeReference(scene, in, detail.temperature(), detail.opacity()));
  return std::move(ref.image);
}

std::vector<int> budgetFrames(int first, int last) {
  PUFF_CHECK(first >= 0 && first <= last);
  std::vector<int> frames{first, first + (last - first + 1) / 2, last};
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  return frames;
}

Result<MediaBudget> measureMediaBudget(const Scene& scene, std::span<const int> frames,
                                       const MediaBudgetOptions& options) {
  PUFF_TRY(checkMediaBudget(scene, frames, options));

  // What the reference does not model is left out of the renders measured (budget.h).
  Scene measured = scene;
  measured.media->lights.clear();
  measured.media->compose.shimmerPixels = 0.0f;
  measured.media->motionBlurFrames = 0;

  PUFF_TRY_ASSIGN(auto detail, loadDetail(*scene.media));

  MediaBudget budget;
  budget.frames.assign(frames.begin(), frames.end());
  std::sort(budget.frames.begin(), budget.frames.end());
  budget.frames.erase(std::unique(budget.frames.begin(), budget.frames.end()), budget.frames.end());

  // One renderer per resolution, all alive at once, so the timed renders can take turns and any
  // change in the machine's load falls on every resolution alike.
  std::vector<std::unique_ptr<SceneRenderer>> renderers;
  for (float r : kMediaResolutions) {
    measured.media->resolution = r;
    PUFF_TRY_ASSIGN(auto renderer, SceneRenderer::create(measured));
    renderers.push_back(std::move(renderer));
    MediaCandidate c;
    c.resolution = r;
    budget.candidates.push_back(c);
  }
  std::vector<std::vector<double>> times(renderers.size());

  const int steps = static_cast<int>(budget.frames.size());
  int done = 0;
  if (options.progress) options.progress(0, steps);
  for (int f : budget.frames) {
    PUFF_TRY(measureMediaErrors(scene, measured, f, renderers, detail, options.physical, budget));
    for (int k = 0; k < options.timedRenders; ++k) {
      for (std::size_t i = 0; i < renderers.size(); ++i) {
        const auto t0 = Clock::now();
        auto image = renderers[i]->renderFrame(f);
        times[i].push_back(core::millisecondsSince(t0));
        if (!image) return image.error();
      }
    }
    if (options.progress) options.progress(++done, steps);
  }
  for (std::size_t i = 0; i < budget.candidates.size(); ++i) {
    MediaCandidate& c = budget.candidates[i];
    c.worstRmse = *std::max_element(c.rmse.begin(), c.rmse.end());
    if (!c.rmsePhysical.empty()) c.worstRmsePhysical = *std::max_element(c.rmsePhysical.begin(), c.rmsePhysical.end());
    finishRegionErrors(c.regions);
    finishRegionErrors(c.regionsPhysical);
    c.medianMs = median(times[i]);
  }
  return budget;
}

Result<MediaChoice> chooseMediaResolution(const MediaBudget& budget, double maxError) {
  return chooseWithin(budget.candidates, maxError, "media");
}

std::string budgetTable(const MediaBudget& budget, const MediaChoice& choice) {
  // The worst over the measured frames of each figure; the choice reads the first column only.
  const bool physical = !budget.candidates.empty() && !budget.candidates.front().rmsePhysical.empty();
  std::string s = "  resolution  worst RMSE";
  if (physical) s += "  vs physical";
  s += "  media RMSE   band RMSE    SSIM  median ms\n";
  for (std::size_t i = 0; i < budget.candidates.size(); ++i) {
    const MediaCandidate& c = budget.candidates[i];
    char line[192];
    std::snprintf(line, sizeof line, "  %10s  %10s", resolutionText(c.resolution).c_str(),
                  errorText(c.worstRmse).c_str());
    s += line;
    if (physical) {
      std::snprintf(line, sizeof line, "  %11s", errorText(c.worstRmsePhysical).c_str());
      s += line;
    }
    std::snprintf(line, sizeof line, "  %10s  %10s  %6.4f  %9.1f%s\n", errorText(c.regions.worstRmseMedia).c_str(),
                  errorText(c.regions.worstRmseBand).c_str(), c.regions.worstSsim, c.medianMs,
                  i == choice.chosen ? "  <- chosen" : "");
    s += line;
  }
  return s;
}

std::string budgetSummary(const MediaBudget& budget, const MediaChoice& choice) {
  PUFF_CHECK(choice.chosen < budget.candidates.size() && choice.best < budget.candidates.size());
  const std::string maxError = core::numberText(choice.maxError);
  const MediaCandidate& c = budget.candidates[choice.chosen];
  std::string s = "--max-error " + maxError + ": media resolution " + resolutionText(c.resolution);
  const std::string frames = (budget.frames.size() == 1 ? "frame " : "frames ") + framesText(budget.frames);
  if (!choice.met) {
    const MediaCandidate& b = budget.candidates[choice.best];
    return s + ", the dearest (no resolution meets it: the smallest worst RMSE is " + errorText(b.worstRmse) + ", at " +
           resolutionText(b.resolution) + ", over " + frames + ")";
  }
  s += " (worst RMSE " + errorText(c.worstRmse) + " over " + frames;
  if (choice.chosen > 0) {
    // Why not cheaper: the next cheaper one misses.
    const MediaCandidate& cheaper = budget.candidates[choice.chosen - 1];
    s += "; " + resolutionText(cheaper.resolution) + " misses with " + errorText(cheaper.worstRmse);
  } else {
    s += "; the cheapest";
  }
  if (choice.chosen + 1 < budget.candidates.size()) {
    // Why not dearer: what it would cost.
    const MediaCandidate& dearer = budget.candidates[choice.chosen + 1];
    char ratio[64];
    if (c.medianMs > 0.0) {
      std::snprintf(ratio, sizeof ratio, "%.1fx as much", dearer.medianMs / c.medianMs);
    } else {
      std::snprintf(ratio, sizeof ratio, "more");
    }
    s += "; " + resolutionText(dearer.resolution) + " would cost " + ratio;
  }
  return s + ")";
}

std::string budgetWarning(const MediaBudget& budget, const MediaChoice& choice) {
  if (choice.met) return {};
  PUFF_CHECK(choice.chosen < budget.candidates.size() && choice.best < budget.candidates.size());
  const std::string maxError = core::numberText(choice.maxError);
  const MediaCandidate& b = budget.candidates[choice.best];
  return "--max-error " + maxError + " cannot be met: the smallest worst RMSE measured is " + errorText(b.worstRmse) +
         " (media resolution " + resolutionText(b.resolution) + "); rendering at " +
         resolutionText(budget.candidates[choice.chosen].resolution);
}

namespace {

std::string fractionText(float f) {
  if (f >= 1.0f) return "1";
  char buf[16];
  std::snprintf(buf, sizeof buf, "1/%d", static_cast<int>(std::lround(1.0 / f)));
  return buf;
}

// What a candidate is, for people: "atlas level 2 (64-texel cells)" or "particles 1/4 (1052)".
std::string candidateText(const CelBudget& b, const CelCandidate& c) {
  if (b.knob == CelKnob::kShadows) {
    if (c.shadowMethod == cel::ShadowMethod::kVolumes) return "shadow volumes";
    char buf[64];
    std::snprintf(buf, sizeof buf, "shadow map at scale %g", static_cast<double>(c.shadowMapScale));
    return buf;
  }
  if (b.knob == CelKnob::kTumble) {
    if (c.tumble == cel::TumbleMethod::kBlend) return "the blend on every oriented puff";
    if (c.hullFromPixels <= 0.0f) return "the hull on every oriented puff";
    return "the hull from " + core::numberText(c.hullFromPixels) + " px";
  }
  if (b.knob == CelKnob::kAtlasLevel) {
    return "atlas level " + std::to_string(c.atlasLevel) + " (" + std::to_string(c.cellSize) + "-texel cells)";
  }
  return "particles " + fractionText(c.particleFraction) + " (" + std::to_string(c.particles) + ")";
}

std::string megabytes(std::size_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f MB", static_cast<double>(bytes) / (1024.0 * 1024.0));
  return buf;
}

Result<void> checkCelBudget(const Scene& scene, std::span<const int> frames, const CelBudgetOptions& options,
                            CelKnob knob) {
  if (scene.atlas.empty()) return Error::at(scene.file, "/atlas: the scene has no atlas, so no cel model to choose");
  if (scene.particles.empty() && scene.emitters.empty() && !(scene.simulation && !scene.simulation->emitters.empty()))
    return Error::at(scene.file, "the scene has no cel particles, so no cel model to choose");
  if (knob == CelKnob::kParticleFraction && scene.emitters.empty())
    return Error::at(scene.file, "/emitters: the scene places no particles, so no particle count to choose");
  if (knob == CelKnob::kShadows && !scene.style.shadows)
    return Error::at(scene.file, "/style/shadows: the scene has no shadows, so no shadow method to choose");
  if (knob == CelKnob::kTumble && scene::orientedPuffs(scene).empty())
    return Error::at(scene.file, "the scene has no oriented puffs, so no tumble method to choose");
  if (frames.empty() || frames.size() > 16)
    return Error{"measure 1 to 16 frames, got " + std::to_string(frames.size())};
  for (int f : frames) {
    if (f < 0 || f >= scene.animation.frames)
      return Error{"frame " + std::to_string(f) + " is not in the scene (0.." +
                   std::to_string(scene.animation.frames - 1) + ")"};
  }
  if (options.timedRenders < 1 || options.timedRenders > 100)
    return Error{"timed renders must be in [1, 100], got " + std::to_string(options.timedRenders)};
  return {};
}

// The reference: the full model (every particle), whatever the scene asks for.
Result<void> celReferences(const Scene& s, std::span<const core::Image> reuse, CelBudget& budget) {
  std::vector<core::Image>& references = budget.references;
  if (!reuse.empty()) {
    if (reuse.size() != budget.frames.size() || reuse[0].width != s.width || reuse[0].height != s.height)
      return Error{"the references to reuse are not of these frames at the scene's size"};
    references.assign(reuse.begin(), reuse.end());
  } else {
    const auto t0 = Clock::now();
    Scene full = s;
    full.particleFraction = 1.0f;
    PUFF_TRY_ASSIGN(auto ref, createCelReference(full));
    for (int f : budget.frames) {
      PUFF_TRY_ASSIGN(auto image, (ref)->renderFrame(f));
      references.push_back(std::move(image));
    }
    budget.referenceMs = core::millisecondsSince(t0);
  }
  return {};
}

// The scenes to measure: each atlas level from the deepest with cells of 16 texels or more, or
// each particle fraction.
std::vector<Scene> celCandidates(const Scene& s, const core::AtlasDesc& desc, CelKnob knob) {
  std::vector<Scene> candidates;
  if (knob == CelKnob::kAtlasLevel) {
    int deepest = core::deepestAtlasLevel(desc);
    while (deepest > 0 && (desc.cellSize >> deepest) < 16) --deepest;
    for (int level = deepest; level >= 0; --level) {
      candidates.push_back(s);
      candidates.back().atlasLevel = level;
    }
  } else if (knob == CelKnob::kShadows) {
    for (float scale : kShadowMapScales) {
      candidates.push_back(s);
      candidates.back().style.shadowMethod = cel::ShadowMethod::kMap;
      candidates.back().style.shadowMapScale = scale;
    }
    candidates.push_back(s);
    candidates.back().style.shadowMethod = cel::ShadowMethod::kVolumes;
  } else if (knob == CelKnob::kTumble) {
    candidates.push_back(s);
    candidates.back().style.tumble = cel::TumbleMethod::kBlend;
    for (float from : kHullFromPixels) {
      candidates.push_back(s);
      candidates.back().style.tumble = cel::TumbleMethod::kHull;
      candidates.back().style.hullFromPixels = from;
    }
    candidates.push_back(s);
    candidates.back().style.tumble = cel::TumbleMethod::kHull;
    candidates.back().style.hullFromPixels = 0.0f;
  } else {
    for (float f : kParticleFractions) {
      candidates.push_back(s);
      candidates.back().particleFraction = f;
    }
  }
  return candidates;
}

// One candidate: its atlas's size, its error at each frame against the reference, its time.
Result<CelCandidate> measureCelCandidate(const Scene& c, const core::AtlasDesc& desc, const CelBudget& budget,
                                         const CelBudgetOptions& options) {
  PUFF_TRY_ASSIGN(auto r, SceneRenderer::create(c));
  CelCandidate cand;
  cand.atlasLevel = c.atlasLevel;
  cand.particleFraction = c.particleFraction;
  cand.shadowMethod = c.style.shadowMethod;
  cand.shadowMapScale = c.style.shadowMapScale;
  cand.tumble = c.style.tumble;
  cand.hullFromPixels = c.style.hullFromPixels;
  cand.cellSize = desc.cellSize >> c.atlasLevel;
  core::AtlasDesc reduced = desc;
  reduced.width = std::max(1, desc.width >> c.atlasLevel);
  reduced.height = std::max(1, desc.height >> c.atlasLevel);
  reduced.mipLevels = desc.mipLevels - c.atlasLevel;
  cand.atlasBytes = core::atlasTextureBytes(reduced);
  std::vector<double> times;
  for (std::size_t i = 0; i < budget.frames.size(); ++i) {
    FrameStats stats;
    PUFF_TRY_ASSIGN(auto image, (r)->renderFrame(budget.frames[i], &stats));
    cand.particles = std::max(cand.particles, stats.particles);
    // Cel shading is a display palette operation (docs/colour.md): its error is measured on what the
    // screen shows, both frames through the standard view transform.
    cand.rmse.push_back(reference::imageError(core::viewTransform(image, core::ViewTransform::kStandard),
                                              core::viewTransform(budget.references[i], core::ViewTransform::kStandard))
                            .rmse);
    for (int k = 0; k < options.timedRenders; ++k) {
      const auto t0 = Clock::now();
      if (auto again = (r)->renderFrame(budget.frames[i]); !again) return again.error();
      times.push_back(core::millisecondsSince(t0));
    }
  }
  cand.worstRmse = *std::max_element(cand.rmse.begin(), cand.rmse.end());
  cand.medianMs = median(times);
  return cand;
}

}  // namespace

Result<CelBudget> measureCelBudget(const Scene& scene, std::span<const int> frames, const CelBudgetOptions& options,
                                   CelKnob knob, std::span<const core::Image> reuse) {
  PUFF_TRY(checkCelBudget(scene, frames, options, knob));
  PUFF_TRY_ASSIGN(auto desc, core::loadAtlasDesc(scene.atlas));
  Scene s = scene;
  s.media.reset();
  CelBudget budget;
  budget.knob = knob;
  budget.frames.assign(frames.begin(), frames.end());
  std::sort(budget.frames.begin(), budget.frames.end());

  const std::vector<Scene> candidates = celCandidates(s, desc, knob);
  // Steps: the references (one, however many frames), then each candidate.
  const int steps = 1 + static_cast<int>(candidates.size());
  if (options.progress) options.progress(0, steps);
  PUFF_TRY(celReferences(s, reuse, budget));
  if (options.progress) options.progress(1, steps);
  for (const Scene& c : candidates) {
    PUFF_TRY_ASSIGN(auto cand, measureCelCandidate(c, desc, budget, options));
    budget.candidates.push_back(std::move(cand));
    if (options.progress) options.progress(1 + static_cast<int>(budget.candidates.size()), steps);
  }
  if (knob == CelKnob::kShadows) {
    // No order of cost is known beforehand (the volumes' fill against the map's passes): the measured one.
    std::stable_sort(budget.candidates.begin(), budget.candidates.end(),
                     [](const CelCandidate& a, const CelCandidate& b) { return a.medianMs < b.medianMs; });
  }
  return budget;
}

Result<MediaChoice> chooseCelBudget(const CelBudget& budget, double maxError) {
  auto choice = chooseWithin(budget.candidates, maxError,
                             budget.knob == CelKnob::kAtlasLevel ? "atlas"
                             : budget.knob == CelKnob::kShadows  ? "shadow"
                             : budget.knob == CelKnob::kTumble   ? "tumble"
                                                                 : "particle");
  if (choice && !choice->met && (budget.knob == CelKnob::kShadows || budget.knob == CelKnob::kTumble))
    choice->chosen = choice->best;
  return choice;
}

std::string celBudgetTable(const CelBudget& budget, const MediaChoice& choice) {
  const bool atlas = budget.knob == CelKnob::kAtlasLevel;
  const bool shadows = budget.knob == CelKnob::kShadows || budget.knob == CelKnob::kTumble;  // one label each
  const int label = budget.knob == CelKnob::kTumble ? 32 : 26;
  std::string s = budget.knob == CelKnob::kTumble ? "  oriented puffs                    worst RMSE  median ms\n"
                  : shadows                       ? "  shadows                     worst RMSE  median ms\n"
                  : atlas                         ? "  atlas level  cell texels  atlas MB  worst RMSE  median ms\n"
                                                  : "   particles       count  worst RMSE  median ms\n";
  for (std::size_t i = 0; i < budget.candidates.size(); ++i) {
    const CelCandidate& c = budget.candidates[i];
    char line[160];
    if (shadows) {
      std::snprintf(line, sizeof line, "  %-*s  %10s  %9.1f%s\n", label, candidateText(budget, c).c_str(),
                    errorText(c.worstRmse).c_str(), c.medianMs, i == choice.chosen ? "  <- chosen" : "");
    } else if (atlas) {
      std::snprintf(line, sizeof line, "  %11d  %11d  %8.2f  %10s  %9.1f%s\n", c.atlasLevel, c.cellSize,
                    static_cast<double>(c.atlasBytes) / (1024.0 * 1024.0), errorText(c.worstRmse).c_str(), c.medianMs,
                    i == choice.chosen ? "  <- chosen" : "");
    } else {
      std::snprintf(line, sizeof line, "  %10s  %10zu  %10s  %9.1f%s\n", fractionText(c.particleFraction).c_str(),
                    c.particles, errorText(c.worstRmse).c_str(), c.medianMs, i == choice.chosen ? "  <- chosen" : "");
    }
    s += line;
  }
  return s;
}

std::string celBudgetSummary(const CelBudget& budget, const MediaChoice& choice) {
  PUFF_CHECK(choice.chosen < budget.candidates.size() && choice.best < budget.candidates.size());
  const bool atlas = budget.knob == CelKnob::kAtlasLevel;
  const std::string maxError = core::numberText(choice.maxError);
  const CelCandidate& c = budget.candidates[choice.chosen];
  std::string s = "--max-error " + maxError + ": " + candidateText(budget, c);
  const std::string frames = (budget.frames.size() == 1 ? "frame " : "frames ") + framesText(budget.frames);
  if (budget.knob == CelKnob::kShadows || budget.knob == CelKnob::kTumble) {
    // Candidates are in the order of their measured time (shadows) or of how many puffs take the hull
    // (tumble): the chosen one is the first within it.
    if (!choice.met) {
      return s + " (none meets it: the closest to the cel reference, RMSE " + errorText(c.worstRmse) + " over " +
             frames + ")";
    }
    char ms[64];
    std::snprintf(ms, sizeof ms, ", %.1f ms a frame", c.medianMs);
    s += ": worst RMSE " + errorText(c.worstRmse) + " against the cel reference over " + frames + ms;
    if (budget.knob == CelKnob::kTumble) {
      s += choice.chosen == 0 ? "; the least of the hull" : "; every one with less of the hull misses";
    } else {
      s += choice.chosen == 0 ? "; the fastest measured" : "; every faster one misses";
    }
    const CelCandidate& closest = budget.candidates[choice.best];
    if (choice.best != choice.chosen) {
      std::snprintf(ms, sizeof ms, " (%.1f ms)", closest.medianMs);
      s += "; the closest is " + candidateText(budget, closest) + " with " + errorText(closest.worstRmse) + ms;
    }
    return s;
  }
  if (!choice.met) {
    const CelCandidate& b = budget.candidates[choice.best];
    return s + (atlas ? ", the largest" : ", all of them") + " (none meets it: the smallest worst RMSE against the " +
           "cel reference is " + errorText(b.worstRmse) + ", with " + candidateText(budget, b) + ", over " + frames +
           ")";
  }
  s += ": worst RMSE " + errorText(c.worstRmse) + " against the cel reference over " + frames;
  if (atlas) s += ", atlas " + megabytes(c.atlasBytes);
  if (choice.chosen > 0) {
    const CelCandidate& cheaper = budget.candidates[choice.chosen - 1];
    s += "; " + candidateText(budget, cheaper) + " misses with " + errorText(cheaper.worstRmse);
  } else {
    s += "; the cheapest measured";
  }
  const CelCandidate& full = budget.candidates.back();
  if (choice.chosen + 1 < budget.candidates.size()) {
    char more[160];
    if (atlas) {
      std::snprintf(more, sizeof more, "; the full atlas (level 0) takes %s, %.0fx as much, for RMSE %s",
                    megabytes(full.atlasBytes).c_str(),
                    c.atlasBytes > 0 ? static_cast<double>(full.atlasBytes) / static_cast<double>(c.atlasBytes) : 0.0,
                    errorText(full.worstRmse).c_str());
    } else {
      std::snprintf(more, sizeof more,
                    "; all the particles would cost %.1fx as much (%.1f ms against %.1f) for RMSE %s",
                    c.medianMs > 0.0 ? full.medianMs / c.medianMs : 0.0, full.medianMs, c.medianMs,
                    errorText(full.worstRmse).c_str());
    }
    s += more;
  }
  return s;
}

std::string celBudgetWarning(const CelBudget& budget, const MediaChoice& choice) {
  if (choice.met) return {};
  PUFF_CHECK(choice.chosen < budget.candidates.size() && choice.best < budget.candidates.size());
  const std::string maxError = core::numberText(choice.maxError);
  const CelCandidate& b = budget.candidates[choice.best];
  return "--max-error " + maxError + " cannot be met by the nailboards: the smallest worst RMSE " +
         "against the cel reference is " + errorText(b.worstRmse) + " (" + candidateText(budget, b) +
         "); rendering with " + candidateText(budget, budget.candidates[choice.chosen]);
}

}  // namespace puff::eval
