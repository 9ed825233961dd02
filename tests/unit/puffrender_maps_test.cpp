// puffrender --flipbook --maps: the maps an engine lights the cells with, checked against a sphere
// puff's analytic normals and depth, and against the colour sheet they sit beside.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <puff/core/colour.h>
#include <puff/core/files.h>
#include <puff/core/image.h>

#include "puffrender_cli_fixture.h"
#include "support/assert_ok.h"
#include "support/cli_test.h"

namespace puff::puffrender_cli_test {
namespace {

// One sphere puff (the tests' sphere atlas) a diameter of 2 units across, seen by an orthographic
// camera 2.5 units high over `size` pixels: a disc of radius 0.4 size pixels at the frame's centre.
std::string sphereScene(int size, int samples,
                        const std::string& particles = R"([{"position": [0, 0, 0], "size": 2}])") {
  return R"({
  "atlas": ")" +
         std::string(PUFF_TEST_SPHERE_ATLAS_DIR) +
         R"(/puff.json",
  "output": {"width": )" +
         std::to_string(size) + R"(, "height": )" + std::to_string(size) + R"(, "samples": )" +
         std::to_string(samples) + R"(, "background": "transparent"},
  "camera": {"position": [0, 0, 6], "target": [0, 0, 0], "fovY": 0, "orthoHeight": 2.5},
  "light": {"direction": [0.3, 0.8, 0.5]},
  "particles": )" +
         particles +
         R"(,
  "animation": {"fps": 10, "frames": 2}
})";
}

struct Maps {
  core::Image colour, normal, depth, ink;
  nlohmann::json layout;
};

Maps readMaps(const fs::path& sheet) {
  Maps m;
  auto read = [](const fs::path& p) {
    auto image = core::readImage(p);
    EXPECT_TRUE(static_cast<bool>(image)) << p;
    return image ? *image : core::Image();
  };
  m.colour = read(sheet);
  const std::string stem = (sheet.parent_path() / sheet.stem()).string();
  m.normal = read(stem + "_normal.png");
  m.depth = read(stem + "_depth.png");
  m.ink = read(stem + "_ink.png");
  m.layout = nlohmann::json::parse(*core::readFileBytes(fs::path(stem + ".json")));
  return m;
}

// The normal map of a sphere puff is the analytic sphere's normal, 0.5 n + 0.5 with y up: within
// 1/255 in each channel over the inner half of the disc, and within 6/255 out to a pixel and a half
// inside the rim, where the atlas's own 8-bit normals lose precision (z is rebuilt from x and y, so
// a step of x or y moves z by x/z of a step: over 3 steps at 0.95 of the radius; the nailboards
// shade with those same normals). The depth map is the sphere's analytic depth about the camera's
// target within 2/255 (the atlas's 8-bit depth offset is 0.8/255 of the map's range a step), as
// the layout says it is encoded; the ink map is 0 on the body and 1 on the ring just beyond it. At
// 1 and 4 samples and 8 and 16 bits.
TEST_F(PuffrenderCli, SphereMapsAreTheAnalyticSpheres) {
  for (const int samples : {1, 4}) {
    for (const int bits : {8, 16}) {
      SCOPED_TRACE("samples " + std::to_string(samples) + ", " + std::to_string(bits) + " bits");
      constexpr int kSize = 96;
      const fs::path scene = write("sphere.json", sphereScene(kSize, samples));
      const fs::path sheet = dir_ / "sheet.png";
      CliRun r = run(scene.string() + " -q --flipbook 1x1 --maps normal,depth,ink --map-bits " + std::to_string(bits) +
                     " -o " + sheet.string());
      ASSERT_EQ(r.exitCode, 0) << r.err;
      const Maps m = readMaps(sheet);
      ASSERT_EQ(m.normal.channels, 3);
      ASSERT_EQ(m.depth.channels, 1);
      ASSERT_EQ(m.ink.channels, 1);
      const nlohmann::json& depth = m.layout["maps"]["depth"];
      const double range = depth["depthRange"], target = depth["targetDistance"];
      EXPECT_DOUBLE_EQ(target, 6.0);
      EXPECT_DOUBLE_EQ(range, 1.25) << "half the frame's larger side, 2.5 units";
      EXPECT_EQ(m.layout["maps"]["normal"]["bits"], bits);
      const double unit = 2.5 / kSize, centre = 0.5 * kSize;
      double worstInner = 0.0, worstNormal = 0.0, worstDepth = 0.0, worstInkOnBody = 0.0;
      int body = 0, ring = 0, inkOnRing = 0;
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
          const double px = (x + 0.5 - centre) * unit, py = (centre - y - 0.5) * unit;
          const double r2 = px * px + py * py, rPixels = std::sqrt(r2) / unit;
          const double rim = 1.0 / unit;  // the disc's radius in pixels
          if (rPixels < rim - 1.5) {
            // The body, a pixel and a half inside its antialiased rim.
            ASSERT_EQ(m.colour.at(x, y, 3), 1.0f) << x << "," << y;
            const double n[3] = {px, py, std::sqrt(std::max(0.0, 1.0 - r2))};
            for (int c = 0; c < 3; ++c) {
              const double off = std::abs(m.normal.at(x, y, c) - (0.5 * n[c] + 0.5));
              (rPixels <= 0.5 * rim ? worstInner : worstNormal) =
                  std::max(rPixels <= 0.5 * rim ? worstInner : worstNormal, off);
            }
            worstDepth = std::max(worstDepth, std::abs(m.depth.at(x, y, 0) - (0.5 + n[2] / (2.0 * range))));
            worstInkOnBody = std::max(worstInkOnBody, static_cast<double>(m.ink.at(x, y, 0)));
            ++body;
          } else if (m.colour.at(x, y, 3) > 0.0f && m.colour.at(x, y, 3) < 1.0f) {
            // An edge texel: its map values unpremultiplied, as a covered one's.
            const double nx = 2.0 * m.normal.at(x, y, 0) - 1.0, ny = 2.0 * m.normal.at(x, y, 1) - 1.0,
                         nz = 2.0 * m.normal.at(x, y, 2) - 1.0;
            EXPECT_NEAR(std::sqrt(nx * nx + ny * ny + nz * nz), 1.0, 0.1) << x << "," << y;
          } else if (rPixels > rim + 0.75 && rPixels < rim + 1.25 && m.colour.at(x, y, 3) == 1.0f) {
            ++ring;
            inkOnRing += m.ink.at(x, y, 0) == 1.0f ? 1 : 0;
          }
        }
      EXPECT_GT(body, 4000);
      EXPECT_LE(worstInner, 1.0 / 255.0) << "worst normal channel within half the radius off by " << worstInner * 255.0
                                         << "/255";
      EXPECT_LE(worstNormal, 6.0 / 255.0) << "worst normal channel off by " << worstNormal * 255.0 << "/255";
      EXPECT_GT(worstNormal, worstInner) << "(the rim's normals are the least precise)";
      EXPECT_LE(worstDepth, 2.0 / 255.0) << "worst depth off by " << worstDepth * 255.0 << "/255";
      EXPECT_EQ(worstInkOnBody, 0.0);
      EXPECT_GT(ring, 100);
      EXPECT_EQ(inkOnRing, ring) << "the ink's ring beyond the silhouette";
    }
  }
}

// The maps' cells lie where the colour sheet's do, through --crop, --padding and --pow2 over a
// moving puff: every covered texel the colour sheet draws as ink (black) is ink in the ink map, every
// lit one is not.
TEST_F(PuffrenderCli, MapsShareTheSheetsLayout) {
  const fs::path scene = write(
      "moving-scene.json", sphereScene(64, 1, R"([{"position": [-0.4, 0, 0], "size": 1.2, "velocity": [4, 1, 0]}])"));
  const fs::path sheet = dir_ / "moving.png";
  CliRun r = run(scene.string() + " --flipbook 2x1 --crop --padding 3 --pow2 --maps ink,normal -o " + sheet.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("moving_ink.png, " + (dir_ / "moving_normal.png").string()), std::string::npos) << r.out;
  auto colour = core::readImage(sheet), ink = core::readImage(dir_ / "moving_ink.png"),
       normal = core::readImage(dir_ / "moving_normal.png");
  ASSERT_OK(colour);
  ASSERT_OK(ink);
  ASSERT_OK(normal);
  EXPECT_EQ(ink->width, colour->width);
  EXPECT_EQ(ink->height, colour->height);
  EXPECT_EQ(normal->width, colour->width);
  EXPECT_EQ(normal->height, colour->height);
  EXPECT_FALSE(fs::exists(dir_ / "moving_depth.png")) << "only the maps asked for";
  int inked = 0, lit = 0, bled = 0;
  for (int y = 0; y < colour->height; ++y)
    for (int x = 0; x < colour->width; ++x) {
      if (colour->at(x, y, 3) == 0.0f) {
        // Uncovered: a covered texel's normal, bled out (a unit vector, not the encoding's 0).
        const glm::vec3 n = 2.0f * glm::vec3(normal->at(x, y, 0), normal->at(x, y, 1), normal->at(x, y, 2)) - 1.0f;
        EXPECT_NEAR(glm::length(n), 1.0f, 0.02f) << x << "," << y;
        ++bled;
        continue;
      }
      if (colour->at(x, y, 3) < 1.0f) continue;
      const float brightest = std::max({colour->at(x, y, 0), colour->at(x, y, 1), colour->at(x, y, 2)});
      const float share = ink->at(x, y, 0);
      if (brightest == 0.0f) {
        EXPECT_EQ(share, 1.0f) << x << "," << y;
        ++inked;
        continue;
      }
      // The colour is mix(body, black ink, share) in linear light, and the body is at most 1 there
      // (within both files' rounding: half a display step is up to 1.2/255 of linear near white).
      EXPECT_LE(core::srgbToLinear(brightest), 1.0 - share + 2.0 / 255.0) << x << "," << y;
      if (share == 0.0f) {
        EXPECT_GT(normal->at(x, y, 2), 0.5f) << x << "," << y << ": a visible surface faces the camera";
        ++lit;
      }
    }
  EXPECT_GT(inked, 100);
  EXPECT_GT(lit, 500);
  EXPECT_GT(bled, 1000) << "the padding and the crop's margin";
  const auto layout = nlohmann::json::parse(*core::readFileBytes(dir_ / "moving.json"));
  ASSERT_TRUE(layout.contains("maps"));
  EXPECT_EQ(layout["maps"].size(), 2u);
  EXPECT_EQ(layout["maps"]["ink"]["image"], "moving_ink.png");
  EXPECT_FALSE(layout["maps"]["normal"].contains("depthRange"));
}

// What --maps cannot do is refused before anything is drawn, writing nothing.
TEST_F(PuffrenderCli, MapsRefuseWhatTheyCannotDo) {
  const fs::path scene = write("sphere.json", sphereScene(32, 1));
  const std::string out = " -o " + (dir_ / "x.png").string();
  expectOneLineError(run(scene.string() + " --maps normal" + out), "--maps applies to a --flipbook", 2);
  // CLI11 checks the names and bits: its error, then the house's pointer to --help.
  CliRun r = run(scene.string() + " --flipbook 1x1 --maps normal,colour" + out);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--maps: colour not in {normal,depth,ink,motion}"), std::string::npos) << r.err;
  r = run(scene.string() + " --flipbook 1x1 --maps ink --map-bits 12" + out);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--map-bits: 12 not in {8,16}"), std::string::npos) << r.err;
  expectOneLineError(run(scene.string() + " --flipbook 2x1 --loop 1 --maps depth" + out),
                     "--maps and --loop do not go together", 2);
  expectOneLineError(run(scene.string() + " --flipbook 1x1 --maps ink --path fixed" + out),
                     "only the cel path writes maps", 2);
  expectOneLineError(run(scene.string() + " --flipbook 1x1 --map-bits 16" + out), "--map-bits applies to --maps", 2);
  expectOneLineError(run(scene.string() + " --flipbook 1x1 --map-bits 8" + out), "--map-bits applies to --maps", 2);
  expectOneLineError(run(scene.string() + " --flipbook 1x1 --maps ink,normal,ink" + out),
                     "--maps: ink is asked for twice", 2);
  // A moving camera: the maps' depth and motion need one.
  const fs::path orbit =
      write("orbit.json", sphereScene(32, 1).replace(sphereScene(32, 1).find("\"fps\""), 0, "\"orbit\": 30, "));
  expectOneLineError(run(orbit.string() + " --flipbook 2x1 --maps depth" + out), "--maps: the camera moves", 2);
  EXPECT_EQ(run(orbit.string() + " -q --flipbook 2x1" + out).exitCode, 0) << "without maps it may move";
  fs::remove(dir_ / "x.png");
  fs::remove(dir_ / "x.json");
  EXPECT_TRUE(outputs().empty());
  // A map's name taken by a file this sheet did not write: left alone, nothing written. Once the
  // sheet's own layout names its maps, they are replaced.
  const fs::path mine = write("mine_normal.png", "not a map");
  expectOneLineError(run(scene.string() + " --flipbook 1x1 --maps ink,normal -o " + (dir_ / "mine.png").string()),
                     "the normal map goes to " + mine.string() + ", which exists and is not a map puffrender wrote", 2);
  EXPECT_FALSE(fs::exists(dir_ / "mine.png"));
  EXPECT_EQ(*core::readFileBytes(mine), "not a map");
  fs::remove(mine);
  ASSERT_EQ(run(scene.string() + " -q --flipbook 1x1 --maps ink,normal -o " + (dir_ / "mine.png").string()).exitCode,
            0);
  EXPECT_EQ(run(scene.string() + " -q --flipbook 1x1 --maps ink,normal -o " + (dir_ / "mine.png").string()).exitCode, 0)
      << "its own maps are replaced";
  // Names with spaces around them, and a scene without cel puffs: said so.
  const fs::path empty = write("empty.json", sphereScene(32, 1, "[]"));
  const CliRun spaced =
      run(empty.string() + " --flipbook 1x1 --maps \"normal, depth\" -o " + (dir_ / "e.png").string());
  EXPECT_EQ(spaced.exitCode, 0) << spaced.err;
  EXPECT_NE(spaced.out.find("note: the maps hold the puffs and objects alone, and empty.json has no cel puffs"),
            std::string::npos)
      << spaced.out;
  EXPECT_TRUE(fs::exists(dir_ / "e_depth.png"));
  ASSERT_EQ(run(scene.string() + " -q --flipbook 1x1 -o " + (dir_ / "mine.png").string()).exitCode, 0);
  EXPECT_EQ(run(scene.string() + " -q --flipbook 1x1 --maps normal -o " + (dir_ / "mine.png").string()).exitCode, 0)
      << "a map puffrender wrote is replaced when the layout no longer names it";
}

}  // namespace
}  // namespace puff::puffrender_cli_test
