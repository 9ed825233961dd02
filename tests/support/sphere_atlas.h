// The sphere atlas (sphere_bake.h) shared by a suite: the build bakes it once
// (bake_sphere_atlas.cpp, into PUFF_TEST_SPHERE_ATLAS_DIR) and each suite copies it.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <utility>

#include <puff/core/atlas.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/sphere_bake.h"
#include "support/temp_dir.h"

namespace puff::test {

/// A suite of GL tests sharing one sphere atlas (bakeSphereAtlas), copied from the build's into a
/// scratch directory when the suite starts and removed with it when the suite ends: dir_ (the tests may write there
/// too) and sidecar_; atlas_ too where the suite's SetUpTestSuite calls setUpSphereAtlas(true).
/// The shared GL context stays for the next suite.
class SphereAtlasTest : public GlTest {
 protected:
  static void SetUpTestSuite() { setUpSphereAtlas(false); }
  static void TearDownTestSuite() {
    atlas_.reset();
    scratch_.reset();
  }

  /// Makes the context, copies the build's atlas and, with `load`, loads it into atlas_.
  static void setUpSphereAtlas(bool load) {
    GlTest::SetUpTestSuite();
    scratch_.emplace("puff_sphere_atlas");
    dir_ = scratch_->path();
    const std::filesystem::path built = PUFF_TEST_SPHERE_ATLAS_DIR;
    std::error_code error;
    std::filesystem::copy(built, dir_, std::filesystem::copy_options::recursive, error);
    ASSERT_FALSE(error) << "copying the sphere atlas from " << built << ": " << error.message();
    sidecar_ = dir_ / (bake::BakeOptions{}.name + ".json");
    ASSERT_TRUE(std::filesystem::is_regular_file(sidecar_)) << sidecar_ << " (tests/support/bake_sphere_atlas.cpp)";
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
