// puffbake as a user meets it: --help tells the truth, bad input gets one line naming the file
// and the problem, a non-zero exit, and no output written or clobbered.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <puff/core/files.h>

#include "support/cli_test.h"

namespace {

namespace fs = std::filesystem;
using puff::test::CliRun;

class PuffbakeCli : public puff::test::CliTest {
 protected:
  PuffbakeCli() : CliTest(PUFFBAKE_EXE, "puffbake") {}
};

TEST_F(PuffbakeCli, HelpListsTheOptionsThatExist) {
  CliRun r = run("bake --help");
  EXPECT_EQ(r.exitCode, 0);
  for (const char* flag :
       {"--size", "--flange", "--views", "--view-layout", "--format", "--lod", "--generate", "--seed", "--supersample",
        "--color", "--no-mips", "--print-defaults", "--gl", "--shader-dir"}) {
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
  }
  CliRun top = run("--help");
  EXPECT_EQ(top.exitCode, 0);
  EXPECT_NE(top.out.find("bake"), std::string::npos);
  EXPECT_NE(top.out.find("mesh"), std::string::npos);
}

TEST_F(PuffbakeCli, PrintDefaultsMatchesTheLibrary) {
  CliRun r = run("bake --print-defaults");
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.out.find("size = 256"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("flange = 3%"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("variations = 4"), std::string::npos) << r.out;
}

TEST_F(PuffbakeCli, BakesAGeneratedPuffAndReportsWhereItWent) {
  CliRun r = run("bake -g lumpy -n 2 --subdivisions 3 -s 32 -o " + (dir_ / "out").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("contact sheet: " + (dir_ / "out" / "puff_contact.png").string()), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "puff.json"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "puff_normal_depth.png"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "puff_color.mip1.png"));
}

TEST_F(PuffbakeCli, BadUsageExitsTwo) {
  expectOneLineError(run("bake -g lumpy -s 0 -o " + (dir_ / "o").string()), "--size must be in [8, 16384], got 0", 2);
  expectOneLineError(run("bake -g lumpy -s 16385 -o " + (dir_ / "o").string()), "--size", 2);
  expectOneLineError(run("bake -o " + (dir_ / "o").string()), "nothing to bake", 2);
  expectOneLineError(run("bake -g lumpy --flange wide -o " + (dir_ / "o").string()), "--flange", 2);
  EXPECT_FALSE(fs::exists(dir_ / "o"));
}

TEST_F(PuffbakeCli, BadMeshesFailWithTheFileAndTheProblem) {
  const fs::path out = dir_ / "out";
  struct Case {
    std::string name, text, needle;
  };
  const std::vector<Case> cases = {
      {"garbage.obj", "this is not a mesh\n\x01\x02\x03", "garbage.obj: "},
      {"empty.obj", "# nothing here\n", "empty.obj: no faces"},
      {"nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n", "nan.obj: vertex"},
      {"flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 2 1 4\n", "flat.obj: face"},
      {"fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n", "fin.obj: non-manifold"},
      {"garbage.stl", "solid x\n facet nonsense\n", "garbage.stl: "},
      {"garbage.ply", "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n", "garbage.ply: "},
      {"mesh.xyz", "v 0 0 0\n", "mesh.xyz: "},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path p = write(c.name, c.text);
    expectOneLineError(run("bake " + p.string() + " -o " + out.string()), c.needle);
    EXPECT_FALSE(fs::exists(out)) << "a failed bake left " << out;
  }
  expectOneLineError(run("bake " + (dir_ / "missing.obj").string() + " -o " + out.string()),
                     "missing.obj: cannot open");
  expectOneLineError(run("bake " + dir_.string() + " -o " + out.string()), ": cannot open");  // a directory
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(PuffbakeCli, UnwritableOutputFailsAndExistingOutputsSurvive) {
  // A file where the output directory should be.
  const fs::path notDir = write("file", "x");
  expectOneLineError(run("bake -g sphere -n 1 -s 16 -o " + notDir.string()), "not a directory");
  // A directory we may not write (root ignores permissions, so only check when that holds).
  const fs::path locked = dir_ / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  if (::access(locked.c_str(), W_OK) != 0) {
    expectOneLineError(run("bake -g sphere -n 1 -s 16 -o " + locked.string()), "cannot write");
  }
  // A previous bake's outputs are untouched by a bake that fails.
  const fs::path out = dir_ / "out";
  ASSERT_EQ(run("bake -g sphere -n 1 -s 16 -o " + out.string()).exitCode, 0);
  std::map<std::string, std::string> before;
  for (const auto& e : fs::directory_iterator(out))
    before[e.path().filename().string()] = *puff::core::readFileBytes(e.path());
  const fs::path bad = write("bad.obj", "v 0 0 0\n");
  EXPECT_EQ(run("bake " + bad.string() + " -s 16 -o " + out.string()).exitCode, 1);
  std::map<std::string, std::string> after;
  for (const auto& e : fs::directory_iterator(out))
    after[e.path().filename().string()] = *puff::core::readFileBytes(e.path());
  EXPECT_TRUE(before == after);
}

TEST_F(PuffbakeCli, SeparateRunsWithLodAndExrAreByteIdentical) {
  std::vector<std::map<std::string, std::string>> runs;
  for (int i = 0; i < 2; ++i) {
    const fs::path out = dir_ / ("run" + std::to_string(i));
    CliRun r = run("bake -g lumpy -n 2 --subdivisions 3 -s 32 --views 2 --lod auto --format exr -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::map<std::string, std::string> files;
    for (const auto& e : fs::directory_iterator(out))
      files[e.path().filename().string()] = *puff::core::readFileBytes(e.path());
    runs.push_back(std::move(files));
    // Let the wall clock tick over, so a timestamp in any file header shows as a difference.
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  }
  ASSERT_GE(runs[0].size(), 8u);
  EXPECT_TRUE(runs[0] == runs[1]);
}

TEST_F(PuffbakeCli, MeshCommandWritesAGeneratedPuffThatBakes) {
  const fs::path mesh = dir_ / "cluster.ply";
  CliRun r = run("mesh -g cluster --count 4 --seed 3 -o " + mesh.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  ASSERT_TRUE(fs::exists(mesh));
  CliRun b = run("bake " + mesh.string() + " -s 32 -o " + (dir_ / "out").string());
  EXPECT_EQ(b.exitCode, 0) << b.err;
}

}  // namespace
