// The colour pipeline (docs/colour.md), end to end against closed forms: the sRGB transfer
// function and its round trip through a ramp texture and the render target; the view transform on
// the CPU and the GPU; a black body's on-screen chromaticity through the EXR (scene-linear) and PNG
// (display) outputs; an EXR keeping values above 1; opaque frames keeping alpha 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/opaque.h>
#include <puff/core/blackbody.h>
#include <puff/core/colour.h>
#include <puff/core/gl.h>
#include <puff/core/image.h>
#include <puff/gl_api.h>
#include <puff/mesh/mesh.h>
#include <puff/render/cel_scene.h>
#include <puff/render/render.h>
#include <puff/render/view.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/cli_test.h"
#include "support/gl_fixture.h"
#include "support/gl_target.h"
#include "support/linear_frame.h"
#include "support/temp_dir.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

// CIE xy chromaticity of an XYZ colour.
glm::dvec2 chromaticity(const glm::dvec3& xyz) { return glm::dvec2(xyz.x, xyz.y) / (xyz.x + xyz.y + xyz.z); }

// ---- the sRGB transfer function (no GL) ------------------------------------------------------------

TEST(ColourSrgb, EveryEightBitValueRoundTrips) {
  double previous = -1.0;
  for (int k = 0; k <= 255; ++k) {
    const double d = k / 255.0;
    const double l = core::srgbToLinear(d);
    EXPECT_NEAR(core::linearToSrgb(l), d, 1e-6) << k;
    EXPECT_GT(l, previous) << k << ": decoding is strictly increasing";
    previous = l;
    // The float overloads (what images and uniforms use) agree with the double ones.
    const glm::vec3 v(static_cast<float>(d));
    EXPECT_NEAR(core::linearToSrgb(core::srgbToLinear(v)).g, d, 1e-6) << k;
    EXPECT_NEAR(core::srgbToLinear(v).r, l, 1e-7) << k;
  }
}

TEST(ColourSrgb, MatchesTheIecClosedFormAtKnownPoints) {
  // IEC 61966-2-1: linear below the 0.04045 break (slope 1 / 12.92), the 2.4 power law above it.
  EXPECT_EQ(core::srgbToLinear(0.0), 0.0);
  EXPECT_EQ(core::srgbToLinear(1.0), 1.0);
  EXPECT_DOUBLE_EQ(core::srgbToLinear(0.04045), 0.04045 / 12.92);
  EXPECT_DOUBLE_EQ(core::srgbToLinear(0.02), 0.02 / 12.92);
  EXPECT_DOUBLE_EQ(core::linearToSrgb(0.0031308), 0.0031308 * 12.92);
  // The two pieces meet at the break (the standard's constants make them continuous to ~1e-8).
  EXPECT_NEAR(core::srgbToLinear(0.04045), std::pow((0.04045 + 0.055) / 1.055, 2.4), 1e-7);
  EXPECT_NEAR(core::srgbToLinear(0.5), 0.214041, 1e-6);
  EXPECT_NEAR(core::srgbToLinear(128.0 / 255.0), 0.215861, 1e-6);
  EXPECT_NEAR(core::linearToSrgb(0.214041), 0.5, 1e-6);
  EXPECT_NEAR(core::linearToSrgb(0.18), 1.055 * std::pow(0.18, 1.0 / 2.4) - 0.055, 1e-15);
  // Defined for every real: negatives mirrored, values above 1 on the same power law.
  EXPECT_EQ(core::srgbToLinear(-0.5), -core::srgbToLinear(0.5));
  EXPECT_EQ(core::linearToSrgb(-0.25), -core::linearToSrgb(0.25));
  EXPECT_NEAR(core::srgbToLinear(2.0), std::pow(2.055 / 1.055, 2.4), 1e-12);
}

// ---- the view transform on the CPU -------------------------------------------------------------------

TEST(ColourView, FilmicShoulderIsIdentityBelowTheKneeAndC1AboveIt) {
  const double k = core::kFilmicKnee;
  for (double m : {0.0, 0.1, 0.3, k}) EXPECT_EQ(core::filmicShoulder(m), m);
  const double h = 1e-6;
  EXPECT_NEAR((core::filmicShoulder(k + h) - core::filmicShoulder(k)) / h, 1.0, 1e-5) << "slope 1 at the knee";
  double previous = k;
  for (double m = k + 0.01; m <= 100.0; m *= 1.1) {
    const double s = core::filmicShoulder(m);
    EXPECT_EQ(s, k + (1.0 - k) * (1.0 - std::exp(-(m - k) / (1.0 - k)))) << m;
    // Strictly below 1 and rising while exp(-(m - k) / (1 - k)) is well above double's epsilon
    // (exp(-30) = 9e-14); beyond that the shoulder rounds to exactly 1 (never above it).
    if (m < k + 30.0 * (1.0 - k)) {
      EXPECT_LT(s, 1.0) << m;
      EXPECT_GT(s, previous) << m;
    } else {
      EXPECT_LE(s, 1.0) << m;
      EXPECT_GE(s, previous) << m;
    }
    previous = s;
  }
}

TEST(ColourView, FilmicKeepsChromaticityAndLeavesColoursAtOrBelowTheKneeAlone) {
  const glm::dvec3 hues[] = {{1.0, 0.55, 0.12}, {0.2, 0.4, 1.0}, {1.0, 1.0, 1.0}, {0.05, 1.0, 0.6}, {1.0, 0.0, 0.0}};
  for (const glm::dvec3& hue : hues) {
    for (int i = 0; i <= 400; ++i) {
      const double m = 8.0 * i / 400.0;  // the largest channel, 0..8
      const glm::dvec3 in = hue * m;
      const glm::dvec3 out = core::viewTransform(in, core::ViewTransform::kFilmic);
      const glm::dvec3 lin(core::srgbToLinear(out.r), core::srgbToLinear(out.g), core::srgbToLinear(out.b));
      if (m <= core::kFilmicKnee) {
        // Unchanged: the same display values as the plain encoding (and as the standard view).
        for (int c = 0; c < 3; ++c) EXPECT_EQ(out[c], core::linearToSrgb(in[c])) << m;
        EXPECT_EQ(out, core::viewTransform(in, core::ViewTransform::kStandard)) << m;
        continue;
      }
      // One factor for all three channels: the ratios of channels (hue and saturation) are kept.
      const double f = core::filmicShoulder(m) / m;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(lin[c], in[c] * f, 1e-12) << "m " << m << " channel " << c;
      EXPECT_NEAR(std::max({lin.r, lin.g, lin.b}), core::filmicShoulder(m), 1e-12);
    }
  }
}

TEST(ColourView, StandardClipsEachChannel) {
  using core::ViewTransform;
  // Display white: 1.055 * 1 - 0.055 is 1 - 2^-53 in doubles (1.0f as a float, 255 in 8 bits).
  const double white = core::linearToSrgb(1.0);
  EXPECT_DOUBLE_EQ(white, 1.0);
  EXPECT_EQ(static_cast<float>(white), 1.0f);
  const glm::dvec3 out = core::viewTransform(glm::dvec3{2.0, 1.0, 0.5}, ViewTransform::kStandard);
  EXPECT_EQ(out, glm::dvec3(white, white, core::linearToSrgb(0.5))) << "channels above 1 clip alone: the hue shifts";
  EXPECT_EQ(core::viewTransform(glm::dvec3{4.0, 4.0, 4.0}, ViewTransform::kStandard), glm::dvec3(white));
  EXPECT_EQ(core::viewTransform(glm::dvec3{-0.2, 0.25, 8.0}, ViewTransform::kStandard),
            glm::dvec3(0.0, core::linearToSrgb(0.25), white));
  // Within [0, 1] it is the exact encoding.
  const glm::dvec3 in{0.9, 0.3, 0.001};
  const glm::dvec3 enc = core::viewTransform(in, ViewTransform::kStandard);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(enc[c], core::linearToSrgb(in[c]));
  // The image form: alpha passes through clamped to [0, 1].
  core::Image im(2, 1, 4);
  im.pixels = {4.0f, 0.5f, 0.0f, 1.7f, 0.25f, 0.25f, 0.25f, -0.5f};
  const core::Image d = core::viewTransform(im, ViewTransform::kStandard);
  EXPECT_EQ(d.at(0, 0, 0), 1.0f);
  EXPECT_EQ(d.at(0, 0, 3), 1.0f);
  EXPECT_FLOAT_EQ(d.at(1, 0, 1), static_cast<float>(core::linearToSrgb(0.25)));
  EXPECT_EQ(d.at(1, 0, 3), 0.0f);
}

// ---- through the GPU -------------------------------------------------------------------------------

class ColourGpu : public test::GlTest {
 protected:
  void TearDown() override {
    EXPECT_EQ(core::drainGlErrors(), "");
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
};

TEST_F(ColourGpu, RampColoursComeBackAsTheSameEightBitDisplayValues) {
  // A 256-texel ramp of known display colours, every 8-bit value in every channel, written as an
  // 8-bit PNG and loaded with cel::Ramp (nearest: nothing filtered). A cel-lit plane with albedo 1,
  // no ambient and a white light shows exactly q(N.L) (Eq. 2 in display values), which the shader
  // decodes to linear, the RGBA16F target stores and readColor() encodes again.
  test::ScopedTempDir dir("puff_colour");
  constexpr int kTexels = 256;
  core::Image rampImage(kTexels, 1, 3);
  auto want = [](int i) { return glm::ivec3(i, 255 - i, (i * 97 + 31) % 256); };
  for (int i = 0; i < kTexels; ++i) {
    for (int c = 0; c < 3; ++c) rampImage.at(i, 0, c) = static_cast<float>(want(i)[c]) / 255.0f;
  }
  ASSERT_OK(core::writeImage(dir / "ramp.png", rampImage, core::PixelType::kUInt8));
  auto ramp = cel::Ramp::load(dir / "ramp.png");
  ASSERT_OK(ramp);

  auto renderer = cel::OpaqueRenderer::create();
  ASSERT_OK(renderer);
  cel::OpaqueObject plane;
  plane.name = "ground";
  plane.mesh = render::toTriangleMesh(mesh::makePlane());
  plane.albedo = glm::vec3(1.0f);
  ASSERT_OK((*renderer)->setObjects({plane}));

  constexpr int kSize = 4;
  test::OffscreenTarget target(kSize);
  ASSERT_TRUE(target.complete());
  cel::Camera camera;  // orthographic, straight down onto the plane
  camera.position = {0, 5, 0};
  camera.target = {0, 0, 0};
  camera.up = {0, 0, -1};
  camera.fovYDegrees = 0.0f;
  camera.orthoHeight = 1.0f;
  camera.nearPlane = 1.0f;
  camera.farPlane = 9.0f;
  cel::Frame frame = test::linearFrame(camera, kSize, kSize);
  frame.ambient = puff::core::srgbToLinear(glm::vec3(0.0f));
  frame.light.color = glm::vec3(1.0f);
  cel::FrameBlock block;
  float worst = 0.0f;
  for (int i = 0; i < kTexels; ++i) {
    const float nDotL = (i + 0.5f) / kTexels;  // texel i's centre
    frame.light.direction = {std::sqrt(1.0f - nDotL * nDotL), nDotL, 0.0f};
    EXPECT_OK(block.upload(frame));
    ramp->bind();
    target.clear(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    (*renderer)->draw(cel::ShadePass::kLit);
    const std::vector<glm::vec4> px = target.readColor();
    EXPECT_EQ(px[kSize + 1].a, 1.0f) << "texel " << i << ": opaque objects write alpha 1";
    for (int c = 0; c < 3; ++c) {
      const float got = px[kSize + 1][c], expected = static_cast<float>(want(i)[c]) / 255.0f;
      worst = std::max(worst, std::abs(got - expected));
      EXPECT_NEAR(got, expected, 0.5f / 255.0f) << "texel " << i << ", channel " << c;
    }
  }
  std::printf("ramp round trip: worst display error %.3g (%.3f / 255)\n", worst, worst * 255.0f);
}

TEST_F(ColourGpu, ViewPassMatchesTheCpuViewTransform) {
  // A 32 x 32 scene-linear texture sweeping the largest channel over 0..8 in five hues (and alpha
  // over 0..1.5), through ViewPass into an RGBA32F target: the display values the GPU writes equal
  // core::viewTransform's (double precision) to 1e-3, for both views.
  constexpr int kSize = 32;
  const glm::vec3 hues[] = {
      {1.0f, 1.0f, 1.0f}, {1.0f, 0.55f, 0.12f}, {0.2f, 0.4f, 1.0f}, {1.0f, 0.0f, 0.0f}, {0.05f, 1.0f, 0.6f}};
  std::vector<glm::vec4> texels(kSize * kSize);
  for (int i = 0; i < kSize * kSize; ++i) {
    const float t = static_cast<float>(i) / (kSize * kSize - 1);
    texels[static_cast<std::size_t>(i)] = glm::vec4(hues[i % 5] * (8.0f * t), 1.5f * t);
  }
  core::Texture linear = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(linear.get(), 1, GL_RGBA32F, kSize, kSize);
  glTextureSubImage2D(linear.get(), 0, 0, 0, kSize, kSize, GL_RGBA, GL_FLOAT, texels.data());
  glTextureParameteri(linear.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(linear.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  auto pass = render::ViewPass::create();
  ASSERT_OK(pass);
  test::OffscreenTarget target(kSize, GL_RGBA32F);
  ASSERT_TRUE(target.complete());
  for (core::ViewTransform view : {core::ViewTransform::kStandard, core::ViewTransform::kFilmic}) {
    SCOPED_TRACE(std::string(core::toString(view)));
    target.bind();
    pass->draw(linear.get(), cel::Viewport{0, 0, kSize, kSize}, view);
    const std::vector<glm::vec4> got = target.readLinear();  // as stored: display values here
    double worst = 0.0;
    for (std::size_t i = 0; i < texels.size(); ++i) {
      const glm::dvec3 want = core::viewTransform(glm::dvec3(glm::vec3(texels[i])), view);
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(got[i][c] - want[c]));
        EXPECT_NEAR(got[i][c], want[c], 1e-3) << "texel " << i << " " << texels[i][c] << ", channel " << c;
      }
      EXPECT_EQ(got[i].a, std::clamp(texels[i].a, 0.0f, 1.0f)) << "texel " << i;
    }
    std::printf("ViewPass %s: worst |GPU - CPU| %.3g\n", std::string(core::toString(view)).c_str(), worst);
  }
}

// ---- a black body on screen ------------------------------------------------------------------------

constexpr double kKelvins[] = {2000, 2500, 3200, 4000, 5000, 6500};
constexpr double kNormalizeKelvin = 3200;

// Linear sRGB of a black body at `kelvin`, luminance 1 at kNormalizeKelvin (as the media ramp), with
// the gamut clip at 0 the media shader applies.
glm::dvec3 blackbodyLinear(double kelvin) {
  const glm::dvec3 rgb = core::xyzToLinearSrgb(core::blackbodyXYZ(kelvin)) / core::blackbodyXYZ(kNormalizeKelvin).y;
  return glm::max(rgb, glm::dvec3(0.0));
}

// One dense fire sphere per temperature in a row, each of uniform temperature (temperatureRange 0,
// no detail video: T = T0 + 0.5 T1 = T0) and emission scaled so its brightest channel is `peak` in
// the linear frame; black background, no light, orthographic camera, media layer at full size.
// Sphere i is centred on pixel (16 + 32 i, 16) of a 192 x 32 frame.
nlohmann::json blackbodyScene(double peak, const char* view = "standard") {
  nlohmann::json materials = nlohmann::json::array(), particles = nlohmann::json::array();
  for (int i = 0; i < 6; ++i) {
    const glm::dvec3 le = blackbodyLinear(kKelvins[i]);
    const std::string name = "fire" + std::to_string(static_cast<int>(kKelvins[i]));
    materials.push_back({{"name", name},
                         {"emissive", true},
                         {"temperature", kKelvins[i]},
                         {"temperatureRange", 0},
                         {"emission", peak / std::max({le.r, le.g, le.b})},
                         {"density", 40},
                         {"burn", 1}});
    particles.push_back({{"position", {-2.5 + i, 0, 0}}, {"radius", 0.45}, {"material", name}});
  }
  nlohmann::json j = {
      {"output", {{"width", 192}, {"height", 32}, {"samples", 1}, {"background", {0, 0, 0}}, {"view", view}}},
      {"camera",
       {{"position", {0, 0, 5}}, {"target", {0, 0, 0}}, {"fovY", 0}, {"orthoHeight", 1}, {"near", 1}, {"far", 10}}},
      {"ambient", {{"color", {0, 0, 0}}}},
      {"light", {{"color", {0, 0, 0}}}},
      {"media",
       {{"resolution", 1},
        {"exposure", 1},
        {"blackbody", {{"minKelvin", 1000}, {"maxKelvin", 10000}, {"normalizeKelvin", kNormalizeKelvin}}},
        {"materials", materials},
        {"particles", particles}}}};
  return j;
}

// The mean RGB of the 3 x 3 block around (cx, cy), each channel through `decode`.
template <class Decode>
glm::dvec3 blockMean(const core::Image& im, int cx, int cy, Decode decode) {
  glm::dvec3 sum(0.0);
  for (int y = cy - 1; y <= cy + 1; ++y) {
    for (int x = cx - 1; x <= cx + 1; ++x) {
      for (int c = 0; c < 3; ++c) sum[c] += decode(double{im.at(x, y, c)});
    }
  }
  return sum / 9.0;
}

class ColourBlackbody : public test::GlTest {};

TEST_F(ColourBlackbody, SpheresShowTheirTemperaturesChromaticityInExrAndPng) {
  auto scene = scene::parseScene(blackbodyScene(0.8), "blackbody.json");
  ASSERT_OK(scene);
  ASSERT_EQ(scene::viewTransformFor(*scene), core::ViewTransform::kStandard);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  render::FrameStats stats;
  auto frame = (*renderer)->renderFrame(0, &stats);
  ASSERT_OK(frame);
  ASSERT_EQ(frame->channels, 4);
  EXPECT_EQ(stats.mediaParticles, 6u);

  test::ScopedTempDir dir("puff_colour");
  // (a) The scene-linear frame as puffrender writes an EXR (half float), read back.
  ASSERT_OK(core::writeImage(dir / "frame.exr", *frame, core::PixelType::kHalf));
  auto exr = core::readImage(dir / "frame.exr");
  ASSERT_OK(exr);
  // (b) The display frame as puffrender writes a PNG (standard view, 8 bits), read back.
  const core::Image display = core::viewTransform(*frame, scene::viewTransformFor(*scene));
  ASSERT_OK(core::writeImage(dir / "frame.png", display, core::PixelType::kUInt8));
  auto png = core::readImage(dir / "frame.png");
  ASSERT_OK(png);

  for (int i = 0; i < 6; ++i) {
    const double kelvin = kKelvins[i];
    SCOPED_TRACE(kelvin);
    const int cx = 16 + 32 * i, cy = 16;
    const glm::dvec2 want = chromaticity(core::blackbodyXYZ(kelvin));
    const glm::dvec3 lin = blockMean(*exr, cx, cy, [](double v) { return v; });
    // Nothing clipped: the sphere's centre is close to the chosen peak, no channel reaches 1.
    EXPECT_GT(std::max({lin.r, lin.g, lin.b}), 0.7);
    EXPECT_LT(std::max({lin.r, lin.g, lin.b}), 1.0);
    const glm::dvec2 xyExr = chromaticity(core::linearSrgbToXyz(lin));
    const glm::dvec3 dec = blockMean(*png, cx, cy, [](double v) { return core::srgbToLinear(v); });
    const glm::dvec2 xyPng = chromaticity(core::linearSrgbToXyz(dec));
    std::printf("%5.0f K: locus (%.4f, %.4f)  EXR (%.4f, %.4f) d %.2g  PNG (%.4f, %.4f) d %.2g\n", kelvin, want.x,
                want.y, xyExr.x, xyExr.y, glm::length(xyExr - want), xyPng.x, xyPng.y, glm::length(xyPng - want));
    EXPECT_NEAR(xyExr.x, want.x, 0.003);
    EXPECT_NEAR(xyExr.y, want.y, 0.003);
    EXPECT_NEAR(xyPng.x, want.x, 0.01);
    EXPECT_NEAR(xyPng.y, want.y, 0.01);
  }
}

// ---- EXR keeps scene-linear values above 1 -----------------------------------------------------------

class ColourExr : public test::GlTest {};

TEST_F(ColourExr, WritesFourAsFourInHalfAndFloat) {
  test::ScopedTempDir dir("puff_colour");
  core::Image im(2, 2, 4);
  im.pixels = {4.0f, 0.25f, 1.0f, 1.0f, 2048.0f, 0.0f, 0.5f, 1.0f, 1.5f, 8.0f, 0.125f, 1.0f, 4.0f, 4.0f, 4.0f, 1.0f};
  for (core::PixelType type : {core::PixelType::kHalf, core::PixelType::kFloat}) {
    const fs::path file = dir / (type == core::PixelType::kHalf ? "half.exr" : "float.exr");
    ASSERT_OK(core::writeImage(file, im, type));
    auto back = core::readImage(file);
    ASSERT_OK(back);
    EXPECT_EQ(back->channels, 4);
    EXPECT_EQ(back->pixels, im.pixels) << file;  // every value is exact in half
    EXPECT_EQ(back->at(0, 0, 0), 4.0f);
  }
}

TEST_F(ColourExr, ARenderedFireAboveOneSurvivesTheHalfFloatFile) {
  // The fire spheres with their brightest channel at 4: the half-float target keeps values above 1,
  // and since they are half values, a half-float EXR gives back exactly the frame.
  auto scene = scene::parseScene(blackbodyScene(4.0), "bright.json");
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  auto frame = (*renderer)->renderFrame(0);
  ASSERT_OK(frame);
  const float peak = *std::max_element(frame->pixels.begin(), frame->pixels.end());
  EXPECT_GT(peak, 3.0f);
  EXPECT_LE(peak, 4.0f * 1.001f);
  test::ScopedTempDir dir("puff_colour");
  ASSERT_OK(core::writeImage(dir / "frame.exr", *frame, core::PixelType::kHalf));
  auto back = core::readImage(dir / "frame.exr");
  ASSERT_OK(back);
  EXPECT_EQ(back->pixels, frame->pixels);
  std::printf("brightest value in the frame and the EXR: %.4f\n", peak);
}

// puffrender as a user runs it: a fire scene to EXR keeps light above 1; to PNG is opaque and equals
// the EXR through the scene's view transform (filmic, the default with fire).
class ColourCli : public test::CliTest {
 protected:
  ColourCli() : CliTest(PUFFRENDER_EXE, "puffrender") {}
};

TEST_F(ColourCli, PuffrenderWritesLightAboveOneToExrAndAnOpaquePng) {
  nlohmann::json j = blackbodyScene(3.0);
  j["output"].erase("view");
  const fs::path scene = write("fire.json", j.dump());
  const fs::path exrPath = dir_ / "x.exr", pngPath = dir_ / "x.png";
  test::CliRun r = run(scene.string() + " -q -o " + exrPath.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = run(scene.string() + " -q -o " + pngPath.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto exr = core::readImage(exrPath);
  ASSERT_OK(exr);
  auto png = core::readImage(pngPath);
  ASSERT_OK(png);
  ASSERT_EQ(png->channels, 4);
  ASSERT_EQ(exr->channels, 4);
  ASSERT_EQ(png->width, exr->width);
  EXPECT_EQ(*core::readImageAttribute(exrPath, "puff:colorspace"), "scene-linear Rec.709");
  EXPECT_EQ(*core::readImageAttribute(pngPath, "puff:view"), "filmic");
  float peak = 0.0f;
  for (std::size_t i = 0; i < exr->pixels.size(); ++i) {
    if (i % 4 != 3) peak = std::max(peak, exr->pixels[i]);
  }
  EXPECT_GT(peak, 2.0f) << "the EXR holds scene-linear light above 1";
  int notOpaque = 0;
  for (std::size_t i = 3; i < png->pixels.size(); i += 4) notOpaque += png->pixels[i] != 1.0f;
  EXPECT_EQ(notOpaque, 0) << "PNG alpha is 255 everywhere";
  const core::Image display = core::viewTransform(*exr, core::ViewTransform::kFilmic);
  float worst = 0.0f;
  for (std::size_t i = 0; i < display.pixels.size(); ++i) {
    worst = std::max(worst, std::abs(display.pixels[i] - png->pixels[i]));
  }
  EXPECT_LE(worst, 0.5f / 255.0f + 1e-6f) << "the PNG is the EXR through the filmic view, rounded to 8 bits";
  // Filmic rolls the fire off without a hue shift: each sphere's centre, decoded from the PNG, still
  // has its black body's chromaticity (where the standard view would clip it towards yellow-white).
  for (int i = 0; i < 6; ++i) {
    SCOPED_TRACE(kKelvins[i]);
    const glm::dvec2 want = chromaticity(core::blackbodyXYZ(kKelvins[i]));
    const glm::dvec3 dec = blockMean(*png, 16 + 32 * i, 16, [](double v) { return core::srgbToLinear(v); });
    const glm::dvec2 got = chromaticity(core::linearSrgbToXyz(dec));
    EXPECT_NEAR(got.x, want.x, 0.01);
    EXPECT_NEAR(got.y, want.y, 0.01);
  }
}

// ---- alpha ------------------------------------------------------------------------------------------

class ColourAlpha : public test::GlTest {};

TEST_F(ColourAlpha, CelSceneWithOutlinesAndMsaaIsOpaqueEverywhere) {
  auto scene = scene::loadScene(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / "cloud-fig8c.json", PUFF_ART_DIR);
  ASSERT_OK(scene);
  scene->width = 240;  // half size: the same edges, a quarter of the time
  scene->height = 180;
  ASSERT_EQ(scene->samples, 4);
  ASSERT_TRUE(scene->style.outlines);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  render::FrameStats stats;
  auto frame = (*renderer)->renderFrame(0, &stats);
  ASSERT_OK(frame);
  ASSERT_EQ(frame->channels, 4);
  EXPECT_EQ(stats.particles, 135u);
  int notOpaque = 0, ink = 0;
  for (std::size_t i = 0; i < frame->pixels.size(); i += 4) {
    notOpaque += frame->pixels[i + 3] != 1.0f;
    ink += std::max({frame->pixels[i], frame->pixels[i + 1], frame->pixels[i + 2]}) < 0.01f;
  }
  EXPECT_EQ(notOpaque, 0) << "of " << frame->pixels.size() / 4 << " pixels";
  EXPECT_GT(ink, 500) << "the black outlines are drawn";
  const core::Image display = core::viewTransform(*frame, scene::viewTransformFor(*scene));
  for (std::size_t i = 3; i < display.pixels.size(); i += 4) ASSERT_EQ(display.pixels[i], 1.0f);
  // Eq. 2 is limited to the display's range before it is decoded: a cel frame holds no light above
  // display white (K_a + C K_L q exceeds 1 on this scene's lit puffs).
  float brightest = 0.0f;
  for (std::size_t i = 0; i < frame->pixels.size(); ++i) {
    if (i % 4 != 3) brightest = std::max(brightest, frame->pixels[i]);
  }
  EXPECT_LE(brightest, 1.0f);
  EXPECT_GT(brightest, 0.99f) << "white highlights are drawn";
}

// The fixed path (GL 1.x, a compatibility context) alpha-tests its puff texture: the texel's alpha
// decides coverage and never reaches the frame.
class ColourAlphaFixed : public test::GlSuite<true> {};

TEST_F(ColourAlphaFixed, FixedPathFrameIsOpaqueEverywhere) {
  auto scene = scene::loadScene(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / "magic-lamp.json", PUFF_ART_DIR);
  ASSERT_OK(scene);
  scene->width = 240;
  scene->height = 180;
  auto renderer = render::SceneRenderer::create(*scene, render::RenderPath::kFixed);
  ASSERT_OK(renderer);
  render::FrameStats stats;
  auto frame = (*renderer)->renderFrame(0, &stats);
  ASSERT_OK(frame);
  EXPECT_GT(stats.particles, 20u);
  int notOpaque = 0;
  for (std::size_t i = 3; i < frame->pixels.size(); i += 4) notOpaque += frame->pixels[i] != 1.0f;
  EXPECT_EQ(notOpaque, 0) << "of " << frame->pixels.size() / 4 << " pixels";
}

}  // namespace
}  // namespace puff
