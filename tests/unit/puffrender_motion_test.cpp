// puffrender --flipbook --maps motion: the motion map is each texel's analytic motion to the next
// frame, and it warps a frame toward the next: frame N warped halfway along its vectors is compared
// with the frame truly halfway to N + 1 (the scene at twice the frame rate, its simulation stepped by
// the same steps), with frame N as it is, and with the plain cross-fade of N and N + 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include <puff/core/files.h>
#include <puff/core/image.h>

#include "puffrender_cli_fixture.h"
#include "support/assert_ok.h"
#include "support/cli_test.h"

namespace puff::puffrender_cli_test {
namespace {

struct MotionCase {
  const char* scene;
  int frame;
  bool beatsCrossFade;  // where motion is most of the change (docs/flipbooks.md has the figures)
};

// Bilinear sample of `im` at pixel coordinates (x, y) (texel centres at +0.5), clamped to the edge.
float sample(const core::Image& im, float x, float y, int c, int x0, int y0, int w, int h) {
  const float fx = std::clamp(x - 0.5f, 0.0f, static_cast<float>(w - 1)),
              fy = std::clamp(y - 0.5f, 0.0f, static_cast<float>(h - 1));
  const int ix = std::min(static_cast<int>(fx), w - 2 < 0 ? 0 : w - 2),
            iy = std::min(static_cast<int>(fy), h - 2 < 0 ? 0 : h - 2);
  const float tx = fx - static_cast<float>(ix), ty = fy - static_cast<float>(iy);
  auto at = [&](int u, int v) { return im.at(x0 + std::min(u, w - 1), y0 + std::min(v, h - 1), c); };
  return (1 - ty) * ((1 - tx) * at(ix, iy) + tx * at(ix + 1, iy)) +
         ty * ((1 - tx) * at(ix, iy + 1) + tx * at(ix + 1, iy + 1));
}

// Two sphere puffs seen by an orthographic camera 2.5 units high over 64 pixels (25.6 pixels a
// unit), moving at 1 and 0.5 units a second right and up (10 frames a second: 2.56 and 1.28 pixels
// a frame); the second lives 2 s and shrinks by its 0.1 s a frame (size (1 - t / 2) after its
// first tenth). At frame 3 each covered texel of the body moves as its point on the billboard:
// the centre's motion plus its offset from the centre times the size's ratio less 1, within 0.02
// pixels, at 16 bits; the layout's range is the largest motion rounded up.
TEST_F(PuffrenderCli, MotionMapsAreEachPointsMotion) {
  const std::string atlas = std::string(PUFF_TEST_SPHERE_ATLAS_DIR) + "/puff.json";
  const fs::path scene = write("moving-scene.json", R"({
  "atlas": ")" + atlas + R"(",
  "output": {"width": 64, "height": 64, "samples": 1, "background": "transparent"},
  "camera": {"position": [0, 0, 6], "target": [0, 0, 0], "fovY": 0, "orthoHeight": 2.5},
  "particles": [{"position": [-0.8, -0.4, 0], "size": 0.8, "velocity": [1, 0.5, 0]},
                {"position": [0.1, 0.1, 0], "size": 1.0, "velocity": [1, 0.5, 0], "lifetime": 2}],
  "animation": {"fps": 10, "frames": 8}
})");
  const fs::path sheet = dir_ / "moving.png";
  CliRun r = run(scene.string() + " -q --flipbook 1x1 --frames 3 --maps motion,ink --map-bits 16 -o " + sheet.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto colour = core::readImage(sheet), motion = core::readImage(dir_ / "moving_motion.png"),
       ink = core::readImage(dir_ / "moving_ink.png");
  ASSERT_OK(colour);
  ASSERT_OK(motion);
  ASSERT_OK(ink);
  const auto layout = nlohmann::json::parse(*core::readFileBytes(dir_ / "moving.json"));
  const float range = layout["maps"]["motion"]["motionRange"];
  constexpr double kPixelsPerUnit = 25.6, t = 0.3;
  const double shrink = (1.0 - (t + 0.1) / 2.0) / (1.0 - t / 2.0) - 1.0;  // the second puff's size ratio less 1
  struct Puff {
    double cx, cy, radius, grow;  // centre (pixels, y down), radius (pixels), size ratio less 1
  };
  const Puff puffs[2] = {
      {32 + (-0.8 + t) * kPixelsPerUnit, 32 - (-0.4 + 0.5 * t) * kPixelsPerUnit, 0.4 * kPixelsPerUnit, 0.0},
      {32 + (0.1 + t) * kPixelsPerUnit, 32 - (0.1 + 0.5 * t) * kPixelsPerUnit, 0.5 * (1.0 - t / 2.0) * kPixelsPerUnit,
       shrink}};
  double worst = 0.0, largest = 0.0;
  int checked[2] = {0, 0};
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      if (colour->at(x, y, 3) < 1.0f || ink->at(x, y, 0) > 0.0f) continue;
      for (int k = 0; k < 2; ++k) {
        const Puff& p = puffs[k];
        const double dx = x + 0.5 - p.cx, dy = y + 0.5 - p.cy;
        if (std::hypot(dx, dy) > p.radius - 2.0) continue;
        // x right and y up: rows run down.
        const double ex = 0.1 * kPixelsPerUnit + dx * p.grow, ey = 0.05 * kPixelsPerUnit - dy * p.grow;
        const double mx = (motion->at(x, y, 0) - 0.5) * 2.0 * range, my = (motion->at(x, y, 1) - 0.5) * 2.0 * range;
        worst = std::max({worst, std::abs(mx - ex), std::abs(my - ey)});
        largest = std::max({largest, std::abs(ex), std::abs(ey)});
        ++checked[k];
      }
    }
  EXPECT_GT(checked[0], 100);
  EXPECT_GT(checked[1], 100);
  EXPECT_LT(shrink, -0.05) << "the second puff shrinks, so its texels converge";
  EXPECT_LE(worst, 0.02) << "pixels";
  EXPECT_EQ(range, std::ceil(largest)) << "the largest motion, rounded up";
  EXPECT_DOUBLE_EQ(layout["maps"]["motion"]["motionRangeInCell"][0].get<double>(), range / 64.0);
  EXPECT_EQ(motion->at(0, 0, 2), 0.0f);

  // Cells no frame fills hold nothing (no motion, a normal facing the camera), and leave the range
  // as it was.
  const fs::path grid = dir_ / "grid.png";
  r = run(scene.string() + " -q --flipbook 2x2 --frames 3-4 --maps motion,normal -o " + grid.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto gridMotion = core::readImage(dir_ / "grid_motion.png"), gridNormal = core::readImage(dir_ / "grid_normal.png");
  ASSERT_OK(gridMotion);
  ASSERT_OK(gridNormal);
  const auto gridLayout = nlohmann::json::parse(*core::readFileBytes(dir_ / "grid.json"));
  EXPECT_EQ(gridLayout["maps"]["motion"]["motionRange"].get<float>(), range);
  for (const int x : {0, 40, 63})
    for (const int y : {64, 100, 127}) {
      EXPECT_NEAR(gridMotion->at(x, y, 0), 0.5f, 1.0f / 255.0f) << x << "," << y;
      EXPECT_NEAR(gridMotion->at(x, y, 1), 0.5f, 1.0f / 255.0f) << x << "," << y;
      EXPECT_NEAR(gridNormal->at(x, y, 2), 1.0f, 1.0f / 255.0f) << x << "," << y;
    }
}

class MotionMaps : public PuffrenderCli, public ::testing::WithParamInterface<MotionCase> {};

// RMSE (premultiplied scene-linear RGBA, over the frame) against the true frame N + 1/2: frame N
// warped halfway by its motion map is well below frame N as it is (the vectors point where the
// content goes), and below the cross-fade of N and N + 1 where motion is most of the change.
TEST_P(MotionMaps, WarpFrameNTowardTheNext) {
  const MotionCase c = GetParam();
  nlohmann::json scene = nlohmann::json::parse(
      *core::readFileBytes(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / (std::string(c.scene) + ".json")));
  // A still camera (the map holds the particles' motion, not the camera's), a small frame, and
  // steps of 1/48 s whether the scene runs at 24 or 48 frames a second.
  scene["animation"]["orbit"] = 0;
  scene["output"]["width"] = 160;
  scene["output"]["height"] = 160;
  scene["output"]["background"] = "transparent";
  scene["simulation"]["substeps"] = 2;
  const fs::path scenes = fs::path(PUFF_SOURCE_DIR) / "art" / "scenes";
  for (const char* key : {"ramp", "gradient"}) {
    if (scene.contains(key)) scene[key] = (scenes / scene[key].get<std::string>()).lexically_normal().string();
  }
  nlohmann::json twice = scene;
  twice["animation"]["fps"] = 2 * scene["animation"]["fps"].get<int>();
  twice["animation"]["frames"] = 2 * scene["animation"]["frames"].get<int>();
  twice["simulation"]["substeps"] = 1;
  const std::string art = " --art-dir " + std::string(PUFF_ART_DIR);
  const fs::path at24 = write("at24.json", scene.dump()), at48 = write("at48.json", twice.dump());
  const fs::path sheet = dir_ / "pair.exr", half = dir_ / "half.exr";
  CliRun r = run(at24.string() + art + " -q --flipbook 2x1 --maps motion --frames " + std::to_string(c.frame) + "-" +
                 std::to_string(c.frame + 1) + " -o " + sheet.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = run(at48.string() + art + " -q --frames " + std::to_string(2 * c.frame + 1) + " -o " + half.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto pair = core::readImage(sheet), truth = core::readImage(half), motion = core::readImage(dir_ / "pair_motion.png");
  ASSERT_OK(pair);
  ASSERT_OK(truth);
  ASSERT_OK(motion);
  const auto layout = nlohmann::json::parse(*core::readFileBytes(dir_ / "pair.json"));
  const float range = layout["maps"]["motion"]["motionRange"];
  const int w = 160, h = 160;
  double warpError = 0.0, fadeError = 0.0, stillError = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // Where the content at (x, y) halfway came from: half its motion back (the vector read at the
      // destination, as an engine's flipbook blending reads it). y up in the map, down in rows.
      const float mx = (motion->at(x, y, 0) - 0.5f) * 2.0f * range, my = (motion->at(x, y, 1) - 0.5f) * 2.0f * range;
      const float sx = x + 0.5f - 0.5f * mx, sy = y + 0.5f + 0.5f * my;
      for (int ch = 0; ch < 4; ++ch) {
        const float warped = sample(*pair, sx, sy, ch, 0, 0, w, h);
        const float fade = 0.5f * (pair->at(x, y, ch) + pair->at(w + x, y, ch));
        const float t = truth->at(x, y, ch);
        warpError += (warped - t) * (warped - t);
        stillError += (pair->at(x, y, ch) - t) * (pair->at(x, y, ch) - t);
        fadeError += (fade - t) * (fade - t);
      }
    }
  const double n = 4.0 * w * h;
  warpError = std::sqrt(warpError / n);
  fadeError = std::sqrt(fadeError / n);
  stillError = std::sqrt(stillError / n);
  std::printf("%s frame %d: RMSE against frame N + 1/2: N warped %.5f, N %.5f, cross-fade %.5f (motion range %g)\n",
              c.scene, c.frame, warpError, stillError, fadeError, range);
  EXPECT_GT(fadeError, 1e-3) << "the frames move";
  EXPECT_LT(warpError, 0.8 * stillError) << "the vectors point where the content goes";
  if (c.beatsCrossFade) EXPECT_LT(warpError, fadeError);
}

INSTANTIATE_TEST_SUITE_P(ArtScenes, MotionMaps,
                         ::testing::Values(MotionCase{"puff-burst", 2, true}, MotionCase{"puff-burst", 4, true},
                                           MotionCase{"puff-burst", 12, false}, MotionCase{"puff-burst", 24, false},
                                           MotionCase{"lamp-plume", 24, false}, MotionCase{"lamp-plume", 48, false}),
                         [](const ::testing::TestParamInfo<MotionCase>& i) {
                           std::string n = i.param.scene;
                           for (char& ch : n) ch = ch == '-' ? '_' : ch;
                           return n + "_" + std::to_string(i.param.frame);
                         });

}  // namespace
}  // namespace puff::puffrender_cli_test
