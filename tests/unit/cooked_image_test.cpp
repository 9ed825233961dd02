// Cooked images (core/image.h) and cooking (bake/cook.h): puff::core reads and writes them with no
// image library, every value as the PNG or EXR it came from held it, and a game with no codec
// loads a cooked atlas whole. Bad files give one error naming the file, never a crash or a huge
// allocation.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>

#include <puff/bake/baker.h>
#include <puff/bake/cook.h>
#include <puff/core/atlas.h>
#include <puff/core/detail_video.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/io/openimageio.h>
#include <puff/mesh/mesh.h>
#include <puff/support/json_read.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using puff::core::Image;
using puff::core::ImageFileInfo;
using puff::core::PixelType;

// Removes the codec for one scope, as in a game that links no puff::io.
class NoCodec {
 public:
  NoCodec() : saved_(puff::core::imageCodec()) { puff::core::setImageCodec(nullptr); }
  ~NoCodec() { puff::core::setImageCodec(saved_); }
  NoCodec(const NoCodec&) = delete;
  NoCodec& operator=(const NoCodec&) = delete;

 private:
  const puff::core::ImageCodec* saved_;
};

bool sameValue(float a, float b) {
  return (std::isnan(a) && std::isnan(b)) || std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

// Every pixel equal, bit for bit (NaN equals NaN).
::testing::AssertionResult samePixels(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) {
    return ::testing::AssertionFailure() << a.width << "x" << a.height << "x" << a.channels << " against " << b.width
                                         << "x" << b.height << "x" << b.channels;
  }
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    if (!sameValue(a.pixels[i], b.pixels[i])) {
      return ::testing::AssertionFailure() << "value " << i << ": " << a.pixels[i] << " against " << b.pixels[i];
    }
  }
  return ::testing::AssertionSuccess();
}

// Values that probe each type: [0, 1] on a fine grid, out of range, and for the float types
// subnormals (of half and of float), the largest finite halves, halfway cases, infinities, NaN.
Image probeImage(int channels) {
  std::vector<float> v;
  for (int i = 0; i <= 4096; ++i) v.push_back(static_cast<float>(i) / 4096.0f);
  for (float x : {-1.0f,
                  -0.0f,
                  1.5f,
                  1e-30f,
                  0x1p-24f,
                  0x1p-25f,
                  0x1.8p-25f,
                  0x1p-14f,
                  0x1.ffcp-15f,
                  65504.0f,
                  65519.0f,
                  65520.0f,
                  1e9f,
                  1.0009765625f,
                  1.00048828125f,
                  1.00146484375f,
                  3.14159265f,
                  -2.71828f,
                  std::numeric_limits<float>::denorm_min(),
                  std::numeric_limits<float>::infinity(),
                  -std::numeric_limits<float>::infinity(),
                  std::numeric_limits<float>::quiet_NaN()}) {
    v.push_back(x);
  }
  for (std::uint32_t bits = 0x3f800000u; bits < 0x3f800000u + 8192u; ++bits) v.push_back(std::bit_cast<float>(bits));
  const int width = 97;
  const int height = static_cast<int>((v.size() + width * channels - 1) / (width * channels));
  Image img(width, height, channels, 0.25f);
  std::copy(v.begin(), v.end(), img.pixels.begin());
  return img;
}

class CookedImage : public ::testing::Test {
 protected:
  puff::test::ScopedTempDir dir_{"puff_cooked"};
};

// What the codec's PNG (8/16-bit) and EXR (half, float) writers and readers make of the values is
// what a cooked image of the same type makes of them: OpenImageIO and Imath are the yardstick.
TEST_F(CookedImage, EveryTypeHoldsWhatThePngOrExrOfThatTypeHolds) {
  struct Case {
    PixelType type;
    const char* ext;
  };
  for (const Case c : {Case{PixelType::kUInt8, ".png"}, Case{PixelType::kUInt16, ".png"},
                       Case{PixelType::kHalf, ".exr"}, Case{PixelType::kFloat, ".exr"}}) {
    for (int channels : {1, 3, 4}) {
      SCOPED_TRACE(std::to_string(static_cast<int>(c.type)) + " type, " + std::to_string(channels) + " channels");
      const Image probe = probeImage(channels);
      const fs::path file = dir_ / (std::string("probe") + c.ext), cooked = dir_ / "probe.puffimg";
      ASSERT_OK(puff::core::writeImage(file, probe, c.type));
      ASSERT_OK(puff::core::writeImage(cooked, probe, c.type));
      ImageFileInfo fileInfo, cookedInfo;
      auto fromFile = puff::core::readImage(file, &fileInfo);
      auto fromCooked = puff::core::readImage(cooked, &cookedInfo);
      ASSERT_OK(fromFile);
      ASSERT_OK(fromCooked);
      EXPECT_TRUE(samePixels(*fromCooked, *fromFile));
      EXPECT_EQ(cookedInfo.type, c.type);
      EXPECT_EQ(fileInfo.type, c.type);
      if (c.type == PixelType::kFloat) {
        EXPECT_TRUE(samePixels(*fromCooked, probe));  // float keeps every bit
      }
    }
  }
  // Closed forms, independent of OpenImageIO: 8-bit 0.5 is 128/255, half keeps 1 + 2^-10 and rounds
  // 1 + 2^-11 (a tie) to even, 65520 overflows to infinity, 2^-25 (a tie) goes to zero.
  Image img(6, 1, 1);
  img.pixels = {0.5f, 1.0009765625f, 1.00048828125f, 65520.0f, 0x1p-25f, 0x1.8p-25f};
  ASSERT_OK(puff::core::writeImage(dir_ / "c8.puffimg", img, PixelType::kUInt8));
  ASSERT_OK(puff::core::writeImage(dir_ / "ch.puffimg", img, PixelType::kHalf));
  auto u8 = puff::core::readImage(dir_ / "c8.puffimg");
  auto half = puff::core::readImage(dir_ / "ch.puffimg");
  ASSERT_OK(u8);
  ASSERT_OK(half);
  EXPECT_EQ(u8->pixels[0], 128.0f * (1.0f / 255.0f));
  EXPECT_EQ(half->pixels[1], 1.0009765625f);
  EXPECT_EQ(half->pixels[2], 1.0f);
  EXPECT_EQ(half->pixels[3], std::numeric_limits<float>::infinity());
  EXPECT_EQ(half->pixels[4], 0.0f);
  EXPECT_EQ(half->pixels[5], 0x1p-24f);
}

TEST_F(CookedImage, KeepsAttributesAndIsTheSameBytesEachTime) {
  const Image img(5, 3, 2, 0.75f);
  const puff::core::ImageAttributes attributes = {{"puff:frames", "8"}, {"puff:source", "clip/*.png"}, {"empty", ""}};
  ASSERT_OK(puff::core::writeImage(dir_ / "a.puffimg", img, PixelType::kUInt16, attributes));
  ASSERT_OK(puff::core::writeImage(dir_ / "b.puffimg", img, PixelType::kUInt16, attributes));
  EXPECT_EQ(*puff::core::readFileBytes(dir_ / "a.puffimg"), *puff::core::readFileBytes(dir_ / "b.puffimg"));
  ImageFileInfo info;
  ASSERT_OK(puff::core::readImage(dir_ / "a.puffimg", &info));
  EXPECT_EQ(info.attributes, attributes);
  EXPECT_EQ(*puff::core::readImageAttribute(dir_ / "a.puffimg", "puff:source"), "clip/*.png");
  EXPECT_EQ(*puff::core::readImageAttribute(dir_ / "a.puffimg", "absent"), "");
  // Header 32 bytes, attributes 3 x 8 + their text, 5 x 3 x 2 values of 2 bytes, 8 bytes of hash.
  EXPECT_EQ(fs::file_size(dir_ / "a.puffimg"), 32u + 24u + 11u + 1u + 11u + 10u + 5u + 0u + 60u + 8u);
}

TEST_F(CookedImage, WithoutACodecOnlyCookedImagesAreReadAndTheErrorSaysWhatToDo) {
  ASSERT_OK(puff::core::writeImage(dir_ / "ramp.png", Image(4, 1, 3, 0.5f), PixelType::kUInt8));
  ASSERT_OK(puff::core::writeImage(dir_ / "ramp.puffimg", Image(4, 1, 3, 0.5f), PixelType::kUInt8));
  NoCodec none;
  auto png = puff::core::readImage(dir_ / "ramp.png");
  ASSERT_FALSE(png.ok());
  EXPECT_EQ(png.error().message, (dir_ / "ramp.png").string() +
                                     ": cannot read .png files: this program reads and writes only cooked images "
                                     "(.puffimg); cook the file with `puffbake cook`, or link puff::io and call "
                                     "puff::io::useOpenImageIO() first");
  auto write = puff::core::writeImage(dir_ / "out.exr", Image(1, 1, 1), PixelType::kHalf);
  ASSERT_FALSE(write.ok());
  EXPECT_NE(write.error().message.find("cannot write .exr files"), std::string::npos) << write.error().message;
  EXPECT_FALSE(fs::exists(dir_ / "out.exr"));
  EXPECT_FALSE(puff::core::readImageAttribute(dir_ / "ramp.png", "x").ok());
  auto cooked = puff::core::readImage(dir_ / "ramp.puffimg");
  ASSERT_OK(cooked);
  EXPECT_EQ(cooked->pixels[0], 128.0f * (1.0f / 255.0f));
  // A cooked image is known by its magic, whatever its name.
  fs::copy_file(dir_ / "ramp.puffimg", dir_ / "ramp.bin");
  EXPECT_OK(puff::core::readImage(dir_ / "ramp.bin"));
}

TEST_F(CookedImage, APngNamedPuffimgIsTheCodecsAndDamagedWithout) {
  ASSERT_OK(puff::core::writeImage(dir_ / "ramp.png", Image(4, 1, 3, 0.5f), PixelType::kUInt8));
  fs::copy_file(dir_ / "ramp.png", dir_ / "ramp.puffimg");
  EXPECT_OK(puff::core::readImage(dir_ / "ramp.puffimg"));
  NoCodec none;
  auto r = puff::core::readImage(dir_ / "ramp.puffimg");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, (dir_ / "ramp.puffimg").string() + ": not a cooked image (no PUFFIMG magic)");
}

// Every damaged file is one error naming the file: each truncation, each flipped byte, headers that
// lie, and files that are not images at all.
TEST_F(CookedImage, DamagedFilesAreOneErrorNamingTheFile) {
  NoCodec none;  // as in a game: no other reader may take the file
  const fs::path good = dir_ / "good.puffimg", bad = dir_ / "bad.puffimg";
  ASSERT_OK(puff::core::writeImage(good, Image(3, 2, 4, 0.5f), PixelType::kHalf, {{"puff:k", "v"}}));
  const std::string bytes = *puff::core::readFileBytes(good);
  const auto expectError = [&](const std::string& content, const std::string& problem) {
    ASSERT_OK(puff::core::writeFileBytes(bad, content));
    auto r = puff::core::readImage(bad);
    ASSERT_FALSE(r.ok()) << problem;
    EXPECT_EQ(r.error().message.rfind(bad.string() + ": ", 0), 0u) << r.error().message;
    EXPECT_NE(r.error().message.find(problem), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
  };
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    SCOPED_TRACE("truncated to " + std::to_string(n));
    expectError(bytes.substr(0, n), n < 8 ? "not a cooked image" : "truncated");
  }
  for (std::size_t i = 8; i < bytes.size(); ++i) {
    std::string flipped = bytes;
    flipped[i] = static_cast<char>(flipped[i] ^ 0x10);
    ASSERT_OK(puff::core::writeFileBytes(bad, flipped));
    EXPECT_FALSE(puff::core::readImage(bad).ok()) << "byte " << i << " flipped was read";
  }
  const auto withU32 = [](std::string b, std::size_t at, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) b[at + k] = static_cast<char>((v >> (8 * k)) & 0xffu);
    return b;
  };
  expectError(withU32(bytes, 8, 2), "cooked image version 2, this Puff reads version 1");
  // A header that claims 2^32 pixels: refused before anything is allocated.
  expectError(withU32(withU32(bytes, 12, 65536), 16, 65536),
              "a 65536x65536 image is larger than an image may be (at most 16384x16384)");
  expectError(withU32(bytes, 12, 0), "image has no pixels");
  expectError(withU32(bytes, 20, 5), "5 channels");
  expectError(withU32(bytes, 24, 4), "unknown pixel type 4");
  expectError(withU32(bytes, 28, 1000), "1000 attributes");
  expectError(withU32(withU32(bytes, 12, 0xffffffffu), 16, 0xffffffffu),
              "a 4294967295x4294967295 image is larger than");
  expectError(bytes + "x", "1 byte after the cooked image's end");
  expectError("PNG, honest", "not a cooked image");
  // Not regular files: a directory, a FIFO (would block a read), a missing file.
  fs::create_directory(dir_ / "d.puffimg");
  auto r = puff::core::readImage(dir_ / "d.puffimg");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("is a directory"), std::string::npos);
  ASSERT_EQ(::mkfifo((dir_ / "fifo.puffimg").c_str(), 0600), 0);
  r = puff::core::readImage(dir_ / "fifo.puffimg");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("not a regular file"), std::string::npos) << r.error().message;
  r = puff::core::readImage(dir_ / "none.puffimg");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("no such file"), std::string::npos);
}

TEST_F(CookedImage, CookingAnImageKeepsTypeValuesAndAttributes) {
  // A detail video as `puffbake detail` writes it (16-bit PNG with puff: attributes) cooks into one
  // that loads to the same video.
  Image frames(8, 24, 1);
  for (std::size_t i = 0; i < frames.pixels.size(); ++i) frames.pixels[i] = static_cast<float>(i % 17) / 16.0f;
  ASSERT_OK(puff::core::writeImage(dir_ / "detail.png", frames, PixelType::kUInt16,
                                   {{"puff:frames", "3"}, {"puff:source", "test"}}));
  auto cooked = puff::bake::cookImage(dir_ / "detail.png", dir_ / "detail.puffimg");
  ASSERT_OK(cooked);
  EXPECT_EQ(cooked->files, std::vector<fs::path>{dir_ / "detail.puffimg"});
  ImageFileInfo info;
  auto back = puff::core::readImage(dir_ / "detail.puffimg", &info);
  ASSERT_OK(back);
  EXPECT_EQ(info.type, PixelType::kUInt16);
  EXPECT_TRUE(samePixels(*back, *puff::core::readImage(dir_ / "detail.png")));
  NoCodec none;
  auto video = puff::core::loadDetailVideo(dir_ / "detail.puffimg");
  ASSERT_OK(video);
  EXPECT_EQ(video->frames, 3);
  // Input that no cooked image holds is the input's error, and an unwritable output names where it
  // cannot go (not the temporary file written first).
  puff::core::setImageCodec(&puff::io::openImageIOCodec());
  ASSERT_OK(puff::core::writeImage(dir_ / "five.tif", Image(2, 2, 5, 0.5f), PixelType::kUInt8));
  auto five = puff::bake::cookImage(dir_ / "five.tif", dir_ / "five.puffimg");
  ASSERT_FALSE(five.ok());
  EXPECT_EQ(five.error().message,
            (dir_ / "five.tif").string() + ": has 5 channels, more than a cooked image may have (1 to 4)");
  auto proc = puff::bake::cookImage(dir_ / "detail.png", "/proc/puff_cook_test.puffimg");
  ASSERT_FALSE(proc.ok());
  EXPECT_EQ(proc.error().message.rfind("/proc: cannot write: ", 0), 0u) << proc.error().message;
  puff::core::setImageCodec(nullptr);
  // Refused: a name that is not .puffimg, the input itself; nothing is written.
  EXPECT_FALSE(puff::bake::cookImage(dir_ / "detail.png", dir_ / "detail2.png").ok());
  EXPECT_FALSE(puff::bake::cookImage(dir_ / "detail.puffimg", dir_ / "detail.puffimg").ok());
  EXPECT_FALSE(fs::exists(dir_ / "detail2.png"));
}

// An atlas cooks into one a program with no codec loads with the same pixels at every level, and
// a cook that fails leaves nothing.
class CookedAtlas : public puff::test::GlTest {
 protected:
  puff::test::ScopedTempDir dir_{"puff_cooked_atlas"};

  /// A small bake into `outDir`: 32-texel cells, no contact sheet.
  static puff::bake::BakeOptions smallBake(const fs::path& outDir) {
    puff::bake::BakeOptions o;
    o.cellSize = 32;
    o.contactSheet = false;
    o.outDir = outDir;
    return o;
  }
  /// `count` generated spheres of `subdivisions`.
  static std::vector<puff::bake::PuffSource> spheres(int count, int subdivisions) {
    std::vector<puff::bake::PuffSource> sources(static_cast<std::size_t>(count));
    for (auto& s : sources) {
      s.mesh = puff::mesh::generateSphere({subdivisions});
      s.provenance.generator = "sphere";
    }
    return sources;
  }

  static void expectSameAtlas(const puff::core::Atlas& a, const puff::core::Atlas& b) {
    // Equal but for the file names.
    nlohmann::json ja = puff::core::toJson(a.desc), jb = puff::core::toJson(b.desc);
    for (nlohmann::json* j : {&ja, &jb}) {
      j->erase("maps");
      for (auto& source : (*j)["sources"]) source.erase("lodMesh");
    }
    EXPECT_EQ(ja, jb);
    ASSERT_EQ(a.maps.size(), b.maps.size());
    for (const auto& [name, levels] : a.maps) {
      ASSERT_EQ(levels.size(), b.maps.at(name).size()) << name;
      for (std::size_t l = 0; l < levels.size(); ++l)
        EXPECT_TRUE(samePixels(levels[l], b.maps.at(name)[l])) << name << " " << l;
    }
  }
};

TEST_F(CookedAtlas, LoadsWithoutACodecToTheSamePixelsForPngAndExrAtlases) {
  for (const auto format : {puff::bake::MapFormat::kPng, puff::bake::MapFormat::kExr}) {
    const std::string name = format == puff::bake::MapFormat::kPng ? "png" : "exr";
    SCOPED_TRACE(name);
    puff::bake::BakeOptions o = smallBake(dir_ / name);
    o.format = format;
    o.lodAuto = true;
    auto baked = puff::bake::bakeAtlas(spheres(2, 4), o);
    ASSERT_OK(baked);
    auto source = puff::core::loadAtlas(baked->sidecar);
    ASSERT_OK(source);
    const fs::path out = dir_ / ("cooked-" + name) / "atlas.json";
    auto cooked = puff::bake::cookAtlas(baked->sidecar, out);
    ASSERT_OK(cooked);
    EXPECT_EQ(cooked->files.back(), out);
    std::size_t lodMeshes = 0;
    for (const auto& s : source->desc.sources) lodMeshes += s.lodMesh.empty() ? 0 : 1;
    EXPECT_GT(lodMeshes, 0u) << "no variation was decimated: the LOD mesh copy is not tested";
    EXPECT_EQ(cooked->files.size(), 3u * source->desc.mipLevels + lodMeshes + 1u);  // maps, LOD meshes, sidecar
    NoCodec none;
    auto loaded = puff::core::loadAtlas(out);
    ASSERT_OK(loaded);
    expectSameAtlas(*source, *loaded);
    EXPECT_EQ(loaded->desc.fileFormat, name);
    for (std::size_t i = 0; i < loaded->desc.sources.size(); ++i) {
      auto lod = puff::core::lodMeshFile(loaded->desc, i, out);
      ASSERT_OK(lod);
      EXPECT_EQ(*puff::core::readFileBytes(*lod),
                *puff::core::readFileBytes(*puff::core::lodMeshFile(source->desc, i, baked->sidecar)));
    }
  }
}

// Cooked files are named after the output sidecar and lie beside it, whatever the source sidecar
// names (a subdirectory, "../"); two cooked atlases share a directory; cooking over a cooked atlas
// replaces it whole.
TEST_F(CookedAtlas, FilesAreTheOutputsOwnAndAReplacedAtlasLeavesNothingBehind) {
  puff::bake::BakeOptions o = smallBake(dir_ / "src");
  const std::vector<puff::bake::PuffSource> sources = spheres(1, 3);
  auto baked = puff::bake::bakeAtlas(sources, o);
  ASSERT_OK(baked);
  // The source names one level in a subdirectory and one through "../".
  nlohmann::json j = *puff::core::jsonread::loadJsonFile(baked->sidecar);
  fs::create_directories(dir_ / "src" / "sub");
  fs::create_directories(dir_ / "other");
  const std::string color = baked->desc.maps.at("color").levels[0];
  const std::string distance = baked->desc.maps.at("distance").levels[0];
  fs::rename(dir_ / "src" / color, dir_ / "src" / "sub" / "puff_color.png");
  fs::rename(dir_ / "src" / distance, dir_ / "other" / "puff_distance.png");
  j["maps"]["color"]["levels"][0] = "sub/puff_color.png";
  j["maps"]["distance"]["levels"][0] = "../other/puff_distance.png";
  ASSERT_OK(puff::core::writeFileBytes(baked->sidecar, j.dump(2)));
  const auto filesIn = [](const fs::path& d) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  };
  const fs::path out = dir_ / "game";
  ASSERT_OK(puff::bake::cookAtlas(baked->sidecar, out / "smoke.json"));
  const int levels = puff::core::loadAtlasDesc(baked->sidecar)->mipLevels;
  EXPECT_EQ(filesIn(out).size(), 3u * levels + 1u);
  EXPECT_EQ(filesIn(dir_ / "other"), std::vector<std::string>{"puff_distance.png"});
  ASSERT_OK(puff::bake::cookAtlas(baked->sidecar, out / "dust.json"));  // a second atlas beside it
  NoCodec none;
  EXPECT_OK(puff::core::loadAtlas(out / "smoke.json"));
  EXPECT_OK(puff::core::loadAtlas(out / "dust.json"));
  EXPECT_EQ(filesIn(out).size(), 2u * (3u * levels + 1u));
  // smoke.json replaced by a one-level atlas: its mip files go, dust.json's stay.
  puff::core::setImageCodec(&puff::io::openImageIOCodec());
  o.mips = false;
  o.outDir = dir_ / "flat";
  ASSERT_OK(puff::bake::bakeAtlas(sources, o));
  ASSERT_OK(puff::bake::cookAtlas(dir_ / "flat" / "puff.json", out / "smoke.json"));
  puff::core::setImageCodec(nullptr);
  EXPECT_EQ(filesIn(out).size(), 3u + 1u + 3u * levels + 1u);
  const auto mip1 = [&](const std::string& stem) {
    return std::count_if(fs::directory_iterator(out), fs::directory_iterator(), [&](const fs::directory_entry& e) {
      return e.path().filename().string().rfind(stem + "_color.mip1.", 0) == 0;
    });
  };
  EXPECT_EQ(mip1("smoke"), 0);
  EXPECT_EQ(mip1("dust"), 1);
  EXPECT_OK(puff::core::loadAtlas(out / "smoke.json"));
  EXPECT_OK(puff::core::loadAtlas(out / "dust.json"));
  // Without a codec an uncooked atlas says what to cook: the sidecar, not the map.
  auto uncooked = puff::core::loadAtlas(dir_ / "flat" / "puff.json");
  ASSERT_FALSE(uncooked.ok());
  const std::string flat = (dir_ / "flat" / "puff.json").string();
  EXPECT_EQ(uncooked.error().message,
            flat + ": its maps are not cooked images (" +
                puff::core::loadAtlasDesc(dir_ / "flat" / "puff.json")->maps.at("color").levels[0] +
                "), and this program reads no other format: "
                "cook the atlas with `puffbake cook " +
                flat + " -o OUT.json` and load OUT.json, or link puff::io and call puff::io::useOpenImageIO() first");
}

// A level that names another map's file, or a map holding NaN, would draw wrong pictures with exit
// 0; both are refused naming the file.
TEST_F(CookedAtlas, WrongMapsAndNonFiniteTexelsAreRefused) {
  puff::bake::BakeOptions o = smallBake(dir_ / "exr");
  o.format = puff::bake::MapFormat::kExr;
  o.mips = false;
  o.viewGrid = 2;  // with a back map
  auto baked = puff::bake::bakeAtlas(spheres(1, 3), o);
  ASSERT_OK(baked);
  ASSERT_OK(puff::core::loadAtlas(baked->sidecar));
  const nlohmann::json good = *puff::core::jsonread::loadJsonFile(baked->sidecar);
  const std::string color = good["maps"]["color"]["levels"][0];
  for (const char* map : {"distance", "back"}) {
    nlohmann::json j = good;
    j["maps"][map]["levels"][0] = color;
    const fs::path swapped = o.outDir / "swapped.json";
    ASSERT_OK(puff::core::writeFileBytes(swapped, j.dump(2)));
    auto wrong = puff::core::loadAtlas(swapped);
    ASSERT_FALSE(wrong.ok());
    EXPECT_EQ(wrong.error().message, (o.outDir / color).string() + ": has 4 channel(s), but the " + map +
                                         " map has 1 (does the sidecar name the right file?)");
  }
  nlohmann::json j = good;
  j["maps"]["back"]["levels"].push_back(color);
  auto levels = puff::core::atlasFromJson(j, "x.json");
  ASSERT_FALSE(levels.ok());
  EXPECT_EQ(levels.error().message, "x.json: /maps/back/levels: must list mipLevels files");
  const fs::path normal = o.outDir / std::string(j["maps"]["normalDepth"]["levels"][0]);
  auto image = puff::core::readImage(normal);
  ASSERT_OK(image);
  image->at(5, 3, 2) = std::numeric_limits<float>::quiet_NaN();
  ASSERT_OK(puff::core::writeImage(normal, *image, PixelType::kHalf));
  auto nan = puff::core::loadAtlas(baked->sidecar);
  ASSERT_FALSE(nan.ok());
  EXPECT_EQ(nan.error().message, normal.string() + ": texel (5, 3) is not finite");
}

TEST_F(CookedAtlas, AFailedCookWritesNothingAndTheSourceIsNeverReplaced) {
  const puff::bake::BakeOptions o = smallBake(dir_ / "atlas");
  auto baked = puff::bake::bakeAtlas(spheres(1, 3), o);
  ASSERT_OK(baked);
  auto same = puff::bake::cookAtlas(baked->sidecar, baked->sidecar);
  ASSERT_FALSE(same.ok());
  EXPECT_NE(same.error().message.find("is the atlas being cooked"), std::string::npos);
  // The last level's file is damaged: the cook fails on it, after the others were read.
  const puff::core::AtlasDesc desc = *puff::core::loadAtlasDesc(baked->sidecar);
  const fs::path last = o.outDir / desc.maps.rbegin()->second.levels.back();
  ASSERT_OK(puff::core::writeFileBytes(last, "\x89PNG\r\n\x1a\n broken"));
  const fs::path out = dir_ / "cooked" / "atlas.json";
  auto failed = puff::bake::cookAtlas(baked->sidecar, out);
  ASSERT_FALSE(failed.ok());
  EXPECT_EQ(failed.error().message.rfind(last.string() + ": ", 0), 0u) << failed.error().message;
  EXPECT_FALSE(fs::exists(dir_ / "cooked"));
}

// Cook must not write an atlas the runtime then refuses (a level of the wrong channels, the wrong
// size or with NaN): it checks every level as loadAtlas does, and the cooked atlas already in place
// stays.
TEST_F(CookedAtlas, CookRefusesWhatTheRuntimeWouldRefuse) {
  const puff::bake::BakeOptions o = smallBake(dir_ / "atlas");
  auto baked = puff::bake::bakeAtlas(spheres(1, 3), o);
  ASSERT_OK(baked);
  const fs::path out = dir_ / "cooked" / "atlas.json";
  ASSERT_OK(puff::bake::cookAtlas(baked->sidecar, out));
  const std::string before = *puff::core::readFileBytes(out);
  const puff::core::AtlasDesc desc = *puff::core::loadAtlasDesc(baked->sidecar);
  const fs::path level1 = o.outDir / desc.maps.at("color").levels.at(1);
  const Image good = *puff::core::readImage(level1);
  const std::string saved = *puff::core::readFileBytes(level1);
  Image threeChannels(good.width, good.height, 3, 0.5f), larger(good.width * 2, good.height * 2, 4, 0.5f);
  Image nan = good;
  nan.pixels[5] = NAN;
  const std::pair<const Image*, std::string> cases[] = {
      {&threeChannels, "has 3 channel(s), but the color map has 4"},
      {&larger, "image is larger than this atlas level (the sidecar's size) may be"},
      {&nan, "is not finite"}};
  for (const auto& [image, problem] : cases) {
    SCOPED_TRACE(problem);
    const bool isNan = image == &nan;
    // NaN survives only a float file: write the level as EXR bytes under its PNG name (read by content).
    ASSERT_OK(puff::core::writeImage(level1, *image, isNan ? PixelType::kFloat : PixelType::kUInt8, {},
                                     isNan ? fs::path("x.exr") : fs::path("x.png")));
    auto r = puff::bake::cookAtlas(baked->sidecar, out);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message.rfind(level1.string() + ": ", 0), 0u) << r.error().message;
    EXPECT_NE(r.error().message.find(problem), std::string::npos) << r.error().message;
    EXPECT_EQ(*puff::core::readFileBytes(out), before);
  }
  ASSERT_OK(puff::core::writeFileBytes(level1, saved));
  EXPECT_OK(puff::bake::cookAtlas(baked->sidecar, out));
}

}  // namespace
