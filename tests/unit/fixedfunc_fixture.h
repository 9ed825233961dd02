// What fixedfunc_test.cpp and fixedfunc_draw_test.cpp share: the OSMesa compatibility context
// they draw into (the FixedFuncTest fixture), a frame looking down -z, and small helpers.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <puff/gl_api.h>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/fixedfunc/renderer.h>
#include <puff/mesh/mesh.h>
#include <puff/platform/gl_context.h>

#include "support/skip.h"

namespace puff::fixedfunc::test {

inline constexpr int kSize = 256;  // the OSMesa default framebuffer the tests draw into
inline constexpr float kFovY = 60.0f;

inline Result<std::unique_ptr<core::GlContext>> makeCompatContext(int major, int minor) {
  core::GlContextOptions options;
  options.backend = "osmesa";  // a default framebuffer with alpha to draw into, as a host's window
  options.profile = core::GlProfile::kCompatibility;
  options.major = major;
  options.minor = minor;
  options.width = kSize;
  options.height = kSize;
  return core::createGlContext(options);
}

inline FixedFrame makeFrame() {
  FixedFrame f;
  f.view = glm::mat4(1.0f);  // camera at the origin looking down -z
  f.projection = glm::perspective(glm::radians(kFovY), 1.0f, 0.1f, 100.0f);
  f.viewport = {0, 0, kSize, kSize};
  f.lightDirection = {1.0f, 0.0f, 0.0f};  // +x of the camera
  f.lightColor = {1.0f, 0.8f, 0.6f};
  f.ambientColor = {0.1f, 0.05f, 0.0f};
  f.background = {0.6f, 0.75f, 0.95f, 1.0f};
  return f;
}

inline core::Image twoToneRamp(float low, float high) {
  core::Image ramp(2, 1, 1);
  ramp.at(0, 0) = low;
  ramp.at(1, 0) = high;
  return ramp;
}

inline mesh::TriMesh unitSphere() {
  mesh::SphereParams p;
  p.subdivisions = 4;
  return mesh::generateSphere(p);
}

/// The current framebuffer, RGBA floats, row 0 at the bottom.
inline std::vector<glm::vec4> readFramebuffer() {
  std::vector<glm::vec4> px(static_cast<std::size_t>(kSize) * kSize);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, kSize, kSize, GL_RGBA, GL_FLOAT, px.data());
  return px;
}

class FixedFuncTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (context_) return;
    auto c = makeCompatContext(2, 1);
    if (!c) {
      skipReason_ = c.error().message;
      return;
    }
    context_ = std::move(*c);
  }
  static void TearDownTestSuite() { context_.reset(); }
  void SetUp() override {
    if (!context_) PUFF_SKIP_UNLESS_CI("no OSMesa compatibility context: " << skipReason_);
    context_->makeCurrent();
    glViewport(0, 0, kSize, kSize);
    while (glGetError() != GL_NO_ERROR) {
    }
  }
  static inline std::unique_ptr<core::GlContext> context_;
  static inline std::string skipReason_;
};

}  // namespace puff::fixedfunc::test
