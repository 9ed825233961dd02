// Output for compositing (McGuire & Fein Fig. 8d): a transparent background whose
// alpha is the frame's coverage, written straight or premultiplied to PNG and EXR, and a plate drawn
// under the frame. Closed forms: an opaque box's edge through the middle of a pixel column covers
// exactly the samples left of it (the multisample positions, queried), and the frame's colour there
// is that share of the box's colour.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <puff/core/colour.h>
#include <puff/core/gl.h>
#include <puff/core/image.h>
#include <puff/gl_api.h>
#include <puff/render/plate.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

#include "support/assert_ok.h"
#include "support/display.h"
#include "support/gl_fixture.h"
#include "support/sphere_atlas.h"
#include "support/temp_dir.h"

namespace puff::compose {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kSize = 128;  // 16 pixels per world unit: orthoHeight 8
constexpr int kEdgeColumn = 80;

// Camera down -z, orthographic. A box x in [-2.96875, 1.03125], y in [-3, 3]: its right edge runs
// through the centre of column 80 ((80.5 - 64) / 16 = 1.03125), its top and bottom along pixel
// boundaries. A sphere puff at (2.7, 2.5), clear of the box. Light and ambient uniform: the box's
// front face is one colour.
json composeScene(const fs::path& atlas, int samples) {
  json j = {
      {"output", {{"width", kSize}, {"height", kSize}, {"samples", samples}, {"background", "transparent"}}},
      {"camera",
       {{"position", {0, 0, 10}}, {"target", {0, 0, 0}}, {"fovY", 0}, {"orthoHeight", 8}, {"near", 1}, {"far", 20}}},
      {"light", {{"direction", {0.3, 0.4, 1}}, {"color", {0.6, 0.6, 0.6}}}},
      {"ambient", {{"color", {0.3, 0.25, 0.2}}}},
      {"style", {{"preset", "cel"}}},
      {"objects",
       {{{"type", "box"}, {"translate", {-0.96875, 0, 0}}, {"scale", {2, 3, 1}}, {"albedo", {0.9, 0.5, 0.3}}}}}};
  if (!atlas.empty()) {
    j["atlas"] = atlas.string();
    j["particles"] = {{{"position", {2.7, 2.5, 0}}, {"size", 1.5}}};
  }
  return j;
}

// The share of a pixel's samples left of its centre line, from the sample positions GL reports for
// a multisampled framebuffer of `samples` (the target's format).
float coveredLeftOfCentre(int samples) {
  core::Renderbuffer rb = core::makeRenderbuffer();
  glNamedRenderbufferStorageMultisample(rb.get(), samples, GL_RGBA16F, 4, 4);
  core::Framebuffer fb = core::makeFramebuffer();
  glNamedFramebufferRenderbuffer(fb.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb.get());
  GLint previous = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fb.get());
  GLint actual = 0;
  glGetIntegerv(GL_SAMPLES, &actual);
  int left = 0;
  for (int i = 0; i < actual; ++i) {
    float p[2] = {0.0f, 0.0f};
    glGetMultisamplefv(GL_SAMPLE_POSITION, static_cast<GLuint>(i), p);
    left += p[0] < 0.5f ? 1 : 0;
  }
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(previous));
  return actual > 0 ? static_cast<float>(left) / static_cast<float>(actual) : -1.0f;
}

class RenderCompose : public test::SphereAtlasTest {};

TEST_F(RenderCompose, TransparentAlphaIsCoverage) {
  auto scene = scene::parseScene(composeScene(sidecar_, 4), dir_ / "scene.json");
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  auto image = (*renderer)->renderFrame(0);
  ASSERT_OK(image);
  const core::Image& f = *image;
  // Nothing drawn: colour and alpha 0 (the corners, far from box and puff).
  for (auto [x, y] : {std::pair{2, 2}, {125, 125}, {2, 125}, {125, 60}}) {
    for (int c = 0; c < 4; ++c) EXPECT_EQ(f.at(x, y, c), 0.0f) << x << "," << y << " channel " << c;
  }
  // Inside the box and inside the puff: alpha 1 (the puff's centre: world (2.7, 2.5)).
  EXPECT_NEAR(f.at(40, 64, 3), 1.0f, 1e-3f);
  EXPECT_NEAR(f.at(107, 23, 3), 1.0f, 1e-3f);
  EXPECT_GT(f.at(107, 23, 0), 0.01f);  // and it has colour
  // The box's edge column: alpha = the share of samples left of the pixel's centre; colour = that
  // share of the box's colour (premultiplied).
  const float share = coveredLeftOfCentre(4);
  ASSERT_GT(share, 0.0f);
  ASSERT_LT(share, 1.0f);
  for (int y : {30, 64, 100}) {
    EXPECT_NEAR(f.at(kEdgeColumn, y, 3), share, 2e-3f) << "row " << y;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f.at(kEdgeColumn, y, c), share * f.at(40, y, c), 2e-3f) << "row " << y;
    EXPECT_EQ(f.at(kEdgeColumn + 1, y, 3), 0.0f);
  }
}

// The files: straight PNG holds the box's display colour and the share as alpha; premultiplied PNG
// the display colour times the share; EXR the scene-linear premultiplied values (half floats).
TEST_F(RenderCompose, StraightAndPremultipliedFilesHoldTheClosedForms) {
  auto scene = scene::parseScene(composeScene(sidecar_, 4), dir_ / "scene.json");
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  auto image = (*renderer)->renderFrame(0);
  ASSERT_OK(image);
  const float share = coveredLeftOfCentre(4);
  const int y = 64;
  const glm::vec3 linear(image->at(40, y, 0), image->at(40, y, 1), image->at(40, y, 2));  // the box, covered
  const glm::vec3 display = core::linearToSrgb(linear);
  test::ScopedTempDir tmp("puff_compose");
  const auto view = core::ViewTransform::kStandard;
  for (core::AlphaMode mode : {core::AlphaMode::kStraight, core::AlphaMode::kPremultiplied}) {
    const fs::path png = tmp.path() / (std::string(core::toString(mode)) + ".png");
    ASSERT_OK(core::writeImage(png, core::viewTransform(*image, view, mode), core::PixelType::kUInt8));
    auto read = core::readImage(png);
    ASSERT_OK(read);
    ASSERT_EQ(read->channels, 4);
    const float k = mode == core::AlphaMode::kStraight ? 1.0f : share;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(read->at(kEdgeColumn, y, c), display[c] * k, 1.0f / 255.0f) << core::toString(mode) << " " << c;
      EXPECT_NEAR(read->at(40, y, c), display[c], 1.0f / 255.0f);
      EXPECT_EQ(read->at(2, 2, c), 0.0f);  // alpha 0: colour 0 (the guard), both ways
    }
    EXPECT_NEAR(read->at(kEdgeColumn, y, 3), share, 1.0f / 255.0f);
    EXPECT_EQ(read->at(2, 2, 3), 0.0f);
  }
  const fs::path exr = tmp.path() / "premultiplied.exr";
  ASSERT_OK(core::writeImage(exr, *image, core::PixelType::kHalf));
  auto read = core::readImage(exr);
  ASSERT_OK(read);
  // Half floats: 11 significant bits; the alpha is a difference of two frames, a few ulps near 1.
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(read->at(kEdgeColumn, y, c), share * linear[c], 2e-3f);
  EXPECT_NEAR(read->at(kEdgeColumn, y, 3), share, 2e-3f);
  EXPECT_EQ(read->at(2, 2, 3), 0.0f);
}

TEST(RenderComposeAlpha, UnpremultiplyAndViewTransformClosedForms) {
  // One half-covered pixel of scene-linear colour c, and one empty pixel.
  core::Image p(2, 1, 4, 0.0f);
  const glm::vec3 c(0.2f, 0.5f, 0.8f);
  for (int i = 0; i < 3; ++i) p.at(0, 0, i) = 0.5f * c[i];
  p.at(0, 0, 3) = 0.5f;
  const core::Image s = core::unpremultiply(p);
  for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(s.at(0, 0, i), c[i]);
  EXPECT_FLOAT_EQ(s.at(0, 0, 3), 0.5f);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(s.at(1, 0, i), 0.0f);  // alpha 0: no division
  const core::Image straight = core::viewTransform(p, core::ViewTransform::kStandard, core::AlphaMode::kStraight);
  const core::Image pre = core::viewTransform(p, core::ViewTransform::kStandard, core::AlphaMode::kPremultiplied);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(straight.at(0, 0, i), core::linearToSrgb(double{c[i]}), 1e-6);
    EXPECT_NEAR(pre.at(0, 0, i), 0.5 * core::linearToSrgb(double{c[i]}), 1e-6);
  }
  EXPECT_FLOAT_EQ(pre.at(0, 0, 3), 0.5f);
}

// The plate: a deterministic 8-bit pattern, the frame's size, shows exactly where nothing is drawn.
core::Image platePattern(int w, int h) {
  core::Image img(w, h, 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      img.at(x, y, 0) = static_cast<float>((x * 7 + y * 3) % 256) / 255.0f;
      img.at(x, y, 1) = static_cast<float>((x * 2 + y * 11) % 256) / 255.0f;
      img.at(x, y, 2) = static_cast<float>((255 - x - y + 512) % 256) / 255.0f;
    }
  }
  return img;
}

json plateScene(const fs::path& plate) {
  json j = composeScene({}, 4);
  j["output"]["background"] = "#ff00ff";  // never seen: the plate replaces it
  j["output"]["plate"] = plate.string();
  return j;
}

// Counts, over the pixels right of the box (x > 82), those whose display value differs from the
// plate's by more than `tol` in any channel.
int plateMismatches(const core::Image& displayed, const core::Image& plate, float tol) {
  int bad = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 83; x < kSize; ++x) {
      for (int c = 0; c < 3; ++c) bad += std::abs(displayed.at(x, y, c) - plate.at(x, y, c)) > tol ? 1 : 0;
    }
  }
  return bad;
}

TEST_F(RenderCompose, PlateShowsWhereNothingIsDrawn) {
  const core::Image plate = platePattern(kSize, kSize);
  ASSERT_OK(core::writeImage(dir_ / "plate.png", plate, core::PixelType::kUInt8));
  auto scene = scene::parseScene(plateScene("plate.png"), dir_ / "scene.json");
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  auto image = (*renderer)->renderFrame(0);
  ASSERT_OK(image);
  const core::Image shown = test::display(*image);
  // Half-float scene-linear and back: within one 8-bit step.
  EXPECT_EQ(plateMismatches(shown, plate, 1.0f / 255.0f + 1e-6f), 0);
  EXPECT_GT(std::abs(shown.at(40, 64, 0) - plate.at(40, 64, 0)) + std::abs(shown.at(40, 64, 2) - plate.at(40, 64, 2)),
            0.02f);  // the box is drawn over it
  EXPECT_EQ(image->at(100, 100, 3), 1.0f);

  // A smaller plate is stretched (render::resizePlate, in scene-linear light).
  const core::Image small = platePattern(40, 30);
  ASSERT_OK(core::writeImage(dir_ / "small.png", small, core::PixelType::kUInt8));
  scene::Scene next = *scene;
  next.plate = dir_ / "small.png";
  ASSERT_OK((*renderer)->update(next));  // the reload rule: a new plate is loaded
  auto stretched = (*renderer)->renderFrame(0);
  ASSERT_OK(stretched);
  auto decoded = render::loadPlate(next);
  ASSERT_OK(decoded);
  const core::Image expected = test::display(render::resizePlate(*decoded, kSize, kSize));
  EXPECT_EQ(plateMismatches(test::display(*stretched), expected, 1.0f / 255.0f + 1e-6f), 0);

  // A plate that is not there: one line naming the scene, the field and the file; the renderer keeps
  // what it had.
  next.plate = dir_ / "missing.png";
  auto failed = (*renderer)->update(next);
  ASSERT_FALSE(failed.ok());
  const std::string& m = failed.error().message;
  EXPECT_NE(m.find("scene.json: /output/plate: "), std::string::npos) << m;
  EXPECT_NE(m.find("missing.png"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  auto again = render::SceneRenderer::create(next);
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.error().message, m);
}

TEST(RenderComposePlate, ResizeClosedForms) {
  core::Image ramp(2, 1, 1);
  ramp.at(1, 0) = 1.0f;
  // Enlarging is bilinear between pixel centres, clamped at the edges.
  const core::Image up = render::resizePlate(ramp, 4, 1);
  const float expectUp[4] = {0.0f, 0.25f, 0.75f, 1.0f};
  for (int x = 0; x < 4; ++x) EXPECT_FLOAT_EQ(up.at(x, 0), expectUp[x]);
  // Shrinking 4 -> 2: a tent two source pixels wide around 0.5 and 2.5 (weights 1/8, 3/8, 3/8, 1/8).
  core::Image step(4, 1, 1);
  step.at(2, 0) = step.at(3, 0) = 1.0f;
  const core::Image down = render::resizePlate(step, 2, 1);
  EXPECT_FLOAT_EQ(down.at(0, 0), 0.125f);
  EXPECT_FLOAT_EQ(down.at(1, 0), 0.875f);
  // The same size: the image as it is.
  EXPECT_EQ(render::resizePlate(step, 4, 1).pixels, step.pixels);
}

// The fixed path: the plate is its host frame (drawn first, no clear), in display values exactly;
// a transparent frame's alpha is its coverage too.
class RenderComposeFixed : public test::GlSuite<true> {};

TEST_F(RenderComposeFixed, PlateAndTransparentOnTheFixedPath) {
  test::ScopedTempDir tmp("puff_compose_fixed");
  const core::Image plate = platePattern(kSize, kSize);
  ASSERT_OK(core::writeImage(tmp.path() / "plate.png", plate, core::PixelType::kUInt8));
  auto scene = scene::parseScene(plateScene("plate.png"), tmp.path() / "scene.json");
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene, render::RenderPath::kFixed);
  ASSERT_OK(renderer);
  auto image = (*renderer)->renderFrame(0);
  ASSERT_OK(image);
  EXPECT_EQ(plateMismatches(test::display(*image), plate, 0.5f / 255.0f), 0);
  EXPECT_GT(std::abs(test::display(*image).at(40, 64, 2) - plate.at(40, 64, 2)), 0.02f);

  auto transparent = scene::parseScene(composeScene({}, 1), tmp.path() / "scene.json");
  ASSERT_OK(transparent);
  auto fixed = render::SceneRenderer::create(*transparent, render::RenderPath::kFixed);
  ASSERT_OK(fixed);
  auto frame = (*fixed)->renderFrame(0);
  ASSERT_OK(frame);
  EXPECT_EQ(frame->at(2, 2, 3), 0.0f);
  EXPECT_EQ(frame->at(125, 125, 3), 0.0f);
  EXPECT_NEAR(frame->at(40, 64, 3), 1.0f, 1e-6f);
  EXPECT_GT(frame->at(40, 64, 0), 0.01f);
}

TEST(SceneOutput, TransparentAlphaAndPlateReadAndRoundTrip) {
  const fs::path file = "/scenes/x.json";
  json j = {{"output", {{"background", "transparent"}, {"alpha", "premultiplied"}}}};
  auto s = scene::parseScene(j, file);
  ASSERT_OK(s);
  EXPECT_TRUE(s->transparent);
  EXPECT_EQ(s->alpha, core::AlphaMode::kPremultiplied);
  auto back = scene::parseScene(scene::toJson(*s), file);
  ASSERT_OK(back);
  EXPECT_EQ(*back, *s);
  EXPECT_EQ(scene::toJson(*back)["output"]["background"], "transparent");

  auto p = scene::parseScene(json{{"output", {{"plate", "../plates/hills.png"}, {"background", "#102030"}}}}, file);
  ASSERT_OK(p);
  EXPECT_EQ(p->plate, fs::path("/plates/hills.png"));
  EXPECT_FALSE(p->transparent);
  const json written = scene::toJson(*p);
  EXPECT_EQ(written["output"]["plate"], "../plates/hills.png");
  EXPECT_FALSE(written["output"].contains("alpha"));
  auto p2 = scene::parseScene(written, file);
  ASSERT_OK(p2);
  EXPECT_EQ(*p2, *p);
}

TEST(SceneOutput, CompositingErrorsNameTheField) {
  const fs::path file = "x.json";
  auto expectError = [&](const json& j, const std::string& part) {
    auto s = scene::parseScene(j, file);
    ASSERT_FALSE(s.ok()) << j.dump();
    EXPECT_NE(s.error().message.find(part), std::string::npos) << s.error().message;
  };
  expectError({{"output", {{"background", "transparent"}, {"plate", "p.png"}}}}, "/output/plate: ");
  expectError({{"output", {{"alpha", "straight"}}}}, "/output/alpha: only with");
  expectError({{"output", {{"background", "transparent"}, {"alpha", "linear"}}}}, "/output/alpha");
  expectError({{"output", {{"background", "clear"}}}}, "\"transparent\"");
}

}  // namespace
}  // namespace puff::compose
