// Colour pipeline checks (docs/colour.md) that no other test pins down: the cel shader encodes the
// scene-linear colour map to a display value for Eq. 2 (8-bit sRGB and EXR maps alike), the
// outline's antialiased inner edge mixes ink and Eq. 2 in linear light, and ink of any colour is
// its display value on the nailboard and the reference paths. Each test states the closed form it
// checks against; grey (display 0.5, linear 0.214) is used where black and white would hide a
// missing decode or encode (both are fixed points of the sRGB transfer function).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/core/colour.h>
#include <puff/eval/cel_reference.h>
#include <puff/gl_api.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/display.h"
#include "support/gl_target.h"
#include "support/linear_frame.h"
#include "support/sphere_atlas.h"
#include "support/temp_dir.h"

namespace puff::colour_pipeline {
namespace {

using cel::Particle;

constexpr int kPx = 128;            // target size
constexpr float kWorld = 8.0f;      // orthographic view height: 16 px per unit
constexpr float kSize = 4.0f;       // puff diameter: R = 2 units = 32 px
constexpr float kRadiusPx = 32.0f;  // the puff's silhouette radius in pixels
constexpr float kGrey = 0.5f;       // a display value
constexpr float kEightBit = 1.0f / 255.0f;

// core::decodeSrgb: RGB decoded channel by channel (the closed form), alpha as it was; a 1- or
// 3-channel image has no alpha and every channel is decoded.
TEST(ColourDecode, DecodeSrgbDecodesColourAndLeavesAlpha) {
  core::Image rgba(2, 1, 4);
  rgba.pixels = {0.5f, 0.04f, 1.0f, 0.5f, 0.2f, 0.0f, 0.73f, 0.25f};
  const core::Image d = core::decodeSrgb(rgba);
  ASSERT_EQ(d.channels, 4);
  for (std::size_t i = 0; i < rgba.pixels.size(); ++i) {
    const float want = i % 4 == 3 ? rgba.pixels[i] : static_cast<float>(core::srgbToLinear(double{rgba.pixels[i]}));
    EXPECT_EQ(d.pixels[i], want) << "value " << i;
  }
  EXPECT_NEAR(d.pixels[0], 0.214041, 1e-6);  // ((0.5 + 0.055) / 1.055)^2.4
  EXPECT_NEAR(d.pixels[1], 0.04 / 12.92, 1e-9);
  for (int channels : {1, 3}) {
    core::Image im(1, 1, channels, 0.5f);
    const core::Image g = core::decodeSrgb(im);
    for (float v : g.pixels) EXPECT_NEAR(v, 0.214041, 1e-6) << channels << " channels";
  }
}

// Distance in pixels of pixel (x, y)'s centre from the target's centre.
float radiusPx(int x, int y) { return glm::length(glm::vec2(x + 0.5f - kPx / 2.0f, y + 0.5f - kPx / 2.0f)); }

// The scene file's camera these tests draw through: orthographic on +z, kWorld tall, as frame() below.
nlohmann::json orthoCamera() {
  return {{"position", {0, 0, 10}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fovY", 0},
          {"orthoHeight", kWorld},  {"near", 1},           {"far", 20}};
}

// Curves over life: one puff of kSize at the origin, born at 0 and living 2 s, its colour
// over life a curve of display values; ambient 0.2 and a light of 0.7, flat and without outlines, so
// K_a + tint C K_L = 0.2 + 0.7 tint wherever the body is (the sphere atlas's and mesh's C is white):
// the tint multiplies C alone, not the ambient.
nlohmann::json tintedPuffScene(const std::filesystem::path& sidecar) {
  return {
      {"output", {{"width", kPx}, {"height", kPx}, {"samples", 1}, {"background", {0, 0, 0}}}},
      {"camera", orthoCamera()},
      {"light", {{"direction", {0, 0, 1}}, {"color", {0.7, 0.7, 0.7}}}},
      {"ambient", {{"color", {0.2, 0.2, 0.2}}}},
      {"atlas", sidecar.string()},
      {"style", {{"outlines", false}, {"shading", false}, {"shadows", false}}},
      {"animation", {{"fps", 24}, {"frames", 48}}},
      {"emitters",
       {{{"count", 1},
         {"radius", 0},
         {"sizeMin", kSize},
         {"sizeMax", kSize},
         {"lifetime", 2},
         {"overLife",
          {{"size", {{"keys", {{0, 1}}}}}, {"color", {{"keys", {{0, {1.0, 0.5, 0.25}}, {1, {0.2, 0.6, 1.0}}}}}}}}}}}};
}

// Every body pixel of frame `f` (life f / 48) of the tinted puff on `path` is 0.2 + 0.7 times the
// curve's display value there, within `tolerance` (display units).
void expectTintedBody(const scene::Scene& scene, render::RenderPath path, double tolerance) {
  auto renderer = eval::createRenderer(scene, path);
  ASSERT_OK(renderer);
  const glm::vec3 birth(1.0f, 0.5f, 0.25f), death(0.2f, 0.6f, 1.0f);
  for (int f : {0, 12, 24, 36, 47}) {
    SCOPED_TRACE("frame " + std::to_string(f) + " on the " + std::string(render::toString(path)) + " path");
    auto linear = (*renderer)->renderFrame(f);
    ASSERT_OK(linear);
    const glm::vec3 want = 0.2f + 0.7f * (birth + (death - birth) * (static_cast<float>(f) / 48.0f));
    int body = 0;
    double worst = 0.0;
    for (int y = 0; y < kPx; ++y) {
      for (int x = 0; x < kPx; ++x) {
        if (radiusPx(x, y) > 0.8f * kRadiusPx) continue;
        for (int k = 0; k < 3; ++k) {
          const double got = core::linearToSrgb(double{linear->at(x, y, k)});
          worst = std::max(worst, std::abs(got - want[k]));
          EXPECT_NEAR(got, want[k], tolerance) << x << "," << y << " channel " << k;
        }
        ++body;
      }
    }
    EXPECT_GT(body, 2000);
    std::printf("%s path, frame %d: body within %.4f of K_a + tint C K_L\n",
                std::string(render::toString(path)).c_str(), f, worst);
  }
}

class ColourPipeline : public test::SphereAtlasTest {
 protected:
  static void SetUpTestSuite() { setUpSphereAtlas(true); }
  void SetUp() override {
    GlTest::SetUp();
    auto r = cel::NailboardRenderer::create();
    ASSERT_OK(r);
    renderer_ = std::move(*r);
    block_ = std::make_unique<cel::FrameBlock>();
    target_ = std::make_unique<test::OffscreenTarget>(kPx);
    ramp_ = std::make_unique<cel::Ramp>(cel::Ramp::twoTone());
  }
  void TearDown() override {
    EXPECT_EQ(core::drainGlErrors(), "");
    renderer_.reset();
    block_.reset();
    target_.reset();
    ramp_.reset();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  // Orthographic camera on +z looking down -z; world (x, y) maps to pixel (64 + 16x, 64 + 16y).
  // Light toward the viewer; light and ambient colours (display values) as given.
  static cel::Frame frame(glm::vec3 light, glm::vec3 ambient) {
    cel::Camera cam;
    cam.position = glm::vec3(0, 0, 10);
    cam.target = glm::vec3(0);
    cam.fovYDegrees = 0.0f;
    cam.orthoHeight = kWorld;
    cam.nearPlane = 1.0f;
    cam.farPlane = 21.0f;
    cel::Frame f = test::linearFrame(cam, kPx, kPx);
    f.light.direction = glm::vec3(0, 0, 1);
    f.light.color = puff::core::srgbToLinear(light);
    f.ambient = puff::core::srgbToLinear(ambient);
    return f;
  }

  // One puff of kSize at the origin over a white background; the frame as stored (scene-linear).
  std::vector<glm::vec4> drawPuff(const cel::Frame& f, const cel::Style& style) {
    target_->clear(glm::vec4(1.0f));
    EXPECT_OK(block_->upload(f));
    ramp_->bind();
    renderer_->upload(std::vector<Particle>{Particle{glm::vec3(0), kSize}});
    renderer_->drawNailboards(style, cel::ShadePass::kLit);
    return target_->readLinear();
  }

  std::unique_ptr<cel::NailboardRenderer> renderer_;
  std::unique_ptr<cel::FrameBlock> block_;
  std::unique_ptr<test::OffscreenTarget> target_;
  std::unique_ptr<cel::Ramp> ramp_;
};

// The sphere atlas with every colour texel (all levels) a display grey, alpha kept; `fileFormat`
// "png" uploads it as an 8-bit sRGB texture (decoded by the GPU), "exr" as half floats decoded on
// upload.
core::Atlas greyAtlas(const core::Atlas& atlas, const char* fileFormat) {
  core::Atlas grey = atlas;
  grey.desc.fileFormat = fileFormat;
  for (core::Image& level : grey.maps.at("color")) {
    const auto ch = static_cast<std::size_t>(level.channels);
    for (std::size_t i = 0; i < level.pixels.size(); ++i) {
      if (i % ch < 3) level.pixels[i] = kGrey;
    }
  }
  return grey;
}

// Flat Eq. 2 with no ambient and a white light: K_a + C K_L = C, the colour map's display value,
// whichever file format the map came from. (A map read as if its display values were light, or
// light used as if it were a display value, moves grey 0.5 to 0.735 or to 0.214.)
TEST_F(ColourPipeline, AGreyColourMapShowsItsDisplayValueThroughEq2) {
  cel::Style style;
  style.outlines = false;
  style.shading = false;
  for (const char* format : {"png", "exr"}) {
    SCOPED_TRACE(format);
    ASSERT_OK(renderer_->setAtlas(greyAtlas(*atlas_, format)));
    const std::vector<glm::vec4> px = drawPuff(frame(glm::vec3(1.0f), glm::vec3(0.0f)), style);
    int body = 0;
    for (int y = 0; y < kPx; ++y) {
      for (int x = 0; x < kPx; ++x) {
        if (radiusPx(x, y) > 0.9f * kRadiusPx) continue;
        const glm::vec4 c = px[static_cast<std::size_t>(y) * kPx + x];
        for (int k = 0; k < 3; ++k) {
          EXPECT_NEAR(core::linearToSrgb(double{c[k]}), kGrey, 1.5 * kEightBit) << x << "," << y << " channel " << k;
        }
        ++body;
      }
    }
    EXPECT_GT(body, 2500);
  }
}

// The outline's inner edge is antialiased: the shader mixes ink and Eq. 2 by the body's coverage b
// (from the distance map). In linear light the two complementary drawings (black ink on a white
// body, white ink on a black body) give b and 1 - b at every pixel, summing to exactly 1; mixed as
// display values they would give decode(b) + decode(1 - b), 0.43 at b = 1/2.
TEST_F(ColourPipeline, TheOutlinesInnerEdgeMixesInkAndBodyInLinearLight) {
  ASSERT_OK(renderer_->setAtlas(*atlas_));
  cel::Style style;
  style.outlines = true;
  style.outlineWidth = 2.0f;
  style.shading = false;
  style.outlineColor = glm::vec3(0.0f);
  const std::vector<glm::vec4> blackInk = drawPuff(frame(glm::vec3(0.0f), glm::vec3(1.0f)), style);  // body: K_a = 1
  style.outlineColor = glm::vec3(1.0f);
  const std::vector<glm::vec4> whiteInk = drawPuff(frame(glm::vec3(0.0f), glm::vec3(0.0f)), style);  // body: 0
  int edge = 0, checked = 0;
  double worst = 0.0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      if (radiusPx(x, y) > kRadiusPx + 1.0f) continue;  // body, inner edge and the ink band's inner half
      const std::size_t i = static_cast<std::size_t>(y) * kPx + x;
      const float b = blackInk[i].r;  // linear body coverage where ink is black and the body white
      for (int k = 0; k < 3; ++k) {
        const double sum = double{blackInk[i][k]} + double{whiteInk[i][k]};
        worst = std::max(worst, std::abs(sum - 1.0));
        EXPECT_NEAR(sum, 1.0, 0.01) << x << "," << y << " channel " << k << " (coverage " << b << ")";
      }
      if (b > 0.1f && b < 0.9f) ++edge;
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000);
  EXPECT_GT(edge, 60) << "the inner edge is antialiased (about one pixel around a 32 px circle)";
  std::printf("outline edge: %d mixed pixels, worst |b + (1 - b) - 1| %.3g\n", edge, worst);
}

// Ink: a host gives it scene-linear (display grey 0.5 is linear 0.214), a scene file as a display
// value; either way it shows as display grey in the outline band: on the nailboards, and from a
// scene file on the cel path and the cel reference path.
TEST_F(ColourPipeline, GreyInkIsItsDisplayValueOnTheNailboardsAndTheReference) {
  ASSERT_OK(renderer_->setAtlas(*atlas_));
  cel::Style style;
  style.outlines = true;
  style.outlineWidth = 2.0f;
  style.shading = false;
  style.outlineColor = puff::core::srgbToLinear(glm::vec3(kGrey));
  const std::vector<glm::vec4> nb = drawPuff(frame(glm::vec3(0.5f), glm::vec3(0.2f)), style);
  int ink = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const float r = radiusPx(x, y);
      if (r < kRadiusPx + 0.6f || r > kRadiusPx + 1.4f) continue;  // the middle of the 2 px band
      const glm::vec4 c = nb[static_cast<std::size_t>(y) * kPx + x];
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(core::linearToSrgb(double{c[k]}), kGrey, 1.5 * kEightBit) << "nailboard ink at " << x << "," << y;
      ++ink;
    }
  }
  EXPECT_GT(ink, 120);  // a 0.8 px band around a 32 px circle: about 2 pi 33 0.8 = 166

  // The reference path, through a scene file: the same puff, ink and colours; background 0.9.
  const nlohmann::json j = {
      {"output", {{"width", kPx}, {"height", kPx}, {"samples", 1}, {"background", {0.9, 0.9, 0.9}}}},
      {"camera", orthoCamera()},
      {"light", {{"direction", {0, 0, 1}}, {"color", {0.5, 0.5, 0.5}}}},
      {"ambient", {{"color", {0.2, 0.2, 0.2}}}},
      {"atlas", sidecar_.string()},
      {"style",
       {{"outlines", true},
        {"outlineWidth", 2},
        {"outlineColor", {kGrey, kGrey, kGrey}},
        {"shading", false},
        {"shadows", false}}},
      {"particles", {{{"position", {0, 0, 0}}, {"size", kSize}}}}};
  // The scene file's ink is a display value; each path takes it decoded (scene::celStyleFor) and
  // draws it as that display value again.
  auto scene = scene::parseScene(j, dir_ / "grey_ink.json");
  ASSERT_OK(scene);
  for (const render::RenderPath path : {render::RenderPath::kReference, render::RenderPath::kCel}) {
    SCOPED_TRACE(std::string(render::toString(path)) + " path from the scene file");
    auto renderer = eval::createRenderer(*scene, path);
    ASSERT_OK(renderer);
    auto linear = (*renderer)->renderFrame(0);
    ASSERT_OK(linear);
    const core::Image img = test::display(*linear);  // image row 0 at the top
    int sceneInk = 0;
    for (int y = 0; y < kPx; ++y) {
      for (int x = 0; x < kPx; ++x) {
        const float r = radiusPx(x, kPx - 1 - y);
        if (r < kRadiusPx + 0.6f || r > kRadiusPx + 1.4f) continue;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(img.at(x, y, k), kGrey, 1.5 * kEightBit) << "ink at " << x << "," << y;
        ++sceneInk;
      }
    }
    EXPECT_GT(sceneInk, 120);
  }
}

// The tint multiplies C on the nailboards (7 bits a channel: within 0.7 x half of 1/127, plus the
// frame's half floats) and on the reference (its float), at every age the curve passes through.
TEST_F(ColourPipeline, AColourCurveOverLifeTintsThePuffOnTheNailboardsAndTheReference) {
  auto scene = scene::parseScene(tintedPuffScene(sidecar_), dir_ / "tinted.json");
  ASSERT_OK(scene);
  expectTintedBody(*scene, render::RenderPath::kCel, 0.5 / 127.0 + 0.002);
  expectTintedBody(*scene, render::RenderPath::kReference, 0.002);
}

// An opaque frame has alpha 1 everywhere (docs/colour.md), the fill-rate floor's bare quads too:
// their colour map's alpha decides coverage (the alpha test) and must not reach the frame. (It failed
// before NailboardRenderer::drawBaseline masked alpha writes: 0.63, 0.72, ... on the quads' edges.)
TEST_F(ColourPipeline, TheFillRateFloorsFrameIsOpaqueEverywhere) {
  const nlohmann::json j = {
      {"output", {{"width", kPx}, {"height", kPx}, {"samples", 1}, {"background", {0.9, 0.9, 0.9}}}},
      {"camera", orthoCamera()},
      {"atlas", sidecar_.string()},
      {"style", {{"outlines", true}, {"outlineWidth", 2}, {"shading", true}, {"shadows", false}}},
      {"particles", {{{"position", {0, 0, 0}}, {"size", kSize}}, {{"position", {1.3, 0.4, 0.5}}, {"size", 1.7}}}}};
  auto scene = scene::parseScene(j, dir_ / "floor.json");
  ASSERT_OK(scene);
  auto r = render::SceneRenderer::create(*scene);
  ASSERT_OK(r);
  (*r)->setFillRateFloor(true);
  auto linear = (*r)->renderFrame(0);
  ASSERT_OK(linear);
  int notOpaque = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      if (linear->at(x, y, 3) != 1.0f) ++notOpaque;
      EXPECT_EQ(linear->at(x, y, 3), 1.0f) << x << "," << y;
    }
  }
  EXPECT_EQ(notOpaque, 0);
}

// An explosion's light on an opaque surface is light (volumetric-explosion-effects, docs/colour.md):
// its colour, a display value, is decoded, and the lit surface may exceed 1 before the view
// transform. A black wall (no ambient, no light) seen head-on behind the light's centre, where the
// light is full (w_z = 1) and the radial weight (1 - rho^2)^2 is 1 at the projected centre:
// the composed pixel is decode(colour) * intensity, here (1, 0.5, 0) * 2 -> (2, 0.428, 0).
TEST_F(ColourPipeline, AnExplosionsLightOnAWallIsDecodedAndNotLimitedToOne) {
  constexpr int kW = 64;
  const nlohmann::json j = {
      {"output", {{"width", kW}, {"height", kW}, {"samples", 1}, {"background", {0, 0, 0}}}},
      {"camera",
       {{"position", {0, 0, 10}}, {"target", {0, 0, 0}}, {"fovY", 0}, {"orthoHeight", 8}, {"near", 1}, {"far", 30}}},
      {"ambient", {{"color", {0, 0, 0}}}},
      {"light", {{"color", {0, 0, 0}}}},
      {"objects",
       {{{"type", "box"}, {"name", "wall"}, {"translate", {0, 0, -2}}, {"scale", {6, 6, 0.5}}, {"albedo", {1, 1, 1}}}}},
      {"media",
       {{"resolution", 1},
        {"materials", {{{"name", "smoke"}, {"albedo", 1}, {"density", 1}, {"detail", 0}}}},
        // One puff far outside the view: the media pass runs, nothing of it shows.
        {"particles", {{{"position", {100, 0, 0}}, {"radius", 0.5}}}},
        {"lights",
         {{{"center", {0, 0, 0}},
           {"radius", 3},
           {"color", {1.0, 0.5, 0.0}},
           {"intensity", 2},
           {"mode", "additive"}}}}}}};
  auto scene = scene::parseScene(j, dir_ / "explosion_light.json");
  ASSERT_OK(scene);
  auto r = render::SceneRenderer::create(*scene);
  ASSERT_OK(r);
  auto linear = (*r)->renderFrame(0);
  ASSERT_OK(linear);
  // Pixel (32, 32)'s centre is half a pixel (1/16 unit) off the axis in x and y: rho = 0.03.
  const glm::vec3 got(linear->at(kW / 2, kW / 2, 0), linear->at(kW / 2, kW / 2, 1), linear->at(kW / 2, kW / 2, 2));
  const glm::vec3 want = core::srgbToLinear(glm::vec3(1.0f, 0.5f, 0.0f)) * 2.0f;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 0.01f * want[k] + 0.002f) << "channel " << k;
  std::printf("explosion light on the wall: (%.4f, %.4f, %.4f), closed form (%.4f, %.4f, %.4f)\n", got.r, got.g, got.b,
              want.r, want.g, want.b);
}

// Media colours are display values decoded where they meet light (scene::linearMediaMaterials,
// scene::mediaFrameFor): the smoke's colour, the ambient and the light each multiply the light a
// smoke puff scatters, so against a black background a channel at display 0.5 is decode(0.5) =
// 0.214 of the channel at 1, whatever the puff's opacity and phase. One dense puff, head-on.
TEST_F(ColourPipeline, MediaColourAmbientAndLightAreDecodedBeforeTheyLight) {
  constexpr int kW = 32;
  auto draw = [&](glm::vec3 color, glm::vec3 ambient, glm::vec3 light) {
    const nlohmann::json j = {
        {"output", {{"width", kW}, {"height", kW}, {"samples", 1}, {"background", {0, 0, 0}}}},
        {"camera",
         {{"position", {0, 0, 6}}, {"target", {0, 0, 0}}, {"fovY", 0}, {"orthoHeight", 2}, {"near", 1}, {"far", 20}}},
        {"ambient", {{"color", {ambient.r, ambient.g, ambient.b}}}},
        {"light", {{"direction", {0, 0, 1}}, {"color", {light.r, light.g, light.b}}}},
        {"media",
         {{"resolution", 1},
          {"materials",
           {{{"name", "smoke"}, {"albedo", 1}, {"density", 2}, {"detail", 0}, {"color", {color.r, color.g, color.b}}}}},
          {"particles", {{{"position", {0, 0, 0}}, {"radius", 0.8}}}}}}};
    auto scene = scene::parseScene(j, dir_ / "media_colour.json");
    EXPECT_OK(scene);
    auto r = render::SceneRenderer::create(*scene);
    EXPECT_OK(r);
    auto linear = (*r)->renderFrame(0);
    EXPECT_OK(linear);
    return glm::vec3(linear->at(kW / 2, kW / 2, 0), linear->at(kW / 2, kW / 2, 1), linear->at(kW / 2, kW / 2, 2));
  };
  const double half = core::srgbToLinear(0.5);  // 0.214
  // Colour (1, 0.5, 1) and ambient (1, 1, 0.5), no light: green and blue are 0.214 of red.
  const glm::vec3 a = draw({1.0f, 0.5f, 1.0f}, {1.0f, 1.0f, 0.5f}, {0.0f, 0.0f, 0.0f});
  ASSERT_GT(a.r, 0.05f) << "the puff scatters the ambient";
  EXPECT_NEAR(a.g / a.r, half, 0.01) << "the material's colour";
  EXPECT_NEAR(a.b / a.r, half, 0.01) << "the ambient colour";
  // White smoke, no ambient, light (1, 0.5, 1): green is 0.214 of red.
  const glm::vec3 l = draw({1.0f, 1.0f, 1.0f}, {0.0f, 0.0f, 0.0f}, {1.0f, 0.5f, 1.0f});
  ASSERT_GT(l.r, 0.05f) << "the puff scatters the light";
  EXPECT_NEAR(l.g / l.r, half, 0.01) << "the light's colour";
  EXPECT_NEAR(l.b / l.r, 1.0, 0.01);
  std::printf("media colours: ambient-lit (%.4f, %.4f, %.4f), light-lit (%.4f, %.4f, %.4f)\n", a.r, a.g, a.b, l.r, l.g,
              l.b);
}

// The fixed path's target holds display values in 8 bits; renderFrame decodes its read-back, so the
// frame is scene-linear on every path: a background at display (0.5, 0.2, 1) comes back as
// (0.214, 0.0331, 1) within half an 8-bit step decoded (the slope is 0.93 at 0.5: under 0.002).
class ColourFixedPath : public test::GlSuite<true> {};

TEST_F(ColourFixedPath, TheFixedPathsFrameIsSceneLinear) {
  const nlohmann::json j = {
      {"output", {{"width", 16}, {"height", 16}, {"samples", 1}, {"background", {0.5, 0.2, 1.0}}}},
      {"camera",
       {{"position", {0, 0, 10}}, {"target", {0, 0, 0}}, {"fovY", 0}, {"orthoHeight", 8}, {"near", 1}, {"far", 20}}}};
  auto scene = scene::parseScene(j, "fixed_background.json");
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene, render::RenderPath::kFixed);
  ASSERT_OK(renderer);
  ASSERT_TRUE((*renderer)->targetNeeds().displayValues) << "the fixed path draws display values";
  auto frame = (*renderer)->renderFrame(0);
  ASSERT_OK(frame);
  const glm::vec3 want = core::srgbToLinear(glm::vec3(0.5f, 0.2f, 1.0f));
  for (int y = 0; y < frame->height; ++y) {
    for (int x = 0; x < frame->width; ++x) {
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(frame->at(x, y, c), want[c], 0.003f) << x << "," << y << " channel " << c;
      EXPECT_EQ(frame->at(x, y, 3), 1.0f);
    }
  }
}

// The fixed path: the sprite is K_a + tint (texel - K_a), one texture-combine interpolation of
// 8-bit values (the puff texture's texel and the frame's): within 2.5 / 255.
TEST_F(ColourFixedPath, AColourCurveOverLifeTintsThePuff) {
  test::ScopedTempDir dir("puff_tint_fixed");
  const std::filesystem::path sidecar = std::filesystem::path(PUFF_TEST_SPHERE_ATLAS_DIR) / "puff.json";  // read only
  // The fixed path draws the puff mesh itself (the sphere the atlas was baked from).
  ASSERT_OK(mesh::saveMesh(mesh::generateSphere({6}), dir.path() / "sphere.ply", mesh::SaveNormals::kYes));
  nlohmann::json j = tintedPuffScene(sidecar);
  j["fixed"] = {{"puff", (dir.path() / "sphere.ply").string()}};
  auto scene = scene::parseScene(j, dir.path() / "tinted.json");
  ASSERT_OK(scene);
  expectTintedBody(*scene, render::RenderPath::kFixed, 2.5 / 255.0);
}

}  // namespace
}  // namespace puff::colour_pipeline
