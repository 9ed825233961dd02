// puff::mesh: loading (Puff's own readers; OpenMesh builds the connectivity) and saving.
#include <puff/core/files.h>
#include <puff/mesh/mesh.h>

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#include <OpenMesh/Core/System/omstream.hh>
#pragma GCC diagnostic pop

#include "mesh_test_support.h"
#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace fs = std::filesystem;
using namespace puff::mesh;
using puff::test::closedAndOriented;
using puff::test::colored;
using puff::test::signedVolume;

namespace {

const fs::path kData = fs::path(PUFF_TEST_DATA_DIR) / "meshes";

bool oneLine(const std::string& s) { return !s.empty() && s.find('\n') == std::string::npos && s.back() != '.'; }

/// A per-test scratch directory, removed afterwards.
class MeshIo : public ::testing::Test {
 protected:
  std::vector<std::string> listDir() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_.path())) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  void writeBytes(const fs::path& p, const std::string& bytes) const {
    std::ofstream out(p, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
  }

  /// Loads `path`, expecting failure with exactly "path: expected".
  void expectLoadError(const fs::path& path, const std::string& expected) const {
    SCOPED_TRACE(path.string());
    const puff::Result<TriMesh> r = loadMesh(path);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, path.string() + ": " + expected);
    EXPECT_TRUE(oneLine(r.error().message)) << r.error().message;
  }

  puff::test::ScopedTempDir dir_{"puff_mesh_test"};
};

}  // namespace

// ---- loading ----------------------------------------------------------------------------------

TEST_F(MeshIo, LoadsAQuadCubeNormalized) {
  LoadInfo info;
  const auto r = loadMesh(kData / "cube.obj", &info);
  ASSERT_OK(r);
  EXPECT_EQ(info.sourceFaces, 6u);
  EXPECT_EQ(info.sourceVertices, 8u);
  EXPECT_FALSE(info.flippedInward);
  EXPECT_FALSE(info.hadColors);
  EXPECT_FALSE(info.hadNormals);
  EXPECT_EQ(r->faceCount(), 12u);
  for (const glm::vec3& p : r->positions) {
    EXPECT_NEAR(glm::length(p), 1.0f, 1e-6f);  // every corner is farthest
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::abs(p[k]), 1.0f / std::sqrt(3.0f), 1e-6f);
  }
  EXPECT_NEAR(signedVolume(*r), 8.0 / (3.0 * std::sqrt(3.0)), 1e-5);
  EXPECT_TRUE(closedAndOriented(*r));
  for (std::size_t i = 0; i < r->positions.size(); ++i) EXPECT_GT(glm::dot(r->normals[i], r->positions[i]), 0.5f);
}

// The share of its bounding sphere a mesh encloses: a cube of side 2 encloses 8 of the
// 4/3 pi (sqrt 3)^3 its corners' sphere holds; a flat card none; the art's puffs far more than the
// flat limit.
TEST_F(MeshIo, TheVolumeFractionTellsAPuffFromACard) {
  LoadInfo info;
  ASSERT_TRUE(loadMesh(kData / "cube.obj", &info).ok());
  EXPECT_NEAR(info.volumeFraction, 8.0 / (4.0 / 3.0 * M_PI * 3.0 * std::sqrt(3.0)), 1e-9);
  writeBytes(dir_ / "card.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  ASSERT_TRUE(loadMesh(dir_ / "card.obj", &info).ok());
  EXPECT_EQ(info.volumeFraction, 0.0);
  EXPECT_LT(info.volumeFraction, kFlatVolumeFraction);
  for (const char* art : {"variation-1.obj", "variation-2.ply", "variation-3.off", "variation-4.stl"}) {
    ASSERT_TRUE(loadMesh(fs::path(PUFF_SOURCE_DIR) / "art" / "puffs" / art, &info).ok());
    EXPECT_GT(info.volumeFraction, 10.0 * kFlatVolumeFraction) << art;
  }
}

TEST_F(MeshIo, AnInwardCubeIsFlipped) {
  LoadInfo info;
  const auto r = loadMesh(kData / "cube_inward.obj", &info);
  ASSERT_OK(r);
  EXPECT_TRUE(info.flippedInward);
  EXPECT_NEAR(signedVolume(*r), 8.0 / (3.0 * std::sqrt(3.0)), 1e-5);
  for (std::size_t i = 0; i < r->positions.size(); ++i) EXPECT_GT(glm::dot(r->normals[i], r->positions[i]), 0.5f);
}

TEST_F(MeshIo, ReadsEightBitColorsFromPlyAndOff) {
  // tetra_colors.off has a comment line, which OpenMesh's own OFF reader cannot skip.
  for (const char* name : {"tetra_colors.ply", "tetra_colors.off"}) {
    SCOPED_TRACE(name);
    LoadInfo info;
    const auto r = loadMesh(kData / name, &info);
    ASSERT_OK(r);
    EXPECT_TRUE(info.hadColors);
    EXPECT_FALSE(info.flippedInward);
    EXPECT_EQ(r->faceCount(), 4u);
    ASSERT_EQ(r->colors.size(), 4u);
    EXPECT_EQ(r->colors[0], glm::vec3(1, 0, 0));
    EXPECT_EQ(r->colors[1], glm::vec3(0, 1, 0));
    EXPECT_EQ(r->colors[2], glm::vec3(0, 0, 1));
    EXPECT_NEAR(r->colors[3].r, 128.0f / 255.0f, 1e-6f);
    EXPECT_TRUE(closedAndOriented(*r));
    EXPECT_GT(signedVolume(*r), 0.0);
  }
}

TEST_F(MeshIo, ReadsAsciiStlMergingCorners) {
  LoadInfo info;
  const auto r = loadMesh(kData / "tetra.stl", &info);
  ASSERT_OK(r);
  EXPECT_EQ(r->faceCount(), 4u);
  EXPECT_EQ(r->positions.size(), 4u);  // 12 corners, 4 distinct points
  EXPECT_FALSE(info.hadColors);
  EXPECT_FALSE(info.hadNormals);
  EXPECT_FALSE(r->hasColors());
  EXPECT_TRUE(closedAndOriented(*r));
  for (std::size_t i = 0; i < r->positions.size(); ++i)
    EXPECT_NEAR(glm::dot(r->normals[i], r->positions[i]), 1.0f, 1e-5f);  // regular tetra: radial
}

TEST_F(MeshIo, KeepsUnitNormalsFromTheFile) {
  LoadInfo info;
  const auto r = loadMesh(kData / "tetra_normals.obj", &info);
  ASSERT_OK(r);
  EXPECT_TRUE(info.hadNormals);
  for (const glm::vec3& n : r->normals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
}

TEST_F(MeshIo, BadFilesGiveTheExpectedError) {
  expectLoadError(dir_ / "missing.obj", "cannot open: no such file or directory");
  fs::create_directory(dir_ / "folder.obj");
  expectLoadError(dir_ / "folder.obj", "cannot open: is a directory");
  expectLoadError(dir_ / "mesh.xyz", "unsupported extension '.xyz' (accepted: .obj, .off, .ply, .stl, .gltf, .glb)");
  expectLoadError(kData / "empty.obj", "no faces");
  expectLoadError(kData / "nan_vertex.obj", "vertex 1 has a non-finite coordinate");
  expectLoadError(kData / "zero_area.obj", "face 1 (line 10) is degenerate (zero area)");
  // A header that counts more faces than the file holds, or a face that refers to a missing vertex.
  writeBytes(dir_ / "short.off", "OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n");
  expectLoadError(dir_ / "short.off", "the header declares 5 faces after 4 vertices; the file holds 1");
  writeBytes(dir_ / "missing_vertex.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 9\n");
  expectLoadError(dir_ / "missing_vertex.off",
                  "the file declares 2 faces, only 1 could be added: face 1 (line 8) refers to vertex 9, but the file "
                  "has 4");
  // OBJ numbers its vertices from 1, and the message does as the file does.
  writeBytes(dir_ / "missing_vertex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n# a comment\nf 1 2 9\n");
  expectLoadError(dir_ / "missing_vertex.obj",
                  "the file declares 1 face, only 0 could be added: face 0 (line 5) refers to vertex 9, but the file "
                  "has 3");

  // Fixed pseudo-random bytes, control characters included.
  std::string garbage;
  for (int i = 0; i < 300; ++i) garbage.push_back(char((i * 73 + 41) & 0xff));
  for (const auto& [ext, name] : std::vector<std::pair<std::string, std::string>>{
           {".obj", "OBJ"}, {".ply", "PLY"}, {".stl", "STL"}, {".off", "OFF"}, {".OBJ", "OBJ"}}) {
    const fs::path p = dir_ / ("garbage" + ext);
    writeBytes(p, garbage);
    const auto r = loadMesh(p);
    ASSERT_FALSE(r.ok()) << p;
    EXPECT_EQ(r.error().message.rfind(p.string() + ": not a valid " + name + " file", 0), 0u) << r.error().message;
  }
  writeBytes(dir_ / "words.obj", "hello world\n");
  expectLoadError(dir_ / "words.obj", "not a valid OBJ file (line 1)");
  writeBytes(dir_ / "zero.ply", "");
  expectLoadError(dir_ / "zero.ply", "not a valid PLY file");
}

TEST_F(MeshIo, FacesOpenMeshDropsAreCounted) {
  // A face that repeats a vertex is left out (as OpenMesh's importer does); the file declared it, so
  // loading must fail.
  writeBytes(dir_ / "repeat.obj",
             "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\n"
             "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\nf 1 1 2\n");
  expectLoadError(dir_ / "repeat.obj",
                  "the file declares 5 faces, only 4 could be added: face 4 (line 9) repeats vertex 1");
}

TEST_F(MeshIo, ObjColorsWrittenAsBytesAreScaledToUnit) {
  writeBytes(dir_ / "bytes.obj",
             "v 1 1 1 255 0 0\nv 1 -1 -1 0 255 0\nv -1 1 -1 0 0 255\nv -1 -1 1 51 102 153\n"
             "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n");
  LoadInfo info;
  const auto r = loadMesh(dir_ / "bytes.obj", &info);
  ASSERT_OK(r);
  EXPECT_TRUE(info.hadColors);
  EXPECT_EQ(r->colors[0], glm::vec3(1, 0, 0));
  EXPECT_NEAR(glm::length(r->colors[3] - glm::vec3(0.2f, 0.4f, 0.6f)), 0.0f, 1e-6f);
}

TEST_F(MeshIo, ANanInBinaryPlyIsCaughtAfterReading) {
  // Text readers cannot even parse "nan"; binary PLY carries it to the mesh check.
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
  const float v[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, NAN, -1}, {-1, -1, 1}};
  bytes.append(reinterpret_cast<const char*>(v), sizeof v);
  const int faces[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  for (const auto& f : faces) {
    bytes.push_back(3);
    bytes.append(reinterpret_cast<const char*>(f), sizeof f);
  }
  writeBytes(dir_ / "nan.ply", bytes);
  expectLoadError(dir_ / "nan.ply", "vertex 2 has a non-finite coordinate");
}

TEST_F(MeshIo, OpenMeshStaysQuietAndItsStreamsAreRestored) {
  testing::internal::CaptureStderr();
  EXPECT_TRUE(loadMesh(kData / "nonmanifold.obj").ok());  // OpenMesh logs the faces it splits
  EXPECT_TRUE(saveMesh(generateSphere({1}), dir_ / "s.ply").ok());
  EXPECT_TRUE(saveMesh(generateSphere({1}), dir_ / "s.stl").ok());
  EXPECT_TRUE(saveMesh(generateSphere({1}), dir_ / "s.off").ok());
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_TRUE(omerr().is_enabled());
  EXPECT_TRUE(omlog().is_enabled());
  // A stream the host application switched off stays off.
  omerr().disable();
  EXPECT_TRUE(loadMesh(kData / "nonmanifold.obj").ok());
  EXPECT_FALSE(omerr().is_enabled());
  omerr().enable();
}

// Real meshes (the cow's one non-manifold vertex, the beetle's dozens of non-manifold edges) load,
// since the baker only rasterizes triangles: their faces are split onto their own vertices, every
// face is kept, and the split is counted.
TEST_F(MeshIo, NonManifoldFacesAreSplitOntoTheirOwnVerticesAndCounted) {
  LoadInfo info;
  auto fin = loadMesh(kData / "nonmanifold.obj", &info);  // three triangles on one edge
  ASSERT_OK(fin);
  EXPECT_EQ(fin->faceCount(), 3u);
  EXPECT_EQ(info.sourceFaces, 3u);
  EXPECT_EQ(info.separatedFaces, 1u);

  // Two closed tetrahedra touching at one vertex (a bowtie): its second fan cannot join the first.
  writeBytes(dir_ / "bowtie.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv -1 0 0\nv 0 -1 0\nv 0 0 -1\n"
             "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 5 6\nf 1 7 5\nf 1 6 7\nf 5 7 6\n");
  auto bowtie = loadMesh(dir_ / "bowtie.obj", &info);
  ASSERT_OK(bowtie);
  EXPECT_EQ(bowtie->faceCount(), 8u);
  EXPECT_EQ(info.separatedFaces, 3u);  // the second tetrahedron's three faces at the shared vertex
  EXPECT_FALSE(info.flippedInward);

  // A closed sphere with 40 fins standing on 40 of its edges: 40 non-manifold edges.
  TriMesh sphere = generateSphere({2});
  std::string obj;
  for (const glm::vec3& p : sphere.positions)
    obj += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  for (const glm::uvec3& t : sphere.triangles)
    obj += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
  std::size_t vertices = sphere.positions.size();
  for (std::size_t k = 0; k < 40; ++k) {
    const glm::uvec3& t = sphere.triangles[k * 7];
    const glm::vec3 tip = 1.3f * glm::normalize(sphere.positions[t[0]] + sphere.positions[t[1]]);
    obj += "v " + std::to_string(tip.x) + " " + std::to_string(tip.y) + " " + std::to_string(tip.z) + "\n";
    ++vertices;
    obj += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(vertices) + "\n";
  }
  writeBytes(dir_ / "fins.obj", obj);
  auto fins = loadMesh(dir_ / "fins.obj", &info);
  ASSERT_OK(fins);
  EXPECT_EQ(fins->faceCount(), sphere.triangles.size() + 40u);
  EXPECT_EQ(info.separatedFaces, 40u);
}

// A PLY of triangle strips (as the Igea model stores itself) is read as triangles. Strips alternate
// their winding (OpenGL's rule), -1 restarts a strip, and the degenerate triangles that stitch strips
// together are dropped.
TEST_F(MeshIo, PlyTriangleStripsAreRead) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
      "1 1 1\n-1 -1 1\n-1 1 -1\n1 -1 -1\n";
  // One strip around a tetrahedron: 0 1 2 3 0 1 is its four faces, consistently wound only if every
  // second triangle's first two corners are swapped.
  writeBytes(dir_ / "tetra.ply", header + "6 0 1 2 3 0 1\n");
  LoadInfo info;
  auto tetra = loadMesh(dir_ / "tetra.ply", &info);
  ASSERT_OK(tetra);
  EXPECT_EQ(tetra->faceCount(), 4u);
  EXPECT_EQ(info.separatedFaces, 0u);  // a wrong winding would leave two faces non-manifold
  EXPECT_TRUE(closedAndOriented(*tetra));
  EXPECT_GT(signedVolume(*tetra), 0.0);
  // The same faces as two strips with a restart and a stitching (degenerate) triangle.
  writeBytes(dir_ / "tetra2.ply", header + "9 0 1 2 3 3 -1 0 3 1\n");
  auto restarted = loadMesh(dir_ / "tetra2.ply", &info);
  ASSERT_OK(restarted);
  EXPECT_EQ(restarted->faceCount(), 3u);  // (0 1 2) (2 1 3), (2 3 3) dropped, then (0 3 1)
  EXPECT_EQ(info.sourceFaces, 3u);
  EXPECT_EQ(info.separatedFaces, 0u);

  // A closed sphere of 1280 triangles stored as one strip per triangle pair, binary, as Igea's
  // scanner wrote it: every face arrives, none split, the same solid.
  const TriMesh sphere = generateSphere({3});
  std::string bytes = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                      std::to_string(sphere.positions.size()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement tristrips 1\n"
                      "property list int int vertex_indices\nend_header\n";
  for (const glm::vec3& p : sphere.positions) bytes.append(reinterpret_cast<const char*>(&p), sizeof p);
  std::vector<std::int32_t> strip;
  for (const glm::uvec3& t : sphere.triangles) {
    strip.insert(strip.end(), {std::int32_t(t[0]), std::int32_t(t[1]), std::int32_t(t[2]), -1});
  }
  const std::int32_t n = std::int32_t(strip.size());
  bytes.append(reinterpret_cast<const char*>(&n), sizeof n);
  bytes.append(reinterpret_cast<const char*>(strip.data()), strip.size() * sizeof strip[0]);
  writeBytes(dir_ / "sphere_strips.ply", bytes);
  auto strips = loadMesh(dir_ / "sphere_strips.ply", &info);
  ASSERT_OK(strips);
  EXPECT_EQ(strips->faceCount(), sphere.faceCount());
  EXPECT_EQ(info.separatedFaces, 0u);
  EXPECT_FALSE(info.flippedInward);
  EXPECT_TRUE(closedAndOriented(*strips));
  EXPECT_NEAR(signedVolume(*strips), signedVolume(sphere), 1e-4);
}

// Puff reads the files itself (OpenMesh's readers crash on fuzzed input): every form of every
// format, as the fuzz seeds hold them (tests/fuzz/seeds/mesh), gives the same solid.
TEST_F(MeshIo, EveryFormOfEveryFormatReads) {
  const fs::path seeds = fs::path(PUFF_SOURCE_DIR) / "tests" / "fuzz" / "seeds" / "mesh";
  for (const char* name : {"tetra_binary_le.ply", "tetra_binary_be.ply", "tetra_strips.ply", "tetra_ascii.stl",
                           "tetra_binary.stl", "tetra_comments.off", "tetra_binary.off"}) {
    SCOPED_TRACE(name);
    LoadInfo info;
    auto m = loadMesh(seeds / name, &info);
    ASSERT_OK(m);
    EXPECT_EQ(m->faceCount(), std::string(name) == "tetra_strips.ply" ? 3u : 4u);  // strips 0 1 2 3 | 2 3 0
    EXPECT_EQ(m->positions.size(), 4u);
    EXPECT_EQ(info.separatedFaces, 0u);
  }
  // Binary PLY of both byte orders: colours (200, 100, 50) / 255 and the file's unit normals.
  for (const char* name : {"tetra_binary_le.ply", "tetra_binary_be.ply"}) {
    SCOPED_TRACE(name);
    LoadInfo info;
    auto m = loadMesh(seeds / name, &info);
    ASSERT_OK(m);
    ASSERT_TRUE(info.hadColors);
    EXPECT_NEAR(glm::length(m->colors[0] - glm::vec3(200, 100, 50) / 255.0f), 0.0f, 1e-6f);
    EXPECT_TRUE(info.hadNormals);
    EXPECT_GT(glm::dot(m->normals[0], glm::normalize(m->positions[0])), 0.999f);
  }
  // Quads with relative (negative) indices: six faces, twelve triangles, a closed cube.
  LoadInfo info;
  auto cube = loadMesh(seeds / "cube_relative.obj", &info);
  ASSERT_OK(cube);
  EXPECT_EQ(info.sourceFaces, 6u);
  EXPECT_EQ(cube->faceCount(), 12u);
  EXPECT_TRUE(closedAndOriented(*cube));
}

// A polygon with a corner on one of its edges: the fan from that corner holds a flat triangle, so the
// fan starts from a corner that gives none (so the face bakes whichever corner the file lists
// first).
TEST_F(MeshIo, APolygonWithACornerOnAnEdgeIsTriangulatedFromAnotherApex) {
  for (const char* face : {"f 1 2 3 4 5\n", "f 2 3 4 5 1\n", "f 4 5 1 2 3\n"}) {
    SCOPED_TRACE(face);
    writeBytes(dir_ / "pent.obj", std::string("v 0 0 0\nv 0.5 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n") + face);
    auto m = loadMesh(dir_ / "pent.obj");
    ASSERT_OK(m);
    EXPECT_EQ(m->faceCount(), 3u);
    for (const glm::uvec3& t : m->triangles) {
      const glm::vec3 n = glm::cross(m->positions[t[1]] - m->positions[t[0]], m->positions[t[2]] - m->positions[t[0]]);
      EXPECT_GT(glm::length(n), 0.0f);
    }
  }
}

// What some writers do that the readers take.
TEST_F(MeshIo, WritersQuirksAreRead) {
  const std::string tetraV = "1 1 1\n-1 -1 1\n-1 1 -1\n1 -1 -1\n";
  const std::string tetraF = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  // "ply " with a trailing space.
  writeBytes(dir_ / "space.ply",
             "ply \nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
             "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n" +
                 tetraV + tetraF);
  // A comment before the OFF keyword.
  writeBytes(dir_ / "comment.off", "# written by a tool\nOFF\n4 4 0\n" + tetraV + tetraF);
  // An ASCII STL in upper case.
  std::string stl = "SOLID T\n";
  const float v[4][3] = {{1, 1, 1}, {-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}};
  for (const auto& f : {std::array<int, 3>{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}) {
    stl += "FACET NORMAL 0 0 0\nOUTER LOOP\n";
    for (int i : f)
      stl += "VERTEX " + std::to_string(v[i][0]) + " " + std::to_string(v[i][1]) + " " + std::to_string(v[i][2]) + "\n";
    stl += "ENDLOOP\nENDFACET\n";
  }
  writeBytes(dir_ / "upper.stl", stl + "ENDSOLID T\n");
  // A binary STL with 4 bytes of padding after its facets.
  std::string bin(80, ' ');
  const std::uint32_t n = 4;
  bin.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& f : {std::array<int, 3>{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}) {
    const float normal[3] = {0, 0, 0};
    bin.append(reinterpret_cast<const char*>(normal), 12);
    for (int i : f) bin.append(reinterpret_cast<const char*>(v[i]), 12);
    bin.append(2, '\0');
  }
  writeBytes(dir_ / "padded.stl", bin + std::string(4, '\0'));
  // An OBJ statement continued over lines.
  writeBytes(dir_ / "continued.obj",
             "v 1 1 1\nv -1 -1 \\\n 1\nv -1 1 -1\nv 1 -1 -1\nf 1 3 2\nf 1 2 \\\n4\nf 1 4 3\nf 2 3 4\n");
  for (const char* name : {"space.ply", "comment.off", "upper.stl", "padded.stl", "continued.obj"}) {
    SCOPED_TRACE(name);
    LoadInfo info;
    auto m = loadMesh(dir_ / name, &info);
    ASSERT_OK(m);
    EXPECT_EQ(m->faceCount(), 4u);
    EXPECT_EQ(m->positions.size(), 4u);
    EXPECT_FALSE(info.flippedInward);
    EXPECT_TRUE(closedAndOriented(*m));
  }
}

// ---- saving -----------------------------------------------------------------------------------

TEST_F(MeshIo, EachFormatRoundTrips) {
  LumpyParams lp;
  lp.subdivisions = 2;
  lp.seed = 3;
  const TriMesh plain = generateLumpy(lp);
  for (const char* ext : {".obj", ".off", ".ply", ".stl", ".PLY"}) {
    SCOPED_TRACE(ext);
    const bool carriesColor = std::string(ext) != ".stl";
    const TriMesh src = carriesColor ? colored(plain) : plain;
    const fs::path p = dir_ / (std::string("rt") + ext);
    const auto saved = saveMesh(src, p);
    ASSERT_OK(saved);
    LoadInfo info;
    const auto r = loadMesh(p, &info);
    ASSERT_OK(r);
    EXPECT_EQ(r->faceCount(), src.faceCount());
    EXPECT_EQ(r->positions.size(), src.positions.size());  // STL's corners merge back to shared vertices
    EXPECT_EQ(info.sourceFaces, src.faceCount());
    EXPECT_FALSE(info.flippedInward);
    EXPECT_EQ(info.hadColors, carriesColor);
    // Compare corner by corner: STL renumbers vertices, and a triangle may start at another corner.
    const float colorTol = std::string(ext) == ".ply" || std::string(ext) == ".PLY" ? 0.5f / 255 + 1e-6f : 1e-6f;
    for (std::size_t t = 0; t < src.faceCount(); ++t) {
      const glm::uvec3 a = src.triangles[t], b = r->triangles[t];
      int shift = 0;
      while (shift < 3 && glm::length(src.positions[a[0]] - r->positions[b[shift]]) > 1e-5f) ++shift;
      ASSERT_LT(shift, 3) << "triangle " << t;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t i = a[k], j = b[(k + shift) % 3];
        EXPECT_NEAR(glm::length(src.positions[i] - r->positions[j]), 0.0f, 1e-5f);
        EXPECT_GT(glm::dot(src.normals[i], r->normals[j]), 0.9999f);
        if (carriesColor) {
          EXPECT_NEAR(glm::length(src.colors[i] - r->colors[j]), 0.0f, colorTol * 1.8f);
        }
      }
    }
  }
  EXPECT_EQ(listDir(), (std::vector<std::string>{"rt.PLY", "rt.obj", "rt.off", "rt.ply", "rt.stl"}));
}

TEST_F(MeshIo, SavingIntoAMissingDirectoryFailsAndLeavesNothing) {
  const fs::path p = dir_ / "missing" / "out.obj";
  const auto r = saveMesh(generateSphere({1}), p);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, p.string() + ": cannot write: no such file or directory");
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
  EXPECT_TRUE(listDir().empty());
  const auto u = saveMesh(generateSphere({1}), dir_ / "out.vrml");
  ASSERT_FALSE(u.ok());
  EXPECT_NE(u.error().message.find("unsupported extension '.vrml'"), std::string::npos);
  EXPECT_TRUE(listDir().empty());
}

TEST_F(MeshIo, SavingReplacesAnExistingFileByRename) {
  for (const char* name : {"a.obj", "a.ply"}) {
    SCOPED_TRACE(name);
    const fs::path p = dir_ / name;
    writeBytes(p, "old contents\n");
    struct stat before {};
    ASSERT_EQ(::stat(p.c_str(), &before), 0);
    ASSERT_TRUE(saveMesh(generateSphere({2}), p).ok());
    struct stat after {};
    ASSERT_EQ(::stat(p.c_str(), &after), 0);
    // A new inode: the target was swapped whole, never truncated and rewritten in place.
    EXPECT_NE(before.st_ino, after.st_ino);
    const auto r = loadMesh(p);
    ASSERT_OK(r);
    EXPECT_EQ(r->faceCount(), 320u);
  }
  EXPECT_EQ(listDir(), (std::vector<std::string>{"a.obj", "a.ply"}));  // no temporaries left
}

namespace {

// A FIFO named as a mesh (or any file Puff reads whole) would hang the run; a device such as
// /dev/zero never ends. Only regular files are read.
TEST(MeshLoad, AFifoOrADeviceIsRefusedNotWaitedOn) {
  puff::test::ScopedTempDir dir("puff_mesh_fifo");
  const std::filesystem::path fifo = dir / "puff.obj";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto mesh = puff::mesh::loadMesh(fifo);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().message, fifo.string() + ": cannot open: not a regular file");
  auto bytes = puff::core::readFileBytes(fifo);
  ASSERT_FALSE(bytes.ok());
  EXPECT_EQ(bytes.error().message, fifo.string() + ": cannot open: not a regular file");
  auto zero = puff::core::readFileBytes("/dev/zero");
  ASSERT_FALSE(zero.ok());
  EXPECT_EQ(zero.error().message, "/dev/zero: cannot open: not a regular file");
}

}  // namespace
