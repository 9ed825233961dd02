// puffbake reads glTF 2.0 as an artist exports it from Blender: a lumpy puff written as a .glb the
// way Blender's glTF exporter lays one out bakes to the same atlas, map for map and byte for byte,
// as the same puff written as OBJ.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include <puff/core/files.h>
#include <puff/mesh/mesh.h>

#include "support/assert_ok.h"
#include "support/cli_test.h"
#include "support/gltf_writer.h"

namespace {

namespace fs = std::filesystem;
using puff::test::CliRun;

class PuffbakeGltf : public puff::test::CliTest {
 protected:
  PuffbakeGltf() : CliTest(PUFFBAKE_EXE, "puffbake") {}
};

// `m` as Blender's exporter writes a smooth-shaded mesh with a UV map: one glTF vertex per distinct
// (vertex, normal, UV) in the order the faces' corners first use them, so vertices on the UV seam
// (here a spherical map's, where u wraps from 1 to 0) are written twice; POSITION with its min and
// max, NORMAL, TEXCOORD_0 and 16-bit indices, each in its own bufferView with its target; one
// material; a node named after the object; the asset's generator. The object sits at the origin
// unrotated, as an artist applies transforms before export.
puff::test::GltfWriter blenderStyle(const puff::mesh::TriMesh& m, bool withNormals) {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs;
  std::vector<std::uint16_t> indices;
  std::map<std::pair<std::uint32_t, bool>, std::uint16_t> written;  // (vertex, past the seam) -> glTF vertex
  auto u = [](glm::vec3 p) { return 0.5f + std::atan2(p.z, p.x) / glm::two_pi<float>(); };
  for (const glm::uvec3& t : m.triangles) {
    float us[3];
    for (int k = 0; k < 3; ++k) us[k] = u(m.positions[t[k]]);
    const bool acrossSeam = std::max({us[0], us[1], us[2]}) - std::min({us[0], us[1], us[2]}) > 0.5f;
    for (int k = 0; k < 3; ++k) {
      const bool wrapped = acrossSeam && us[k] < 0.5f;
      const auto [it, added] = written.try_emplace({t[k], wrapped}, static_cast<std::uint16_t>(positions.size()));
      if (added) {
        const glm::vec3 p = m.positions[t[k]];
        positions.push_back(p);
        normals.push_back(m.normals[t[k]]);
        uvs.emplace_back(us[k] + (wrapped ? 1.0f : 0.0f),
                         0.5f + std::asin(std::clamp(p.y, -1.0f, 1.0f)) / glm::pi<float>());
      }
      indices.push_back(it->second);
    }
  }
  puff::test::GltfWriter w;
  auto& doc = w.doc();
  doc["asset"] = {{"generator", "Khronos glTF Blender I/O v3.6.27"}, {"version", "2.0"}};
  const int pos = w.vec3s(positions), uv = w.vec2s(uvs), idx = w.indices16(indices);
  const int nor = withNormals ? w.vec3s(normals) : uv;
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& p : positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  doc["accessors"][pos]["min"] = {lo.x, lo.y, lo.z};
  doc["accessors"][pos]["max"] = {hi.x, hi.y, hi.z};
  for (int view : {pos, nor, uv}) doc["bufferViews"][view]["target"] = 34962;
  doc["bufferViews"][idx]["target"] = 34963;
  doc["materials"] = {{{"name", "Smoke"}, {"doubleSided", false}, {"pbrMetallicRoughness", {{"metallicFactor", 0}}}}};
  nlohmann::json attributes = {{"POSITION", pos}, {"TEXCOORD_0", uv}};
  if (withNormals) attributes["NORMAL"] = nor;
  const int mesh = w.mesh({{"attributes", attributes}, {"indices", idx}, {"material", 0}});
  doc["meshes"][mesh]["name"] = "Icosphere";
  doc["scenes"][0]["name"] = "Scene";
  w.node({{"mesh", mesh}, {"name", "Puff"}});
  return w;
}

// The atlas's sidecar, and each map file it names with its bytes.
std::map<std::string, std::string> atlasFiles(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    auto bytes = puff::core::readFileBytes(e.path());
    files[e.path().filename().string()] = bytes ? *bytes : std::string("(unreadable)");
  }
  return files;
}

TEST_F(PuffbakeGltf, ABlenderStyleGlbBakesToTheSameAtlasAsItsObj) {
  // The art's first lumpy puff with its smooth normals, as an artist's OBJ (with "vn") and .glb,
  // and without normals (then loading computes them, and the seam's split vertices must be one
  // vertex again for them to come out the same).
  auto source = puff::mesh::loadMesh(fs::path(PUFF_SOURCE_DIR) / "art" / "puffs" / "variation-1.obj", nullptr,
                                     puff::mesh::Normalize::kNo);
  ASSERT_OK(source);
  ASSERT_OK(puff::mesh::saveMesh(*source, dir_ / "lumpy.obj", puff::mesh::SaveNormals::kYes));
  ASSERT_OK(puff::mesh::saveMesh(*source, dir_ / "bare.obj", puff::mesh::SaveNormals::kNo));
  const puff::test::GltfWriter glb = blenderStyle(*source, true);
  glb.writeGlb(dir_ / "lumpy.glb");
  glb.writeGltf(dir_ / "lumpy.gltf", "lumpy.bin");
  blenderStyle(*source, false).writeGlb(dir_ / "bare.glb");
  const std::size_t written = glb.doc()["accessors"][0]["count"].get<std::size_t>();
  ASSERT_GT(written, source->positions.size()) << "the seam split some vertices, as Blender's export does";

  std::map<std::string, std::string> baked[5];
  const char* inputs[5] = {"lumpy.obj", "lumpy.glb", "lumpy.gltf", "bare.obj", "bare.glb"};
  for (int i = 0; i < 5; ++i) {
    const fs::path out = dir_ / ("out" + std::to_string(i));
    const CliRun r = run("bake -q -s 64 --no-contact-sheet " + (dir_ / inputs[i]).string() + " -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << inputs[i] << ": " << r.err;
    baked[i] = atlasFiles(out);
  }
  // Maps are named by their content: the same names are the same maps; the bytes say so too.
  ASSERT_GT(baked[0].size(), 4u);
  for (int i : {1, 2, 4}) {
    SCOPED_TRACE(inputs[i]);
    const auto& obj = baked[i == 4 ? 3 : 0];
    ASSERT_EQ(baked[i].size(), obj.size());
    for (const auto& [name, bytes] : obj) {
      if (name == "puff.json") continue;  // names its source mesh
      ASSERT_TRUE(baked[i].count(name)) << name << " is not in the glTF's atlas";
      EXPECT_TRUE(baked[i].at(name) == bytes) << name << " differs";
    }
  }
  EXPECT_NE(baked[0], baked[3]) << "(the normals the file gives and those loading computes differ)";
}

TEST_F(PuffbakeGltf, ABadGlbIsOneLineNamingTheFile) {
  puff::test::GltfWriter w;
  const int pos = w.vec3s({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  w.node({{"mesh", w.mesh({{"attributes", {{"POSITION", pos}}}})}});
  w.doc()["accessors"][0]["count"] = 4;
  w.writeGlb(dir_ / "bad.glb");
  const fs::path out = dir_ / "out";
  expectOneLineError(run("bake " + (dir_ / "bad.glb").string() + " -o " + out.string()),
                     "bad.glb: not a valid glTF file (accessor 0: 4 elements run past bufferView 0's 36 bytes)");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
