// Billboard shadow volumes against analytic expectations: where shadows fall, clipping cases, oriented puffs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <numbers>
#include <utility>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include <puff/bake/baker.h>
#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/core/atlas.h>
#include <puff/mesh/mesh.h>

#include "nailboard_fixture.h"
#include "support/linear_frame.h"

namespace puff::nailboard_test {
namespace {

namespace fs = std::filesystem;

// Stencil != 0 where the receiver (the depth buffer) is inside some volume.
std::vector<bool> shadowMask(const Target& t) {
  const auto st = t.readStencil();
  std::vector<bool> m(st.size());
  for (std::size_t i = 0; i < st.size(); ++i) m[i] = st[i] != 0;
  return m;
}

// A lone sphere puff, a plane behind it, light at 45 degrees: the shadow on the plane is the
// sphere's cylinder cut at 45 degrees, an ellipse with semi-axes R*sqrt2 (x) and R (y), centred
// where the light's projection puts the centre.
TEST_F(Nailboards, ShadowFallsWhereTheLightProjectsIt) {
  const float R = 1.0f, H = 3.0f;  // particle at z = H in front of the plane z = 0
  cel::Frame f = orthoFrame();
  f.light.direction = glm::normalize(glm::vec3(1, 0, 1));
  cel::Style style;
  target_->clear(depthOfZ(0.0f));
  EXPECT_OK(block_->upload(f));
  renderer_->upload(std::vector<Particle>{Particle{glm::vec3(0, 0, H), 2 * R}});
  renderer_->drawShadowVolumes(style);
  const auto mask = shadowMask(*target_);
  int wrong = 0, inside = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const glm::vec2 w = pixelToWorld(x, y);
      const float e = std::pow((w.x + H) / (R * std::numbers::sqrt2_v<float>), 2.0f) + std::pow(w.y / R, 2.0f);
      const bool expected = e < 1.0f;
      if (std::abs(e - 1.0f) < 0.12f) continue;  // the edge pixels
      inside += expected ? 1 : 0;
      wrong += mask[static_cast<std::size_t>(y) * kPx + x] != expected ? 1 : 0;
    }
  }
  EXPECT_GT(inside, 500);
  EXPECT_EQ(wrong, 0);
}

// The camera stands inside a puff's shadow (below it, light straight down) looking at a wall that
// is partly inside the shadow column x^2 + z^2 <= R^2: exactly that part is shadowed. Depth-pass
// counting would be off by one everywhere here.
TEST_F(Nailboards, ShadowStaysRightWithTheCameraInsideTheVolume) {
  const float R = 1.0f;
  cel::Camera cam;
  cam.position = glm::vec3(0, 0, 0.5f);
  cam.target = glm::vec3(0, 0, -1);
  cam.fovYDegrees = 90.0f;
  cam.nearPlane = 0.1f;
  cam.farPlane = 10.1f;
  cel::Frame f = test::linearFrame(cam, kPx, kPx);
  f.light.direction = glm::vec3(0, 1, 0);
  const float wallZ = -0.5f;  // the wall is 1 in front of the camera
  target_->clear((1.0f - 0.1f) / 10.0f);
  EXPECT_OK(block_->upload(f));
  renderer_->upload(std::vector<Particle>{Particle{glm::vec3(0, 6, 0), 2 * R}});
  cel::Style style;
  renderer_->drawShadowVolumes(style);
  const auto mask = shadowMask(*target_);
  int wrong = 0, shadowed = 0, lit = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      // Pixel -> point on the wall: tan(45) = 1, so NDC * 1 world unit.
      const float ndcX = (x + 0.5f) / kPx * 2 - 1, ndcY = (y + 0.5f) / kPx * 2 - 1;
      const glm::vec3 p(ndcX, ndcY, wallZ);
      const float r2 = p.x * p.x + p.z * p.z;
      const bool expected = r2 < R * R;
      if (std::abs(std::sqrt(r2) - R) < 0.03f) continue;
      (expected ? shadowed : lit)++;
      wrong += mask[static_cast<std::size_t>(y) * kPx + x] != expected ? 1 : 0;
    }
  }
  EXPECT_GT(shadowed, 1000);
  EXPECT_GT(lit, 500);
  EXPECT_EQ(wrong, 0);
}

// A puff just in front of the camera, partly behind the near plane, light from behind the camera:
// its volume crosses the near plane and its shadow on a wall 3 units away is a disc of radius R.
TEST_F(Nailboards, ShadowStaysRightWithAVolumeThroughTheNearPlane) {
  const float R = 0.3f;
  cel::Camera cam;
  cam.position = glm::vec3(0, 0, 3);
  cam.target = glm::vec3(0);
  cam.fovYDegrees = 40.0f;
  cam.nearPlane = 0.2f;
  cam.farPlane = 10.2f;
  cel::Frame f = test::linearFrame(cam, kPx, kPx);
  f.light.direction = glm::vec3(0, 0, 1);  // from behind the camera
  target_->clear((3.0f - 0.2f) / 10.0f);   // the wall z = 0
  EXPECT_OK(block_->upload(f));
  renderer_->upload(std::vector<Particle>{Particle{glm::vec3(0.4f, 0.1f, 2.75f), 2 * R}});
  cel::Style style;
  renderer_->drawShadowVolumes(style);
  const auto mask = shadowMask(*target_);
  const float tanHalf = std::tan(glm::radians(20.0f));
  int wrong = 0, shadowed = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const float ndcX = (x + 0.5f) / kPx * 2 - 1, ndcY = (y + 0.5f) / kPx * 2 - 1;
      const glm::vec2 p(ndcX * tanHalf * 3.0f, ndcY * tanHalf * 3.0f);
      const float r = glm::length(p - glm::vec2(0.4f, 0.1f));
      if (std::abs(r - R) < 0.025f) continue;
      const bool expected = r < R;
      shadowed += expected ? 1 : 0;
      wrong += mask[static_cast<std::size_t>(y) * kPx + x] != expected ? 1 : 0;
    }
  }
  EXPECT_GT(shadowed, 200);
  EXPECT_EQ(wrong, 0);
}

// The entry and exit faces of a volume cover the same samples with the same eye ray, so a lone
// puff's count is 0 or 1 at every pixel: never a stray -1 (255) or 2 where one face was drawn and
// the other was not. Swept over lights from straight at the camera to 75 degrees off, with the camera's
// winding flipped by the host (glFrontFace CW), which must change nothing.
TEST_F(Nailboards, ShadowCountIsZeroOrOneForEveryLightAndWinding) {
  cel::Style style;
  int shadowedTotal = 0;
  for (GLenum frontFace : {GL_CCW, GL_CW}) {
    for (int i = 0; i < 24; ++i) {
      cel::Frame f = orthoFrame();
      const float polar = glm::radians(3.0f + 72.0f * static_cast<float>(i % 8) / 7.0f);
      const float azimuth = glm::radians(37.0f + 120.0f * static_cast<float>(i / 8));
      f.light.direction =
          glm::vec3(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth), std::cos(polar));
      target_->clear(depthOfZ(0.6f));
      EXPECT_OK(block_->upload(f));
      renderer_->upload(std::vector<Particle>{Particle{glm::vec3(0.3f, -0.2f, 1.5f), 2.3f}});
      glFrontFace(frontFace);
      renderer_->drawShadowVolumes(style);
      glFrontFace(GL_CCW);
      int shadowed = 0, bad = 0;
      for (unsigned char v : target_->readStencil()) {
        shadowed += v == 1 ? 1 : 0;
        bad += v > 1 ? 1 : 0;
      }
      EXPECT_EQ(bad, 0) << "light " << i << (frontFace == GL_CW ? " (CW)" : "");
      EXPECT_GT(shadowed, 0) << "light " << i;
      shadowedTotal += shadowed;
    }
  }
  EXPECT_GT(shadowedTotal, 48 * 100);
}

// A one-view atlas baked from `m` (128-texel cells) into dir / name, loaded.
core::Atlas bakeOneView(const mesh::TriMesh& m, const fs::path& dir) {
  bake::BakeOptions o;
  o.cellSize = 128;
  o.flange = {4.0f, false};
  o.outDir = dir;
  o.contactSheet = false;
  bake::PuffSource src;
  src.mesh = m;
  src.provenance.generator = "sphere";
  auto r = bake::bakeAtlas({src}, o);
  EXPECT_TRUE(r.ok());
  auto atlas = core::loadAtlas(r->sidecar);
  EXPECT_TRUE(atlas.ok());
  return std::move(*atlas);
}

// The angle (degrees, [0, 180)) of the principal axis of the set pixels of `mask`, and their count.
std::pair<double, int> principalAxis(const std::vector<bool>& mask, int n) {
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  int count = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      if (!mask[static_cast<std::size_t>(y) * n + x]) continue;
      sx += x, sy += y, sxx += double(x) * x, syy += double(y) * y, sxy += double(x) * y;
      ++count;
    }
  }
  if (count == 0) return {0.0, 0};
  const double mx = sx / count, my = sy / count;
  const double cxx = sxx / count - mx * mx, cyy = syy / count - my * my, cxy = sxy / count - mx * my;
  double a = 0.5 * std::atan2(2.0 * cxy, cxx - cyy) * 180.0 / std::numbers::pi;
  if (a < 0) a += 180.0;
  return {a, count};
}

double angleBetweenAxes(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 180.0);
  return std::min(d, 180.0 - d);
}

// An elongated puff (an ellipsoid three times longer than wide, one baked view) turned about the
// light's axis: its shadow on the plane behind turns with it (the silhouette table lives in the
// frame of the cell the light sees, carried by the puff's orientation).
TEST_F(Nailboards, OrientedPuffsShadowTurnsWithIt) {
  mesh::TriMesh m = mesh::generateSphere({5});
  for (glm::vec3& p : m.positions) p *= glm::vec3(1.0f, 0.33f, 0.5f);
  mesh::computeNormals(m);
  mesh::normalizeToUnitSphere(m);
  ASSERT_TRUE(renderer_->setAtlas(bakeOneView(m, dir_ / "elongated")).ok());
  cel::Frame f = orthoFrame();  // light along +z, toward the camera: the shadow falls straight back
  cel::Style style;
  for (double degrees : {0.0, 25.0, 50.0, 90.0, 115.0, 150.0}) {
    Particle p{glm::vec3(0, 0, 3), 5.0f};
    p.oriented = true;
    p.orientation = glm::angleAxis(static_cast<float>(glm::radians(degrees)), glm::vec3(0, 0, 1));
    target_->clear(depthOfZ(0.0f));
    EXPECT_OK(block_->upload(f));
    renderer_->upload(std::vector<Particle>{p});
    renderer_->drawShadowVolumes(style);
    const auto [angle, count] = principalAxis(shadowMask(*target_), kPx);
    EXPECT_GT(count, 300) << degrees;
    EXPECT_LT(angleBetweenAxes(angle, degrees), 3.0) << "turned " << degrees << ", shadow axis at " << angle;
  }
}

// The start cap follows the depth map at each point, not the centre's depth with a sphere's
// falloff. A ball of radius Rb with two spikes along the light (toward it and away: the depth map
// mirrored through the billboard plane is exact for it) and a receiver plane just behind the
// ball's far side: around the spikes, where the far side is the ball's, the plane is in shadow.
// (The centre's depth, the spike's, would start the shadow far behind the plane everywhere.)
TEST_F(Nailboards, ShadowStartsAtTheFarSideTheDepthMapGivesAtEachPoint) {
  mesh::TriMesh m = mesh::generateSphere({5});
  for (glm::vec3& p : m.positions) {
    const glm::vec3 u = glm::normalize(p);
    p = u * (1.0f + 0.7f * std::exp(-(u.x * u.x + u.y * u.y) / 0.03f));
  }
  mesh::computeNormals(m);
  mesh::normalizeToUnitSphere(m);
  ASSERT_TRUE(renderer_->setAtlas(bakeOneView(m, dir_ / "spiked")).ok());
  const float size = 5.0f, ball = 0.5f * size / 1.7f;  // the ball's radius, world units
  const float centreZ = 3.0f, planeZ = centreZ - 1.04f * ball;
  cel::Frame f = orthoFrame();  // light along +z
  cel::Style style;
  style.shadowBias = 0.0f;
  target_->clear(depthOfZ(planeZ));
  EXPECT_OK(block_->upload(f));
  renderer_->upload(std::vector<Particle>{Particle{glm::vec3(0, 0, centreZ), size}});
  renderer_->drawShadowVolumes(style);
  const auto mask = shadowMask(*target_);
  int ring = 0, shadowed = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const float r = glm::length(pixelToWorld(x, y));
      if (r < 0.5f * ball || r > 0.85f * ball) continue;
      ++ring;
      shadowed += mask[static_cast<std::size_t>(y) * kPx + x] ? 1 : 0;
    }
  }
  EXPECT_GT(ring, 200);
  EXPECT_EQ(shadowed, ring);
}

}  // namespace
}  // namespace puff::nailboard_test
