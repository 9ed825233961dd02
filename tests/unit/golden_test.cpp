// The golden-image helper itself: thresholds, failing fractions, and the files it writes.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "golden/golden.h"
#include "support/temp_dir.h"

namespace puff::test {
namespace {

namespace fs = std::filesystem;

class Golden : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(root_ / "refs");
    for (const char* name : {"PUFF_GOLDEN_REFERENCE_DIR", "PUFF_GOLDEN_OUTPUT_DIR"}) {
      const char* v = std::getenv(name);
      saved_.emplace_back(name, v ? std::optional<std::string>(v) : std::nullopt);
    }
    setenv("PUFF_GOLDEN_REFERENCE_DIR", (root_ / "refs").c_str(), 1);
    setenv("PUFF_GOLDEN_OUTPUT_DIR", (root_ / "out").c_str(), 1);
    ref_ = core::Image(20, 10, 3, 0.5f);
    ASSERT_TRUE(core::writeImage(root_ / "refs" / "case.png", ref_, core::PixelType::kUInt8).ok());
  }
  // Puts back what the process had (tests/mutation/run.py points the output elsewhere: the tests
  // after these must keep writing there).
  void TearDown() override {
    for (const auto& [name, value] : saved_) {
      if (value) {
        setenv(name.c_str(), value->c_str(), 1);
      } else {
        unsetenv(name.c_str());
      }
    }
  }
  std::vector<std::pair<std::string, std::optional<std::string>>> saved_;
  ScopedTempDir root_{"puff_golden_test"};
  core::Image ref_;
};

TEST_F(Golden, PassesWithinThresholdAndWritesNothing) {
  core::Image a = ref_;
  a.at(3, 3, 1) += 4.0f / 255.0f;  // under the 5/255 threshold
  GoldenResult r = compareToGolden(a, "case");
  EXPECT_TRUE(r.passed) << r.message;
  EXPECT_FALSE(fs::exists(root_ / "out" / "case.actual.png"));
}

TEST_F(Golden, FailingFractionDecidesAndFailureWritesActualAndDiff) {
  core::Image a = ref_;
  a.at(3, 3, 0) = 1.0f;  // one pixel of 200 = 0.5%
  GoldenResult strict = compareToGolden(a, "case", {5.0f / 255.0f, 0.001});
  EXPECT_FALSE(strict.passed);
  EXPECT_NEAR(strict.failingFraction, 1.0 / 200.0, 1e-12);
  EXPECT_NEAR(strict.maxDifference, 127.0f / 255.0f, 1.5f / 255.0f);
  EXPECT_TRUE(fs::exists(strict.actualPath));
  EXPECT_TRUE(fs::exists(strict.diffPath));
  auto diff = core::readImage(strict.diffPath);
  ASSERT_TRUE(diff.ok());
  EXPECT_GT(diff->at(3, 3, 0), 0.5f);
  EXPECT_EQ(diff->at(3, 3, 1), 0.0f);
  GoldenResult lenient = compareToGolden(a, "case", {5.0f / 255.0f, 0.01});
  EXPECT_TRUE(lenient.passed) << lenient.message;
}

TEST_F(Golden, MissingReferenceOrWrongSizeFails) {
  GoldenResult missing = compareToGolden(ref_, "absent");
  EXPECT_FALSE(missing.passed);
  EXPECT_NE(missing.message.find("no reference"), std::string::npos);
  EXPECT_TRUE(fs::exists(root_ / "out" / "absent.actual.png"));
  GoldenResult size = compareToGolden(core::Image(10, 10, 3, 0.5f), "case");
  EXPECT_FALSE(size.passed);
  EXPECT_NE(size.message.find("differs from the reference"), std::string::npos);
}

}  // namespace
}  // namespace puff::test
