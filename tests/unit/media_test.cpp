// The media path (spherical billboards, soft particles, burn blending, layer composition,
// explosion light) against closed-form expectations: one sphere seen from a camera at the origin
// looking down -z, walls made by filling the linear depth texture with a known depth, every pixel
// compared with the double-precision formula (media::sphereOpacity).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include <puff/core/blackbody.h>
#include <puff/gl_api.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/media_target.h"

namespace puff {
namespace {

using media::Method;

constexpr int kSize = 65;  // odd: the centre pixel's ray goes through the sphere's centre

using test::MediaTarget;
using test::plainMaterial;
using test::sphereAt;
using Camera = test::MediaCamera;

class MediaTest : public test::MediaRendererTest {
 protected:
  // Draws one particle over background `bg` and returns the target.
  std::vector<glm::vec4> drawOne(MediaTarget& t, const Camera& cam, const media::Particle& p, Method method,
                                 const glm::vec4& bg = {0, 0, 0, 1}) {
    t.clear(bg);
    t.bind();
    renderer_->draw(cam.frame(t.size), std::span(&p, 1), method, t.depth.get());
    EXPECT_EQ(core::drainGlErrors(), "");
    return t.read();
  }
};

// Every pixel's opacity (1 - transmittance) against the closed form for a wall at `wallDistance`.
void expectMatchesClosedForm(const std::vector<glm::vec4>& px, const Camera& cam, glm::dvec3 centre, double r,
                             double tau, double wallDistance, double tolerance = 2e-5) {
  double worst = 0.0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const double expected =
          media::sphereOpacity(glm::dvec3(0.0), cam.ray(x, y, kSize), centre, r, tau, wallDistance, cam.nearPlane);
      const double got = 1.0 - px[static_cast<std::size_t>(y) * kSize + x].a;
      worst = std::max(worst, std::abs(got - expected));
    }
  }
  EXPECT_LT(worst, tolerance);
}

TEST_F(MediaTest, SphereCentreOpacityIsOneMinusExpTwoTauR) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.4f)}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);  // no surface
  const Camera cam;
  const auto px = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kSpherical);
  const float alpha = 1.0f - px[(kSize / 2) * kSize + kSize / 2].a;
  EXPECT_NEAR(alpha, 1.0 - std::exp(-2.0 * 0.4 * 1.0), 1e-5);
  expectMatchesClosedForm(px, cam, {0, 0, -5}, 1.0, 0.4, 1e30);
  // Outside the sphere's silhouette nothing is drawn.
  EXPECT_EQ(px[0].a, 1.0f);
}

// The benchmarks' fill-rate floor: the same quads, a constant (alpha 0.01 each) wherever the quad
// covers, the sphere's formula nowhere; back to the real program when switched off.
TEST_F(MediaTest, TheFillRateFloorDrawsTheSameQuadsComputingNothing) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.4f)}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  const Camera cam;
  const media::Particle p = sphereAt({0, 0, -5}, 1.0f);
  renderer_->setFillRateFloor(true);
  const auto floor = drawOne(t, cam, p, Method::kSpherical);
  renderer_->setFillRateFloor(false);
  const auto real = drawOne(t, cam, p, Method::kSpherical);
  const std::size_t centre = (kSize / 2) * kSize + kSize / 2;
  EXPECT_NEAR(floor[centre].a, 0.99f, 1e-6f);
  EXPECT_NEAR(1.0f - real[centre].a, 1.0 - std::exp(-2.0 * 0.4), 1e-5);
  int covered = 0;
  for (std::size_t i = 0; i < floor.size(); ++i) {
    if (real[i].a < 1.0f) {
      EXPECT_NEAR(floor[i].a, 0.99f, 1e-6f) << "the floor covers what the particle covers";
    }
    covered += floor[i].a < 1.0f ? 1 : 0;
  }
  EXPECT_GT(covered, 100);
  EXPECT_EQ(floor[0].a, 1.0f);  // outside the quad: untouched
}

TEST_F(MediaTest, PlanarAndSoftMatchSphericalAwayFromSurfaces) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.7f)}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  const Camera cam;
  for (Method m : {Method::kPlanar, Method::kSoftLinear, Method::kSoftSCurve}) {
    SCOPED_TRACE(std::string(media::toString(m)));
    // Soft methods fade against the far plane too: keep the sphere far from it (fade = 1).
    expectMatchesClosedForm(drawOne(t, cam, sphereAt({0.3f, -0.2f, -6}, 1.2f), m), cam, {0.3, -0.2, -6}, 1.2, 0.7,
                            1e30);
  }
}

TEST_F(MediaTest, WallThroughTheCentreHalvesThePath) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.4f)}).ok());
  MediaTarget t(kSize);
  const Camera cam;
  t.setDepth(cam.linear(5.0f));  // a wall perpendicular to the view axis through the centre
  const auto px = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kSpherical);
  EXPECT_NEAR(1.0f - px[(kSize / 2) * kSize + kSize / 2].a, 1.0 - std::exp(-0.4 * 1.0), 1e-5);
  expectMatchesClosedForm(px, cam, {0, 0, -5}, 1.0, 0.4, 5.0);
}

TEST_F(MediaTest, WallInFrontGivesZeroNotNegative) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.4f)}).ok());
  MediaTarget t(kSize);
  const Camera cam;
  t.setDepth(cam.linear(3.5f));  // in front of the sphere's front at 4
  for (Method m :
       {Method::kSpherical, Method::kPlanar, Method::kSoftLinear, Method::kSoftSCurve, Method::kPlanarTextured}) {
    SCOPED_TRACE(std::string(media::toString(m)));
    const auto px = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), m, {0.25f, 0.5f, 0.75f, 1.0f});
    for (const glm::vec4& p : px) ASSERT_EQ(p, glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));  // untouched, not darkened
  }
}

TEST_F(MediaTest, NearPlaneInsideTheSphereClipsAsTheFormulaSays) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.4f)}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  for (float nearPlane : {4.5f, 5.0f, 5.5f}) {
    Camera cam;
    cam.nearPlane = nearPlane;
    const auto px = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kSpherical);
    SCOPED_TRACE(nearPlane);
    // Centre ray: from the near plane to the back at 6.
    EXPECT_NEAR(1.0f - px[(kSize / 2) * kSize + kSize / 2].a, 1.0 - std::exp(-0.4 * (6.0 - nearPlane)), 1e-5);
    expectMatchesClosedForm(px, cam, {0, 0, -5}, 1.0, 0.4, 1e30);
  }
}

TEST_F(MediaTest, PlanarPopsAtTheNearPlaneWhereSphericalIsContinuous) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.4f)}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  auto centreAlpha = [&](Method m, float nearPlane) {
    Camera cam;
    cam.nearPlane = nearPlane;
    return 1.0f - drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), m)[(kSize / 2) * kSize + kSize / 2].a;
  };
  // The near plane crosses the centre: the planar billboard vanishes at once, the sphere's opacity
  // changes by what 0.02 of path is worth.
  const float planarBefore = centreAlpha(Method::kPlanar, 4.99f), planarAfter = centreAlpha(Method::kPlanar, 5.01f);
  const float sphereBefore = centreAlpha(Method::kSpherical, 4.99f),
              sphereAfter = centreAlpha(Method::kSpherical, 5.01f);
  EXPECT_NEAR(planarBefore, 1.0 - std::exp(-0.8), 1e-5);
  EXPECT_EQ(planarAfter, 0.0f);
  EXPECT_LT(std::abs(sphereBefore - sphereAfter), 0.4 * 0.02 + 1e-5);
}

TEST_F(MediaTest, PlanarCutsIntoAWallSoftAndSphericalDoNot) {
  // A wall through the sphere's centre at an angle: planar shows a hard edge where the wall
  // crosses the billboard plane; spherical and soft particles vary smoothly.
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(1.0f)}).ok());
  MediaTarget t(kSize);
  const Camera cam;
  std::vector<float> depth(static_cast<std::size_t>(kSize) * kSize);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      // The wall z = -(5 + 0.8 * X) seen along each ray: distance along the axis where it hits.
      const glm::dvec3 d = cam.ray(x, y, kSize);
      const double t0 = 5.0 / (-d.z - 0.8 * d.x);
      depth[static_cast<std::size_t>(y) * kSize + x] = cam.linear(static_cast<float>(-d.z * t0));
    }
  t.setDepth(depth);
  auto largestStep = [&](Method m) {
    const auto px = drawOne(t, cam, sphereAt({0, 0, -5}, 1.5f), m);
    float worst = 0.0f;
    const int y = kSize / 2;
    for (int x = 1; x < kSize; ++x) worst = std::max(worst, std::abs(px[y * kSize + x].a - px[y * kSize + x - 1].a));
    return worst;
  };
  const float planar = largestStep(Method::kPlanar), spherical = largestStep(Method::kSpherical),
              soft = largestStep(Method::kSoftLinear), scurve = largestStep(Method::kSoftSCurve);
  EXPECT_GT(planar, 0.3f);  // the clipping artefact: a jump across one pixel
  EXPECT_LT(spherical, 0.12f);
  EXPECT_LT(soft, 0.12f);
  EXPECT_LT(scurve, 0.12f);
}

// The spherical billboard's path length at every pixel, off-axis ones included, against an
// independent derivation: the ray's chord through the sphere as a segment [t0, t1], cut by the
// near plane (z = -near, so t >= near / -dir.z) and by a wall tilted 35 degrees off the view
// axis (the plane n.p = k, hit at t = k / n.dir), with the opacity 1 - exp(-tau (1 - d/r) ds).
// The renderer sees the wall only as the linear depth a depth buffer holds at each pixel centre,
// and must turn it into a length along that pixel's own ray; the sphere sits off the axis, so
// rays cross it at up to 20 degrees from the axis. Three near planes: before the sphere, through
// its front, through its centre.
TEST_F(MediaTest, SphericalPathLengthIsTheChordCutByATiltedWallAndTheNearPlane) {
  const double tau = 0.9, r = 1.1;
  const glm::dvec3 c(0.9, -0.5, -5.5);
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(static_cast<float>(tau))}).ok());
  MediaTarget t(kSize);
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.5, 0.35, 1.0));  // faces the camera
  const double k = glm::dot(n, c + glm::dvec3(0.2, 0.0, -0.3));     // the wall passes behind the centre
  for (float nearPlane : {0.5f, 4.6f, 5.4f}) {
    Camera cam;
    cam.nearPlane = nearPlane;
    std::vector<float> depth(static_cast<std::size_t>(kSize) * kSize);
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        const glm::dvec3 d = cam.ray(x, y, kSize);
        const double tw = k / glm::dot(n, d);
        depth[static_cast<std::size_t>(y) * kSize + x] = tw > 0.0 ? cam.linear(static_cast<float>(-d.z * tw)) : 1.0f;
      }
    }
    t.setDepth(depth);
    const auto px = drawOne(t, cam, sphereAt(glm::vec3(c), static_cast<float>(r)), Method::kSpherical);
    double worst = 0.0;
    int cut = 0, clipped = 0;
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        const glm::dvec3 d = cam.ray(x, y, kSize);
        const double along = glm::dot(c, d);
        const double miss = glm::length(c - along * d);
        double expected = 0.0;
        if (miss < r) {
          const double half = std::sqrt(r * r - miss * miss);
          const double tw = k / glm::dot(n, d);
          const double t0 = std::max(along - half, nearPlane / -d.z);
          const double t1 = std::min(along + half, tw > 0.0 ? tw : 1e30);
          cut += tw > 0.0 && tw < along + half;
          clipped += nearPlane / -d.z > along - half;
          expected = 1.0 - std::exp(-tau * (1.0 - miss / r) * std::max(0.0, t1 - t0));
        }
        const double got = 1.0 - px[static_cast<std::size_t>(y) * kSize + x].a;
        worst = std::max(worst, std::abs(got - expected));
      }
    }
    EXPECT_GT(cut, 300) << "the wall cuts the sphere's chords";
    if (nearPlane > 1.0f) EXPECT_GT(clipped, 100) << "the near plane cuts them";
    EXPECT_LT(worst, 5e-5) << "near " << nearPlane;
  }
}

// Soft particles fade the planar billboard by how far the scene lies behind its plane, x = (z_scene
// - z_centre) / 2r in [0, 1]: linearly (Ilmonen) or by Lorach's contrast curve (2x^2 below a half,
// 1 - 2(1 - x)^2 above), times the full chord's opacity. Walls at eight depths from the sphere's
// front to past its back, so x sweeps the whole curve.
TEST_F(MediaTest, SoftParticlesFadeLinearlyOrByLorachsCurve) {
  const double tau = 0.8, r = 1.0;
  const glm::dvec3 c(0.3, 0.2, -5.0);
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(static_cast<float>(tau))}).ok());
  MediaTarget t(kSize);
  const Camera cam;
  for (Method m : {Method::kSoftLinear, Method::kSoftSCurve}) {
    for (double wall : {4.2, 4.6, 4.9, 5.1, 5.35, 5.6, 5.9, 6.3}) {
      t.setDepth(cam.linear(static_cast<float>(wall)));
      const auto px = drawOne(t, cam, sphereAt(glm::vec3(c), static_cast<float>(r)), m);
      const double x = std::clamp((wall - 5.0) / (2.0 * r), 0.0, 1.0);
      const double fade = m == Method::kSoftLinear ? x : x < 0.5 ? 2.0 * x * x : 1.0 - 2.0 * (1.0 - x) * (1.0 - x);
      double worst = 0.0;
      for (int y = 0; y < kSize; ++y) {
        for (int i = 0; i < kSize; ++i) {
          const glm::dvec3 d = cam.ray(i, y, kSize);
          const double along = glm::dot(c, d), miss = glm::length(c - along * d);
          const double chord = miss < r ? 2.0 * std::sqrt(r * r - miss * miss) : 0.0;
          const double expected = miss < r ? (1.0 - std::exp(-tau * (1.0 - miss / r) * chord)) * fade : 0.0;
          worst = std::max(worst, std::abs((1.0 - px[static_cast<std::size_t>(y) * kSize + i].a) - expected));
        }
      }
      EXPECT_LT(worst, 5e-5) << media::toString(m) << ", wall at " << wall << " (x = " << x << ")";
    }
  }
}

// planar-textured: the quad of half side r in the centre's plane, the opacity from the baked
// falloff texture. Its closed form at a pixel: the pixel's ray meets the quad's plane at rho radii
// from the centre, alpha = 1 - exp(-tau r falloffWeight(rho)). The texture samples falloffWeight
// at texel centres and filters linearly, so it may differ by up to the weight's largest change
// across one texel diagonal; at the centre a texel centre lies on the quad's (odd size): exact.
double falloffResolutionError() {
  const double step = std::sqrt(2.0) * 2.0 / media::kFalloffTexels;  // one texel diagonal, in radii
  double worst = 0.0;
  for (double rho = 0.0; rho < 1.0 + step; rho += 1e-4)
    worst = std::max(worst, std::abs(media::falloffWeight(rho) - media::falloffWeight(rho + step)));
  return worst;
}

TEST_F(MediaTest, PlanarTexturedCentreOpacityIsOneMinusExpTwoTauR) {
  EXPECT_EQ(media::falloffWeight(0.0), 2.0);  // the full chord 2 r at full falloff
  EXPECT_EQ(media::falloffWeight(1.0), 0.0);
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.4f)}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  const Camera cam;
  const double tau = 0.4, r = 1.0, dz = 5.0;
  const auto px = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kPlanarTextured);
  const double bound = tau * r * falloffResolutionError();
  EXPECT_LT(bound, 0.05);  // the texture is fine enough to matter
  EXPECT_NEAR(1.0f - px[(kSize / 2) * kSize + kSize / 2].a, 1.0 - std::exp(-2.0 * tau * r), 1e-5);
  double worst = 0.0;
  int inside = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const glm::dvec3 d = cam.ray(x, y, kSize);
      const glm::dvec2 onPlane = glm::dvec2(d) * (dz / -d.z);
      const double rho = glm::length(onPlane) / r;
      const double got = 1.0 - px[static_cast<std::size_t>(y) * kSize + x].a;
      if (std::max(std::abs(onPlane.x), std::abs(onPlane.y)) > r) {
        EXPECT_EQ(got, 0.0) << "outside the quad at " << x << "," << y;
        continue;
      }
      worst = std::max(worst, std::abs(got - (1.0 - std::exp(-tau * r * media::falloffWeight(rho)))));
      inside += rho < 1.0 ? 1 : 0;
    }
  }
  EXPECT_LT(worst, bound);
  EXPECT_GT(inside, 400);
  std::printf("planar-textured: worst |alpha - closed form| %.5f (resolution bound %.5f)\n", worst, bound);
}

TEST_F(MediaTest, PlanarTexturedMatchesTheMaterialTermsOfTheSphereProfile) {
  // The same material terms: in-scattered colour and burn blending per pixel as billboard.frag, so
  // colour / opacity is the material's scattered radiance at every covered pixel.
  media::Material m = plainMaterial(0.7f);
  m.color = {0.2f, 0.5f, 0.9f};
  m.burn = 0.5f;
  ASSERT_TRUE(renderer_->setMaterials({m}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  const Camera cam;
  const glm::vec3 bg(0.3f, 0.6f, 0.1f);
  const auto px = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kPlanarTextured, glm::vec4(bg, 1.0f));
  int checked = 0;
  for (const glm::vec4& p : px) {
    const float a = (1.0f - p.a) / (1.0f - m.burn);  // the layer keeps 1 - alpha (1 - burn)
    if (a < 0.05f) continue;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[c], m.color[c] * a + bg[c] * (1.0f - a * (1.0f - m.burn)), 2e-5);
    ++checked;
  }
  EXPECT_GT(checked, 200);
}

TEST_F(MediaTest, PlanarTexturedIsHardClippedByAWall) {
  // A wall at distance 4.5 over the left half of the image, in front of the quad's plane at 5: the
  // depth test hides the quad there entirely and leaves the right half whole, so the opacity jumps
  // from 0 to the full profile across one pixel. The spherical billboard sees the path from the
  // sphere's front at 4 to the wall on the left: no jump of that size.
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.4f)}).ok());
  MediaTarget t(kSize);
  const Camera cam;
  std::vector<float> depth(static_cast<std::size_t>(kSize) * kSize, 1.0f);
  const int edge = kSize / 2;  // columns below it: the wall
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < edge; ++x) depth[static_cast<std::size_t>(y) * kSize + x] = cam.linear(4.5f);
  t.setDepth(depth);
  const auto textured = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kPlanarTextured);
  const auto spherical = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kSpherical);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < edge; ++x) ASSERT_EQ(textured[static_cast<std::size_t>(y) * kSize + x].a, 1.0f);
  const int y = kSize / 2;
  const float jump = textured[y * kSize + edge - 1].a - textured[y * kSize + edge].a;
  const float sphericalJump = std::abs(spherical[y * kSize + edge - 1].a - spherical[y * kSize + edge].a);
  EXPECT_GT(jump, 0.5f);  // the full centre opacity 1 - e^-0.8 = 0.55, less a pixel's falloff
  EXPECT_LT(sphericalJump, 0.45f);
  std::printf("wall edge: planar-textured jumps %.3f, spherical %.3f\n", jump, sphericalJump);
}

TEST_F(MediaTest, PlanarTexturedPopsAtTheNearPlane) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.4f)}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  auto centreAlpha = [&](float nearPlane) {
    Camera cam;
    cam.nearPlane = nearPlane;
    return 1.0f -
           drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kPlanarTextured)[(kSize / 2) * kSize + kSize / 2].a;
  };
  EXPECT_NEAR(centreAlpha(4.99f), 1.0 - std::exp(-0.8), 1e-5);
  EXPECT_EQ(centreAlpha(5.01f), 0.0f);
}

// Each method's fill-rate floor keeps its depth test: behind a wall in front of the sphere the
// depth-tested methods' floors draw nothing (as the methods do), the others' floors the quad.
TEST_F(MediaTest, TheFillRateFloorKeepsEachMethodsDepthTest) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.4f)}).ok());
  MediaTarget t(kSize);
  const Camera cam;
  t.setDepth(cam.linear(3.5f));
  const std::size_t centre = (kSize / 2) * kSize + kSize / 2;
  renderer_->setFillRateFloor(true);
  for (Method m : {Method::kPlanar, Method::kPlanarTextured, Method::kSoftLinear, Method::kSpherical}) {
    SCOPED_TRACE(std::string(media::toString(m)));
    const auto floor = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), m);
    const bool tested = m == Method::kPlanar || m == Method::kPlanarTextured;
    EXPECT_NEAR(floor[centre].a, tested ? 1.0f : 0.99f, 1e-6f);
  }
  t.setDepth(1.0f);
  const auto texturedFloor = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kPlanarTextured);
  renderer_->setFillRateFloor(false);
  const auto textured = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kPlanarTextured);
  int covered = 0;
  for (std::size_t i = 0; i < textured.size(); ++i) {
    if (textured[i].a < 1.0f) {
      EXPECT_NEAR(texturedFloor[i].a, 0.99f, 1e-6f) << "the floor covers what the particle covers";
      ++covered;
    }
  }
  EXPECT_GT(covered, 100);
}

TEST_F(MediaTest, BurnBlendingIsIlmonenEquationThree) {
  // c = fg * alpha + bg * (1 - alpha * (1 - burn)) for a grid of colours, backgrounds, opacities
  // (every pixel of two spheres of different density) and burns.
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  const Camera cam;
  double worst = 0.0;
  int checked = 0;
  for (glm::vec3 fg : {glm::vec3(1, 0, 0), glm::vec3(0.2f, 0.5f, 0.9f)}) {
    for (glm::vec3 bg : {glm::vec3(0), glm::vec3(0.3f, 0.6f, 0.1f), glm::vec3(1)}) {
      for (float burn : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) {
        for (float tau : {0.3f, 3.0f}) {
          media::Material m = plainMaterial(tau);
          m.color = fg;  // albedo 1, ambient 1, no light: the scattered radiance is fg exactly
          m.burn = burn;
          ASSERT_TRUE(renderer_->setMaterials({m}).ok());
          const auto px = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kSpherical, glm::vec4(bg, 1.0f));
          for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
              const double a =
                  media::sphereOpacity(glm::dvec3(0), cam.ray(x, y, kSize), {0, 0, -5}, 1.0, tau, 1e30, cam.nearPlane);
              const glm::vec4 got = px[static_cast<std::size_t>(y) * kSize + x];
              for (int c = 0; c < 3; ++c) {
                const double expected = fg[c] * a + bg[c] * (1.0 - a * (1.0 - burn));
                worst = std::max(worst, std::abs(got[c] - expected));
              }
              // The layer's alpha: the transmittance left for what is behind, 1 - alpha (1 - burn).
              worst = std::max(worst, std::abs(got.a - (1.0 - a * (1.0 - burn))));
              if (a > 0.0) ++checked;
            }
          }
        }
      }
    }
  }
  EXPECT_LT(worst, 5e-5);
  EXPECT_GT(checked, 1000);
}

TEST_F(MediaTest, FireEmitsTheBlackBodyRampColour) {
  media::Material fire = media::fireMaterial();
  fire.temperatureRange = 0.0f;  // T = T0 exactly
  fire.temperature = 3000.0f;
  fire.burn = 0.0f;
  ASSERT_TRUE(renderer_->setMaterials({fire}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  const Camera cam;
  const auto px = drawOne(t, cam, sphereAt({0, 0, -5}, 1.0f), Method::kSpherical);
  const glm::vec4 c = px[(kSize / 2) * kSize + kSize / 2];
  const float alpha = 1.0f - c.a;
  ASSERT_GT(alpha, 0.5f);
  auto ramp = core::makeBlackbodyRamp(1000, 10000, 1024, 3200);  // the renderer's default settings
  ASSERT_TRUE(ramp.ok());
  const glm::vec3 expected = glm::max(ramp->at(3000.0), glm::vec3(0.0f));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(c[i] / alpha, expected[i], 2e-3 * std::max(1.0f, expected[i]));
  EXPECT_GT(expected.r, expected.g);  // flame colour: red over green over blue at 3000 K
  EXPECT_GT(expected.g, expected.b);
}

TEST_F(MediaTest, InScatteringFollowsThePhaseFunction) {
  for (media::PhaseModel model : {media::PhaseModel::kHenyeyGreenstein, media::PhaseModel::kCornetteShanks}) {
    media::Settings s;
    s.phase = model;
    auto r = media::Renderer::create(s);
    ASSERT_OK(r);
    for (float g : {0.6f, 0.9f, 0.95f, -0.7f}) {
      media::Material m = plainMaterial(0.5f);
      m.g = g;
      ASSERT_TRUE((*r)->setMaterials({m}).ok());
      MediaTarget t(kSize);
      t.setDepth(1.0f);
      t.clear({0, 0, 0, 1});
      t.bind();
      Camera cam;
      media::Frame f = cam.frame(kSize);
      f.ambient = glm::vec3(0.0f);
      f.lightColor = glm::vec3(1.0f);
      for (glm::vec3 l : {glm::vec3(0, 0.6f, 0.8f), glm::vec3(0, 0.6f, -0.8f), glm::vec3(1, 0, 0),
                          glm::vec3(0, 0.1f, -1), glm::vec3(0, 0.03f, -1), glm::vec3(0, 0, -1)}) {
        f.lightDirection = l;
        t.clear({0, 0, 0, 1});
        const media::Particle p = sphereAt({0, 0, -5}, 1.0f);
        (*r)->draw(f, std::span(&p, 1), Method::kSpherical, t.depth.get());
        const glm::vec4 c = t.read()[(kSize / 2) * kSize + kSize / 2];
        // Centre ray: direction (0, 0, -1); the light travels along -l.
        const double cosTheta = glm::dot(glm::normalize(glm::dvec3(l)), glm::dvec3(0, 0, -1));
        const double expected = 4.0 * std::numbers::pi * media::phase(model, cosTheta, g);
        // g rows are 0.0075 apart: the lookup mixes the two nearest (a normalized mix), within 2% of the
        // exact value even on the g = 0.95 peak.
        EXPECT_NEAR(c.r / (1.0f - c.a), expected, 0.02 * expected)
            << media::toString(model) << " g " << g << " cos " << cosTheta;
      }
    }
  }
}

TEST_F(MediaTest, OrthographicRaysAreParallel) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.5f)}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  media::Frame f = Camera{}.frame(kSize);
  f.orthographic = true;
  f.projection = glm::ortho(-2.0f, 2.0f, -2.0f, 2.0f, f.nearPlane, f.farPlane);
  const media::Particle p = sphereAt({0.3f, -0.4f, -5}, 1.1f);
  for (Method m : {Method::kSpherical, Method::kPlanar}) {
    t.clear({0, 0, 0, 1});
    t.bind();
    renderer_->draw(f, std::span(&p, 1), m, t.depth.get());
    const auto px = t.read();
    double worst = 0.0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const glm::dvec3 o((x + 0.5) / kSize * 4.0 - 2.0, (y + 0.5) / kSize * 4.0 - 2.0, 0.0);
        const double a = media::sphereOpacity(o, {0, 0, -1}, {0.3, -0.4, -5}, 1.1, 0.5, 1e30, f.nearPlane);
        worst = std::max(worst, std::abs((1.0 - px[static_cast<std::size_t>(y) * kSize + x].a) - a));
      }
    EXPECT_LT(worst, 2e-5) << media::toString(m);
  }
}

TEST_F(MediaTest, AMaterialBecomesAnotherOverItsLife) {
  media::Material red = plainMaterial(0.8f), blue = plainMaterial(0.8f);
  red.color = {1, 0, 0};
  red.becomes = 1;
  red.transitionStart = 0.2f;
  red.transitionEnd = 0.6f;
  blue.color = {0, 0, 1};
  blue.burn = 1.0f;
  ASSERT_TRUE(renderer_->setMaterials({red, blue}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  const Camera cam;
  for (auto [life, f] : {std::pair{0.1f, 0.0f}, std::pair{0.4f, 0.5f}, std::pair{0.9f, 1.0f}}) {
    media::Particle p = sphereAt({0, 0, -5}, 1.0f);
    p.life = life;
    const glm::vec4 c = drawOne(t, cam, p, Method::kSpherical)[(kSize / 2) * kSize + kSize / 2];
    const double a = 1.0 - std::exp(-0.8 * 2.0);
    EXPECT_NEAR(c.r, (1.0 - f) * a, 1e-4) << life;
    EXPECT_NEAR(c.b, f * a, 1e-4) << life;
    EXPECT_NEAR(c.a, 1.0 - a * (1.0 - f), 1e-4) << life;  // burn 0 -> 1 along the way
  }
}

TEST(MediaPhase, BothModelsIntegrateToOne) {
  for (media::PhaseModel model : {media::PhaseModel::kHenyeyGreenstein, media::PhaseModel::kCornetteShanks}) {
    for (double g : {-0.5, 0.0, 0.3, 0.8}) {
      double sum = 0.0;
      const int n = 20000;
      for (int i = 0; i < n; ++i) {  // midpoint rule over cos in [-1, 1], times 2 pi
        const double c = -1.0 + (i + 0.5) * 2.0 / n;
        sum += media::phase(model, c, g) * 2.0 / n * 2.0 * std::numbers::pi;
      }
      EXPECT_NEAR(sum, 1.0, 1e-4) << media::toString(model) << " g " << g;
    }
  }
  EXPECT_NEAR(media::phase(media::PhaseModel::kHenyeyGreenstein, 0.3, 0.0), 1.0 / (4.0 * std::numbers::pi), 1e-12);
  // The paper's form is Rayleigh-shaped at g = 0: not isotropic.
  EXPECT_NEAR(media::phase(media::PhaseModel::kCornetteShanks, 1.0, 0.0), 3.0 / (8.0 * std::numbers::pi), 1e-12);
  EXPECT_NEAR(media::phase(media::PhaseModel::kCornetteShanks, 0.0, 0.0), 3.0 / (16.0 * std::numbers::pi), 1e-12);
}

// Forward and back, where g matters: c = cos of the angle between the light's travel and the
// scattered direction, so g > 0 scatters forward (c = 1). Values worked by hand from the printed
// formulas, at g = 0.5: Henyey-Greenstein (1 - g^2) / (4 pi (1 + g^2 -+ 2g)^1.5) = 0.75 / (4 pi
// 0.125) forward, 0.75 / (4 pi 3.375) back; Cornette-Shanks 3/2 (1 - g^2)/(2 + g^2) (1 + c^2) /
// (1 + g^2 -+ 2g)^1.5 / (4 pi) = 8 / (4 pi) forward, 8 / 27 / (4 pi) back. (Integrating to one and
// the g = 0 values cannot see the angle reversed.)
TEST(MediaPhase, ForwardScatteringIsWhereGPoints) {
  const double fourPi = 4.0 * std::numbers::pi;
  EXPECT_NEAR(media::phase(media::PhaseModel::kHenyeyGreenstein, 1.0, 0.5), 6.0 / fourPi, 1e-12);
  EXPECT_NEAR(media::phase(media::PhaseModel::kHenyeyGreenstein, -1.0, 0.5), (0.75 / 3.375) / fourPi, 1e-12);
  EXPECT_NEAR(media::phase(media::PhaseModel::kCornetteShanks, 1.0, 0.5), 8.0 / fourPi, 1e-12);
  EXPECT_NEAR(media::phase(media::PhaseModel::kCornetteShanks, -1.0, 0.5), (8.0 / 27.0) / fourPi, 1e-12);
  // g < 0 mirrors it.
  EXPECT_NEAR(media::phase(media::PhaseModel::kHenyeyGreenstein, -1.0, -0.5), 6.0 / fourPi, 1e-12);
}

TEST(MediaSort, BackToFrontIsStableAndFarthestFirst) {
  std::vector<media::Particle> ps;
  const float zs[] = {-3, -10, -3, 2, -7.5f, -0.0f, -10};
  for (float z : zs) ps.push_back(sphereAt({1, 2, z}, 1));
  const glm::mat4 view(1.0f);
  const auto order = media::backToFront(view, ps);
  const std::vector<std::uint32_t> expected = {1, 6, 4, 0, 2, 5, 3};
  EXPECT_EQ(order, expected);
  // A large shuffled set comes out monotone.
  std::vector<media::Particle> many;
  for (int i = 0; i < 50000; ++i)
    many.push_back(sphereAt({0, 0, -std::fmod(static_cast<float>(i) * 7.31f, 100.0f) + 1.0f}, 1));
  const glm::mat4 turned = glm::lookAt(glm::vec3(3, 4, 5), glm::vec3(0), glm::vec3(0, 1, 0));
  const auto o = media::backToFront(turned, many);
  ASSERT_EQ(o.size(), many.size());
  for (std::size_t i = 1; i < o.size(); ++i)
    ASSERT_LE((turned * glm::vec4(many[o[i - 1]].position, 1)).z, (turned * glm::vec4(many[o[i]].position, 1)).z);
}

TEST_F(MediaTest, DrawOrderDoesNotDependOnInputOrder) {
  media::Material smoke = plainMaterial(0.8f), fire = media::fireMaterial();
  fire.detail = 0.0f;
  ASSERT_TRUE(renderer_->setMaterials({smoke, fire}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  const Camera cam;
  media::Particle a = sphereAt({0.2f, 0, -6}, 1.0f), b = sphereAt({-0.2f, 0.1f, -4.5f}, 0.8f);
  b.material = 1;
  auto draw = [&](std::vector<media::Particle> ps) {
    t.clear({0, 0, 0, 1});
    t.bind();
    renderer_->draw(cam.frame(kSize), ps, Method::kSpherical, t.depth.get());
    return t.read();
  };
  EXPECT_EQ(draw({a, b}), draw({b, a}));
}

TEST(MediaMaterial, ValidationNamesTheField) {
  media::Material m = media::smokeMaterial();
  m.albedo = 1.5f;
  auto r = media::validate(m, 1);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "smoke: albedo: expected a number in [0, 1], got 1.5");
  m = media::fireMaterial();
  m.becomes = 3;
  EXPECT_NE(media::validate(m, 2).error().message.find("becomes"), std::string::npos);
  m.becomes = -1;
  m.transitionStart = 0.9f;
  m.transitionEnd = 0.2f;
  EXPECT_NE(media::validate(m, 2).error().message.find("transitionEnd"), std::string::npos);
}

// ---- layer composition -------------------------------------------------------------------------

class MediaLayersTest : public MediaTest {};

// Fills the opaque pass: background (linear depth 1) and a near "pole" rectangle at `poleDepth`.
void fillOpaque(media::Layers& layers, int x0, int x1, float poleDepth, const glm::vec4& poleColor) {
  const GLuint fbo = layers.opaqueFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  const glm::vec4 sky(0.4f, 0.6f, 0.9f, 1.0f);
  glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &sky.x);
  glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
  glEnable(GL_SCISSOR_TEST);
  glScissor(x0, 0, x1 - x0, layers.height());
  glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &poleColor.x);
  glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, poleDepth, 0);
  glDisable(GL_SCISSOR_TEST);
}

std::vector<glm::vec4> composeScene(media::Renderer& r, float scale, bool depthAware,
                                    std::span<const media::ExplosionLight> lights = {}, float shimmerPixels = 0.0f,
                                    int w = 96, int h = 64, bool pole = true) {
  auto layers = media::Layers::create(w, h, 1, scale);
  EXPECT_OK(layers);
  Camera cam;
  // A pole at 3 (columns 45-50), smoke behind it at 6.
  fillOpaque(**layers, 45, pole ? 51 : 45, cam.linear(3.0f), {0.1f, 0.1f, 0.1f, 1.0f});
  (*layers)->resolveOpaque();
  (*layers)->beginMedia();
  media::Frame f = cam.frame(0);
  f.projection = glm::perspective(glm::radians(cam.fovDegrees), static_cast<float>(w) / h, cam.nearPlane, cam.farPlane);
  f.width = w;
  f.height = h;
  const media::Particle p = sphereAt({0, 0, -6}, 2.0f);
  r.draw((*layers)->layerFrame(f), std::span(&p, 1), Method::kSpherical, (*layers)->mediaDepth(), true);
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, w, h);
  glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  const int vp[4] = {0, 0, w, h};
  media::ComposeSettings cs;
  cs.depthAware = depthAware;
  cs.shimmerPixels = shimmerPixels;
  (*layers)->compose(out.get(), vp, f, lights, cs);
  std::vector<glm::vec4> px(static_cast<std::size_t>(w) * h);
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(glm::vec4)), px.data());
  EXPECT_EQ(core::drainGlErrors(), "");
  return px;
}

TEST_F(MediaLayersTest, FullResolutionCompositionIsOpaqueTimesTransmittancePlusMedia) {
  media::Material m = plainMaterial(0.6f);
  m.color = glm::vec3(1.0f, 0.5f, 0.25f);
  ASSERT_TRUE(renderer_->setMaterials({m}).ok());
  const auto px = composeScene(*renderer_, 1.0f, true);
  // A sky pixel at the sphere's centre column, away from the pole: sky * T + colour * alpha.
  Camera cam;
  const int x = 30, y = 32;
  const double t = std::tan(glm::radians(20.0));
  const glm::dvec3 d = glm::normalize(glm::dvec3(((x + 0.5) / 96 * 2 - 1) * t * 1.5, ((y + 0.5) / 64 * 2 - 1) * t, -1));
  const double a = media::sphereOpacity(glm::dvec3(0), d, {0, 0, -6}, 2.0, 0.6, 1e30, cam.nearPlane);
  ASSERT_GT(a, 0.3);
  const glm::dvec3 sky(0.4, 0.6, 0.9), c(1.0, 0.5, 0.25);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(px[y * 96 + x][i], sky[i] * (1 - a) + c[i] * a, 2e-3);
  // The pole is in front of the smoke: its own colour, untouched.
  EXPECT_NEAR(px[y * 96 + 48].r, 0.1f, 1e-4);  // the opaque colour target holds half floats
}

TEST_F(MediaLayersTest, DepthAwareUpsamplingRemovesHalosAroundNearEdges) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.6f)}).ok());
  const auto reference = composeScene(*renderer_, 1.0f, true);
  for (float scale : {0.5f, 0.25f, 0.125f}) {
    const auto aware = composeScene(*renderer_, scale, true), plain = composeScene(*renderer_, scale, false);
    // Mean error on the pole and the two columns either side of it, where halos show.
    auto bandError = [&](const std::vector<glm::vec4>& px) {
      double e = 0.0;
      for (int y = 0; y < 64; ++y)
        for (int x = 43; x < 53; ++x) e += std::abs(px[y * 96 + x].r - reference[y * 96 + x].r);
      return e / (64 * 10);
    };
    const double a = bandError(aware), p = bandError(plain);
    std::printf("pole band at %g: mean error depth-aware %.4f, plain bilinear %.4f\n", scale, a, p);
    SCOPED_TRACE(scale);
    // Measured 0.0068 / 0.063, 0.014 / 0.076, 0.052 / 0.121: a coarser layer is coarser smoke too.
    EXPECT_LT(a, (scale == 0.5f ? 0.15 : scale == 0.25f ? 0.25 : 0.5) * p);
    // The pole itself (in front of the smoke) keeps its own colour at every scale.
    for (int y = 0; y < 64; ++y)
      for (int x = 45; x < 51; ++x) ASSERT_EQ(aware[y * 96 + x].r, reference[y * 96 + x].r) << x << "," << y;
  }
}

TEST_F(MediaLayersTest, ALowResolutionLayerStaysAlignedAtSizesNotAMultipleOfItsFactor) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.6f)}).ok());
  for (const auto& size : {std::pair{100, 61}, std::pair{201, 77}}) {
    const int w = size.first, h = size.second;  // named, not bound: lambdas capture them (clang 14)
    // Where the smoke is: the centroid of how far each pixel moved from the bare sky.
    auto centroid = [&](const std::vector<glm::vec4>& px) {
      double sx = 0, sy = 0, sw = 0;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const double wgt = std::abs(px[static_cast<std::size_t>(y) * w + x].r - 0.4);
          sx += wgt * x, sy += wgt * y, sw += wgt;
        }
      return glm::dvec2(sx / sw, sy / sw);
    };
    const auto fullpx = composeScene(*renderer_, 1.0f, true, {}, 0.0f, w, h, false);
    const glm::dvec2 full = centroid(fullpx);
    for (float scale : {0.5f, 0.25f, 0.125f}) {
      const glm::dvec2 low = centroid(composeScene(*renderer_, scale, true, {}, 0.0f, w, h, false));
      EXPECT_LT(glm::length(low - full), 0.6)
          << w << "x" << h << " at " << scale << ": " << low.x - full.x << ", " << low.y - full.y;
    }
  }
}

TEST_F(MediaLayersTest, HeatShimmerDisplacesTheSceneOnlyBehindFire) {
  media::Material fire = media::fireMaterial();
  fire.shimmer = 1.0f;
  fire.emission = 0.0f;  // no colour of its own: what changes is where the scene is sampled
  fire.burn = 1.0f;      // and it hides nothing
  media::Renderer& r = *renderer_;
  ASSERT_TRUE(r.setMaterials({fire}).ok());
  // The offsets come from the temperature detail video: a ramp across x.
  core::DetailVideo ramp;
  ramp.width = ramp.height = 16;
  ramp.frames = 2;
  for (int f = 0; f < 2; ++f)
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) ramp.values.push_back(static_cast<float>(x) / 15.0f);
  r.setDetail(&ramp, nullptr);
  const auto still = composeScene(r, 1.0f, true);
  const auto shimmering = composeScene(r, 1.0f, true, {}, 40.0f);
  r.setDetail(nullptr, nullptr);
  int moved = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 96; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * 96 + x;
      // Outside the sphere's disc (radius about 31 px around the centre) nothing moves.
      const float dx = x + 0.5f - 48.0f, dy = y + 0.5f - 32.0f;
      if (dx * dx + dy * dy > 33.0f * 33.0f) {
        ASSERT_EQ(shimmering[i], still[i]) << x << "," << y;
      } else {
        moved += shimmering[i] != still[i] ? 1 : 0;
      }
    }
  }
  EXPECT_GT(moved, 10);  // the pole's edges move where the fire is
}

// Heat shimmer moves the scene by fractions of a pixel: the opaque colour is fetched bilinearly at
// the displaced position. An opaque image whose red rises 4/255 per column and green 8/255 per row
// (linear in both, so the bilinear fetch is exactly the displaced ramp), a shimmer layer holding
// the constant offset (0.375, -0.25) and 1 pixel per unit: every pixel shows (x + 0.375, y - 0.25),
// clamped at the image's edges. Rounding to whole pixels gave (x, y) instead.
TEST_F(MediaLayersTest, HeatShimmerDisplacesBySubPixelAmountsBilinearly) {
  const int w = 24, h = 12;
  auto layers = media::Layers::create(w, h, 1, 1.0f);
  ASSERT_OK(layers);
  const GLuint fbo = (*layers)->opaqueFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);  // no surface: no explosion light
  glEnable(GL_SCISSOR_TEST);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      glScissor(x, y, 1, 1);
      const glm::vec4 c(4.0f * x / 255.0f, 8.0f * y / 255.0f, 0.0f, 1.0f);
      glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &c.x);
    }
  }
  glDisable(GL_SCISSOR_TEST);
  (*layers)->resolveOpaque();
  (*layers)->beginMedia();  // no medium (M = 0, T = 1); the media framebuffer is bound to draw
  const float offset[4] = {0.375f, -0.25f, 0.0f, 0.0f};  // exact in RG16F
  glClearBufferfv(GL_COLOR, 1, offset);
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, w, h);
  glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  const int vp[4] = {0, 0, w, h};
  media::ComposeSettings cs;
  cs.shimmerPixels = 1.0f;
  Camera cam;
  media::Frame f = cam.frame(0);
  f.width = w, f.height = h;
  (*layers)->compose(out.get(), vp, f, {}, cs);
  std::vector<glm::vec4> px(static_cast<std::size_t>(w) * h);
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(glm::vec4)), px.data());
  ASSERT_EQ(core::drainGlErrors(), "");
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double sx = std::clamp(x + 0.375, 0.0, w - 1.0), sy = std::clamp(y - 0.25, 0.0, h - 1.0);
      const glm::vec4 got = px[static_cast<std::size_t>(y) * w + x];
      // The opaque layer holds half floats: the bilinear mix of the two texels as stored, within one
      // half-float step (llvmpipe filters half textures at that precision). A snapped offset would
      // miss by 0.006 or more.
      auto stored = [](double v) { return double{glm::unpackHalf1x16(glm::packHalf1x16(static_cast<float>(v)))}; };
      auto lerp = [&](double s, double scale) {
        const double i0 = std::floor(s), t = s - i0;
        return (1 - t) * stored(scale * i0 / 255.0) + t * stored(scale * std::min(i0 + 1, s + 1) / 255.0);
      };
      const double er = lerp(sx, 4.0), eg = lerp(sy, 8.0);
      ASSERT_NEAR(got.r, er, std::max(1e-6, er / 1024.0)) << x << "," << y;
      ASSERT_NEAR(got.g, eg, std::max(1e-6, eg / 1024.0)) << x << "," << y;
    }
  }
  // Interior: a quarter of the way between two 8-bit levels, which no whole-pixel shift gives.
  // (Half floats: within a half-float step, 1.2e-4 here, against 8-bit levels 0.016 and 0.031 apart.)
  EXPECT_NEAR(px[5 * w + 10].r, 4.0 * 10.375 / 255.0, 2e-4);
  EXPECT_NEAR(px[5 * w + 10].g, 8.0 * 4.75 / 255.0, 2e-4);
}

// A floor seen at a grazing angle, the case where upsampling by depth must degrade gracefully: the
// camera at the origin looking down -z, the floor the plane y = -1, so row y's linear depth is
// that of the distance 1 / (-ndc_y * tan(fov / 2)) (the sky above the horizon), and three smoke
// spheres sitting in it (the floor cuts them: the layer's texels along the floor are drawn against
// depths that drift from each pixel's). Returns the composed image, row 0 at the bottom.
std::vector<glm::vec4> composeFloor(media::Renderer& r, float scale, media::Layers::Upsampling rule, int w, int h,
                                    std::vector<bool>* floorMask = nullptr) {
  auto layers = media::Layers::create(w, h, 1, scale);
  EXPECT_OK(layers);
  (*layers)->setUpsampling(rule);
  Camera cam;
  const GLuint fbo = (*layers)->opaqueFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glEnable(GL_SCISSOR_TEST);
  const double t = std::tan(glm::radians(static_cast<double>(cam.fovDegrees)) / 2.0);
  if (floorMask) floorMask->assign(static_cast<std::size_t>(w) * h, false);
  for (int y = 0; y < h; ++y) {
    const double ndc = (y + 0.5) / h * 2.0 - 1.0;
    const double z = ndc < 0.0 ? 1.0 / (-ndc * t) : 1e30;
    const float lin = z < cam.farPlane ? cam.linear(static_cast<float>(z)) : 1.0f;
    const glm::vec4 c = lin < 1.0f ? glm::vec4(0.55f, 0.5f, 0.42f, 1.0f) : glm::vec4(0.4f, 0.6f, 0.9f, 1.0f);
    glScissor(0, y, w, 1);
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &c.x);
    glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, lin, 0);
    if (floorMask && lin < 1.0f)
      for (int x = 0; x < w; ++x) (*floorMask)[static_cast<std::size_t>(y) * w + x] = true;
  }
  glDisable(GL_SCISSOR_TEST);
  (*layers)->resolveOpaque();
  (*layers)->beginMedia();
  media::Frame f = cam.frame(0);
  f.projection = glm::perspective(glm::radians(cam.fovDegrees), static_cast<float>(w) / h, cam.nearPlane, cam.farPlane);
  f.width = w;
  f.height = h;
  const std::vector<media::Particle> ps = {sphereAt({0.0f, -0.3f, -13.0f}, 2.0f), sphereAt({1.2f, -0.4f, -8.0f}, 1.5f),
                                           sphereAt({-1.5f, -0.6f, -5.0f}, 1.2f)};  // back to front
  r.draw((*layers)->layerFrame(f), ps, Method::kSpherical, (*layers)->mediaDepth(), false);
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, w, h);
  glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  const int vp[4] = {0, 0, w, h};
  (*layers)->compose(out.get(), vp, f, {}, media::ComposeSettings{});
  std::vector<glm::vec4> px(static_cast<std::size_t>(w) * h);
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(glm::vec4)), px.data());
  EXPECT_EQ(core::drainGlErrors(), "");
  return px;
}

TEST_F(MediaLayersTest, BilateralUpsamplingDegradesGracefullyOnASlantedFloor) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.6f)}).ok());
  using Rule = media::Layers::Upsampling;
  const int w = 192, h = 128;
  std::vector<bool> floor;
  const auto reference = composeFloor(*renderer_, 1.0f, Rule::kBilateral, w, h, &floor);
  // At full size both rules are the layer itself.
  EXPECT_EQ(composeFloor(*renderer_, 1.0f, Rule::kAllOrNearest, w, h), reference);
  // Mean |error| over the R, G and B of the floor's pixels against the full-size layer.
  auto floorError = [&](const std::vector<glm::vec4>& px) {
    double e = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < px.size(); ++i) {
      if (!floor[i]) continue;
      for (int c = 0; c < 3; ++c) e += std::abs(static_cast<double>(px[i][c]) - reference[i][c]);
      n += 3;
    }
    return e / static_cast<double>(n);
  };
  for (float scale : {0.25f, 0.125f}) {
    const double bilateral = floorError(composeFloor(*renderer_, scale, Rule::kBilateral, w, h));
    const double switched = floorError(composeFloor(*renderer_, scale, Rule::kAllOrNearest, w, h));
    std::printf("slanted floor at %g: mean error bilateral %.5f, all-or-nearest %.5f\n", scale, bilateral, switched);
    SCOPED_TRACE(scale);
    EXPECT_LE(bilateral, switched);
  }
}

TEST_F(MediaLayersTest, ExplosionLightFollowsDepthNotPolygons) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.0f)}).ok());  // invisible medium: only the light
  media::ExplosionLight light;
  light.center = {0, 0, -6};
  light.radius = 2.0f;
  light.color = {1.0f, 0.5f, 0.0f};
  light.intensity = 0.5f;
  const auto lit = composeScene(*renderer_, 1.0f, true, std::span(&light, 1));
  const auto dark = composeScene(*renderer_, 1.0f, true);
  // The pole at distance 3 is in front of the explosion sphere (front at 4): unlit.
  EXPECT_EQ(lit[32 * 96 + 48], dark[32 * 96 + 48]);
  // Background (no surface): unlit.
  EXPECT_EQ(lit[32 * 96 + 30], dark[32 * 96 + 30]);
  // Put the pole behind the explosion's centre: full light at the projected centre.
  light.center = {0, 0, -2.5f};
  light.radius = 1.0f;
  const auto behind = composeScene(*renderer_, 1.0f, true, std::span(&light, 1));
  // Column 48 is half a pixel off the view axis: the radial weight is ~1.
  EXPECT_NEAR(behind[32 * 96 + 48].r, 0.1f + 0.5f, 0.01f);
  EXPECT_NEAR(behind[32 * 96 + 48].g, 0.1f + 0.25f, 0.01f);
  // Halfway between the sphere's front (1.5) and centre (2.5): the pole at 3 is past the centre;
  // move the light so the pole sits at its mid-depth: centre at 3.5, radius 1 -> front 2.5, 3 = half.
  light.center = {0, 0, -3.5f};
  const auto half = composeScene(*renderer_, 1.0f, true, std::span(&light, 1));
  EXPECT_NEAR(half[32 * 96 + 48].r, 0.1f + 0.25f, 0.02f);
  // Full at the back instead: at the same depth a quarter of the way from front to back.
  light.fullAtBack = true;
  const auto back = composeScene(*renderer_, 1.0f, true, std::span(&light, 1));
  EXPECT_NEAR(back[32 * 96 + 48].r, 0.1f + 0.125f, 0.02f);
  // Modulating: the surface times mix(1, colour, weight), here weight 0.5 * intensity... with
  // intensity 0.5 at half depth: k = 0.25 -> red x 1, green x 0.875, blue x 0.75.
  light.fullAtBack = false;
  light.modulate = true;
  light.color = {1.0f, 0.5f, 0.0f};
  const auto modulated = composeScene(*renderer_, 1.0f, true, std::span(&light, 1));
  const float pole = 26.0f / 255.0f;
  EXPECT_NEAR(modulated[32 * 96 + 48].r, pole, 0.005f);
  EXPECT_NEAR(modulated[32 * 96 + 48].g, pole * 0.875f, 0.005f);
  EXPECT_NEAR(modulated[32 * 96 + 48].b, pole * 0.75f, 0.005f);
}

// The explosion light's projected texture: over the cone from the eye tangent to the explosion's
// sphere, the weight falls as (1 - rho^2)^2, rho the angle from the sphere's centre over the cone's
// half angle. The pole stands behind the centre (full in depth), and each of its rows sees the
// light at another angle: the added light down the column is 0.5 (1 - rho^2)^2 of its colour.
TEST_F(MediaLayersTest, ExplosionLightFallsOffOverItsProjectedDisc) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.0f)}).ok());
  media::ExplosionLight light;
  light.center = {0.15f, 0.3f, -2.5f};
  light.radius = 1.0f;
  light.color = {1.0f, 0.5f, 0.0f};
  light.intensity = 0.5f;
  const auto lit = composeScene(*renderer_, 1.0f, true, std::span(&light, 1));
  const int w = 96, h = 64, x = 48;
  const double t = std::tan(glm::radians(20.0)), aspect = double(w) / h;
  const glm::dvec3 c(light.center);
  const double halfAngle = std::asin(light.radius / glm::length(c));
  double worst = 0.0, lowest = 1.0;
  for (int y = 0; y < h; ++y) {
    const glm::dvec3 dir =
        glm::normalize(glm::dvec3(((x + 0.5) / w * 2.0 - 1.0) * t * aspect, ((y + 0.5) / h * 2.0 - 1.0) * t, -1.0));
    const double rho = std::acos(std::clamp(glm::dot(dir, glm::normalize(c)), -1.0, 1.0)) / halfAngle;
    const double weight = rho < 1.0 ? (1.0 - rho * rho) * (1.0 - rho * rho) : 0.0;
    lowest = std::min(lowest, weight);
    const glm::vec4 p = lit[static_cast<std::size_t>(y) * w + x];
    worst = std::max({worst, std::abs(p.r - (0.1 + 0.5 * weight)), std::abs(p.g - (0.1 + 0.25 * weight))});
  }
  EXPECT_LT(lowest, 0.3);  // the column reaches well out toward the disc's edge
  EXPECT_LT(worst, 2e-3);
}

}  // namespace
}  // namespace puff
