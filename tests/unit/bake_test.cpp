// A unit sphere's bake against closed forms, the sidecar, view rotations, distance transform, options.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include <puff/bake/baker.h>
#include <puff/bake/maps.h>
#include <puff/core/atlas.h>

#include "bake_sphere_sources.h"
#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/temp_dir.h"

namespace puff::bake {
namespace {

// Analytic unit sphere seen from +z, sampled at a texel centre of a cell.
struct SphereTexel {
  double u, v, r2;
};
SphereTexel sphereAt(const core::AtlasDesc& d, int x, int y) {
  const double scale = 2.0 / d.contentSize;
  const double u = ((x + 0.5) - d.margin) * scale - 1.0;
  const double v = 1.0 - ((y + 0.5) - d.margin) * scale;
  return {u, v, u * u + v * v};
}

class BakeSphere : public test::GlTest {
 protected:
  static void SetUpTestSuite() {
    GlTest::SetUpTestSuite();
    dir_.emplace("puff_bake_test_sphere");
    BakeOptions o;
    o.cellSize = 128;
    o.flange = {4.0f, false};
    o.supersample = 4;
    o.outDir = dir_->path();
    auto r = bakeAtlas(sphereSources(), o);
    ASSERT_OK(r);
    auto atlas = core::loadAtlas(r->sidecar);
    ASSERT_OK(atlas);
    atlas_ = std::make_unique<core::Atlas>(std::move(*atlas));
  }
  static void TearDownTestSuite() {
    dir_.reset();
    atlas_.reset();
  }
  static inline std::optional<test::ScopedTempDir> dir_;
  static inline std::unique_ptr<core::Atlas> atlas_;
};

// The colour map holds the puff's colour past its silhouette, at every mip level: each texel
// outside takes the colour of the puff nearest it, so a filtered read at the rim mixes the puff's
// own colour, not black (which darkened the body's edge by a fifth of a pixel and read as ink).
// A sphere red on its right half and blue on its left: the nearest point of a disc lies on the
// same side of its centre line as the texel, so every texel of the cell, inside or out, is red on
// the right and blue on the left (away from the seam), and coverage (alpha) is untouched.
TEST_F(BakeSphere, TheColourMapCarriesThePuffsColourPastItsSilhouette) {
  std::vector<PuffSource> src = sphereSources(1, 5);
  mesh::TriMesh& m = src[0].mesh;
  m.colors.resize(m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    m.colors[i] = m.positions[i].x >= 0.0f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
  }
  test::ScopedTempDir dir("puff_bake_test_colour");
  BakeOptions o;
  o.cellSize = 64;
  o.flange = {3.0f, false};
  o.outDir = dir.path();
  o.contactSheet = false;
  auto r = bakeAtlas(src, o);
  ASSERT_OK(r);
  auto atlas = core::loadAtlas(r->sidecar);
  ASSERT_OK(atlas);
  const std::vector<core::Image>& levels = atlas->maps.at("color");
  ASSERT_GE(levels.size(), 4u);
  for (std::size_t level = 0; level < levels.size(); ++level) {
    const core::Image& c = levels[level];
    int outside = 0, wrong = 0;
    for (int y = 0; y < c.height; ++y) {
      for (int x = 0; x < c.width; ++x) {
        const float u = (x + 0.5f) / c.width - 0.5f;         // one cell: its centre is the puff's
        if (std::abs(u) < 1.5f / c.width + 0.02f) continue;  // the seam
        outside += c.at(x, y, 3) == 0.0f;
        const glm::vec3 want = u > 0.0f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
        const glm::vec3 got(c.at(x, y, 0), c.at(x, y, 1), c.at(x, y, 2));
        if (glm::length(got - want) > 0.02f) ++wrong;
      }
    }
    EXPECT_EQ(wrong, 0) << "level " << level;
    if (level == 0) {
      EXPECT_GT(outside, 200) << "coverage stays 0 past the flange";
    }
  }
}

TEST_F(BakeSphere, InteriorNormalsAndDepthMatchTheSphereWithin1Over255) {
  const core::AtlasDesc& d = atlas_->desc;
  const core::Image& nd = atlas_->maps.at("normalDepth")[0];
  const core::Image& dist = atlas_->maps.at("distance")[0];
  const double tol = 1.0 / 255.0 + 1e-6;
  int checked = 0;
  double worst = 0;
  for (int y = 0; y < d.cellSize; ++y) {
    for (int x = 0; x < d.cellSize; ++x) {
      // Interior: the texel's whole footprint lies at least one texel inside the silhouette.
      const double signedDist = (dist.at(x, y) - 0.5) * 2.0 * d.distanceRange;
      if (signedDist > -1.5) continue;
      const SphereTexel s = sphereAt(d, x, y);
      ASSERT_LT(s.r2, 1.0);
      const double nz = std::sqrt(1.0 - s.r2);
      const double expected[4] = {(s.u + 1) / 2, (s.v + 1) / 2, (nz + 1) / 2, nz / 2 + 0.5};
      for (int c = 0; c < 4; ++c) {
        const double err = std::abs(nd.at(x, y, c) - expected[c]);
        worst = std::max(worst, err);
        ASSERT_LE(err, tol) << "texel " << x << "," << y << " channel " << c;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 0.6 * kPi * std::pow(d.contentSize / 2.0, 2)) << "too few interior texels checked";
  RecordProperty("worst_error_255", std::to_string(worst * 255));
}

TEST_F(BakeSphere, CoverageRadiusWithinOneTexelAndFlangeAsAsked) {
  const core::AtlasDesc& d = atlas_->desc;
  const core::Image& color = atlas_->maps.at("color")[0];
  const core::Image& dist = atlas_->maps.at("distance")[0];
  // Body coverage from the distance map (texels inside), dilated coverage from alpha: both are
  // discs, so their areas give the radii.
  double bodyArea = 0, dilatedArea = 0;
  for (int y = 0; y < d.cellSize; ++y) {
    for (int x = 0; x < d.cellSize; ++x) {
      const double sd = (dist.at(x, y) - 0.5) * 2.0 * d.distanceRange;
      bodyArea += std::clamp(0.5 - sd, 0.0, 1.0);
      dilatedArea += color.at(x, y, 3);
    }
  }
  const double radius = d.contentSize / 2.0;
  EXPECT_NEAR(std::sqrt(bodyArea / kPi), radius, 1.0);
  EXPECT_NEAR(std::sqrt(dilatedArea / kPi) - radius, d.flangeTexels, 0.25);
  EXPECT_FLOAT_EQ(d.flangeTexels, 4.0f);
  // Flange texels are opaque at d = 0, the outline of the paper's Fig. 3; their colour is the
  // puff's (white here), carried out past the silhouette, where the paper bakes them black (the
  // ink comes from the distance map).
  const core::Image& nd = atlas_->maps.at("normalDepth")[0];
  int flangeTexels = 0;
  for (int y = 0; y < d.cellSize; ++y) {
    for (int x = 0; x < d.cellSize; ++x) {
      const double r = std::sqrt(sphereAt(d, x, y).r2) * radius;  // texels from the centre
      if (r > radius + 1.0 && r < radius + d.flangeTexels - 1.0) {
        ++flangeTexels;
        ASSERT_NEAR(color.at(x, y, 3), 1.0, 1e-6);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(color.at(x, y, c), 1.0, 1e-6);
        ASSERT_NEAR(nd.at(x, y, 3), 0.5, 1.0 / 255.0);
      }
      if (r > radius + d.flangeTexels + 1.0) {
        ASSERT_EQ(color.at(x, y, 3), 0.0f) << x << "," << y;
      }
    }
  }
  EXPECT_GT(flangeTexels, 0);
}

TEST_F(BakeSphere, DistanceFieldMatchesTheAnalyticCircle) {
  const core::AtlasDesc& d = atlas_->desc;
  const core::Image& dist = atlas_->maps.at("distance")[0];
  const double radius = d.contentSize / 2.0;
  double worst = 0;
  for (int y = 0; y < d.cellSize; ++y) {
    for (int x = 0; x < d.cellSize; ++x) {
      const double analytic = std::sqrt(sphereAt(d, x, y).r2) * radius - radius;
      if (std::abs(analytic) > d.distanceRange - 1.0) continue;  // beyond the encoded range
      const double baked = (dist.at(x, y) - 0.5) * 2.0 * d.distanceRange;
      worst = std::max(worst, std::abs(baked - analytic));
    }
  }
  EXPECT_LE(worst, 0.3) << "texels";
}

TEST_F(BakeSphere, MipLevelsKeepCoverageAndCellsApart) {
  const core::AtlasDesc& d = atlas_->desc;
  ASSERT_EQ(d.mipLevels, mipLevelCount(d.cellSize));
  ASSERT_GE(d.mipLevels, 4);
  const auto& colors = atlas_->maps.at("color");
  const double base = coverageFraction(colors[0], 0, 0, d.cellSize, d.alphaThreshold);
  for (int i = 0; i < d.cellSize; ++i) {  // level 0: the margin keeps the cell's border empty
    EXPECT_EQ(colors[0].at(i, 0, 3), 0.0f);
    EXPECT_EQ(colors[0].at(0, i, 3), 0.0f);
    EXPECT_EQ(colors[0].at(i, d.cellSize - 1, 3), 0.0f);
    EXPECT_EQ(colors[0].at(d.cellSize - 1, i, 3), 0.0f);
  }
  for (int l = 1; l < d.mipLevels; ++l) {
    const int cell = d.cellSize >> l;
    const double f = coverageFraction(colors[static_cast<std::size_t>(l)], 0, 0, cell, d.alphaThreshold);
    EXPECT_NEAR(f, base, 1.5 / cell) << "level " << l;  // within about one ring of texels
    for (int i = 0; i < cell; ++i) {
      EXPECT_EQ(colors[static_cast<std::size_t>(l)].at(i, 0, 3), 0.0f);
      EXPECT_EQ(colors[static_cast<std::size_t>(l)].at(0, i, 3), 0.0f);
    }
  }
}

TEST_F(BakeSphere, SidecarRoundTrips) {
  const core::AtlasDesc& d = atlas_->desc;
  auto again = core::atlasFromJson(core::toJson(d));
  ASSERT_OK(again);
  EXPECT_EQ(core::toJson(*again), core::toJson(d));
  EXPECT_EQ(d.sources.size(), 1u);
  EXPECT_EQ(d.sources[0].generator, "sphere");
  EXPECT_EQ(d.cells.size(), 1u);
  EXPECT_EQ(d.contentSize, d.cellSize - 2 * d.margin);
}

TEST(BakeSidecar, RejectsBrokenFieldsWithTheirPointer) {
  nlohmann::json j = {{"formatVersion", 1}};
  auto r = core::atlasFromJson(j, "x.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "x.json: /fileFormat: missing");
  auto v = core::atlasFromJson(nlohmann::json{{"formatVersion", 99}}, "x.json");
  ASSERT_FALSE(v.ok());
  EXPECT_NE(v.error().message.find("/formatVersion"), std::string::npos);
}

// The sidecar is read with the scene's reader: a value of the wrong kind names its pointer, what was
// expected and what came, at every depth of the file.
TEST(BakeSidecar, WrongKindsOfValueSayWhatWasExpected) {
  const core::AtlasDesc good = [] {
    core::AtlasDesc d;
    d.fileFormat = "png";
    d.width = d.height = d.cellSize = 64;
    d.columns = d.rows = 1;
    d.margin = 4;
    d.contentSize = 56;
    d.mipLevels = 1;
    d.variations = d.views = d.viewGrid = 1;
    d.viewLayout = "hemioct";
    d.distanceRange = 8.0f;
    d.cells.push_back(core::AtlasCell{0, 0, {0, 0, 64, 64}, {0, 0, 1}, {0, 1, 0}});
    d.sources.push_back(core::AtlasSource{});
    d.sources[0].generator = "sphere";
    for (const char* name : {"normalDepth", "color", "distance"}) d.maps[name].levels = {std::string(name) + ".png"};
    return d;
  }();
  ASSERT_OK(core::atlasFromJson(core::toJson(good), "x.json"));
  const std::tuple<const char*, nlohmann::json, std::string> cases[] = {
      {"/cellSize", "big", "x.json: /cellSize: expected an integer, got \"big\""},
      {"/cellSize", 64.5, "x.json: /cellSize: expected an integer, got 64.5"},
      {"/depthScale", "big", "x.json: /depthScale: expected a number, got \"big\""},
      {"/cells/0/viewDir", "big", "x.json: /cells/0/viewDir: expected an array of 3 numbers, got \"big\""},
      {"/cells/0/rect/2", "big", "x.json: /cells/0/rect/2: expected an integer, got \"big\""},
      {"/sources/0/faces", -1, "x.json: /sources/0/faces: expected a count (an integer >= 0), got -1"},
      {"/maps/color/levels/0", 7, "x.json: /maps/color/levels/0: expected a string, got 7"},
  };
  for (const auto& [pointer, value, message] : cases) {
    nlohmann::json j = core::toJson(good);
    j[nlohmann::json::json_pointer(pointer)] = value;
    auto r = core::atlasFromJson(j, "x.json");
    ASSERT_FALSE(r.ok()) << pointer;
    EXPECT_EQ(r.error().message, message);
  }
}

// Values of the right kind that no bake writes, each of which would draw nothing, NaN or the wrong
// map with exit 0, are refused with their pointer.
TEST(BakeSidecar, ValuesNoBakeWritesAreRefused) {
  core::AtlasDesc good;
  good.fileFormat = "png";
  good.width = good.height = 128;
  good.cellSize = 64;
  good.columns = good.rows = 2;
  good.margin = 4;
  good.contentSize = 56;
  good.mipLevels = 1;
  good.variations = 4;
  good.views = good.viewGrid = 1;
  good.viewLayout = "hemioct";
  good.distanceRange = 8.0f;
  good.flangeTexels = 3.0f;
  for (int i = 0; i < 4; ++i) {
    good.cells.push_back(core::AtlasCell{i, 0, {64 * (i % 2), 64 * (i / 2), 64, 64}, {0, 0, 1}, {0, 1, 0}});
    good.sources.push_back(core::AtlasSource{});
    good.sources.back().generator = "sphere";
  }
  for (const char* name : {"normalDepth", "color", "distance"}) good.maps[name].levels = {std::string(name) + ".png"};
  ASSERT_OK(core::atlasFromJson(core::toJson(good), "x.json"));
  const std::pair<const char*, nlohmann::json> cases[] = {
      {"/cells/0/viewDir", {0, 0, 0}},
      {"/cells/0/viewDir", {0, 0, 2}},
      {"/cells/0/viewUp", {0, 0, 1}},
      {"/cells/0/viewUp", {0, 2, 0}},
      {"/cells/1/view", -5},
      {"/cells/1/variation", 7},
      {"/depthScale", 0},
      {"/depthScale", -1e30},
      {"/depthScale", 1e30},
      {"/distanceRange", 1e-38},
      {"/distanceRange", 1e38},
      {"/alphaThreshold", 7},
      {"/alphaThreshold", 0},
      {"/flangeTexels", -50},
      {"/flangeTexels", 65},
      {"/supersample", 0},
      {"/supersample", 65},
  };
  for (const auto& [pointer, value] : cases) {
    SCOPED_TRACE(std::string(pointer) + " = " + value.dump());
    nlohmann::json j = core::toJson(good);
    j[nlohmann::json::json_pointer(pointer)] = value;
    auto r = core::atlasFromJson(j, "x.json");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message.rfind(std::string("x.json: ") + pointer, 0), 0u) << r.error().message;
  }
}

TEST(BakeDistance, ExactTransformOfAPointAndAnEmptyImage) {
  std::vector<std::uint8_t> f(9 * 7, 0);
  f[3 * 9 + 4] = 1;  // (4, 3)
  auto d = squaredDistanceTransform(f, 9, 7);
  for (int y = 0; y < 7; ++y) {
    for (int x = 0; x < 9; ++x)
      EXPECT_EQ(d[static_cast<std::size_t>(y * 9 + x)], float((x - 4) * (x - 4) + (y - 3) * (y - 3)));
  }
  auto none = squaredDistanceTransform(std::vector<std::uint8_t>(16, 0), 4, 4);
  for (float v : none) EXPECT_TRUE(std::isinf(v));
}

TEST(BakeViews, RotationIsOrthonormalAndLooksAlongTheView) {
  for (ViewLayout layout : {ViewLayout::kHemiOct, ViewLayout::kOct}) {
    for (int grid : {1, 2, 3, 5}) {
      for (int i = 0; i < grid * grid; ++i) {
        const glm::vec3 dir = viewDirection(layout, grid, i);
        const glm::mat3 r = viewRotation(dir);
        const glm::vec3 z = r * dir;
        EXPECT_NEAR(z.z, 1.0f, 1e-5f);
        EXPECT_NEAR(glm::determinant(r), 1.0f, 1e-5f) << "a mirrored view";
        const glm::mat3 shouldBeIdentity = r * glm::transpose(r);
        for (int a = 0; a < 3; ++a) {
          for (int b = 0; b < 3; ++b) {
            EXPECT_NEAR(shouldBeIdentity[a][b], a == b ? 1.0f : 0.0f, 1e-5f);
          }
        }
      }
    }
    EXPECT_NEAR(viewDirection(layout, 1, 0).z, 1.0f, 1e-6f);
  }
  // The octahedral grid reaches the back hemisphere.
  bool back = false;
  for (int i = 0; i < 16; ++i) back |= viewDirection(ViewLayout::kOct, 4, i).z < -0.5f;
  EXPECT_TRUE(back);
}

TEST(BakeOptions, NameIsAPlainVisiblePrefix) {
  BakeOptions o;
  for (const char* bad : {"", ".", "..", ".hidden", "a/b"}) {
    o.name = bad;
    auto r = validate(o, 1);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(r.error().message,
              std::string("--name must be a plain file prefix (no '/', not starting with '.'), got \"") + bad + "\"");
  }
  o.name = "smoke.v2";
  EXPECT_OK(validate(o, 1));
}

TEST(BakeOptions, RejectsAbsurdSizes) {
  BakeOptions o;
  o.cellSize = 0;
  EXPECT_EQ(validate(o, 1).error().message, "--size must be in [8, 16384], got 0");
  o.cellSize = 16385;
  EXPECT_FALSE(validate(o, 1).ok());
  o.cellSize = 2048;
  EXPECT_OK(validate(o, 16));  // an 8192^2 atlas fits
  o.cellSize = 4096;
  EXPECT_NE(validate(o, 17).error().message.find("above the 16384 limit"), std::string::npos);
  o.cellSize = 8192;
  EXPECT_NE(validate(o, 4).error().message.find("more than the 12.0 GiB"), std::string::npos);
  o.cellSize = 4096;
  o.supersample = 8;  // 32768 samples across
  EXPECT_NE(validate(o, 1).error().message.find("a GL framebuffer can hold"), std::string::npos);
  o.flange = {1e10f, false};  // must not wrap an int
  o.supersample = 0;
  EXPECT_EQ(validate(o, 1).error().message,
            "--size 4096 leaves no room for the puff: each side of the cell keeps the flange (1e+10 texels, rounded "
            "up) and a 128-texel guard band, and the puff needs 4 texels; lower --flange");
  o.cellSize = 64;
  o.flange = {40.0f, false};
  EXPECT_EQ(validate(o, 1).error().message,
            "--size 64 leaves no room for the puff: each side of the cell keeps the flange (40 texels, rounded up) and "
            "a 2-texel guard band, and the puff needs 4 texels; the least --size that fits is 88, or lower --flange");
}

TEST(BakeOptions, TheSmallestCellsSayWhatFits) {
  // Each side keeps the flange rounded up and a guard band of max(2, size / 32) texels; the puff
  // needs 4 texels across. The default flange (3% of the cell) rounds up to one texel below 34.
  BakeOptions o;
  for (int size : {8, 9}) {
    o.cellSize = size;
    const std::string flange = size == 8 ? "0.24" : "0.27";
    EXPECT_EQ(validate(o, 1).error().message,
              "--size " + std::to_string(size) + " leaves no room for the puff: each side of the cell keeps the " +
                  "flange (" + flange + " texels, rounded up) and a 2-texel guard band, and the puff needs 4 " +
                  "texels; the least --size that fits is 10, or lower --flange");
  }
  o.cellSize = 10;
  EXPECT_OK(validate(o, 1));
  o.cellSize = 8;
  o.flange = {0.0f, false};  // no flange: 8 - 2 x 2 = 4 texels
  EXPECT_OK(validate(o, 1));
  o.flange = {4.5f, false};  // 16 - 2 x (5 + 2) = 2
  o.cellSize = 16;
  EXPECT_EQ(validate(o, 1).error().message,
            "--size 16 leaves no room for the puff: each side of the cell keeps the flange (4.5 texels, rounded up) "
            "and a 2-texel guard band, and the puff needs 4 texels; the least --size that fits is 18, or lower "
            "--flange");
  o.flange = {0.49f, true};  // a percentage grows with the cell: 49% never leaves 4 texels
  EXPECT_NE(validate(o, 1).error().message.find("texels; lower --flange"), std::string::npos);
}

class BakeFlange : public test::GlTest {};

TEST_F(BakeFlange, PercentOfTheCellGivesThatWidth) {
  auto src = sphereSources(1, 5);
  BakeOptions o;
  o.cellSize = 128;
  o.flange = {0.03f, true};  // "3%"
  o.mips = false;
  o.contactSheet = false;
  const test::ScopedTempDir out("puff_bake_test_flange_percent");
  o.outDir = out.path();
  auto r = bakeAtlas(src, o);
  ASSERT_OK(r);
  auto atlas = core::loadAtlas(r->sidecar);
  ASSERT_OK(atlas);
  const core::AtlasDesc& d = atlas->desc;
  EXPECT_NEAR(d.flangeTexels, 3.84f, 1e-4f);
  double dilatedArea = 0;
  const core::Image& color = atlas->maps.at("color")[0];
  for (int y = 0; y < d.cellSize; ++y) {
    for (int x = 0; x < d.cellSize; ++x) dilatedArea += color.at(x, y, 3);
  }
  EXPECT_NEAR(std::sqrt(dilatedArea / kPi) - d.contentSize / 2.0, 0.03 * 128, 0.25);
}

}  // namespace
}  // namespace puff::bake
