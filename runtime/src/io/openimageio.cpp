// The OpenImageIO image codec (puff/io/openimageio.h).
#include <puff/io/openimageio.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
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

// OpenEXR allocates each header attribute at the size the file claims before reading it, so a few
// hundred bytes claiming a 2 GB attribute cost 2 GB and seconds. An EXR file's headers (every part
// of a multi-part file) are walked here first, and any attribute claiming more bytes than the file
// has left is refused. Other formats, and a file that cannot be opened, are left to OpenImageIO.
// An attribute's name as the file holds it, fit for a one-line message: printable ASCII as it is,
// any other byte as \xNN.
std::string printable(std::string_view name) {
  std::string out;
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", u);
      out += hex;
    }
  }
  return out;
}

std::string exrHeaderProblem(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return {};
  f.seekg(0, std::ios::end);
  const std::int64_t size = f.tellg();
  f.seekg(0);
  unsigned char magic[8] = {};
  if (!f.read(reinterpret_cast<char*>(magic), 8) || magic[0] != 0x76 || magic[1] != 0x2f || magic[2] != 0x31 ||
      magic[3] != 0x01)
    return {};
  const bool multiPart = (magic[5] & 0x10) != 0;  // version flags, bit 12
  constexpr int kMaxAttributes = 100000;
  std::int64_t pos = 8;
  for (int attributes = 0; attributes < kMaxAttributes; ++attributes) {
    // An attribute: its name and type name, each NUL-terminated (at most 255 characters), its size
    // (int32, little-endian), its value. An empty name ends a header; a multi-part file's headers
    // end with an empty one.
    char buf[520] = {};
    f.clear();
    f.seekg(pos);
    f.read(buf, sizeof buf);
    const std::int64_t got = f.gcount();
    if (got == 0) return "EXR header ends before its end";
    if (buf[0] == '\0') {
      if (!multiPart) return {};
      if (got < 2 || buf[1] == '\0') return {};
      pos += 1;
      continue;
    }
    const char* nameEnd = static_cast<const char*>(std::memchr(buf, '\0', static_cast<std::size_t>(got)));
    if (!nameEnd || nameEnd - buf > 255) return "EXR header attribute name is not terminated";
    const std::int64_t typeAt = nameEnd - buf + 1;
    const char* typeEnd = static_cast<const char*>(
        std::memchr(buf + typeAt, '\0', static_cast<std::size_t>(std::max<std::int64_t>(0, got - typeAt))));
    if (!typeEnd || typeEnd - (buf + typeAt) > 255) return "EXR header attribute type is not terminated";
    const std::int64_t sizeAt = typeEnd - buf + 1;
    if (sizeAt + 4 > got) return "EXR header ends inside attribute '" + printable(buf) + "'";
    const auto* b = reinterpret_cast<const unsigned char*>(buf + sizeAt);
    const std::int32_t claimed =
        static_cast<std::int32_t>(static_cast<std::uint32_t>(b[0]) | (std::uint32_t(b[1]) << 8) |
                                  (std::uint32_t(b[2]) << 16) | (std::uint32_t(b[3]) << 24));
    const std::int64_t valueAt = pos + sizeAt + 4;
    if (claimed < 0 || claimed > size - valueAt) {
      return "EXR header attribute '" + printable(buf) + "' claims " + std::to_string(claimed) +
             " bytes; the file has " + std::to_string(std::max<std::int64_t>(0, size - valueAt)) + " left";
    }
    pos = valueAt + claimed;
  }
  return "EXR header has more than " + std::to_string(kMaxAttributes) + " attributes";
}

Result<Image> read(const fs::path& path, ImageFileInfo* info, const core::ImageLimits& limits) {
  if (std::string p = exrHeaderProblem(path); !p.empty()) return Error::at(path, "not a readable image: " + p);
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
  if (std::string p = exrHeaderProblem(path); !p.empty()) return Error::at(path, "not a readable image: " + p);
  const LibpngLinesDropped quiet;
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return Error::at(path, "not a readable image: " + firstLine(OIIO::geterror()));
  return std::string(in->spec().get_string_attribute(name));
}

constexpr core::ImageCodec kCodec{"OpenImageIO", &read, &readAttribute, &write};

}  // namespace

const core::ImageCodec& openImageIOCodec() { return kCodec; }

bool canWriteGif() {
  static const bool can = [] { return OIIO::ImageOutput::create("probe.gif") != nullptr; }();
  return can;
}

GifTiming gifTiming(int count, double fps) {
  GifTiming t;
  if (count < 1 || !(fps > 0.0)) return t;
  t.delay = std::max(2, static_cast<int>(std::lround(100.0 / fps)));
  // GIF frame k shows at k * delay / 100 s: the sequence's frame due then.
  for (int k = 0;; ++k) {
    const double due = static_cast<double>(k) * t.delay / 100.0 * fps;
    const int frame = static_cast<int>(std::floor(due + 1e-9));
    if (frame >= count) break;
    t.source.push_back(frame);
  }
  return t;
}

struct AnimatedGif::Impl {
  std::unique_ptr<OIIO::ImageOutput> out;
  std::vector<OIIO::ImageSpec> specs;
  fs::path path, naming;
  int width = 0, height = 0, added = 0;
  std::vector<float> rgb;
};

AnimatedGif::AnimatedGif() : impl_(std::make_unique<Impl>()) {}
AnimatedGif::~AnimatedGif() {
  if (impl_ && impl_->out && impl_->added > 0) impl_->out->close();
}

Result<std::unique_ptr<AnimatedGif>> AnimatedGif::open(const fs::path& path, int frames, int width, int height,
                                                       int delay, const fs::path& name) {
  std::unique_ptr<AnimatedGif> gif(new AnimatedGif());
  Impl& m = *gif->impl_;
  m.path = path;
  m.naming = name.empty() ? path : name;
  if (frames < 1 || width < 1 || height < 1) return Error::at(m.naming, "an animated GIF needs at least one frame");
  m.out = OIIO::ImageOutput::create("animation.gif");
  if (!m.out) return Error::at(m.naming, "this OpenImageIO has no GIF writer: " + firstLine(OIIO::geterror()));
  if (frames > 1 && !m.out->supports("appendsubimage")) {
    return Error::at(m.naming, "this OpenImageIO's GIF writer cannot append frames");
  }
  m.width = width;
  m.height = height;
  // GIF keeps one delay between frames, in hundredths of a second; OpenImageIO's writer takes it as
  // the frame rate 100 / delay.
  if (delay < 1 || delay > 65535)
    return Error::at(m.naming, "a GIF's frame delay is 1 to 65535 hundredths of a second");
  const int fpsRational[2] = {100, delay};
  m.specs.assign(static_cast<std::size_t>(frames), OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8));
  for (OIIO::ImageSpec& spec : m.specs) {
    spec.attribute("FramesPerSecond", OIIO::TypeRational, fpsRational);
    spec.attribute("oiio:Movie", 1);
    spec.attribute("gif:LoopCount", 0);  // forever
  }
  m.rgb.resize(static_cast<std::size_t>(width) * height * 3);
  return gif;
}

Result<void> AnimatedGif::add(const Image& f) {
  Impl& m = *impl_;
  if (m.added >= static_cast<int>(m.specs.size())) {
    return Error::at(m.naming, "more frames than the " + std::to_string(m.specs.size()) + " it was opened for");
  }
  if (f.width != m.width || f.height != m.height || f.channels < 3) {
    return Error::at(m.naming, "frame " + std::to_string(m.added) + " is " + std::to_string(f.width) + "x" +
                                   std::to_string(f.height) + "x" + std::to_string(f.channels) + ", not " +
                                   std::to_string(m.width) + "x" + std::to_string(m.height) + " RGB");
  }
  const bool opened = m.added == 0 ? m.out->open(m.path.string(), static_cast<int>(m.specs.size()), m.specs.data())
                                   : m.out->open(m.path.string(), m.specs[static_cast<std::size_t>(m.added)],
                                                 OIIO::ImageOutput::AppendSubimage);
  if (!opened) return Error::at(m.naming, "cannot write: " + firstLine(m.out->geterror()));
  ++m.added;
  const std::size_t pixels = static_cast<std::size_t>(m.width) * m.height;
  for (std::size_t p = 0; p < pixels; ++p) {
    for (std::size_t c = 0; c < 3; ++c) {
      const float v = f.pixels[p * static_cast<std::size_t>(f.channels) + c];
      m.rgb[p * 3 + c] = v != v ? 0.0f : std::clamp(v, 0.0f, 1.0f);
    }
  }
  if (!m.out->write_image(OIIO::TypeDesc::FLOAT, m.rgb.data())) {
    return Error::at(m.naming, "write failed: " + firstLine(m.out->geterror()));
  }
  return {};
}

Result<void> AnimatedGif::close() {
  Impl& m = *impl_;
  if (m.added != static_cast<int>(m.specs.size())) {
    return Error::at(m.naming, std::to_string(m.added) + " of the " + std::to_string(m.specs.size()) +
                                   " frames it was opened for were written");
  }
  m.added = 0;  // closed: the destructor has nothing to do
  if (!m.out->close()) return Error::at(m.naming, "write failed: " + firstLine(m.out->geterror()));
  return {};
}

void useOpenImageIO() { core::setImageCodec(&kCodec); }

}  // namespace puff::io
