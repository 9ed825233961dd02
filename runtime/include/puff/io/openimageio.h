// puff::io: image files through OpenImageIO (PNG, EXR, TIFF, JPEG, ... whatever the installed
// OpenImageIO reads and writes), for the programs that read artists' files: Puff's tools, and a game
// that loads uncooked assets. puff::core itself reads and writes only cooked images (".puffimg",
// core/image.h); a game that ships cooked assets needs neither this component nor OpenImageIO.
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include <puff/core/image.h>

namespace puff::io {

/// The OpenImageIO codec: reads any format OpenImageIO knows, values as stored (no division by a
/// fourth channel that may not be alpha), and the file's "puff:" string attributes; writes with
/// the attributes in the file's metadata, float formats zip-compressed, with no time stamp (the
/// same inputs give the same bytes).
const core::ImageCodec& openImageIOCodec();

/// Whether the installed OpenImageIO has a GIF writer.
bool canWriteGif();

/// An animated GIF written a frame at a time (a long sequence is never held whole): frames are
/// display-encoded RGB or RGBA in [0, 1] (alpha dropped), all `width` x `height`, shown `delay`
/// hundredths of a second each (GIF has one delay for all; gifTiming() picks it); it loops
/// forever; OpenImageIO picks each frame's 256-colour palette. Errors name `name` (the user's file;
/// `path` may be a staged temporary), else `path`.
class AnimatedGif {
 public:
  static Result<std::unique_ptr<AnimatedGif>> open(const std::filesystem::path& path, int frames, int width, int height,
                                                   int delay, const std::filesystem::path& name = {});
  ~AnimatedGif();
  AnimatedGif(const AnimatedGif&) = delete;
  AnimatedGif& operator=(const AnimatedGif&) = delete;
  Result<void> add(const core::Image& frame);
  /// After the last of the frames it was opened for.
  Result<void> close();

 private:
  AnimatedGif();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// How `count` frames at `fps` play in a GIF, whose frames all show for one whole number of
/// hundredths of a second: that delay (at least 2: browsers slow shorter ones to a tenth of a second),
/// and for each GIF frame the frame it shows (source[k], non-decreasing), the one due at its time,
/// so the GIF lasts as long as the sequence (a frame shown twice, or one skipped, where the rate is
/// not 100 / delay).
struct GifTiming {
  int delay = 4;
  std::vector<int> source;
};
GifTiming gifTiming(int count, double fps);

/// Installs openImageIOCodec() for every later core::readImage / core::writeImage
/// (core::setImageCodec). Call it first thing in main.
void useOpenImageIO();

}  // namespace puff::io
