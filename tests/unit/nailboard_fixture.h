// The nailboard tests' fixture: a renderer with the sphere atlas, an orthographic camera and a target.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/cel/types.h>

#include "support/assert_ok.h"
#include "support/gl_target.h"
#include "support/linear_frame.h"
#include "support/sphere_atlas.h"

namespace puff::nailboard_test {

using cel::Particle;

// The nailboard tests clear to white and to the depth of a receiving plane.
struct Target : test::OffscreenTarget {
  explicit Target(int n) : OffscreenTarget(n) {}
  void clear(float depthValue, glm::vec3 bg = glm::vec3(1.0f)) const {
    OffscreenTarget::clear(glm::vec4(bg, 1.0f), depthValue);
  }
};

// The sphere atlas, an orthographic camera (so world and pixel sizes map exactly), and receivers made
// by clearing the linear depth buffer to a known plane.
class Nailboards : public test::SphereAtlasTest {
 protected:
  static constexpr int kPx = 128;        // target size
  static constexpr float kWorld = 8.0f;  // orthographic view height (and width): 16 px per unit

  static void SetUpTestSuite() { setUpSphereAtlas(true); }
  void SetUp() override {
    GlTest::SetUp();
    auto r = cel::NailboardRenderer::create();
    ASSERT_OK(r);
    renderer_ = std::move(*r);
    ASSERT_TRUE(renderer_->setAtlas(*atlas_).ok());
    block_ = std::make_unique<cel::FrameBlock>();
    target_ = std::make_unique<Target>(kPx);
    ramp_ = std::make_unique<cel::Ramp>(cel::Ramp::twoTone());
  }
  void TearDown() override {
    renderer_.reset();
    block_.reset();
    target_.reset();
    ramp_.reset();
  }

  // Orthographic camera on +z looking down -z; world (x, y) maps to pixel (64 + 16x, 64 + 16y).
  cel::Frame orthoFrame() const {
    cel::Camera cam;
    cam.position = glm::vec3(0, 0, 10);
    cam.target = glm::vec3(0);
    cam.fovYDegrees = 0.0f;
    cam.orthoHeight = kWorld;
    cam.nearPlane = 1.0f;
    cam.farPlane = 21.0f;
    cel::Frame f = test::linearFrame(cam, kPx, kPx);
    f.light.direction = glm::vec3(0, 0, 1);
    f.light.color = puff::core::srgbToLinear(glm::vec3(0.5f));
    f.ambient = puff::core::srgbToLinear(glm::vec3(0.2f));
    return f;
  }
  static glm::vec2 pixelToWorld(int x, int y) {
    const float scale = kWorld / kPx;
    return {(x + 0.5f - kPx / 2.0f) * scale, (y + 0.5f - kPx / 2.0f) * scale};
  }
  // Linear depth of world z for orthoFrame (camera at z = 10, near 1, far 21).
  static float depthOfZ(float z) { return ((10.0f - z) - 1.0f) / 20.0f; }

  void draw(const cel::Frame& f, const std::vector<Particle>& ps, const cel::Style& style, float clearDepth = 1.0f) {
    target_->clear(clearDepth);
    EXPECT_OK(block_->upload(f));
    ramp_->bind();
    renderer_->upload(ps);
    renderer_->drawNailboards(style, cel::ShadePass::kLit);
  }

  std::unique_ptr<cel::NailboardRenderer> renderer_;
  std::unique_ptr<cel::FrameBlock> block_;
  std::unique_ptr<Target> target_;
  std::unique_ptr<cel::Ramp> ramp_;
};

}  // namespace puff::nailboard_test
