// Golden images of every art scene (art/scenes/*.json, the Fig. 8 stages among them), rendered
// in-process from the atlas the build bakes into build/art. Tolerances: a pixel fails when a
// channel differs by more than 8/255 and a scene fails when more than 0.3% of its pixels do —
// room for rounding differences between llvmpipe builds, far below what any change to shading,
// outlines or shadows moves (a one-pixel outline shift alone fails ~1%).
// New references: tests/golden/accept.sh after looking at golden-out/*.actual.png.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include <puff/render/render.h>

#include "golden/golden.h"
#include "support/gl_fixture.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

class SceneGolden : public test::GlTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(SceneGolden, MatchesReference) {
  const std::string name = GetParam();
  const fs::path file = fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / (name + ".json");
  auto scene = render::loadScene(file, PUFF_ART_DIR);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  auto image = (*renderer)->renderFrame(0);
  ASSERT_TRUE(image.ok()) << image.error().message;
  test::GoldenTolerance tol;
  tol.pixelThreshold = 8.0f / 255.0f;
  tol.maxFailingFraction = 0.003;
  const test::GoldenResult r = test::compareToGolden(*image, "scene-" + name, tol);
  EXPECT_TRUE(r.passed) << r.message;
}

INSTANTIATE_TEST_SUITE_P(ArtScenes, SceneGolden,
                         ::testing::Values("cloud-fig8a", "cloud-fig8b", "cloud-fig8c", "magic-lamp", "missile-trail",
                                           "cloud-50k", "explosion", "explosion-solid"),
                         [](const ::testing::TestParamInfo<const char*>& i) {
                           std::string n = i.param;
                           for (char& c : n) c = (c == '-') ? '_' : c;
                           return n;
                         });

// A render farm splits frame ranges: a frame rendered alone equals the same frame of a sequence.
class SceneFrames : public test::GlTest {};

// The tolerances above would be useless if the Fig. 8 stages passed for one another: each stage
// differs from the previous one in far more pixels than a golden case may.
TEST_F(SceneFrames, Fig8StagesDifferByMoreThanTheGoldenTolerance) {
  std::vector<core::Image> stages;
  for (const char* name : {"cloud-fig8a", "cloud-fig8b", "cloud-fig8c"}) {
    auto scene =
        render::loadScene(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / (std::string(name) + ".json"), PUFF_ART_DIR);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    auto renderer = render::SceneRenderer::create(*scene);
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    auto image = (*renderer)->renderFrame(0);
    ASSERT_TRUE(image.ok()) << image.error().message;
    stages.push_back(std::move(*image));
  }
  auto differing = [](const core::Image& a, const core::Image& b) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.pixels.size(); i += 4) {
      bool differs = false;
      for (int c = 0; c < 3; ++c) differs |= std::abs(a.pixels[i + c] - b.pixels[i + c]) > 8.0f / 255.0f;
      n += differs ? 1 : 0;
    }
    return static_cast<double>(n) / static_cast<double>(a.pixels.size() / 4);
  };
  EXPECT_GT(differing(stages[0], stages[1]), 0.003 * 3);  // + cel shading
  EXPECT_GT(differing(stages[1], stages[2]), 0.003 * 2);  // + self-shadows
}

TEST_F(SceneFrames, RenderedAloneEqualsTheSameFrameOfASequence) {
  const fs::path file = fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / "magic-lamp.json";
  auto scene = render::loadScene(file, PUFF_ART_DIR);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  scene->width = 160;
  scene->height = 120;
  auto a = render::SceneRenderer::create(*scene);
  ASSERT_TRUE(a.ok()) << a.error().message;
  for (int f = 0; f < 5; ++f) ASSERT_TRUE((*a)->renderFrame(f).ok());
  auto sequenceFrame = (*a)->renderFrame(5);
  auto b = render::SceneRenderer::create(*scene);
  ASSERT_TRUE(b.ok());
  auto aloneFrame = (*b)->renderFrame(5);
  ASSERT_TRUE(sequenceFrame.ok() && aloneFrame.ok());
  EXPECT_EQ(sequenceFrame->pixels, aloneFrame->pixels);
  auto frame0 = (*b)->renderFrame(0);
  ASSERT_TRUE(frame0.ok());
  EXPECT_NE(frame0->pixels, aloneFrame->pixels);  // the camera orbits: frames differ
}

}  // namespace
}  // namespace puff
