// The tumble suites' fixtures (tumble_test.cpp, tumble_split_test.cpp): atlases of the art's puffs
// baked with multi-view layouts, and scenes of a few oriented puffs drawn by the cel path.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include <glm/glm.hpp>

#include <puff/bake/baker.h>
#include <puff/core/atlas.h>
#include <puff/eval/budget.h>
#include <puff/eval/cel_reference.h>
#include <puff/eval/tumble.h>
#include <puff/reference/metrics.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include <nlohmann/json.hpp>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/sphere_atlas.h"

namespace puff::tumble {

namespace fs = std::filesystem;

// An atlas's views, the tumble method (cel::Style::tumble), and the floors its sweep must keep:
// coverage IoU (worst pose, mean over the poses) and outline IoU (worst, mean). The bars are
// coverage >= 0.95 and outline >= 0.5 at every pose; the floors are at least the coverage bar
// where it is met, and else what this code measured on the suite's sample (48-px puffs,
// point-sampled, four rolls) less about 0.01 (coverage) and 0.03 (outline): they catch a change that
// turns puffs worse. The hull meets both bars at every atlas here (worst coverage on the sample
// 0.962-0.986, worst outline 0.704-0.912; hemi-oct 3 x 3, nine views of one hemisphere, is the
// loosest hull and keeps its earlier floors). The baked front view itself, unturned, reaches
// 0.974-0.979 against the mesh at this size, where a pixel all around the silhouette is about 10% of
// a puff's pixels. docs/cel-rendering.md, "Tumbling puffs", and docs/report/README.md have the whole
// sweep's numbers. The blend is kept for its cost (about a fifth of the hull's on llvmpipe) and
// guarded at two atlases.
struct Config {
  bake::ViewLayout layout;
  int grid;
  double minCoverage, meanCoverage, minOutline, meanOutline;
  cel::TumbleMethod method = cel::TumbleMethod::kHull;
};

inline std::string name(const Config& c) {
  return std::string(c.layout == bake::ViewLayout::kOct ? "oct" : "hemioct") + std::to_string(c.grid) +
         (c.method == cel::TumbleMethod::kBlend ? "_blend" : "");
}

// Each suite bakes into its own directory, removed when the suite ends.
class TumbleBase : public test::GlSuite<> {
 protected:
  static void SetUpTestSuite() {
    GlSuite::SetUpTestSuite();
    hemi_.clear();
    // (A parameterized suite's name holds a '/': one directory, not two.)
    std::string suite = ::testing::UnitTest::GetInstance()->current_test_suite()->name();
    std::replace(suite.begin(), suite.end(), '/', '-');
    dir_ = fs::temp_directory_path() / ("puff-tumble-" + suite + "-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
    references_.clear();
    hemi_.clear();
    GlSuite::TearDownTestSuite();
  }

  // The art's four puffs baked at 128 texels a cell with `c`'s views.
  static fs::path atlasFor(const Config& c) {
    std::vector<fs::path> meshes;
    for (const char* m : {"variation-1.obj", "variation-2.ply", "variation-3.off", "variation-4.stl"})
      meshes.push_back(fs::path(PUFF_SOURCE_DIR) / "art" / "puffs" / m);
    auto sources = bake::loadSources(meshes, std::nullopt);
    EXPECT_OK(sources);
    bake::BakeOptions o;
    o.cellSize = 128;
    o.viewGrid = c.grid;
    o.viewLayout = c.layout;
    o.outDir = dir_ / name(c);
    o.contactSheet = false;
    auto r = bake::bakeAtlas(*sources, o);
    EXPECT_OK(r);
    return r ? r->sidecar : fs::path();
  }

  // The reference depends on the meshes only: drawn once, with the first atlas baked.
  static const eval::TumbleReference& reference(const fs::path& atlas) {
    if (references_.empty()) {
      // Yaw and pitch on options()'s grid, at kRolls (the report sweeps roll every 15 degrees:
      // docs/report, tumble.csv).
      auto r = eval::renderTumbleReference(atlas, options(), {kRolls.begin(), kRolls.end()});
      EXPECT_OK(r);
      references_.emplace(0, std::move(*r));
    }
    return references_.at(0);
  }

  // The suite's sample of the sweep: yaw and pitch every 30 degrees offset by 15, one pose in each
  // 30-degree square of the report's 15-degree grid (tests/bench/report.sh sweeps every pose at
  // every roll), each between the poses of a 30-degree grid, at the four rolls of reference().
  // Rolls: none, a diagonal (a rolled quad reaches farthest past its cell), a half turn (the views
  // across the ray are the other sides') and a quarter turn the other way.
  static constexpr std::array<int, 4> kRolls = {0, 45, 180, 270};

  static eval::TumbleOptions options() {
    eval::TumbleOptions o;
    o.stepDegrees = 30;
    o.offsetDegrees = 15;
    o.puffPixels = 48;
    return o;
  }

  static inline fs::path dir_;
  static inline std::map<int, eval::TumbleReference> references_;
  static inline fs::path hemi_;
};

// ---- what a tumbling puff must never show ---------------------------------------------------------

// Both ways of drawing a tumbling puff (cel::Style::tumble) must keep what follows.
inline constexpr const char* kMethods[] = {"hull", "blend"};

// One hemi-oct 5 x 5 atlas of the art's puffs; scenes of a few oriented puffs drawn by the cel path.
class TumbleCases : public TumbleBase {
 public:
  // One oriented puff of `variation` at the origin, 1 unit across, turned by `degrees` about `axis`.
  static nlohmann::json puff(int variation, glm::vec3 axis, float degrees) {
    return {{"position", {0, 0, 0}},
            {"size", 1.0},
            {"variation", variation},
            {"oriented", true},
            {"orientation", {{"axis", {axis.x, axis.y, axis.z}}, {"degrees", degrees}}}};
  }

 protected:
  static fs::path hemiAtlas() {
    if (hemi_.empty()) hemi_ = atlasFor(Config{bake::ViewLayout::kHemiOct, 5, 0.0, 0.0, 0.0, 0.0});
    return hemi_;
  }

  // 160 px a puff diameter, orthographic camera on +z, the light from the camera (every surface the
  // camera sees faces it: the lit band), outlines 2 px.
  static nlohmann::json sceneJson(const fs::path& atlas, const nlohmann::json& particles,
                                  const nlohmann::json& objects = nlohmann::json::array(),
                                  const char* tumble = "hull") {
    return {
        {"output", {{"width", 240}, {"height", 240}, {"samples", 1}, {"background", {0.9, 0.9, 0.9}}}},
        {"camera",
         {{"position", {0, 0, 20}},
          {"target", {0, 0, 0}},
          {"up", {0, 1, 0}},
          {"fovY", 0},
          {"orthoHeight", 1.5},
          {"near", 1},
          {"far", 40}}},
        {"light", {{"direction", {0, 0, 1}}, {"color", {0.5, 0.5, 0.5}}}},
        {"ambient", {{"color", {0.3, 0.3, 0.3}}}},
        {"atlas", atlas.string()},
        {"style", {{"outlines", true}, {"outlineWidth", 2}, {"shading", true}, {"shadows", false}, {"tumble", tumble}}},
        {"particles", particles},
        {"objects", objects}};
  }

  static Result<core::Image> render(const nlohmann::json& j) {
    PUFF_TRY_ASSIGN(auto scene, scene::parseScene(j, dir_ / "case.json"));
    PUFF_TRY_ASSIGN(auto r, render::SceneRenderer::create(scene));
    return (r)->renderFrame(0);
  }

  // The cel reference's frame of scene `j` (the meshes turned).
  static std::optional<core::Image> referenceFrame(const nlohmann::json& j) {
    auto scene = scene::parseScene(j, dir_ / "case.json");
    EXPECT_OK(scene);
    if (!scene) return std::nullopt;
    auto ref = eval::createCelReference(*scene, eval::CelReferenceOptions{.supersample = 1});
    EXPECT_OK(ref);
    if (!ref) return std::nullopt;
    auto image = (*ref)->renderFrame(0);
    EXPECT_OK(image);
    if (!image) return std::nullopt;
    return std::move(*image);
  }

  // The coverage IoU of the nailboards' frame of scene `j` against `reference`, the cel reference's
  // frame of it (referenceFrame; the background: the reference's corner pixel).
  static double coverageAgainst(const nlohmann::json& j, const core::Image& reference, core::Image* drawn = nullptr) {
    auto cel = render(j);
    EXPECT_OK(cel);
    if (!cel) return 0.0;
    core::Image background = reference;
    for (int y = 0; y < background.height; ++y)
      for (int x = 0; x < background.width; ++x)
        for (int c = 0; c < 4; ++c) background.at(x, y, c) = reference.at(0, 0, c);
    if (drawn) *drawn = *cel;
    return reference::coverageIoU(*cel, reference, background);
  }

  // The same against the reference's frame of `j` itself.
  static double coverageAgainstReference(const nlohmann::json& j, core::Image* drawn = nullptr) {
    const std::optional<core::Image> reference = referenceFrame(j);
    return reference ? coverageAgainst(j, *reference, drawn) : 0.0;
  }

  static bool isBackground(const core::Image& im, int x, int y) {
    return std::abs(im.at(x, y, 0) - im.at(0, 0, 0)) < 0.01f && std::abs(im.at(x, y, 1) - im.at(0, 0, 1)) < 0.01f &&
           std::abs(im.at(x, y, 2) - im.at(0, 0, 2)) < 0.01f;
  }
};

}  // namespace puff::tumble
