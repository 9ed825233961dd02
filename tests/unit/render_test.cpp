// The whole cel frame through puff::render::SceneRenderer: opaque ground, a nailboard, its shadow
// volume and the shadowed pass, checked against where the light's projection puts the shadow.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include <puff/bake/baker.h>
#include <puff/core/files.h>
#include <puff/mesh/mesh.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/display.h"
#include "support/gl_fixture.h"
#include "support/sphere_atlas.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

class RenderFrame : public test::SphereAtlasTest {};

// Camera straight down (orthographic, 16 px per unit), a white sphere puff of radius R at height
// H over a ground plane, light from 45 degrees in +x: the shadow on the ground is the ellipse
// ((x + H) / (R sqrt2))^2 + (z / R)^2 < 1, coloured albedo * K_a; the rest of the ground is lit,
// albedo * (K_a + K_L) (two-tone ramp, N.L = cos 45 > 0.5).
TEST_F(RenderFrame, ShadowOnTheGroundWhereTheLightProjectsIt) {
  const float R = 0.5f, H = 2.0f;
  nlohmann::json j = {{"output", {{"width", 128}, {"height", 128}, {"samples", 1}}},
                      {"camera",
                       {{"position", {0, 10, 0}},
                        {"target", {0, 0, 0}},
                        {"up", {0, 0, -1}},
                        {"fovY", 0},
                        {"orthoHeight", 8},
                        {"near", 1},
                        {"far", 20}}},
                      {"light", {{"direction", {1, 1, 0}}, {"color", {0.5, 0.5, 0.5}}}},
                      {"ambient", {{"color", {0.2, 0.2, 0.2}}}},
                      {"atlas", sidecar_.string()},
                      {"style", {{"preset", "cel-shadows"}}},
                      {"objects", {{{"type", "plane"}, {"scale", {10, 1, 10}}, {"albedo", {1, 1, 1}}}}},
                      {"particles", {{{"position", {0, H, 0}}, {"size", 2 * R}}}}};
  auto scene = scene::parseScene(j, dir_ / "scene.json");
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  auto image = (*renderer)->renderFrame(0);
  ASSERT_OK(image);
  *image = test::display(*image);
  int shadowed = 0, lit = 0;
  for (int y = 0; y < 128; ++y) {
    for (int x = 0; x < 128; ++x) {
      // Image row 0 is the top; the camera's up is -z, so the top of the image is -z.
      const float wx = (x + 0.5f - 64.0f) / 16.0f, wz = (y + 0.5f - 64.0f) / 16.0f;
      if (std::hypot(wx, wz) < R + 0.4f) continue;  // the puff and its outline
      const float e = std::pow((wx + H) / (R * std::numbers::sqrt2_v<float>), 2.0f) + std::pow(wz / R, 2.0f);
      if (std::abs(e - 1.0f) < 0.25f) continue;  // the ellipse's edge
      const float v = image->at(x, y, 0);
      if (e < 1.0f) {
        EXPECT_NEAR(v, 0.2f, 2.0f / 255.0f) << x << "," << y;
        ++shadowed;
      } else {
        EXPECT_NEAR(v, 0.7f, 2.0f / 255.0f) << x << "," << y;
        ++lit;
      }
    }
  }
  EXPECT_GT(shadowed, 100);
  EXPECT_GT(lit, 10000);
}

// A scene with particles and no atlas, or an atlas that does not exist, fails with the file named.
TEST_F(RenderFrame, MissingAtlasIsAClearError) {
  nlohmann::json j = {{"atlas", (dir_ / "nope.json").string()}, {"particles", {{{"position", {0, 0, 0}}}}}};
  auto scene = scene::parseScene(j, dir_ / "scene.json");
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_FALSE(renderer.ok());
  EXPECT_NE(renderer.error().message.find("nope.json"), std::string::npos) << renderer.error().message;
}

TEST_F(RenderFrame, AtlasOfAnotherFormatVersionIsAClearError) {
  auto text = core::readFileBytes(sidecar_);
  ASSERT_TRUE(text.ok());
  nlohmann::json sidecar = nlohmann::json::parse(*text);
  sidecar["formatVersion"] = 99;
  const fs::path future = dir_ / "future.json";
  ASSERT_TRUE(core::writeFileAtomic(future, sidecar.dump()).ok());
  nlohmann::json j = {{"atlas", future.string()}, {"particles", {{{"position", {0, 0, 0}}}}}};
  auto scene = scene::parseScene(j, dir_ / "scene.json");
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_FALSE(renderer.ok());
  EXPECT_NE(renderer.error().message.find("future.json"), std::string::npos) << renderer.error().message;
  EXPECT_NE(renderer.error().message.find("/formatVersion"), std::string::npos) << renderer.error().message;
}

// What a renderer was switched to survives an edit that makes its path again (another size): a
// frame asked for normals still gives normals, then colour once asked back. (The other switches,
// the floor, the lit shading and the hull's occluders, travel with it: one struct.)
TEST_F(RenderFrame, SwitchesSurviveAnEditThatRemakesThePath) {
  nlohmann::json j = {{"output", {{"width", 48}, {"height", 48}, {"samples", 1}, {"background", "transparent"}}},
                      {"camera", {{"position", {0, 0, 6}}, {"target", {0, 0, 0}}, {"fovY", 0}, {"orthoHeight", 2.5}}},
                      {"atlas", sidecar_.string()},
                      {"particles", {{{"position", {0, 0, 0}}, {"size", 2}}}}};
  auto scene = scene::parseScene(j, dir_ / "scene.json");
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  ASSERT_OK((*renderer)->setOutput(cel::FrameOutput::kNormal));
  scene::Scene bigger = *scene;
  bigger.width = bigger.height = 64;
  ASSERT_OK((*renderer)->update(bigger));
  EXPECT_EQ((*renderer)->output(), cel::FrameOutput::kNormal);
  // The disc's centre faces the camera: 0.5 n + 0.5 = (0.5, 0.5, 1), where the colour would be lit.
  auto normals = (*renderer)->renderFrame(0);
  ASSERT_OK(normals);
  ASSERT_EQ(normals->width, 64);
  EXPECT_NEAR(normals->at(32, 32, 0), 0.5f, 0.02f);
  EXPECT_NEAR(normals->at(32, 32, 1), 0.5f, 0.02f);
  EXPECT_NEAR(normals->at(32, 32, 2), 1.0f, 0.02f);
  ASSERT_OK((*renderer)->setOutput(cel::FrameOutput::kColour));
  auto colour = (*renderer)->renderFrame(0);
  ASSERT_OK(colour);
  EXPECT_GT(std::abs(colour->at(32, 32, 2) - normals->at(32, 32, 2)), 0.05f) << "the colour again";
  // A path that writes no maps refuses them, changing nothing.
  auto fixed = render::SceneRenderer::create(*scene, render::RenderPath::kFixed);
  if (fixed) {
    EXPECT_FALSE((*fixed)->setOutput(cel::FrameOutput::kDepth));
    EXPECT_EQ((*fixed)->output(), cel::FrameOutput::kColour);
  }
}

}  // namespace
}  // namespace puff
