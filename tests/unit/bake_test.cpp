// The baker against closed forms: a unit sphere's normals, depth, coverage radius, flange width
// and distance field; an ellipsoid's projected area in every view; determinism; mips.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <puff/bake/baker.h>
#include <puff/bake/raster.h>
#include <puff/core/atlas.h>
#include <puff/core/colour.h>
#include <puff/core/files.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/temp_dir.h"

namespace puff::bake {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

std::vector<PuffSource> sphereSources(int count = 1, int subdivisions = 6) {
  std::vector<PuffSource> s(static_cast<std::size_t>(count));
  for (auto& src : s) {
    src.mesh = mesh::generateSphere({subdivisions});
    src.provenance.generator = "sphere";
    src.provenance.faces = src.mesh.faceCount();
  }
  return s;
}

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

// Bakes `src` with `o` into a fresh temporary directory `dir` and loads the atlas back (nullopt, with a
// test failure, if either fails).
std::optional<core::Atlas> bakeAndLoad(const std::vector<PuffSource>& src, BakeOptions o, const std::string& dir) {
  const test::ScopedTempDir out(dir);
  o.outDir = out.path();
  auto r = bakeAtlas(src, o);
  if (!r) {
    ADD_FAILURE() << r.error().message;
    return std::nullopt;
  }
  auto atlas = core::loadAtlas(r->sidecar);
  if (!atlas) {
    ADD_FAILURE() << atlas.error().message;
    return std::nullopt;
  }
  return std::move(*atlas);
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

class BakeGl : public test::GlTest {};

TEST_F(BakeGl, EllipsoidProjectedAreaInEveryView) {
  // An ellipsoid with semi-axes (1, 0.5, 0.7) seen along unit v covers pi*a*b*c*|(vx/a, vy/b, vz/c)|.
  const glm::vec3 axes(1.0f, 0.5f, 0.7f);
  auto src = sphereSources(1, 5);
  for (auto& p : src[0].mesh.positions) p *= axes;
  for (auto& n : src[0].mesh.normals) n = glm::normalize(n / axes);
  for (ViewLayout layout : {ViewLayout::kHemiOct, ViewLayout::kOct}) {
    BakeOptions o;
    o.cellSize = 96;
    o.viewGrid = 3;
    o.viewLayout = layout;
    o.flange = {0.0f, false};
    o.mips = false;
    o.contactSheet = false;
    const test::ScopedTempDir out("puff_bake_test_ellipsoid");
    o.outDir = out.path();
    auto r = bakeAtlas(src, o);
    ASSERT_OK(r);
    auto atlas = core::loadAtlas(r->sidecar);
    ASSERT_OK(atlas);
    const core::AtlasDesc& d = atlas->desc;
    ASSERT_EQ(d.cells.size(), 9u);
    for (const core::AtlasCell& c : d.cells) {
      EXPECT_NEAR(glm::length(c.viewDir), 1.0f, 1e-5f);
      if (layout == ViewLayout::kHemiOct) {
        EXPECT_GE(c.viewDir.z, 0.0f);
      }
      double area = 0;
      for (int y = 0; y < d.cellSize; ++y) {
        for (int x = 0; x < d.cellSize; ++x) area += atlas->maps.at("color")[0].at(c.rect[0] + x, c.rect[1] + y, 3);
      }
      const glm::vec3 v = c.viewDir;
      const double expectedUnits = kPi * axes.x * axes.y * axes.z * glm::length(v / axes);
      const double texelsPerUnit = d.contentSize / 2.0;
      EXPECT_NEAR(area / (texelsPerUnit * texelsPerUnit), expectedUnits, 0.01 * expectedUnits)
          << "view " << c.view << " dir " << v.x << "," << v.y << "," << v.z;
    }
  }
}

// The back map against the closed form: an ellipsoid's far side along each view's ray, the
// farthest over the texel's samples (a bound), at every level the farthest of the block below, no
// bound off the silhouette; a one-view atlas has none.
TEST_F(BakeGl, BackMapIsTheEllipsoidsFarSideInEveryView) {
  const glm::dvec3 axes(1.0, 0.5, 0.7);
  auto src = sphereSources(1, 5);
  for (auto& p : src[0].mesh.positions) p *= glm::vec3(axes);
  for (auto& n : src[0].mesh.normals) n = glm::normalize(n / glm::vec3(axes));
  // Far crossing (d, diameters toward the viewer) of the ray through (u, w) (radii) along -dir, or
  // nothing where it misses.
  auto farSide = [&](const glm::dvec3& right, const glm::dvec3& up, const glm::dvec3& dir, double u,
                     double w) -> std::optional<double> {
    const glm::dvec3 q = (u * right + w * up) / axes, d = dir / axes;
    const double a = glm::dot(d, d), b = 2.0 * glm::dot(q, d), c = glm::dot(q, q) - 1.0;
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0.0) return std::nullopt;
    return 0.5 * (-b - std::sqrt(disc)) / (2.0 * a);
  };
  for (ViewLayout layout : {ViewLayout::kHemiOct, ViewLayout::kOct}) {
    SCOPED_TRACE(layout == ViewLayout::kOct ? "oct" : "hemioct");
    BakeOptions o;
    o.cellSize = 96;
    o.supersample = 4;
    o.viewGrid = 3;
    o.viewLayout = layout;
    o.flange = {0.0f, false};
    o.contactSheet = false;
    const auto atlas = bakeAndLoad(src, o, "puff_bake_test_back");
    ASSERT_TRUE(atlas);
    const core::AtlasDesc& d = atlas->desc;
    ASSERT_EQ(atlas->maps.count("back"), 1u);
    const std::vector<core::Image>& back = atlas->maps.at("back");
    ASSERT_EQ(back.size(), static_cast<std::size_t>(d.mipLevels));
    ASSERT_GE(d.mipLevels, 3);
    const core::Image& dist = atlas->maps.at("distance")[0];
    const int ss = d.supersample;
    for (const core::AtlasCell& cell : d.cells) {
      SCOPED_TRACE("view " + std::to_string(cell.view));
      const glm::dvec3 dir = glm::normalize(glm::dvec3(cell.viewDir)), up = glm::normalize(glm::dvec3(cell.viewUp));
      const glm::dvec3 right = glm::cross(up, dir);
      int interior = 0;
      for (int y = 0; y < d.cellSize; ++y) {
        for (int x = 0; x < d.cellSize; ++x) {
          const int ax = cell.rect[0] + x, ay = cell.rect[1] + y;
          const double signedDist = (dist.at(ax, ay) - 0.5) * 2.0 * d.distanceRange;
          const float value = back[0].at(ax, ay);
          if (signedDist >= 1.0) {
            ASSERT_EQ(value, 0.0f) << "texel " << x << "," << y << " off the silhouette bounds something";
            continue;
          }
          if (signedDist > -1.5) continue;
          // The farthest far side over the texel's samples (each at its own centre).
          double farthest = 1.0;
          for (int sy = 0; sy < ss; ++sy) {
            for (int sx = 0; sx < ss; ++sx) {
              const double u = ((x + (sx + 0.5) / ss) - d.margin) * 2.0 / d.contentSize - 1.0;
              const double w = 1.0 - ((y + (sy + 0.5) / ss) - d.margin) * 2.0 / d.contentSize;
              const auto f = farSide(right, up, dir, u, w);
              ASSERT_TRUE(f.has_value()) << "texel " << x << "," << y << " is inside but its ray misses";
              farthest = std::min(farthest, *f);
            }
          }
          ASSERT_NEAR(value, farthest + 0.5, 1.0 / 255.0) << "texel " << x << "," << y;
          ++interior;
        }
      }
      EXPECT_GT(interior, 100) << "too few interior texels checked";
    }
    // Each level keeps the farthest of the block below it (8-bit rounding keeps the order).
    for (int l = 1; l < d.mipLevels; ++l) {
      const core::Image& fine = back[static_cast<std::size_t>(l) - 1];
      const core::Image& coarse = back[static_cast<std::size_t>(l)];
      for (int y = 0; y < coarse.height; ++y) {
        for (int x = 0; x < coarse.width; ++x) {
          const float least = std::min({fine.at(2 * x, 2 * y), fine.at(2 * x + 1, 2 * y), fine.at(2 * x, 2 * y + 1),
                                        fine.at(2 * x + 1, 2 * y + 1)});
          ASSERT_EQ(coarse.at(x, y), least) << "level " << l << " texel " << x << "," << y;
        }
      }
    }
  }
  BakeOptions one;
  one.cellSize = 32;
  one.contactSheet = false;
  const test::ScopedTempDir out("puff_bake_test_back_one");
  one.outDir = out.path();
  auto r = bakeAtlas(src, one);
  ASSERT_OK(r);
  EXPECT_EQ(r->desc.maps.count("back"), 0u) << "a one-view atlas has no back map (no hull reads it)";
}

// Where a ray meets two runs of puff, the back map holds the far side of the farther: it bounds the
// whole puff, never cutting the farther run away (as the first run's end would). Two spheres of
// radius 0.4 (radii of the unit sphere), one behind the other along z (centres at z = +-0.55): seen
// along z (view 4 of a hemi-oct 3x3 grid) every ray through them meets both; from the other views
// (55-63 degrees off z) their discs lie apart, and each ray meets one. Checked against the closed
// form in every view.
TEST_F(BakeGl, BackMapIsTheFarSideOfTheLastRunAlongEachRay) {
  auto a = mesh::generateSphere({4});
  mesh::TriMesh two;
  const glm::dvec3 centres[2] = {{0.0, 0.0, 0.55}, {0.0, 0.0, -0.55}};
  const double radius = 0.4;
  for (const glm::dvec3& c : centres) {
    const auto base = static_cast<unsigned>(two.positions.size());
    for (std::size_t i = 0; i < a.positions.size(); ++i) {
      two.positions.push_back(static_cast<float>(radius) * a.positions[i] + glm::vec3(c));
      two.normals.push_back(a.normals[i]);
    }
    for (const glm::uvec3& t : a.triangles) two.triangles.push_back(t + glm::uvec3(base));
  }
  std::vector<PuffSource> src(1);
  src[0].mesh = std::move(two);
  src[0].provenance.generator = "sphere";
  BakeOptions o;
  o.cellSize = 64;
  o.supersample = 4;
  o.viewGrid = 3;
  o.flange = {0.0f, false};
  o.mips = false;
  o.contactSheet = false;
  const auto atlas = bakeAndLoad(src, o, "puff_bake_test_back_runs");
  ASSERT_TRUE(atlas);
  const core::AtlasDesc& d = atlas->desc;
  const core::Image& back = atlas->maps.at("back")[0];
  const core::Image& dist = atlas->maps.at("distance")[0];
  ASSERT_EQ(d.cells[4].viewDir, glm::vec3(0.0f, 0.0f, 1.0f));
  const int ss = d.supersample;
  for (const core::AtlasCell& cell : d.cells) {
    SCOPED_TRACE("view " + std::to_string(cell.view));
    const glm::dvec3 dir = glm::normalize(glm::dvec3(cell.viewDir)), up = glm::normalize(glm::dvec3(cell.viewUp));
    const glm::dvec3 right = glm::cross(up, dir);
    int interior = 0, behindBoth = 0;
    for (int y = 0; y < d.cellSize; ++y) {
      for (int x = 0; x < d.cellSize; ++x) {
        const int ax = cell.rect[0] + x, ay = cell.rect[1] + y;
        if ((dist.at(ax, ay) - 0.5) * 2.0 * d.distanceRange > -1.5) continue;
        double farthest = 1.0;  // radii
        int both = 0;
        for (int sy = 0; sy < ss; ++sy) {
          for (int sx = 0; sx < ss; ++sx) {
            const double u = ((x + (sx + 0.5) / ss) - d.margin) * 2.0 / d.contentSize - 1.0;
            const double w = 1.0 - ((y + (sy + 0.5) / ss) - d.margin) * 2.0 / d.contentSize;
            const glm::dvec3 q = u * right + w * up;  // on the ray, at z = 0; the ray runs along -dir
            int hits = 0;
            for (const glm::dvec3& c : centres) {
              const glm::dvec3 off = q - c;
              const double along = glm::dot(off, dir), across = glm::dot(off, off) - along * along;
              if (across >= radius * radius) continue;
              ++hits;
              // The sphere's far crossing: -dir by along + sqrt(r^2 - across) from q's foot.
              farthest = std::min(farthest, -along - std::sqrt(radius * radius - across));
            }
            both += hits == 2;
          }
        }
        if (farthest >= 1.0) continue;  // a texel inside the silhouette whose samples all miss: none here
        ASSERT_NEAR(back.at(ax, ay), 0.5 * farthest + 0.5, 1.0 / 255.0) << "texel " << x << "," << y;
        ++interior;
        behindBoth += both > 0;
      }
    }
    EXPECT_GT(interior, 200);
    if (cell.view == 4) {
      EXPECT_EQ(behindBoth, interior) << "seen along z every ray meets both spheres";
    } else {
      EXPECT_EQ(behindBoth, 0) << "seen from here the spheres lie apart";
    }
  }
}

// What the tumbling hull relies on (docs/cel-rendering.md): every point of the puff lies, in every
// view, before the far side the back map holds, read as the hull reads it (the farthest of the four
// level-0 texels around the point, less a step of 8 bits). Checked at every vertex and triangle
// centre of the art's meshes (the default flange). The front depth is not a bound in the same sense:
// a texel holds the mean of its samples' front, and at a steep rim a point of the surface lies up to
// 0.1 diameters in front of the nearest of four (recorded as worst_front; the hull allows a step).
TEST_F(BakeGl, EveryPointOfThePuffLiesBeforeEachViewsFarSide) {
  std::vector<fs::path> files;
  for (const char* f : {"variation-1.obj", "variation-2.ply", "variation-3.off", "variation-4.stl"})
    files.push_back(fs::path(PUFF_SOURCE_DIR) / "art" / "puffs" / f);
  auto sources = loadSources(files, std::nullopt);
  ASSERT_OK(sources);
  BakeOptions o;
  o.cellSize = 128;
  o.viewGrid = 3;
  o.contactSheet = false;
  const auto atlas = bakeAndLoad(*sources, o, "puff_bake_test_bounds");
  ASSERT_TRUE(atlas);
  const core::AtlasDesc& d = atlas->desc;
  const core::Image& nd = atlas->maps.at("normalDepth")[0];
  const core::Image& back = atlas->maps.at("back")[0];
  const core::Image& color = atlas->maps.at("color")[0];
  const double step = 1.0 / 255.0;
  for (int var = 0; var < d.variations; ++var) {
    const mesh::TriMesh& m = (*sources)[static_cast<std::size_t>(var)].mesh;
    std::vector<glm::vec3> points = m.positions;
    for (const glm::uvec3& t : m.triangles)
      points.push_back((m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0f);
    double worstBack = 0.0, worstFront = 0.0;
    int bounded = 0;
    for (int view = 0; view < d.views; ++view) {
      const core::AtlasCell& cell = d.cell(var, view);
      const glm::vec3 dir = cell.viewDir, up = cell.viewUp, right = glm::cross(up, dir);
      for (const glm::vec3& q : points) {
        const glm::vec3 p = 0.5f * q;  // diameters
        // Texel coordinates (texel centres at +0.5), rows down.
        const double x = cell.rect[0] + d.margin + (glm::dot(p, right) + 0.5) * d.contentSize;
        const double y = cell.rect[1] + d.margin + (0.5 - glm::dot(p, up)) * d.contentSize;
        const int x0 = static_cast<int>(std::floor(x - 0.5)), y0 = static_cast<int>(std::floor(y - 0.5));
        double least = 1.0, top = -1.0;
        for (int j = 0; j < 2; ++j) {
          for (int i = 0; i < 2; ++i) {
            least = std::min(least, double(back.at(x0 + i, y0 + j)));
            if (color.at(x0 + i, y0 + j, 3) > 0.0f) top = std::max(top, double(nd.at(x0 + i, y0 + j, 3)));
          }
        }
        const double h = glm::dot(p, dir);
        if (top >= 0.0) worstFront = std::max(worstFront, h - (top - 0.5 + step));
        if (least > 0.0) {
          ++bounded;
          worstBack = std::max(worstBack, (least - 0.5 - step) - h);
        }
      }
    }
    EXPECT_GT(bounded, static_cast<int>(points.size())) << "variation " << var << ": too few points bounded";
    EXPECT_LE(worstBack, 0.0) << "variation " << var << ": a point beyond a view's far side";
    RecordProperty("worst_front_" + std::to_string(var), std::to_string(worstFront));
  }
}

TEST_F(BakeGl, VertexColoursReachTheColourMap) {
  auto src = sphereSources(1, 4);
  src[0].mesh.colors.assign(src[0].mesh.positions.size(), glm::vec3(0.2f, 0.6f, 0.8f));
  BakeOptions o;
  o.cellSize = 64;
  const test::ScopedTempDir out("puff_bake_test_colors");
  o.outDir = out.path();
  o.defaultColor = glm::vec3(1.0f, 0.0f, 0.0f);  // must not be used
  auto r = bakeAtlas(src, o);
  ASSERT_OK(r);
  auto atlas = core::loadAtlas(r->sidecar);
  ASSERT_TRUE(atlas.ok());
  const core::Image& color = atlas->maps.at("color")[0];
  EXPECT_NEAR(color.at(32, 32, 0), 0.2, 0.5 / 255 + 1e-6);
  EXPECT_NEAR(color.at(32, 32, 1), 0.6, 0.5 / 255 + 1e-6);
  EXPECT_NEAR(color.at(32, 32, 2), 0.8, 0.5 / 255 + 1e-6);
  EXPECT_EQ(color.at(32, 32, 3), 1.0f);
}

std::map<std::string, std::string> readAll(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir))
    files[e.path().filename().string()] = *core::readFileBytes(e.path());
  return files;
}

TEST_F(BakeGl, TwoBakesAreByteIdentical) {
  mesh::LumpyParams p;
  p.subdivisions = 4;
  BakeOptions o;
  o.cellSize = 64;
  o.viewGrid = 2;
  std::vector<std::map<std::string, std::string>> runs;
  for (int i = 0; i < 2; ++i) {
    std::vector<PuffSource> src(2);
    for (int k = 0; k < 2; ++k) {
      p.seed = 7 + static_cast<std::uint64_t>(k);
      src[static_cast<std::size_t>(k)].mesh = mesh::generateLumpy(p);
      src[static_cast<std::size_t>(k)].provenance.generator = "lumpy";
    }
    const test::ScopedTempDir out("puff_bake_test_determinism" + std::to_string(i));
    o.outDir = out.path();
    auto r = bakeAtlas(src, o);
    ASSERT_OK(r);
    runs.push_back(readAll(o.outDir));
  }
  ASSERT_EQ(runs[0].size(), runs[1].size());
  ASSERT_GE(runs[0].size(), 5u);
  for (const auto& [name, bytes] : runs[0]) EXPECT_TRUE(runs[1].at(name) == bytes) << name << " differs";
}

TEST_F(BakeGl, ExrMapsMatchThePngMaps) {
  auto src = sphereSources(1, 4);
  BakeOptions o;
  o.cellSize = 32;
  const test::ScopedTempDir out("puff_bake_test_exr");
  o.outDir = out.path();
  auto png = bakeAtlas(src, o);
  ASSERT_OK(png);
  // Read now: the EXR bake replaces the atlas whole, PNG files included.
  auto pngColor = core::readImage(o.outDir / png->desc.maps.at("color").levels[0]);
  o.format = MapFormat::kExr;
  auto exr = bakeAtlas(src, o);
  ASSERT_OK(exr);
  EXPECT_EQ(exr->desc.fileFormat, "exr");
  EXPECT_EQ(exr->sidecar, png->sidecar);  // same sidecar name: the EXR bake replaced it
  auto a = core::loadAtlas(exr->sidecar);
  ASSERT_OK(a);
  EXPECT_EQ(fs::path(a->desc.maps.at("color").levels[0]).extension(), ".exr");
  ASSERT_TRUE(pngColor.ok());
  EXPECT_FALSE(fs::exists(o.outDir / png->desc.maps.at("color").levels[0]));
  const core::Image& exrColor = a->maps.at("color")[0];
  ASSERT_EQ(exrColor.pixels.size(), pngColor->pixels.size());
  for (std::size_t i = 0; i < exrColor.pixels.size(); ++i)
    ASSERT_NEAR(exrColor.pixels[i], pngColor->pixels[i], 0.5 / 255 + 1e-3);
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

}  // namespace
}  // namespace puff::bake

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

}  // namespace
}  // namespace puff::bake

namespace puff::bake {
namespace {

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
