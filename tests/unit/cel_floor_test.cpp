// The nailboards' fill-rate floor (NailboardRenderer::drawBaseline, shaders/cel/sprite.*) keeps
// the depth convention of what it bounds: Puff's depth buffer holds LINEAR depth
// ((distance - near) / (far - near), common/frame.glsl), and the floor writes the quad plane's
// linear depth as the nailboards write theirs. A perspective camera tells the two conventions
// apart: the hardware's hyperbolic window depth of the same point is far from its linear depth.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/gl_target.h"
#include "support/linear_frame.h"
#include "support/sphere_atlas.h"

namespace puff {
namespace {

class CelFloor : public test::SphereAtlasTest {
 protected:
  static constexpr int kPx = 64;
  static constexpr float kNear = 1.0f, kFar = 21.0f, kCameraZ = 10.0f;

  static void SetUpTestSuite() { setUpSphereAtlas(true); }
  void SetUp() override {
    GlTest::SetUp();
    auto r = cel::NailboardRenderer::create();
    ASSERT_OK(r);
    renderer_ = std::move(*r);
    ASSERT_TRUE(renderer_->setAtlas(*atlas_).ok());
    block_ = std::make_unique<cel::FrameBlock>();
    target_ = std::make_unique<test::OffscreenTarget>(kPx);
    ramp_ = std::make_unique<cel::Ramp>(cel::Ramp::twoTone());
  }
  void TearDown() override {
    renderer_.reset();
    block_.reset();
    target_.reset();
    ramp_.reset();
  }

  // Perspective camera on +z looking at the origin.
  static cel::Frame frame() {
    cel::Camera cam;
    cam.position = glm::vec3(0, 0, kCameraZ);
    cam.target = glm::vec3(0);
    cam.fovYDegrees = 40.0f;
    cam.nearPlane = kNear;
    cam.farPlane = kFar;
    return test::linearFrame(cam, kPx, kPx);
  }
  static float linearOfZ(float z) { return ((kCameraZ - z) - kNear) / (kFar - kNear); }

  // The depth buffer after the floor (or the nailboards) drew one puff at the origin over a
  // receiver cleared to `clearDepth`.
  std::vector<float> drawDepth(bool floor, float clearDepth) {
    target_->clear(glm::vec4(1.0f), clearDepth);
    EXPECT_OK(block_->upload(frame()));
    ramp_->bind();
    renderer_->upload(std::vector<cel::Particle>{cel::Particle{glm::vec3(0), 2.0f}});
    cel::Style style;
    style.outlines = false;
    if (floor)
      renderer_->drawBaseline(style);
    else
      renderer_->drawNailboards(style, cel::ShadePass::kLit);
    return target_->readDepth();
  }

  std::unique_ptr<cel::NailboardRenderer> renderer_;
  std::unique_ptr<cel::FrameBlock> block_;
  std::unique_ptr<test::OffscreenTarget> target_;
  std::unique_ptr<cel::Ramp> ramp_;
};

TEST_F(CelFloor, WritesTheQuadPlanesLinearDepth) {
  const std::vector<float> depth = drawDepth(true, 1.0f);
  const float d = depth[(kPx / 2) * kPx + kPx / 2];
  // The plane through the centre faces the camera: linear 0.45 there (hyperbolic would be 0.945).
  EXPECT_NEAR(d, linearOfZ(0.0f), 1e-3f);
  int written = 0;
  for (float v : depth) written += v < 1.0f ? 1 : 0;
  EXPECT_GT(written, 50);
}

TEST_F(CelFloor, PassesAndFailsTheDepthTestWhereTheNailboardsDo) {
  // A receiver just in front of the puff's plane hides the floor whole; just behind it, the floor
  // shows. The nailboards' body comes forward of the plane (up to the radius), so they still show
  // in front of the first receiver: the floor draws no more than the nailboards.
  for (float receiverZ : {0.05f, -0.05f}) {
    SCOPED_TRACE(receiverZ);
    const float clear = linearOfZ(receiverZ);
    const std::vector<float> floorDepth = drawDepth(true, clear);
    const std::vector<float> nailDepth = drawDepth(false, clear);
    int floorShown = 0, nailShown = 0;
    for (std::size_t i = 0; i < floorDepth.size(); ++i) {
      floorShown += floorDepth[i] < clear - 1e-4f ? 1 : 0;
      nailShown += nailDepth[i] < clear - 1e-4f ? 1 : 0;
    }
    if (receiverZ > 0.0f)
      EXPECT_EQ(floorShown, 0);
    else
      EXPECT_GT(floorShown, 50);
    EXPECT_GT(nailShown, 50);
  }
}

}  // namespace
}  // namespace puff
