// Float images in memory and their files. Rows are stored top to bottom, channels interleaved;
// values are whatever the producer put there (usually [0,1]).
//
// Files: puff::core reads and writes Puff's cooked images (".puffimg", below) itself, with no image
// library. Every other format (PNG, EXR, ...) goes through an image codec the program installs:
// puff::io's OpenImageIO codec (<puff/io/openimageio.h>, `puff::io::useOpenImageIO()`), which
// Puff's tools call first thing. A game that loads only cooked assets (`puffbake cook`) links no
// image library at all.
//
// A cooked image (".puffimg", version 1), every integer little-endian:
//   bytes 0-7    magic "PUFFIMG\0"
//   u32 version (1), u32 width, u32 height, u32 channels (1-4), u32 pixel type (PixelType's order:
//   0 uint8, 1 uint16, 2 half, 3 float), u32 attribute count (at most 64)
//   per attribute: u32 key length, key bytes, u32 value length, value bytes (each at most 64 KiB)
//   pixels: width * height * channels values of the type, rows top to bottom, channels interleaved
//   u64 FNV-1a hash of every byte before it
// and nothing after. Unsigned-normalized values read as v * (1 / (2^bits - 1)) in float and are written
// as floor(x * (2^bits - 1) + 0.5) after clamping to [0, 1], as OpenImageIO does for PNG;
// half floats are IEEE 754 binary16, written rounded to nearest even.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <puff/core/error.h>

namespace puff::core {

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> pixels;  ///< width * height * channels values, row 0 at the top

  Image() = default;
  Image(int w, int h, int c, float fill = 0.0f)
      : width(w), height(h), channels(c), pixels(static_cast<std::size_t>(w) * h * c, fill) {}

  std::size_t index(int x, int y, int c = 0) const { return (static_cast<std::size_t>(y) * width + x) * channels + c; }
  float& at(int x, int y, int c = 0) { return pixels[index(x, y, c)]; }
  float at(int x, int y, int c = 0) const { return pixels[index(x, y, c)]; }
  bool empty() const { return pixels.empty(); }
};

/// How a file stores the values: 8- or 16-bit unsigned normalized (values clamped to [0,1] and
/// rounded), or 16-/32-bit float.
enum class PixelType { kUInt8, kUInt16, kHalf, kFloat };

/// Extra string attributes written into the file's metadata (EXR header, PNG text).
using ImageAttributes = std::vector<std::pair<std::string, std::string>>;

/// What a file held besides its pixels: how it stored them, and its "puff:" string attributes (the
/// ones Puff writes; a codec may return others).
struct ImageFileInfo {
  PixelType type = PixelType::kFloat;
  ImageAttributes attributes;
};

/// What a caller accepts from an image file, checked against the file's size and its header before
/// any pixel is decoded, so that a small file claiming a huge image costs nothing. Every use of an
/// image has its own (ramps, gradients, atlas maps, detail clips, plates: each documents its
/// limits beside its format); the defaults are the most any image may be.
struct ImageLimits {
  const char* use = "an image";  ///< for messages: "a ramp", "an atlas map", ...
  int maxWidth = 16384, maxHeight = 16384;
  int maxChannels = 4;  ///< files with more channels are refused
  /// At most this many pixels (width * height) whatever the sides.
  long long maxPixels = 1ll << 28;
  /// The file itself, in bytes (a compressed 16384x16384 image fits in far less).
  std::uintmax_t maxFileBytes = std::uintmax_t{1} << 30;
};

/// The problem with a width x height x channels image under `limits`, or "" when it is within them.
std::string imageLimitProblem(long long width, long long height, int channels, const ImageLimits& limits);

/// The extension of Puff's cooked images.
inline constexpr const char* kCookedImageExtension = ".puffimg";

/// True when `path`'s extension is ".puffimg" (case-insensitive).
bool isCookedImagePath(const std::filesystem::path& path);

/// How a program reads and writes image files other than cooked ones. Plain function pointers, so
/// that a codec is a constant with no constructor; all three are required.
struct ImageCodec {
  const char* name;  ///< for messages, e.g. "OpenImageIO"
  /// Reads the file; refuses, from the header and before decoding, an image outside `limits`
  /// (imageLimitProblem). core has already checked that it is a regular file within maxFileBytes.
  Result<Image> (*read)(const std::filesystem::path& path, ImageFileInfo* info, const ImageLimits& limits);
  Result<std::string> (*readAttribute)(const std::filesystem::path& path, const std::string& name);
  Result<void> (*write)(const std::filesystem::path& path, const Image& image, PixelType type,
                        const ImageAttributes& attributes, const std::filesystem::path& formatHint);
};

/// Installs the codec every later readImage / writeImage of a non-cooked file uses (nullptr: none,
/// the default). Safe to call from any thread; `codec` must outlive its use.
void setImageCodec(const ImageCodec* codec);
/// The installed codec, or nullptr.
const ImageCodec* imageCodec();

/// Writes `image` to exactly `path` (format from `formatHint`'s extension, or `path`'s if empty):
/// ".puffimg" by core itself, anything else through the installed codec (an error without one).
/// Callers that must not clobber outputs write to an OutputTransaction's staged path.
Result<void> writeImage(const std::filesystem::path& path, const Image& image, PixelType type,
                        const ImageAttributes& attributes = {}, const std::filesystem::path& formatHint = {});

/// Reads an image file into floats (unsigned-normalized formats become [0,1]): a cooked image by
/// core itself (recognized by its magic, whatever its name), anything else through the installed
/// codec. `info`, when given, receives the stored pixel type and the attributes.
/// Errors: missing file, not a regular file, unknown format, no codec for it, a truncated or
/// corrupt file, an image of 0 pixels, a file or an image beyond `limits` (found before decoding).
Result<Image> readImage(const std::filesystem::path& path, ImageFileInfo* info = nullptr,
                        const ImageLimits& limits = {});

/// Reads one string attribute from an image file's metadata; empty if absent.
Result<std::string> readImageAttribute(const std::filesystem::path& path, const std::string& name);

}  // namespace puff::core
