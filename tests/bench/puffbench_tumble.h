// puffbench's tumble part: see puffbench_tumble.cpp.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <puff/core/error.h>

namespace puffbench {

/// One multi-view atlas of the sweep: a view layout and its grid (grid x grid views per variation).
struct TumbleAtlas {
  std::string layout;  ///< "oct" or "hemioct"
  int grid = 3;
};

struct TumbleBenchOptions {
  std::filesystem::path puffDir;  ///< art/puffs: variation-1.obj, -2.ply, -3.off, -4.stl
  std::vector<TumbleAtlas> atlases{{"oct", 3},     {"oct", 5},     {"oct", 7},    {"oct", 9},
                                   {"hemioct", 3}, {"hemioct", 5}, {"hemioct", 7}};
  std::vector<int> cellSizes{64, 128, 256};
  int stepDegrees = 15;  ///< eval::TumbleOptions::stepDegrees: yaw, pitch and roll this far apart
};

/// One atlas measured over the whole sweep against the cel reference, drawn by one tumble method.
struct TumbleRow {
  std::string layout;
  std::string method;                     ///< cel::Style::tumble: "hull" or "blend"
  int grid = 0, views = 0, cellSize = 0;  ///< views: per variation (grid^2)
  std::size_t atlasBytes = 0;             ///< core::atlasTextureBytes of the baked atlas: what the GL holds
  std::size_t poses = 0;
  double minCoverageIoU = 0.0, meanCoverageIoU = 0.0, coverageShare = 0.0;  ///< share: poses >= 0.95
  double minOutlineIoU = 0.0, meanOutlineIoU = 0.0, outlineShare = 0.0;     ///< share: poses >= 0.5
  double ms = 0.0;  ///< median frame time of the nailboards' pose grid (eval::measureTumble's msPerFrame)
};

/// Bakes each atlas of options.atlases x options.cellSizes from the art's four puffs and measures it
/// with eval::measureTumble, once per tumble method (hull, blend), against one
/// eval::renderTumbleReference of the sweep (all rolls). Needs a
/// current GL 4.5 context. Logs progress to stderr.
puff::Result<std::vector<TumbleRow>> runTumbleBench(const TumbleBenchOptions& options);
std::string tumbleCsv(const std::vector<TumbleRow>& rows);

/// Parses "oct3,oct5,hemioct7" (a layout name and its grid, comma-separated).
puff::Result<std::vector<TumbleAtlas>> parseTumbleAtlases(const std::string& list);

}  // namespace puffbench
