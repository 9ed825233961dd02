// The OpenImageIO image codec (puff/io/openimageio.h).
#include <puff/io/openimageio.h>

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <mutex>

#include <OpenImageIO/imageio.h>

namespace puff::io {

namespace fs = std::filesystem;
using core::Image;
using core::ImageAttributes;
using core::ImageFileInfo;
using core::PixelType;
using puff::Error;
using puff::Result;

namespace {

OIIO::TypeDesc toTypeDesc(PixelType t) {
  switch (t) {
    case PixelType::kUInt8:
      return OIIO::TypeDesc::UINT8;
    case PixelType::kUInt16:
      return OIIO::TypeDesc::UINT16;
    case PixelType::kHalf:
      return OIIO::TypeDesc::HALF;
    case PixelType::kFloat:
      return OIIO::TypeDesc::FLOAT;
  }
  return OIIO::TypeDesc::UINT8;
}

// The nearest pixel type that holds the file's values without loss (8-bit for 8 bits or fewer,
// 16-bit for more, half and float as they are; anything else reads as float).
PixelType storedType(const OIIO::TypeDesc& t) {
  if (t == OIIO::TypeDesc::UINT8) return PixelType::kUInt8;
  if (t == OIIO::TypeDesc::UINT16) return PixelType::kUInt16;
  if (t == OIIO::TypeDesc::HALF) return PixelType::kHalf;
  return PixelType::kFloat;
}

std::string firstLine(std::string s) {
  if (auto nl = s.find('\n'); nl != std::string::npos) s.resize(nl);
  return s.empty() ? "unknown error" : s;
}

Result<void> write(const fs::path& path, const Image& image, PixelType type, const ImageAttributes& attributes,
                   const fs::path& formatHint) {
  const fs::path& naming = formatHint.empty() ? path : formatHint;
  auto out = OIIO::ImageOutput::create(naming.string());
  if (!out) return Error::at(naming, "cannot write images of this type: " + firstLine(OIIO::geterror()));
  OIIO::ImageSpec spec(image.width, image.height, image.channels, toTypeDesc(type));
  // Same inputs, same bytes: OpenImageIO's EXR writer stamps the current time unless DateTime is
  // set, and an empty value leaves the attribute out.
  spec.attribute("DateTime", "");
  for (const auto& [key, value] : attributes) spec.attribute(key, value);
  // Puff's four-channel images are straight values (and normalDepth's fourth channel is depth,
  // not alpha): never let OpenImageIO divide by "alpha" on the way out.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  if (type == PixelType::kHalf || type == PixelType::kFloat) spec.attribute("compression", "zip");
  // Unsigned-normalized outputs: clamp first so out-of-range values never wrap.
  std::vector<float> clamped;
  const float* data = image.pixels.data();
  if (type == PixelType::kUInt8 || type == PixelType::kUInt16) {
    clamped.resize(image.pixels.size());
    for (std::size_t i = 0; i < clamped.size(); ++i) {
      const float v = image.pixels[i];
      clamped[i] = v != v ? 0.0f : (v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v));
    }
    data = clamped.data();
  }
  // Errors name the user's file (`naming`): `path` may be a staged temporary.
  if (!out->open(path.string(), spec)) return Error::at(naming, "cannot write: " + firstLine(out->geterror()));
  if (!out->write_image(OIIO::TypeDesc::FLOAT, data)) {
    std::string err = firstLine(out->geterror());
    out->close();
    return Error::at(naming, "write failed: " + err);
  }
  if (!out->close()) return Error::at(naming, "write failed: " + firstLine(out->geterror()));
  return {};
}

// libpng, under OpenImageIO's PNG reader, prints its own "libpng error: ..." and "libpng warning:
// ..." lines on stderr before OpenImageIO returns the error Puff reports in one line. While an
// image is read, stderr goes to a temporary file; afterwards every line but libpng's goes back
// to stderr. Reads take turns (stderr is one per process); other threads' lines written meanwhile
// come out after the read, in order.
class LibpngLinesDropped {
 public:
  LibpngLinesDropped() : lock_(mutex()) {
    std::fflush(stderr);
    capture_ = std::tmpfile();
    if (!capture_) return;  // no temporary file: libpng's lines stay, nothing else changes
    saved_ = ::dup(STDERR_FILENO);
    if (saved_ < 0 || ::dup2(::fileno(capture_), STDERR_FILENO) < 0) {
      if (saved_ >= 0) ::close(saved_);
      std::fclose(capture_);
      capture_ = nullptr;
    }
  }
  ~LibpngLinesDropped() {
    if (!capture_) return;
    std::fflush(stderr);
    ::dup2(saved_, STDERR_FILENO);
    ::close(saved_);
    std::rewind(capture_);
    char line[4096];
    while (std::fgets(line, sizeof line, capture_)) {
      if (std::strncmp(line, "libpng ", 7) != 0) std::fputs(line, stderr);
    }
    std::fclose(capture_);
  }
  LibpngLinesDropped(const LibpngLinesDropped&) = delete;
  LibpngLinesDropped& operator=(const LibpngLinesDropped&) = delete;

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  std::FILE* capture_ = nullptr;
  int saved_ = -1;
};

Result<Image> read(const fs::path& path, ImageFileInfo* info, const core::ImageLimits& limits) {
  const LibpngLinesDropped quiet;
  // Read values as stored: no multiplication by a fourth channel that may not be alpha.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) return Error::at(path, "not a readable image: " + firstLine(OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  // From the header alone, before a pixel is decoded.
  if (std::string p = core::imageLimitProblem(spec.width, spec.height, spec.nchannels, limits); !p.empty())
    return Error::at(path, p);
  Image img(spec.width, spec.height, spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.pixels.data())) {
    return Error::at(path, "corrupt or truncated image: " + firstLine(in->geterror()));
  }
  if (info) {
    info->type = storedType(spec.format);
    info->attributes.clear();
    for (const OIIO::ParamValue& p : spec.extra_attribs) {
      const std::string name = p.name().string();
      if (name.rfind("puff:", 0) != 0) continue;
      // Puff writes strings; a tool (oiiotool --attrib puff:frames 4) may store a number instead.
      if (p.type() == OIIO::TypeDesc::STRING) {
        info->attributes.emplace_back(name, std::string(p.get_string()));
      } else if (p.type() == OIIO::TypeDesc::INT) {
        info->attributes.emplace_back(name, std::to_string(p.get_int()));
      }
    }
  }
  in->close();
  return img;
}

Result<std::string> readAttribute(const fs::path& path, const std::string& name) {
  const LibpngLinesDropped quiet;
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return Error::at(path, "not a readable image: " + firstLine(OIIO::geterror()));
  return std::string(in->spec().get_string_attribute(name));
}

constexpr core::ImageCodec kCodec{"OpenImageIO", &read, &readAttribute, &write};

}  // namespace

const core::ImageCodec& openImageIOCodec() { return kCodec; }

void useOpenImageIO() { core::setImageCodec(&kCodec); }

}  // namespace puff::io
