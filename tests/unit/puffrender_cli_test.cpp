// puffrender as a user meets it: --help, usage and scene errors, nothing clobbered, frames written where asked.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <puff/core/files.h>
#include <puff/core/image.h>

#include "puffrender_cli_fixture.h"
#include "support/assert_ok.h"
#include "support/cli_test.h"

namespace puff::puffrender_cli_test {
namespace {

TEST_F(PuffrenderCli, HelpListsTheOptionsThatExist) {
  CliRun r = run("--help");
  EXPECT_EQ(r.exitCode, 0);
  for (const char* flag :
       {"--out", "--frames", "--format", "--gl", "--width", "--height", "--samples", "--art-dir", "--shader-dir",
        "--style", "--print-scene", "--quiet", "%0Nd", "####", "--flipbook", "--alpha"}) {
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
  }
  for (const char* preset : {"outlines", "cel-shadows", "ink", "solid"}) {
    EXPECT_NE(r.out.find(preset), std::string::npos) << preset;
  }
}

// A scene that is valid but likely not what was meant renders, with a warning naming the file and
// the pointer; -q leaves it out.
TEST_F(PuffrenderCli, APrerollNoEmitterFillsIsWarnedAbout) {
  const fs::path scene =
      write("preroll.json", R"({"atlas": "a.json", "simulation": {"preroll": 3, "emitters": [{"rate": 5}]}})");
  CliRun r = run(scene.string() + " --print-scene");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("puffrender: warning: " + scene.string() + ": /simulation/preroll: 3 s are simulated"),
            std::string::npos)
      << r.err;
  r = run(scene.string() + " --print-scene -q");
  EXPECT_EQ(r.err, "");
}

TEST_F(PuffrenderCli, BadUsageExitsTwo) {
  const fs::path scene = write("ground.json", kGroundScene);
  const std::string s = scene.string();
  EXPECT_EQ(run("").exitCode, 2);
  expectOneLineError(run(s), "-o OUT is required", 2);
  EXPECT_EQ(run(s + " -o x.png --samples 3").exitCode, 2);
  EXPECT_EQ(run(s + " -o x.png --width 0").exitCode, 2);
  EXPECT_EQ(run(s + " -o x.png --style watercolour").exitCode, 2);
  EXPECT_EQ(run(s + " -o x.png --format tiff").exitCode, 2);
  EXPECT_EQ(run(s + " -o x.png --no-such-flag").exitCode, 2);
  expectOneLineError(run(s + " -o x.png --frames 3-1"), "ends before it starts", 2);
  expectOneLineError(run(s + " -o x.png --frames two"), "--frames: expected a frame N or a range A-B", 2);
  expectOneLineError(run(s + " -o " + (dir_ / "f%d_###.png").string()), "more than one frame-number pattern", 2);
  // Needs the scene: frames beyond its last, several frames into one file, an unknown extension.
  expectOneLineError(run(s + " -o " + (dir_ / "f_##.png").string() + " --frames 2-4"), "the scene has 4 frame(s)", 2);
  expectOneLineError(run(s + " -o " + (dir_ / "x.png").string() + " --frames 0-1"), "need a numbered output", 2);
  expectOneLineError(run(s + " -o " + (dir_ / "x.tif").string()), "cannot tell the format", 2);
  expectOneLineError(run(s + " -o " + (dir_ / "x.png").string() + " --format exr"), "contradicts", 2);
  EXPECT_TRUE(outputs().empty());
}

TEST_F(PuffrenderCli, BadScenesFailWithTheFileAndThePointer) {
  const fs::path out = dir_ / "out.png";
  const fs::path bad = write("scenes/bad.json", R"({"camera": {"fovY": "wide"}})");
  expectOneLineError(
      run(bad.string() + " -o " + out.string()),
      bad.string() + ": /camera/fovY: expected a number in (0, 180), or 0 for orthographic, got \"wide\"");
  const fs::path typo = write("scenes/typo.json", R"({"output": {"widht": 3}})");
  expectOneLineError(
      run(typo.string() + " -o " + out.string()),
      typo.string() + ": /output/widht: unknown key, expected one of width, height, samples, background");
  const fs::path syntax = write("scenes/syntax.json", "{\n  \"output\": {\n}");
  expectOneLineError(run(syntax.string() + " -o " + out.string()), syntax.string() + ":3:2: ");
  expectOneLineError(run((dir_ / "missing.json").string() + " -o " + out.string()), "missing.json: cannot read");
  EXPECT_FALSE(fs::exists(out));
}

// A file a scene names that cannot be read is one line naming the scene, the JSON pointer
// that named the file, and the file's own problem, on both paths.
TEST_F(PuffrenderCli, AMissingFileNamesTheSceneAndThePointer) {
  const fs::path out = dir_ / "out.png";
  const fs::path atlas =
      write("scenes/atlas.json", R"({"output": {"width": 32, "height": 32}, "atlas": "none/puff.json",
                                                       "particles": [{"position": [0, 0, 0], "size": 1}]})");
  for (const char* path : {"cel", "fixed"}) {
    expectOneLineError(run(atlas.string() + " --path " + path + " -o " + out.string()),
                       atlas.string() + ": /atlas: " + (dir_ / "scenes" / "none" / "puff.json").string() +
                           ": cannot read: No such file or directory");
  }
  const fs::path ramp = write("scenes/ramp.json", R"({"output": {"width": 32, "height": 32}, "ramp": "none.png",
                                                     "objects": [{"type": "box"}]})");
  for (const char* path : {"cel", "fixed"}) {
    expectOneLineError(
        run(ramp.string() + " --path " + path + " -o " + out.string()),
        ramp.string() + ": /ramp: " + (dir_ / "scenes" / "none.png").string() + ": cannot open: no such file");
  }
  EXPECT_FALSE(fs::exists(out));
}

// Output for compositing: a transparent frame's alpha reaches the PNG (straight by default, said in
// puff:alpha) and the EXR (premultiplied); straight EXR is refused before anything is drawn; a
// missing plate is one line naming the scene, the field and the file.
TEST_F(PuffrenderCli, TransparentOutputAndPlateErrors) {
  const fs::path scene = write("scenes/clear.json",
                               R"({"output": {"width": 24, "height": 16, "background": "transparent"},
                                   "objects": [{"type": "box", "translate": [4, 0, 0]}]})");
  const fs::path png = dir_ / "clear.png";
  CliRun r = run(scene.string() + " -o " + png.string() + " -q");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto image = puff::core::readImage(png);
  ASSERT_TRUE(image.ok());
  ASSERT_EQ(image->channels, 4);
  for (int c = 0; c < 4; ++c) EXPECT_EQ(image->at(0, 0, c), 0.0f);  // nothing there: alpha and colour 0
  auto attribute = puff::core::readImageAttribute(png, "puff:alpha");
  ASSERT_TRUE(attribute.ok());
  EXPECT_EQ(*attribute, "straight");
  const fs::path exr = dir_ / "clear.exr";
  r = run(scene.string() + " -o " + exr.string() + " -q");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto exrAttribute = puff::core::readImageAttribute(exr, "puff:alpha");
  ASSERT_TRUE(exrAttribute.ok());
  EXPECT_EQ(*exrAttribute, "premultiplied");

  const fs::path straight =
      write("scenes/straight.json", R"({"output": {"background": "transparent", "alpha": "straight"}})");
  expectOneLineError(run(straight.string() + " -o " + (dir_ / "s.exr").string()),
                     straight.string() + ": /output/alpha: \"straight\" cannot be written to EXR", 2);
  EXPECT_FALSE(fs::exists(dir_ / "s.exr"));

  const fs::path plate = write("scenes/plate.json", R"({"output": {"width": 16, "height": 16, "plate": "gone.png"}})");
  expectOneLineError(run(plate.string() + " -o " + (dir_ / "p.png").string()),
                     plate.string() + ": /output/plate: " + (dir_ / "scenes" / "gone.png").string());
  EXPECT_FALSE(fs::exists(dir_ / "p.png"));
}

TEST_F(PuffrenderCli, ParticlesWithoutAnAtlasAndAMissingAtlasAreErrors) {
  const fs::path out = dir_ / "out.png";
  const fs::path none = write("none.json", R"({"particles": [{"position": [0, 0, 0]}]})");
  expectOneLineError(run(none.string() + " -o " + out.string()),
                     none.string() + ": /atlas: expected an atlas sidecar path (the scene has particles), got none");
  const fs::path missing = write("missing.json", R"({"atlas": "${PUFF_ART}/nowhere/puff.json",
                                                     "particles": [{"position": [0, 0, 0]}]})");
  const CliRun r = run(missing.string() + " -o " + out.string() + " --art-dir " + (dir_ / "art").string());
  expectOneLineError(r, (dir_ / "art" / "nowhere" / "puff.json").string());
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(PuffrenderCli, PrintSceneWritesEveryFieldAndReadsBack) {
  const fs::path scene = write("ground.json", kGroundScene);
  CliRun r = run(scene.string() + " --print-scene --width 77 --style ink");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["output"]["width"], 77);
  EXPECT_EQ(j["output"]["height"], 30);
  EXPECT_EQ(j["style"]["preset"], "ink");
  for (const char* key : {"output", "camera", "light", "ambient", "ramp", "atlas", "style", "particles", "emitters",
                          "objects", "animation"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  // What it prints is a scene that prints the same.
  const fs::path again = write("again.json", r.out);
  CliRun r2 = run(again.string() + " --print-scene");
  ASSERT_EQ(r2.exitCode, 0) << r2.err;
  EXPECT_EQ(r2.out, r.out);
  EXPECT_TRUE(outputs().empty());
}

TEST_F(PuffrenderCli, UnwritableOutputLeavesNothingAndExistingOutputsSurvive) {
  const fs::path scene = write("ground.json", kGroundScene);
  // A file where the output directory should be.
  write("file", "x");
  expectOneLineError(run(scene.string() + " -o " + (dir_ / "file" / "out.png").string()), "not a directory");
  // A directory no one may write, root included (CI runs as root, which ignores permissions): no
  // file or directory can be made in /proc. Then one the permissions lock, where they hold.
  expectOneLineError(run(scene.string() + " -o /proc/out.png"), "/proc: cannot write");
  expectOneLineError(run(scene.string() + " -o /proc/sub/f_##.png"), "/proc/sub: cannot create directory");
  const fs::path locked = dir_ / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  if (::access(locked.c_str(), W_OK) != 0) {  // not root
    expectOneLineError(run(scene.string() + " -o " + (locked / "out.png").string()), "cannot write");
    expectOneLineError(run(scene.string() + " -o " + (locked / "sub" / "f_##.png").string()), "cannot");
  }
  fs::permissions(locked, fs::perms::owner_all);
  fs::remove(locked);
  fs::remove(dir_ / "file");
  EXPECT_TRUE(outputs().empty());

  // An output from before is untouched by a run that fails, even one that fails while loading
  // what the scene names (after the output directory was checked).
  const fs::path out = write("out.png", "previous image");
  const fs::path badRamp = write("badramp.json", R"({"ramp": "no-such-ramp.png"})");
  const CliRun r = run(badRamp.string() + " -o " + out.string());
  expectOneLineError(r, "no-such-ramp.png");
  EXPECT_EQ(*puff::core::readFileBytes(out), "previous image");
  // A failed run into a new directory takes the directory back.
  const CliRun r2 = run(badRamp.string() + " -o " + (dir_ / "new" / "deeper" / "out.png").string());
  EXPECT_EQ(r2.exitCode, 1);
  EXPECT_FALSE(fs::exists(dir_ / "new"));
  EXPECT_EQ(outputs(), std::vector<std::string>{"out.png"});
}

TEST_F(PuffrenderCli, RendersOneFrameToExactlyTheNamedFile) {
  const fs::path scene = write("ground.json", kGroundScene);
  const fs::path out = dir_ / "out" / "ground.png";
  CliRun r = run(scene.string() + " -o " + out.string() + " --frames 2");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("wrote " + out.string()), std::string::npos) << r.out;
  EXPECT_EQ(outputs(), (std::vector<std::string>{"out", "out/ground.png"}));
  auto image = puff::core::readImage(out);
  ASSERT_OK(image);
  EXPECT_EQ(image->width, 40);
  EXPECT_EQ(image->height, 30);
  EXPECT_EQ(image->channels, 4);
  // The background shows in the top-left corner: #336699.
  EXPECT_NEAR(image->at(0, 0, 0), 0x33 / 255.0f, 1.5f / 255.0f);
  EXPECT_NEAR(image->at(0, 0, 1), 0x66 / 255.0f, 1.5f / 255.0f);
  EXPECT_NEAR(image->at(0, 0, 2), 0x99 / 255.0f, 1.5f / 255.0f);

  // Same frame, same bytes; -q prints nothing; --width/--height resize.
  const fs::path again = dir_ / "again.png";
  r = run(scene.string() + " -o " + again.string() + " --frames 2 -q");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(r.out.empty() && r.err.empty()) << r.out << r.err;
  EXPECT_EQ(*puff::core::readFileBytes(again), *puff::core::readFileBytes(out));
  r = run(scene.string() + " -o " + again.string() + " --width 20 --height 10 -q");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  image = puff::core::readImage(again);
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image->width, 20);
  EXPECT_EQ(image->height, 10);
}

TEST_F(PuffrenderCli, RendersANumberedSequenceAsHalfFloatExr) {
  const fs::path scene = write("ground.json", kGroundScene);
  CliRun r = run(scene.string() + " -o " + (dir_ / "seq" / "f_###.exr").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(outputs(),
            (std::vector<std::string>{"seq", "seq/f_000.exr", "seq/f_001.exr", "seq/f_002.exr", "seq/f_003.exr"}));
  // Progress shows only for work longer than a second (progress_test.cpp); if it showed, it ended.
  EXPECT_TRUE(r.err.empty() || r.err.find("frames 4/4 (100%)") != std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("error"), std::string::npos) << r.err;
  auto image = puff::core::readImage(dir_ / "seq" / "f_002.exr");
  ASSERT_OK(image);
  EXPECT_EQ(image->channels, 4);
  // A range of a printf-style pattern; a frame rendered alone equals the same frame of the run.
  r = run(scene.string() + " -q -o " + (dir_ / "part" / "g%04d.exr").string() + " --frames 1-2");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "part" / "g0001.exr"));
  EXPECT_TRUE(fs::exists(dir_ / "part" / "g0002.exr"));
  EXPECT_FALSE(fs::exists(dir_ / "part" / "g0000.exr"));
  EXPECT_EQ(*puff::core::readFileBytes(dir_ / "part" / "g0002.exr"),
            *puff::core::readFileBytes(dir_ / "seq" / "f_002.exr"));
  // --format names the format when the extension does not.
  r = run(scene.string() + " -q -o " + (dir_ / "frame.img").string() + " --format png");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  image = puff::core::readImage(dir_ / "frame.img");
  ASSERT_OK(image);
}

TEST_F(PuffrenderCli, RendersParticlesFromABakedAtlas) {
  const fs::path art = dir_ / "art";
  const std::string bake = std::string(PUFFBAKE_EXE) + " bake -q -g sphere -s 64 --no-contact-sheet -o " +
                           (art / "tiny").string() + " --name puff";
  ASSERT_EQ(std::system(bake.c_str()), 0);
  const fs::path scene = write("puffs.json", R"({
    "output": {"width": 48, "height": 48, "samples": 1},
    "camera": {"position": [0, 0, 6], "target": [0, 0, 0]},
    "atlas": "${PUFF_ART}/tiny/puff.json",
    "style": {"preset": "cel-shadows"},
    "particles": [{"position": [0, 0, 0], "size": 2}],
    "emitters": [{"shape": "box", "count": 20, "halfExtent": [2, 1, 0.5], "sizeMin": 0.3, "sizeMax": 0.6}],
    "objects": [{"type": "plane", "translate": [0, -1.5, 0], "scale": [5, 1, 5]}]
  })");
  const fs::path out = dir_ / "puffs.png";
  CliRun r = run(scene.string() + " -o " + out.string() + " --art-dir " + art.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto image = puff::core::readImage(out);
  ASSERT_OK(image);
  // The big puff covers the centre: not the white background.
  const float centre = image->at(24, 24, 0) + image->at(24, 24, 1) + image->at(24, 24, 2);
  EXPECT_LT(centre, 2.9f);
}

}  // namespace
}  // namespace puff::puffrender_cli_test
