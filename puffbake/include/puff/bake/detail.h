// Making detail videos (core/detail_video.h): the looping greyscale textures that perturb fire
// temperature and smoke opacity (Umenhoffer et al. 2006, §3.1-3.2). Either generated, as
// periodic gradient-noise fBm that tiles in x and y and loops in time, or imported from an image
// sequence (a filmed fire or smoke clip) made to loop by a cross-fade.
#pragma once

#include <filesystem>
#include <vector>

#include <puff/core/detail_video.h>
#include <puff/core/error.h>

namespace puff::bake {

using core::kMaxDetailTexels;  ///< size * size * frames, 64 Mi (256 MiB of floats)
/// What each frame of `puffbake detail --from` may be, checked from its header before decoding: at
/// most 8192 x 8192 pixels, 1 to 4 channels, a file of at most 512 MiB.
inline constexpr core::ImageLimits kDetailSourceFrameLimits{"a detail source frame",  8192, 8192, 4, 1ll << 26,
                                                            std::uintmax_t{512} << 20};

/// A procedural detail video. Every field is checked by validate().
struct DetailSpec {
  int size = 128;      ///< width = height in texels, [4, 4096]
  int frames = 32;     ///< frames in the loop, [1, 1024]; size * size * frames <= 2^26
  unsigned seed = 1;   ///< any value; the same spec always gives the same values
  int octaves = 4;     ///< fBm octaves, [1, 10]; each doubles the frequency and halves the amplitude
  int frequency = 4;   ///< lattice cells across the tile in the first octave, [1, 256]
  float contrast = 1;  ///< [0, 16]: standard deviation = contrast / 6 around the mean 0.5, then clipped to [0, 1]
};

/// "--size must be in [4, 4096], got 0": the first bad field, named by its puffbake flag.
Result<void> validate(const DetailSpec& spec);

/// The raw fBm field of `spec` (before normalization), at texel coordinates x, y (texel i's centre
/// is i + 0.5) and time t in frames. Periodic: the value at x + size, y + size or t + frames is
/// the value at x, y, t (up to rounding of the coordinates), so the texture tiles and loops.
/// Octave o has frequency * 2^o lattice cells across the tile and min(frequency * 2^o,
/// max(1, frames / 4)) cells along the loop (at least four frames per cell, so fine octaves do
/// not flicker).
/// `spec` must be valid (PUFF_CHECK).
double detailNoise(const DetailSpec& spec, double x, double y, double t);

/// Samples detailNoise at texel centres and integer frames, then normalizes: value = 0.5 +
/// contrast * (n - mean) / (6 * standard deviation), clipped to [0, 1] (mean 0.5 up to the
/// clipping). Deterministic: the same spec gives the same values (and file bytes) on a machine.
/// Errors: validate()'s.
Result<core::DetailVideo> generateDetailVideo(const DetailSpec& spec);

/// Imports an image sequence (any format the installed codec reads; all frames the same size), in the
/// order given:
///  - each frame becomes one channel: channel 0 of 1-2 channel images, else the Rec. 709 luma
///    0.2126 R + 0.7152 G + 0.0722 B of the stored values (no sRGB decoding), clipped to [0, 1];
///  - it is resampled to size x size per axis: an area-weighted box filter where the axis shrinks
///    (or keeps its size: then the values are copied exactly), bilinear at texel centres with
///    clamped edges where it grows. The aspect ratio is not kept, and x/y do not tile;
///  - with N input frames and L = loopFrames, the output has N - L frames: out[i] = in[i] for
///    L <= i < N - L, and for i < L out[i] = (1 - w) * in[N - L + i] + w * in[i] with
///    w = (i + 1) / (L + 1). The dropped tail frames fade into the head, so the last output frame
///    in[N - L - 1] runs on into mostly in[N - L] and the loop has no jump. L = 0 keeps all frames
///    (for a sequence that already loops).
/// Errors: no frames; size outside [4, 4096]; loopFrames outside [0, N / 2]; more than 1024 output
/// frames or 2^26 texels; a frame missing, unreadable or of a different size than the first (the
/// message names the file).
Result<core::DetailVideo> importDetailVideo(const std::vector<std::filesystem::path>& frames, int size, int loopFrames);

}  // namespace puff::bake
