// The cel reference (RenderPath::kReference): the image the nailboards approximate, checked
// against what geometry alone says: a sphere puff is a disc of its size, shaded by q(N.L) of the
// sphere's normals, ringed by ink of the outline's width; shadows fall where the light projects the
// puff, on the ground and on other puffs, never on the puff itself. Then the nailboards against it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <puff/bake/baker.h>
#include <puff/core/files.h>
#include <puff/eval/cel_reference.h>
#include <puff/mesh/mesh.h>
#include <puff/reference/metrics.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/display.h"
#include "support/gl_fixture.h"
#include "support/sphere_atlas.h"

namespace puff {
namespace {

namespace fs = std::filesystem;
constexpr int kPx = 128;
constexpr float kPxPerUnit = 16.0f;  // orthoHeight 8 over 128 pixels

class CelReference : public test::SphereAtlasTest {
 protected:
  // An orthographic camera looking down -z at the origin, 16 px per unit, white light K_L, ambient
  // 0.2, background 0.9; `style` and `particles` (and `objects`) as given.
  static nlohmann::json frontScene(const nlohmann::json& style, const nlohmann::json& particles,
                                   const glm::vec3& light = {0, 0, 1}) {
    return {{"output", {{"width", kPx}, {"height", kPx}, {"samples", 1}, {"background", {0.9, 0.9, 0.9}}}},
            {"camera",
             {{"position", {0, 0, 10}},
              {"target", {0, 0, 0}},
              {"up", {0, 1, 0}},
              {"fovY", 0},
              {"orthoHeight", 8},
              {"near", 1},
              {"far", 20}}},
            {"light", {{"direction", {light.x, light.y, light.z}}, {"color", {0.5, 0.5, 0.5}}}},
            {"ambient", {{"color", {0.2, 0.2, 0.2}}}},
            {"atlas", sidecar_.string()},
            {"style", style},
            {"particles", particles}};
  }

  static core::Image render(const nlohmann::json& j, render::RenderPath path = render::RenderPath::kReference) {
    auto scene = scene::parseScene(j, dir_ / "scene.json");
    EXPECT_OK(scene);
    if (!scene) return {};
    auto renderer = eval::createRenderer(*scene, path);
    EXPECT_OK(renderer);
    if (!renderer) return {};
    auto image = (*renderer)->renderFrame(0);
    EXPECT_OK(image);
    return image ? test::display(*image) : core::Image{};
  }

  // World (x, y) of pixel (px, py)'s centre in the front scene (image row 0 at the top).
  static glm::vec2 world(int px, int py) {
    return {(px + 0.5f - kPx / 2) / kPxPerUnit, (kPx / 2 - py - 0.5f) / kPxPerUnit};
  }
};

const nlohmann::json kFlat = {{"outlines", false}, {"shading", false}, {"shadows", false}};

TEST_F(CelReference, ASpherePuffIsADiscOfItsSizeInEq2sFlatColour) {
  const float R = 2.0f;  // size 4: 32 pixels across
  const core::Image img = render(frontScene(kFlat, {{{"position", {0, 0, 0}}, {"size", 2 * R}}}));
  ASSERT_EQ(img.width, kPx);
  int inside = 0, outside = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const float r = glm::length(world(x, y));
      if (std::abs(r - R) < 1.0f / kPxPerUnit) continue;  // the antialiased edge
      // Flat Eq. 2: K_a + C K_L = 0.2 + 1 * 0.5 (white puff); background 0.9.
      const float expected = r < R ? 0.7f : 0.9f;
      EXPECT_NEAR(img.at(x, y, 0), expected, 1.5f / 255.0f) << x << "," << y;
      (r < R ? inside : outside)++;
    }
  }
  EXPECT_GT(inside, 3000);
  EXPECT_GT(outside, 10000);
}

// Light along +x, two-tone ramp (q = 0 below 0.5, 1 from 0.5): a sphere's normal at image offset
// (dx, dy) from its centre is (dx, dy, sqrt(R^2 - dx^2 - dy^2)) / R, so the lit band is dx > R / 2.
TEST_F(CelReference, ShadingIsQOfTheSpheresOwnNormals) {
  const float R = 2.0f;
  const nlohmann::json style = {{"outlines", false}, {"shading", true}, {"shadows", false}};
  const core::Image img = render(frontScene(style, {{{"position", {0, 0, 0}}, {"size", 2 * R}}}, {1, 0, 0}));
  ASSERT_EQ(img.width, kPx);
  int lit = 0, dark = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const glm::vec2 w = world(x, y);
      if (glm::length(w) > R - 2.0f / kPxPerUnit) continue;
      const float nDotL = w.x / R;
      if (std::abs(nDotL - 0.5f) < 2.0f / (kPxPerUnit * R)) continue;  // the band's edge
      const float expected = nDotL >= 0.5f ? 0.7f : 0.2f;
      EXPECT_NEAR(img.at(x, y, 0), expected, 1.5f / 255.0f) << x << "," << y;
      (nDotL >= 0.5f ? lit : dark)++;
    }
  }
  EXPECT_GT(lit, 300);
  EXPECT_GT(dark, 1500);
}

// Ink 2 pixels wide just outside the silhouette; none inside; background beyond.
TEST_F(CelReference, OutlinesRingTheTrueSilhouetteAtTheirWidth) {
  const float R = 2.0f;
  const nlohmann::json style = {{"outlines", true}, {"outlineWidth", 2}, {"shading", false}, {"shadows", false}};
  const core::Image img = render(frontScene(style, {{{"position", {0, 0, 0}}, {"size", 2 * R}}}));
  ASSERT_EQ(img.width, kPx);
  int ink = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const float rPx = glm::length(world(x, y)) * kPxPerUnit, edge = R * kPxPerUnit;
      if (rPx < edge - 1.0f) {
        EXPECT_NEAR(img.at(x, y, 0), 0.7f, 1.5f / 255.0f) << x << "," << y;
      } else if (rPx > edge + 0.5f && rPx < edge + 1.5f) {
        EXPECT_LT(img.at(x, y, 0), 0.05f) << "ink at " << x << "," << y;
        ++ink;
      } else if (rPx > edge + 3.0f) {
        EXPECT_NEAR(img.at(x, y, 0), 0.9f, 1.5f / 255.0f) << x << "," << y;
      }
    }
  }
  EXPECT_GT(ink, 150);  // about 2 pi 32
}

// The ink is every pixel within the outline's width of the silhouette: its outer edge is a circle
// of radius R + width around a sphere puff, measured from the areas the ink and the body cover
// (point-sampled, one sample a pixel, as the tumble sweep draws it). Over the sizes and widths a
// style can set: the bands of a polygon's edges drawn as rectangles reach past that at every corner
// (by up to 0.41 widths; 0.25 px at width 4 on this sphere).
TEST_F(CelReference, InkReachesTheOutlinesWidthAndNoFarther) {
  for (float R : {1.0f, 2.0f, 3.0f}) {
    for (float width : {1.0f, 2.0f, 4.0f, 8.0f}) {
      const nlohmann::json style = {
          {"outlines", true}, {"outlineWidth", width}, {"shading", false}, {"shadows", false}};
      auto scene =
          scene::parseScene(frontScene(style, {{{"position", {0, 0, 0}}, {"size", 2 * R}}}), dir_ / "ink.json");
      ASSERT_OK(scene);
      auto reference = eval::createCelReference(*scene, eval::CelReferenceOptions{.supersample = 1});
      ASSERT_OK(reference);
      auto frame = (*reference)->renderFrame(0);
      ASSERT_OK(frame);
      const core::Image img = test::display(*frame);
      int covered = 0, ink = 0;
      for (int y = 0; y < kPx; ++y) {
        for (int x = 0; x < kPx; ++x) {
          covered += std::abs(img.at(x, y, 0) - 0.9f) > 0.01f;
          ink += img.at(x, y, 0) < 0.05f;
        }
      }
      const double outer = std::sqrt(covered / std::numbers::pi), body = std::sqrt((covered - ink) / std::numbers::pi);
      const double r = R * kPxPerUnit;
      EXPECT_NEAR(outer, r + width, 0.15) << "sphere " << r << " px, width " << width;
      EXPECT_NEAR(body, r, 0.15) << "sphere " << r << " px, width " << width;
    }
  }
}

// A nearer puff hides the farther one's outline where it covers it: no ink inside the nearer disc.
TEST_F(CelReference, ANearerPuffHidesTheFartherOnesOutline) {
  const float R = 1.5f;
  const nlohmann::json style = {{"outlines", true}, {"outlineWidth", 2}, {"shading", false}, {"shadows", false}};
  const core::Image img = render(
      frontScene(style, {{{"position", {-1, 0, -2}}, {"size", 2 * R}}, {{"position", {1, 0, 2}}, {"size", 2 * R}}}));
  ASSERT_EQ(img.width, kPx);
  int checked = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const glm::vec2 w = world(x, y);
      // Inside the near puff (centre x = 1), away from its own rim: its body only, although the far
      // puff's silhouette (centre x = -1) passes behind.
      if (glm::length(w - glm::vec2(1, 0)) < R - 1.0f / kPxPerUnit &&
          std::abs(glm::length(w - glm::vec2(-1, 0)) - R) < 2.0f / kPxPerUnit) {
        EXPECT_NEAR(img.at(x, y, 0), 0.7f, 1.5f / 255.0f) << x << "," << y;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 20);
}

// The ground shadow where the light projects the puff (the same scene as render_test's nailboard
// check): camera straight down, puff of radius R at height H, light from 45 degrees in +x.
TEST_F(CelReference, ShadowOnTheGroundIsTheLightsProjectionOfThePuff) {
  const float R = 0.5f, H = 2.0f;
  nlohmann::json j = {{"output", {{"width", kPx}, {"height", kPx}, {"samples", 1}}},
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
  const core::Image img = render(j);
  ASSERT_EQ(img.width, kPx);
  int shadowed = 0, lit = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const float wx = (x + 0.5f - 64.0f) / 16.0f, wz = (y + 0.5f - 64.0f) / 16.0f;
      if (std::hypot(wx, wz) < R + 0.4f) continue;  // the puff and its outline
      const float e = std::pow((wx + H) / (R * std::numbers::sqrt2_v<float>), 2.0f) + std::pow(wz / R, 2.0f);
      if (std::abs(e - 1.0f) < 0.15f) continue;  // the ellipse's antialiased edge
      const float v = img.at(x, y, 0);
      if (e < 1.0f) {
        EXPECT_NEAR(v, 0.2f, 1.5f / 255.0f) << x << "," << y;
        ++shadowed;
      } else {
        EXPECT_NEAR(v, 0.7f, 1.5f / 255.0f) << x << "," << y;
        ++lit;
      }
    }
  }
  EXPECT_GT(shadowed, 40);
  EXPECT_GT(lit, 10000);
}

// Light straight down the y axis onto two touching puffs, one above the other, seen from the front
// with flat shading: every point of the lower puff has the upper one straight above it, so the whole
// lower puff is in shadow; nothing shadows the upper puff, and it does not shadow itself (its lower
// half, whose way to the light crosses only its own body, stays lit).
TEST_F(CelReference, PuffsShadowEachOtherButNeverThemselves) {
  const float R = 1.0f;
  const nlohmann::json style = {{"outlines", false}, {"shading", false}, {"shadows", true}};
  const nlohmann::json particles = {{{"position", {0, R, 0}}, {"size", 2 * R}},
                                    {{"position", {0, -R, 0}}, {"size", 2 * R}}};
  const core::Image img = render(frontScene(style, particles, {0, 1, 0}));
  ASSERT_EQ(img.width, kPx);
  int upperTop = 0, upperBottom = 0, lower = 0;
  const float margin = 2.0f / kPxPerUnit;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const glm::vec2 w = world(x, y);
      const float v = img.at(x, y, 0);
      if (glm::length(w - glm::vec2(0, R)) < R - margin && w.y > margin) {
        EXPECT_NEAR(v, 0.7f, 1.5f / 255.0f) << "upper puff lit at " << x << "," << y;
        (w.y < R ? upperBottom : upperTop)++;
      } else if (glm::length(w - glm::vec2(0, -R)) < R - margin && w.y < -margin &&
                 R * R - (w.y + R) * (w.y + R) < (R - 0.05f) * (R - 0.05f)) {
        // (x^2 + z^2 = R^2 - (y + R)^2 on the lower sphere: its way up passes 0.05 inside the upper
        // puff's rim, not grazing it.)
        EXPECT_NEAR(v, 0.2f, 1.5f / 255.0f) << "lower puff shadowed at " << x << "," << y;
        ++lower;
      }
    }
  }
  EXPECT_GT(upperTop, 250);
  EXPECT_GT(upperBottom, 250);
  EXPECT_GT(lower, 250);
}

// The nailboards approximate the reference: on a sphere puff with shading, outlines and a ground
// shadow the RMSE stays small and the coverage agrees; the error is what the 128-texel atlas, the
// billboard's flat depth for the shadow cap and the distance-map outline cost.
TEST_F(CelReference, NailboardsComeCloseToTheReferenceOnASpherePuff) {
  nlohmann::json j = frontScene(
      {{"outlines", true}, {"outlineWidth", 2}, {"shading", true}, {"shadows", false}},
      {{{"position", {0.3, 0.2, 0}}, {"size", 3.0}}, {{"position", {-1.2, -0.8, 1}}, {"size", 2.0}}}, {0.4, 0.8, 0.45});
  const core::Image ref = render(j);
  const core::Image cel = render(j, render::RenderPath::kCel);
  nlohmann::json bareJson = j;
  bareJson["particles"] = nlohmann::json::array();
  const core::Image bare = render(bareJson, render::RenderPath::kCel);
  ASSERT_EQ(ref.width, kPx);
  ASSERT_EQ(cel.width, kPx);
  if (const char* dir = std::getenv("PUFF_DEBUG_DIR")) {
    (void)core::writeImage(fs::path(dir) / "ref.png", ref, core::PixelType::kUInt8);
    (void)core::writeImage(fs::path(dir) / "cel.png", cel, core::PixelType::kUInt8);
  }
  const reference::ImageError e = reference::imageError(cel, ref);
  const double iou = reference::coverageIoU(cel, ref, bare);
  // Measured: RMSE 0.045, IoU 0.955. The nailboards' outer ink edge is hard (one sample a pixel) where
  // the reference's is antialiased, so the reference's mask (any pixel 1/64 off the background) runs
  // about half a pixel wider around the ~250 pixels of silhouette.
  EXPECT_LT(e.rmse, 0.06) << "nailboards vs reference";
  EXPECT_GT(iou, 0.94);
  std::printf("nailboards vs reference on two sphere puffs: RMSE %.4f, coverage IoU %.4f\n", e.rmse, iou);
  // The reference is not the nailboards: they differ somewhere (the test would pass on a copy).
  EXPECT_GT(e.rmse, 1e-3);
}

// A frame is a function of the scene and its number, not of what was drawn before: with the camera
// orbiting, frame 6 after frame 0 equals frame 6 drawn first (the puff ids, shadow maps and copies
// the reference keeps between frames are all cleared or rewritten).
TEST_F(CelReference, AFrameDoesNotDependOnTheFramesBeforeIt) {
  nlohmann::json j = {
      {"output", {{"width", 96}, {"height", 72}, {"samples", 1}}},
      {"camera", {{"position", {0, 4, 8}}, {"target", {0, 0.5, 0}}, {"near", 1}, {"far", 30}}},
      {"light", {{"direction", {0.6, 1, 0.2}}, {"color", {0.5, 0.5, 0.5}}}},
      {"atlas", sidecar_.string()},
      {"style", {{"preset", "cel-shadows"}}},
      {"objects", {{{"type", "plane"}, {"scale", {6, 1, 6}}}}},
      {"particles", {{{"position", {-1.5, 1.2, 0}}, {"size", 1.5}}, {{"position", {1, 1.6, 0.5}}, {"size", 1.2}}}},
      {"animation", {{"fps", 4}, {"frames", 8}, {"orbit", 60}}}};
  auto scene = scene::parseScene(j, dir_ / "scene.json");
  ASSERT_OK(scene);
  auto first = eval::createCelReference(*scene);
  ASSERT_OK(first);
  ASSERT_TRUE((*first)->renderFrame(0).ok());
  auto after = (*first)->renderFrame(6);
  auto fresh = eval::createCelReference(*scene);
  ASSERT_TRUE(fresh.ok());
  auto alone = (*fresh)->renderFrame(6);
  ASSERT_TRUE(after.ok() && alone.ok());
  EXPECT_EQ(after->pixels, alone->pixels);
}

// The benchmarks' fill-rate floor: the same particles as bare alpha-tested quads of the atlas colour,
// no shading: the puff's disc white (C as baked), and the flange alpha-tested in over the same
// pixels as the nailboard's ink (in the puff's colour, which the atlas carries out past the
// silhouette: white, not the 0.9 background).
TEST_F(CelReference, TheFillRateFloorDrawsBareQuads) {
  const float R = 2.0f;
  nlohmann::json j = frontScene({{"outlines", true}, {"outlineWidth", 2}, {"shading", true}, {"shadows", false}},
                                {{{"position", {0, 0, 0}}, {"size", 2 * R}}});
  auto scene = scene::parseScene(j, dir_ / "scene.json");
  ASSERT_OK(scene);
  auto r = render::SceneRenderer::create(*scene);
  ASSERT_OK(r);
  auto lit = (*r)->renderFrame(0);
  (*r)->setFillRateFloor(true);
  auto floor = (*r)->renderFrame(0);
  if (lit) *lit = test::display(*lit);
  if (floor) *floor = test::display(*floor);
  ASSERT_TRUE(lit.ok() && floor.ok());
  int disc = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const float rPx = glm::length(world(x, y)) * kPxPerUnit, edge = R * kPxPerUnit;
      if (rPx < edge - 1.5f) {
        ++disc;
        EXPECT_NEAR(floor->at(x, y, 0), 1.0f, 3.0f / 255.0f) << "unshaded C at " << x << "," << y;  // (its mips)
        EXPECT_LT(lit->at(x, y, 0), 0.71f) << "Eq. 2 at " << x << "," << y;
      }
      if (rPx > edge + 0.6f && rPx < edge + 1.5f) {  // past the inner edge's antialiasing (dist < 0.5 px)
        EXPECT_LT(lit->at(x, y, 0), 0.05f) << "the nailboard's ink at " << x << "," << y;
        EXPECT_GT(floor->at(x, y, 0), 0.97f) << "the flange on the floor at " << x << "," << y;
      }
    }
  }
  EXPECT_GT(disc, 2500);
}

TEST_F(CelReference, AStaleOrMissingSourceMeshIsNamed) {
  const fs::path dir = dir_ / "stale";
  fs::create_directories(dir);
  const fs::path meshFile = dir / "blob.obj";
  ASSERT_TRUE(mesh::saveMesh(mesh::generateSphere({2}), meshFile).ok());
  bake::BakeOptions o;
  o.cellSize = 32;
  o.outDir = dir / "atlas";
  o.contactSheet = false;
  auto sources = bake::loadSources({meshFile}, std::nullopt);
  ASSERT_OK(sources);
  auto baked = bake::bakeAtlas(*sources, o);
  ASSERT_OK(baked);
  nlohmann::json j = frontScene(kFlat, {{{"position", {0, 0, 0}}}});
  j["atlas"] = baked->sidecar.string();
  auto scene = scene::parseScene(j, dir / "scene.json");
  ASSERT_OK(scene);
  ASSERT_TRUE(eval::createCelReference(*scene).ok());

  std::ofstream(meshFile, std::ios::app) << "# edited\n";
  auto stale = eval::createCelReference(*scene);
  ASSERT_FALSE(stale.ok());
  EXPECT_NE(stale.error().message.find(meshFile.string() + " has changed since the atlas was baked"), std::string::npos)
      << stale.error().message;

  fs::remove(meshFile);
  auto missing = eval::createCelReference(*scene);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("cannot be read"), std::string::npos) << missing.error().message;

  auto bad = eval::createCelReference(*scene, {.supersample = 0});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("supersampling must be in [1, 8]"), std::string::npos) << bad.error().message;
}

}  // namespace
}  // namespace puff
