// The tumbling hull's occluders (SceneRenderer::setHullOcclusion) on the art's tumbling scene: the
// frames drawn with the occluders (kCores), dropping the fragments behind other
// puffs' cores are the frames drawn marching every fragment, pixel for pixel, single-sampled and multisampled (where
// the discs' margin keeps every sample of a pixel they cover inside the core), with the shadow map and with shadow
// volumes (whose shadowed pass draws the hull again, depth-tested EQUAL against the lit pass), at frames where the
// puffs start to roll, pile up and spread.
#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <ostream>
#include <string>

#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

struct OccluderCase {
  int frame;
  int samples;
  cel::ShadowMethod shadows;
};
void PrintTo(const OccluderCase& c, std::ostream* os) {
  *os << "frame " << c.frame << ", " << c.samples << " samples, "
      << (c.shadows == cel::ShadowMethod::kMap ? "map" : "volumes");
}

class HullOccludersScene : public test::GlTest, public ::testing::WithParamInterface<OccluderCase> {};

TEST_P(HullOccludersScene, DustRollIsDrawnAsMarchingEveryFragmentDrawsIt) {
  const OccluderCase c = GetParam();
  auto loaded = scene::loadScene(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / "dust-roll.json", PUFF_ART_DIR);
  ASSERT_OK(loaded);
  scene::Scene s = *loaded;
  ASSERT_EQ(s.style.tumble, cel::TumbleMethod::kHull);
  s.width = 320;
  s.height = 180;
  s.samples = c.samples;
  s.style.shadows = true;
  s.style.shadowMethod = c.shadows;
  auto renderer = render::SceneRenderer::create(s);
  ASSERT_OK(renderer);
  (*renderer)->setHullOcclusion(cel::HullOcclusion::kCores);
  auto dropped = (*renderer)->renderFrame(c.frame);
  ASSERT_OK(dropped);
  (*renderer)->setHullOcclusion(cel::HullOcclusion::kNone);
  auto marched = (*renderer)->renderFrame(c.frame);
  ASSERT_OK(marched);
  ASSERT_EQ(dropped->pixels.size(), marched->pixels.size());
  std::size_t differ = 0, drawn = 0;
  const auto channels = static_cast<std::size_t>(marched->channels);
  for (std::size_t i = 0; i < marched->pixels.size(); i += channels) {
    bool same = true;
    for (std::size_t k = 0; k < channels; ++k) same = same && dropped->pixels[i + k] == marched->pixels[i + k];
    differ += same ? 0 : 1;
    drawn += marched->pixels[i] != marched->pixels[0] ? 1 : 0;
  }
  EXPECT_GT(drawn, marched->pixels.size() / channels / 20) << "the puffs are on screen";
  EXPECT_EQ(differ, 0u);
}

INSTANTIATE_TEST_SUITE_P(DustRoll, HullOccludersScene,
                         ::testing::Values(OccluderCase{10, 1, cel::ShadowMethod::kMap},
                                           OccluderCase{30, 1, cel::ShadowMethod::kVolumes},
                                           OccluderCase{30, 4, cel::ShadowMethod::kMap},
                                           OccluderCase{60, 4, cel::ShadowMethod::kVolumes}));

}  // namespace
}  // namespace puff
