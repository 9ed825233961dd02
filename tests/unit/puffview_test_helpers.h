// What the puffview tests share (puffview_test.cpp, puffview_window_test.cpp): the skip for tests
// that open a window where there is no display, and comparisons of window images.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <string>

#include <glm/vec3.hpp>

#include <puff/core/image.h>

namespace puff::view::test {

inline bool displayRequired() {
  const char* v = std::getenv("PUFF_TEST_REQUIRE_GLFW");
  return v != nullptr && std::string(v) == "1";
}
inline bool haveDisplay() { return std::getenv("DISPLAY") != nullptr || std::getenv("WAYLAND_DISPLAY") != nullptr; }

// Share of pixels whose R, G and B all lie within `tolerance` (0-255 steps) of the other image's.
inline double shareWithin(const core::Image& a, const core::Image& b, int tolerance) {
  std::size_t good = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      bool ok = true;
      for (int c = 0; c < 3; ++c) ok = ok && std::abs(a.at(x, y, c) - b.at(x, y, c)) * 255.0f <= tolerance + 0.5f;
      good += ok ? 1 : 0;
    }
  }
  return static_cast<double>(good) / (static_cast<double>(a.width) * a.height);
}

inline glm::vec3 rgb(const core::Image& image, int x, int y) {
  return {image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2)};
}

}  // namespace puff::view::test

/// Skips the test where there is no display, unless PUFF_TEST_REQUIRE_GLFW=1 (set by ctest under Xvfb) requires one.
#define PUFFVIEW_NEEDS_DISPLAY()                                                              \
  do {                                                                                        \
    if (!::puff::view::test::displayRequired() && !::puff::view::test::haveDisplay())         \
      GTEST_SKIP() << "no display; ctest runs this under Xvfb with PUFF_TEST_REQUIRE_GLFW=1"; \
  } while (0)
