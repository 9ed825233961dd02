// Opaque objects' shadow volumes (OpaqueRenderer::drawShadowVolumes): the stencil count they leave
// on the receivers against the exact answer, a ray from the receiver toward the light that hits the
// caster (ray / box and ray / square tests).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/opaque.h>
#include <puff/cel/volume_clip.h>
#include <puff/gl_api.h>
#include <puff/mesh/mesh.h>
#include <puff/render/cel_scene.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/gl_target.h"
#include "support/linear_frame.h"

namespace puff::cel::opaque_volume {
namespace {

constexpr int kSize = 160;

std::shared_ptr<const TriangleMesh> plane() { return render::toTriangleMesh(mesh::makePlane()); }
std::shared_ptr<const TriangleMesh> box() { return render::toTriangleMesh(mesh::makeBox()); }
std::shared_ptr<const TriangleMesh> sphere() { return render::toTriangleMesh(mesh::makeSphere(64)); }

OpaqueObject object(std::shared_ptr<const TriangleMesh> mesh, const glm::mat4& transform) {
  OpaqueObject o;
  o.mesh = std::move(mesh);
  o.transform = transform;
  return o;
}

// Where the ray o + t d (t > 0) enters the box [lo, hi], if it does.
std::optional<float> rayBox(const glm::vec3& o, const glm::vec3& d, const glm::vec3& lo, const glm::vec3& hi) {
  float t0 = 0.0f, t1 = 1e30f;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-12f) {
      if (o[a] < lo[a] || o[a] > hi[a]) return std::nullopt;
      continue;
    }
    float ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  if (t1 < t0) return std::nullopt;
  return t0;
}

class OpaqueVolumes : public test::GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    if (HasFatalFailure()) return;
    auto r = OpaqueRenderer::create();
    ASSERT_OK(r);
    renderer_ = std::move(*r);
    block_ = std::make_unique<FrameBlock>();
    ramp_ = std::make_unique<Ramp>(Ramp::twoTone());
    target_ = std::make_unique<test::OffscreenTarget>(kSize);
  }
  void TearDown() override {
    EXPECT_EQ(core::drainGlErrors(), "");
    renderer_.reset();
    block_.reset();
    ramp_.reset();
    target_.reset();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  static Frame camera(const glm::vec3& at, const glm::vec3& lightToward) {
    Camera c;
    c.position = at;
    c.target = {0.0f, 0.6f, 0.0f};
    c.fovYDegrees = 45.0f;
    c.nearPlane = 0.5f;
    c.farPlane = 30.0f;
    Frame f = test::linearFrame(c, kSize, kSize);
    f.light.direction = glm::normalize(lightToward);
    return f;
  }

  // Draws the objects' depth, then their volumes; returns the stencil (row 0 at the bottom).
  std::vector<unsigned char> countVolumes(const Frame& f, std::vector<OpaqueObject> objects) {
    EXPECT_TRUE(renderer_->setObjects(std::move(objects)).ok());
    EXPECT_OK(block_->upload(f));
    ramp_->bind();
    target_->clear(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    renderer_->draw(ShadePass::kLit);
    Style style;
    style.shadowLength = 20.0f;
    renderer_->drawShadowVolumes(style);
    return target_->readStencil();
  }

  // The world point each pixel's centre ray meets first among `hit` (a ray -> t function), if any.
  template <class Hit>
  static std::optional<glm::vec3> pixelHit(const Frame& f, int x, int y, Hit hit) {
    const glm::mat4 inv = glm::inverse(f.projection * f.view);
    const glm::vec2 ndc((x + 0.5f) / kSize * 2.0f - 1.0f, (y + 0.5f) / kSize * 2.0f - 1.0f);
    const glm::vec4 n = inv * glm::vec4(ndc, -1.0f, 1.0f), far = inv * glm::vec4(ndc, 1.0f, 1.0f);
    const glm::vec3 o = glm::vec3(n) / n.w, d = glm::normalize(glm::vec3(far) / far.w - o);
    const std::optional<float> t = hit(o, d);
    if (!t) return std::nullopt;
    return o + *t * d;
  }

  std::unique_ptr<OpaqueRenderer> renderer_;
  std::unique_ptr<FrameBlock> block_;
  std::unique_ptr<Ramp> ramp_;
  std::unique_ptr<test::OffscreenTarget> target_;
};

// A box hovering over the floor: the floor's shadowed pixels are exactly the floor points whose
// ray toward the light meets the box (IoU >= 0.95), straight down and at angles; the box's own
// faces toward the light are lit and those turned away are in shadow.
TEST_F(OpaqueVolumes, BoxShadowOnTheFloorIsItsProjectionAlongTheLight) {
  const glm::vec3 lo(-0.6f, 1.0f, -0.5f), hi(0.6f, 1.8f, 0.5f);
  const glm::mat4 boxTransform = glm::scale(glm::translate(glm::mat4(1.0f), 0.5f * (lo + hi)), 0.5f * (hi - lo));
  for (const glm::vec3& light :
       {glm::vec3(0, 1, 0), glm::vec3(0.5f, 1.0f, 0.3f), glm::vec3(-0.8f, 1.0f, -0.6f), glm::vec3(0.2f, 0.4f, 1.0f)}) {
    SCOPED_TRACE(testing::Message() << "light " << light.x << " " << light.y << " " << light.z);
    const Frame f = camera({4.0f, 5.0f, 6.0f}, light);
    const glm::vec3 L = f.light.direction;
    const auto stencil = countVolumes(
        f, {object(plane(), glm::scale(glm::mat4(1.0f), glm::vec3(30, 1, 30))), object(box(), boxTransform)});
    int both = 0, either = 0, floor = 0, faceWrong = 0, faces = 0;
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        const bool shadowed = stencil[static_cast<std::size_t>(y) * kSize + x] != 0;
        // What the pixel sees: the box if its ray meets it, else the floor.
        const auto boxHit = pixelHit(f, x, y, [&](glm::vec3 o, glm::vec3 d) { return rayBox(o, d, lo, hi); });
        if (boxHit) {
          // The face it lies on; light-facing faces lit, faces turned away shadowed (edges left out).
          const glm::vec3 rel = (*boxHit - 0.5f * (lo + hi)) / (0.5f * (hi - lo));
          int axis = 0;
          for (int a = 1; a < 3; ++a) axis = std::abs(rel[a]) > std::abs(rel[axis]) ? a : axis;
          bool nearEdge = false;
          for (int a = 0; a < 3; ++a) nearEdge = nearEdge || (a != axis && std::abs(rel[a]) > 0.93f);
          glm::vec3 n(0.0f);
          n[axis] = rel[axis] > 0 ? 1.0f : -1.0f;
          const float nl = glm::dot(n, L);
          if (nearEdge || std::abs(nl) < 0.05f) continue;
          ++faces;
          faceWrong += shadowed != (nl < 0.0f) ? 1 : 0;
          continue;
        }
        const auto floorHit = pixelHit(f, x, y, [](glm::vec3 o, glm::vec3 d) -> std::optional<float> {
          if (d.y >= 0.0f) return std::nullopt;
          return -o.y / d.y;
        });
        if (!floorHit) continue;
        ++floor;
        const bool expected = rayBox(*floorHit, L, lo, hi).has_value();
        both += expected && shadowed ? 1 : 0;
        either += expected || shadowed ? 1 : 0;
      }
    }
    EXPECT_GT(floor, kSize * kSize / 3);
    ASSERT_GT(either, 300);
    EXPECT_GE(static_cast<double>(both) / either, 0.95) << both << " of " << either;
    EXPECT_GT(faces, 200);
    EXPECT_LE(faceWrong, faces / 200) << "box face pixels shadowed wrongly";
  }
}

// An open mesh casts: a square plane above a sphere, facing the light or turned away from it,
// shadows the sphere's lit side exactly where a ray toward the light meets the square.
TEST_F(OpaqueVolumes, OpenPlaneShadowsASphereWhicheverWayItFaces) {
  const float half = 0.55f, height = 2.2f;
  for (bool flipped : {false, true}) {
    for (const glm::vec3& light : {glm::vec3(0, 1, 0), glm::vec3(0.4f, 1.0f, -0.2f)}) {
      SCOPED_TRACE(testing::Message() << (flipped ? "flipped, " : "") << "light " << light.x << " " << light.z);
      const Frame f = camera({3.0f, 4.0f, 4.5f}, light);
      const glm::vec3 L = f.light.direction;
      glm::mat4 square = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(0, height, 0)), glm::vec3(half, 1, half));
      if (flipped) square = glm::rotate(square, glm::radians(180.0f), glm::vec3(1, 0, 0));
      const auto stencil = countVolumes(f, {object(sphere(), glm::mat4(1.0f)), object(plane(), square)});
      int both = 0, either = 0, lit = 0;
      for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
          // The sphere where the pixel sees it (not where the square, a little widened, hides it).
          const auto hit = pixelHit(f, x, y, [&](glm::vec3 o, glm::vec3 d) -> std::optional<float> {
            const float b = glm::dot(o, d), c = glm::dot(o, o) - 1.0f, disc = b * b - c;
            if (disc < 0.0f) return std::nullopt;
            const float ts = -b - std::sqrt(disc), tp = (height - o.y) / d.y;
            const glm::vec3 q = o + tp * d;
            if (tp > 0.0f && tp < ts && std::abs(q.x) < half + 0.05f && std::abs(q.z) < half + 0.05f) {
              return std::nullopt;
            }
            return ts;
          });
          if (!hit) continue;
          // The sphere's lit side only (its far side is in its own shadow), away from the terminator.
          if (glm::dot(*hit, L) < 0.15f) continue;
          ++lit;
          const float t = (height - hit->y) / L.y;
          const glm::vec3 p = *hit + t * L;
          const bool expected = std::abs(p.x) < half && std::abs(p.z) < half;
          const bool shadowed = stencil[static_cast<std::size_t>(y) * kSize + x] != 0;
          both += expected && shadowed ? 1 : 0;
          either += expected || shadowed ? 1 : 0;
        }
      }
      EXPECT_GT(lit, 1000);
      ASSERT_GT(either, 200);
      EXPECT_GE(static_cast<double>(both) / either, 0.95) << both << " of " << either;
    }
  }
}

// The volume passes' clip: an orthographic camera on +z (8 units tall over 128 pixels, near 1,
// far 21 from z = 10) sees the box [-1, 2] x [0, 1] x [-3, 4] as pixels [48, 96) x [64, 80) and
// linear depths (10 - 4 - 1) / 20 to (10 + 3 - 1) / 20; a box reaching behind the eye clips
// nothing; a box off screen draws nothing.
TEST(VolumeClip, IsTheReceiversBoxOnScreenAndInDepth) {
  Camera cam;
  cam.position = glm::vec3(0, 0, 10);
  cam.target = glm::vec3(0);
  cam.fovYDegrees = 0.0f;
  cam.orthoHeight = 8.0f;
  cam.nearPlane = 1.0f;
  cam.farPlane = 21.0f;
  const Frame f = test::linearFrame(cam, 128, 128);
  Bounds b;
  b.add(glm::vec3(-1, 0, -3));
  b.add(glm::vec3(2, 1, 4));
  const VolumeClip c = volumeClip(f, b);
  EXPECT_FALSE(c.everything);
  EXPECT_FALSE(c.nothing);
  EXPECT_EQ(c.scissor.x, 48);
  EXPECT_EQ(c.scissor.y, 64);
  EXPECT_EQ(c.scissor.width, 48);
  EXPECT_EQ(c.scissor.height, 16);
  EXPECT_NEAR(c.depthMin, 5.0f / 20.0f, 1e-6f);
  EXPECT_NEAR(c.depthMax, 12.0f / 20.0f, 1e-6f);
  EXPECT_TRUE(volumeClip(f, Bounds{}).everything);
  Bounds off;
  off.add(glm::vec3(10, 10, 0));
  off.add(glm::vec3(11, 11, 1));
  EXPECT_TRUE(volumeClip(f, off).nothing);
  Camera persp = cam;
  persp.fovYDegrees = 60.0f;
  Bounds behind = b;
  behind.add(glm::vec3(0, 0, 12));  // behind the eye at z = 10
  EXPECT_TRUE(volumeClip(test::linearFrame(persp, 128, 128), behind).everything);
}

}  // namespace
}  // namespace puff::cel::opaque_volume
