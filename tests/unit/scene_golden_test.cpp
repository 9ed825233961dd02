// Golden images of every art scene (art/scenes/*.json, the Fig. 8 stages among them), rendered
// in-process from the atlas the build bakes into build/art. Tolerance (test::kSceneTolerance): a
// pixel fails when a channel differs by more than 3/255, a scene when more than 0.2% of its pixels
// do. Each scene also checks that the tolerance means something (test::expectSceneGolden): the
// frame 3% brighter or darker fails, and so do its outlines 1 px wider where it shows ink.
// New references: tests/golden/accept.sh after looking at build/tests/golden-out/*.actual.png.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "golden/golden.h"
#include "support/assert_ok.h"
#include "support/display.h"
#include "support/gl_fixture.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

class SceneGolden : public test::GlTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(SceneGolden, MatchesReference) {
  const std::string name = GetParam();
  const fs::path file = fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / (name + ".json");
  auto scene = scene::loadScene(file, PUFF_ART_DIR);
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  auto image = (*renderer)->renderFrame(0);
  ASSERT_OK(image);
  test::expectSceneGolden(test::display(*image, scene::viewTransformFor(*scene)), "scene-" + name);
}

INSTANTIATE_TEST_SUITE_P(ArtScenes, SceneGolden,
                         ::testing::Values("cloud-fig8a", "cloud-fig8b", "cloud-fig8c", "plate-cloud", "magic-lamp",
                                           "missile-trail", "cloud-50k", "explosion", "explosion-solid", "dust-roll"),
                         [](const ::testing::TestParamInfo<const char*>& i) {
                           std::string n = i.param;
                           for (char& c : n) c = (c == '-') ? '_' : c;
                           return n;
                         });

// The animated, simulated scenes, each at a frame where its motion shows: the missile's
// trail, the propeller's wake through the cloud, the lamp's plume. Same tolerances.
struct AnimatedCase {
  const char* scene;
  int frame;
};

void PrintTo(const AnimatedCase& c, std::ostream* os) { *os << c.scene << " frame " << c.frame; }

class AnimatedSceneGolden : public test::GlTest, public ::testing::WithParamInterface<AnimatedCase> {};

TEST_P(AnimatedSceneGolden, MatchesReference) {
  const AnimatedCase c = GetParam();
  const fs::path file = fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / (std::string(c.scene) + ".json");
  auto scene = scene::loadScene(file, PUFF_ART_DIR);
  ASSERT_OK(scene);
  ASSERT_TRUE(scene->simulation.has_value());
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  render::FrameStats stats;
  auto image = (*renderer)->renderFrame(c.frame, &stats);
  ASSERT_OK(image);
  EXPECT_GT(stats.simulated, 50u);
  test::expectSceneGolden(test::display(*image, scene::viewTransformFor(*scene)),
                          "scene-" + std::string(c.scene) + "-" + std::to_string(c.frame));
}

INSTANTIATE_TEST_SUITE_P(ArtScenes, AnimatedSceneGolden,
                         ::testing::Values(AnimatedCase{"missile-flight", 30}, AnimatedCase{"propeller-cloud", 60},
                                           AnimatedCase{"lamp-plume", 24}, AnimatedCase{"bouncing-ball", 30}),
                         [](const ::testing::TestParamInfo<AnimatedCase>& i) {
                           std::string n = i.param.scene;
                           for (char& ch : n) ch = (ch == '-') ? '_' : ch;
                           return n + "_" + std::to_string(i.param.frame);
                         });

// A render farm splits frame ranges: a frame rendered alone equals the same frame of a sequence.
class SceneFrames : public test::GlTest {
 protected:
  // Frames 0-9 of `file` at 160 x 120 in a sequence; frames 9 and 3 rendered alone equal them.
  static void expectAloneEqualsSequence(const fs::path& file);
};

// The tolerances above would be useless if the Fig. 8 stages passed for one another: each stage
// differs from the previous one in far more pixels than a golden case may.
TEST_F(SceneFrames, Fig8StagesDifferByMoreThanTheGoldenTolerance) {
  std::vector<core::Image> stages;
  for (const char* name : {"cloud-fig8a", "cloud-fig8b", "cloud-fig8c"}) {
    auto scene =
        scene::loadScene(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / (std::string(name) + ".json"), PUFF_ART_DIR);
    ASSERT_OK(scene);
    auto renderer = render::SceneRenderer::create(*scene);
    ASSERT_OK(renderer);
    auto image = (*renderer)->renderFrame(0);
    ASSERT_OK(image);
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
  auto scene = scene::loadScene(file, PUFF_ART_DIR);
  ASSERT_OK(scene);
  scene->width = 160;
  scene->height = 120;
  auto a = render::SceneRenderer::create(*scene);
  ASSERT_OK(a);
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

namespace puff {
namespace {

// The same for a simulated scene: frame 9 reached alone (re-simulated from the start) equals frame
// 9 of a sequence, and going back to an earlier frame restarts and gives that frame again.
TEST_F(SceneFrames, SimulatedFrameRenderedAloneEqualsTheSequence) {
  // lamp-plume's smoke, and bouncing-ball's rigid body with the dust it trails.
  for (const char* name : {"lamp-plume", "bouncing-ball"}) {
    SCOPED_TRACE(name);
    expectAloneEqualsSequence(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / (std::string(name) + ".json"));
  }
}

void SceneFrames::expectAloneEqualsSequence(const fs::path& file) {
  auto scene = scene::loadScene(file, PUFF_ART_DIR);
  ASSERT_OK(scene);
  scene->width = 160;
  scene->height = 120;
  auto a = render::SceneRenderer::create(*scene);
  ASSERT_OK(a);
  std::vector<std::vector<float>> frames;
  for (int f = 0; f <= 9; ++f) {
    auto image = (*a)->renderFrame(f);
    ASSERT_TRUE(image.ok());
    frames.push_back(image->pixels);
  }
  auto b = render::SceneRenderer::create(*scene);
  ASSERT_TRUE(b.ok());
  auto alone = (*b)->renderFrame(9);
  ASSERT_TRUE(alone.ok());
  EXPECT_EQ(alone->pixels, frames[9]);
  auto back = (*b)->renderFrame(3);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->pixels, frames[3]);
  EXPECT_NE(frames[3], frames[9]);  // the smoke moves
}

// A viewer's edit: new forces show at once, and the frame drawn is that frame of the edited scene
// (a pure function of the scene, as puffrender would make it from the saved file); a bad value is
// refused and nothing changes; a resource change (another ramp) reloads, or fails naming the file.
TEST_F(SceneFrames, UpdateAppliesForcesAndFramesStayPure) {
  const fs::path file = fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / "lamp-plume.json";
  auto scene = scene::loadScene(file, PUFF_ART_DIR);
  ASSERT_OK(scene);
  scene->width = 160;
  scene->height = 120;
  auto r = render::SceneRenderer::create(*scene);
  ASSERT_TRUE(r.ok());
  auto before = (*r)->renderFrame(6);
  ASSERT_TRUE(before.ok());
  scene::Scene edited = *scene;
  edited.simulation->forces.wind = glm::vec3(3.0f, 0.0f, 0.0f);
  ASSERT_TRUE((*r)->update(edited).ok());
  auto after = (*r)->renderFrame(7);
  ASSERT_TRUE(after.ok());
  auto fresh = render::SceneRenderer::create(edited);  // frame 7 of the edited scene, from scratch
  ASSERT_TRUE(fresh.ok());
  auto expected = (*fresh)->renderFrame(7);
  ASSERT_TRUE(expected.ok());
  EXPECT_EQ(after->pixels, expected->pixels);
  auto unedited = render::SceneRenderer::create(*scene);
  ASSERT_TRUE(unedited.ok());
  auto still = (*unedited)->renderFrame(7);
  ASSERT_TRUE(still.ok());
  EXPECT_NE(after->pixels, still->pixels);  // and the wind shows
  scene::Scene bad = edited;
  bad.simulation->forces.drag = -1.0f;
  auto refused = (*r)->update(bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("/simulation/forces/drag"), std::string::npos) << refused.error().message;
  EXPECT_EQ((*r)->scene().simulation->forces.drag, edited.simulation->forces.drag);
  scene::Scene otherRamp = edited;
  otherRamp.ramp = fs::path(PUFF_SOURCE_DIR) / "art" / "ramps" / "missing.png";
  auto reload = (*r)->update(otherRamp);
  ASSERT_FALSE(reload.ok());
  EXPECT_NE(reload.error().message.find("missing.png"), std::string::npos) << reload.error().message;
}

}  // namespace
}  // namespace puff
