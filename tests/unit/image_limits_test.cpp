// Limits before work: every use of an image refuses, from the file's size and its header
// and before a pixel is decoded, an image larger than that use may be (docs/file-formats.md). The
// files here claim huge images and hold no pixels at all: an error that names the use's limit (not
// "truncated" or "corrupt") proves the header was checked first, and nothing was allocated for
// the pixels a decoder would have produced.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>

#include <puff/cel/frame.h>
#include <puff/core/atlas.h>
#include <puff/core/blackbody.h>
#include <puff/core/detail_video.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/mesh/mesh.h>
#include <puff/render/plate.h>
#include <puff/scene/scene.h>

#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using puff::Result;

std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return ~c;
}

void putBigEndian(std::string& out, std::uint32_t v) {
  for (int i = 3; i >= 0; --i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}

std::string pngChunk(const std::string& type, const std::string& data) {
  std::string c;
  putBigEndian(c, static_cast<std::uint32_t>(data.size()));
  c += type + data;
  putBigEndian(c, crc32(type + data));
  return c;
}

// A PNG that is all header: IHDR claiming width x height, 8-bit RGBA, then an IDAT holding only a
// zlib header (a decoder would fail on it at once), and IEND.
std::string pngClaiming(std::uint32_t width, std::uint32_t height) {
  std::string ihdr;
  putBigEndian(ihdr, width);
  putBigEndian(ihdr, height);
  ihdr += std::string("\x08\x06\x00\x00\x00", 5);  // bit depth 8, RGBA, deflate, no filter, no interlace
  return std::string("\x89PNG\r\n\x1a\n", 8) + pngChunk("IHDR", ihdr) + pngChunk("IDAT", "\x78\x9c") +
         pngChunk("IEND", "");
}

// A cooked image that is all header (core/image.h's layout): width x height x 4, 8-bit, no
// attributes, and no pixels or hash after it.
std::string cookedClaiming(std::uint32_t width, std::uint32_t height) {
  std::string b("PUFFIMG\0", 8);
  for (std::uint32_t v : {1u, width, height, 4u, 0u, 0u}) {
    for (int i = 0; i < 4; ++i) b.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
  }
  return b;
}

class ImageLimits : public ::testing::Test {
 protected:
  // The error reading `bytes` as `name` in each way a use reads it.
  template <class Read>
  std::string errorOf(const std::string& name, const std::string& bytes, Read read) {
    const fs::path file = dir_ / name;
    EXPECT_OK(puff::core::writeFileBytes(file, bytes));
    auto r = read(file);
    if (r.ok()) return "accepted";
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
    return r.error().message;
  }
  // Both kinds of file (a PNG through the codec, a cooked image by core) claiming width x height:
  // the same message, which names the file.
  template <class Read>
  void expectRefused(std::uint32_t width, std::uint32_t height, Read read, const std::string& problem) {
    for (const auto& [name, bytes] : {std::pair{std::string("claim.png"), pngClaiming(width, height)},
                                      std::pair{std::string("claim.puffimg"), cookedClaiming(width, height)}}) {
      SCOPED_TRACE(name);
      EXPECT_EQ(errorOf(name, bytes, read), (dir_ / name).string() + ": " + problem);
    }
  }
  puff::test::ScopedTempDir dir_{"puff_limits"};
};

TEST_F(ImageLimits, EachUseRefusesAHugeImageFromItsHeader) {
  // Any image (puffbake cook and every reader without a use of its own).
  const auto any = [](const fs::path& f) { return puff::core::readImage(f); };
  expectRefused(20000, 20000, any, "a 20000x20000 image is larger than an image may be (at most 16384x16384)");
  expectRefused(16384, 16385, any, "a 16384x16385 image is larger than an image may be (at most 16384x16384)");
  // A 1 MB PNG claiming 16384 x 16384: over 9 GB as a gradient.
  const auto gradient = [](const fs::path& f) { return puff::cel::Gradient::read(f); };
  expectRefused(16384, 16384, gradient, "a 16384x16384 image is larger than a gradient may be (at most 4096x4096)");
  expectRefused(4097, 1, gradient, "a 4097x1 image is larger than a gradient may be (at most 4096x4096)");
  const auto ramp = [](const fs::path& f) { return puff::cel::Ramp::read(f); };
  expectRefused(16384, 16384, ramp, "a 16384x16384 image is larger than a ramp may be (at most 16384x256)");
  expectRefused(2, 257, ramp, "a 2x257 image is larger than a ramp may be (at most 16384x256)");
  const auto detail = [](const fs::path& f) { return puff::core::loadDetailVideo(f); };
  expectRefused(16384, 16384, detail,
                "a 16384x16384 image is larger than a detail clip may be (at most 4096x4194304 and 67108864 pixels)");
  expectRefused(4096, 16385, detail,
                "a 4096x16385 image is larger than a detail clip may be (at most 4096x4194304 and 67108864 pixels)");
  const auto blackbody = [](const fs::path& f) { return puff::core::readBlackbodyRamp(f); };
  expectRefused(65536, 65536, blackbody,
                "a 65536x65536 image is larger than a black-body ramp may be (at most 65536x16)");
  expectRefused(65537, 1, blackbody, "a 65537x1 image is larger than a black-body ramp may be (at most 65536x16)");
}

TEST_F(ImageLimits, APlateIsRefusedFromItsHeaderAndNamedByTheScene) {
  puff::scene::Scene scene;
  scene.file = dir_ / "scene.json";
  scene.plate = dir_ / "claim.png";
  ASSERT_OK(puff::core::writeFileBytes(scene.plate, pngClaiming(8193, 8192)));
  auto plate = puff::render::loadPlate(scene);
  ASSERT_FALSE(plate.ok());
  EXPECT_EQ(plate.error().message, scene.file.string() + ": /output/plate: " + scene.plate.string() +
                                       ": a 8193x8192 image is larger than a plate may be (at most 8192x8192)");
}

TEST_F(ImageLimits, AnAtlasMapMayBeNoLargerThanItsLevel) {
  // The small baked atlas of the fuzz seeds (48 x 48, two levels).
  const fs::path seeds = fs::path(PUFF_SOURCE_DIR) / "tests" / "fuzz" / "seeds" / "atlas";
  for (const auto& entry : fs::directory_iterator(seeds)) fs::copy_file(entry.path(), dir_ / entry.path().filename());
  ASSERT_OK(puff::core::loadAtlas(dir_ / "tiny.json"));
  // Level 1 is 24 x 24: a file that claims 25 x 24 there, or 16384 x 16384, is refused before decoding.
  for (const auto& [w, h] : {std::pair{25u, 24u}, std::pair{16384u, 16384u}}) {
    for (const auto& [level, bytes] : {std::pair{std::string("tiny_color.mip1.png"), pngClaiming(w, h)},
                                       std::pair{std::string("tinyc_color.mip1.puffimg"), cookedClaiming(w, h)}}) {
      SCOPED_TRACE(level);
      const std::string saved = *puff::core::readFileBytes(dir_ / level);
      ASSERT_OK(puff::core::writeFileBytes(dir_ / level, bytes));
      auto atlas = puff::core::loadAtlas(dir_ / (level.rfind("tinyc", 0) == 0 ? "tinyc.json" : "tiny.json"));
      ASSERT_FALSE(atlas.ok());
      EXPECT_EQ(atlas.error().message, (dir_ / level).string() + ": a " + std::to_string(w) + "x" + std::to_string(h) +
                                           " image is larger than this atlas level (the sidecar's size) may be "
                                           "(at most 24x24)");
      ASSERT_OK(puff::core::writeFileBytes(dir_ / level, saved));
    }
  }
  // A sidecar may not claim more than 16384 texels a side (what puffbake bakes at most).
  auto j = *puff::core::readFileBytes(dir_ / "tiny.json");
  auto json = nlohmann::json::parse(j);
  json["width"] = 3 * 8192;
  json["cellSize"] = 8192;
  auto desc = puff::core::atlasFromJson(json, dir_ / "tiny.json");
  ASSERT_FALSE(desc.ok());
  EXPECT_EQ(desc.error().message,
            (dir_ / "tiny.json").string() + ": /width: width and height must be at most 16384 texels");
}

TEST_F(ImageLimits, FilesLargerThanTheirUseAreRefusedBeforeTheyAreRead) {
  // Sparse files: their size is what is checked, and nothing of them is read.
  const auto sparse = [&](const std::string& name, std::uintmax_t size) {
    const fs::path f = dir_ / name;
    EXPECT_OK(puff::core::writeFileBytes(f, pngClaiming(4, 1)));
    fs::resize_file(f, size);
    return f;
  };
  const fs::path ramp = sparse("ramp.png", (std::uintmax_t{64} << 20) + 1);
  auto r = puff::cel::Ramp::read(ramp);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message,
            ramp.string() + ": a file of 67108865 bytes is larger than a ramp may be (67108864 bytes)");
  const fs::path gradient = sparse("gradient.puffimg", (std::uintmax_t{256} << 20) + 1);
  auto g = puff::cel::Gradient::read(gradient);
  ASSERT_FALSE(g.ok());
  EXPECT_EQ(g.error().message,
            gradient.string() + ": a file of 268435457 bytes is larger than a gradient may be (268435456 bytes)");
  const fs::path mesh = sparse("huge.obj", puff::mesh::kMaxMeshFileBytes + 1);
  auto m = puff::mesh::loadMesh(mesh);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.error().message,
            mesh.string() + ": a mesh file of 1073741825 bytes is larger than Puff reads (1073741824 bytes)");
}

TEST_F(ImageLimits, ImagesWithinTheLimitsStillRead) {
  // The largest ramp row count and a cooked gradient at its largest side read (the limits are not
  // off by one), as a real file with pixels.
  puff::core::Image ramp(4, 256, 3, 0.5f);
  ASSERT_OK(puff::core::writeImage(dir_ / "ramp.puffimg", ramp, puff::core::PixelType::kUInt8));
  ASSERT_OK(puff::cel::Ramp::read(dir_ / "ramp.puffimg"));
  puff::core::Image gradient(4096, 1, 3, 0.25f);
  ASSERT_OK(puff::core::writeImage(dir_ / "gradient.png", gradient, puff::core::PixelType::kUInt8));
  ASSERT_OK(puff::cel::Gradient::read(dir_ / "gradient.png"));
}

}  // namespace
