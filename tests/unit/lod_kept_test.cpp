// puffbake --lod auto keeps the mesh it chose (written beside the atlas,
// named by the sidecar, drawn by the fixed path; the cel reference keeps the full source), its
// tolerance judges depth and colour and keeps authored normals; and the atlas memory reported is
// what the GL holds.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <puff/bake/baker.h>
#include <puff/bake/raster.h>
#include <puff/cel/nailboards.h>
#include <puff/core/atlas.h>
#include <puff/core/files.h>
#include <puff/eval/cel_reference.h>
#include <puff/mesh/mesh.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "../../runtime/src/eval/cel_reference_gl.h"
#include "../../runtime/src/render/paths.h"
#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/temp_dir.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

// Two lumpy variations, 32-texel cells, --lod auto unless `lod` is false.
Result<bake::BakeReport> bakeLumpy(const fs::path& dir, bool lod, bake::MapFormat format = bake::MapFormat::kPng,
                                   int viewGrid = 1) {
  bake::GeneratorSpec gen;
  gen.kind = "lumpy";
  gen.lumpy.subdivisions = 4;
  gen.count = 2;
  PUFF_TRY_ASSIGN(auto sources, bake::loadSources({}, gen));
  bake::BakeOptions o;
  o.cellSize = 32;
  o.lodAuto = lod;
  o.format = format;
  o.viewGrid = viewGrid;
  o.contactSheet = false;
  o.outDir = dir;
  return bake::bakeAtlas(sources, o);
}

// The (compatibility) context both the bake and the fixed path draw in.
class LodKept : public test::GlSuite<true> {};

TEST_F(LodKept, LodAutoWritesEachChosenMeshAndTheSidecarNamesIt) {
  const test::ScopedTempDir out("puff_lod_kept");
  auto r = bakeLumpy(out.path(), true);
  ASSERT_OK(r);
  ASSERT_EQ(r->lodMeshes.size(), 2u);
  auto desc = core::loadAtlasDesc(r->sidecar);
  ASSERT_OK(desc);
  for (int v = 0; v < 2; ++v) {
    SCOPED_TRACE(v);
    const auto& lod = *r->lod[static_cast<std::size_t>(v)];
    const core::AtlasSource& s = desc->sources[static_cast<std::size_t>(v)];
    // Named by its content: puff_lodV.HASH.ply.
    EXPECT_EQ(s.lodMesh.rfind("puff_lod" + std::to_string(v) + ".", 0), 0u) << s.lodMesh;
    EXPECT_EQ(s.lodMesh.size(), std::string("puff_lod0.").size() + 12 + 4) << s.lodMesh;
    EXPECT_EQ(core::lodMeshPath(s, r->sidecar), r->lodMeshes[static_cast<std::size_t>(v)]);
    auto m = mesh::loadMesh(core::lodMeshPath(s, r->sidecar), nullptr, mesh::Normalize::kNo);
    ASSERT_OK(m);
    // The face count the report and the sidecar give, fewer than the source's.
    EXPECT_EQ(m->faceCount(), lod.facesAfter);
    EXPECT_EQ(s.facesBaked, lod.facesAfter);
    EXPECT_LT(lod.facesAfter, s.faces);
    // In the source's normalized space: a halfedge collapse keeps vertices where they were, so every
    // vertex of the level of detail is a vertex of the source (no re-centring or re-scaling).
    bake::GeneratorSpec gen;
    gen.lumpy.subdivisions = 4;
    gen.count = 2;
    auto src = bake::loadSources({}, gen);
    ASSERT_OK(src);
    const mesh::TriMesh& full = (*src)[static_cast<std::size_t>(v)].mesh;
    for (const glm::vec3& p : m->positions) {
      float nearest = 1e9f;
      for (const glm::vec3& q : full.positions) nearest = std::min(nearest, glm::length(p - q));
      ASSERT_LT(nearest, 1e-6f);
    }
  }
}

TEST_F(LodKept, WithoutLodTheFieldIsAbsentAndOldSidecarsLoad) {
  const test::ScopedTempDir out("puff_lod_kept_full");
  auto r = bakeLumpy(out.path(), false);
  ASSERT_OK(r);
  EXPECT_TRUE(r->lodMeshes.empty());
  auto text = core::readFileBytes(r->sidecar);
  ASSERT_OK(text);
  EXPECT_EQ(text->find("lodMesh"), std::string::npos);
  auto desc = core::loadAtlasDesc(r->sidecar);
  ASSERT_OK(desc);
  EXPECT_TRUE(desc->sources[0].lodMesh.empty());
  EXPECT_EQ(desc->sources[0].facesBaked, desc->sources[0].faces);
}

TEST_F(LodKept, AMissingOrEmptyLodMeshIsAnErrorNamingTheSidecar) {
  const test::ScopedTempDir out("puff_lod_kept_missing");
  auto r = bakeLumpy(out.path(), true);
  ASSERT_OK(r);
  const fs::path lod1 = out.path() / r->lodMeshes[1].filename();
  fs::remove(lod1);
  // The atlas still loads (the nailboards and the reference do not draw the LOD mesh); the fixed
  // path, which does, asks for it by lodMeshFile.
  auto desc = core::loadAtlasDesc(r->sidecar);
  ASSERT_OK(desc);
  EXPECT_TRUE(core::loadAtlas(r->sidecar).ok());
  EXPECT_OK(core::lodMeshFile(*desc, 0, r->sidecar));
  auto missing = core::lodMeshFile(*desc, 1, r->sidecar);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, r->sidecar.string() + ": /sources/1/lodMesh: " + lod1.string() +
                                         " does not exist (the level of detail the atlas was baked from; re-bake it)");
  nlohmann::json j = nlohmann::json::parse(*core::readFileBytes(r->sidecar));
  j["sources"][0]["lodMesh"] = "";
  auto empty = core::atlasFromJson(j, r->sidecar);
  ASSERT_FALSE(empty.ok());
  EXPECT_EQ(empty.error().message, r->sidecar.string() + ": /sources/0/lodMesh: must name a mesh file");
  j["sources"][0]["lodMesh"] = 3;
  EXPECT_FALSE(core::atlasFromJson(j, r->sidecar).ok());
}

// The fixed path draws the chosen mesh; the cel reference the full source it stands in for.
TEST_F(LodKept, TheFixedPathDrawsTheLodAndTheCelReferenceTheFullMesh) {
  const test::ScopedTempDir out("puff_lod_kept_fixed");
  auto r = bakeLumpy(out.path(), true);
  ASSERT_OK(r);
  const std::size_t baked = r->desc.sources[0].facesBaked, full = r->desc.sources[0].faces;
  ASSERT_LT(baked, full);
  const nlohmann::json j = {
      {"output", {{"width", 64}, {"height", 64}, {"samples", 1}}},
      {"camera",
       {{"position", {0, 0, 10}}, {"target", {0, 0, 0}}, {"fovY", 0}, {"orthoHeight", 4}, {"near", 1}, {"far", 20}}},
      {"atlas", r->sidecar.string()},
      {"particles", {{{"position", {0, 0, 0}}, {"size", 2.0}}}}};
  auto scene = scene::parseScene(j, out.path() / "scene.json");
  ASSERT_OK(scene);
  auto atlas = core::loadAtlas(scene->atlas);
  ASSERT_OK(atlas);
  auto puff = render::detail::fixedPuffMesh(*scene, &*atlas);
  ASSERT_OK(puff);
  EXPECT_EQ(puff->faceCount(), baked);
  // The variations are generated: before the level of detail was kept, the fixed path had no mesh
  // file to load and refused the scene. Now it draws, and the puff shows in the middle.
  auto renderer = render::SceneRenderer::create(*scene, render::RenderPath::kFixed);
  ASSERT_OK(renderer);
  auto frame = (*renderer)->renderFrame(0);
  ASSERT_OK(frame);
  const glm::vec4 bg(frame->at(0, 0, 0), frame->at(0, 0, 1), frame->at(0, 0, 2), 1.0f);
  const glm::vec4 mid(frame->at(32, 32, 0), frame->at(32, 32, 1), frame->at(32, 32, 2), 1.0f);
  EXPECT_GT(glm::length(mid - bg), 0.05f) << "the puff is drawn";
  // scene.fixed.puff still wins.
  const fs::path own = out.path() / "own.ply";
  ASSERT_OK(mesh::saveMesh(mesh::generateSphere({1}), own));
  scene::Scene withPuff = *scene;
  withPuff.fixed.puff = own;
  auto ownPuff = render::detail::fixedPuffMesh(withPuff, &*atlas);
  ASSERT_OK(ownPuff);
  EXPECT_EQ(ownPuff->faceCount(), 80u);

  auto meshes = eval::detail::atlasSourceMeshes(atlas->desc, scene->atlas);
  ASSERT_OK(meshes);
  ASSERT_EQ(meshes->size(), 2u);
  EXPECT_EQ((*meshes)[0].faceCount(), full);
  EXPECT_EQ((*meshes)[1].faceCount(), r->desc.sources[1].faces);
}

// Authored normals survive decimation: a sphere whose file gives the bent field N = normalize(p + b)
// (far from the faces' own normals, which point along p) keeps N at every kept vertex.
TEST_F(LodKept, AuthoredNormalsAreKeptThroughDecimation) {
  const test::ScopedTempDir out("puff_lod_kept_normals");
  const glm::vec3 bend(0.6f, 0.0f, 0.0f);
  mesh::TriMesh sphere = mesh::generateSphere({4});
  for (std::size_t i = 0; i < sphere.positions.size(); ++i)
    sphere.normals[i] = glm::normalize(sphere.positions[i] + bend);
  const fs::path file = out.path() / "bent.ply";
  ASSERT_OK(mesh::saveMesh(sphere, file, mesh::SaveNormals::kYes));
  auto sources = bake::loadSources({file}, std::nullopt);
  ASSERT_OK(sources);
  ASSERT_TRUE((*sources)[0].normalsAuthored);
  bake::BakeOptions o;
  o.cellSize = 32;
  o.lodAuto = true;
  o.contactSheet = false;
  o.outDir = out.path() / "atlas";
  auto r = bake::bakeAtlas(*sources, o);
  ASSERT_OK(r);
  auto lod = mesh::loadMesh(r->lodMeshes.at(0), nullptr, mesh::Normalize::kNo);
  ASSERT_OK(lod);
  EXPECT_EQ(lod->faceCount(), r->lod[0]->facesAfter);
  ASSERT_LT(lod->faceCount(), sphere.faceCount() / 2);
  float worst = 0.0f, worstRecomputed = 0.0f;
  mesh::TriMesh recomputed = *lod;
  mesh::computeNormals(recomputed);
  for (std::size_t i = 0; i < lod->positions.size(); ++i) {
    const glm::vec3 want = glm::normalize(lod->positions[i] + bend);
    worst = std::max(worst, glm::length(lod->normals[i] - want));
    worstRecomputed = std::max(worstRecomputed, glm::length(recomputed.normals[i] - want));
  }
  EXPECT_LT(worst, 1e-5f);
  EXPECT_GT(worstRecomputed, 0.3f) << "recomputing would have lost the field";

  // The same through mesh::decimate directly: kFromSource keeps, kRecompute does not.
  const mesh::TriMesh kept = mesh::decimate(sphere, 300, mesh::DecimatedNormals::kFromSource);
  for (std::size_t i = 0; i < kept.positions.size(); ++i)
    ASSERT_LT(glm::length(kept.normals[i] - glm::normalize(kept.positions[i] + bend)), 1e-6f);
}

// saveMesh writes normals when asked (PLY, OBJ), and loading gives exactly them back, authored.
TEST(LodMeshFile, NormalsRoundTripThroughPlyAndObj) {
  const test::ScopedTempDir out("puff_lod_normals_io");
  mesh::TriMesh m = mesh::generateSphere({2});
  for (std::size_t i = 0; i < m.positions.size(); ++i)
    m.normals[i] = glm::normalize(m.positions[i] + glm::vec3(0, 0.7f, 0));
  for (const char* name : {"n.ply", "n.obj"}) {
    SCOPED_TRACE(name);
    ASSERT_OK(mesh::saveMesh(m, out.path() / name, mesh::SaveNormals::kYes));
    mesh::LoadInfo info;
    auto back = mesh::loadMesh(out.path() / name, &info, mesh::Normalize::kNo);
    ASSERT_OK(back);
    EXPECT_TRUE(info.hadNormals);
    ASSERT_EQ(back->normals.size(), m.normals.size());
    for (std::size_t i = 0; i < m.normals.size(); ++i) ASSERT_LT(glm::length(back->normals[i] - m.normals[i]), 1e-6f);
  }
  for (const char* name : {"n.off", "n.stl"}) {
    auto r = mesh::saveMesh(m, out.path() / name, mesh::SaveNormals::kYes);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message,
              (out.path() / name).string() + ": cannot write normals: only PLY and OBJ files carry them here");
  }
}

// What the level of detail compares, in each of its views: the cell maps at 2 samples per texel.
class LodTolerance : public test::GlTest {
 protected:
  static constexpr int kCell = 32, kMargin = 2, kContent = 28;
  std::vector<bake::CellMaps> maps(const mesh::TriMesh& m) {
    if (!raster_) raster_ = std::move(*bake::PuffRasterizer::create(kCell * 2));
    raster_->setMesh(m, glm::vec3(1.0f));
    bake::SampleBuffer samples;
    raster_->render(bake::viewRotation({0, 0, 1}), kMargin * 2, kContent * 2, samples);
    return {bake::resolveCell(samples, 2, 0.0f)};
  }
  bake::LodResult choose(const mesh::TriMesh& m, const bake::LodTolerances& t, mesh::DecimatedNormals normals) {
    return bake::chooseLod(
        m, [&](const mesh::TriMesh& c) { return maps(c); }, t, normals, nullptr);
  }
  std::unique_ptr<bake::PuffRasterizer> raster_;
};

TEST_F(LodTolerance, ColourBreaksBeforeNormalsAndStopsDecimation) {
  // A sphere striped in colour every 0.2 units of x: collapsing vertices blurs the stripes long before
  // its (smooth) normals show the coarser faces.
  mesh::TriMesh striped = mesh::generateSphere({4});
  for (const glm::vec3& p : striped.positions) {
    const float s = std::fmod(std::floor((p.x + 2.0f) / 0.2f), 2.0f);
    striped.colors.emplace_back(s, 0.5f, 1.0f - s);
  }
  bake::LodTolerances t;
  const bake::LodResult judged = choose(striped, t, mesh::DecimatedNormals::kRecompute);
  t.color = 1.0f;  // colour not judged
  const bake::LodResult blind = choose(striped, t, mesh::DecimatedNormals::kRecompute);
  std::printf("striped sphere: colour judged %zu faces (colour %.4f, normal %.4f); not judged %zu (colour %.4f)\n",
              judged.facesAfter, judged.colorError, judged.normalError, blind.facesAfter, blind.colorError);
  EXPECT_LE(judged.colorError, bake::kDefaultLodColorTolerance);
  EXPECT_GT(blind.colorError, bake::kDefaultLodColorTolerance) << "normals and silhouette alone let colour break";
  EXPECT_GT(judged.facesAfter, blind.facesAfter);
}

TEST_F(LodTolerance, DepthBreaksBeforeNormalsAndStopsDecimation) {
  // A sphere with its exact normals authored and kept: the normal map hardly changes as faces fall,
  // but the flat faces sink below the sphere (sagitta), so the depth map is what breaks.
  mesh::TriMesh sphere = mesh::generateSphere({4});
  for (std::size_t i = 0; i < sphere.positions.size(); ++i) sphere.normals[i] = glm::normalize(sphere.positions[i]);
  bake::LodTolerances t;
  const bake::LodResult judged = choose(sphere, t, mesh::DecimatedNormals::kFromSource);
  t.depth = 1.0f;  // depth not judged
  const bake::LodResult blind = choose(sphere, t, mesh::DecimatedNormals::kFromSource);
  std::printf("sphere, kept normals: depth judged %zu faces (depth %.5f, normal %.4f); not judged %zu (depth %.5f)\n",
              judged.facesAfter, judged.depthError, judged.normalError, blind.facesAfter, blind.depthError);
  EXPECT_LE(judged.depthError, bake::kDefaultLodDepthTolerance);
  EXPECT_GT(blind.depthError, bake::kDefaultLodDepthTolerance) << "normals and silhouette alone let depth break";
  EXPECT_GT(judged.facesAfter, blind.facesAfter);
}

// The bytes atlasTextureBytes reports are the bytes the nailboard renderer's textures hold.
class AtlasMemory : public test::GlTest {};

TEST_F(AtlasMemory, ReportedBytesAreTheBytesTheGlHolds) {
  auto renderer = cel::NailboardRenderer::create();
  ASSERT_OK(renderer);
  EXPECT_EQ((*renderer)->textureBytes(), 0u);
  for (const int grid : {1, 2}) {
    for (const auto format : {bake::MapFormat::kPng, bake::MapFormat::kExr}) {
      const bool exr = format == bake::MapFormat::kExr;
      SCOPED_TRACE(std::string(exr ? "exr" : "png") + ", " + std::to_string(grid * grid) + " views");
      const test::ScopedTempDir out("puff_atlas_memory");
      auto r = bakeLumpy(out.path(), false, format, grid);
      ASSERT_OK(r);
      auto atlas = core::loadAtlas(r->sidecar);
      ASSERT_OK(atlas);
      // Two variations of 32-texel cells: 2 cells side by side (64 x 32 texels, mip levels 64x32,
      // 32x16, 16x8); with 4 views, 8 cells in 3 x 3 (96 x 96, 48 x 48, 24 x 24).
      const int w = grid == 1 ? 64 : 96, h = grid == 1 ? 32 : 96;
      ASSERT_EQ(atlas->desc.width, w);
      ASSERT_EQ(atlas->desc.height, h);
      ASSERT_EQ(atlas->desc.mipLevels, 3);
      // Per texel: the packed normal/depth/distance map (RGBA8, 4 bytes) and the colour map
      // (SRGB8_ALPHA8, 4 bytes; RGBA16F, 8 bytes, for exr). No distance texture of its own. With
      // views, the tumbling hull's field: 32 points a side (the least, for puffs under 64 texels
      // across) per variation, R16F (2 bytes).
      const std::size_t texels = static_cast<std::size_t>(w * h + (w / 2) * (h / 2) + (w / 4) * (h / 4));
      const std::size_t byHand = texels * (exr ? 12u : 8u) + (grid > 1 ? 32u * 32u * 32u * 2u * 2u : 0u);
      ASSERT_EQ(atlas->maps.count("back"), grid > 1 ? 1u : 0u);
      ASSERT_OK((*renderer)->setAtlas(*atlas));
      EXPECT_EQ((*renderer)->textureBytes(), byHand);
      EXPECT_EQ(core::atlasTextureBytes(atlas->desc), byHand);
    }
  }
}

}  // namespace
}  // namespace puff
