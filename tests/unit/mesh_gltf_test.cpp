// puff::mesh's glTF 2.0 reader: the same mesh as the other formats whatever the container (.glb,
// .gltf with a .bin, a data: URI), the nodes' transforms applied, strips and fans, vertices split at
// UV seams merged, and every malformed file refused in one line naming the part at fault.
#include <puff/mesh/mesh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "support/assert_ok.h"
#include "support/gltf_writer.h"
#include "support/temp_dir.h"

namespace fs = std::filesystem;
using namespace puff::mesh;
using puff::test::GltfWriter;

namespace {

// A tetrahedron, counter-clockwise from outside.
const std::vector<glm::vec3> kTetra{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const std::vector<std::uint16_t> kTetraFaces{0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};

GltfWriter tetra(const nlohmann::json& node = nlohmann::json::object()) {
  GltfWriter w;
  const int pos = w.vec3s(kTetra), idx = w.indices16(kTetraFaces);
  nlohmann::json n = node;
  n["mesh"] = w.mesh({{"attributes", {{"POSITION", pos}}}, {"indices", idx}});
  w.node(n);
  return w;
}

// Each triangle's corners, in order: the mesh whatever order its vertices are numbered in.
std::vector<std::array<glm::vec3, 3>> corners(const TriMesh& m) {
  std::vector<std::array<glm::vec3, 3>> out;
  for (const glm::uvec3& t : m.triangles) out.push_back({m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]});
  return out;
}

class MeshGltf : public ::testing::Test {
 protected:
  TriMesh load(const fs::path& p, LoadInfo* info = nullptr) {
    auto r = loadMesh(p, info, Normalize::kNo);
    EXPECT_TRUE(r.ok()) << (r.ok() ? std::string() : r.error().message);
    return r.ok() ? *r : TriMesh{};
  }
  void expectError(const GltfWriter& w, const std::string& needle) {
    SCOPED_TRACE(needle);
    const fs::path p = dir_ / "bad.glb";
    w.writeGlb(p);
    const auto r = loadMesh(p);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message.rfind(p.string() + ": not a valid glTF file (", 0), 0u) << r.error().message;
    EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
  }
  puff::test::ScopedTempDir dir_{"puff_gltf_test"};
};

TEST_F(MeshGltf, EveryContainerGivesTheSameTetrahedron) {
  // The same tetrahedron as OBJ (vertices numbered from 1).
  std::ofstream(dir_ / "t.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const TriMesh obj = load(dir_ / "t.obj");
  const GltfWriter w = tetra();
  w.writeGlb(dir_ / "t.glb");
  // A .bin whose name has a space, which the URI percent-encodes.
  w.writeGltf(dir_ / "t.gltf", "t data.bin");
  nlohmann::json doc = w.doc();
  doc["buffers"][0]["uri"] = "t%20data.bin";
  std::ofstream(dir_ / "t.gltf") << doc.dump(2);
  w.writeGltfEmbedded(dir_ / "embedded.gltf");
  for (const char* name : {"t.glb", "t.gltf", "embedded.gltf"}) {
    SCOPED_TRACE(name);
    LoadInfo info;
    const TriMesh m = load(dir_ / name, &info);
    ASSERT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(corners(m), corners(obj));
    EXPECT_FALSE(info.flippedInward);
    EXPECT_FALSE(info.hadNormals);
  }
}

TEST_F(MeshGltf, NodesPlaceTheirMeshesByTheirTransforms) {
  // Parent: translate (1, 2, 3); child: rotate 90 degrees about z, scale 2. A vertex p lands at
  // (1, 2, 3) + Rz(90) * 2p.
  GltfWriter w;
  const int pos = w.vec3s(kTetra), idx = w.indices16(kTetraFaces);
  const int mesh = w.mesh({{"attributes", {{"POSITION", pos}}}, {"indices", idx}});
  const float s = std::sqrt(0.5f);
  const int child = w.node({{"mesh", mesh}, {"rotation", {0, 0, s, s}}, {"scale", {2, 2, 2}}}, false);
  w.node({{"translation", {1, 2, 3}}, {"children", {child}}});
  w.writeGlb(dir_ / "trs.glb");
  const TriMesh m = load(dir_ / "trs.glb");
  ASSERT_EQ(m.triangles.size(), 4u);
  for (std::size_t t = 0; t < 4; ++t)
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = kTetra[kTetraFaces[3 * t + static_cast<std::size_t>(k)]];
      const glm::vec3 expected = glm::vec3(1, 2, 3) + glm::vec3(-2.0f * p.y, 2.0f * p.x, 2.0f * p.z);
      EXPECT_NEAR(glm::distance(m.positions[m.triangles[t][k]], expected), 0.0f, 1e-5f) << t << "," << k;
    }
  // The same as one column-major matrix.
  GltfWriter mw = tetra({{"matrix", {0, 2, 0, 0, -2, 0, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1}}});
  mw.writeGlb(dir_ / "matrix.glb");
  const TriMesh mm = load(dir_ / "matrix.glb");
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(glm::distance(mm.positions[i], m.positions[i]), 0.0f, 1e-5f);
  // A mirroring scale turns the triangles inside out; the reader turns them back, so loading does
  // not have to.
  GltfWriter mirror = tetra({{"scale", {-1, 1, 1}}});
  mirror.writeGlb(dir_ / "mirror.glb");
  LoadInfo info;
  const TriMesh mirrored = load(dir_ / "mirror.glb", &info);
  EXPECT_FALSE(info.flippedInward);
  EXPECT_EQ(mirrored.positions[1], glm::vec3(-1, 0, 0));
  // A mesh two nodes place is there twice.
  GltfWriter twice = tetra();
  twice.node({{"mesh", 0}, {"translation", {5, 0, 0}}});
  twice.writeGlb(dir_ / "twice.glb");
  EXPECT_EQ(load(dir_ / "twice.glb").triangles.size(), 8u);
}

TEST_F(MeshGltf, StripsAndFansAreTriangulatedAsTheSpecificationSays) {
  // A square as a strip (0 1 2 3) and as a fan (0 1 3 2 around vertex 0), both facing +z.
  const std::vector<glm::vec3> square{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  for (const auto& [mode, order] :
       {std::pair{5, std::vector<std::uint16_t>{0, 1, 2, 3}}, std::pair{6, std::vector<std::uint16_t>{0, 1, 3, 2}}}) {
    SCOPED_TRACE(mode);
    GltfWriter w;
    const int pos = w.vec3s(square), idx = w.indices16(order);
    w.node({{"mesh", w.mesh({{"attributes", {{"POSITION", pos}}}, {"indices", idx}, {"mode", mode}})}});
    // Points of the same vertices: no surface, left out.
    const int points = w.vec3s(square);
    w.node({{"mesh", w.mesh({{"attributes", {{"POSITION", points}}}, {"mode", 0}})}});
    w.writeGlb(dir_ / "square.glb");
    const TriMesh m = load(dir_ / "square.glb");
    ASSERT_EQ(m.triangles.size(), 2u);
    for (const glm::uvec3& t : m.triangles) {
      const glm::vec3 n = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
      EXPECT_GT(n.z, 0.0f) << "every triangle faces +z";
    }
  }
}

TEST_F(MeshGltf, VerticesSplitAtUvSeamsAreOneVertexAgainAndNormalsAreKept) {
  // Each tetrahedron face on its own three vertices (as an exporter splits them where UVs differ),
  // all with the same normal per position: four vertices again, the file's normals kept.
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs;
  std::vector<std::uint32_t> order;
  for (std::size_t k = 0; k < kTetraFaces.size(); ++k) {
    const glm::vec3 p = kTetra[kTetraFaces[k]];
    positions.push_back(p);
    normals.push_back(glm::normalize(p - glm::vec3(0.25f)));
    uvs.emplace_back(static_cast<float>(k) / 12.0f, 0.0f);
    order.push_back(static_cast<std::uint32_t>(k));
  }
  GltfWriter w;
  const int pos = w.vec3s(positions), nor = w.vec3s(normals), uv = w.vec2s(uvs), idx = w.indices32(order);
  w.node(
      {{"mesh", w.mesh({{"attributes", {{"POSITION", pos}, {"NORMAL", nor}, {"TEXCOORD_0", uv}}}, {"indices", idx}})}});
  w.writeGlb(dir_ / "seams.glb");
  LoadInfo info;
  const TriMesh m = load(dir_ / "seams.glb", &info);
  EXPECT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.triangles.size(), 4u);
  EXPECT_TRUE(info.hadNormals);
  ASSERT_EQ(m.normals.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(glm::distance(m.normals[i], glm::normalize(m.positions[i] - glm::vec3(0.25f))), 0.0f, 1e-6f);
  }
}

TEST_F(MeshGltf, InterleavedAttributesAreReadByTheirStride) {
  // POSITION and NORMAL interleaved in one bufferView, 24 bytes a vertex, NORMAL at byte 12.
  std::vector<glm::vec3> interleaved;
  for (const glm::vec3& p : kTetra) interleaved.insert(interleaved.end(), {p, glm::normalize(p - glm::vec3(0.25f))});
  GltfWriter w;
  const int both = w.vec3s(interleaved), idx = w.indices16(kTetraFaces);
  auto& doc = w.doc();
  doc["bufferViews"][0]["byteStride"] = 24;
  doc["accessors"][both]["count"] = 4;
  doc["accessors"].push_back(doc["accessors"][both]);
  doc["accessors"].back()["byteOffset"] = 12;
  const int normals = static_cast<int>(doc["accessors"].size() - 1);
  w.node({{"mesh", w.mesh({{"attributes", {{"POSITION", both}, {"NORMAL", normals}}}, {"indices", idx}})}});
  w.writeGlb(dir_ / "interleaved.glb");
  LoadInfo info;
  const TriMesh m = load(dir_ / "interleaved.glb", &info);
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_TRUE(info.hadNormals);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NE(std::find(kTetra.begin(), kTetra.end(), m.positions[i]), kTetra.end()) << i;
    EXPECT_NEAR(glm::distance(m.normals[i], glm::normalize(m.positions[i] - glm::vec3(0.25f))), 0.0f, 1e-6f) << i;
  }
  // A stride shorter than the element it steps over is refused.
  doc["bufferViews"][0]["byteStride"] = 8;
  expectError(w, "bufferView 0: byteStride 8 is less than accessor 0's elements");
}

TEST_F(MeshGltf, MalformedFilesAreRefusedNamingThePart) {
  {
    GltfWriter w = tetra();
    w.doc()["accessors"][0]["count"] = 5;
    expectError(w, "accessor 0: 5 elements run past bufferView 0's 48 bytes");
  }
  {
    GltfWriter w = tetra();
    w.doc()["buffers"][0]["byteLength"] = 4096;
    expectError(w, "buffer 0 holds 72 bytes, its byteLength says 4096");
  }
  {
    GltfWriter w = tetra();
    w.doc()["accessors"][1]["sparse"] = nlohmann::json::object();
    expectError(w, "accessor 1 is sparse");
  }
  {
    GltfWriter w = tetra();
    w.doc()["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    expectError(w, "needs the extension \"KHR_draco_mesh_compression\"");
  }
  {
    GltfWriter w = tetra();
    w.doc()["extensionsRequired"] = {"KHR_materials_unlit"};  // leaves the triangles alone
    w.writeGlb(dir_ / "unlit.glb");
    EXPECT_EQ(load(dir_ / "unlit.glb").triangles.size(), 4u);
  }
  {
    GltfWriter w;
    const int pos = w.vec3s(kTetra), idx = w.indices16({0, 2, 9});
    w.node({{"mesh", w.mesh({{"attributes", {{"POSITION", pos}}}, {"indices", idx}})}});
    expectError(w, "mesh 0 primitive 0: index 9 names a vertex past its 4");
  }
  {
    GltfWriter w;
    const int pos = w.vec3s(kTetra), idx = w.indices16({0, 2, 1, 0});
    w.node({{"mesh", w.mesh({{"attributes", {{"POSITION", pos}}}, {"indices", idx}})}});
    expectError(w, "4 indices, not a multiple of 3");
  }
  {
    GltfWriter w = tetra();
    w.doc()["nodes"][0]["children"] = {0};
    expectError(w, "node 0 is reached twice");
  }
  {
    GltfWriter w = tetra();
    w.doc()["asset"]["version"] = "1.0";
    expectError(w, "asset.version is not 2.x");
  }
  {
    GltfWriter w = tetra();
    w.doc()["scenes"][0]["nodes"] = nlohmann::json::array();
    expectError(w, "its scene places no mesh");
  }
  {
    GltfWriter w = tetra();
    w.doc()["accessors"][0]["componentType"] = 5122;
    expectError(w, "accessor 0: componentType 5122, expected 5126");
  }
  {
    GltfWriter w = tetra({{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}, {"scale", {2, 2, 2}}});
    expectError(w, "node 0 has both a matrix and translation, rotation or scale");
  }
  {
    GltfWriter w = tetra();
    w.doc()["nodes"][0]["mesh"] = 7;
    expectError(w, "names meshes 7, which the file does not have");
  }
}

TEST_F(MeshGltf, BuffersAreReadOnlyFromTheFileOrBesideIt) {
  // Buffers outside the glTF's folder, or that are not there, are not read.
  for (const std::string& uri :
       {std::string("../t.bin"), std::string("/etc/hostname"), std::string("http://x/t.bin"),
        std::string("missing.bin"), std::string("data:application/octet-stream;base64,@@@@")}) {
    SCOPED_TRACE(uri);
    GltfWriter w = tetra();
    nlohmann::json doc = w.doc();
    doc["buffers"][0]["uri"] = uri;
    std::ofstream(dir_ / "uri.gltf") << doc.dump();
    const auto r = loadMesh(dir_ / "uri.gltf");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("buffer 0"), std::string::npos) << r.error().message;
  }
  // A GLB whose header does not match its size, and JSON that does not parse.
  {
    const GltfWriter w = tetra();
    w.writeGlb(dir_ / "cut.glb");
    fs::resize_file(dir_ / "cut.glb", fs::file_size(dir_ / "cut.glb") - 8);
    const auto r = loadMesh(dir_ / "cut.glb");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("the GLB header says"), std::string::npos) << r.error().message;
    std::ofstream(dir_ / "syntax.gltf") << "{\"asset\": {\"version\": \"2.0\"},\n \"nodes\": [}";
    std::ofstream(dir_ / "json.glb") << "{\"asset\": {\"version\": \"2.0\"}}";
    const auto magic = loadMesh(dir_ / "json.glb");
    ASSERT_FALSE(magic.ok());
    EXPECT_NE(magic.error().message.find("a .glb that does not start with \"glTF\""), std::string::npos)
        << magic.error().message;
    const auto s = loadMesh(dir_ / "syntax.gltf");
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("syntax.gltf:2:"), std::string::npos) << s.error().message;
  }
}

// Normals turn with the inverse transpose of the node's transform: under a non-uniform scale a
// face's normal stays perpendicular to it; under a mirror it turns with the triangles.
TEST_F(MeshGltf, NormalsTurnWithTheirNodes) {
  std::vector<glm::vec3> normals;
  for (const glm::vec3& p : kTetra) normals.push_back(glm::normalize(p - glm::vec3(0.25f)));
  for (const nlohmann::json& transform :
       {nlohmann::json{{"scale", {4, 1, 0.5}}}, nlohmann::json{{"scale", {-1, 2, 1}}}}) {
    SCOPED_TRACE(transform.dump());
    GltfWriter w;
    const int pos = w.vec3s(kTetra), nor = w.vec3s(normals), idx = w.indices16(kTetraFaces);
    nlohmann::json node = transform;
    node["mesh"] = w.mesh({{"attributes", {{"POSITION", pos}, {"NORMAL", nor}}}, {"indices", idx}});
    w.node(node);
    w.writeGlb(dir_ / "turned.glb");
    LoadInfo info;
    const TriMesh m = load(dir_ / "turned.glb", &info);
    ASSERT_TRUE(info.hadNormals);
    const glm::vec3 s(transform["scale"][0].get<float>(), transform["scale"][1].get<float>(),
                      transform["scale"][2].get<float>());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      // The vertex's source: the tetrahedron corner it is the image of.
      const glm::vec3 source = m.positions[i] / s;
      const glm::vec3 expected = glm::normalize(glm::normalize(source - glm::vec3(0.25f)) / s);
      EXPECT_NEAR(glm::distance(m.normals[i], expected), 0.0f, 1e-5f) << i;
    }
    EXPECT_FALSE(info.flippedInward) << "a mirror's triangles are turned back with it";
  }
}

// NORMAL is kept only when every placed primitive has it; indices may be 8-bit; a node scaled to
// nothing places nothing; a rotation not quite of unit length is read as the unit one.
TEST_F(MeshGltf, MixedPrimitivesAndExportersHabits) {
  GltfWriter w;
  const int pos = w.vec3s(kTetra), idx = w.indices8({0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
  std::vector<glm::vec3> normals(4, glm::vec3(0, 0, 1));
  const int nor = w.vec3s(normals);
  const int withNormals = w.mesh({{"attributes", {{"POSITION", pos}, {"NORMAL", nor}}}, {"indices", idx}});
  const int without = w.mesh({{"attributes", {{"POSITION", pos}}}, {"indices", idx}});
  w.node({{"mesh", withNormals}});
  w.node({{"mesh", without}, {"translation", {3, 0, 0}}, {"rotation", {0, 0, 0.7, 0.7}}});
  w.node({{"mesh", without}, {"scale", {0, 0, 0}}});
  w.writeGlb(dir_ / "mixed.glb");
  LoadInfo info;
  const TriMesh m = load(dir_ / "mixed.glb", &info);
  EXPECT_EQ(m.triangles.size(), 8u) << "the node scaled to nothing places nothing";
  EXPECT_FALSE(info.hadNormals) << "one primitive has no NORMAL, so normals are computed for all";
  // The rotated copy: (1, 0, 0) turned 90 degrees about z and moved by (3, 0, 0), at unit length.
  bool found = false;
  for (const glm::vec3& p : m.positions) found = found || glm::distance(p, glm::vec3(3, 1, 0)) < 1e-5f;
  EXPECT_TRUE(found);
  w.doc()["nodes"][1]["rotation"] = {0, 0, 0, 0};
  expectError(w, "node 1: rotation is not a quaternion of non-zero length");
}

TEST_F(MeshGltf, GltfIsReadNotWritten) {
  const GltfWriter w = tetra();
  w.writeGlb(dir_ / "t.glb");
  const TriMesh m = load(dir_ / "t.glb");
  const auto r = saveMesh(m, dir_ / "out.glb");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("cannot write glTF"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "out.glb"));
}

}  // namespace
