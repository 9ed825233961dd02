// puffrender --period: a simulated scene as a loop, and a flipbook of one period that loops without
// a seam and without the doubled ink a cross-fade leaves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <puff/core/files.h>
#include <puff/core/image.h>

#include "golden/golden.h"
#include "puffrender_cli_fixture.h"
#include "support/assert_ok.h"

namespace puff::puffrender_cli_test {
namespace {

// A chimney's column of inked cel puffs, steady once its first puffs have died. `prerolled`: the
// emitter starts 4 s before frame 0 (what a cross-faded loop needs to start full).
std::string chimney(bool prerolled) {
  return std::string(R"({
  "output": {"width": 96, "height": 128, "samples": 4, "background": "transparent"},
  "camera": {"position": [0, 1.9, 9], "target": [0, 1.9, 0], "fovY": 0, "orthoHeight": 4.4},
  "light": {"direction": [-0.5, 0.8, 0.6]},
  "ambient": {"color": [0.35, 0.3, 0.45]},
  "atlas": "${PUFF_ART}/default/puff.json",
  "style": {"preset": "cel", "outlineWidth": 2},
  "simulation": {
    "substeps": 2,)") +
         (prerolled ? R"( "preroll": 4,)" : "") + R"(
    "forces": {"drag": 1.5, "buoyancy": 1.6, "turbulence": {"strength": 0.3, "scale": 0.5, "speed": 1.0, "seed": 3}},
    "emitters": [
      {"shape": "disc", "position": [0, 0.2, 0], "radius": 0.2, "rate": 14, "seed": 5,)" +
         (prerolled ? R"( "start": -4,)" : "") + R"(
       "velocity": [0, 1.1, 0], "spread": 10, "speedSpread": 0.2,
       "sizeMin": 0.6, "sizeMax": 0.9, "lifetime": 3.2, "lifetimeSpread": 0.1,
       "overLife": {"size": {"keys": [[0, 0.3], [0.2, 1.1], [0.7, 1.0], [1, 0]], "interp": "smooth"}}}
    ]
  },
  "animation": {"fps": 24, "frames": 48}
})";
}

constexpr int kColumns = 6, kRows = 4, kCellW = 96, kCellH = 128;

// What one cell holds: its coverage (the sum of alpha), its ink (texels covered at least a tenth whose
// straight colour is darker than any lit or shaded puff texel: the outline's), and its see-through ink
// (ink covered between a tenth and nine tenths). A drawn frame's see-through ink is the outline's
// antialiased outer edge; a mix of two frames adds each one's outline where the other does not cover.
struct CellMeasure {
  double coverage = 0.0;
  int ink = 0, seeThrough = 0;
};

std::vector<CellMeasure> measureCells(const core::Image& sheet) {
  std::vector<CellMeasure> cells(kColumns * kRows);
  for (int c = 0; c < kColumns * kRows; ++c) {
    const int x0 = (c % kColumns) * kCellW, y0 = (c / kColumns) * kCellH;
    for (int y = y0; y < y0 + kCellH; ++y)
      for (int x = x0; x < x0 + kCellW; ++x) {
        const float a = sheet.at(x, y, 3);
        cells[static_cast<std::size_t>(c)].coverage += a;
        const float brightest = std::max({sheet.at(x, y, 0), sheet.at(x, y, 1), sheet.at(x, y, 2)});
        if (a > 0.1f && brightest < 0.2f) ++cells[static_cast<std::size_t>(c)].ink;
        if (a > 0.1f && a < 0.9f && brightest < 0.2f) ++cells[static_cast<std::size_t>(c)].seeThrough;
      }
  }
  return cells;
}

// The mean of cell c's two neighbours in the loop (the last cell's next is the first).
template <class Get>
double neighbours(const std::vector<CellMeasure>& cells, std::size_t c, Get get) {
  const std::size_t n = cells.size();
  return 0.5 * (get(cells[(c + n - 1) % n]) + get(cells[(c + 1) % n]));
}

// The median cell's see-through ink.
double medianSeeThrough(const std::vector<CellMeasure>& cells) {
  std::vector<int> v;
  for (const CellMeasure& m : cells) v.push_back(m.seeThrough);
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

TEST_F(PuffrenderCli, APeriodicFlipbookLoopsWithoutASeamOrDoubledInk) {
  const fs::path scene = write("chimney.json", chimney(false));
  const std::string art = " --art-dir " + std::string(PUFF_ART_DIR);
  const fs::path sheetFile = dir_ / "loop.png";
  CliRun r = run(scene.string() + art + " --period 24 --flipbook 6x4 -o " + sheetFile.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("24 frames, 0 to 23, in 6x4 cells of 96x128"), std::string::npos) << r.out;
  const auto layout = nlohmann::json::parse(*core::readFileBytes(dir_ / "loop.json"));
  EXPECT_EQ(layout["period"], 24);
  EXPECT_EQ(layout["loop"], 0);
  auto sheet = core::readImage(sheetFile);
  ASSERT_OK(sheet);

  // The frame after the last is the first.
  const fs::path after = dir_ / "after.png";
  ASSERT_EQ(run(scene.string() + art + " -q --period 24 --frames 24 -o " + after.string()).exitCode, 0);
  auto next = core::readImage(after);
  ASSERT_OK(next);
  core::Image first(kCellW, kCellH, 4);
  for (int y = 0; y < kCellH; ++y)
    for (int x = 0; x < kCellW; ++x)
      for (int c = 0; c < 4; ++c) first.at(x, y, c) = sheet->at(x, y, c);
  int failing = 0;
  for (int y = 0; y < kCellH; ++y)
    for (int x = 0; x < kCellW; ++x) {
      if (next->at(x, y, 3) == 0.0f && first.at(x, y, 3) == 0.0f) continue;  // the sheet bleeds colour into alpha 0
      for (int c = 0; c < 4; ++c)
        failing += std::abs(next->at(x, y, c) - first.at(x, y, c)) > test::kSceneTolerance.pixelThreshold ? 1 : 0;
    }
  EXPECT_LE(failing, test::kSceneTolerance.maxFailingFraction * kCellW * kCellH);

  // Every cell like its neighbours, across the seam too: no jump in coverage, no extra ink.
  const std::vector<CellMeasure> cells = measureCells(*sheet);
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const double around = neighbours(cells, c, [](const CellMeasure& m) { return m.coverage; });
    EXPECT_GT(around, 1000.0) << "cell " << c << " shows the chimney";
    EXPECT_LE(std::abs(cells[c].coverage - around), 0.02 * around) << "cell " << c;
    const double ink = neighbours(cells, c, [](const CellMeasure& m) { return m.ink; });
    EXPECT_LE(cells[c].ink, 1.15 * ink) << "cell " << c << ": " << cells[c].ink << " ink texels";
    EXPECT_LE(cells[c].seeThrough, 1.25 * medianSeeThrough(cells))
        << "cell " << c << ": " << cells[c].seeThrough << " see-through ink texels";
  }

  // A grid larger than the loop holds one period, its other cells empty.
  const fs::path small = dir_ / "small.png";
  CliRun twelve = run(scene.string() + art + " -q --period 12 --flipbook 4x4 -o " + small.string());
  ASSERT_EQ(twelve.exitCode, 0) << twelve.err;
  const auto smallLayout = nlohmann::json::parse(*core::readFileBytes(dir_ / "small.json"));
  EXPECT_EQ(smallLayout["frameCount"], 12);
  EXPECT_EQ(smallLayout["lastFrame"], 11);
  EXPECT_EQ(smallLayout["period"], 12);

  // The same measure sees what a cross-fade does: its first four cells mix two frames' ink.
  const fs::path prerolled = write("prerolled.json", chimney(true));
  ASSERT_EQ(
      run(prerolled.string() + art + " -q --loop 4 --frames 0-27 --flipbook 6x4 -o " + (dir_ / "fade.png").string())
          .exitCode,
      0);
  auto fade = core::readImage(dir_ / "fade.png");
  ASSERT_OK(fade);
  const std::vector<CellMeasure> faded = measureCells(*fade);
  const double median = medianSeeThrough(faded);
  for (std::size_t c = 0; c < faded.size(); ++c) {
    EXPECT_EQ(faded[c].seeThrough > 1.25 * median, c < 4) << "cell " << c << ": " << faded[c].seeThrough;
  }
}

// Media loop too: the fire's simulator repeats, its detail videos play whole times a period, and the
// motion blur of the first frames reads the loop's last ones.
TEST_F(PuffrenderCli, AMediaLoopRepeatsItsDetailAndItsMotionBlur) {
  auto fire = nlohmann::json::parse(*core::readFileBytes(fs::path(PUFF_SOURCE_DIR) / "art/scenes/fire-to-smoke.json"));
  fire["output"]["width"] = 96;
  fire["output"]["height"] = 128;
  fire["media"]["motionBlur"] = {{"frames", 2}, {"persistence", 0.5}};
  fire["animation"]["period"] = 12;
  const fs::path scene = write("fire.json", fire.dump());
  const std::string common = scene.string() + " -q --art-dir " + std::string(PUFF_ART_DIR) + " --frames ";
  for (int f : {0, 1, 7}) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const fs::path a = dir_ / ("a" + std::to_string(f) + ".png"), b = dir_ / ("b" + std::to_string(f) + ".png");
    ASSERT_EQ(run(common + std::to_string(f) + " -o " + a.string()).exitCode, 0);
    ASSERT_EQ(run(common + std::to_string(f + 12) + " -o " + b.string()).exitCode, 0);
    auto first = core::readImage(a), later = core::readImage(b);
    ASSERT_OK(first);
    ASSERT_OK(later);
    float worst = 0.0f;
    for (std::size_t i = 0; i < first->pixels.size(); ++i)
      worst = std::max(worst, std::abs(first->pixels[i] - later->pixels[i]));
    EXPECT_LE(worst, test::kSceneTolerance.pixelThreshold);
  }
}

TEST_F(PuffrenderCli, ALoopRefusesWhatWouldBreakItAndWritesNothing) {
  const fs::path scene = write("chimney.json", chimney(false));
  const std::string art = " --art-dir " + std::string(PUFF_ART_DIR);
  const std::string out = " -o " + (dir_ / "sheet.png").string();
  struct Case {
    std::string args, error;
  };
  for (const Case& c : std::vector<Case>{
           {"--period 24 --flipbook 6x4 --loop 2",
            "--loop cross-fades, and the scene is a loop of 24 frames (--period) that repeats without one"},
           {"--period 24 --flipbook 6x4 --skip-empty", "--skip-empty would cut into the loop"},
           {"--period 30 --flipbook 6x4",
            "--flipbook 6x4 holds 24 frames, and the scene is a loop of 30 frames (--period): give a larger grid"},
           {"--period 12 --flipbook 6x4 --frames 0-17",
            "--frames 0-17 holds 18 frames, and the scene is a loop of 12 frames (--period): a sheet loops when it "
            "holds whole periods"},
           {"--period -1", "--period: Value -1 not in range"},
           {"--period 60 --flipbook 8x8",
            "the loop is longer than the scene: the scene is a loop of 60 frames (--period), and /animation/frames is "
            "48"},
       }) {
    SCOPED_TRACE(c.args);
    const CliRun r = run(scene.string() + art + " " + c.args + out);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find(c.error), std::string::npos) << r.err;
    EXPECT_TRUE(outputs().empty());
  }
  // What does not repeat is named: here, the camera's orbit.
  std::string orbiting = chimney(false);
  orbiting.replace(orbiting.find("\"frames\": 48"), 12, "\"frames\": 48, \"orbit\": 10");
  const fs::path turning = write("turning.json", orbiting);
  const CliRun r = run(turning.string() + art + " --period 24" + out);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--period 24: " + turning.string() +
                       ": /animation/orbit: a camera that orbits does not repeat every period of a loop"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(outputs().empty());
  // The same scene file with the loop in it: read, refused the same way (exit 1: the file is wrong).
  orbiting.replace(orbiting.find("\"orbit\": 10"), 11, "\"orbit\": 10, \"period\": 24");
  const fs::path inFile = write("in-file.json", orbiting);
  const CliRun fromFile = run(inFile.string() + art + out);
  EXPECT_EQ(fromFile.exitCode, 1);
  EXPECT_NE(fromFile.err.find("/animation/orbit: a camera that orbits"), std::string::npos) << fromFile.err;
  EXPECT_TRUE(outputs().empty());
  // --period 0 turns the file's loop off: the orbit renders.
  const CliRun off = run(inFile.string() + art + " -q --period 0" + out);
  EXPECT_EQ(off.exitCode, 0) << off.err;
}

}  // namespace
}  // namespace puff::puffrender_cli_test
