// Golden-image comparison for render tests, after Filament's renderdiff: each case has a
// per-pixel threshold and a failing-pixel fraction. On failure the actual image and a diff image
// are written next to each other so a person can look, and tests/golden/accept.sh copies the
// actual images over the references once they are judged right.
#pragma once

#include <filesystem>
#include <string>

#include <puff/core/image.h>

namespace puff::test {

struct GoldenTolerance {
  float pixelThreshold = 5.0f / 255.0f;  ///< a pixel fails when any channel differs by more
  double maxFailingFraction = 0.001;     ///< the case fails when more pixels than this fail
};

struct GoldenResult {
  bool passed = false;
  double failingFraction = 0.0;
  float maxDifference = 0.0f;
  std::string message;                         ///< why it failed, with the paths written
  std::filesystem::path actualPath, diffPath;  ///< written only on failure
};

/// References live in referenceDir() as CASE.png; failures write CASE.actual.png and
/// CASE.diff.png into outputDir() unless `writeOnFailure` is false. A missing reference fails (and
/// writes the actual image).
GoldenResult compareToGolden(const core::Image& actual, const std::string& caseName, const GoldenTolerance& tol = {},
                             bool writeOnFailure = true);

/// The art scenes' tolerance (scene_golden_test.cpp, media_scene_test.cpp): a pixel fails when a
/// channel differs by more than 3/255, a scene when more than 0.2% of its pixels fail. Derived from
/// what must not change, and checked on every scene by expectSceneGolden: every channel 3% brighter
/// or darker fails every scene, and outlines 1 px wider fail every scene that shows ink.
inline constexpr GoldenTolerance kSceneTolerance{3.0f / 255.0f, 0.002};

/// A rendered art scene (display values) against its reference at kSceneTolerance, then the
/// tolerance itself: the same image changed as a reviewer would notice (3% colour either way;
/// outlines one pixel wider where the frame shows ink) must fail, each as a separate expectation.
void expectSceneGolden(const core::Image& actual, const std::string& caseName);

/// $PUFF_GOLDEN_REFERENCE_DIR, else tests/golden/references in the source tree.
std::filesystem::path referenceDir();
/// $PUFF_GOLDEN_OUTPUT_DIR, else golden-out/ in the build's tests directory (PUFF_GOLDEN_OUT_DIR,
/// set by tests/CMakeLists.txt: build/tests/golden-out, where tests/golden/accept.sh looks).
std::filesystem::path outputDir();

}  // namespace puff::test
