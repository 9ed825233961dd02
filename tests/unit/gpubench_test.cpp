// The GPU benchmark's route as its user takes it: puff_cook_scene writes a scene whose every
// asset a program without an image library reads, drawing exactly what the source scene draws;
// tests/bench/gpu.sh packs puff_gpubench with the libraries it needs (EGL alone among the GL ones)
// and runs it from the package, writing one CSV row per case with its floor and baseline.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <puff/core/files.h>

#include "support/cli_test.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using puff::test::CliRun;

// The file's text, or nothing.
std::string text(const fs::path& file) {
  auto bytes = puff::core::readFileBytes(file);
  return bytes ? *bytes : std::string();
}

class CookedScene : public puff::test::CliTest {
 protected:
  CookedScene() : CliTest(std::string(PUFF_BUILD_DIR) + "/tests/puff_cook_scene", "puff_cook_scene") {}

  // Frame `frame` of `scene` through puffrender at a small size, as PNG bytes.
  std::string render(const fs::path& scene, int frame, const std::string& name) {
    const fs::path out = dir_ / (name + ".png");
    const std::string cmd = std::string(PUFFRENDER_EXE) + " " + scene.string() + " -o " + out.string() + " --frames " +
                            std::to_string(frame) + " --width 96 --height 64 --art-dir " + PUFF_ART_DIR +
                            " >/dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    auto bytes = puff::core::readFileBytes(out);
    return bytes ? *bytes : std::string();
  }
};

// Every kind of asset a scene names (atlas single- and multi-view, ramp, gradient, plate, media detail
// videos, a mesh object): cooked, the scene draws the same bytes, and names no file but cooked images,
// sidecars and meshes.
TEST_F(CookedScene, DrawsWhatItsSourceDraws) {
  const fs::path scenes = fs::path(PUFF_SOURCE_DIR) / "art" / "scenes";
  const fs::path obj =
      write("meshes/tri.obj", "v -1 0 -1\nv 1 0 -1\nv 0 1.5 0\nv 0 0 1\nf 1 2 3\nf 2 4 3\nf 4 1 3\nf 1 4 2\n");
  const fs::path mesh = write("mesh-object.json", R"({
  "output": {"width": 96, "height": 64},
  "camera": {"position": [0, 1, 6], "target": [0, 0.5, 0], "fovY": 40},
  "atlas": "${PUFF_ART}/default/puff.json",
  "objects": [{"type": "mesh", "mesh": "meshes/tri.obj", "albedo": [0.6, 0.4, 0.3]},
              {"type": "mesh", "mesh": "meshes/tri.obj", "translate": [1.5, 0, 0]}],
  "particles": [{"position": [0, 1.2, 1], "size": 1.0}]
})");
  const std::vector<std::pair<fs::path, int>> cases{{scenes / "plate-cloud.json", 0},
                                                    {scenes / "dust-roll.json", 30},
                                                    {scenes / "explosion-walls.json", 20},
                                                    {mesh, 0}};
  for (const auto& [scene, frame] : cases) {
    SCOPED_TRACE(scene.filename().string());
    const fs::path out = dir_ / "cooked" / scene.filename();
    CliRun r = run(scene.string() + " -o " + out.string() + " --art-dir " + PUFF_ART_DIR);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("scene cooked into"), std::string::npos) << r.out;
    const std::string stem = scene.stem().string();
    for (const auto& e : fs::recursive_directory_iterator(dir_ / "cooked" / (stem + ".cooked"))) {
      const std::string ext = e.path().extension().string();
      EXPECT_TRUE(ext == ".puffimg" || ext == ".json" || ext == ".obj") << e.path();
    }
    const std::string cooked = text(out);
    EXPECT_EQ(cooked.find(".png"), std::string::npos) << cooked;  // every image it names is cooked
    EXPECT_EQ(cooked.find("../"), std::string::npos) << cooked;   // and inside its .cooked folder
    EXPECT_EQ(render(out, frame, stem + "-cooked"), render(scene, frame, stem));
  }
  // Both objects' one mesh is copied once.
  EXPECT_TRUE(fs::exists(dir_ / "cooked" / "mesh-object.cooked" / "mesh-0.obj"));
  EXPECT_FALSE(fs::exists(dir_ / "cooked" / "mesh-object.cooked" / "mesh-1.obj"));
}

// A scene whose asset is missing: one line naming it, exit 1, no scene written; bad usage exits 2.
TEST_F(CookedScene, RefusesWhatItCannotCookAndWritesNothing) {
  // The atlas cooks before the ramp is found missing: nothing of it is left.
  write("ramp-missing.json", R"({"ramp": "no-such-ramp.png", "atlas": "${PUFF_ART}/default/puff.json",
                                 "particles": [{"position": [0, 0, 0], "size": 1}]})");
  const fs::path out = dir_ / "cooked" / "ramp-missing.json";
  expectOneLineError(run((dir_ / "ramp-missing.json").string() + " -o " + out.string() + " --art-dir " + PUFF_ART_DIR),
                     "no-such-ramp.png: cannot");
  EXPECT_FALSE(fs::exists(out));
  if (fs::exists(dir_ / "cooked")) {
    EXPECT_TRUE(fs::is_empty(dir_ / "cooked"));
  }
  write("tiny.json", R"({"particles": []})");
  expectOneLineError(run((dir_ / "tiny.json").string() + " -o " + (dir_ / "x.puffimg").string()),
                     "a scene cooks into a scene: name a .json file");
  expectOneLineError(run((dir_ / "tiny.json").string() + " -o " + (dir_ / "tiny.json").string()),
                     "is the scene being cooked");
  // Bad usage: the problem, then the usage, on stderr; exit 2.
  for (const std::string& args : {(dir_ / "tiny.json").string(), (dir_ / "tiny.json").string() + " -o " +
                                                                     (dir_ / "c.json").string() + " --frobnicate"}) {
    CliRun r = run(args);
    EXPECT_EQ(r.exitCode, 2) << args;
    EXPECT_EQ(r.err.rfind("puff_cook_scene: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("usage: puff_cook_scene"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "c.json"));
}

// One CSV row: the header's names to the fields.
std::vector<std::map<std::string, std::string>> readCsv(const std::string& text) {
  std::vector<std::map<std::string, std::string>> rows;
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> names;
  auto split = [](const std::string& l) {
    std::vector<std::string> f;
    std::stringstream s(l);
    for (std::string x; std::getline(s, x, ',');) f.push_back(x);
    if (!l.empty() && l.back() == ',') f.emplace_back();
    return f;
  };
  while (std::getline(in, line)) {
    if (names.empty()) {
      names = split(line);
      continue;
    }
    const auto f = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < names.size() && i < f.size(); ++i) row[names[i]] = f[i];
    EXPECT_EQ(f.size(), names.size()) << line;
    rows.push_back(row);
  }
  return rows;
}

// Packed and run from its package as on a GPU machine (here llvmpipe through EGL): one row per case
// of the quick plan, every time positive, every floor and baseline beside its row, the particle
// counts the scenes place.
TEST(GpuBench, PacksAndRunsFromItsPackage) {
  puff::test::ScopedTempDir dir("gpubench");
  const fs::path package = dir / "package";
  const std::string pack = "bash " + std::string(PUFF_SOURCE_DIR) + "/tests/bench/gpu.sh pack " + PUFF_BUILD_DIR + " " +
                           package.string() + " >" + (dir / "pack.log").string() + " 2>&1";
  ASSERT_EQ(std::system(pack.c_str()), 0) << text(dir / "pack.log");
  EXPECT_TRUE(fs::exists(package / "lib" / "libEGL.so.1"));
  const fs::path csv = dir / "out.csv";
  const std::string runCmd = "bash " + (package / "gpu.sh").string() + " run --quick --samples 1 --csv " +
                             csv.string() + " >" + (dir / "run.log").string() + " 2>&1";
  ASSERT_EQ(std::system(runCmd.c_str()), 0) << text(dir / "run.log");
  const auto rows = readCsv(text(csv));
  const std::map<std::string, std::string> particles{{"nailboards-1000-512", "1000"},
                                                     {"full-map-1000-512", "1000"},
                                                     {"full-volumes-1000-512", "1000"},
                                                     {"cloud-50k-270", "50000"},
                                                     {"blend", "84"},
                                                     {"hull", "84"},
                                                     {"no-media", "0"},
                                                     {"media-0.5", "263"}};
  ASSERT_EQ(rows.size(), particles.size());
  for (const auto& row : rows) {
    const std::string name = row.at("case");
    SCOPED_TRACE(name);
    ASSERT_TRUE(particles.count(name));
    EXPECT_EQ(row.at("particles"), particles.at(name));
    EXPECT_EQ(row.at("samples"), "1");
    for (const char* field : {"gpu_ms", "wall_ms", "floor_gpu_ms", "floor_wall_ms"})
      EXPECT_GT(std::stod(row.at(field)), 0.0) << field;
    // The cloud's rows: the same frame with the lit nailboards shading every layer.
    const std::size_t dash = name.find('-', name.find("full-") == 0 ? 5 : 0);
    const bool cloudRow = name.starts_with("nailboards-") || name.starts_with("full-");
    const std::string baseline = name == "hull"        ? "blend"
                                 : name == "media-0.5" ? "no-media"
                                 : cloudRow            ? name.substr(0, dash) + ".every-layer" + name.substr(dash)
                                                       : "";
    EXPECT_EQ(row.at("baseline"), baseline);
    if (!baseline.empty()) {
      EXPECT_GT(std::stod(row.at("baseline_wall_ms")), 0.0);
    }
    EXPECT_NE(row.at("renderer"), "unknown");
    // The floor draws other pixels than its case wherever there are particles: it was applied.
    EXPECT_EQ(row.at("image").size(), 16u);
    if (row.at("particles") != "0") {
      EXPECT_NE(row.at("image"), row.at("floor_image"));
    }
  }
}

// What pack checks before it packs: a binary that needs an image library or a window system is
// refused, naming them (puffrender needs OpenImageIO, OSMesa and GLFW); puff_gpubench passes.
TEST(GpuBench, RefusesToPackABinaryThatNeedsMoreThanEgl) {
  puff::test::ScopedTempDir dir("gpubench");
  const std::string script = "bash " + std::string(PUFF_SOURCE_DIR) + "/tests/bench/gpu.sh check ";
  const fs::path err = dir / "err.txt";
  const int refused = std::system((script + PUFFRENDER_EXE + " 2>" + err.string()).c_str());
  ASSERT_TRUE(WIFEXITED(refused));
  EXPECT_EQ(WEXITSTATUS(refused), 1);
  const std::string message = text(err);
  EXPECT_EQ(message.rfind("gpu.sh: error: puffrender needs ", 0), 0u) << message;
  for (const char* lib : {"libOpenImageIO", "libOSMesa", "libglfw"})
    EXPECT_NE(message.find(lib), std::string::npos) << lib;
  EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1) << message;
  EXPECT_EQ(std::system((script + PUFF_BUILD_DIR + "/tests/puff_gpubench").c_str()), 0);
}

}  // namespace
