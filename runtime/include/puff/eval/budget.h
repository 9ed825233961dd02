// Just enough model: for a scene and some of its frames, measure what each candidate model costs
// and how far its image lies from a reference, then pick the cheapest within an error budget.
// Media: the layer resolution against the exact media image (puff::reference). Cel: the particle
// count and the atlas level against the cel reference of the full model. docs/measurement.md says
// what is compared and what is left out.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <puff/core/error.h>
#include <puff/core/image.h>
#include <puff/render/render.h>
#include <puff/scene/scene.h>

namespace puff::eval {

/// The media layer resolutions measured, cheapest first: the layer has resolution^2 of the output's
/// pixels, so this is also the order of cost (the measured times are reported, not used to order).
inline constexpr std::array<float, 4> kMediaResolutions{0.125f, 0.25f, 0.5f, 1.0f};

struct MediaBudgetOptions {
  /// Timed renders per frame and resolution, [1, 100]. The first render of a frame (which also steps
  /// the simulators there and gives the measured image) is never timed.
  int timedRenders = 3;
  /// Also measure every candidate against the PHYSICAL reference (reference/media_physical.h: the
  /// particles' summed density fields integrated along each ray), the method's own error, beside the
  /// model reference's discretisation error (layer resolution, tables, sort). Seconds per frame; the
  /// choice never uses it.
  bool physical = false;
  /// Told (steps done, of all) as the measurement goes: frames for the media, the references and
  /// then the candidates for the nailboards. A tool's progress line (cli::Progress).
  std::function<void(int done, int total)> progress{};
};

/// measureCelBudget's options: the timed renders and the progress as MediaBudgetOptions's (the cel
/// budget has no physical reference).
struct CelBudgetOptions {
  int timedRenders = 3;                                 ///< per frame and candidate, [1, 100]
  std::function<void(int done, int total)> progress{};  ///< references, then candidates
};

/// Where the error lies, per measured frame (MediaBudget::frames order) against one reference: the
/// whole-frame RMSE says how far an image is, these say where. Scene-linear, not clamped.
struct RegionErrors {
  /// RMSE over the pixels where that reference shows a medium (reference::mediaMask of its own
  /// layer, epsilon half an 8-bit step). A frame without such pixels gives 0.
  std::vector<double> rmseMedia;
  /// RMSE over the clip band: within 2 pixels of where a particle sphere meets an opaque surface or
  /// the near plane (reference::clipBand of the frame's opaque depth, particles and camera; the same
  /// band for both references). A frame without such pixels gives 0.
  std::vector<double> rmseBand;
  /// SSIM over the whole frame (reference::ssim: per R, G, B, 11 x 11 Gaussian window), in [-1, 1];
  /// 1 where the images agree.
  std::vector<double> ssim;
  double worstRmseMedia = 0.0;  ///< the largest of rmseMedia
  double worstRmseBand = 0.0;   ///< the largest of rmseBand
  double worstSsim = 1.0;       ///< the SMALLEST of ssim (the worst frame)
};

/// One resolution, measured.
struct MediaCandidate {
  float resolution = 1.0f;  ///< MediaSpec::resolution
  std::vector<double>
      rmse;  ///< per measured frame (MediaBudget::frames order), scene-linear, against the model reference
  double worstRmse = 0.0;  ///< the largest of `rmse`; the only figure chooseMediaResolution uses
  /// With MediaBudgetOptions::physical: per measured frame against the physical reference (else empty).
  std::vector<double> rmsePhysical;
  double worstRmsePhysical = 0.0;  ///< the largest of rmsePhysical
  RegionErrors regions;            ///< against the model reference
  RegionErrors regionsPhysical;    ///< against the physical reference (empty vectors without options.physical)
  double medianMs = 0.0;           ///< median wall time of one render::SceneRenderer::renderFrame, milliseconds
};

struct MediaBudget {
  std::vector<int> frames;                 ///< the frames measured, ascending
  std::vector<MediaCandidate> candidates;  ///< in kMediaResolutions order: cheapest first
  double referenceMs = 0.0;                ///< wall time spent computing the references, milliseconds
  double physicalMs = 0.0;                 ///< of that, the physical references' (0 without them)
  /// Per measured frame, the pixels RegionErrors counted (of the reference the first resolution was
  /// measured against: every resolution draws the same opaque pass). mediaPixelsPhysical is empty
  /// without options.physical.
  std::vector<std::size_t> mediaPixels, mediaPixelsPhysical, bandPixels;
};

/// The frames to measure for a render of frames first..last (0 <= first <= last): first, middle
/// ((first + last + 1) / 2) and last, without repeats, ascending (1 to 3 frames).
std::vector<int> budgetFrames(int first, int last);

/// Renders `frames` (each in [0, scene.animation.frames), 1 .. 16 of them) at every resolution of
/// kMediaResolutions on the programmable path in the CURRENT context (GL 4.5), computes the
/// reference of each frame (once: the opaque layer does not depend on the media's resolution; again
/// if a render's opaque layer differs) and returns the errors (whole frame, media pixels, clip band,
/// SSIM: RegionErrors) and times. The scene's method, size,
/// samples and everything else are kept; lights, shimmer and motion blur are left out (see above).
/// Deterministic except for the times. Cost: 4 x (1 + timedRenders) renders per frame, plus one
/// reference per frame, its clip band (every pixel against every particle, one thread) and per
/// resolution an SSIM map (two with physical) (explosion-walls, 640 x 480, 241 particles and a temperature video: about
/// 1.5 s on 2 cores; measuring frames 0, 36 and 71 of it: about 6 s).
/// Errors: a scene without media or with cartoon media (the references are photoreal), no frames
/// or a frame outside the scene, timedRenders outside [1, 100], and what render::SceneRenderer::create, renderFrame,
/// core::loadDetailVideo and reference::renderMediaReference return.
Result<MediaBudget> measureMediaBudget(const scene::Scene& scene, std::span<const int> frames,
                                       const MediaBudgetOptions& options = {});

/// What chooseMediaResolution picked.
struct MediaChoice {
  double maxError = 0.0;   ///< the budget: the largest worst RMSE accepted, linear colour
  std::size_t chosen = 0;  ///< index into MediaBudget::candidates
  bool met = false;        ///< false: no candidate's worst RMSE is <= maxError; `chosen` is then the dearest
  std::size_t best = 0;    ///< the candidate with the smallest worst RMSE (for the message when not met)
};

/// The exact media image of the frame `renderer` drew last (render::SceneRenderer::lastMediaFrame: the same
/// particles over the same opaque layer), as measureMediaBudget computes it: scene-linear, not clamped,
/// RGBA, row 0 at the top. `scene` is the renderer's scene (its materials, settings and detail videos).
/// Needs the renderer's context current.
Result<core::Image> mediaReference(const scene::Scene& scene, const render::SceneRenderer& renderer);

/// The cheapest candidate whose worstRmse <= maxError; none: the dearest (the last), met = false.
/// Errors: maxError not in (0, 1] (NaN included), a budget without candidates.
Result<MediaChoice> chooseMediaResolution(const MediaBudget& budget, double maxError);

/// For people. The table: a header and one line per candidate (resolution, worst RMSE, then the worst
/// media-pixel RMSE, clip-band RMSE and SSIM against the model reference, with physical measured the
/// worst whole-frame RMSE against the physical reference too, median ms; the chosen one marked
/// "<- chosen"), each line ending in '\n'. The summary, one line without
/// '\n', e.g. "--max-error 0.01: media resolution 0.25 (worst RMSE 0.0063 over frames 0, 36, 71;
/// 0.125 misses with 0.0132; 0.5 would cost 1.8x as much)". The warning, when !choice.met (else
/// empty), one line without '\n': the budget cannot be met, and the best error measured.
std::string budgetTable(const MediaBudget& budget, const MediaChoice& choice);
std::string budgetSummary(const MediaBudget& budget, const MediaChoice& choice);
std::string budgetWarning(const MediaBudget& budget, const MediaChoice& choice);

// ---- the cel path: particle count, atlas resolution, shadows ---------------------------------------

/// Which parameter a CelBudget varies.
enum class CelKnob {
  kParticleFraction,
  kAtlasLevel,
  kShadows,  ///< the shadow method and the map's scale (Style::shadowMethod, shadowMapScale)
  kTumble,   ///< how oriented puffs turn: the blend, or the hull from a size on (Style::tumble, hullFromPixels)
};

/// The shadow maps' scales measured (Style::shadowMapScale), beside the volumes.
inline constexpr std::array<float, 4> kShadowMapScales{0.25f, 0.5f, 1.0f, 2.0f};

/// kTumble's sizes (Style::hullFromPixels) between the blend on every oriented puff and the hull on
/// every one: the hull only for puffs at least this many pixels across.
inline constexpr std::array<float, 3> kHullFromPixels{96.0f, 48.0f, 24.0f};

/// One candidate, measured.
struct CelCandidate {
  float particleFraction = 1.0f;  ///< scene::Scene::particleFraction
  std::size_t particles = 0;      ///< cel particles drawn (the most over the measured frames)
  int atlasLevel = 0;             ///< scene::Scene::atlasLevel
  int cellSize = 0;               ///< texels per cell at that level
  std::size_t atlasBytes = 0;     ///< core::atlasTextureBytes at that level
  cel::ShadowMethod shadowMethod = cel::ShadowMethod::kMap;  ///< the scene's Style::shadowMethod
  float shadowMapScale = 1.0f;                               ///< the scene's Style::shadowMapScale
  cel::TumbleMethod tumble = cel::TumbleMethod::kHull;       ///< the scene's Style::tumble
  float hullFromPixels = 0.0f;                               ///< the scene's Style::hullFromPixels
  std::vector<double> rmse;  ///< per measured frame, display values (both frames through the standard view)
  double worstRmse = 0.0;
  double medianMs = 0.0;  ///< median wall time of one render::SceneRenderer::renderFrame, milliseconds
};

struct CelBudget {
  CelKnob knob = CelKnob::kAtlasLevel;
  std::vector<int> frames;  ///< the frames measured, ascending
  std::vector<CelCandidate>
      candidates;            ///< cheapest first: fewest particles / smallest atlas / fastest measured (shadows)
  double referenceMs = 0.0;  ///< wall time spent rendering the references (0: reused)
  std::vector<core::Image> references;  ///< the full model's reference of each frame (for reuse)
};

/// The particle fractions measured, cheapest first.
inline constexpr std::array<float, 4> kParticleFractions{0.125f, 0.25f, 0.5f, 1.0f};

/// Renders `frames` (1..16, each in the scene) with every value of `knob` on the programmable path in
/// the CURRENT context (GL 4.5, where the reference path runs too), the other parameter as the scene
/// has it, and the cel reference of the full model at each frame once. kAtlasLevel: every level from
/// core::deepestAtlasLevel (but no smaller than 16-texel cells) to 0. kParticleFraction:
/// kParticleFractions (the scene needs placed emitters). kShadows: the map at each of kShadowMapScales
/// and the volumes, ordered by their measured median time (the scene needs Style::shadows on). kTumble:
/// the blend on every oriented puff, the hull from each of kHullFromPixels and the hull on every one,
/// in that order: the fewest puffs taking the hull first, whatever the noise in their measured times
/// (the scene needs oriented puffs). Media
/// are left out. Errors: a scene without an atlas or particles (or, for kParticleFraction, without
/// placed emitters; for kShadows, without shadows; for kTumble, without oriented puffs), bad frames,
/// timedRenders outside [1, 100], and what render::SceneRenderer::create / createReference / renderFrame return.
/// `references` (optional): the full model's references of these frames from an earlier budget of the
/// same scene and frames (CelBudget::references), reused instead of rendered again.
Result<CelBudget> measureCelBudget(const scene::Scene& scene, std::span<const int> frames,
                                   const CelBudgetOptions& options = {}, CelKnob knob = CelKnob::kAtlasLevel,
                                   std::span<const core::Image> references = {});

/// The cheapest candidate whose worstRmse <= maxError; none: the dearest (the last: level 0, or all
/// the particles), met = false; for kShadows and kTumble the closest instead (the dearest is not
/// always the closest there). Errors: maxError not in (0, 1], no candidates.
Result<MediaChoice> chooseCelBudget(const CelBudget& budget, double maxError);

/// For people, as budgetTable / budgetSummary / budgetWarning above.
std::string celBudgetTable(const CelBudget& budget, const MediaChoice& choice);
std::string celBudgetSummary(const CelBudget& budget, const MediaChoice& choice);
std::string celBudgetWarning(const CelBudget& budget, const MediaChoice& choice);

}  // namespace puff::eval
