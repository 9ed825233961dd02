// puffbake as a user meets it: --help tells the truth, bad input gets one line naming the file
// and the problem, a non-zero exit, and no output written or clobbered.
#include <gtest/gtest.h>

#include <cstring>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>
#include <vector>

#include <puff/core/atlas.h>
#include <puff/core/blackbody.h>
#include <puff/core/detail_video.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/mesh/mesh.h>

#include "support/assert_ok.h"
#include "support/cli_test.h"
#include "support/read_text.h"

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
  for (const char* flag : {"--size", "--flange", "--views", "--view-layout", "--format", "--lod", "--generate",
                           "--seed", "--supersample", "--color", "--no-mips", "--print-defaults", "--gl",
                           "--shader-dir", "--lod-depth-tolerance", "--lod-color-tolerance"}) {
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
  }
  CliRun top = run("--help");
  EXPECT_EQ(top.exitCode, 0);
  for (const char* cmd : {"bake", "mesh", "blackbody", "detail", "cook"})
    EXPECT_NE(top.out.find(cmd), std::string::npos) << cmd;
  CliRun cook = run("cook --help");
  EXPECT_EQ(cook.exitCode, 0);
  for (const char* text : {"--out", "--quiet", ".puffimg", "input"})
    EXPECT_NE(cook.out.find(text), std::string::npos) << text;
  CliRun bb = run("blackbody --help");
  EXPECT_EQ(bb.exitCode, 0);
  for (const char* flag : {"--out", "--min", "--max", "--size", "--normalize", "--quiet"})
    EXPECT_NE(bb.out.find(flag), std::string::npos) << flag;
  CliRun detail = run("detail --help");
  EXPECT_EQ(detail.exitCode, 0);
  for (const char* flag : {"--out", "--size", "--frames", "--seed", "--octaves", "--frequency", "--contrast", "--from",
                           "--loop-frames", "--quiet"})
    EXPECT_NE(detail.out.find(flag), std::string::npos) << flag;
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
  auto desc = puff::core::loadAtlasDesc(dir_ / "out" / "puff.json");
  ASSERT_TRUE(desc.ok()) << desc.error().message;
  // Maps are named by their content: NAME_MAP[.mipN].HASH.png, HASH 12 hex digits.
  const std::string nd = desc->maps.at("normalDepth").levels.at(0), mip = desc->maps.at("color").levels.at(1);
  EXPECT_EQ(nd.rfind("puff_normal_depth.", 0), 0u) << nd;
  EXPECT_EQ(nd.size(), std::string("puff_normal_depth.").size() + 12 + 4) << nd;
  EXPECT_EQ(mip.rfind("puff_color.mip1.", 0), 0u) << mip;
  EXPECT_TRUE(fs::exists(dir_ / "out" / nd));
  EXPECT_TRUE(fs::exists(dir_ / "out" / mip));
  // Baked again without a contact sheet: the old atlas's sheet goes with the old atlas.
  ASSERT_EQ(run("bake -q -g sphere -n 1 -s 32 --no-contact-sheet -o " + (dir_ / "out").string()).exitCode, 0);
  EXPECT_FALSE(fs::exists(dir_ / "out" / "puff_contact.png"));
  EXPECT_FALSE(fs::exists(dir_ / "out" / nd));
}

// Contact sheets a person can read: the columns are titled and the rows named; a
// multi-view atlas gets a sheet per variation with its views as a grid, each numbered, whose front
// view is the main sheet's preview; a later bake with fewer views or variations takes the extra
// sheets away.
TEST_F(PuffbakeCli, ContactSheetsAreLabelledAndMultiViewAtlasesGetAGridPerVariation) {
  const fs::path out = dir_ / "views";
  CliRun r = run("bake -g lumpy -n 2 --subdivisions 3 -s 32 --views 3 --view-layout oct -o " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(
      r.out.find("views of each variation: " + (out / "puff_contact_v0.png").string() + " .. puff_contact_v1.png"),
      std::string::npos)
      << r.out;
  auto sheet = puff::core::readImage(out / "puff_contact.png");
  ASSERT_OK(sheet);
  // Layout: a 4-pixel gap, a margin as wide as "V1", columns as wide as "DISTANCE" (47 px) plus two
  // gaps; a title row 15 px high, then a row of 32-px thumbnails per variation.
  const int margin = 4 + puff::core::textWidth("V1"), pitch = puff::core::textWidth("DISTANCE") + 8;
  EXPECT_EQ(sheet->width, margin + 4 + 6 * pitch);
  EXPECT_EQ(sheet->height, 15 + 2 * (32 + 4));
  const char* titles[] = {"PREVIEW", "NORMALS", "DEPTH", "COLOUR", "COVERAGE", "DISTANCE"};
  for (int c = 0; c < 6; ++c) {
    EXPECT_EQ(puff::test::readText(*sheet, margin + 4 + c * pitch, 4, static_cast<int>(std::strlen(titles[c]))),
              titles[c]);
  }
  for (int v = 0; v < 2; ++v) {
    EXPECT_EQ(puff::test::readText(*sheet, 2, 15 + v * 36 + (32 - 7) / 2, 2), "V" + std::to_string(v))
        << "numbered from 0, as a scene's variations";
  }
  for (int v = 0; v < 2; ++v) {
    auto views = puff::core::readImage(out / ("puff_contact_v" + std::to_string(v) + ".png"));
    ASSERT_OK(views);
    EXPECT_EQ(puff::test::readText(*views, 4, 4, 12), "VARIATION " + std::to_string(v) + ":");
    // A 3 x 3 grid of 32-px thumbnails, each with its number under it.
    const int pitchX = 32 + 4, pitchY = 32 + 11 + 4;
    for (int view = 0; view < 9; ++view) {
      const int ox = 4 + (view % 3) * pitchX, oy = 15 + (view / 3) * pitchY;
      EXPECT_EQ(puff::test::readGlyph(*views, ox, oy + 32 + 2), static_cast<char>('0' + view)) << "view " << view;
    }
    // View 4, the centre of the oct grid, looks from +z: it is the main sheet's preview of this variation.
    int differ = 0;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x)
        for (int c = 0; c < 3; ++c)
          differ += views->at(4 + pitchX + x, 15 + pitchY + y, c) != sheet->at(margin + 4 + x, 15 + v * 36 + y, c);
    EXPECT_EQ(differ, 0) << "variation " << v;
  }
  // Fewer variations, then one view: the sheets of what is gone go with it.
  ASSERT_EQ(run("bake -q -g lumpy -n 1 --subdivisions 3 -s 32 --views 3 -o " + out.string()).exitCode, 0);
  EXPECT_TRUE(fs::exists(out / "puff_contact_v0.png"));
  EXPECT_FALSE(fs::exists(out / "puff_contact_v1.png"));
  ASSERT_EQ(run("bake -q -g lumpy -n 1 --subdivisions 3 -s 32 -o " + out.string()).exitCode, 0);
  EXPECT_FALSE(fs::exists(out / "puff_contact_v0.png"));
  EXPECT_TRUE(fs::exists(out / "puff_contact.png"));
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
  expectOneLineError(run("bake " + dir_.path().string() + " -o " + out.string()), ": cannot open");  // a directory
  EXPECT_FALSE(fs::exists(out));
}

// A mesh with a non-manifold vertex or edges bakes (the baker rasterizes triangles), and
// A flat mesh bakes, with a warning that it is a card and not a puff; a round one says nothing.
TEST_F(PuffbakeCli, AFlatMeshBakesWithAWarning) {
  const fs::path card = dir_ / "card.obj";
  std::ofstream(card) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  CliRun r = run("bake " + card.string() + " -s 32 --no-contact-sheet -o " + (dir_ / "out").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + card.string() + " is flat (it encloses 0% of its bounding sphere)"),
            std::string::npos)
      << r.err;
  r = run("bake " + (fs::path(PUFF_SOURCE_DIR) / "art" / "puffs" / "variation-1.obj").string() +
          " -s 32 --no-contact-sheet -o " + (dir_ / "round").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
}

// puffbake says how many faces it split.
TEST_F(PuffbakeCli, NonManifoldMeshesBakeAndTheSplitIsReported) {
  const fs::path bowtie = write("bowtie.obj",
                                "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv -1 0 0\nv 0 -1 0\nv 0 0 -1\n"
                                "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 5 6\nf 1 7 5\nf 1 6 7\nf 5 7 6\n");
  const fs::path fin = write("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  CliRun r = run("bake " + bowtie.string() + " " + fin.string() + " -s 64 -o " + (dir_ / "out").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("puffbake: " + bowtie.string() + ": 3 non-manifold faces split onto their own vertices\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("puffbake: " + fin.string() + ": 1 non-manifold face split onto their own vertices\n"),
            std::string::npos)
      << r.out;
  auto desc = puff::core::loadAtlasDesc(dir_ / "out" / "puff.json");
  ASSERT_TRUE(desc.ok()) << desc.error().message;
  EXPECT_EQ(desc->sources[0].faces, 8u);
  EXPECT_EQ(desc->sources[1].faces, 3u);
}

TEST_F(PuffbakeCli, UnwritableOutputFailsAndExistingOutputsSurvive) {
  // A file where the output directory should be.
  const fs::path notDir = write("file", "x");
  expectOneLineError(run("bake -g sphere -n 1 -s 16 -o " + notDir.string()), "not a directory");
  // A directory no one may write, root included (CI runs as root, which ignores permissions): no
  // file can be made in /proc. Then one the permissions lock, where they hold.
  expectOneLineError(run("bake -g sphere -n 1 -s 16 -o /proc"), "/proc: cannot write");
  const fs::path locked = dir_ / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  if (::access(locked.c_str(), W_OK) != 0) {  // not root
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

// --lod auto keeps what it chose: the mesh beside the atlas, named in the sidecar, with the face
// count the report prints.
TEST_F(PuffbakeCli, LodAutoWritesTheMeshItReports) {
  const fs::path out = dir_ / "lod";
  CliRun r = run("bake -g lumpy -n 1 --subdivisions 4 -s 32 --lod auto --no-contact-sheet -o " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto lodDesc = puff::core::loadAtlasDesc(out / "puff.json");
  ASSERT_TRUE(lodDesc.ok()) << lodDesc.error().message;
  const fs::path lod = out / lodDesc->sources[0].lodMesh;
  EXPECT_EQ(lodDesc->sources[0].lodMesh.rfind("puff_lod0.", 0), 0u) << lodDesc->sources[0].lodMesh;
  const std::string reported = "puffbake: lod: variation 0: 5120 -> ";
  const std::size_t at = r.out.find(reported);
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::size_t faces = std::stoul(r.out.substr(at + reported.size()));
  EXPECT_NE(r.out.find("trials): " + lod.string() + "\n"), std::string::npos) << r.out;
  auto m = puff::mesh::loadMesh(lod, nullptr, puff::mesh::Normalize::kNo);
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->faceCount(), faces);
  EXPECT_LT(faces, 5120u);
  auto desc = puff::core::loadAtlasDesc(out / "puff.json");
  ASSERT_TRUE(desc.ok()) << desc.error().message;
  EXPECT_EQ(desc->sources[0].lodMesh, lod.filename().string());
  EXPECT_EQ(desc->sources[0].facesBaked, faces);
  // Without --lod auto: no mesh, no field.
  CliRun full = run("bake -g lumpy -n 1 --subdivisions 4 -s 32 --no-contact-sheet -o " + (dir_ / "full").string());
  ASSERT_EQ(full.exitCode, 0) << full.err;
  for (const auto& e : fs::directory_iterator(dir_ / "full"))
    EXPECT_EQ(e.path().filename().string().find("_lod"), std::string::npos) << e.path();
  EXPECT_EQ(puff::core::readFileBytes(dir_ / "full" / "puff.json")->find("lodMesh"), std::string::npos);
}

TEST_F(PuffbakeCli, MeshCommandWritesAGeneratedPuffThatBakes) {
  const fs::path mesh = dir_ / "cluster.ply";
  CliRun r = run("mesh -g cluster --count 4 --seed 3 -o " + mesh.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  ASSERT_TRUE(fs::exists(mesh));
  CliRun b = run("bake " + mesh.string() + " -s 32 -o " + (dir_ / "out").string());
  EXPECT_EQ(b.exitCode, 0) << b.err;
}

// The sidecar's readers (the cel reference, the fixed path) look for a relative source mesh beside
// the sidecar: a mesh named relative to the working directory must be found from there, and an
// absolute one stays as typed.
TEST_F(PuffbakeCli, ASourceMeshIsFoundFromTheSidecarHoweverItWasNamed) {
  fs::create_directories(dir_ / "meshes");
  ASSERT_EQ(run("mesh -g cluster --count 4 --seed 3 -o " + (dir_ / "meshes" / "cluster.ply").string()).exitCode, 0);
  const fs::path cwd = fs::current_path();
  fs::current_path(dir_.path());  // the child inherits it
  CliRun r = run("bake meshes/cluster.ply -s 32 -o out/relative");
  fs::current_path(cwd);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto desc = puff::core::loadAtlasDesc(dir_ / "out" / "relative" / "puff.json");
  ASSERT_OK(desc);
  ASSERT_EQ(desc->sources.size(), 1u);
  EXPECT_EQ(desc->sources[0].path, "../../meshes/cluster.ply");
  EXPECT_TRUE(fs::equivalent(dir_ / "out" / "relative" / desc->sources[0].path, dir_ / "meshes" / "cluster.ply"));

  const fs::path absolute = fs::absolute(dir_ / "meshes" / "cluster.ply");
  ASSERT_EQ(run("bake " + absolute.string() + " -s 32 -o " + (dir_ / "out" / "absolute").string()).exitCode, 0);
  desc = puff::core::loadAtlasDesc(dir_ / "out" / "absolute" / "puff.json");
  ASSERT_OK(desc);
  EXPECT_EQ(desc->sources[0].path, absolute.string());
}

// ---- blackbody ----------------------------------------------------------------------------------

TEST_F(PuffbakeCli, BlackbodyWritesTheRampWithItsRange) {
  const fs::path out = dir_ / "media" / "blackbody.exr";
  CliRun r = run("blackbody --min 1500 --max 9000 --size 64 --normalize 3000 -o " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.out, "puffbake: wrote " + out.string() +
                       ": black-body ramp 1500..9000 K in 64 texels (linear sRGB, luminance 1 at 3000 K)\n");
  auto ramp = puff::core::readBlackbodyRamp(out);
  ASSERT_OK(ramp);
  EXPECT_EQ(ramp->minKelvin, 1500.0);
  EXPECT_EQ(ramp->maxKelvin, 9000.0);
  EXPECT_EQ(ramp->normalizeKelvin, 3000.0);
  EXPECT_EQ(ramp->rgb.size(), 64u);
  // The defaults, quietly.
  CliRun q = run("blackbody -q -o " + (dir_ / "default.exr").string());
  ASSERT_EQ(q.exitCode, 0) << q.err;
  EXPECT_TRUE(q.out.empty()) << q.out;
  auto d = puff::core::readBlackbodyRamp(dir_ / "default.exr");
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->minKelvin, 1000.0);
  EXPECT_EQ(d->maxKelvin, 10000.0);
  EXPECT_EQ(d->normalizeKelvin, 3200.0);
  EXPECT_EQ(d->rgb.size(), 1024u);
}

TEST_F(PuffbakeCli, BlackbodyBadUsageExitsTwoAndWritesNothing) {
  const std::string o = " -o " + (dir_ / "bb.exr").string();
  expectOneLineError(run("blackbody --min 0" + o), "--min must be in (0, 100000) kelvin, got 0", 2);
  expectOneLineError(run("blackbody --min 5000 --max 4000" + o), "--max must be above --min (5000)", 2);
  expectOneLineError(run("blackbody --max 200000" + o), "--max", 2);
  expectOneLineError(run("blackbody --size 1" + o), "--size must be in [2, 65536], got 1", 2);
  expectOneLineError(run("blackbody --normalize -3" + o), "--normalize must be in (0, 100000] kelvin", 2);
  expectOneLineError(run("blackbody --normalize 10" + o), "no visible light", 2);
  expectOneLineError(run("blackbody -o " + (dir_ / "bb.png").string()), "must end in .exr", 2);
  EXPECT_EQ(run("blackbody --min warm" + o).exitCode, 2);
  EXPECT_EQ(run("blackbody").exitCode, 2);  // -o is required
  EXPECT_TRUE(fs::is_empty(dir_.path()));
}

TEST_F(PuffbakeCli, BlackbodyUnwritableOutputFailsAndExistingOutputSurvives) {
  const fs::path notDir = write("file", "x");
  expectOneLineError(run("blackbody -o " + (notDir / "bb.exr").string()), "file: not a directory");
  const fs::path locked = dir_ / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  expectOneLineError(run("blackbody -o /proc/bb.exr"), "/proc: cannot write");  // root too (see above)
  if (::access(locked.c_str(), W_OK) != 0) {                                    // not root
    expectOneLineError(run("blackbody -o " + (locked / "bb.exr").string()), "cannot write");
    EXPECT_TRUE(fs::is_empty(locked));
  }
  const fs::path out = dir_ / "bb.exr";
  ASSERT_EQ(run("blackbody -q --size 16 -o " + out.string()).exitCode, 0);
  const std::string before = *puff::core::readFileBytes(out);
  EXPECT_EQ(run("blackbody --size 16 --normalize 10 -o " + out.string()).exitCode, 2);
  // A directory where the file should go cannot be replaced: the run fails and leaves no temporary.
  fs::create_directories(dir_ / "taken.exr");
  expectOneLineError(run("blackbody --size 16 -o " + (dir_ / "taken.exr").string()), "is a directory");
  EXPECT_EQ(*puff::core::readFileBytes(out), before);
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir_.path())) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"bb.exr", "file", "locked", "taken.exr"}));
}

// ---- detail -------------------------------------------------------------------------------------

TEST_F(PuffbakeCli, DetailGeneratesAVideoWithItsMetadataAndTheSameBytesEachRun) {
  for (const char* name : {"fire.png", "smoke.exr"}) {
    SCOPED_TRACE(name);
    const fs::path out = dir_ / "media" / name;
    CliRun r = run("detail --size 32 --frames 8 --seed 3 --frequency 2 -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.out, "puffbake: wrote " + out.string() + ": detail video 32x32, 8 frames (generated, seed 3)\n");
    auto v = puff::core::loadDetailVideo(out);
    ASSERT_OK(v);
    EXPECT_EQ(v->width, 32);
    EXPECT_EQ(v->height, 32);
    EXPECT_EQ(v->frames, 8);
    EXPECT_EQ(*puff::core::readImageAttribute(out, "puff:frames"), "8");
    EXPECT_NE(v->source.find("seed 3"), std::string::npos) << v->source;
  }
  // Same flags, same bytes, even a second later (no timestamps in the files).
  const std::string first = *puff::core::readFileBytes(dir_ / "media" / "fire.png");
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  ASSERT_EQ(run("detail -q --size 32 --frames 8 --seed 3 --frequency 2 -o " + (dir_ / "again.png").string()).exitCode,
            0);
  EXPECT_TRUE(*puff::core::readFileBytes(dir_ / "again.png") == first);
}

TEST_F(PuffbakeCli, DetailImportsFramesAndMakesThemLoop) {
  std::string from;
  for (int k = 0; k < 6; ++k) {
    const fs::path p = dir_ / "clip" / ("f" + std::to_string(k) + ".exr");
    fs::create_directories(p.parent_path());
    ASSERT_TRUE(puff::core::writeImage(p, puff::core::Image(8, 6, 3, k / 10.0f), puff::core::PixelType::kFloat).ok());
    from += " " + p.string();
  }
  const fs::path out = dir_ / "clip.png";
  CliRun r = run("detail --size 4 --loop-frames 2 -o " + out.string() + " --from" + from);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("detail video 4x4, 4 frames (imported from 6 files, last 2 cross-faded into the first)"),
            std::string::npos)
      << r.out;
  auto v = puff::core::loadDetailVideo(out);
  ASSERT_OK(v);
  ASSERT_EQ(v->frames, 4);
  // out[0] = 2/3 in[4] + 1/3 in[0] (core/detail.h), within 16-bit rounding.
  EXPECT_NEAR(v->at(2, 2, 0), 2.0f / 3.0f * 0.4f, 1e-5f);
  EXPECT_NEAR(v->at(2, 2, 3), 0.3f, 1e-5f);
}

TEST_F(PuffbakeCli, DetailBadUsageExitsTwoAndWritesNothing) {
  const std::string o = " -o " + (dir_ / "d.png").string();
  expectOneLineError(run("detail --size 2" + o), "--size must be in [4, 4096], got 2", 2);
  expectOneLineError(run("detail --frames 0" + o), "--frames must be in [1, 1024], got 0", 2);
  expectOneLineError(run("detail --octaves 11" + o), "--octaves must be in [1, 10], got 11", 2);
  expectOneLineError(run("detail --frequency 0" + o), "--frequency", 2);
  expectOneLineError(run("detail --contrast 20" + o), "--contrast", 2);
  expectOneLineError(run("detail --size 4096 --frames 8" + o), "too large", 2);
  expectOneLineError(run("detail -o " + (dir_ / "d.jpg").string()), "must end in .png (16-bit) or .exr", 2);
  const std::string a = write("a.png", "x").string(), b = write("b.png", "x").string();
  expectOneLineError(run("detail --loop-frames 2" + o + " --from " + a + " " + b), "--loop-frames must be in [0, 1]",
                     2);
  EXPECT_EQ(run("detail --seed 4" + o + " --from " + a).exitCode, 2);  // generator flags exclude --from
  EXPECT_EQ(run("detail --loop-frames 1" + o).exitCode, 2);            // --loop-frames needs --from
  EXPECT_EQ(run("detail").exitCode, 2);                                // -o is required
  EXPECT_FALSE(fs::exists(dir_ / "d.png"));
  EXPECT_FALSE(fs::exists(dir_ / "d.jpg"));
}

TEST_F(PuffbakeCli, DetailBadFramesFailNamingTheFileAndExistingOutputSurvives) {
  const fs::path out = dir_ / "detail.png";
  ASSERT_EQ(run("detail -q --size 8 --frames 2 -o " + out.string()).exitCode, 0);
  const std::string before = *puff::core::readFileBytes(out);
  const fs::path good = dir_ / "good.exr", wide = dir_ / "wide.exr";
  ASSERT_TRUE(puff::core::writeImage(good, puff::core::Image(8, 8, 1, 0.5f), puff::core::PixelType::kFloat).ok());
  ASSERT_TRUE(puff::core::writeImage(wide, puff::core::Image(16, 8, 1, 0.5f), puff::core::PixelType::kFloat).ok());
  const fs::path garbage = write("garbage.png", "this is not a png");
  const std::string o = " --loop-frames 0 -o " + out.string() + " --from " + good.string() + " ";
  expectOneLineError(run("detail" + o + (dir_ / "missing.png").string()), "missing.png: cannot open: no such file");
  expectOneLineError(run("detail" + o + garbage.string()), "garbage.png: not a readable image");
  expectOneLineError(run("detail" + o + wide.string()),
                     "wide.exr: frame is 16x8, but good.exr (the first frame) is 8x8");
  EXPECT_EQ(*puff::core::readFileBytes(out), before);
  // Unwritable places.
  const fs::path notDir = write("file", "x");
  expectOneLineError(run("detail --size 8 --frames 2 -o " + (notDir / "d.png").string()), "file: not a directory");
  const fs::path locked = dir_ / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  expectOneLineError(run("detail --size 8 --frames 2 -o /proc/d.png"), "/proc: cannot write");  // root too
  if (::access(locked.c_str(), W_OK) != 0) {                                                    // not root
    expectOneLineError(run("detail --size 8 --frames 2 -o " + (locked / "d.png").string()), "cannot write");
    EXPECT_TRUE(fs::is_empty(locked));
  }
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir_.path())) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"detail.png", "file", "garbage.png", "good.exr", "locked", "wide.exr"}));
}

}  // namespace

// `puffbake cook` as a game team uses it: an atlas and a detail video cooked, their files named in
// the sidecar and loaded back; bad usage exits 2, a bad input 1, and neither writes anything.
TEST_F(PuffbakeCli, CookWritesWhatAGameLoadsAndRefusesWhatItCannot) {
  ASSERT_EQ(run("bake -q -g sphere -n 1 -s 32 --no-contact-sheet -o " + (dir_ / "baked").string()).exitCode, 0);
  const fs::path out = dir_ / "game" / "smoke.json";
  CliRun r = run("cook " + (dir_ / "baked" / "puff.json").string() + " -o " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto desc = puff::core::loadAtlasDesc(out);
  ASSERT_TRUE(desc.ok()) << desc.error().message;
  ASSERT_GT(desc->mipLevels, 1);
  const std::string files = std::to_string(3 * desc->mipLevels + 1) + " files";  // the maps' levels, the sidecar
  EXPECT_NE(r.out.find("puffbake: wrote " + out.string() + ": atlas cooked into " + files), std::string::npos) << r.out;
  EXPECT_EQ(desc->maps.at("color").levels.at(0).rfind("smoke_color.", 0), 0u);
  EXPECT_EQ(desc->maps.at("normalDepth").levels.at(1).rfind("smoke_normal_depth.mip1.", 0), 0u);
  EXPECT_EQ(fs::path(desc->maps.at("color").levels.at(0)).extension(), ".puffimg");
  for (const auto& [name, map] : desc->maps) {
    for (const std::string& level : map.levels) EXPECT_TRUE(fs::exists(dir_ / "game" / level)) << level;
  }
  EXPECT_TRUE(puff::core::loadAtlas(out).ok());
  ASSERT_EQ(run("detail -q --size 8 --frames 2 -o " + (dir_ / "fire.png").string()).exitCode, 0);
  ASSERT_EQ(run("cook -q " + (dir_ / "fire.png").string() + " -o " + (dir_ / "fire.puffimg").string()).exitCode, 0);
  auto video = puff::core::loadDetailVideo(dir_ / "fire.puffimg");
  ASSERT_TRUE(video.ok()) << video.error().message;
  EXPECT_EQ(video->frames, 2);

  expectOneLineError(run("cook " + (dir_ / "baked" / "puff.json").string() + " -o " + (dir_ / "c.png").string()),
                     "an atlas cooks into a sidecar, so -o must end in .json", 2);
  expectOneLineError(run("cook " + (dir_ / "fire.png").string() + " -o " + (dir_ / "c.png").string()),
                     "an image cooks into a .puffimg file", 2);
  EXPECT_EQ(run("cook " + (dir_ / "fire.png").string()).exitCode, 2);  // -o is required
  expectOneLineError(run("cook " + (dir_ / "none.json").string() + " -o " + (dir_ / "c" / "c.json").string()),
                     "none.json: cannot read: No such file or directory");
  expectOneLineError(run("cook " + write("junk.png", "junk").string() + " -o " + (dir_ / "c" / "c.puffimg").string()),
                     "junk.png: not a readable image");
  // A truncated PNG: libpng's own "libpng error: ..." line is not printed, Puff's one line is.
  puff::core::Image noise(96, 96, 4);
  std::uint32_t state = 2463534242u;  // xorshift32: values that do not compress
  for (float& v : noise.pixels) {
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    v = static_cast<float>(state & 255u) / 255.0f;
  }
  ASSERT_TRUE(puff::core::writeImage(dir_ / "noise.png", noise, puff::core::PixelType::kUInt8).ok());
  const std::string png = *puff::core::readFileBytes(dir_ / "noise.png");
  ASSERT_GT(png.size(), 4000u);
  const fs::path truncated = write("truncated.png", png.substr(0, png.size() / 2));
  expectOneLineError(run("cook " + truncated.string() + " -o " + (dir_ / "c" / "t.puffimg").string()),
                     "truncated.png: corrupt or truncated image");
  expectOneLineError(
      run("cook " + write("header.png", png.substr(0, 40)).string() + " -o " + (dir_ / "c" / "h.puffimg").string()),
      "header.png: not a readable image");
  EXPECT_FALSE(fs::exists(dir_ / "c"));
  EXPECT_FALSE(fs::exists(dir_ / "c.png"));
  // The cooked sidecar is never replaced by a failed cook.
  const std::string before = *puff::core::readFileBytes(out);
  const std::string mip1 = puff::core::loadAtlasDesc(dir_ / "baked" / "puff.json")->maps.at("color").levels.at(1);
  fs::remove(dir_ / "baked" / mip1);
  expectOneLineError(run("cook " + (dir_ / "baked" / "puff.json").string() + " -o " + out.string()),
                     mip1 + ": cannot open: no such file");
  EXPECT_EQ(*puff::core::readFileBytes(out), before);
}
