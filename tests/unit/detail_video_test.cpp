// Detail videos (core/detail_video.h, bake/detail.h): the generated noise tiles and loops, its
// values are where the header says, the file round-trips, and import resamples and cross-fades
// exactly as documented.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <puff/bake/detail.h>
#include <puff/core/detail_video.h>
#include <puff/core/files.h>
#include <puff/core/image.h>

#include "support/assert_ok.h"
#include "support/skip.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using puff::bake::DetailSpec;
using puff::core::DetailVideo;

TEST(DetailVideoNoise, FieldIsPeriodicInXYAndTime) {
  DetailSpec spec;
  spec.size = 48;
  spec.frames = 20;
  spec.frequency = 3;
  spec.octaves = 5;
  for (int i = 0; i < 200; ++i) {
    const double x = 0.37 * i, y = 48.0 - 0.53 * i, t = 0.29 * i;
    const double v = puff::bake::detailNoise(spec, x, y, t);
    EXPECT_NEAR(puff::bake::detailNoise(spec, x + spec.size, y, t), v, 1e-9);
    EXPECT_NEAR(puff::bake::detailNoise(spec, x, y - spec.size, t), v, 1e-9);
    EXPECT_NEAR(puff::bake::detailNoise(spec, x, y, t + spec.frames), v, 1e-9);
    EXPECT_NEAR(puff::bake::detailNoise(spec, x - 2.0 * spec.size, y + spec.size, t - spec.frames), v, 1e-9);
  }
}

// Mean absolute difference between neighbours along one axis: every interior pair, and the
// wrap-around pair (last -> first). A seamless tile/loop has a seam no rougher than the inside.
struct Steps {
  double interior = 0, seam = 0, far = 0;
};
Steps steps(const DetailVideo& v, int axis) {
  const int n[3] = {v.width, v.height, v.frames};
  Steps s;
  long long ni = 0, ns = 0;
  for (int f = 0; f < v.frames; ++f) {
    for (int y = 0; y < v.height; ++y) {
      for (int x = 0; x < v.width; ++x) {
        int p[3] = {x, y, f};
        if (p[axis] == n[axis] - 1) {
          int q[3] = {x, y, f};
          q[axis] = 0;
          s.seam += std::abs(v.at(x, y, f) - v.at(q[0], q[1], q[2]));
          int r[3] = {x, y, f};
          r[axis] = n[axis] / 2;  // not a neighbour: what a seam would look like without wrapping
          s.far += std::abs(v.at(x, y, f) - v.at(r[0], r[1], r[2]));
          ++ns;
        } else {
          int q[3] = {x, y, f};
          q[axis] += 1;
          s.interior += std::abs(v.at(x, y, f) - v.at(q[0], q[1], q[2]));
          ++ni;
        }
      }
    }
  }
  s.interior /= static_cast<double>(ni);
  s.seam /= static_cast<double>(ns);
  s.far /= static_cast<double>(ns);
  return s;
}

TEST(DetailVideoGenerate, TilesInXAndYAndLoopsInTime) {
  DetailSpec spec;
  spec.size = 64;
  spec.frames = 24;
  spec.seed = 7;
  auto v = puff::bake::generateDetailVideo(spec);
  ASSERT_OK(v);
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE("axis " + std::to_string(axis));
    const Steps s = steps(*v, axis);
    EXPECT_GT(s.interior, 0.0);
    EXPECT_GT(s.seam, 0.7 * s.interior);
    EXPECT_LT(s.seam, 1.3 * s.interior);
    // The check has teeth: unrelated texels differ far more than neighbours.
    EXPECT_GT(s.far, 2.0 * s.interior);
  }
}

TEST(DetailVideoGenerate, ValuesAreInUnitRangeWithMeanHalfAndTheContrastsSpread) {
  double sdAtOne = 0;
  for (float contrast : {0.5f, 1.0f, 2.0f}) {
    DetailSpec spec;
    spec.size = 64;
    spec.frames = 16;
    spec.contrast = contrast;
    auto v = puff::bake::generateDetailVideo(spec);
    ASSERT_TRUE(v.ok());
    ASSERT_EQ(v->values.size(), 64u * 64u * 16u);
    double sum = 0, sum2 = 0;
    for (float x : v->values) {
      ASSERT_GE(x, 0.0f);
      ASSERT_LE(x, 1.0f);
      sum += x;
      sum2 += double(x) * x;
    }
    const double n = static_cast<double>(v->values.size());
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(mean, 0.5, 0.01) << contrast;
    if (contrast <= 1.0f) {
      EXPECT_NEAR(sd, contrast / 6.0, 0.02 * contrast / 6.0) << contrast;  // (3 sigma: hardly any clipping)
      sdAtOne = sd;
    } else {
      // Clipped at 1.5 sigma: wider than contrast 1, narrower than 2/6, and both ends reached.
      EXPECT_GT(sd, 1.5 * sdAtOne);
      EXPECT_LT(sd, contrast / 6.0);
      EXPECT_NE(std::count(v->values.begin(), v->values.end(), 0.0f), 0);
      EXPECT_NE(std::count(v->values.begin(), v->values.end(), 1.0f), 0);
    }
  }
  DetailSpec flat;
  flat.size = 8;
  flat.frames = 2;
  flat.contrast = 0;
  auto v = puff::bake::generateDetailVideo(flat);
  ASSERT_TRUE(v.ok());
  for (float x : v->values) EXPECT_EQ(x, 0.5f);
}

TEST(DetailVideoGenerate, SameSpecSameValuesOtherSeedOtherValues) {
  DetailSpec spec;
  spec.size = 32;
  spec.frames = 8;
  auto a = puff::bake::generateDetailVideo(spec);
  auto b = puff::bake::generateDetailVideo(spec);
  spec.seed = 2;
  auto c = puff::bake::generateDetailVideo(spec);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_TRUE(a->values == b->values);
  EXPECT_FALSE(a->values == c->values);
}

TEST(DetailVideoGenerate, BadSpecsNameTheFlag) {
  struct Case {
    DetailSpec spec;
    const char* needle;
  };
  std::vector<Case> cases;
  auto add = [&](auto change, const char* needle) {
    DetailSpec s;
    change(s);
    cases.push_back({s, needle});
  };
  add([](DetailSpec& s) { s.size = 3; }, "--size must be in [4, 4096], got 3");
  add([](DetailSpec& s) { s.size = 4097; }, "--size");
  add([](DetailSpec& s) { s.frames = 0; }, "--frames must be in [1, 1024], got 0");
  add([](DetailSpec& s) { s.frames = 1025; }, "--frames");
  add(
      [](DetailSpec& s) {
        s.size = 4096;
        s.frames = 8;
      },
      "too large");
  add([](DetailSpec& s) { s.octaves = 0; }, "--octaves must be in [1, 10], got 0");
  add([](DetailSpec& s) { s.frequency = 0; }, "--frequency must be in [1, 256], got 0");
  add([](DetailSpec& s) { s.contrast = -1; }, "--contrast must be in [0, 16], got -1");
  add([](DetailSpec& s) { s.contrast = NAN; }, "--contrast");
  for (const Case& c : cases) {
    auto r = puff::bake::generateDetailVideo(c.spec);
    ASSERT_FALSE(r.ok()) << c.needle;
    EXPECT_NE(r.error().message.find(c.needle), std::string::npos) << r.error().message;
  }
}

class DetailVideoFile : public ::testing::Test {
 protected:
  // A float EXR frame (stored exactly) filled by fn(x, y) in every channel.
  template <class Fn>
  fs::path frame(const std::string& name, int w, int h, Fn fn, int channels = 1) {
    puff::core::Image img(w, h, channels);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < channels; ++c) img.at(x, y, c) = fn(x, y);
    const fs::path p = dir_ / name;
    EXPECT_TRUE(puff::core::writeImage(p, img, puff::core::PixelType::kFloat).ok());
    return p;
  }

  puff::test::ScopedTempDir dir_{"puff_detail"};
};

TEST_F(DetailVideoFile, PngRoundTripsWithin16BitPrecisionAndExrWithinHalf) {
  DetailSpec spec;
  spec.size = 32;
  spec.frames = 6;
  auto v = puff::bake::generateDetailVideo(spec);
  ASSERT_TRUE(v.ok());
  for (const char* name : {"detail.png", "detail.exr"}) {
    SCOPED_TRACE(name);
    const fs::path path = dir_ / "out" / name;
    ASSERT_TRUE(puff::core::saveDetailVideo(path, *v).ok());
    EXPECT_EQ(puff::core::readImageAttribute(path, "puff:frames").value(), "6");
    auto back = puff::core::loadDetailVideo(path);
    ASSERT_OK(back);
    EXPECT_EQ(back->width, 32);
    EXPECT_EQ(back->height, 32);
    EXPECT_EQ(back->frames, 6);
    EXPECT_EQ(back->source, v->source);
    // The image itself: frames stacked top to bottom, one channel.
    auto img = puff::core::readImage(path);
    ASSERT_TRUE(img.ok());
    EXPECT_EQ(img->width, 32);
    EXPECT_EQ(img->height, 32 * 6);
    EXPECT_EQ(img->channels, 1);
    const bool png = fs::path(name).extension() == ".png";
    const float tolerance = png ? 0.5f / 65535.0f + 1e-7f : 1.0f / 2048.0f;  // half: 11-bit significand
    for (int f = 0; f < 6; ++f)
      for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
          ASSERT_NEAR(back->at(x, y, f), v->at(x, y, f), tolerance) << x << "," << y << "," << f;
  }
  // Byte-identical when written again.
  ASSERT_TRUE(puff::core::saveDetailVideo(dir_ / "again.png", *v).ok());
  EXPECT_EQ(puff::core::readFileBytes(dir_ / "again.png").value(),
            puff::core::readFileBytes(dir_ / "out" / "detail.png").value());
}

TEST_F(DetailVideoFile, LoadTakesLuminanceOfColourImages) {
  puff::core::Image img(4, 8, 3);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 4; ++x) {
      img.at(x, y, 0) = 1.0f;
      img.at(x, y, 1) = 0.5f;
      img.at(x, y, 2) = 0.0f;
    }
  const fs::path p = dir_ / "rgb.exr";
  ASSERT_TRUE(puff::core::writeImage(p, img, puff::core::PixelType::kFloat, {{"puff:frames", "2"}}).ok());
  auto v = puff::core::loadDetailVideo(p);
  ASSERT_OK(v);
  EXPECT_EQ(v->frames, 2);
  EXPECT_EQ(v->height, 4);
  EXPECT_NEAR(v->at(3, 3, 1), 0.2126f + 0.7152f * 0.5f, 1e-6f);
}

TEST_F(DetailVideoFile, BadFilesAreErrorsNamingTheFile) {
  auto expectError = [](const fs::path& p, const std::string& needle) {
    auto r = puff::core::loadDetailVideo(p);
    ASSERT_FALSE(r.ok()) << p;
    EXPECT_NE(r.error().message.find(p.string()), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
  };
  expectError(dir_ / "missing.png", "no such file");
  std::ofstream(dir_ / "garbage.png") << "not a png";
  expectError(dir_ / "garbage.png", "not a readable image");
  const puff::core::Image img(8, 24, 1, 0.5f);
  auto write = [&](const char* name, const puff::core::ImageAttributes& attributes) {
    EXPECT_TRUE(puff::core::writeImage(dir_ / name, img, puff::core::PixelType::kUInt16, attributes).ok());
    return dir_ / name;
  };
  expectError(write("plain.png", {}), "missing attribute puff:frames");
  expectError(write("words.png", {{"puff:frames", "three"}}), "puff:frames must be an integer in [1, 1024]");
  expectError(write("zero.png", {{"puff:frames", "0"}}), "puff:frames must be an integer");
  expectError(write("uneven.png", {{"puff:frames", "5"}}), "image height 24 is not a multiple of puff:frames 5");
  expectError(write("thin.png", {{"puff:frames", "8"}}), "height must be in [4, 4096], got 3");
}

TEST_F(DetailVideoFile, SaveRefusesBadVideosAndNeverClobbers) {
  DetailVideo v;
  v.width = v.height = 4;
  v.frames = 2;
  v.values.assign(32, 0.25f);
  const fs::path good = dir_ / "good.png";
  ASSERT_TRUE(puff::core::saveDetailVideo(good, v).ok());
  const std::string before = puff::core::readFileBytes(good).value();

  auto r = puff::core::saveDetailVideo(dir_ / "video.jpg", v);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("video.jpg: a detail video is a .png"), std::string::npos) << r.error().message;
  DetailVideo tooSmall = v;
  tooSmall.width = 2;
  tooSmall.values.resize(16);
  r = puff::core::saveDetailVideo(good, tooSmall);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("width must be in [4, 4096], got 2"), std::string::npos) << r.error().message;
  // A path under a regular file cannot be written.
  r = puff::core::saveDetailVideo(good / "x.png", v);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("good.png"), std::string::npos) << r.error().message;
  EXPECT_EQ(puff::core::readFileBytes(good).value(), before);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_.path()), fs::directory_iterator()), 1);  // no temporaries
}

TEST_F(DetailVideoFile, ImportCrossFadesTheTailIntoTheHeadExactly) {
  // Six flat frames of value k / 10; loop 2: out[0] = 2/3 in[4] + 1/3 in[0], out[1] = 1/3 in[5] + 2/3 in[1],
  // out[2] = in[2], out[3] = in[3].
  std::vector<fs::path> frames;
  for (int k = 0; k < 6; ++k) {
    const std::string name = std::string("f") + static_cast<char>('0' + k) + ".exr";
    frames.push_back(frame(name, 4, 4, [k](int, int) { return k / 10.0f; }));
  }
  auto v = puff::bake::importDetailVideo(frames, 4, 2);
  ASSERT_OK(v);
  ASSERT_EQ(v->frames, 4);
  const float expected[4] = {(2.0f * 0.4f + 0.0f) / 3.0f, (0.5f + 2.0f * 0.1f) / 3.0f, 0.2f, 0.3f};
  for (int f = 0; f < 4; ++f)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) EXPECT_NEAR(v->at(x, y, f), expected[f], 1e-6f) << f;
  // No cross-fade keeps every frame as it is.
  auto all = puff::bake::importDetailVideo(frames, 4, 0);
  ASSERT_TRUE(all.ok());
  ASSERT_EQ(all->frames, 6);
  for (int f = 0; f < 6; ++f) EXPECT_FLOAT_EQ(all->at(1, 2, f), f / 10.0f);
}

TEST_F(DetailVideoFile, ImportResamplesWithABoxDownAndBilinearUp) {
  auto pattern = [](int x, int y) { return static_cast<float>((x * 7 + y * 3) % 11) / 10.0f; };
  const fs::path big = frame("big.exr", 8, 8, pattern);
  auto down = puff::bake::importDetailVideo({big}, 4, 0);
  ASSERT_OK(down);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      const float box = (pattern(2 * x, 2 * y) + pattern(2 * x + 1, 2 * y) + pattern(2 * x, 2 * y + 1) +
                         pattern(2 * x + 1, 2 * y + 1)) /
                        4.0f;
      EXPECT_NEAR(down->at(x, y, 0), box, 1e-6f) << x << "," << y;
    }
  // Up: a ramp 0, 1/3, 2/3, 1 across 4 texels sampled at 8 texel centres, edges clamped.
  const fs::path ramp = frame("ramp.exr", 4, 4, [](int x, int) { return x / 3.0f; });
  auto up = puff::bake::importDetailVideo({ramp}, 8, 0);
  ASSERT_TRUE(up.ok());
  const float expected[8] = {0.0f, 0.25f / 3, 0.75f / 3, 1.25f / 3, 1.75f / 3, 2.25f / 3, 2.75f / 3, 1.0f};
  for (int x = 0; x < 8; ++x) EXPECT_NEAR(up->at(x, 5, 0), expected[x], 1e-6f) << x;
  // Colour frames become luma.
  const fs::path rgb = frame(
      "rgb.exr", 4, 4, [](int, int) { return 0.5f; }, 3);
  auto grey = puff::bake::importDetailVideo({rgb}, 4, 0);
  ASSERT_TRUE(grey.ok());
  EXPECT_NEAR(grey->at(0, 0, 0), 0.5f, 1e-6f);
}

TEST_F(DetailVideoFile, ImportErrorsNameTheFile) {
  const fs::path a = frame("a.exr", 8, 8, [](int, int) { return 0.5f; });
  const fs::path b = frame("b.exr", 8, 8, [](int, int) { return 0.5f; });
  const fs::path wide = frame("wide.exr", 16, 8, [](int, int) { return 0.5f; });
  std::ofstream(dir_ / "garbage.png") << "not a png";
  auto expectError = [](const puff::Result<DetailVideo>& r, const std::string& needle) {
    ASSERT_FALSE(r.ok()) << needle;
    EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
  };
  expectError(puff::bake::importDetailVideo({a, dir_ / "missing.png"}, 8, 0), "missing.png: cannot open");
  expectError(puff::bake::importDetailVideo({a, dir_ / "garbage.png"}, 8, 0), "garbage.png: not a readable image");
  expectError(puff::bake::importDetailVideo({a, wide}, 8, 0),
              "wide.exr: frame is 16x8, but a.exr (the first frame) is 8x8");
  expectError(puff::bake::importDetailVideo({a, b}, 8, 2), "--loop-frames must be in [0, 1]");
  expectError(puff::bake::importDetailVideo({a, b}, 2, 0), "--size must be in [4, 4096], got 2");
  expectError(puff::bake::importDetailVideo({}, 8, 0), "no frames");
}

// A detail clip made by another tool may store puff:frames as a number, not a string (as
// `oiiotool --attrib:type=int puff:frames 2` does); it is read, not "missing attribute puff:frames".
TEST(DetailVideoAttributes, AFramesAttributeStoredAsANumberIsRead) {
  puff::test::ScopedTempDir dir("puff_detail_int");
  const fs::path clip = dir / "clip.exr";
  const std::string cmd = "oiiotool --pattern constant:color=0.5 4x8 1 --attrib:type=int puff:frames 2 -d half -o " +
                          clip.string() + " >/dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) PUFF_SKIP_UNLESS_CI("oiiotool (openimageio-tools, setup.sh) is not installed");
  auto v = puff::core::loadDetailVideo(clip);
  ASSERT_OK(v);
  EXPECT_EQ(v->frames, 2);
  EXPECT_EQ(v->width, 4);
  EXPECT_EQ(v->height, 4);
  EXPECT_NEAR(v->at(1, 1, 1), 0.5f, 1e-3f);
}

}  // namespace
