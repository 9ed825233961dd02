// Float images in memory and their files (through OpenImageIO). Rows are stored top to bottom,
// channels interleaved; values are whatever the producer put there (usually [0,1]).
#pragma once

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

/// Writes `image` to exactly `path` (format from `formatHint`'s extension, or `path`'s if empty).
/// Callers that must not clobber outputs write to an OutputTransaction's staged path.
Result<void> writeImage(const std::filesystem::path& path, const Image& image, PixelType type,
                        const ImageAttributes& attributes = {}, const std::filesystem::path& formatHint = {});

/// Reads any format OpenImageIO knows into floats (unsigned-normalized formats become [0,1]).
/// Errors: missing file, unknown format, a truncated or corrupt file, an image of 0 pixels.
Result<Image> readImage(const std::filesystem::path& path);

/// Reads one string attribute from an image file's metadata; empty if absent.
Result<std::string> readImageAttribute(const std::filesystem::path& path, const std::string& name);

}  // namespace puff::core
