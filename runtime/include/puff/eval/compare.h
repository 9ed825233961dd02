// Comparing two render paths on one scene: where each draws smoke (its mask: the pixels that
// differ from the same frame drawn without particles) and how close the tones are where both do.
// The command line's path comparison and the fixed-function parity tests use it.
#pragma once

#include <string>
#include <vector>

#include <puff/core/image.h>
#include <puff/scene/scene.h>

namespace puff::eval {

/// The scene without any particle (listed, placed or simulated): the background a mask is taken
/// against.
scene::Scene withoutParticles(const scene::Scene& scene);

/// The scene within the fixed-function path's limits (McGuire & Fein §4.4), so both paths draw the
/// same thing: no shadows, the uniform ambient colour instead of a gradient, view-plane billboards,
/// one sample per pixel, no media (fire, smoke, dust). `changes` (optional) lists what was changed, for a report.
scene::Scene restrictToFixedLimits(const scene::Scene& scene, std::vector<std::string>* changes = nullptr);

struct Parity {
  double iou = 0.0;          ///< |A ∩ B| / |A ∪ B| of the two smoke masks; 1 when both are empty
  double toneShare = 0.0;    ///< of the pixels in A ∩ B, the share within `tolerance` in every channel
                             ///< (1 when A ∩ B is empty: check `both`)
  double meanAbsDiff = 0.0;  ///< mean over A ∪ B of the largest channel difference, in [0, 1]
  std::size_t maskA = 0, maskB = 0, both = 0;  ///< pixels in A, in B, in both
};

/// `a` and `b`: one frame by each path; `aBare` and `bBare`: the same frame without particles.
/// All four the same size, RGBA, scene-linear (SceneRenderer::renderFrame's); they are compared as
/// display values, through the standard view transform, as is `sideBySide`. A pixel is smoke when
/// some channel differs from the bare image by
/// more than 1/64 (above 8-bit rounding, below any ink or tone step). `tolerance` is per channel.
/// `sideBySide` (optional) receives [a | b | difference], the difference as |a - b| scaled by 4
/// over a grey background where the masks disagree: red = only A has smoke, blue = only B.
Parity compareFrames(const core::Image& a, const core::Image& aBare, const core::Image& b, const core::Image& bBare,
                     float tolerance, core::Image* sideBySide = nullptr);

}  // namespace puff::eval
