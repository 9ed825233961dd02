// puffbench's shadow part: see puffbench_shadows.cpp.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <puff/core/error.h>

#include "puffbench_cel.h"

namespace puffbench {

struct ShadowRow {
  std::string scene, method;  ///< method: volumes or map
  float mapScale = 0.0f;      ///< Style::shadowMapScale (map; 0 for volumes)
  std::size_t particles = 0;
  int width = 0, height = 0;
  double ms = 0.0, floorMs = 0.0, noShadowMs = 0.0;  ///< median frame times: this, the fill-rate floor, no shadows
  double shadowIoU = 1.0;                            ///< the darkened pixels against the reference's; worst frame
  double rmse = 0.0;                                 ///< against the reference's frame, display values; worst frame
  double referenceShadowFraction = 0.0;  ///< the share of the frame the reference's shadows darken (largest)
};

/// The shadow sweep over `scenes` (art scene names, or "cloud-10k": cloud-50k scaled to 10,000
/// particles), at options.width x options.height with options.reps timed renders per frame.
puff::Result<std::vector<ShadowRow>> runShadowBench(const CelBenchOptions& options,
                                                    std::span<const std::string> scenes);
std::string shadowCsv(const std::vector<ShadowRow>& rows);

}  // namespace puffbench
