// Image metrics for comparing renderers with the reference (media_reference.h) and with each
// other: error against a reference, coverage, temporal smoothness and spatial jumps. All work on
// the first three channels (RGB) of core::Images in linear colour; alpha is ignored. Images of the
// wrong size or with fewer than 3 channels are a broken promise of the caller (PUFF_CHECK).
#pragma once

#include <span>
#include <vector>

#include <puff/core/image.h>

namespace puff::reference {

/// Error of `a` against `b` over the R, G and B values of every pixel (or of the pixels in a mask).
struct ImageError {
  double rmse = 0.0;    ///< sqrt(mean of (a - b)^2 over the values), same unit as the images (linear)
  double psnr = 0.0;    ///< 10 log10(1 / mse) in dB, peak 1; +infinity when rmse is 0
  double maxAbs = 0.0;  ///< largest |a - b| of any value
};

/// a and b: the same width and height, each with >= 3 channels (they may differ: RGB vs RGBA).
/// `mask` (optional): width * height flags, row 0 at the top like the images; only pixels with
/// their flag set count. No counted pixel gives {0, +infinity, 0}.
ImageError imageError(const core::Image& a, const core::Image& b, const std::vector<bool>& mask = {});

/// Where an image shows something over `background`: a pixel is covered when any of R, G, B
/// differs from the background's by more than `threshold`. This is render::compareFrames'
/// definition (compare.h), whose threshold is 1/64 (above 8-bit rounding, below any visible tone).
/// Returns width * height flags, row 0 at the top.
std::vector<bool> coverageMask(const core::Image& image, const core::Image& background, double threshold = 1.0 / 64.0);

/// |A ∩ B| / |A ∪ B| of two masks of the same size, in [0, 1]; 1 when both are empty.
double maskIoU(const std::vector<bool>& a, const std::vector<bool>& b);

/// Coverage IoU of two images drawn over the same `background`:
/// maskIoU(coverageMask(a, background, threshold), coverageMask(b, background, threshold)).
double coverageIoU(const core::Image& a, const core::Image& b, const core::Image& background,
                   double threshold = 1.0 / 64.0);

/// The temporal metric: |f[k+1] - 2 f[k] + f[k-1]| over every interior frame k, pixel and RGB
/// channel of a sequence of same-size frames. Smooth motion keeps it small (a linear fade gives 0);
/// a pop of size s shows as s. largest: the maximum; mean: the mean over all those values.
/// Fewer than 3 frames give 0.
double largestSecondDifference(std::span<const core::Image> frames);
double meanSecondDifference(std::span<const core::Image> frames);

/// The spatial clipping metric: the largest |difference| of any RGB channel between two
/// 4-neighbour pixels (left-right or up-down) that are both in `region` (width * height flags, row
/// 0 at the top; empty = the whole image). A hard edge where a billboard cuts into a wall shows as
/// a jump of the medium's opacity; a smooth medium gives about its gradient per pixel. 0 when no
/// neighbouring pair lies in the region.
double largestJump(const core::Image& image, const std::vector<bool>& region = {});

}  // namespace puff::reference
