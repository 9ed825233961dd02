// A one-variation atlas of the unit sphere, baked in-process for tests that need analytic shapes:
// its silhouette is a circle, its depth map sqrt(1/4 - r^2) diameters.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <utility>

#include <puff/bake/baker.h>
#include <puff/core/atlas.h>
#include <puff/mesh/mesh.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/temp_dir.h"

namespace puff::test {

/// Bakes into `dir` (128-texel cells, a 4-texel flange, no contact sheet; `viewGrid` x `viewGrid`
/// views laid out by `layout`) and returns the sidecar.
inline Result<std::filesystem::path> bakeSphereAtlas(const std::filesystem::path& dir, int viewGrid = 1,
                                                     bake::ViewLayout layout = bake::BakeOptions{}.viewLayout) {
  bake::BakeOptions o;
  o.cellSize = 128;
  o.flange = {4.0f, false};
  o.viewGrid = viewGrid;
  o.viewLayout = layout;
  o.outDir = dir;
  o.contactSheet = false;
  bake::PuffSource src;
  src.mesh = mesh::generateSphere({6});
  src.provenance.generator = "sphere";
  src.provenance.params = {{"subdivisions", 6}};  // what the cel reference regenerates it from
  auto r = bake::bakeAtlas({src}, o);
  if (!r) return r.error();
  return r->sidecar;
}

/// A suite of GL tests sharing one sphere atlas (bakeSphereAtlas), baked into a scratch directory
/// when the suite starts and removed with it when the suite ends: dir_ (the tests may write there
/// too) and sidecar_; atlas_ too where the suite's SetUpTestSuite calls setUpSphereAtlas(true).
/// The shared GL context stays for the next suite.
class SphereAtlasTest : public GlTest {
 protected:
  static void SetUpTestSuite() { setUpSphereAtlas(false); }
  static void TearDownTestSuite() {
    atlas_.reset();
    scratch_.reset();
  }

  /// Makes the context, bakes the atlas and, with `load`, loads it into atlas_.
  static void setUpSphereAtlas(bool load) {
    GlTest::SetUpTestSuite();
    scratch_.emplace("puff_sphere_atlas");
    dir_ = scratch_->path();
    auto sidecar = bakeSphereAtlas(dir_);
    ASSERT_OK(sidecar);
    sidecar_ = *sidecar;
    if (!load) return;
    auto atlas = core::loadAtlas(sidecar_);
    ASSERT_OK(atlas);
    atlas_ = std::make_unique<core::Atlas>(std::move(*atlas));
  }

  static inline std::filesystem::path dir_, sidecar_;
  static inline std::unique_ptr<core::Atlas> atlas_;

 private:
  static inline std::optional<ScopedTempDir> scratch_;
};

}  // namespace puff::test
