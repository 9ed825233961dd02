// puffrender's render paths: the fixed-function and reference paths, --compare, and the fallback to fixed.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ios>
#include <string>

#include <nlohmann/json.hpp>

#include <puff/core/files.h>
#include <puff/core/image.h>

#include "puffrender_cli_fixture.h"
#include "support/assert_ok.h"

namespace puff::puffrender_cli_test {
namespace {

class PuffrenderPaths : public PuffrenderCli {
 protected:
  const std::string lamp = (std::filesystem::path(PUFF_SOURCE_DIR) / "art/scenes/magic-lamp.json").string();
  std::string common() const { return lamp + " --art-dir " + std::string(PUFF_ART_DIR) + " --width 160 --height 120"; }
  // Pixels that differ from the scene's background (#2a1838).
  static int smokeAndObjects(const puff::core::Image& im) {
    int n = 0;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x)
        n += std::abs(im.at(x, y, 0) - 0x2a / 255.0f) + std::abs(im.at(x, y, 2) - 0x38 / 255.0f) > 0.05f ? 1 : 0;
    return n;
  }
};

// The art scene made for flipbooks: every frame but the first (before any puff is born) holds smoke,
// and nothing else: no cell is covered from edge to edge, and each keeps a clear border.
TEST_F(PuffrenderPaths, ThePuffBurstSceneMakesAFlipbookOfSmokeAlone) {
  const std::string burst = std::string(PUFF_SOURCE_DIR) + "/art/scenes/puff-burst.json";
  const fs::path sheetFile = dir_ / "burst.png";
  CliRun r = run(burst + " -q --art-dir " + std::string(PUFF_ART_DIR) + " --flipbook 6x6 -o " + sheetFile.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.err, "");
  auto sheet = puff::core::readImage(sheetFile);
  ASSERT_OK(sheet);
  ASSERT_EQ(sheet->width, 768);
  for (int cell = 0; cell < 36; ++cell) {
    const int x0 = (cell % 6) * 128, y0 = (cell / 6) * 128;
    int covered = 0, border = 0;
    for (int y = 0; y < 128; ++y)
      for (int x = 0; x < 128; ++x) {
        const bool c = sheet->at(x0 + x, y0 + y, 3) > 0.0f;
        covered += c;
        border += c && (x < 2 || y < 2 || x >= 126 || y >= 126);
      }
    if (cell == 0) {
      EXPECT_EQ(covered, 0) << "frame 0: nothing born yet";
      continue;
    }
    EXPECT_GT(covered, 20) << "frame " << cell;
    EXPECT_LT(covered, 128 * 128 / 2) << "frame " << cell << ": smoke, not a background";
    EXPECT_EQ(border, 0) << "frame " << cell << ": a clear border (mipmaps do not mix cells)";
  }
}

TEST_F(PuffrenderPaths, FixedPathDrawsTheSceneWithoutShaders) {
  const fs::path fixed = dir_ / "fixed.png", cel = dir_ / "cel.png";
  CliRun r = run(common() + " --path fixed -o " + fixed.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  ASSERT_EQ(run(common() + " -o " + cel.string()).exitCode, 0);
  auto a = puff::core::readImage(fixed), b = puff::core::readImage(cel);
  ASSERT_TRUE(a && b);
  EXPECT_GT(smokeAndObjects(*a), 160 * 120 / 10);  // the lamp, the table and the plume
  EXPECT_NE(a->pixels, b->pixels);                 // drawn another way
  EXPECT_NE(run("--help").out.find("--path"), std::string::npos);
  EXPECT_EQ(run(common() + " --path gouraud -o x.png").exitCode, 2);
}

// The cel reference is a path of its own: the same scene, meshes instead of nailboards.
TEST_F(PuffrenderPaths, ReferencePathDrawsThePuffMeshes) {
  const fs::path ref = dir_ / "ref.png", cel = dir_ / "cel.png";
  CliRun r = run(common() + " --path reference -o " + ref.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  ASSERT_EQ(run(common() + " -o " + cel.string()).exitCode, 0);
  auto a = puff::core::readImage(ref), b = puff::core::readImage(cel);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->width, 160);
  EXPECT_GT(smokeAndObjects(*a), 160 * 120 / 10);
  EXPECT_NE(a->pixels, b->pixels);
  EXPECT_NE(run("--help").out.find("reference"), std::string::npos);
  // A media scene: the physical reference draws the media, and says what it is.
  const std::string media = std::string(PUFF_SOURCE_DIR) + "/art/scenes/fire-to-smoke.json --art-dir " +
                            std::string(PUFF_ART_DIR) + " --width 48 --height 64";
  CliRun m = run(media + " --path reference -o " + (dir_ / "media.png").string());
  ASSERT_EQ(m.exitCode, 0) << m.err;
  EXPECT_NE(m.err.find("the media are drawn by the physical reference"), std::string::npos) << m.err;
}

// --path reference draws the media by the physical reference: a pure absorber (albedo 0, no
// emission) of tau 0.5 and radius 1 over a white background, seen orthographically, lets exp(-2 tau r)
// of the background through at its centre (the field's optical depth through the centre is the
// model's), and exp(-tau_line(d)) off centre, tau_line(d) = 2 tau [h - (d^2 / r) ln((r + h) / d)].
TEST_F(PuffrenderPaths, ReferencePathDrawsTheMediaByThePhysicalReference) {
  const nlohmann::json scene = {
      {"output", {{"width", 64}, {"height", 64}, {"samples", 1}, {"background", {1, 1, 1}}}},
      {"camera", {{"position", {0, 0, 5}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fovY", 0}, {"orthoHeight", 4}}},
      {"media",
       {{"materials", {{{"name", "absorber"}, {"albedo", 0}, {"density", 0.5}}}},
        {"particles", {{{"position", {0, 0, 0}}, {"radius", 1}, {"material", "absorber"}, {"life", 0.5}}}}}}};
  const fs::path file = dir_ / "absorber.json", out = dir_ / "absorber.exr";
  std::ofstream(file) << scene.dump();
  CliRun r = run(file.string() + " --path reference -o " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto im = puff::core::readImage(out);
  ASSERT_TRUE(im.ok());
  // Pixel centres at (i + 0.5) / 16 - 2 world units; the sphere's centre sits between pixels 31 and 32.
  auto expected = [](double d) {
    const double tau = 0.5, radius = 1.0, h = std::sqrt(radius * radius - d * d);
    return std::exp(-(d < 1e-12 ? 2 * tau * radius : 2 * tau * (h - d * d / radius * std::log((radius + h) / d))));
  };
  for (int i : {32, 36, 40, 44, 46}) {
    const double x = (i + 0.5) / 16.0 - 2.0, y = (32 + 0.5) / 16.0 - 2.0, d = std::hypot(x, y);
    SCOPED_TRACE(i);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(im->at(i, 31, c), expected(d), 2e-3);  // half floats, row 31 = y 0.03
  }
  EXPECT_NEAR(im->at(2, 2, 0), 1.0, 1e-3);  // the background, untouched
}

TEST_F(PuffrenderPaths, CompareReportsParityAndWritesSideBySide) {
  const fs::path out = dir_ / "cmp.png";
  CliRun r = run(common() + " --compare fixed,cel -o " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("comparing within the fixed path's limits: 1 sample per pixel"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("smoke coverage IoU 0."), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("of shared smoke pixels"), std::string::npos) << r.out;
  auto image = puff::core::readImage(out);
  ASSERT_OK(image);
  EXPECT_EQ(image->width, 3 * 160);  // fixed | cel | difference
  EXPECT_EQ(image->height, 120);
}

TEST_F(PuffrenderPaths, FallsBackToFixedWhenTheProgrammablePathCannotRun) {
  // A shader that does not build: an error in one line naming it, exit 1, no image; not
  // a reason to draw with another path.
  const fs::path shaders = dir_ / "shaders";
  fs::copy(fs::path(PUFF_SOURCE_DIR) / "shaders", shaders, fs::copy_options::recursive);
  std::ofstream(shaders / "cel" / "nailboard.frag", std::ios::app) << "\nnot glsl\n";
  const fs::path out = dir_ / "fallback.png";
  CliRun r = run(common() + " --shader-dir " + shaders.string() + " -o " + out.string());
  expectOneLineError(r, "nailboard.frag", 1);
  EXPECT_FALSE(fs::exists(out));
  const fs::path fixed = dir_ / "fixed.png";
  ASSERT_EQ(run(common() + " --path fixed -o " + fixed.string()).exitCode, 0);

  // A context far too old for GL 4.5 (Mesa told to offer OpenGL 1.3 at most: no shaders, no
  // framebuffer objects): the same fallback, drawing into the context's own framebuffer, and the
  // same picture as the fixed path in a modern context (within 1/255: GL 1.3's texture combiners
  // round differently on a handful of pixels).
  const fs::path old = dir_ / "old.png";
  const std::string cmd = "MESA_GL_VERSION_OVERRIDE=1.3 " + std::string(PUFFRENDER_EXE) + " " + common() + " -o " +
                          old.string() + " 2>" + (dir_ / "err.txt").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const std::string err = *puff::core::readFileBytes(dir_ / "err.txt");
  EXPECT_NE(err.find("cannot create a 4.5 core context"), std::string::npos) << err;
  EXPECT_NE(err.find("; drawing with the fixed-function path\n"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;  // one line says why and what instead
  auto oldImage = puff::core::readImage(old), modern = puff::core::readImage(fixed);
  ASSERT_TRUE(oldImage && modern);
  ASSERT_EQ(oldImage->pixels.size(), modern->pixels.size());
  int off = 0;
  for (std::size_t i = 0; i < oldImage->pixels.size(); ++i) {
    const float d = std::abs(oldImage->pixels[i] - modern->pixels[i]);
    EXPECT_LE(d, 1.5f / 255.0f) << "at " << i;
    off += d > 0.0f ? 1 : 0;
  }
  EXPECT_LT(off, 100);

  // Asked for by name, the cel path does not fall back: one line, exit 1, no image.
  const fs::path asked = dir_ / "asked.png";
  const std::string askedCmd = "MESA_GL_VERSION_OVERRIDE=1.3 " + std::string(PUFFRENDER_EXE) + " " + common() +
                               " --path cel -o " + asked.string() + " 2>" + (dir_ / "err.txt").string();
  const int status = std::system(askedCmd.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << status;
  const std::string askedErr = *puff::core::readFileBytes(dir_ / "err.txt");
  EXPECT_EQ(askedErr.rfind("puffrender: error: --path cel cannot run here: ", 0), 0u) << askedErr;
  EXPECT_EQ(std::count(askedErr.begin(), askedErr.end(), '\n'), 1) << askedErr;
  EXPECT_FALSE(fs::exists(asked));
}

}  // namespace
}  // namespace puff::puffrender_cli_test
