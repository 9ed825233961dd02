#include <puff/core/detail_video.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>

#include <puff/core/files.h>
#include <puff/core/image.h>

namespace puff::core {

namespace fs = std::filesystem;

namespace {

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// "[lo, hi]", appended piece by piece: GCC 12 warns falsely (-Wrestrict) on this chain of operator+.
std::string rangeText(int lo, int hi) {
  std::string s = "[";
  s += std::to_string(lo);
  s += ", ";
  s += std::to_string(hi);
  s += "]";
  return s;
}

// Range checks shared by save and load; "" when the sizes are fine.
std::string sizeProblem(int width, int height, int frames) {
  const std::string range = rangeText(kMinDetailSize, kMaxDetailSize);
  if (width < kMinDetailSize || width > kMaxDetailSize)
    return "detail video width must be in " + range + ", got " + std::to_string(width);
  if (height < kMinDetailSize || height > kMaxDetailSize)
    return "detail video height must be in " + range + ", got " + std::to_string(height);
  if (frames < 1 || frames > kMaxDetailFrames)
    return "detail video frames must be in [1, " + std::to_string(kMaxDetailFrames) + "], got " +
           std::to_string(frames);
  return {};
}

}  // namespace

float DetailVideo::at(int x, int y, int f) const {
  PUFF_CHECK(x >= 0 && x < width && y >= 0 && y < height && f >= 0 && f < frames);
  return values[index(x, y, f)];
}

Result<DetailVideo> loadDetailVideo(const fs::path& path) {
  // One read: the pixels and the puff: attributes together.
  ImageFileInfo info;
  PUFF_TRY_ASSIGN(auto img, readImage(path, &info, kDetailClipLimits));
  const auto attribute = [&](const std::string& name) -> std::optional<std::string> {
    for (const auto& [key, value] : info.attributes) {
      if (key == name) return value;
    }
    return std::nullopt;
  };
  const std::optional<std::string> framesText = attribute("puff:frames");
  if (!framesText || framesText->empty()) {
    return Error::at(path, "missing attribute puff:frames (not a detail video?)");
  }
  char* end = nullptr;
  const long frames = std::strtol(framesText->c_str(), &end, 10);
  if (end != framesText->c_str() + framesText->size() || frames < 1 || frames > kMaxDetailFrames) {
    return Error::at(path, "attribute puff:frames must be an integer in [1, " + std::to_string(kMaxDetailFrames) +
                               "], got \"" + *framesText + "\"");
  }
  if (img.height % frames != 0) {
    return Error::at(path, "image height " + std::to_string(img.height) + " is not a multiple of puff:frames " +
                               std::to_string(frames));
  }
  DetailVideo v;
  v.width = img.width;
  v.height = img.height / static_cast<int>(frames);
  v.frames = static_cast<int>(frames);
  if (std::string p = sizeProblem(v.width, v.height, v.frames); !p.empty()) return Error::at(path, p);
  v.source = attribute("puff:source").value_or("");

  const std::size_t n = static_cast<std::size_t>(img.width) * img.height;
  const int ch = img.channels;
  v.values.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &img.pixels[i * static_cast<std::size_t>(ch)];
    const float value = ch >= 3 ? 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2] : p[0];
    if (!std::isfinite(value)) {
      const std::size_t w = static_cast<std::size_t>(img.width);
      return Error::at(path,
                       "value at pixel (" + std::to_string(i % w) + ", " + std::to_string(i / w) + ") is not finite");
    }
    v.values[i] = std::clamp(value, 0.0f, 1.0f);
  }
  return v;
}

Result<void> saveDetailVideo(const fs::path& path, const DetailVideo& video) {
  const std::string ext = lowerExtension(path);
  PixelType type;
  if (ext == ".png") {
    type = PixelType::kUInt16;
  } else if (ext == ".exr") {
    type = PixelType::kHalf;
  } else {
    return Error::at(path, "a detail video is a .png (16-bit) or .exr (half) file, not \"" + ext + "\"");
  }
  if (std::string p = sizeProblem(video.width, video.height, video.frames); !p.empty()) return Error::at(path, p);
  PUFF_CHECK(video.values.size() == static_cast<std::size_t>(video.width) * video.height * video.frames);
  Image img(video.width, video.height * video.frames, 1);
  std::copy(video.values.begin(), video.values.end(), img.pixels.begin());
  ImageAttributes attributes = {{"puff:frames", std::to_string(video.frames)}};
  if (!video.source.empty()) attributes.emplace_back("puff:source", video.source);
  OutputTransaction tx;
  PUFF_TRY(tx.prepareDirectory(path.parent_path()));
  PUFF_TRY(writeImage(tx.stage(path), img, type, attributes, path));
  return tx.commit();
}

}  // namespace puff::core
