// puffview as an artist and a test meet it: --help tells the truth, a broken scene is one line
// naming the file, the batch screenshot is the very image puffrender makes of the same frame, and
// the ramp editor's bands and gradient go to and from the images the renderer reads. The viewer
// driven one displayed frame at a time (puffview_lib) is puffview_window_test.cpp.
//
// Tests that open a window need a display: ctest runs them under Xvfb (PuffviewUnderXvfb,
// with PUFF_TEST_REQUIRE_GLFW=1); in the plain puff_tests run without DISPLAY they skip.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <puff/core/colour.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/render/path.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>
#include <puffview/ramp_edit.h>
#include <puffview/viewer.h>

#include "puffview_test_helpers.h"
#include "support/assert_ok.h"
#include "support/cli_test.h"

namespace {

namespace fs = std::filesystem;
using puff::core::Image;
using puff::test::CliRun;
using puff::view::test::rgb;
using puff::view::test::shareWithin;

// An edit that leaves a temperature curve on media that no longer emit drops the curve, so the
// scene stays one parseScene reads: whether the material was switched, made to scatter, or set to
// become one that does not emit; a material that becomes fire keeps it.
TEST(RampEdit, AnEditNeverLeavesACurveTheSceneWouldRefuse) {
  const std::string text = R"({"atlas": "a.json", "media": {"materials": [
      {"name": "smoke"}, {"name": "fire", "emissive": true}, {"name": "sooty", "becomes": "fire"}],
    "emitters": [{"material": "fire", "lifetime": 1, "overLife": {"temperature": {"keys": [[0, 3000], [1, 900]]}}}]}})";
  auto parsed = puff::scene::parseScene(nlohmann::json::parse(text), "curves.json");
  ASSERT_OK(parsed);
  const puff::scene::Scene base = *parsed;
  const auto reads = [](const puff::scene::Scene& s) {
    auto again = puff::scene::parseScene(puff::scene::toJson(s), "curves.json");
    return again.ok() ? std::string() : again.error().message;
  };
  puff::scene::Scene s = base;
  EXPECT_FALSE(puff::view::dropRefusedCurves(s)) << "fire keeps its curve";
  EXPECT_EQ(s, base);

  s.media->emitters[0].materialIndex = 2;  // a material that becomes fire
  s.media->emitters[0].material = "sooty";
  EXPECT_FALSE(puff::view::dropRefusedCurves(s));
  EXPECT_EQ(reads(s), "");

  for (int edit = 0; edit < 3; ++edit) {
    s = base;
    if (edit == 0) {
      s.media->emitters[0].materialIndex = 0;
      s.media->emitters[0].material = "smoke";
    } else if (edit == 1) {
      s.media->materials[1].emissive = false;
    } else {
      s.media->emitters[0].materialIndex = 2;
      s.media->emitters[0].material = "sooty";
      s.media->materials[2].becomes = 0;
    }
    SCOPED_TRACE("edit " + std::to_string(edit));
    EXPECT_NE(reads(s).find("does not emit"), std::string::npos) << "the edit alone leaves a refused scene";
    EXPECT_TRUE(puff::view::dropRefusedCurves(s));
    EXPECT_TRUE(s.media->emitters[0].emitter.overLife.temperature.empty());
    EXPECT_EQ(reads(s), "");
  }
}

// The ramp editor's bands and the gradient editor's ends, to and from the images the renderer reads.
TEST(RampEdit, BandsBecomeTheRampImageAndReadBack) {
  using puff::view::RampBands;
  RampBands bands;
  bands.starts = {0.0f, 0.25f, 0.5f, 0.75f};
  bands.colors = {{0.1f, 0.0f, 0.2f}, {0.4f, 0.2f, 0.6f}, {0.8f, 0.6f, 0.2f}, {1.0f, 1.0f, 1.0f}};
  const Image image = puff::view::rampImage(bands);
  ASSERT_EQ(image.width, puff::view::kRampWidth);
  ASSERT_EQ(image.height, 1);
  ASSERT_EQ(image.channels, 3);
  // Texel x holds the band of (x + 0.5) / 256: 63 is the first band's last, 64 the second's first.
  EXPECT_EQ(rgb(image, 0, 0), bands.colors[0]);
  EXPECT_EQ(rgb(image, 63, 0), bands.colors[0]);
  EXPECT_EQ(rgb(image, 64, 0), bands.colors[1]);
  EXPECT_EQ(rgb(image, 191, 0), bands.colors[2]);
  EXPECT_EQ(rgb(image, 192, 0), bands.colors[3]);
  EXPECT_EQ(rgb(image, 255, 0), bands.colors[3]);
  EXPECT_EQ(puff::view::bandsFromImage(image), bands) << "starts on texel boundaries read back exactly";

  // Out of order, out of range, the first not at 0: put in order, clamped, the first from 0.
  RampBands messy;
  messy.starts = {0.6f, 0.2f, -1.0f};
  messy.colors = {{1, 1, 1}, {0.5f, 0.5f, 0.5f}, {2.0f, -1.0f, 0.0f}};
  const RampBands tidy = puff::view::normalized(messy);
  EXPECT_EQ(tidy.starts, (std::vector<float>{0.0f, 0.2f, 0.6f}));
  EXPECT_EQ(tidy.colors[0], glm::vec3(1.0f, 0.0f, 0.0f));
  EXPECT_EQ(puff::view::normalized(RampBands{{}, {}}).starts.size(), 1u) << "at least one band";
  RampBands late;
  late.starts = {0.3f, 0.6f};
  late.colors = {{0, 0, 0}, {1, 1, 1}};
  EXPECT_EQ(puff::view::normalized(late).starts, (std::vector<float>{0.0f, 0.6f})) << "the first band from 0";

  // A smooth ramp (every texel its own) is sampled into the most bands the editor holds.
  Image smooth(256, 3, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 256; ++x)
      for (int c = 0; c < 3; ++c) smooth.at(x, y, c) = y == 1 ? static_cast<float>(x) / 255.0f : 0.0f;
  const RampBands sampled = puff::view::bandsFromImage(smooth);
  ASSERT_EQ(sampled.starts.size(), static_cast<std::size_t>(puff::view::kMaxRampBands));
  EXPECT_NEAR(sampled.colors[0].r, 8.0f / 255.0f, 1e-6f) << "the middle row, at the band's middle";
  EXPECT_EQ(sampled.starts[1], 1.0f / 16.0f);

  // The gradient: top row to bottom row, each end the mean of its row.
  const puff::view::VerticalGradient g{{1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  const Image gi = puff::view::gradientImage(g);
  ASSERT_EQ(gi.width, puff::view::kGradientSize);
  EXPECT_NEAR(gi.at(10, 0, 0), 1.0f - 0.5f / 256.0f, 1e-6f);
  EXPECT_NEAR(gi.at(10, 255, 2), 1.0f - 0.5f / 256.0f, 1e-6f);
  EXPECT_NEAR(gi.at(10, 128, 0), 0.5f - 0.5f / 256.0f, 1e-6f);
  const puff::view::VerticalGradient back = puff::view::gradientFromImage(gi);
  EXPECT_NEAR(back.top.r, 1.0f - 0.5f / 256.0f, 1e-6f);
  EXPECT_NEAR(back.bottom.b, 1.0f - 0.5f / 256.0f, 1e-6f);
}

class PuffviewCli : public puff::test::CliTest {
 protected:
  PuffviewCli() : CliTest(PUFFVIEW_EXE, "puffview") {}

  // puffrender's image of `scene` frame `frame` at 320x240, as the batch screenshot is compared to.
  Image puffrender(const std::string& scene, int frame, const std::string& path = "cel") {
    const fs::path out = dir_ / ("puffrender_" + path + "_" + std::to_string(frame) + ".png");
    const std::string cmd = std::string(PUFFRENDER_EXE) + " " + scene + " -o " + out.string() + " --frames " +
                            std::to_string(frame) + " --path " + path +
                            " --width 320 --height 240 -q --art-dir " PUFF_ART_DIR;
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    auto image = puff::core::readImage(out);
    EXPECT_OK(image);
    return image ? *image : Image{};
  }
  // puffview's batch screenshot of frame frames-1 at 320x240; `extra` options go on the command
  // line, and stderr is expected to be `expectedErr`.
  Image puffview(const std::string& scene, int frames, const std::string& extra = "",
                 const std::string& expectedErr = "") {
    const fs::path out = dir_ / ("puffview_" + std::to_string(frames) + "_" + std::to_string(++shots_) + ".png");
    CliRun r = run(scene + " --frames " + std::to_string(frames) + " --screenshot " + out.string() +
                   " --hide-ui --width 320 --height 240 --art-dir " PUFF_ART_DIR + (extra.empty() ? "" : " " + extra));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    // A batch run longer than a second shows its progress (cli/progress.h, tested there): not
    // what this compares.
    std::string err;
    std::istringstream lines(r.err);
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("puffview: frames ", 0) != 0) err += line + "\n";
    }
    EXPECT_EQ(err, expectedErr);
    EXPECT_NE(r.out.find("wrote " + out.string() + " (320x240, frame " + std::to_string(frames - 1) + ")"),
              std::string::npos)
        << r.out;
    auto image = puff::core::readImage(out);
    EXPECT_OK(image);
    return image ? *image : Image{};
  }

  int shots_ = 0;
};

TEST(PuffviewPaths, OnlyPathsThatExistAreListed) {
  ASSERT_EQ(puff::render::renderPaths().size(), 2u);
  EXPECT_EQ(puff::render::renderPaths()[0].name, "cel") << "the default first";
  EXPECT_EQ(puff::render::renderPaths()[1].name, "fixed");
  puff::scene::Scene scene;
  auto missing = puff::view::createRenderer("media", scene);
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().message, "unknown render path \"media\" (available: cel, fixed)");
}

TEST_F(PuffviewCli, HelpListsTheOptions) {
  CliRun r = run("--help");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  for (const char* option :
       {"scene", "--frames", "--screenshot", "--hide-ui", "--width", "--height", "--art-dir", "--shader-dir",
        "--screenshot-dir", "--path", "--quiet", "cel:", "fixed:", "Space", "F12"}) {
    EXPECT_NE(r.out.find(option), std::string::npos) << option << " missing from --help:\n" << r.out;
  }
  // A render path that does not exist is refused, not faked.
  CliRun bad = run("x.json --path media");
  EXPECT_EQ(bad.exitCode, 2) << bad.err;
  EXPECT_NE(bad.err.find("--path"), std::string::npos) << bad.err;
}

TEST_F(PuffviewCli, BrokenSceneIsOneLineNamingTheFile) {
  const fs::path broken = write("broken.json", "{\"output\": {\"width\": 320,\n");
  expectOneLineError(run(broken.string() + " --frames 1"), broken.string() + ":", 1);
  const fs::path wrong = write("wrong.json", R"({"camera": {"fovY": "wide"}})");
  expectOneLineError(run(wrong.string()), wrong.string() + ": /camera/fovY", 1);
  expectOneLineError(run((dir_ / "missing.json").string()), (dir_ / "missing.json").string(), 1);
}

TEST_F(PuffviewCli, NoDisplayIsOneLineNotACrash) {
  const std::string scene = std::string(PUFF_SOURCE_DIR) + "/art/scenes/cloud-fig8c.json";
  const fs::path out = dir_ / "out.txt", err = dir_ / "err.txt";
  const std::string cmd = "env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(PUFFVIEW_EXE) + " " + scene +
                          " --frames 1 --art-dir " PUFF_ART_DIR " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::string text = *puff::core::readFileBytes(err);
  EXPECT_EQ(text.rfind("puffview: error: glfw: cannot open a window", 0), 0u) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
}

// The batch screenshot of a scene is puffrender's image of the same frame: the viewer draws with
// the same renderer into a target with the scene's MSAA samples and resolves it into the window.
// Measured on llvmpipe: identical in every pixel (RGB; puffrender keeps edge coverage in alpha, a
// window is opaque). The tolerance leaves room for a GPU driver's resolve, nothing more.
TEST_F(PuffviewCli, BatchScreenshotMatchesPuffrender) {
  PUFFVIEW_NEEDS_DISPLAY();
  const std::string cloud = std::string(PUFF_SOURCE_DIR) + "/art/scenes/cloud-fig8c.json";
  // cloud-fig8c is a still (no /animation): its one frame, frame 0. More is refused (RangeWith...).
  const Image view = puffview(cloud, 1);
  expectOneLineError(run(cloud + " --frames 3 --hide-ui --art-dir " PUFF_ART_DIR),
                     "--frames 3: the scene has 1 frame(s), 0 to 0 (/animation/frames)", 2);
  const Image render = puffrender(cloud, 0);
  ASSERT_EQ(view.width, 320);
  ASSERT_EQ(view.height, 240);
  ASSERT_EQ(render.width, 320);
  EXPECT_GE(shareWithin(view, render, 2), 0.999);

  // magic-lamp moves (rising plume, orbiting camera): --frames 5 shows frame 4, not 0.
  const std::string lamp = std::string(PUFF_SOURCE_DIR) + "/art/scenes/magic-lamp.json";
  const Image lampView = puffview(lamp, 5);
  EXPECT_GE(shareWithin(lampView, puffrender(lamp, 4), 2), 0.999);
  EXPECT_LT(shareWithin(lampView, puffrender(lamp, 0), 2), 0.99) << "frame 4 differs from frame 0";

  // A simulated scene: the viewer steps the simulator frame by frame, puffrender simulates frame 6
  // from the start; the same smoke either way.
  const std::string plume = std::string(PUFF_SOURCE_DIR) + "/art/scenes/lamp-plume.json";
  const Image plumeView = puffview(plume, 7);
  EXPECT_GE(shareWithin(plumeView, puffrender(plume, 6), 2), 0.999);
  EXPECT_LT(shareWithin(plumeView, puffrender(plume, 0), 2), 0.99) << "the plume moves";
}

// A transparent scene (the flipbook scene) is shown over a grey checkerboard, not black, so
// its ink stays visible: the screenshot is puffrender's straight-alpha frame composited over the
// checkerboard in linear light, and the corners are the checkerboard's 8-pixel squares.
TEST_F(PuffviewCli, ATransparentSceneIsShownOverACheckerboard) {
  PUFFVIEW_NEEDS_DISPLAY();
  const std::string burst = std::string(PUFF_SOURCE_DIR) + "/art/scenes/puff-burst.json";
  const Image view = puffview(burst, 13);
  const Image render = puffrender(burst, 12);
  ASSERT_EQ(view.width, 320);
  ASSERT_EQ(render.channels, 4);
  const auto checker = [](int x, int y) { return ((x / 8) + (y / 8)) % 2 == 0 ? 0.62f : 0.78f; };
  EXPECT_NEAR(view.at(2, 2, 0), checker(2, 2), 1.0f / 255.0f);
  EXPECT_NEAR(view.at(10, 2, 0), checker(10, 2), 1.0f / 255.0f);
  EXPECT_NEAR(view.at(317, 237, 1), checker(317, 237), 1.0f / 255.0f);
  std::size_t same = 0, covered = 0;
  for (int y = 0; y < view.height; ++y) {
    for (int x = 0; x < view.width; ++x) {
      const float a = render.at(x, y, 3);
      covered += a > 0.5f ? 1 : 0;
      bool close = true;
      for (int c = 0; c < 3; ++c) {
        const double linear = puff::core::srgbToLinear(double{render.at(x, y, c)}) * a +
                              puff::core::srgbToLinear(double{checker(x, y)}) * (1.0 - a);
        close = close && std::abs(puff::core::linearToSrgb(linear) - view.at(x, y, c)) <= 3.0 / 255.0;
      }
      same += close ? 1 : 0;
    }
  }
  EXPECT_GT(covered, 2000u) << "the puffs cover part of the frame";
  EXPECT_GE(static_cast<double>(same) / (view.width * view.height), 0.98);
}

// A sequence from the viewer: --frames A-B with a numbered --screenshot writes every frame
// of the range to its own file, each the frame puffrender draws (a simulated scene started at A,
// not 0, is still a pure function of the frame number); a plain name keeps the last frame only.
TEST_F(PuffviewCli, ARangeWithANumberedScreenshotWritesEveryFrame) {
  PUFFVIEW_NEEDS_DISPLAY();
  const std::string plume = std::string(PUFF_SOURCE_DIR) + "/art/scenes/lamp-plume.json";
  const std::string common = " --hide-ui --width 320 --height 240 --art-dir " PUFF_ART_DIR;
  CliRun r = run(plume + " --frames 4-6 --screenshot " + (dir_ / "seq" / "shot_##.png").string() + common);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("wrote 3 frames (320x240): " + (dir_ / "seq" / "shot_04.png").string() + " .. " +
                       (dir_ / "seq" / "shot_06.png").string()),
            std::string::npos)
      << r.out;
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir_ / "seq")) files.push_back(e.path().filename().string());
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"shot_04.png", "shot_05.png", "shot_06.png"}));
  for (int f = 4; f <= 6; ++f) {
    auto shot = puff::core::readImage(dir_ / "seq" / ("shot_0" + std::to_string(f) + ".png"));
    ASSERT_OK(shot);
    EXPECT_GE(shareWithin(*shot, puffrender(plume, f), 2), 0.999) << "frame " << f;
  }
  // A plain name: the range's last frame.
  const fs::path last = dir_ / "last.png";
  r = run(plume + " --frames 4-6 --screenshot " + last.string() + common);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("wrote " + last.string() + " (320x240, frame 6)"), std::string::npos) << r.out;
  EXPECT_EQ(*puff::core::readFileBytes(last), *puff::core::readFileBytes(dir_ / "seq" / "shot_06.png"));
  // A range past the scene's frames, a range backwards, two patterns: usage errors, nothing written.
  expectOneLineError(run(plume + " --frames 70-72 --screenshot " + (dir_ / "x_#.png").string() + common),
                     "the scene has 72 frame(s)", 2);
  expectOneLineError(run(plume + " --frames 73" + common),
                     "--frames 73: the scene has 72 frame(s), 0 to 71 (/animation/frames)", 2);
  expectOneLineError(run(plume + " --frames 6-4" + common), "ends before it starts", 2);
  expectOneLineError(run(plume + " --frames 0-1 --screenshot " + (dir_ / "a_#_#.png").string() + common),
                     "more than one frame-number pattern", 2);
  EXPECT_FALSE(fs::exists(dir_ / "x_70.png"));
}

// The fixed path in the viewer is puffrender's --path fixed: the same SceneRenderer, built for the
// window's size as puffrender builds it for the image's, drawn into a single-sample target.
// Measured on llvmpipe: every RGB byte the same.
TEST_F(PuffviewCli, FixedPathScreenshotMatchesPuffrender) {
  PUFFVIEW_NEEDS_DISPLAY();
  const std::string lamp = std::string(PUFF_SOURCE_DIR) + "/art/scenes/magic-lamp.json";
  const Image fixedView = puffview(lamp, 1, "--path fixed");
  const Image fixedRender = puffrender(lamp, 0, "fixed");
  ASSERT_EQ(fixedView.width, 320);
  ASSERT_EQ(fixedView.height, 240);
  ASSERT_EQ(fixedRender.width, 320);
  EXPECT_GE(shareWithin(fixedView, fixedRender, 0), 0.999);
  EXPECT_LT(shareWithin(fixedView, puffrender(lamp, 0, "cel"), 2), 0.99) << "the fixed path is not the cel path";
}

// A cel program that does not build: an error in one line naming the shader, exit 1 (a
// broken shader is not a reason to draw something else).
TEST_F(PuffviewCli, BrokenCelShaderIsOneLineAndExitOne) {
  PUFFVIEW_NEEDS_DISPLAY();
  const fs::path shaders = dir_ / "shaders";
  fs::copy(fs::path(PUFF_SOURCE_DIR) / "shaders", shaders, fs::copy_options::recursive);
  std::ofstream(shaders / "cel" / "nailboard.frag", std::ios::binary | std::ios::app) << "\nthis is not glsl;\n";
  const std::string lamp = std::string(PUFF_SOURCE_DIR) + "/art/scenes/magic-lamp.json";
  const fs::path out = dir_ / "fallback.png";
  CliRun r = run(lamp + " --frames 1 --screenshot " + out.string() + " --hide-ui --width 320 --height 240 --art-dir " +
                 PUFF_ART_DIR + " --shader-dir " + shaders.string());
  expectOneLineError(r, "cel/nailboard.frag", 1);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
