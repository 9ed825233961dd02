// Image metrics for comparing renderers with the reference (media_reference.h) and with each
// other: error against a reference, structural similarity, coverage, temporal smoothness, spatial
// jumps, and masks of where they matter (media pixels, the band where media meet surfaces and the
// near plane). Image metrics work on the first three channels (RGB) of core::Images in linear
// colour; alpha is ignored unless said. Images of the wrong size or with fewer than 3 channels are a
// broken promise of the caller (PUFF_CHECK).
#pragma once

#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include <puff/core/image.h>
#include <puff/media/types.h>

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

/// Where an image shows ink: every RGB channel within `tolerance` of `ink` where `bare` (the same
/// frame without the inked things, or their background) is not ink. Colours in the images' own
/// space. Returns width * height flags, row 0 at the top.
std::vector<bool> inkMask(const core::Image& image, const core::Image& bare, const glm::vec3& ink,
                          double tolerance = 0.1);

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

/// SSIM (Wang, Bovik, Sheikh & Simoncelli 2004, Eq. 13) at every pixel, per R, G and B channel
/// separately and averaged over the three (not on luminance: a hue error counts):
///     SSIM = (2 mu_a mu_b + C1)(2 sigma_ab + C2) / ((mu_a^2 + mu_b^2 + C1)(sigma_a^2 + sigma_b^2 + C2))
/// with C1 = (0.01)^2 and C2 = (0.03)^2 (dynamic range 1), and the means, variances and covariance
/// weighted by the paper's 11 x 11 Gaussian window (sigma 1.5 pixels, weights normalized). At the
/// image's edges the window is cut to the image and its weights renormalized, so every pixel has a
/// value (the paper's code keeps only the windows wholly inside). Values in linear colour, not
/// clamped. Returns width * height values, row 0 at the top; 1 where the images agree.
std::vector<double> ssimMap(const core::Image& a, const core::Image& b);
/// The mean of ssimMap over every pixel, or over the pixels whose `mask` flag is set (width *
/// height flags, row 0 at the top). No counted pixel gives 1.
double ssim(const core::Image& a, const core::Image& b, const std::vector<bool>& mask = {});

/// Where a media layer shows a medium: the pixels of `layer` (>= 4 channels: rgb the premultiplied
/// radiance M, alpha the transmittance T, as renderMediaReference's `layer` gives it) with
/// T < 1 - epsilon or any of M's channels > epsilon. The default is half an 8-bit step: a medium
/// that can move an 8-bit output value. Returns width * height flags, row 0 at the top.
std::vector<bool> mediaMask(const core::Image& layer, double epsilon = 0.5 / 255.0);

/// Where particle spheres meet the opaque surfaces and the near plane, from plain data (no GL).
/// For each pixel's ray (pixelRay in media_reference.h: through the pixel centre of `frame`,
/// perspective or orthographic, camera space) and each particle sphere it enters (centre:
/// frame.view * position, radius r > 0; entry tF, exit tB along the ray):
///  - `surface`: the opaque surface lies inside the sphere along the ray, tF < tScene < tB (the
///    chord is clipped by the surface; where planar billboards cut into walls and depth-aware
///    upsampling decides);
///  - `nearPlane`: the near plane crosses the chord, tF < tNear < tB (where the camera is entering
///    the medium);
///  - `band`: the pixels within `width` pixels (Chebyshev distance: a (2 width + 1)^2 square) of a
///    pixel of either set.
/// tScene and tNear are the view-axis distances of the surface and the near plane turned into ray
/// parameters; `depth` is frame.width * frame.height linear depths (-z - near) / (far - near), row 0
/// at the BOTTOM as MediaReferenceInput::opaqueDepth and SceneRenderer::lastMediaFrame give them
/// (>= 1: no surface; empty: no surface anywhere). The masks are row 0 at the TOP, like the images.
struct ClipBand {
  std::vector<bool> surface, nearPlane, band;
};
ClipBand clipBand(std::span<const float> depth, std::span<const media::Particle> particles, const media::Frame& frame,
                  int width = 2);

}  // namespace puff::reference
