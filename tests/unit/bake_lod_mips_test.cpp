// The baker's level of detail search and cell comparison, and its coverage- and light-preserving mips.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include <puff/bake/baker.h>
#include <puff/bake/maps.h>
#include <puff/bake/raster.h>
#include <puff/core/colour.h>
#include <puff/core/image.h>
#include <puff/mesh/mesh.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/temp_dir.h"

namespace puff::bake {
namespace {

class BakeLod : public test::GlTest {};

TEST_F(BakeLod, AutoLodFindsFewerFacesWithinTheTolerances) {
  // A finely tessellated sphere baked into a small cell carries far more faces than its texels
  // can show: --lod auto must drop most of them and stay within both tolerances.
  std::vector<PuffSource> src(1);
  src[0].mesh = mesh::generateSphere({5});
  src[0].provenance.generator = "sphere";
  BakeOptions o;
  o.cellSize = 32;
  o.lodAuto = true;
  o.contactSheet = false;
  const test::ScopedTempDir out("puff_bake_test_lod");
  o.outDir = out.path();
  auto r = bakeAtlas(src, o);
  ASSERT_OK(r);
  ASSERT_EQ(r->lod.size(), 1u);
  ASSERT_TRUE(r->lod[0].has_value());
  const LodResult& lod = *r->lod[0];
  EXPECT_EQ(lod.facesBefore, 20480u);
  EXPECT_LT(lod.facesAfter, lod.facesBefore / 4);
  EXPECT_EQ(r->desc.sources[0].faces, 20480u);
  EXPECT_EQ(r->desc.sources[0].facesBaked, lod.facesAfter);

  // Check the choice independently, at the settings the search compares at (2 samples per
  // texel side, no flange): the chosen mesh is within both tolerances, and half its faces is not.
  const core::AtlasDesc& d = r->desc;
  auto raster = PuffRasterizer::create(d.cellSize * 2);
  ASSERT_OK(raster);
  SampleBuffer samples;
  auto maps = [&](const mesh::TriMesh& m) {
    (*raster)->setMesh(m, glm::vec3(1.0f));
    (*raster)->render(viewRotation({0, 0, 1}), d.margin * 2, d.contentSize * 2, samples);
    return resolveCell(samples, 2, 0.0f);
  };
  const CellMaps reference = maps(src[0].mesh);
  const MapDifference chosen = compareCells(reference, maps(mesh::decimate(src[0].mesh, lod.facesAfter)));
  EXPECT_LE(chosen.meanNormalError, o.lodNormalTolerance);
  EXPECT_LE(chosen.silhouetteTexels, o.lodSilhouetteTolerance);
  const MapDifference half = compareCells(reference, maps(mesh::decimate(src[0].mesh, lod.facesAfter / 2)));
  EXPECT_LE(chosen.meanDepthError, o.lodDepthTolerance);
  EXPECT_LE(chosen.meanColorError, o.lodColorTolerance);
  EXPECT_TRUE(half.meanNormalError > o.lodNormalTolerance || half.silhouetteTexels > o.lodSilhouetteTolerance ||
              half.meanDepthError > o.lodDepthTolerance || half.meanColorError > o.lodColorTolerance)
      << "half the faces still passes: the search did not find the fewest";
  RecordProperty("faces_after", std::to_string(lod.facesAfter));
}

TEST(BakeCompare, IdenticalCellsDifferByNothingAndAShiftedDiscByItsShift) {
  auto disc = [](float cx, float radius, float depth = 0.0f, float red = 0.0f) {
    CellMaps m;
    m.normalDepth = core::Image(32, 32, 4);
    m.color = core::Image(32, 32, 4);
    m.distance = core::Image(32, 32, 1);
    m.body = core::Image(32, 32, 1);
    for (int y = 0; y < 32; ++y) {
      for (int x = 0; x < 32; ++x) {
        const float d = std::hypot(x + 0.5f - cx, y + 0.5f - 16.0f) - radius;
        m.distance.at(x, y) = d;
        m.body.at(x, y) = d < 0 ? 1.0f : 0.0f;
        m.normalDepth.at(x, y, 2) = 1.0f;
        m.normalDepth.at(x, y, 3) = depth;
        m.color.at(x, y, 0) = red;
      }
    }
    return m;
  };
  const CellMaps a = disc(16.0f, 8.0f);
  MapDifference same = compareCells(a, a);
  EXPECT_EQ(same.meanNormalError, 0.0f);
  EXPECT_EQ(same.silhouetteTexels, 0.0f);
  EXPECT_EQ(same.meanDepthError, 0.0f);
  EXPECT_EQ(same.meanColorError, 0.0f);
  MapDifference grown = compareCells(a, disc(16.0f, 8.75f));
  EXPECT_NEAR(grown.silhouetteTexels, 0.75f, 1e-4f);
  // The same disc moved 0.1 diameters toward the viewer, its red raised by 0.3: mean depth error 0.1,
  // mean colour error 0.3 / 3 per channel; the normals and silhouette unchanged.
  MapDifference moved = compareCells(a, disc(16.0f, 8.0f, 0.1f, 0.3f));
  EXPECT_NEAR(moved.meanDepthError, 0.1f, 1e-6f);
  EXPECT_NEAR(moved.meanColorError, 0.1f, 1e-6f);
  EXPECT_EQ(moved.meanNormalError, 0.0f);
  EXPECT_EQ(moved.silhouetteTexels, 0.0f);
}

TEST(BakeMips, SoftCoverageSurvivesWhereABoxFilterWouldErodeIt) {
  // Soft coverage, like hair or foliage: alpha uniform in [0, 0.8], so 37.5% of the texels pass
  // the 0.5 test. Box-filtered levels average toward 0.4 and fewer and fewer texels pass (about
  // 19% at level 1 and 4% at level 2), which is how plain mipmaps erode alpha-tested shapes.
  constexpr int kCell = 64;
  AtlasLevel level0{core::Image(kCell, kCell, 4), core::Image(kCell, kCell, 4), core::Image(kCell, kCell, 1, 8.0f), {}};
  std::uint32_t rng = 12345;
  for (int y = 8; y < kCell - 8; ++y) {
    for (int x = 8; x < kCell - 8; ++x) {
      rng = rng * 1664525u + 1013904223u;
      level0.color.at(x, y, 3) = 0.8f * static_cast<float>(rng >> 8) / static_cast<float>(1u << 24);
      level0.normalDepth.at(x, y, 2) = 1.0f;
    }
  }
  const double base = coverageFraction(level0.color, 0, 0, kCell, 0.5f);
  ASSERT_NEAR(base, 0.375 * (48.0 * 48.0) / (64.0 * 64.0), 0.02);
  for (int level = 1; level < mipLevelCount(kCell); ++level) {
    const AtlasLevel mip = buildMipLevel(level0, kCell, level, 0.5f);
    const int cell = kCell >> level;
    // The same box filter without coverage preservation, to show this test can fail.
    std::size_t boxPassing = 0;
    const int f = 1 << level;
    for (int y = 1; y < cell - 1; ++y) {
      for (int x = 1; x < cell - 1; ++x) {
        float a = 0;
        for (int by = 0; by < f; ++by) {
          for (int bx = 0; bx < f; ++bx) a += level0.color.at(x * f + bx, y * f + by, 3);
        }
        boxPassing += a / float(f * f) >= 0.5f;
      }
    }
    EXPECT_LT(static_cast<double>(boxPassing) / (cell * cell), 0.6 * base) << "level " << level;
    EXPECT_NEAR(coverageFraction(mip.color, 0, 0, cell, 0.5f), base, 1.0 / (cell * cell) + 1e-9) << "level " << level;
    for (int i = 0; i < cell; ++i) {
      EXPECT_EQ(mip.color.at(i, cell - 1, 3), 0.0f);
      EXPECT_EQ(mip.color.at(cell - 1, i, 3), 0.0f);
    }
  }
}

// A mip averages light, not display values (docs/colour.md): a black and white checker of opaque
// texels becomes the display value of linear 0.5, 0.7354, not 0.5; a flat colour stays itself.
TEST(BakeMips, ColourIsAveragedInLinearLight) {
  constexpr int kCell = 16;
  AtlasLevel level0{core::Image(kCell, kCell, 4), core::Image(kCell, kCell, 4), core::Image(kCell, kCell, 1, 8.0f), {}};
  for (int y = 0; y < kCell; ++y) {
    for (int x = 0; x < kCell; ++x) {
      const float v = (x + y) % 2 == 0 ? 1.0f : 0.0f;
      for (int c = 0; c < 3; ++c) level0.color.at(x, y, c) = c == 2 ? 0.6f : v;  // blue flat at 0.6
      level0.color.at(x, y, 3) = 1.0f;
      level0.normalDepth.at(x, y, 2) = 1.0f;
    }
  }
  const AtlasLevel mip = buildMipLevel(level0, kCell, 1, 0.5f);
  const float half = static_cast<float>(core::linearToSrgb(0.5));
  EXPECT_NEAR(half, 0.7354f, 1e-4f);
  EXPECT_NEAR(mip.color.at(3, 3, 0), half, 1e-5f);  // an interior texel (the outer ring is emptied)
  EXPECT_NEAR(mip.color.at(3, 3, 1), half, 1e-5f);
  EXPECT_NEAR(mip.color.at(3, 3, 2), 0.6f, 1e-5f);
}

}  // namespace
}  // namespace puff::bake
