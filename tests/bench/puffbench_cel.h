// puffbench's cel part: see puffbench_cel.cpp.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <puff/core/error.h>
#include <puff/core/image.h>
#include <puff/render/render.h>
#include <puff/scene/scene.h>

namespace puffbench {

struct CelBenchOptions {
  std::filesystem::path sceneDir, artDir;
  std::vector<std::string> scenes{"explosion", "cloud-fig8c"};  ///< atlas and level-of-detail sweeps
  std::vector<int> atlasCells{64, 128, 256, 512, 1024};
  std::vector<int> decimations{1, 4, 16, 64};                      ///< faces / k
  std::vector<std::size_t> counts{263, 1052, 4000, 12500, 50000};  ///< on cloud-50k; empty: none
  /// Scenes of oriented puffs, at their own size: the blend, the hull from each of
  /// eval::kHullFromPixels and the hull on all (parameter "tumble"; value: Style::hullFromPixels, the
  /// blend cel::kMaxHullFromPixels).
  std::vector<std::string> tumbleScenes{"dust-roll"};
  std::size_t referenceLimit = 12500;  ///< no reference (so no error) above this many particles
  int width = 320, height = 240, reps = 3;
};

struct CelRow {
  std::string scene, path, parameter, label;  ///< path: cel, fixed or cel-fixed-limits
  double value = 0.0;                         ///< cell size, faces or particle count
  std::size_t particles = 0;
  int width = 0, height = 0;
  double ms = 0.0, floorMs = 0.0;                          ///< floorMs: the fill-rate floor (particles as bare quads)
  double bareMs = 0.0;                                     ///< the frame without particles
  double rmse = 0.0, coverageIoU = 1.0, outlineIoU = 1.0;  ///< NaN: not measured
  double rmsePuffs = 0.0;                                  ///< RMSE over the pixels either image shows puffs on
  bool pareto = false;
};

/// Needs a current compatibility-profile context that runs both paths (GL 4.5 and 1.x calls).
puff::Result<std::vector<CelRow>> runCelBench(const CelBenchOptions& options);
void markParetoFronts(std::vector<CelRow>& rows);
std::string celCsv(const std::vector<CelRow>& rows);

/// One configuration's frames: the median time of a render over frames x reps (0 when reps == 0), the
/// images (scene-linear, one per frame, each from a first render that is not timed) and the most
/// particles drawn.
struct Frames {
  double ms = 0.0;
  std::vector<puff::core::Image> images;
  std::size_t particles = 0;
};

/// Renders `frames` with `path` (the reference with its default sampling; the particles as bare quads
/// with `fillRateFloor`), each once untimed (the image) and then `reps` times timed.
puff::Result<Frames> renderFrames(const puff::scene::Scene& scene, puff::render::RenderPath path,
                                  std::span<const int> frames, int reps, bool fillRateFloor = false);

/// Renders `frame` `reps` times, appending each render's wall time (ms) to `times`: how both parts of
/// puffbench time a frame, after a first render of it that is not timed (the caller's).
puff::Result<void> timeFrame(puff::render::SceneRenderer& renderer, int frame, int reps, std::vector<double>& times);

}  // namespace puffbench
