// Images in memory and their files: Puff's cooked images (".puffimg", read and written here with no
// image library) and the installed codec for every other format (image.h).
#include <puff/core/image.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

namespace puff::core {

namespace fs = std::filesystem;

namespace {

constinit std::atomic<const ImageCodec*> gCodec{nullptr};

constexpr char kMagic[8] = {'P', 'U', 'F', 'F', 'I', 'M', 'G', '\0'};
constexpr std::uint32_t kVersion = 1;
constexpr std::uint32_t kMaxAttributes = 64;
constexpr std::uint32_t kMaxAttributeBytes = 64 * 1024;
constexpr std::size_t kHeaderBytes = 32;  // magic and six u32
constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull, kFnvPrime = 0x100000001b3ull;

std::size_t bytesPerValue(PixelType t) {
  switch (t) {
    case PixelType::kUInt8:
      return 1;
    case PixelType::kUInt16:
    case PixelType::kHalf:
      return 2;
    case PixelType::kFloat:
      return 4;
  }
  return 4;
}

// IEEE 754 binary16 from binary32, rounded to nearest even (NaN stays NaN, quiet).
std::uint16_t halfFromFloat(float value) {
  std::uint32_t u = std::bit_cast<std::uint32_t>(value);
  const std::uint32_t sign = (u >> 16) & 0x8000u;
  u &= 0x7fffffffu;
  std::uint32_t h;
  if (u >= 0x47800000u) {  // |x| >= 65536, inf or NaN: no finite half holds it
    h = u > 0x7f800000u ? 0x7e00u : 0x7c00u;
  } else if (u < 0x38800000u) {  // under 2^-14: a subnormal half or zero
    // Adding 0.5 puts the value's 2^-24 units in the float's low mantissa bits; the float addition
    // rounds them to nearest even.
    const float shifted = std::bit_cast<float>(u) + 0.5f;
    h = std::bit_cast<std::uint32_t>(shifted) - 0x3f000000u;
  } else {
    const std::uint32_t odd = (u >> 13) & 1u;
    u += 0xc8000fffu + odd;  // rebias the exponent (-112 << 23) and round the 13 dropped bits
    h = u >> 13;             // a carry out of the mantissa rounds up to the next exponent, or to inf
  }
  return static_cast<std::uint16_t>(h | sign);
}

float floatFromHalf(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu;
  if (exponent == 0) {
    const float v = static_cast<float>(mantissa) * 0x1p-24f;
    return sign ? -v : v;
  }
  if (exponent == 31) return std::bit_cast<float>(sign | 0x7f800000u | (mantissa << 13));
  return std::bit_cast<float>(sign | ((exponent + 112u) << 23) | (mantissa << 13));
}

void putU32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}

void putU64(std::string& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}

std::uint64_t fnv1a(const char* data, std::size_t n) {
  std::uint64_t h = kFnvOffset;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= kFnvPrime;
  }
  return h;
}

float unitClamped(float v) { return v != v ? 0.0f : std::clamp(v, 0.0f, 1.0f); }

// Writes exactly `path`; errors name `name`, the user's file (`path` may be a staged temporary).
Result<void> writeCooked(const fs::path& path, const fs::path& name, const Image& image, PixelType type,
                         const ImageAttributes& attributes) {
  if (image.channels > 4) {
    return Error::at(name, "cannot write " + std::to_string(image.channels) + " channels (cooked images hold 1-4)");
  }
  if (attributes.size() > kMaxAttributes) return Error::at(name, "too many attributes for a cooked image");
  std::string out(kMagic, sizeof kMagic);
  for (std::uint32_t v : {kVersion, static_cast<std::uint32_t>(image.width), static_cast<std::uint32_t>(image.height),
                          static_cast<std::uint32_t>(image.channels), static_cast<std::uint32_t>(type),
                          static_cast<std::uint32_t>(attributes.size())}) {
    putU32(out, v);
  }
  for (const auto& [key, value] : attributes) {
    if (key.size() > kMaxAttributeBytes || value.size() > kMaxAttributeBytes) {
      return Error::at(name, "attribute " + key.substr(0, 64) + " is longer than a cooked image holds (64 KiB)");
    }
    putU32(out, static_cast<std::uint32_t>(key.size()));
    out += key;
    putU32(out, static_cast<std::uint32_t>(value.size()));
    out += value;
  }
  const std::size_t header = out.size();
  out.resize(header + image.pixels.size() * bytesPerValue(type));
  auto* p = reinterpret_cast<unsigned char*>(out.data() + header);
  for (float v : image.pixels) {
    switch (type) {
      case PixelType::kUInt8:
        *p++ = static_cast<unsigned char>(unitClamped(v) * 255.0f + 0.5f);
        break;
      case PixelType::kUInt16: {
        const auto q = static_cast<std::uint16_t>(unitClamped(v) * 65535.0f + 0.5f);
        *p++ = static_cast<unsigned char>(q & 0xffu);
        *p++ = static_cast<unsigned char>(q >> 8);
        break;
      }
      case PixelType::kHalf: {
        const std::uint16_t q = halfFromFloat(v);
        *p++ = static_cast<unsigned char>(q & 0xffu);
        *p++ = static_cast<unsigned char>(q >> 8);
        break;
      }
      case PixelType::kFloat: {
        const std::uint32_t q = std::bit_cast<std::uint32_t>(v);
        for (int i = 0; i < 4; ++i) *p++ = static_cast<unsigned char>((q >> (8 * i)) & 0xffu);
        break;
      }
    }
  }
  putU64(out, fnv1a(out.data(), out.size()));
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return Error::at(name, std::string("cannot write: ") + std::strerror(errno));
  f.write(out.data(), static_cast<std::streamsize>(out.size()));
  f.close();
  if (!f) return Error::at(name, "write failed (disk full?)");
  return {};
}

// A bounds-checked little-endian reader over a file's bytes.
class Reader {
 public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  bool u32(std::uint32_t& v) {
    if (bytes_.size() - pos_ < 4) return false;
    v = 0;
    for (int i = 0; i < 4; ++i)
      v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes_[pos_ + i])) << (8 * i);
    pos_ += 4;
    return true;
  }
  bool text(std::uint32_t n, std::string& v) {
    if (bytes_.size() - pos_ < n) return false;
    v.assign(bytes_, pos_, n);
    pos_ += n;
    return true;
  }
  void skip(std::size_t n) { pos_ += std::min(n, left()); }
  std::size_t pos() const { return pos_; }
  std::size_t left() const { return bytes_.size() - pos_; }

 private:
  const std::string& bytes_;
  std::size_t pos_ = sizeof kMagic;
};

bool startsWithMagic(const std::string& bytes) {
  return bytes.size() >= sizeof kMagic && std::memcmp(bytes.data(), kMagic, sizeof kMagic) == 0;
}

// A cooked image's header fields (after the magic).
struct CookedHeader {
  std::uint32_t version = 0, width = 0, height = 0, channels = 0, type = 0, count = 0;
};

// Checks the header against the format and `limits`; `size` is the file's size.
Result<CookedHeader> checkCookedHeader(const fs::path& path, const std::string& head, std::uintmax_t size,
                                       const ImageLimits& limits) {
  Reader r(head);
  CookedHeader h;
  const auto truncated = [&] { return Error::at(path, "truncated cooked image (" + std::to_string(size) + " bytes)"); };
  if (!r.u32(h.version)) return truncated();
  if (h.version != kVersion) {
    return Error::at(path, "cooked image version " + std::to_string(h.version) + ", this Puff reads version " +
                               std::to_string(kVersion) + " (cook it again with this Puff's puffbake)");
  }
  if (!r.u32(h.width) || !r.u32(h.height) || !r.u32(h.channels) || !r.u32(h.type) || !r.u32(h.count))
    return truncated();
  if (h.width == 0 || h.height == 0) return Error::at(path, "image has no pixels");
  if (h.channels < 1 || h.channels > 4)
    return Error::at(path, "cooked image with " + std::to_string(h.channels) + " channels (1-4)");
  if (std::string p = imageLimitProblem(h.width, h.height, static_cast<int>(h.channels), limits); !p.empty()) {
    return Error::at(path, p);
  }
  if (h.type > static_cast<std::uint32_t>(PixelType::kFloat))
    return Error::at(path, "unknown pixel type " + std::to_string(h.type));
  if (h.count > kMaxAttributes)
    return Error::at(path, std::to_string(h.count) + " attributes (a cooked image holds at most 64)");
  // Header, attributes, the pixels and the hash: nothing larger is valid.
  const std::uintmax_t largest =
      kHeaderBytes + h.count * 2 * (4 + std::uintmax_t{kMaxAttributeBytes}) +
      std::uintmax_t{h.width} * h.height * h.channels * bytesPerValue(static_cast<PixelType>(h.type)) + 8;
  if (size > largest) {
    return Error::at(path, "cooked image of " + std::to_string(size) + " bytes is larger than its header allows (" +
                               std::to_string(largest) + ")");
  }
  return h;
}

Result<Image> parseCooked(const fs::path& path, const std::string& bytes, ImageFileInfo* info,
                          const ImageLimits& limits) {
  PUFF_TRY_ASSIGN(auto header, checkCookedHeader(path, bytes.substr(0, kHeaderBytes), bytes.size(), limits));
  const auto [version, width, height, channels, type, count] = header;
  (void)version;
  Reader r(bytes);
  r.skip(kHeaderBytes - sizeof kMagic);
  const auto truncated = [&] {
    return Error::at(path, "truncated cooked image (" + std::to_string(bytes.size()) + " bytes)");
  };
  ImageAttributes attributes;
  for (std::uint32_t i = 0; i < count; ++i) {
    std::uint32_t n;
    std::string key, value;
    if (!r.u32(n)) return truncated();
    if (n > kMaxAttributeBytes) return Error::at(path, "attribute name longer than 64 KiB");
    if (!r.text(n, key) || !r.u32(n)) return truncated();
    if (n > kMaxAttributeBytes) return Error::at(path, "attribute value longer than 64 KiB");
    if (!r.text(n, value)) return truncated();
    attributes.emplace_back(std::move(key), std::move(value));
  }
  const auto pixelType = static_cast<PixelType>(type);
  const std::size_t values = static_cast<std::size_t>(width) * height * channels;
  const std::size_t pixelBytes = values * bytesPerValue(pixelType);
  if (r.left() < pixelBytes + 8) return truncated();
  if (r.left() > pixelBytes + 8) {
    const std::size_t extra = r.left() - pixelBytes - 8;
    return Error::at(path, std::to_string(extra) + (extra == 1 ? " byte" : " bytes") + " after the cooked image's end");
  }
  const std::size_t end = r.pos() + pixelBytes;
  std::uint64_t stored = 0;
  for (int i = 0; i < 8; ++i)
    stored |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[end + i])) << (8 * i);
  if (stored != fnv1a(bytes.data(), end))
    return Error::at(path, "corrupt cooked image (its hash does not match its bytes)");

  Image img(static_cast<int>(width), static_cast<int>(height), static_cast<int>(channels));
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + r.pos());
  for (float& v : img.pixels) {
    switch (pixelType) {
      case PixelType::kUInt8:
        v = static_cast<float>(*p++) * (1.0f / 255.0f);
        break;
      case PixelType::kUInt16:
        v = static_cast<float>(p[0] | (p[1] << 8)) * (1.0f / 65535.0f);
        p += 2;
        break;
      case PixelType::kHalf:
        v = floatFromHalf(static_cast<std::uint16_t>(p[0] | (p[1] << 8)));
        p += 2;
        break;
      case PixelType::kFloat:
        v = std::bit_cast<float>(static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
                                 (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24));
        p += 4;
        break;
    }
  }
  if (info) {
    info->type = pixelType;
    info->attributes = std::move(attributes);
  }
  return img;
}

// The file's bytes when it is a cooked image within `limits` (checked from its header first); an
// empty string (and no error) when it is another format within maxFileBytes.
Result<std::string> readIfCooked(const fs::path& path, const ImageLimits& limits) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (!fs::exists(status)) return Error::at(path, "cannot open: no such file");
  if (fs::is_directory(status)) return Error::at(path, "cannot open: is a directory");
  if (!fs::is_regular_file(status)) return Error::at(path, "cannot open: not a regular file");
  const auto size = fs::file_size(path, ec);
  if (ec) return Error::at(path, "cannot read its size: " + ec.message());
  if (size > limits.maxFileBytes) {
    return Error::at(path, "a file of " + std::to_string(size) + " bytes is larger than " + limits.use + " may be (" +
                               std::to_string(limits.maxFileBytes) + " bytes)");
  }
  std::ifstream f(path, std::ios::binary);
  if (!f) return Error::at(path, std::string("cannot open: ") + std::strerror(errno));
  std::string head(kHeaderBytes, '\0');
  f.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(f.gcount()));
  if (!startsWithMagic(head)) return std::string();  // another format: the codec's
  if (auto header = checkCookedHeader(path, head, size, limits); !header) return header.error();
  std::string bytes(static_cast<std::size_t>(size), '\0');
  f.seekg(0);
  f.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (static_cast<std::uintmax_t>(f.gcount()) != size)
    return Error::at(path, "cannot read: the file changed while read");
  return bytes;
}

std::string extensionOf(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// No codec for a file that is not cooked (one named .puffimg without the magic is damaged).
Error noCodec(const fs::path& path, const char* verb) {
  if (isCookedImagePath(path)) return Error::at(path, "not a cooked image (no PUFFIMG magic)");
  const std::string ext = path.extension().string();
  return Error::at(path, std::string("cannot ") + verb + " " + (ext.empty() ? "this file" : ext + " files") +
                             ": this program reads and writes only cooked images (" + kCookedImageExtension +
                             "); cook the file with `puffbake cook`, or link puff::io and call "
                             "puff::io::useOpenImageIO() first");
}

}  // namespace

bool isCookedImagePath(const fs::path& path) { return extensionOf(path) == kCookedImageExtension; }

void setImageCodec(const ImageCodec* codec) {
  PUFF_CHECK(codec == nullptr || (codec->name && codec->read && codec->readAttribute && codec->write));
  gCodec.store(codec);
}

const ImageCodec* imageCodec() { return gCodec.load(); }

Result<void> writeImage(const fs::path& path, const Image& image, PixelType type, const ImageAttributes& attributes,
                        const fs::path& formatHint) {
  PUFF_CHECK(image.width > 0 && image.height > 0 && image.channels > 0);
  PUFF_CHECK(image.pixels.size() == static_cast<std::size_t>(image.width) * image.height * image.channels);
  const fs::path& naming = formatHint.empty() ? path : formatHint;
  if (isCookedImagePath(naming)) return writeCooked(path, naming, image, type, attributes);
  const ImageCodec* codec = imageCodec();
  if (!codec) return noCodec(naming, "write");
  return codec->write(path, image, type, attributes, formatHint);
}

std::string imageLimitProblem(long long width, long long height, int channels, const ImageLimits& limits) {
  const auto size = [](long long w, long long h) { return std::to_string(w) + "x" + std::to_string(h); };
  if (width < 1 || height < 1) return "image has no pixels";
  if (width > limits.maxWidth || height > limits.maxHeight || width * height > limits.maxPixels) {
    std::string p = "a " + size(width, height) + " image is larger than " + limits.use + " may be (at most " +
                    size(limits.maxWidth, limits.maxHeight);
    if (static_cast<long long>(limits.maxWidth) * limits.maxHeight > limits.maxPixels)
      p += " and " + std::to_string(limits.maxPixels) + " pixels";
    return p + ")";
  }
  if (channels < 1) return "image has no channels";
  if (channels > limits.maxChannels) {
    return "has " + std::to_string(channels) + " channels, more than " + limits.use + " may have (1 to " +
           std::to_string(limits.maxChannels) + ")";
  }
  return {};
}

Result<Image> readImage(const fs::path& path, ImageFileInfo* info, const ImageLimits& limits) {
  PUFF_TRY_ASSIGN(auto cooked, readIfCooked(path, limits));
  if (!cooked.empty()) return parseCooked(path, cooked, info, limits);
  const ImageCodec* codec = imageCodec();
  if (!codec) return noCodec(path, "read");
  return codec->read(path, info, limits);
}

Result<std::string> readImageAttribute(const fs::path& path, const std::string& name) {
  const ImageLimits limits;
  PUFF_TRY_ASSIGN(auto cooked, readIfCooked(path, limits));
  if (!cooked.empty()) {
    ImageFileInfo info;
    PUFF_TRY_ASSIGN(auto img, parseCooked(path, cooked, &info, limits));
    for (const auto& [key, value] : info.attributes) {
      if (key == name) return value;
    }
    return std::string();
  }
  const ImageCodec* codec = imageCodec();
  if (!codec) return noCodec(path, "read");
  return codec->readAttribute(path, name);
}

}  // namespace puff::core
