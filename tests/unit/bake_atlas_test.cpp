// Whole bakes: an ellipsoid's projected area and back map in every view, vertex colours, determinism, EXR.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include <puff/bake/baker.h>
#include <puff/core/atlas.h>
#include <puff/core/files.h>
#include <puff/core/image.h>

#include "bake_sphere_sources.h"
#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/temp_dir.h"

namespace puff::bake {
namespace {

namespace fs = std::filesystem;

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

}  // namespace
}  // namespace puff::bake
