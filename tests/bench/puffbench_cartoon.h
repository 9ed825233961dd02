// puffbench's cartoon part: see puffbench_cartoon.cpp.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <puff/core/error.h>

namespace puffbench {

struct CartoonBenchOptions {
  std::filesystem::path sceneDir, artDir;
  /// Art scenes with media.style "cartoon"; each is measured as it is and with style "photoreal".
  std::vector<std::string> scenes{"explosion-walls-cartoon", "fire-to-smoke-cartoon"};
  int width = 320, height = 240, reps = 3;
  int sequenceFrames = 24;  ///< consecutive frames for the stability measure, from the scene's middle
  int isoFrames = 3;        ///< frames compared with the references' iso-lines
};

struct CartoonRow {
  std::string scene, style;  ///< style: photoreal or cartoon
  int width = 0, height = 0;
  /// Median frame times: with media, and the photoreal frame without media particles (what both
  /// styles pay before the media), and this style's frame without them (the cartoon's compose passes
  /// run on an empty layer too).
  double ms = 0.0, bareMs = 0.0, emptyMs = 0.0;
  /// Stability over the sequence (display values, the largest channel): the mean and the 99th
  /// percentile of |x(t+1) - 2 x(t) + x(t-1)|, and the share of pixel-frames that flicker: a step of
  /// more than 0.1 that the next frame undoes, every channel back within 0.02 (an edge passing over
  /// a pixel changes it twice, scene to ink to fill, but the fill is not the scene it covered).
  double d2Mean = 0.0, d2P99 = 0.0, flickerShare = 0.0;
  /// Cartoon only: the fill's mask (A >= threshold, from the GPU's own field) against the mask of
  /// each reference's accumulated opacity (burn ignored, as the cartoon does): IoU, and the mean and
  /// 95th-percentile distance (pixels) from each iso-line's pixels to the other's. NaN: not measured.
  double iouModel = 0.0, meanPxModel = 0.0, p95PxModel = 0.0;
  double iouPhysical = 0.0, meanPxPhysical = 0.0, p95PxPhysical = 0.0;
};

/// Needs a current GL 4.5 context.
puff::Result<std::vector<CartoonRow>> runCartoonBench(const CartoonBenchOptions& options);
std::string cartoonCsv(const std::vector<CartoonRow>& rows);

}  // namespace puffbench
