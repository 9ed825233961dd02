// Detail videos: small looping greyscale 3D textures (x, y, time). Fire particles read one as a
// temperature perturbation, smoke and dust particles as an opacity perturbation (Umenhoffer et
// al. 2006, §3.1-3.2); each particle shows a small window of it, starting at its own time.
//
// File format: ONE single-channel image whose frames are stacked top to bottom (width x
// height * frames; frame 0 at the top), a 16-bit PNG or a half-float EXR (chosen by the
// extension), with the metadata attribute puff:frames = the frame count and, optionally,
// puff:source = how it was made.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <puff/core/error.h>
#include <puff/core/image.h>

namespace puff::core {

inline constexpr int kMinDetailSize = 4, kMaxDetailSize = 4096;  ///< width and height, texels
inline constexpr int kMaxDetailFrames = 1024;                    ///< frames in [1, 1024]
inline constexpr long long kMaxDetailTexels = 1ll << 26;         ///< width * height * frames (256 MiB of floats)
/// What a detail clip's file may be, checked from its header before decoding: at most 4096 wide,
/// 4096 * 1024 tall, 2^26 pixels in all, 1 to 4 channels (luminance is used), at most 512 MiB.
inline constexpr ImageLimits kDetailClipLimits{
    "a detail clip", kMaxDetailSize, kMaxDetailSize* kMaxDetailFrames, 4, kMaxDetailTexels, std::uintmax_t{512} << 20};

struct DetailVideo {
  int width = 0, height = 0, frames = 0;
  /// frames * height * width values in [0, 1], frame-major, row 0 at the top of each frame.
  std::vector<float> values;
  /// Provenance, stored as puff:source when not empty (e.g. "generated: seed 1, ...").
  std::string source;

  std::size_t index(int x, int y, int f) const { return (static_cast<std::size_t>(f) * height + y) * width + x; }
  /// The value at texel (x, y) of frame f; no wrapping (PUFF_CHECK on out-of-range arguments).
  float at(int x, int y, int f) const;
};

/// Reads a detail video: usually the PNG/EXR described above (through the installed codec, core/image.h)
/// or its cooked copy (`puffbake cook`).
/// Images with several channels are accepted: 2 channels (grey + alpha) use channel 0, 3 or more
/// use the Rec. 709 luminance 0.2126 R + 0.7152 G + 0.0722 B of the first three. Values are
/// clamped to [0, 1]. Errors name the file: unreadable, puff:frames missing or not an integer in
/// [1, 1024], image height not a multiple of the frame count, a frame size outside [4, 4096], a
/// value that is not finite.
Result<DetailVideo> loadDetailVideo(const std::filesystem::path& path);

/// Writes `video` as described above: ".png" gives 16-bit PNG (values rounded to 1/65535), ".exr"
/// half-float EXR; any other extension is an error. Atomic: a temporary file beside `path` is
/// renamed over it when complete, so a failure never clobbers an existing file. Errors name the
/// file (extension, directory, write failure) or the bad size (width/height in [4, 4096], frames
/// in [1, 1024]). `values` must hold frames * height * width entries (PUFF_CHECK).
Result<void> saveDetailVideo(const std::filesystem::path& path, const DetailVideo& video);

}  // namespace puff::core
