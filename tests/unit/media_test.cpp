// The media billboards (spherical, planar, soft, planar-textured) and their materials against closed forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/core/blackbody.h>
#include <puff/gl_api.h>
#include <puff/media/media.h>

#include "support/assert_ok.h"
#include "support/media_target.h"

namespace puff {
namespace {

using media::Method;

constexpr int kSize = 65;  // odd: the centre pixel's ray goes through the sphere's centre

using test::MediaTarget;
using test::plainMaterial;
using test::sphereAt;
using Camera = test::MediaCamera;

// One sphere seen from a camera at the origin looking down -z, walls made by filling the linear
// depth texture with a known depth, every pixel compared with the double-precision formula
// (media::sphereOpacity).
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

// The spherical quad is the box the silhouette projects into (billboard.vert): it must hold every
// pixel the sphere covers wherever the sphere is: on the axis and off it to past the target's corner,
// far and close (down to 1.08 r, just outside the quad-over-everything case), through the usual
// projection and an off-centre one (a host's asymmetric frustum: ndc x = P00 x / -z - P20). Every
// pixel against the closed form through that projection's own rays.
TEST_F(MediaTest, TheSphericalQuadHoldsTheWholeSilhouetteAnywhereInView) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(0.9f)}).ok());
  MediaTarget t(kSize);
  t.setDepth(1.0f);
  const Camera cam;
  const double n = cam.nearPlane, tanHalf = std::tan(glm::radians(static_cast<double>(cam.fovDegrees)) / 2.0);
  const struct {
    const char* name;
    glm::dmat4 projection;
  } projections[] = {{"the camera's own",
                      glm::dmat4(glm::perspective(glm::radians(cam.fovDegrees), 1.0f, cam.nearPlane, cam.farPlane))},
                     {"off-centre", glm::frustum(-0.4 * n * tanHalf, 1.6 * n * tanHalf, -1.3 * n * tanHalf,
                                                 0.7 * n * tanHalf, n, static_cast<double>(cam.farPlane))}};
  const double r = 0.8;
  for (const auto& proj : projections) {
    const glm::dmat4 inv = glm::inverse(proj.projection);
    for (double dz : {1.08 * r / 0.95, 2.5, 6.0}) {
      for (glm::dvec2 off : {glm::dvec2(0, 0), glm::dvec2(0.7, 0.2), glm::dvec2(-1.0, 0.9), glm::dvec2(1.3, -1.25)}) {
        // The centre `off` of the half field of view off the axis (1 = the edge's direction).
        const glm::dvec3 centre(off.x * tanHalf * dz, off.y * tanHalf * dz, -dz);
        SCOPED_TRACE(std::string(proj.name) + " projection, centre " + std::to_string(centre.x) + ", " +
                     std::to_string(centre.y) + ", " + std::to_string(centre.z));
        t.clear({0, 0, 0, 1});
        t.bind();
        media::Frame f = cam.frame(t.size);
        f.projection = glm::mat4(proj.projection);
        const media::Particle p = sphereAt(glm::vec3(centre), static_cast<float>(r));
        renderer_->draw(f, std::span(&p, 1), Method::kSpherical, t.depth.get());
        ASSERT_EQ(core::drainGlErrors(), "");
        const std::vector<glm::vec4> px = t.read();
        double worst = 0.0;
        int covered = 0;
        for (int y = 0; y < kSize; ++y) {
          for (int x = 0; x < kSize; ++x) {
            const glm::dvec4 ndc((x + 0.5) / kSize * 2.0 - 1.0, (y + 0.5) / kSize * 2.0 - 1.0, -1.0, 1.0);
            const glm::dvec4 near = inv * ndc;
            const glm::dvec3 ray = glm::normalize(glm::dvec3(near) / near.w);
            const double expected = media::sphereOpacity(glm::dvec3(0.0), ray, centre, r, 0.9, 1e30, n);
            const double got = 1.0 - px[static_cast<std::size_t>(y) * kSize + x].a;
            worst = std::max(worst, std::abs(got - expected));
            covered += expected > 0.0 ? 1 : 0;
          }
        }
        EXPECT_LT(worst, 2e-5) << covered << " pixels covered";
      }
    }
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
    if (nearPlane > 1.0f) {
      EXPECT_GT(clipped, 100) << "the near plane cuts them";
    }
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
      f.light.color = glm::vec3(1.0f);
      for (glm::vec3 l : {glm::vec3(0, 0.6f, 0.8f), glm::vec3(0, 0.6f, -0.8f), glm::vec3(1, 0, 0),
                          glm::vec3(0, 0.1f, -1), glm::vec3(0, 0.03f, -1), glm::vec3(0, 0, -1)}) {
        f.light.direction = l;
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

}  // namespace
}  // namespace puff
