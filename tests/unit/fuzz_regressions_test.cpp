// Every input a fuzz harness ever crashed on (tests/fuzz/regressions/HARNESS/) is read
// again here, in the ordinary build, by the same reader the harness calls: each gives a result or
// one line that names the file, and the known ones give exactly their message. tests/fuzz/run.sh
// replays the same files under libFuzzer and the sanitizers.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>

#include <puff/cel/frame.h>
#include <puff/core/atlas.h>
#include <puff/core/detail_video.h>
#include <puff/core/files.h>
#include <puff/mesh/mesh.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;

const fs::path kRegressions = fs::path(PUFF_SOURCE_DIR) / "tests" / "fuzz" / "regressions";

// The error of reading `input` as harness `harness` reads it ("" when it reads), checked to be one
// line naming the file it was written to.
std::string readAsHarness(const std::string& harness, const fs::path& input, const fs::path& dir) {
  const std::string bytes = *puff::core::readFileBytes(input);
  fs::path file;
  auto message = [&](const auto& result) -> std::string {
    if (result.ok()) return "";
    const std::string& m = result.error().message;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_EQ(m.rfind(file.string() + ": ", 0), 0u) << m;
    return m.substr(file.string().size() + 2);
  };
  if (harness == "scene") {
    file = dir / "scene.json";
    EXPECT_OK(puff::core::writeFileBytes(file, bytes));
    return message(puff::scene::loadScene(file));
  }
  if (harness.rfind("mesh_", 0) == 0) {
    file = dir / ("mesh." + harness.substr(5));
    EXPECT_OK(puff::core::writeFileBytes(file, bytes));
    return message(puff::mesh::loadMesh(file));
  }
  if (harness == "image_ramp" || harness == "image_gradient" || harness == "image_detail") {
    // fuzz_common.h: the first byte picks the extension.
    static const char* kExt[] = {".png", ".exr", ".puffimg"};
    if (bytes.empty()) return "";
    file = dir / (std::string("image") + kExt[static_cast<unsigned char>(bytes[0]) % 3]);
    EXPECT_OK(puff::core::writeFileBytes(file, bytes.substr(1)));
    if (harness == "image_ramp") return message(puff::cel::Ramp::read(file));
    if (harness == "image_gradient") return message(puff::cel::Gradient::read(file));
    return message(puff::core::loadDetailVideo(file));
  }
  ADD_FAILURE() << "no reader for harness " << harness << " (add it here)";
  return "";
}

TEST(FuzzRegressions, EveryInputThatOnceCrashedIsReadOrRefusedInOneLine) {
  // What each known input gives now (its file name under tests/fuzz/regressions/HARNESS/).
  const std::map<std::string, std::string> expected = {
      // A key with a newline was echoed into the message, which then spanned two lines.
      {"key-with-newline.json",
       "/a\\nimation: unknown key, expected one of output, camera, light, ambient, ramp, atlas, atlasLevel, "
       "particleFraction, style, particles, emitters, objects, rigidBodies, animation, simulation, fixed, media (did "
       "you mean "
       "\"animation\"?)"},
      // OpenMesh's OBJ reader writes the normal of "f ... -17/1/1" (no such vertex) out of bounds.
      {"normal-of-missing-vertex.obj",
       "the file declares 6 faces, only 5 could be added: face 0 (line 14) refers to a vertex the file does not have "
       "(it "
       "has 8)"},
      // "x y z+w" on a vertex line: OpenMesh's OFF reader loses its place and never finishes.
      {"openmesh-timeout.off", "not a valid OFF file (line 1196)"},
      // A PLY header with a property line cut in half: OpenMesh's reader segfaults.
      {"openmesh-header-segv.ply", "not a valid PLY file (header line 4)"},
      // A truncated PNG: OpenImageIO leaks its error string (tests/lsan.supp); Puff's error is one line.
      {"oiio-truncated-png-leak.png.in", "*"},
      // An EXR attribute claiming 1.8 GB in a 621-byte file: OpenEXR allocated it, taking seconds.
      // The same with a name holding bytes that are not text: the message shows them as \xNN.
      {"exr-attribute-name-unprintable.exr.in",
       "not a readable image: EXR header attribute 'Exif:ImageHi\\xa5\\xb8\\x0a' claims 1869902592 bytes; the file "
       "has 731 left"},
      // The header walk's edges: one byte more than the file has, a negative size, a multi-part
      // file whose second header claims 1.8 GB, and a valid two-part file, which reads.
      {"exr-attribute-one-byte-over.exr.in",
       "not a readable image: EXR header attribute 'Software' claims 462 bytes; the file has 461 left"},
      {"exr-attribute-negative-size.exr.in",
       "not a readable image: EXR header attribute 'Software' claims -1 bytes; the file has 461 left"},
      {"exr-second-part-claims-2gb.exr.in",
       "not a readable image: EXR header attribute 'Software' claims 1879048192 bytes; the file has 640 left"},
      {"exr-valid-two-parts.exr.in", ""},
      {"exr-attribute-claims-2gb.exr.in",
       "not a readable image: EXR header attribute 'Software' claims 1886216547 bytes; the file has 487 left"},
  };
  std::size_t seen = 0;
  for (const auto& harnessDir : fs::directory_iterator(kRegressions)) {
    for (const auto& input : fs::directory_iterator(harnessDir.path())) {
      SCOPED_TRACE(input.path().string());
      puff::test::ScopedTempDir dir("puff_fuzz_regression");
      const std::string got = readAsHarness(harnessDir.path().filename().string(), input.path(), dir.path());
      const auto known = expected.find(input.path().filename().string());
      ASSERT_NE(known, expected.end()) << "a new regression input: add what it gives to `expected`";
      if (known->second != "*") {
        EXPECT_EQ(got, known->second);
      }
      ++seen;
    }
  }
  EXPECT_EQ(seen, expected.size());
}

}  // namespace
