// puffrender's sequence outputs: flipbooks, contact sheets, GIF and MP4 previews, and the GIF's timing.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/io/openimageio.h>

#include "puffrender_cli_fixture.h"
#include "support/assert_ok.h"
#include "support/cli_test.h"
#include "support/read_text.h"

namespace puff::puffrender_cli_test {
namespace {

// A flipbook's cells are the frames rendered alone with a transparent background, left to right and
// top to bottom; cells past the last frame are empty; the JSON beside it says so.
TEST_F(PuffrenderCli, FlipbookCellsAreTheFramesOnATransparentBackground) {
  const fs::path scene = write("ground.json", kGroundScene);
  std::string transparentText = kGroundScene;
  transparentText.replace(transparentText.find("\"#336699\""), 9, "\"transparent\"");
  const fs::path transparent = write("transparent.json", transparentText);
  const fs::path sheet = dir_ / "book" / "sheet.png";
  // Three frames (1-3) in a 2x2 sheet.
  CliRun r = run(scene.string() + " --flipbook 2x2 --frames 1-3 -o " + sheet.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("3 frames, 1 to 3, in 2x2 cells of 40x30, straight alpha"), std::string::npos) << r.out;
  auto image = puff::core::readImage(sheet);
  ASSERT_OK(image);
  ASSERT_EQ(image->width, 80);
  ASSERT_EQ(image->height, 60);
  ASSERT_EQ(image->channels, 4);
  for (int i = 0; i < 3; ++i) {
    const fs::path alone = dir_ / ("alone" + std::to_string(i) + ".png");
    ASSERT_EQ(run(transparent.string() + " -q --frames " + std::to_string(1 + i) + " -o " + alone.string()).exitCode,
              0);
    auto frame = puff::core::readImage(alone);
    ASSERT_OK(frame);
    const int x0 = (i % 2) * 40, y0 = (i / 2) * 30;
    int differ = 0, clear = 0, black = 0;
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x) {
        const bool covered = frame->at(x, y, 3) > 0.0f;
        clear += covered ? 0 : 1;
        // Covered texels are the frame's; uncovered ones keep alpha 0 and take the nearest covered
        // colour (so an engine's filtering blends no black into the smoke's edge).
        for (int c = 0; c < 4; ++c) {
          if (covered || c == 3) differ += frame->at(x, y, c) != image->at(x0 + x, y0 + y, c) ? 1 : 0;
        }
        if (!covered)
          black += image->at(x0 + x, y0 + y, 0) + image->at(x0 + x, y0 + y, 1) + image->at(x0 + x, y0 + y, 2) == 0.0f;
      }
    EXPECT_EQ(differ, 0) << "frame " << 1 + i;
    EXPECT_GT(clear, 0) << "frame " << 1 + i << ": the background is transparent";
    EXPECT_EQ(black, 0) << "frame " << 1 + i << ": uncovered texels hold a covered neighbour's colour";
  }
  for (int y = 30; y < 60; ++y)
    for (int x = 40; x < 80; ++x) ASSERT_EQ(image->at(x, y, 3), 0.0f) << "the empty fourth cell at " << x << "," << y;
  const auto layout = nlohmann::json::parse(*puff::core::readFileBytes(dir_ / "book" / "sheet.json"));
  EXPECT_EQ(layout["image"], "sheet.png");
  EXPECT_EQ(layout["columns"], 2);
  EXPECT_EQ(layout["rows"], 2);
  EXPECT_EQ(layout["frameCount"], 3);
  EXPECT_EQ(layout["frameWidth"], 40);
  EXPECT_EQ(layout["frameHeight"], 30);
  EXPECT_EQ(layout["firstFrame"], 1);
  EXPECT_EQ(layout["lastFrame"], 3);
  EXPECT_EQ(layout["fps"], 10.0);
  EXPECT_EQ(layout["alpha"], "straight");

  // Premultiplied on request: colour times alpha, and no frames given: as many as the sheet holds
  // (all 4 of the scene's in 3x2).
  const fs::path pre = dir_ / "pre.png";
  r = run(scene.string() + " -q --flipbook 3x2 --alpha premultiplied -o " + pre.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto premultiplied = puff::core::readImage(pre);
  ASSERT_OK(premultiplied);
  EXPECT_EQ(premultiplied->width, 120);
  const auto preLayout = nlohmann::json::parse(*puff::core::readFileBytes(dir_ / "pre.json"));
  EXPECT_EQ(preLayout["frameCount"], 4);
  EXPECT_EQ(preLayout["alpha"], "premultiplied");
  int covered = 0;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      const float a = premultiplied->at(x, y, 3);
      for (int c = 0; c < 3; ++c) EXPECT_LE(premultiplied->at(x, y, c), a + 0.5f / 255.0f);
      covered += a > 0.0f ? 1 : 0;
    }
  EXPECT_GT(covered, 0);
}

// --loop N: the last N frames cross-fade into the first N cells, in scene-linear premultiplied
// light (checked on EXR sheets against the frames rendered alone), so the sheet holds N fewer.
TEST_F(PuffrenderCli, ALoopedFlipbookCrossFadesItsEndIntoItsStart) {
  std::string text = kGroundScene;
  text.replace(text.find("\"#336699\""), 9, "\"transparent\"");
  text.replace(text.find("\"frames\": 4"), std::string("\"frames\": 4").size(), "\"frames\": 6");
  const fs::path scene = write("ground6.json", text);
  const fs::path sheetFile = dir_ / "loop.exr";
  CliRun r = run(scene.string() + " --flipbook 2x2 --loop 2 -o " + sheetFile.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("4 frames, 0 to 3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frames 4 to 5 cross-faded into the first 2 cells"), std::string::npos) << r.out;
  auto sheet = puff::core::readImage(sheetFile);
  ASSERT_OK(sheet);
  std::vector<puff::core::Image> frames;
  for (int f = 0; f < 6; ++f) {
    const fs::path alone = dir_ / ("f" + std::to_string(f) + ".exr");
    ASSERT_EQ(run(scene.string() + " -q --frames " + std::to_string(f) + " -o " + alone.string()).exitCode, 0);
    auto image = puff::core::readImage(alone);
    ASSERT_OK(image);
    frames.push_back(*image);
  }
  double worst = 0.0;
  for (int cell = 0; cell < 4; ++cell) {
    const int x0 = (cell % 2) * 40, y0 = (cell / 2) * 30;
    // Cells 0 and 1: frame j at weight (j + 1) / 3 over frame 4 + j; cells 2 and 3: frames 2 and 3.
    const float weight = cell < 2 ? static_cast<float>(cell + 1) / 3.0f : 1.0f;
    const puff::core::Image& head = frames[static_cast<std::size_t>(cell)];
    const puff::core::Image& tail = frames[static_cast<std::size_t>(cell < 2 ? 4 + cell : cell)];
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x)
        for (int c = 0; c < 4; ++c) {
          const float expected = weight * head.at(x, y, c) + (1.0f - weight) * tail.at(x, y, c);
          worst = std::max(worst, static_cast<double>(std::abs(sheet->at(x0 + x, y0 + y, c) - expected)));
        }
  }
  EXPECT_LT(worst, 2e-3) << "half floats: the mix rounded once more than the frames";
  EXPECT_GT(worst, 0.0) << "(the frames differ, so the mix is not one of them)";
  const auto layout = nlohmann::json::parse(*puff::core::readFileBytes(dir_ / "loop.json"));
  EXPECT_EQ(layout["frameCount"], 4);
  EXPECT_EQ(layout["loop"], 2);
  EXPECT_EQ(layout["lastFrame"], 3);
  // Too short to loop, or a loop without a flipbook.
  expectOneLineError(run(scene.string() + " --flipbook 2x2 --loop 4 -o " + (dir_ / "x.png").string()),
                     "render at least 8 frames", 2);
  expectOneLineError(run(scene.string() + " --loop 2 -o " + (dir_ / "x.png").string()),
                     "--loop applies to a --flipbook", 2);
}

// A ball that comes into view at frame 2 and moves left at frame 3: frames 0 and 1 draw nothing;
// frame 4 looks away again and frame 5 back.
constexpr const char* kBallArrives = R"({
  "output": {"width": 40, "height": 30, "samples": 1, "background": "transparent"},
  "camera": {"position": [0, 0, 6], "target": [0, 0, 0], "fovY": 0, "orthoHeight": 3},
  "objects": [{"type": "sphere", "scale": [0.6, 0.6, 0.6]}],
  "animation": {"fps": 10, "frames": 6,
    "cameraPath": [{"time": 0, "position": [20, 0, 6]}, {"time": 0.1, "position": [20, 0, 6]},
                   {"time": 0.2, "position": [0, 0, 6]}, {"time": 0.3, "position": [0.4, 0.2, 6]},
                   {"time": 0.4, "position": [20, 0, 6]}, {"time": 0.5, "position": [0.4, 0.2, 6]}],
    "targetPath": [{"time": 0, "position": [20, 0, 0]}, {"time": 0.1, "position": [20, 0, 0]},
                   {"time": 0.2, "position": [0, 0, 0]}, {"time": 0.3, "position": [0.4, 0.2, 0]},
                   {"time": 0.4, "position": [20, 0, 0]}, {"time": 0.5, "position": [0.4, 0.2, 0]}]}
})";

// Frames 0 to n - 1 of `scene`, each rendered alone to a PNG and read back.
std::vector<puff::core::Image> renderAlone(const std::function<CliRun(const std::string&)>& run, const fs::path& scene,
                                           int n, const fs::path& dir) {
  std::vector<puff::core::Image> frames;
  for (int f = 0; f < n; ++f) {
    const fs::path file = dir / ("alone" + std::to_string(f) + ".png");
    EXPECT_EQ(run(scene.string() + " -q --frames " + std::to_string(f) + " -o " + file.string()).exitCode, 0);
    auto image = puff::core::readImage(file);
    frames.push_back(image ? *image : puff::core::Image(40, 30, 4));
  }
  return frames;
}

// The rectangle holding every covered texel of frames [from, to].
std::array<int, 4> coveredBox(const std::vector<puff::core::Image>& frames, int from, int to) {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
  for (int f = from; f <= to; ++f)
    for (int y = 0; y < frames[static_cast<std::size_t>(f)].height; ++y)
      for (int x = 0; x < frames[static_cast<std::size_t>(f)].width; ++x) {
        if (frames[static_cast<std::size_t>(f)].at(x, y, 3) == 0.0f) continue;
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
  return {x0, y0, x1, y1};
}

// --skip-empty, --crop, --padding and --pow2: the cells hold the frames rendered alone, cropped to the
// rectangle the sequence covers, at the same offset in equal cells; the padding is empty but for the
// bled colour.
TEST_F(PuffrenderCli, FlipbookSheetsCropPadAndSkipTheEmptyStart) {
  const fs::path scene = write("arrives.json", kBallArrives);
  const std::vector<puff::core::Image> alone =
      renderAlone([&](const std::string& a) { return run(a); }, scene, 4, dir_.path());
  EXPECT_EQ(coveredBox(alone, 0, 1)[2], -1) << "frames 0 and 1 draw nothing";
  const auto [x0, y0, x1, y1] = coveredBox(alone, 2, 3);
  ASSERT_GT(x1, x0);
  const int cw = x1 - x0 + 1, ch = y1 - y0 + 1;
  ASSERT_LT(cw, 30) << "the crop is smaller than the frame";
  for (const bool pow2 : {false, true}) {
    SCOPED_TRACE(pow2 ? "--pow2" : "no --pow2");
    const fs::path sheetFile = dir_ / (pow2 ? "p2.png" : "crop.png");
    const CliRun r = run(scene.string() + " --flipbook 2x1 --skip-empty --crop --padding 3" + (pow2 ? " --pow2" : "") +
                         " -o " + sheetFile.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("2 frames, 2 to 3"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("skipped 2 leading frames that draw nothing"), std::string::npos) << r.out;
    auto sheet = puff::core::readImage(sheetFile);
    ASSERT_OK(sheet);
    fs::path layoutFile = sheetFile;
    const auto j = nlohmann::json::parse(*puff::core::readFileBytes(layoutFile.replace_extension(".json")));
    const int cellW = j["cellWidth"], cellH = j["cellHeight"], ox = j["frameOffset"][0], oy = j["frameOffset"][1];
    EXPECT_EQ(j["version"], 3);
    EXPECT_EQ(j["firstFrame"], 2);
    EXPECT_EQ(j["lastFrame"], 3);
    EXPECT_EQ(j["skippedFrames"], 2);
    EXPECT_EQ(j["frameWidth"], cw);
    EXPECT_EQ(j["frameHeight"], ch);
    EXPECT_EQ(j["crop"]["x"], x0);
    EXPECT_EQ(j["crop"]["y"], y0);
    EXPECT_EQ(j["padding"], 3);
    EXPECT_EQ(sheet->width, 2 * cellW);
    EXPECT_EQ(sheet->height, cellH);
    if (pow2) {
      EXPECT_EQ(sheet->width & (sheet->width - 1), 0) << sheet->width;
      EXPECT_EQ(sheet->height & (sheet->height - 1), 0) << sheet->height;
      EXPECT_LE(std::abs((cellW - cw) / 2 - ox), 1) << "the frame is centred in its cell";
    } else {
      EXPECT_EQ(cellW, cw + 6);
      EXPECT_EQ(cellH, ch + 6);
      EXPECT_EQ(ox, 3);
      EXPECT_EQ(oy, 3);
    }
    for (int cell = 0; cell < 2; ++cell) {
      const puff::core::Image& frame = alone[static_cast<std::size_t>(2 + cell)];
      int differ = 0, black = 0;
      for (int y = 0; y < cellH; ++y)
        for (int x = 0; x < cellW; ++x) {
          const int fx = x - ox + x0, fy = y - oy + y0;
          const bool inCrop = fx >= x0 && fx <= x1 && fy >= y0 && fy <= y1;
          const float a = inCrop ? frame.at(fx, fy, 3) : 0.0f;
          const int sx = cell * cellW + x;
          differ += sheet->at(sx, y, 3) != a ? 1 : 0;
          if (a > 0.0f) {
            for (int c = 0; c < 3; ++c) differ += sheet->at(sx, y, c) != frame.at(fx, fy, c) ? 1 : 0;
          } else {
            black += sheet->at(sx, y, 0) + sheet->at(sx, y, 1) + sheet->at(sx, y, 2) == 0.0f ? 1 : 0;
          }
        }
      EXPECT_EQ(differ, 0) << "cell " << cell;
      EXPECT_EQ(black, 0) << "cell " << cell << ": uncovered texels and the padding hold a covered colour";
    }
  }
}

// The layout's scene units and pivot, measured on what was drawn: the ball (radius 0.6, centred on
// the camera's target at frame 2) spans its diameter in scene units, and its coverage is centred on
// the pivot; orthographic (3 units over 30 texels) and perspective (30 degrees, 6 units away, where
// the sphere's outline is 6 tan(asin(0.1)) = 0.603 in radius on the target's plane).
TEST_F(PuffrenderCli, FlipbookLayoutsMeasureTheirCellsInSceneUnits) {
  std::string perspective = kBallArrives;
  perspective.replace(perspective.find("\"fovY\": 0"), 9, "\"fovY\": 30");
  for (const auto& [text, diameter] : {std::pair{std::string(kBallArrives), 1.2}, std::pair{perspective, 1.206}}) {
    const bool ortho = text == kBallArrives;
    SCOPED_TRACE(ortho ? "orthographic" : "perspective");
    const fs::path scene = write("ball.json", text);
    const fs::path sheetFile = dir_ / "units.png";
    ASSERT_EQ(
        run(scene.string() + " -q --flipbook 1x1 --frames 2 --crop --padding 5 -o " + sheetFile.string()).exitCode, 0);
    auto sheet = puff::core::readImage(sheetFile);
    ASSERT_OK(sheet);
    const auto j = nlohmann::json::parse(*puff::core::readFileBytes(dir_ / "units.json"));
    const double unit = j["sceneUnitsPerTexel"], cellW = j["cellWidth"], cellH = j["cellHeight"];
    EXPECT_NEAR(unit, ortho ? 0.1 : 2.0 * 6.0 * std::tan(15.0 * M_PI / 180.0) / 30.0, 1e-7);
    EXPECT_NEAR(j["cellSizeInSceneUnits"][0].get<double>(), unit * cellW, 1e-6);
    double sx = 0.0, sy = 0.0, sum = 0.0;
    for (int y = 0; y < sheet->height; ++y)
      for (int x = 0; x < sheet->width; ++x) {
        const double a = sheet->at(x, y, 3);
        sx += a * (x + 0.5), sy += a * (y + 0.5), sum += a;
      }
    // The drawn area is a disc: its diameter from its area, within a texel.
    EXPECT_NEAR(2.0 * std::sqrt(sum / M_PI) * unit, diameter, unit);
    EXPECT_NEAR(sx / sum / cellW, j["pivot"][0].get<double>(), 0.5 / cellW);
    EXPECT_NEAR(sy / sum / cellH, j["pivot"][1].get<double>(), 0.5 / cellH);
    EXPECT_NE(j["sceneUnitsMeasured"].get<std::string>().find(ortho ? "orthographic" : "6 units"), std::string::npos);
  }
}

// Only the leading empty frames are skipped (frame 4, empty between drawn ones, keeps its cell), also
// when --loop must wait for them all; what cannot be done says so and writes nothing.
TEST_F(PuffrenderCli, FlipbookSkipsOnlyTheLeadingEmptyFrames) {
  const fs::path scene = write("arrives.json", kBallArrives);
  const std::vector<puff::core::Image> alone =
      renderAlone([&](const std::string& a) { return run(a); }, scene, 6, dir_.path());
  const fs::path sheetFile = dir_ / "middle.exr";
  ASSERT_EQ(run(scene.string() + " -q --flipbook 4x1 --skip-empty -o " + sheetFile.string()).exitCode, 0);
  auto sheet = puff::core::readImage(sheetFile);
  ASSERT_OK(sheet);
  auto j = nlohmann::json::parse(*puff::core::readFileBytes(dir_ / "middle.json"));
  EXPECT_EQ(j["firstFrame"], 2);
  EXPECT_EQ(j["lastFrame"], 5);
  EXPECT_EQ(j["frameCount"], 4);
  for (int cell = 0; cell < 4; ++cell) {
    int differ = 0;
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x)
        differ += std::abs(sheet->at(cell * 40 + x, y, 3) - alone[static_cast<std::size_t>(2 + cell)].at(x, y, 3)) >
                          1.0f / 255.0f
                      ? 1
                      : 0;
    EXPECT_EQ(differ, 0) << "cell " << cell << " is frame " << 2 + cell;
  }
  // With --loop 1 the last kept frame (5) mixes into the first cell (2): three cells, 2 to 4.
  ASSERT_EQ(run(scene.string() + " -q --flipbook 3x1 --skip-empty --loop 1 -o " + sheetFile.string()).exitCode, 0);
  j = nlohmann::json::parse(*puff::core::readFileBytes(dir_ / "middle.json"));
  EXPECT_EQ(j["firstFrame"], 2);
  EXPECT_EQ(j["lastFrame"], 4);
  EXPECT_EQ(j["loop"], 1);

  const std::string s = scene.string(), out = (dir_ / "bad.png").string();
  expectOneLineError(run(s + " --flipbook 3x1 --pow2 -o " + out), "a 3x1 grid cannot divide a power-of-two sheet", 2);
  expectOneLineError(run(s + " --flipbook 2x1 --frames 0-1 --crop -o " + out), "--crop: frames 0 to 1 draw nothing", 1);
  expectOneLineError(run(s + " --flipbook 2x1 --frames 0-1 --skip-empty -o " + out),
                     "--skip-empty: frames 0 to 1 draw nothing", 1);
  const CliRun wide = run(s + " --flipbook 2x1 --padding 257 -o " + out);
  EXPECT_EQ(wide.exitCode, 2);
  EXPECT_NE(wide.err.find("--padding: Value 257 not in range 0 to 256"), std::string::npos) << wide.err;
  for (const char* option : {"--padding 2", "--pow2", "--crop", "--skip-empty"}) {
    expectOneLineError(run(s + " " + option + " -o " + out), "applies to a --flipbook", 2);
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(dir_ / "bad.json"));
}

TEST_F(PuffrenderCli, FlipbookUsageErrorsNameTheProblemAndWriteNothing) {
  const fs::path scene = write("ground.json", kGroundScene);
  const std::string s = scene.string();
  const std::string sheet = (dir_ / "sheet.png").string();
  expectOneLineError(run(s + " --flipbook 3 -o " + sheet), "--flipbook: expected COLSxROWS", 2);
  expectOneLineError(run(s + " --flipbook 0x4 -o " + sheet), "each 1 to 256", 2);
  expectOneLineError(run(s + " --flipbook 2x257 -o " + sheet), "each 1 to 256", 2);
  expectOneLineError(run(s + " --flipbook 1x1x2 -o " + sheet), "--flipbook: expected COLSxROWS", 2);
  expectOneLineError(run(s + " --flipbook 1x2 --frames 0-3 -o " + sheet), "holds 2 frames, and --frames 0-3 asks for 4",
                     2);
  expectOneLineError(run(s + " --flipbook 2x2 -o " + (dir_ / "f_##.png").string()), "one sprite sheet", 2);
  expectOneLineError(run(s + " --flipbook 256x256 --width 2000 --height 2000 -o " + sheet), "--flipbook 256x256", 2);
  expectOneLineError(run(s + " --flipbook 2x2 --alpha straight -o " + (dir_ / "sheet.exr").string()),
                     "cannot be written to EXR", 2);
  expectOneLineError(run(s + " --alpha premultiplied -o " + sheet), "--alpha applies to a transparent frame", 2);
  expectOneLineError(run(s + " --flipbook 2x2 --compare fixed,cel -o " + sheet), "do not go together", 2);
  EXPECT_TRUE(outputs().empty());
  // The layout beside the sheet never replaces the scene, an atlas sidecar or another sheet's layout.
  expectOneLineError(run(s + " --flipbook 2x2 -o " + (dir_ / "ground.png").string()), "the scene itself", 2);
  const std::string sidecar = R"({"version": 1, "cells": [], "maps": {}})";
  write("atlas.json", sidecar);
  expectOneLineError(run(s + " --flipbook 2x2 -o " + (dir_ / "atlas.png").string()), "is not a flipbook layout", 2);
  EXPECT_EQ(*puff::core::readFileBytes(dir_ / "atlas.json"), sidecar);
  ASSERT_EQ(run(s + " -q --flipbook 2x2 -o " + (dir_ / "book.png").string()).exitCode, 0);
  expectOneLineError(run(s + " --flipbook 2x2 -o " + (dir_ / "book.exr").string()), "the layout of another sheet", 2);
  EXPECT_EQ(run(s + " -q --flipbook 1x2 -o " + (dir_ / "book.png").string()).exitCode, 0) << "its own layout, again";
}

// A sequence seen whole: the contact sheet is the frames in a grid, each the frame
// rendered alone, with its number under it; without -o only the sheet is written.
TEST_F(PuffrenderCli, ContactSheetIsTheFramesInAGridWithTheirNumbers) {
  const fs::path scene = write("ground.json", kGroundScene);
  const fs::path sheetFile = dir_ / "sheets" / "ground.png";
  CliRun r = run(scene.string() + " --contact-sheet " + sheetFile.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("contact sheet: " + sheetFile.string() + " (180x60, 4 frames)"), std::string::npos) << r.out;
  EXPECT_EQ(outputs(), (std::vector<std::string>{"sheets", "sheets/ground.png"})) << "no frame files without -o";
  auto sheet = puff::core::readImage(sheetFile);
  ASSERT_OK(sheet);
  // 40x30 thumbnails (the frames' own size: under 256 wide), 44 apart across (40 + the 4-px gap),
  // under a 15-px title row, each with its number 2 px under it.
  ASSERT_EQ(sheet->width, 180);
  ASSERT_EQ(sheet->height, 60);
  EXPECT_EQ(puff::test::readText(*sheet, 4, 4, 18), "GROUND: FRAMES 0-3");
  for (int f = 0; f < 4; ++f) {
    const fs::path alone = dir_ / ("alone" + std::to_string(f) + ".png");
    ASSERT_EQ(run(scene.string() + " -q --frames " + std::to_string(f) + " -o " + alone.string()).exitCode, 0);
    auto frame = puff::core::readImage(alone);
    ASSERT_OK(frame);
    const int ox = 4 + f * 44, oy = 15;
    int differ = 0;
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x)
        for (int c = 0; c < 3; ++c) differ += sheet->at(ox + x, oy + y, c) != frame->at(x, y, c) ? 1 : 0;
    EXPECT_EQ(differ, 0) << "frame " << f;
    EXPECT_EQ(puff::test::readGlyph(*sheet, ox, oy + 30 + 2), static_cast<char>('0' + f));
  }
  // A range of one frame is a range.
  r = run(scene.string() + " -q --frames 2-2 --contact-sheet " + (dir_ / "one.png").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto one = puff::core::readImage(dir_ / "one.png");
  ASSERT_OK(one);
  EXPECT_EQ(puff::test::readText(*one, 4, 4, 18), "GROUND: FRAMES 2-2");
  // A range, with frames written too.
  r = run(scene.string() + " -q --frames 2-3 -o " + (dir_ / "f_#.png").string() + " --contact-sheet " +
          (dir_ / "part.png").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "f_2.png") && fs::exists(dir_ / "f_3.png"));
  auto part = puff::core::readImage(dir_ / "part.png");
  ASSERT_OK(part);
  EXPECT_EQ(puff::test::readText(*part, 4, 4, 18), "GROUND: FRAMES 2-3");
  EXPECT_EQ(puff::test::readGlyph(*part, 4, 15 + 32), '2');
}

// More frames than fit in 8192 pixels: one frame in N, said on the sheet and on stdout.
TEST_F(PuffrenderCli, ContactSheetOfALongSequenceShowsEveryNthFrame) {
  std::string text = kGroundScene;
  text.replace(text.find("\"frames\": 4"), std::string("\"frames\": 4").size(), "\"frames\": 130");
  const fs::path scene = write("long.json", text);
  // 16x4000 frames: 61 columns of 33 px (a 5-digit number's width, and the gap) and 2 rows of
  // 4015 px fit 8192: 122 slots for 130 frames, so one frame in 2, 65 shown.
  const fs::path sheetFile = dir_ / "long.png";
  CliRun r = run(scene.string() + " -q --width 16 --height 4000 --contact-sheet " + sheetFile.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto sheet = puff::core::readImage(sheetFile);
  ASSERT_OK(sheet);
  EXPECT_EQ(puff::test::readText(*sheet, 4, 4, 30), "LONG: FRAMES 0-129, ONE IN 2  ");
  EXPECT_LE(sheet->height, 8192);
  // Slot 1 is frame 2, slot 61 (the second row's first) frame 122.
  EXPECT_EQ(puff::test::readText(*sheet, 4 + 33, 15 + 4000 + 2, 1), "2");
  EXPECT_EQ(puff::test::readText(*sheet, 4, 15 + 4015 + 4000 + 2, 3), "122");
  r = run(scene.string() + " --width 16 --height 4000 --frames 0-9 --contact-sheet " + sheetFile.string());
  EXPECT_NE(r.out.find("(334x4030, 10 frames)"), std::string::npos) << r.out;  // one row of 10
  r = run(scene.string() + " --width 16 --height 4000 --contact-sheet " + sheetFile.string());
  EXPECT_NE(r.out.find("(2017x8045, 65 frames, one in 2)"), std::string::npos) << r.out;
}

// The animated preview: a GIF through OpenImageIO, an MP4 through whatever `ffmpeg` is on PATH
// (here a stand-in that keeps what it is given), and clear errors when neither can be written.
TEST_F(PuffrenderCli, PreviewIsAnAnimatedGifOrAnMp4ThroughFfmpeg) {
  const fs::path scene = write("ground.json", kGroundScene);
  const fs::path gif = dir_ / "ground.gif";
  CliRun r = run(scene.string() + " --preview " + gif.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("preview: " + gif.string() +
                       " (4 frames at 10 fps as 4 GIF frames 10/100 s apart, GIF by "
                       "OpenImageIO)"),
            std::string::npos)
      << r.out;
  const std::string bytes = *puff::core::readFileBytes(gif);
  EXPECT_EQ(bytes.rfind("GIF89a", 0), 0u);
  std::size_t frames = 0;
  for (std::size_t at = bytes.find("\x21\xf9\x04"); at != std::string::npos; at = bytes.find("\x21\xf9\x04", at + 1))
    ++frames;
  EXPECT_EQ(frames, 4u) << "a graphic control block per frame";
  EXPECT_NE(bytes.find("NETSCAPE2.0"), std::string::npos) << "it loops";
  // At 24 fps (GIF delays are whole hundredths) some frames show twice: 12 frames become the 13
  // GIF frames gifTiming says, and the GIF says 4/100 s.
  std::string at24 = kGroundScene;
  at24.replace(at24.find("\"fps\": 10, \"frames\": 4"), std::string("\"fps\": 10, \"frames\": 4").size(),
               "\"fps\": 24, \"frames\": 12");
  const fs::path scene24 = write("ground24.json", at24);
  const fs::path gif24 = dir_ / "ground24.gif";
  r = run(scene24.string() + " --preview " + gif24.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const puff::io::GifTiming timing24 = puff::io::gifTiming(12, 24.0);
  EXPECT_EQ(timing24.source.size(), 13u);
  EXPECT_NE(r.out.find("12 frames at 24 fps as 13 GIF frames 4/100 s apart"), std::string::npos) << r.out;
  const std::string bytes24 = *puff::core::readFileBytes(gif24);
  std::size_t blocks24 = 0;
  for (std::size_t at = bytes24.find("\x21\xf9\x04"); at != std::string::npos;
       at = bytes24.find("\x21\xf9\x04", at + 1))
    ++blocks24;
  EXPECT_EQ(blocks24, timing24.source.size());
  // Its first frame is frame 0, within what a 256-colour palette keeps.
  const fs::path still = dir_ / "still.png";
  ASSERT_EQ(run(scene.string() + " -q -o " + still.string()).exitCode, 0);
  auto first = puff::core::readImage(gif), expected = puff::core::readImage(still);
  ASSERT_OK(first);
  ASSERT_OK(expected);
  ASSERT_EQ(first->width, 40);
  int close = 0;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      bool near = true;
      for (int c = 0; c < 3; ++c) near = near && std::abs(first->at(x, y, c) - expected->at(x, y, c)) <= 8.0f / 255.0f;
      close += near ? 1 : 0;
    }
  EXPECT_GE(close, 40 * 30 * 95 / 100);

  // MP4: raw RGB frames piped into ffmpeg with the size and rate, written whole or not at all.
  const fs::path bin = dir_ / "bin";
  fs::create_directories(bin);
  const fs::path args = dir_ / "ffmpeg_args.txt";
  {
    std::ofstream fake(bin / "ffmpeg");
    fake << "#!/bin/sh\nprintf '%s\\n' \"$@\" > '" << args.string() << "'\n"
         << "for a; do out=\"$a\"; done\n"
         << "if [ -n \"$FAKE_FFMPEG_FAIL\" ]; then echo \"Unknown encoder 'libx264'\" >&2; cat >/dev/null; exit 1; fi\n"
         << "cat > \"$out\"\n";
  }
  fs::permissions(bin / "ffmpeg", fs::perms::owner_all);
  const fs::path mp4 = dir_ / "ground.mp4";
  const auto runWithPath = [&](const std::string& env, const std::string& extra) {
    const std::string cmd = env + " " + PUFFRENDER_EXE + " " + scene.string() + " " + extra + " >" +
                            (dir_ / "out.txt").string() + " 2>" + (dir_ / "err.txt").string();
    const int status = std::system(cmd.c_str());
    CliRun result;
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.out = *puff::core::readFileBytes(dir_ / "out.txt");
    result.err = *puff::core::readFileBytes(dir_ / "err.txt");
    return result;
  };
  r = runWithPath("PATH=" + bin.string() + ":/usr/bin:/bin", "--preview " + mp4.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("(4 frames at 10 fps, MP4 (H.264) by ffmpeg)"), std::string::npos) << r.out;
  EXPECT_EQ(fs::file_size(mp4), 40u * 30u * 3u * 4u) << "4 frames of 40x30 RGB, 8 bits";
  const std::string given = *puff::core::readFileBytes(args);
  for (const char* a :
       {"rawvideo\n", "rgb24\n", "-s\n40x30\n", "-framerate\n10\n", "-i\n-\n", "libx264\n", "yuv420p\n"}) {
    EXPECT_NE(given.find(a), std::string::npos) << a << " in\n" << given;
  }
  // The frames piped are the frames rendered: the first 3600 bytes are frame 0's 8-bit RGB.
  const std::string video = *puff::core::readFileBytes(mp4);
  int equal = 0;
  for (int p = 0; p < 40 * 30; ++p)
    for (int c = 0; c < 3; ++c)
      equal += static_cast<unsigned char>(video[static_cast<std::size_t>(p * 3 + c)]) ==
                       static_cast<unsigned char>(
                           std::lround(expected->pixels[static_cast<std::size_t>(p * 4 + c)] * 255.0f))
                   ? 1
                   : 0;
  EXPECT_EQ(equal, 40 * 30 * 3);
  // ffmpeg failing: its message in one line, and the old preview left as it was.
  r = runWithPath("FAKE_FFMPEG_FAIL=1 PATH=" + bin.string() + ":/usr/bin:/bin", "--preview " + mp4.string());
  expectOneLineError(r, "ffmpeg failed (exit status 1): Unknown encoder 'libx264'", 1);
  EXPECT_EQ(fs::file_size(mp4), 40u * 30u * 3u * 4u);
  // No ffmpeg at all.
  r = runWithPath("PATH=/nonexistent", "--preview " + (dir_ / "none.mp4").string());
  expectOneLineError(r, "an MP4 preview needs the ffmpeg program, and there is none on PATH", 1);
  EXPECT_FALSE(fs::exists(dir_ / "none.mp4"));
  // Usage.
  expectOneLineError(run(scene.string() + " --preview " + (dir_ / "x.avi").string()), "expected a .gif or .mp4 name",
                     2);
  expectOneLineError(run(scene.string() + " --contact-sheet " + (dir_ / "x.jpg").string()), "give a .png name", 2);
  expectOneLineError(
      run(scene.string() + " --preview " + gif.string() + " --flipbook 2x2 -o " + (dir_ / "s.png").string()),
      "not with --flipbook", 2);
  expectOneLineError(run(scene.string()), "-o OUT is required (or --contact-sheet, --preview or --print-scene)", 2);
  expectOneLineError(
      run(scene.string() + " -o " + (dir_ / "same.png").string() + " --contact-sheet " + (dir_ / "same.png").string()),
      "is where -o", 2);
  expectOneLineError(run(scene.string() + " -o " + (dir_ / "f_###.png").string() + " --contact-sheet " +
                         (dir_ / "f_002.png").string()),
                     "is where -o", 2);
  // A sheet that cannot be written is found before any frame is drawn (and no frame file is left).
  write("plain.txt", "not a directory");
  expectOneLineError(run(scene.string() + " -o " + (dir_ / "g_#.png").string() + " --contact-sheet " +
                         (dir_ / "plain.txt" / "sheet.png").string()),
                     "plain.txt", 1);
  EXPECT_FALSE(fs::exists(dir_ / "g_0.png"));
}

// GIF keeps one delay for every frame, in hundredths of a second: frames are shown twice or skipped
// so that the GIF lasts as long as the sequence, and no delay is under 2 (browsers slow those).
TEST(GifTiming, TheGifLastsAsLongAsTheSequence) {
  // 24 fps: 4/100 s a frame, 75 GIF frames for 72 (3 s either way), one frame shown twice in 24.
  auto t = puff::io::gifTiming(72, 24.0);
  EXPECT_EQ(t.delay, 4);
  ASSERT_EQ(t.source.size(), 75u);
  EXPECT_EQ(t.source.front(), 0);
  EXPECT_EQ(t.source.back(), 71);
  EXPECT_TRUE(std::is_sorted(t.source.begin(), t.source.end()));
  for (std::size_t k = 0; k < t.source.size(); ++k) {
    const double shown = static_cast<double>(k) * t.delay / 100.0;  // seconds
    EXPECT_LE(t.source[k] / 24.0, shown + 1e-9) << "no frame before its time";
    EXPECT_GT((t.source[k] + 1) / 24.0, shown) << "and none after the next one is due";
  }
  // 10 fps: exact. 60 fps: 2/100 s, every frame due at 50 per second (some skipped).
  EXPECT_EQ(puff::io::gifTiming(4, 10.0).source, (std::vector<int>{0, 1, 2, 3}));
  t = puff::io::gifTiming(60, 60.0);
  EXPECT_EQ(t.delay, 2);
  EXPECT_EQ(t.source.size(), 50u) << "a second at 50 GIF frames a second";
  EXPECT_EQ(puff::io::gifTiming(3, 0.5).delay, 200);
  // Faster than 50 fps: never under 2/100 s (browsers show 1/100 s frames at a tenth of a second).
  EXPECT_EQ(puff::io::gifTiming(120, 100.0).delay, 2);
  EXPECT_EQ(puff::io::gifTiming(120, 120.0).delay, 2);
  EXPECT_EQ(puff::io::gifTiming(120, 120.0).source.size(), 50u);
}

}  // namespace
}  // namespace puff::puffrender_cli_test
