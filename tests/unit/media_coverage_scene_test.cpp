// The media passes over what the media cover (media::LayersBase::setCoverage, as the cel path runs
// them) draw every media art scene, photoreal and cartoon, bit for bit as the passes over the whole
// frame do (SceneRenderer::setMediaOverWholeFrame), at frames where the media cover part of the
// frame, all of it (the camera inside the smoke) and none of it; and a small flame added to a cel
// scene covers a small part of it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

fs::path sceneFile(const std::string& name) { return fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / (name + ".json"); }

struct CoverageCase {
  const char* scene;
  int frame;
  int width, height;  // smaller than the art's, to keep the suite short; the samples are the scene's
};
void PrintTo(const CoverageCase& c, std::ostream* os) { *os << c.scene << " frame " << c.frame; }

struct Drawn {
  core::Image image;
  render::FrameStats stats;
};

Drawn draw(const scene::Scene& s, int frame, bool wholeFrame) {
  auto renderer = render::SceneRenderer::create(s);
  EXPECT_OK(renderer);
  if (!renderer) return {};
  (*renderer)->setMediaOverWholeFrame(wholeFrame);
  Drawn d;
  auto image = (*renderer)->renderFrame(frame, &d.stats);
  EXPECT_OK(image);
  if (image) d.image = std::move(*image);
  return d;
}

class MediaCoverageScenes : public test::GlTest, public ::testing::WithParamInterface<CoverageCase> {};

TEST_P(MediaCoverageScenes, DrawTheWholeFramesPassesImageBitForBit) {
  const CoverageCase c = GetParam();
  auto loaded = scene::loadScene(sceneFile(c.scene), PUFF_ART_DIR);
  ASSERT_OK(loaded);
  scene::Scene s = *loaded;
  s.width = c.width;
  s.height = c.height;
  const Drawn covered = draw(s, c.frame, false), whole = draw(s, c.frame, true);
  ASSERT_FALSE(covered.image.pixels.empty());
  EXPECT_EQ(covered.stats.mediaParticles, whole.stats.mediaParticles);
  const std::size_t frame = static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height);
  EXPECT_EQ(whole.stats.mediaCoveredPixels, frame);
  EXPECT_LE(covered.stats.mediaCoveredPixels, frame);
  std::cout << c.scene << " frame " << c.frame << ": " << covered.stats.mediaParticles << " media particles cover "
            << 100.0 * static_cast<double>(covered.stats.mediaCoveredPixels) / static_cast<double>(frame)
            << " % of the frame\n";
  ASSERT_EQ(covered.image.pixels.size(), whole.image.pixels.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < covered.image.pixels.size(); ++i)
    differ += covered.image.pixels[i] != whole.image.pixels[i] ? 1 : 0;
  EXPECT_EQ(differ, 0u) << "channel values differ from the whole frame's passes";
}

// Each media art scene at a frame where the media cover part of the frame; explosion-walls also
// before its explosion (none of it) and smoke-flythrough inside the smoke (all of it).
INSTANTIATE_TEST_SUITE_P(
    ArtScenes, MediaCoverageScenes,
    ::testing::Values(CoverageCase{"explosion-walls", 0, 240, 135}, CoverageCase{"explosion-walls", 5, 240, 135},
                      CoverageCase{"explosion-walls", 20, 240, 135},
                      CoverageCase{"explosion-walls-cartoon", 20, 240, 135},
                      CoverageCase{"fire-to-smoke", 48, 160, 212}, CoverageCase{"fire-to-smoke-cartoon", 48, 160, 212},
                      CoverageCase{"smoke-flythrough", 30, 200, 150}, CoverageCase{"smoke-flythrough", 0, 200, 150}),
    [](const ::testing::TestParamInfo<CoverageCase>& i) {
      std::string n = i.param.scene;
      for (char& ch : n) ch = (ch == '-') ? '_' : ch;
      return n + "_" + std::to_string(i.param.frame);
    });

class MediaCoverage : public test::GlTest {};

// magic-lamp with a small flame at the spout (tests/data/media/small-flame.json): the bench's case.
TEST_F(MediaCoverage, ASmallFlameCoversASmallPartOfTheFrameAndDrawsAsOverTheWholeFrame) {
  nlohmann::json j = nlohmann::json::parse(std::ifstream(sceneFile("magic-lamp")));
  j.merge_patch(nlohmann::json::parse(std::ifstream(fs::path(PUFF_TEST_DATA_DIR) / "media" / "small-flame.json")));
  auto s = scene::parseScene(j, sceneFile("magic-lamp"), PUFF_ART_DIR);
  ASSERT_OK(s);
  const Drawn covered = draw(*s, 10, false), whole = draw(*s, 10, true);
  EXPECT_GT(covered.stats.mediaParticles, 5u);
  const double share = static_cast<double>(covered.stats.mediaCoveredPixels) / (s->width * s->height);
  EXPECT_GT(share, 0.0);
  EXPECT_LT(share, 0.02);
  EXPECT_EQ(covered.image.pixels, whole.image.pixels);
}

}  // namespace
}  // namespace puff
