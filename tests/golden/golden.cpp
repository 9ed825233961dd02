#include "golden/golden.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <utility>

#include <gtest/gtest.h>

namespace puff::test {

namespace fs = std::filesystem;

fs::path referenceDir() {
  if (const char* d = std::getenv("PUFF_GOLDEN_REFERENCE_DIR"); d && *d) return d;
  return fs::path(PUFF_SOURCE_DIR) / "tests" / "golden" / "references";
}

fs::path outputDir() {
  if (const char* d = std::getenv("PUFF_GOLDEN_OUTPUT_DIR"); d && *d) return d;
  return PUFF_GOLDEN_OUT_DIR;
}

GoldenResult compareToGolden(const core::Image& actual, const std::string& name, const GoldenTolerance& tol,
                             bool writeOnFailure) {
  GoldenResult r;
  const fs::path refPath = referenceDir() / (name + ".png");
  const fs::path out = outputDir();
  auto writeActual = [&](const std::string& why) {
    r.message = name + ": " + why;
    if (!writeOnFailure) return;
    std::error_code ec;
    fs::create_directories(out, ec);
    r.actualPath = out / (name + ".actual.png");
    auto w = core::writeImage(r.actualPath, actual, core::PixelType::kUInt8);
    r.message = name + ": " + why + "; actual image: " + (w ? r.actualPath.string() : w.error().message);
  };
  if (!fs::exists(refPath)) {
    writeActual("no reference " + refPath.string() + " (accept with tests/golden/accept.sh)");
    return r;
  }
  auto ref = core::readImage(refPath);
  if (!ref) {
    writeActual(ref.error().message);
    return r;
  }
  if (ref->width != actual.width || ref->height != actual.height || ref->channels != actual.channels) {
    std::ostringstream s;
    s << "size " << actual.width << "x" << actual.height << "x" << actual.channels << " differs from the reference's "
      << ref->width << "x" << ref->height << "x" << ref->channels;
    writeActual(s.str());
    return r;
  }
  // Compare as the file stores it: quantize the actual image to 8 bits first.
  core::Image diff(actual.width, actual.height, 3);
  std::size_t failing = 0;
  for (int y = 0; y < actual.height; ++y) {
    for (int x = 0; x < actual.width; ++x) {
      float worst = 0.0f;
      for (int c = 0; c < actual.channels; ++c) {
        const float a = std::round(std::clamp(actual.at(x, y, c), 0.0f, 1.0f) * 255.0f) / 255.0f;
        worst = std::max(worst, std::abs(a - ref->at(x, y, c)));
      }
      r.maxDifference = std::max(r.maxDifference, worst);
      const bool fails = worst > tol.pixelThreshold;
      failing += fails;
      // Diff image: failing pixels red (brighter for larger differences), the rest a dim grey.
      const float grey =
          0.25f * (actual.channels >= 3 ? (actual.at(x, y, 0) + actual.at(x, y, 1) + actual.at(x, y, 2)) / 3.0f
                                        : actual.at(x, y, 0));
      diff.at(x, y, 0) = fails ? 0.5f + 0.5f * std::min(1.0f, worst * 4.0f) : grey;
      diff.at(x, y, 1) = fails ? 0.0f : grey;
      diff.at(x, y, 2) = fails ? 0.0f : grey;
    }
  }
  r.failingFraction = static_cast<double>(failing) / (static_cast<double>(actual.width) * actual.height);
  r.passed = r.failingFraction <= tol.maxFailingFraction;
  if (r.passed && writeOnFailure) {
    // A stale failure's images would be taken for this run's by tests/golden/accept.sh.
    std::error_code ec;
    fs::remove(out / (name + ".actual.png"), ec);
    fs::remove(out / (name + ".diff.png"), ec);
  }
  if (!r.passed) {
    std::ostringstream s;
    s << r.failingFraction * 100.0 << "% of pixels differ by more than " << tol.pixelThreshold * 255.0f
      << "/255 (allowed " << tol.maxFailingFraction * 100.0 << "%), max difference " << r.maxDifference * 255.0f
      << "/255";
    writeActual(s.str());
    if (!writeOnFailure) return r;
    r.diffPath = out / (name + ".diff.png");
    auto w = core::writeImage(r.diffPath, diff, core::PixelType::kUInt8);
    r.message += "; diff image: " + (w ? r.diffPath.string() : w.error().message);
  }
  return r;
}

namespace {

// Ink: all channels below 0.06 display (black outlines; a dark band is K_a, well above).
bool isInkPixel(const core::Image& im, int x, int y) {
  for (int c = 0; c < std::min(3, im.channels); ++c) {
    if (im.at(x, y, c) >= 0.06f) return false;
  }
  return true;
}

}  // namespace

void expectSceneGolden(const core::Image& actual, const std::string& name) {
  const GoldenResult r = compareToGolden(actual, name, kSceneTolerance);
  EXPECT_TRUE(r.passed) << r.message;
  if (!r.passed) return;
  // The tolerance must see a 3% colour change, either way, on every scene.
  for (float scale : {1.03f, 0.97f}) {
    core::Image changed = actual;
    for (int y = 0; y < changed.height; ++y) {
      for (int x = 0; x < changed.width; ++x) {
        for (int c = 0; c < std::min(3, changed.channels); ++c) {
          changed.at(x, y, c) = std::clamp(changed.at(x, y, c) * scale, 0.0f, 1.0f);
        }
      }
    }
    const GoldenResult c = compareToGolden(changed, name, kSceneTolerance, false);
    EXPECT_FALSE(c.passed) << name << ": every channel x" << scale << " passes the tolerance ("
                           << c.failingFraction * 100.0 << "% of pixels fail)";
  }
  // And outlines one pixel wider, where the frame shows ink: every pixel beside ink turns to ink.
  core::Image wider = actual;
  std::size_t ink = 0;
  for (int y = 0; y < actual.height; ++y) {
    for (int x = 0; x < actual.width; ++x) {
      if (isInkPixel(actual, x, y)) {
        ++ink;
        continue;
      }
      bool beside = false;
      for (auto [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
        const int nx = x + dx, ny = y + dy;
        if (nx >= 0 && ny >= 0 && nx < actual.width && ny < actual.height && isInkPixel(actual, nx, ny)) beside = true;
      }
      if (beside) {
        for (int c = 0; c < std::min(3, actual.channels); ++c) wider.at(x, y, c) = 0.0f;
      }
    }
  }
  const double inkFraction = static_cast<double>(ink) / (static_cast<double>(actual.width) * actual.height);
  if (inkFraction >= 0.005) {  // a frame that shows outlines
    const GoldenResult c = compareToGolden(wider, name, kSceneTolerance, false);
    EXPECT_FALSE(c.passed) << name << ": outlines 1 px wider pass the tolerance (" << c.failingFraction * 100.0
                           << "% of pixels fail)";
  }
}

}  // namespace puff::test
