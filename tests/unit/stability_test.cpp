// Stability: where the methods break, and that Puff stays right there. Each test here
// asserts against a closed form and would fail on a regression; the counts they measure are
// printed so the margins can be judged.
//
// This file is the index. Failure cases already covered elsewhere (not repeated here):
//
//  cel path (nailboard_test.cpp, opaque_test.cpp)
//   - camera inside a billboard shadow volume (depth-pass counting is off by one there; Puff counts
//     depth-fail):                          Nailboards.ShadowStaysRightWithTheCameraInsideTheVolume
//   - a shadow volume through the near plane:
//                                           Nailboards.ShadowStaysRightWithAVolumeThroughTheNearPlane
//   - outlines between overlapping puffs (flange must hide behind the other body):
//                                           Nailboards.FlangeBetweenOverlappingParticlesIsHidden
//   - billboard alignment seen from above / off axis (axial foreshortens, viewpoint stretches):
//                                           Nailboards.AxialBillboardsForeshortenFromAbove,
//                                           Nailboards.ViewpointBillboardsDistortLikeASphere
//   - 16-byte packing quantization:         ParticlePacking.SixteenBytesRoundTripWithinQuantization
//   - NaN / infinite / singular opaque objects refused:
//                                           OpaqueTest.SetObjectsRejectsBadInputNamingTheObject
//  media path (media_test.cpp, media_scene_test.cpp)
//   - planar billboards clip where they cross a wall; soft and spherical do not:
//                                           MediaTest.PlanarCutsIntoAWallSoftAndSphericalDoNot
//   - a wall in front of the sphere gives zero, not a negative path (the paper's snippet):
//                                           MediaTest.WallInFrontGivesZeroNotNegative
//   - the near plane crossing a sphere: planar pops, spherical is continuous:
//                                           MediaTest.PlanarPopsAtTheNearPlaneWhereSphericalIsContinuous,
//                                           MediaTest.NearPlaneInsideTheSphereClipsAsTheFormulaSays,
//                                           MediaScenes.FlyingIntoSmokePopsWithPlanarBillboardsNotSpherical
//   - low-resolution layers halo around near edges (bilinear) and drift at odd sizes:
//                                           MediaLayersTest.DepthAwareUpsamplingRemovesHalosAroundNearEdges,
//                                           MediaLayersTest.ALowResolutionLayerStaysAlignedAtSizesNotAMultipleOfItsFactor
//   - the g = 0.95 phase peak (a cos-spaced table misses it):
//                                           MediaTest.InScatteringFollowsThePhaseFunction
//   - Planck's exponent overflowing (no light, not NaN); NaN / empty black-body ramps refused:
//                                           BlackbodyPlanck.IntegratesToStefanBoltzmannAndMeetsRayleighJeans,
//                                           BlackbodyRamp.BadArgumentsSayWhichValueAndTheRange
//  simulator (sim_test.cpp, sim_forces_test.cpp)
//   - forward Euler diverges at drag * step > 2, the exponential integrator stays bounded:
//                                           Simulator.ForwardEulerDivergesWherePuffStaysBounded
//   - drag -> 0 (no division by the drag): Simulator.TinyDragIsTheBallisticLimit
//   - every input at its limit, huge and tiny steps: no non-finite particle:
//                                           Simulator.ExtremeValuesNeverGiveNonFinitePositions
//   - fast particles tunnelling through meshes, moving colliders:
//                                           Simulator.FastParticlesDoNotTunnelThroughAMesh,
//                                           Simulator.MovingCollidersPushParticlesAside,
//                                           Simulator.SweepingMeshPushesTheSmokeItCrosses
//   - dissipation to zero size without a pop: Simulator.DissipationShrinksLinearlyToNothing
//   - a budget below the births (250/s on 100): Simulator.EmittersBornAtTheirRateWithinTheBudget
//   - NaN drag, zero substeps, zero axis, budget + 1: Simulator.RejectsImpossibleValuesNamingTheField
//  scenes and inputs (scene_test.cpp, mesh_test.cpp, detail_video_test.cpp)
//   - NaN / infinite / overflowing numbers: Scene.NonFiniteNumbersAreRejected,
//                                           SceneFiles.OverflowingNumbersInTheFileAreRejected
//   - too many listed / emitted particles (count 1000001, total 2000001), simulation budget 1e12:
//                                           Scene.ErrorsNameTheFileThePointerWhatWasExpectedAndWhatCame,
//                                           SceneSimulation.ImpossibleValuesNameTheField
//   - NaN mesh vertices, NaN generator parameters:
//                                           MeshValidate.NamesTheProblemAndWhere,
//                                           MeshIo.ANanInBinaryPlyIsCaughtAfterReading,
//                                           MeshParams.ErrorsNameTheParameterAndItsRange,
//                                           DetailVideoGenerate.BadSpecsNameTheFlag
//
// Added here:
//   StabilityDepth        linear vs hyperbolic 24-bit depth for nailboards meeting 900 units away
//   StabilityCel          a nailboard larger than the screen; one particle with a non-finite
//                         position does not wipe out its whole batch
//   StabilityMedia        zero and tiny radius, a sphere over the whole screen, the camera inside one
// and in stability_inputs_test.cpp:
//   StabilityBudget(Scene) a million births per second on a budget of a thousand (simulator,
//                         parser limits, a rendered media scene)
//   StabilityInputs       zero-size and NaN inputs the cel and media headers promise to refuse
//                         (ramps, gradients, media layers, renderer settings, materials)
//   StabilityInputsSim    the same for simulator settings, and zero sizes it promises to accept
//                         (zero-size particles and colliders, particles born at a collider's centre)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/core/gl.h>
#include <puff/gl_api.h>
#include <puff/media/media.h>

#include "stability_test_helpers.h"
#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/gl_target.h"
#include "support/linear_frame.h"
#include "support/media_target.h"
#include "support/sphere_atlas.h"

namespace puff {
namespace {

using test::kInf;
using test::kNaN;

bool finite(const glm::vec4& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && std::isfinite(c.a);
}

// ---- cel: a baked sphere puff ---------------------------------------------------------------------

class CelFixture : public test::SphereAtlasTest {
 protected:
  static constexpr int kPx = 128;

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

  // Draws `particles` lit with `frame` into the current contents of the target (no clear).
  void drawOver(const cel::Frame& frame, const std::vector<cel::Particle>& particles, const cel::Style& style) {
    EXPECT_OK(block_->upload(frame));
    ramp_->bind();
    renderer_->upload(particles);
    renderer_->drawNailboards(style, cel::ShadePass::kLit);
  }

  std::unique_ptr<cel::NailboardRenderer> renderer_;
  std::unique_ptr<cel::FrameBlock> block_;
  std::unique_ptr<test::OffscreenTarget> target_;
  std::unique_ptr<cel::Ramp> ramp_;
};

class StabilityDepth : public CelFixture {};
class StabilityCel : public CelFixture {};

// The ray through pixel centre (x, y) of a square perspective target, camera space (looking down -z).
glm::dvec3 pixelRay(int x, int y, int size, double tanHalf) {
  const double nx = (x + 0.5) / size * 2.0 - 1.0, ny = (y + 0.5) / size * 2.0 - 1.0;
  return glm::normalize(glm::dvec3(nx * tanHalf, ny * tanHalf, -1.0));
}

// Distance along the view axis to the front of a sphere on the ray from the origin, or -1 (miss).
// |c x dir| for the distance to the ray: no |c|^2 - b^2 cancellation 900 units away.
double frontDistance(const glm::dvec3& dir, const glm::dvec3& centre, double r, double* rayDistance = nullptr) {
  const glm::dvec3 across = glm::cross(centre, dir);
  const double d2 = glm::dot(across, across);
  if (rayDistance) *rayDistance = std::sqrt(d2);
  if (!(d2 < r * r)) return -1.0;
  const double t = glm::dot(centre, dir) - std::sqrt(r * r - d2);
  return t * -dir.z;
}

// McGuire & Fein §4.2 keep the depth buffer LINEAR so nailboard offsets are additions. The other
// reason is precision. With near 0.1 and far 1000, a standard hyperbolic 24-bit buffer,
//     z_ndc = (f + n) / (f - n) - 2 f n / ((f - n) z),  stored as round((z_ndc / 2 + 1/2) (2^24 - 1)),
// has steps of z^2 (f - n) / (f n (2^24 - 1)) = 0.48 world units at z = 900: fewer than five steps
// across a puff two units deep, whatever the field of view. Linear depth has (f - n) / 2^24 = 6e-5
// units everywhere. Two sphere puffs interpenetrating 900 units away (a telephoto camera, so they
// fill the target and each pixel is a sample of the intersection): the renderer's curve between
// them matches the analytic one, and the hyperbolic values of the same two surfaces, computed here
// on the CPU, cannot even order them over much of the overlap.
TEST_F(StabilityDepth, FarIntersectionsStayRightInLinearDepthWhereHyperbolicCannotOrderThem) {
  const double n = 0.1, f = 1000.0;
  const double tanHalf = 2.0 / 900.0;  // 4 world units tall at 900: 32 px per unit
  cel::Camera cam;
  cam.position = glm::vec3(0.0f);
  cam.target = glm::vec3(0, 0, -1);
  cam.fovYDegrees = static_cast<float>(glm::degrees(2.0 * std::atan(tanHalf)));
  cam.nearPlane = static_cast<float>(n);
  cam.farPlane = static_cast<float>(f);
  cel::Frame frame = test::linearFrame(cam, kPx, kPx);
  frame.light.color = glm::vec3(0.0f);  // colour = K_a exactly, so each puff is known by its colour
  struct Ball {
    glm::dvec3 centre;
    double r;
    glm::vec3 color;
  };
  const Ball balls[2] = {{{-0.55, 0.05, -900.0}, 1.0, {1, 0, 0}}, {{0.6, -0.1, -900.35}, 1.2, {0, 1, 0}}};
  ASSERT_LT(glm::length(balls[0].centre - balls[1].centre), balls[0].r + balls[1].r);  // they interpenetrate
  cel::Style style;
  style.outlines = false;
  style.shading = false;
  target_->clear(glm::vec4(0, 0, 0, 1), 1.0f);
  // One draw per puff: the depth test between them is the same LESS test as inside one draw.
  for (const Ball& b : balls) {
    frame.ambient = puff::core::srgbToLinear(b.color);
    drawOver(frame, {cel::Particle{glm::vec3(b.centre), static_cast<float>(2.0 * b.r)}}, style);
  }
  EXPECT_EQ(core::drainGlErrors(), "");
  const auto px = target_->readColor();
  const auto depth = target_->readDepth();

  // Per pixel: the analytic front distances and owner (0 none, 1 first, 2 second ball).
  const std::size_t count = static_cast<std::size_t>(kPx) * kPx;
  std::vector<double> za(count, -1.0), zb(count, -1.0);
  std::vector<int> owner(count, 0);
  std::vector<bool> both(count, false);  // inside both silhouettes (with a margin): on the overlap
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * kPx + x;
      const glm::dvec3 dir = pixelRay(x, y, kPx, tanHalf);
      double ra = 0.0, rb = 0.0;
      za[i] = frontDistance(dir, balls[0].centre, balls[0].r, &ra);
      zb[i] = frontDistance(dir, balls[1].centre, balls[1].r, &rb);
      if (za[i] > 0.0 && zb[i] > 0.0) {
        owner[i] = za[i] < zb[i] ? 1 : 2;
      } else {
        owner[i] = za[i] > 0.0 ? 1 : (zb[i] > 0.0 ? 2 : 0);
      }
      both[i] = ra < 0.95 * balls[0].r && rb < 0.95 * balls[1].r;
    }
  }

  // 1. The rendered curve: wrong owners only next to the analytic curve.
  auto rendered = [&](std::size_t i) {
    const glm::vec4 c = px[i];
    if (c.r > 0.5f && c.g < 0.5f) return 1;
    if (c.g > 0.5f && c.r < 0.5f) return 2;
    return 0;
  };
  auto nearCurve = [&](int x, int y, int reach) {  // a pixel of the other analytic owner within `reach`
    const int own = owner[static_cast<std::size_t>(y) * kPx + x];
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dx = -reach; dx <= reach; ++dx) {
        const int u = x + dx, v = y + dy;
        if (u < 0 || v < 0 || u >= kPx || v >= kPx) continue;
        const std::size_t j = static_cast<std::size_t>(v) * kPx + u;
        if (both[j] && owner[j] != own) return true;
      }
    return false;
  };
  int overlap = 0, curve = 0, wrong = 0, wrongFar = 0;
  double worstDepth = 0.0;  // |rendered - analytic| front distance, world units
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * kPx + x;
      if (!both[i]) continue;
      ++overlap;
      curve += nearCurve(x, y, 1) ? 1 : 0;
      if (rendered(i) != owner[i]) {
        ++wrong;
        wrongFar += nearCurve(x, y, 2) ? 0 : 1;
      }
      const double zmin = std::min(za[i], zb[i]);
      worstDepth = std::max(worstDepth, std::abs(depth[i] * (f - n) + n - zmin));
    }
  }

  // 2. What each 24-bit buffer would hold for the two surfaces at the same pixels.
  const glm::mat4 proj = frame.projection;
  auto hyperbolicIdeal = [&](double z) {  // exact arithmetic, then quantized
    const double ndc = (f + n) / (f - n) - 2.0 * f * n / ((f - n) * z);
    return std::llround((0.5 * ndc + 0.5) * 16777215.0);
  };
  auto hyperbolicGpu = [&](double z) {  // float32 clip-space arithmetic as a GPU does it
    const glm::vec4 clip = proj * glm::vec4(0.0f, 0.0f, static_cast<float>(-z), 1.0f);
    const float window = clip.z / clip.w * 0.5f + 0.5f;
    return std::llround(static_cast<double>(window) * 16777215.0);
  };
  auto linear = [&](double z) {  // what the cel programs write: (dist - near) / (far - near), in float
    const float lin = (static_cast<float>(z) - static_cast<float>(n)) * (1.0f / static_cast<float>(f - n));
    return std::llround(static_cast<double>(lin) * 16777215.0);
  };
  // A tie, or the nearer surface stored as the farther (1 tie, 2 inversion, 0 ordered).
  auto unordered = [&](auto depthOf, std::size_t i) {
    const long long qa = depthOf(za[i]), qb = depthOf(zb[i]);
    return qa == qb ? 1 : ((qa < qb) != (za[i] < zb[i]) ? 2 : 0);
  };
  // How far from the analytic curve a pixel lies, in pixels (Chebyshev), up to 64.
  auto pixelsFromCurve = [&](int x, int y) {
    int k = 1;
    while (k < 64 && !nearCurve(x, y, k)) ++k;
    return k;
  };
  int idealTies = 0, gpuTies = 0, gpuInversions = 0, linearBad = 0, idealReach = 0;
  double idealWidest = 0.0, linearWidest = 0.0;  // the largest depth gap each one could not order
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * kPx + x;
      if (!both[i]) continue;
      const double gap = std::abs(za[i] - zb[i]);
      if (unordered(hyperbolicIdeal, i) != 0) {  // exact arithmetic can only tie
        ++idealTies;
        idealWidest = std::max(idealWidest, gap);
        idealReach = std::max(idealReach, pixelsFromCurve(x, y));
      }
      const int gpu = unordered(hyperbolicGpu, i);
      gpuTies += gpu == 1 ? 1 : 0;
      gpuInversions += gpu == 2 ? 1 : 0;
      if (unordered(linear, i) != 0) ++linearBad, linearWidest = std::max(linearWidest, gap);
    }
  }
  std::printf(
      "overlap %d px, curve %d px; rendered (linear) owner wrong at %d px, %d of them farther than 2 px from the "
      "curve; depth within %.4f units\n"
      "24-bit hyperbolic cannot order the two surfaces at %d px (exact arithmetic: ties, gaps up to %.3f units, up "
      "to %d px from the curve) / %d ties + %d inversions (float32 clip space); 24-bit linear at %d px\n",
      overlap, curve, wrong, wrongFar, worstDepth, idealTies, idealWidest, idealReach, gpuTies, gpuInversions,
      linearBad);

  ASSERT_GT(overlap, 800);
  ASSERT_GT(curve, 60);
  EXPECT_EQ(wrongFar, 0);       // the rendered curve is right to within two pixels
  EXPECT_LT(wrong, curve / 4);  // and almost everywhere to within one
  EXPECT_LT(worstDepth, 0.05);  // the linear depth of the nearer surface, from the 8-bit depth map
  EXPECT_LE(linearBad, 2);      // only where the surfaces are within 6e-5 units of each other
  // Measured (on the CPU, so on any GL): 521 of 1153 px (45%) tie, at gaps up to 0.43
  // units and up to 10 px from the curve; with float32 clip-space arithmetic 322 px (28%) tie.
  EXPECT_GT(idealTies, overlap / 4);
  EXPECT_GT(idealWidest, 0.3);
  EXPECT_GE(idealReach, 5);
  EXPECT_GT(gpuTies + gpuInversions, overlap / 6);
}

// A nailboard larger than the screen (radius 26 at distance 30, the screen's corners 24.5 from the
// axis there): every pixel is body, no outline shows, and the depth is the nailboard's model,
// (billboard distance - sqrt(R^2 - rho^2)), rho measured in the billboard plane.
TEST_F(StabilityCel, ANailboardLargerThanTheScreenCoversItWithTheRightDepth) {
  cel::Camera cam;
  cam.position = glm::vec3(0, 0, 30);
  cam.target = glm::vec3(0);
  cam.fovYDegrees = 60.0f;
  cam.nearPlane = 1.0f;
  cam.farPlane = 100.0f;
  cel::Frame frame = test::linearFrame(cam, kPx, kPx);
  frame.light.direction = glm::vec3(0, 0, 1);
  frame.light.color = puff::core::srgbToLinear(glm::vec3(0.5f));
  frame.ambient = puff::core::srgbToLinear(glm::vec3(0.2f));
  const double R = 26.0, dz = 30.0, tanHalf = std::tan(glm::radians(30.0));
  cel::Style style;  // outlines on: the flange is off screen, so none may show
  target_->clear(glm::vec4(1.0f), 1.0f);
  drawOver(frame, {cel::Particle{glm::vec3(0.0f), static_cast<float>(2.0 * R)}}, style);
  EXPECT_EQ(core::drainGlErrors(), "");
  const auto px = target_->readColor();
  const auto depth = target_->readDepth();
  int background = 0, ink = 0, nonFinite = 0;
  double worst = 0.0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * kPx + x;
      const glm::vec4 c = px[i];
      nonFinite += finite(c) ? 0 : 1;
      background += (c.r > 0.99f && c.g > 0.99f && c.b > 0.99f) ? 1 : 0;
      ink += (c.r < 0.05f && c.g < 0.05f && c.b < 0.05f) ? 1 : 0;
      const double nx = (x + 0.5) / kPx * 2.0 - 1.0, ny = (y + 0.5) / kPx * 2.0 - 1.0;
      const double rho = std::hypot(nx, ny) * tanHalf * dz;
      const double front = dz - std::sqrt(R * R - rho * rho);
      worst = std::max(worst, std::abs(depth[i] * 99.0 + 1.0 - front));
    }
  }
  std::printf("nailboard over the screen: %d background, %d ink px; depth within %.3f units\n", background, ink, worst);
  EXPECT_EQ(nonFinite, 0);
  EXPECT_EQ(background, 0);
  EXPECT_EQ(ink, 0);
  // 8-bit depth map over a 52-unit diameter: 0.1 units a step, more where the sphere is steep.
  EXPECT_LT(worst, 0.5);
}

// One particle with a non-finite position must not take the whole batch with it: bounds come from
// finite positions only, and a non-finite one draws nothing. Bounds from every position would make
// the box infinite for x = +inf anywhere (or NaN in the first particle), and every particle would
// unpack to NaN (the two puffs below: 975 px without the bad one, 0 with it).
TEST_F(StabilityCel, ANonFiniteParticleDoesNotTakeTheOthersWithIt) {
  const std::vector<cel::Particle> good = {cel::Particle{glm::vec3(-1.2f, 0.6f, 0), 1.5f},
                                           cel::Particle{glm::vec3(1.2f, -0.6f, 0.4f), 1.5f}};
  cel::Camera cam;
  cam.position = glm::vec3(0, 0, 10);
  cam.target = glm::vec3(0);
  cam.fovYDegrees = 40.0f;
  const cel::Frame frame = test::linearFrame(cam, kPx, kPx);
  const cel::Style style;
  auto image = [&](const std::vector<cel::Particle>& ps) {
    target_->clear(glm::vec4(1.0f), 1.0f);
    drawOver(frame, ps, style);
    EXPECT_EQ(core::drainGlErrors(), "");
    return target_->readColor();
  };
  const auto reference = image(good);
  for (const glm::vec3 bad :
       {glm::vec3(kInf, 0, 0), glm::vec3(0, -kInf, 0), glm::vec3(kNaN, 0, 0), glm::vec3(0, 0, kNaN)}) {
    for (bool first : {true, false}) {
      SCOPED_TRACE(std::to_string(bad.x) + " " + std::to_string(bad.y) + " " + std::to_string(bad.z) +
                   (first ? " first" : " last"));
      std::vector<cel::Particle> ps = good;
      ps.insert(first ? ps.begin() : ps.end(), cel::Particle{bad, 1.0f});
      std::vector<cel::PackedParticle> packed;
      const cel::PackBounds b = cel::packParticles(ps, packed);
      for (std::size_t i = 0; i < ps.size(); ++i) {
        if (!std::isfinite(ps[i].position.x + ps[i].position.y + ps[i].position.z)) continue;
        const cel::Particle out = cel::unpackParticle(packed[i], b);
        EXPECT_LT(glm::length(out.position - ps[i].position), 1e-3f) << i;
      }
      const auto px = image(ps);
      int differing = 0;
      for (std::size_t i = 0; i < px.size(); ++i) differing += px[i] != reference[i] ? 1 : 0;
      EXPECT_EQ(differing, 0);  // the bad one draws nothing, the others as before
    }
  }
}

// ---- media ------------------------------------------------------------------------------------

constexpr int kMediaPx = 65;  // odd: the centre pixel's ray is the view axis

using test::MediaCamera;
using test::MediaTarget;
using test::plainMaterial;
using test::sphereAt;

const glm::vec4 kClear(0.25f, 0.5f, 0.75f, 1.0f);

class StabilityMedia : public test::MediaRendererTest {
 protected:
  std::vector<glm::vec4> draw(const MediaTarget& t, const MediaCamera& cam, const media::Particle& p,
                              media::Method method, media::DrawStats* stats = nullptr) {
    glClearNamedFramebufferfv(t.fbo.get(), GL_COLOR, 0, &kClear.x);
    glBindFramebuffer(GL_FRAMEBUFFER, t.fbo.get());
    glViewport(0, 0, kMediaPx, kMediaPx);
    renderer_->draw(cam.frame(kMediaPx), std::span(&p, 1), method, t.depth.get(), media::Shimmer::kOff, stats);
    EXPECT_EQ(core::drainGlErrors(), "");
    return t.read();
  }

  // The largest |opacity - media::sphereOpacity| over the target (opacity = 1 - alpha / kClear.a),
  // with the ray clipped by `clipNear` (the planar methods: no clipping, -1e30).
  static double worstError(const std::vector<glm::vec4>& px, const MediaCamera& cam, const media::Particle& p,
                           double tau, double clipNear, int* nonFinite = nullptr, int* drawn = nullptr,
                           double* above = nullptr) {
    double worst = 0.0;
    for (int y = 0; y < kMediaPx; ++y) {
      for (int x = 0; x < kMediaPx; ++x) {
        const glm::vec4 c = px[static_cast<std::size_t>(y) * kMediaPx + x];
        if (nonFinite) *nonFinite += finite(c) ? 0 : 1;
        if (drawn) *drawn += c.a < 1.0f ? 1 : 0;
        const double expected = media::sphereOpacity(glm::dvec3(0.0), cam.ray(x, y, kMediaPx), glm::dvec3(p.position),
                                                     p.radius, tau, 1e30, clipNear);
        worst = std::max(worst, std::abs((1.0 - c.a) - expected));
        if (above) *above = std::max(*above, (1.0 - c.a) - expected);
      }
    }
    return worst;
  }
};

// A particle shrinking to nothing over its life: every pixel's opacity falls monotonically with the
// radius, stays under the centre's 1 - exp(-2 tau r) and on the formula, and radius 0 draws nothing
// (not one pixel touched). Radii down to a float denormal. Below about 2e-4 (here) the quad is
// narrower than the rasterizer's subpixel grid (1/256 px on llvmpipe) and yields no fragment: the
// particle vanishes while its formula opacity is 8e-5, a step far below what any target holds, and
// never a wrong value above the formula.
TEST_F(StabilityMedia, AParticleShrinkingToZeroRadiusFadesToNothing) {
  const float tau = 0.4f;
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(tau)}).ok());
  const MediaTarget t(kMediaPx);
  const MediaCamera cam;
  std::vector<glm::vec4> last;
  for (float r : {1.0f, 0.3f, 0.1f, 0.03f, 0.01f, 3e-3f, 1e-3f, 1e-4f, 1e-6f, 1e-9f, 1e-20f, 1e-40f, 0.0f}) {
    SCOPED_TRACE(r);
    const media::Particle p = sphereAt({0, 0, -5}, r);
    media::DrawStats stats;
    const auto px = draw(t, cam, p, media::Method::kSpherical, &stats);
    int nonFinite = 0;
    double above = 0.0;
    const double worst = worstError(px, cam, p, tau, cam.nearPlane, &nonFinite, nullptr, &above);
    EXPECT_LE(worst, r >= 1e-3f ? 2e-5 : std::max(2e-5, 1.0 - std::exp(-2.0 * tau * r) + 1e-9));
    EXPECT_LT(above, 2e-5);
    EXPECT_EQ(nonFinite, 0);
    double most = 0.0;
    for (std::size_t i = 0; i < px.size(); ++i) {
      most = std::max(most, 1.0 - px[i].a);
      if (!last.empty()) {
        ASSERT_GE(px[i].a, last[i].a - 1e-6f) << "pixel " << i << " got denser as it shrank";
      }
    }
    EXPECT_LE(most, 1.0 - std::exp(-2.0 * tau * r) + 1e-6);
    if (r == 0.0f) {
      EXPECT_EQ(stats.particles, 0u);
      for (const glm::vec4& c : px) ASSERT_EQ(c, kClear);
    }
    last = px;
  }
}

// A sphere over the whole screen, three ways: the camera deep inside a huge one (opacity = the path
// from the near plane to the exit), one whose front reaches the camera's plane (a quad over the
// whole target), one larger than the view but in front of the near plane (planar and spherical
// agree there). Every pixel is drawn and on the formula.
TEST_F(StabilityMedia, ASphereOverTheWholeScreenMatchesTheFormulaAtEveryPixel) {
  const MediaTarget t(kMediaPx);
  const MediaCamera cam;
  struct Case {
    const char* name;
    glm::vec3 centre;
    float radius, tau;
    media::Method method;
  };
  const Case cases[] = {
      {"camera deep inside", {0, 0, -5}, 1000.0f, 1e-3f, media::Method::kSpherical},
      {"front at the camera plane", {0.2f, 0.1f, -2.0f}, 1.95f, 0.5f, media::Method::kSpherical},
      {"larger than the view", {0, 0, -4}, 3.0f, 0.3f, media::Method::kSpherical},
      {"larger than the view", {0, 0, -4}, 3.0f, 0.3f, media::Method::kPlanar},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.name) + ", " + std::string(media::toString(c.method)));
    ASSERT_TRUE(renderer_->setMaterials({plainMaterial(c.tau)}).ok());
    const media::Particle p = sphereAt(c.centre, c.radius);
    const auto px = draw(t, cam, p, c.method);
    int nonFinite = 0, drawn = 0;
    const double worst = worstError(px, cam, p, c.tau, cam.nearPlane, &nonFinite, &drawn);
    std::printf("%s (%s): %d of %d px drawn, worst error %.2g\n", c.name,
                std::string(media::toString(c.method)).c_str(), drawn, kMediaPx * kMediaPx, worst);
    EXPECT_EQ(nonFinite, 0);
    EXPECT_EQ(drawn, kMediaPx * kMediaPx);
    EXPECT_LT(worst, 2e-5);
  }
}

// The camera inside a particle. Spherical: the path from the near plane to the exit, whether the
// centre is in front of the camera or behind it. Planar: the whole chord while its centre is in
// front of the near plane (its known error: it counts the medium behind the camera too), and
// nothing at all once the centre is behind the near plane.
TEST_F(StabilityMedia, TheCameraInsideAParticle) {
  const float tau = 0.3f;
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(tau)}).ok());
  const MediaTarget t(kMediaPx);
  const MediaCamera cam;  // near plane at 0.5
  const int centre = (kMediaPx / 2) * kMediaPx + kMediaPx / 2;
  for (float z : {-1.0f, -0.3f, 0.8f}) {  // centre in front of the near plane, between it and the eye, behind
    SCOPED_TRACE(z);
    const media::Particle p = sphereAt({0.3f, -0.2f, z}, 2.0f);
    ASSERT_LT(glm::length(p.position), p.radius);  // the eye is inside
    int nonFinite = 0, drawn = 0;
    const auto spherical = draw(t, cam, p, media::Method::kSpherical);
    EXPECT_LT(worstError(spherical, cam, p, tau, cam.nearPlane, &nonFinite, &drawn), 2e-5);
    EXPECT_EQ(drawn, kMediaPx * kMediaPx);
    const auto planar = draw(t, cam, p, media::Method::kPlanar);
    if (-z > cam.nearPlane) {
      EXPECT_LT(worstError(planar, cam, p, tau, -1e30, &nonFinite), 2e-5);  // the unclipped chord
      std::printf("camera inside, centre at %.1f: centre pixel spherical %.4f, planar %.4f\n", z,
                  1.0 - spherical[centre].a, 1.0 - planar[centre].a);
      EXPECT_GT(spherical[centre].a, planar[centre].a + 0.05f);  // planar is too dense by the part behind the eye
    } else {
      for (const glm::vec4& c : planar) ASSERT_EQ(c, kClear);
    }
    EXPECT_EQ(nonFinite, 0);
  }
}

}  // namespace
}  // namespace puff
