// Tumbling puffs against the cel reference: oriented nailboards turned through a sweep of
// yaw, pitch and roll, each pose drawn as one puff in its own square of a grid, and compared pose by
// pose with the cel reference, which turns the actual puff meshes. What a multi-view atlas's view
// count and cell size buy: coverage IoU (the puff's silhouette with its ink) and outline IoU (the
// ink alone) per pose.
#pragma once

#include <filesystem>
#include <vector>

#include <puff/cel/types.h>
#include <puff/core/error.h>
#include <puff/core/image.h>

namespace puff::eval {

struct TumbleOptions {
  int stepDegrees = 15;  ///< yaw and roll in [0, 360), pitch in [-90, 90], this far apart; divides 90
  /// Where yaw and pitch start: yaw at this, pitch at -90 + this, in [0, stepDegrees). A step of 2k
  /// offset by k samples a k-degree grid between its own poses (the poles are then left out).
  int offsetDegrees = 0;
  int puffPixels = 48;        ///< a puff's diameter on screen (it is drawn this many pixels across)
  float outlineWidth = 2.0f;  ///< pixels
};

/// One pose: the puff's frame is Ry(yaw) Rx(pitch) Rz(roll) (degrees) with the camera on +z; roll
/// alone turns the puff about the view axis.
struct TumblePose {
  int yaw = 0, pitch = 0, roll = 0;
  int variation = 0;
  double coverageIoU = 1.0, outlineIoU = 1.0;
  /// Where the coverage differs, as fractions of the reference's pixels: pixels the nailboards cover
  /// and the reference does not (too large), and the reverse (too small).
  double coverageExtra = 0.0, coverageMissing = 0.0;
  /// The same for the puff drawn without outlines (its body, without the ink).
  double bodyExtra = 0.0, bodyMissing = 0.0;
};

/// The reference's frames (one per roll), rendered once and compared with any atlas baked from the
/// same meshes.
struct TumbleReference {
  TumbleOptions options;
  std::vector<core::Image> frames;  ///< scene-linear RGBA
  std::vector<core::Image> bodies;  ///< the same frames without outlines (what the ink adds is the ink)
  std::vector<int> rolls;
};

struct TumbleResult {
  std::vector<TumblePose> poses;
  double minCoverageIoU = 1.0, meanCoverageIoU = 1.0;
  double minOutlineIoU = 1.0, meanOutlineIoU = 1.0;
};

/// The poses of a sweep: yaw and roll in [0, 360) and pitch in [-90, 90] every `stepDegrees`
/// (at pitch +-90 yaw and roll turn about the same axis: only yaw 0 is kept there).
std::vector<TumblePose> tumblePoses(int stepDegrees);
/// The yaw and pitch of each pose of `options`' grid that measureTumble measures at each roll (roll
/// 0 here), row by row (pitch).
std::vector<TumblePose> tumbleGridPoses(const TumbleOptions& options);

/// The cel reference of the sweep, with the source meshes of `atlas` (a sidecar), in the current GL
/// 4.5 context. `rolls` limits the frames drawn (empty: every roll of the sweep).
Result<TumbleReference> renderTumbleReference(const std::filesystem::path& atlas, const TumbleOptions& options,
                                              std::vector<int> rolls = {});

/// The nailboards of `atlas` (baked from the reference's meshes, oriented puffs allowed: more than
/// one view) over the same poses, pose by pose against `reference`, drawn by `method`
/// (cel::Style::tumble). `msPerFrame`, when given, receives the median time of a grid frame (the
/// nailboards only).
Result<TumbleResult> measureTumble(const std::filesystem::path& atlas, const TumbleReference& reference,
                                   cel::TumbleMethod method = cel::TumbleMethod::kHull, double* msPerFrame = nullptr);

}  // namespace puff::eval
