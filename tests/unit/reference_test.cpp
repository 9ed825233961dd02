// The exact media reference against closed forms, and the image metrics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <puff/core/blackbody.h>
#include <puff/core/detail_video.h>
#include <puff/core/image.h>
#include <puff/media/media.h>
#include <puff/reference/media_reference.h>
#include <puff/reference/metrics.h>

#include "reference_test_helpers.h"
#include "support/assert_ok.h"

namespace puff::reference_test {
namespace {

constexpr int kSize = 65;  // odd: the centre pixel's ray is the view axis
constexpr int kCentre = kSize / 2;

// a * color * (ambient + light * 4 pi P): what a non-emissive material scatters along `dir`.
glm::dvec3 scattered(const media::Frame& f, const media::Material& m, const glm::dvec3& dir,
                     media::PhaseModel model = media::PhaseModel::kCornetteShanks) {
  const glm::dvec3 l = glm::normalize(glm::dvec3(f.light.direction));  // view = identity
  const double p4pi = 4.0 * std::numbers::pi * media::phase(model, glm::dot(l, dir), m.g);
  return static_cast<double>(m.albedo) * glm::dvec3(m.color) *
         (glm::dvec3(f.ambient) + glm::dvec3(f.light.color) * p4pi);
}

glm::dvec3 pixel(const core::Image& im, int x, int glRow) {
  const int y = im.height - 1 - glRow;
  return {im.at(x, y, 0), im.at(x, y, 1), im.at(x, y, 2)};
}

void expectNear(const glm::dvec3& got, const glm::dvec3& expected, double tolerance) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], tolerance) << "channel " << c;
}

// ---- the reference against closed forms ----------------------------------------------------------

TEST(ReferenceAnalytic, LoneSphereCentreIsUmenhofferEquationOne) {
  const media::Material m = plain(0.4f);
  const media::Particle p = sphereAt({0, 0, -5}, 1.0f);
  MediaReferenceInput in;
  in.frame = axisFrame(kSize, kSize);
  in.particles = std::span(&p, 1);
  in.materials = std::span(&m, 1);
  in.background = glm::vec3(0.1f, 0.3f, 0.9f);
  core::Image layer;
  const core::Image im = render(in, &layer);
  ASSERT_EQ(im.width, kSize);
  ASSERT_EQ(im.channels, 4);
  // Centre: the full diameter at falloff 1, L = I (1 - alpha) + alpha a C.
  const double alpha = 1.0 - std::exp(-2.0 * 0.4 * 1.0);
  const glm::dvec3 bg(in.background), l = scattered(in.frame, m, {0, 0, -1});
  expectNear(pixel(im, kCentre, kCentre), bg * (1.0 - alpha) + alpha * l, 1e-6);
  EXPECT_NEAR(layer.at(kCentre, kCentre, 3), 1.0 - alpha, 1e-6);  // the layer's transmittance
  EXPECT_EQ(im.at(kCentre, kCentre, 3), 1.0f);
  // An off-axis pixel: chord 2 sqrt(r^2 - d^2), falloff 1 - d / r, phase along its own ray.
  const reference::Ray ray = reference::pixelRay(in.frame, kCentre + 5, kCentre - 3);
  const double b = glm::dot(-glm::dvec3(0, 0, -5), ray.direction);
  const double d = std::sqrt(25.0 - b * b);
  const double a2 = 1.0 - std::exp(-0.4 * (1.0 - d) * 2.0 * std::sqrt(1.0 - d * d));
  expectNear(pixel(im, kCentre + 5, kCentre - 3), bg * (1.0 - a2) + a2 * scattered(in.frame, m, ray.direction), 1e-6);
  // Outside the silhouette: the background.
  expectNear(pixel(im, 0, 0), bg, 0.0);
}

TEST(ReferenceAnalytic, BurnBlendsAsIlmonenEquationThree) {
  media::Material m = plain(0.9f);
  m.burn = 0.4f;
  const media::Particle p = sphereAt({0, 0, -5}, 1.0f);
  MediaReferenceInput in;
  in.frame = axisFrame(kSize, kSize);
  in.particles = std::span(&p, 1);
  in.materials = std::span(&m, 1);
  in.background = glm::vec3(0.5f, 0.7f, 0.2f);
  const double alpha = 1.0 - std::exp(-2.0 * 0.9);
  const glm::dvec3 expected =
      alpha * scattered(in.frame, m, {0, 0, -1}) + glm::dvec3(in.background) * (1.0 - alpha * (1.0 - 0.4));
  expectNear(pixel(render(in), kCentre, kCentre), expected, 1e-6);
}

TEST(ReferenceAnalytic, WallThroughTheCentreHalvesThePath) {
  const media::Material m = plain(0.4f);
  const media::Particle p = sphereAt({0, 0, -5}, 1.0f);
  MediaReferenceInput in;
  in.frame = axisFrame(kSize, kSize);
  in.particles = std::span(&p, 1);
  in.materials = std::span(&m, 1);
  const std::vector<glm::vec3> wall(kSize * kSize, glm::vec3(0.6f, 0.4f, 0.2f));
  const std::vector<float> depth(kSize * kSize, static_cast<float>(linearDepth(in.frame, 5.0)));
  in.opaqueColor = wall;
  in.opaqueDepth = depth;
  const double alpha = 1.0 - std::exp(-0.4 * 1.0);  // from the front at 4 to the wall at 5
  const glm::dvec3 expected = glm::dvec3(wall[0]) * (1.0 - alpha) + alpha * scattered(in.frame, m, {0, 0, -1});
  // The depth is a float: 5 is exact to about 1e-6 of the 49.5 range.
  expectNear(pixel(render(in), kCentre, kCentre), expected, 2e-6);
}

TEST(ReferenceAnalytic, WallInFrontLeavesTheOpaqueColourUntouched) {
  const media::Material m = plain(3.0f);
  const media::Particle p = sphereAt({0, 0, -5}, 1.0f);
  MediaReferenceInput in;
  in.frame = axisFrame(kSize, kSize);
  in.particles = std::span(&p, 1);
  in.materials = std::span(&m, 1);
  std::vector<glm::vec3> wall(kSize * kSize);
  for (std::size_t i = 0; i < wall.size(); ++i) wall[i] = glm::vec3(0.25f, 0.001f * static_cast<float>(i % 500), 0.75f);
  const std::vector<float> depth(kSize * kSize, static_cast<float>(linearDepth(in.frame, 3.5)));  // front is at 4
  in.opaqueColor = wall;
  in.opaqueDepth = depth;
  const core::Image im = render(in);
  for (int j = 0; j < kSize; ++j)
    for (int i = 0; i < kSize; ++i)
      ASSERT_EQ(pixel(im, i, j), glm::dvec3(wall[static_cast<std::size_t>(j) * kSize + i])) << i << ", " << j;
}

TEST(ReferenceAnalytic, NearPlaneInsideTheSphereClipsThePath) {
  const media::Material m = plain(0.4f);
  const media::Particle p = sphereAt({0, 0, -5}, 1.0f);
  for (float nearPlane : {4.5f, 5.0f, 5.5f}) {
    MediaReferenceInput in;
    in.frame = axisFrame(kSize, kSize, nearPlane);
    in.particles = std::span(&p, 1);
    in.materials = std::span(&m, 1);
    const double alpha = 1.0 - std::exp(-0.4 * (6.0 - nearPlane));  // from the near plane to the back at 6
    expectNear(pixel(render(in), kCentre, kCentre), alpha * scattered(in.frame, m, {0, 0, -1}), 1e-6);
  }
  // Wholly in front of the near plane: nothing.
  MediaReferenceInput in;
  in.frame = axisFrame(kSize, kSize, 6.5f);
  in.particles = std::span(&p, 1);
  in.materials = std::span(&m, 1);
  expectNear(pixel(render(in), kCentre, kCentre), glm::dvec3(0.0), 0.0);
}

TEST(ReferenceAnalytic, OrthographicRaysAreParallel) {
  const media::Material m = plain(0.7f);
  const media::Particle p = sphereAt({0.3f, -0.2f, -5}, 1.2f);
  MediaReferenceInput in;
  in.frame = axisFrame(kSize, kSize);
  in.frame.projection = glm::ortho(-2.0f, 2.0f, -2.0f, 2.0f, in.frame.nearPlane, in.frame.farPlane);
  in.particles = std::span(&p, 1);
  in.materials = std::span(&m, 1);
  const core::Image im = render(in);
  for (int j = 0; j < kSize; j += 4) {
    for (int i = 0; i < kSize; i += 4) {
      const double x = ((i + 0.5) / kSize * 2 - 1) * 2, y = ((j + 0.5) / kSize * 2 - 1) * 2;
      const double d = std::hypot(x - 0.3, y + 0.2);
      const double a = d < 1.2 ? 1.0 - std::exp(-0.7 * (1.0 - d / 1.2) * 2.0 * std::sqrt(1.44 - d * d)) : 0.0;
      expectNear(pixel(im, i, j), a * scattered(in.frame, m, {0, 0, -1}), 1e-6);
    }
  }
}

TEST(ReferenceAnalytic, FireIsTheExactBlackBodyNormalizedLikeTheRamp) {
  media::Material fire = media::fireMaterial();
  fire.temperature = 3000.0f;
  fire.temperatureRange = 0.0f;
  fire.burn = 0.0f;
  fire.emission = 1.5f;
  const media::Particle p = sphereAt({0, 0, -5}, 1.0f);
  MediaReferenceInput in;
  in.frame = axisFrame(kSize, kSize);
  in.particles = std::span(&p, 1);
  in.materials = std::span(&fire, 1);
  in.settings.exposure = 2.0f;
  const double alpha = 1.0 - std::exp(-0.8);
  const glm::dvec3 le =
      glm::max(core::xyzToLinearSrgb(core::blackbodyXYZ(3000.0) / core::blackbodyXYZ(3200.0).y), glm::dvec3(0.0));
  const glm::dvec3 got = pixel(render(in), kCentre, kCentre);
  expectNear(got, alpha * 1.5 * 2.0 * le, 1e-6);
  // The GPU's 1024-texel ramp agrees to its interpolation error.
  auto ramp = core::makeBlackbodyRamp(1000, 10000, 1024, 3200);
  ASSERT_TRUE(ramp.ok());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(le[c], std::max(0.0f, ramp->at(3000.0)[c]), 1e-4);
  // Temperatures beyond the settings' range clamp to its end, as the texture lookup does.
  fire.temperature = 20000.0f;
  in.settings.exposure = 1.0f;
  fire.emission = 1.0f;
  const glm::dvec3 hot =
      glm::max(core::xyzToLinearSrgb(core::blackbodyXYZ(10000.0) / core::blackbodyXYZ(3200.0).y), glm::dvec3(0.0));
  expectNear(pixel(render(in), kCentre, kCentre), alpha * hot, 1e-5 * std::max(1.0, hot.b));
}

TEST(ReferenceAnalytic, OverlappingSpheresCompositeInTheirOrderAlongTheRay) {
  // B's centre is nearer the camera's plane than A's, but along the ray through B's centre A's
  // chord midpoint comes first: 10 cos(angle) = 9.14 against 9.85. The GPU sorts by the view axis
  // (B in front); the reference composites A in front of B on this ray.
  media::Material ma = plain(0.8f), mb = plain(1.5f);
  ma.color = glm::vec3(1.0f, 0.0f, 0.0f);
  mb.color = glm::vec3(0.0f, 0.0f, 1.0f);
  const media::Material mats[] = {ma, mb};
  const media::Particle ps[] = {sphereAt({0, 0, -10}, 5.0f, 0), sphereAt({4, 0, -9}, 1.0f, 1)};
  MediaReferenceInput in;
  in.frame = axisFrame(kSize, kSize);
  in.frame.projection = glm::perspective(glm::radians(70.0f), 1.0f, 0.5f, 50.0f);
  in.particles = ps;
  in.materials = mats;
  in.background = glm::vec3(0.5f);
  const core::Image im = render(in);
  // The pixel whose ray passes closest to B's centre.
  int bi = 0, bj = 0;
  double best = 1e9;
  for (int j = 0; j < kSize; ++j)
    for (int i = 0; i < kSize; ++i) {
      const glm::dvec3 dir = reference::pixelRay(in.frame, i, j).direction;
      const double miss = glm::length(glm::cross(glm::dvec3(4, 0, -9), dir));
      if (miss < best) best = miss, bi = i, bj = j;
    }
  const glm::dvec3 dir = reference::pixelRay(in.frame, bi, bj).direction;
  const double tA = glm::dot(glm::dvec3(0, 0, -10), dir), tB = glm::dot(glm::dvec3(4, 0, -9), dir);
  ASSERT_LT(tA, tB);  // A's midpoint is nearer along this ray
  const double aA = media::sphereOpacity({}, dir, {0, 0, -10}, 5.0, 0.8, 1e300, 0.5);
  const double aB = media::sphereOpacity({}, dir, {4, 0, -9}, 1.0, 1.5, 1e300, 0.5);
  ASSERT_GT(aA, 0.5);
  ASSERT_GT(aB, 0.5);
  const glm::dvec3 lA = scattered(in.frame, ma, dir), lB = scattered(in.frame, mb, dir);
  const glm::dvec3 behind = aB * lB + glm::dvec3(0.5) * (1.0 - aB);
  const glm::dvec3 aFront = aA * lA + behind * (1.0 - aA);
  const glm::dvec3 bFront = aB * lB + (aA * lA + glm::dvec3(0.5) * (1.0 - aA)) * (1.0 - aB);
  const glm::dvec3 got = pixel(im, bi, bj);
  expectNear(got, aFront, 1e-6);
  EXPECT_GT(glm::length(aFront - bFront), 0.05);  // the order matters here
}

TEST(ReferenceAnalytic, MaterialsMixOverTheLifeAndTauStaysContinuous) {
  // Fire becomes smoke between 25% and 75% of its life; with an opacity video whose values are far
  // from 0.5, tau must not jump as the transition starts (see the header).
  media::Material fire = media::fireMaterial(), smoke = media::smokeMaterial();
  fire.becomes = 1;
  fire.transitionStart = 0.25f;
  fire.transitionEnd = 0.75f;
  fire.burn = 0.0f;
  smoke.detail = 1.0f;
  const media::Material mats[] = {fire, smoke};
  core::DetailVideo dark;
  dark.width = dark.height = 4;
  dark.frames = 1;
  dark.values.assign(16, 0.1f);  // D = 0.1: the opacity factor 1 + (2 D - 1) = 0.2 for smoke
  media::Particle p = sphereAt({0, 0, -5}, 1.0f);
  MediaReferenceInput in;
  in.frame = axisFrame(kSize, kSize);
  in.particles = std::span(&p, 1);
  in.materials = mats;
  in.opacityDetail = &dark;
  auto centreAt = [&](float life) {
    p.life = life;
    return pixel(render(in), kCentre, kCentre);
  };
  const glm::dvec3 before = centreAt(0.2499f), start = centreAt(0.2501f);
  EXPECT_LT(glm::length(before - start), 1e-3);
  // Half way: every value mixed half and half; the emissive weight 0.5 scales the emission, and
  // the scattered light is that of albedo 0.1 (smoke's 0.2 mixed with fire's 0): linear in f.
  const double tau = 0.4 * (1.0 + 0.5 * (2.0 * 0.1 - 1.0));
  const double alpha = 1.0 - std::exp(-2.0 * tau);
  const glm::dvec3 le =
      glm::max(core::xyzToLinearSrgb(core::blackbodyXYZ(2850.0) / core::blackbodyXYZ(3200.0).y), glm::dvec3(0.0));
  media::Material half = smoke;
  half.albedo = 0.1f;
  const glm::dvec3 expected = alpha * (scattered(in.frame, half, {0, 0, -1}) + 0.5 * le);
  expectNear(centreAt(0.5f), expected, 1e-6);
}

TEST(ReferenceAnalytic, DetailVideoIsSampledLikeARepeatingLinearTexture) {
  core::DetailVideo v;
  v.width = 4;
  v.height = 5;
  v.frames = 2;
  v.values.resize(40);
  for (std::size_t i = 0; i < v.values.size(); ++i) v.values[i] = static_cast<float>(i) / 64.0f;
  // Texel centres: texture row t counts from the bottom, the video's rows from the top.
  EXPECT_DOUBLE_EQ(reference::sampleDetail(&v, 1.5 / 4, 0.5 / 5, 0.25), v.at(1, 4, 0));
  EXPECT_DOUBLE_EQ(reference::sampleDetail(&v, 2.5 / 4, 4.5 / 5, 0.75), v.at(2, 0, 1));
  // Half way between two texels in x, and repeating: s + 1 is s, the edge mixes the first and last.
  EXPECT_DOUBLE_EQ(reference::sampleDetail(&v, 2.0 / 4, 0.5 / 5, 0.25), 0.5 * (v.at(1, 4, 0) + v.at(2, 4, 0)));
  EXPECT_DOUBLE_EQ(reference::sampleDetail(&v, 1.0 + 2.0 / 4, -1.0 + 0.5 / 5, 2.25),
                   reference::sampleDetail(&v, 2.0 / 4, 0.5 / 5, 0.25));
  EXPECT_DOUBLE_EQ(reference::sampleDetail(&v, 0.0, 2.5 / 5, 0.25), 0.5 * (v.at(0, 2, 0) + v.at(3, 2, 0)));
  // Time wraps too: between the last frame and the first.
  EXPECT_DOUBLE_EQ(reference::sampleDetail(&v, 0.5 / 4, 0.5 / 5, 1.0), 0.5 * (v.at(0, 4, 0) + v.at(0, 4, 1)));
  EXPECT_EQ(reference::sampleDetail(nullptr, 0.3, 0.6, 0.2), 0.5);
}

TEST(ReferenceAnalytic, BadInputIsAnError) {
  const media::Material m = plain(0.4f);
  const media::Particle p = sphereAt({0, 0, -5}, 1.0f, 3);
  MediaReferenceInput in;
  in.frame = axisFrame(8, 8);
  in.materials = std::span(&m, 1);
  in.particles = std::span(&p, 1);
  auto r = reference::renderMediaReference(in);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "media reference: particles/0/material: expected an index below 1, got 3");
  in.particles = {};
  const std::vector<float> depth(10, 1.0f);
  in.opaqueDepth = depth;
  r = reference::renderMediaReference(in);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "media reference: opaque depth: expected 64 pixels, got 10");
  in.opaqueDepth = {};
  in.materials = {};
  EXPECT_FALSE(reference::renderMediaReference(in).ok());
}

// ---- metrics --------------------------------------------------------------------------------------

core::Image filled(int w, int h, int channels, float v) { return core::Image(w, h, channels, v); }

TEST(ReferenceMetrics, IdenticalImagesHaveNoError) {
  core::Image a(7, 5, 4);
  for (std::size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] = static_cast<float>(i % 13) / 13.0f;
  const reference::ImageError e = reference::imageError(a, a);
  EXPECT_EQ(e.rmse, 0.0);
  EXPECT_EQ(e.maxAbs, 0.0);
  EXPECT_EQ(e.psnr, std::numeric_limits<double>::infinity());
}

TEST(ReferenceMetrics, AKnownOffsetGivesItsRmseAndPsnr) {
  // Every RGB value off by 0.1 (alpha ignored, RGB against RGBA): RMSE 0.1, PSNR 20 dB.
  core::Image a = filled(6, 4, 4, 0.3f), b = filled(6, 4, 3, 0.4f);
  for (std::size_t i = 3; i < a.pixels.size(); i += 4) a.pixels[i] = 0.0f;
  reference::ImageError e = reference::imageError(a, b);
  EXPECT_NEAR(e.rmse, 0.1, 1e-7);
  EXPECT_NEAR(e.psnr, 20.0, 1e-5);
  EXPECT_NEAR(e.maxAbs, 0.1, 1e-7);
  // One value off by 0.6 of 72: RMSE 0.6 / sqrt(72); a mask without that pixel sees nothing.
  core::Image c = filled(6, 4, 3, 0.4f);
  c.at(2, 1, 1) = 1.0f;
  e = reference::imageError(b, c);
  EXPECT_NEAR(e.rmse, 0.6 / std::sqrt(72.0), 1e-7);
  EXPECT_NEAR(e.psnr, -20.0 * std::log10(0.6 / std::sqrt(72.0)), 1e-5);
  EXPECT_NEAR(e.maxAbs, 0.6, 1e-6);
  std::vector<bool> mask(24, true);
  mask[1 * 6 + 2] = false;
  EXPECT_EQ(reference::imageError(b, c, mask).rmse, 0.0);
}

TEST(ReferenceMetrics, CoverageIoUCountsPixelsThatDifferFromTheBackground) {
  const core::Image bg = filled(4, 1, 4, 0.5f);
  core::Image a = bg, b = bg;
  a.at(0, 0, 0) = 0.6f, a.at(1, 0, 2) = 0.3f, a.at(2, 0, 1) = 0.51f;  // the last is below 1/64
  b.at(1, 0, 0) = 0.9f, b.at(3, 0, 1) = 0.0f;
  EXPECT_EQ(reference::coverageMask(a, bg), (std::vector<bool>{true, true, false, false}));
  EXPECT_DOUBLE_EQ(reference::coverageIoU(a, b, bg), 1.0 / 3.0);  // {1} over {0, 1, 3}
  EXPECT_DOUBLE_EQ(reference::coverageIoU(bg, bg, bg), 1.0);      // both empty
  EXPECT_DOUBLE_EQ(reference::coverageIoU(a, b, bg, 0.5), 1.0);   // nothing differs by more than 0.5
}

TEST(ReferenceMetrics, SecondDifferenceOfARampIsZeroAndOfAStepIsTheStep) {
  std::vector<core::Image> ramp, step;
  for (int k = 0; k < 6; ++k) {
    ramp.push_back(filled(3, 2, 4, 0.125f * static_cast<float>(k)));
    step.push_back(filled(3, 2, 4, k < 3 ? 0.25f : 0.75f));
  }
  EXPECT_EQ(reference::largestSecondDifference(ramp), 0.0);
  EXPECT_EQ(reference::meanSecondDifference(ramp), 0.0);
  EXPECT_DOUBLE_EQ(reference::largestSecondDifference(step), 0.5);
  // Interior frames 1..4: the step shows at k = 2 and k = 3, once each.
  EXPECT_DOUBLE_EQ(reference::meanSecondDifference(step), 0.5 * 2.0 / 4.0);
  EXPECT_EQ(reference::largestSecondDifference(std::span(step).first(2)), 0.0);
}

TEST(ReferenceMetrics, LargestJumpIsBetweenNeighboursInTheRegion) {
  core::Image im = filled(5, 4, 3, 0.0f);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) im.at(x, y, 1) = 0.1f * static_cast<float>(x);
  im.at(4, 3, 2) = 0.9f;  // a spike in the corner
  EXPECT_NEAR(reference::largestJump(im), 0.9, 1e-6);
  std::vector<bool> region(20, true);
  region[3 * 5 + 4] = false;
  EXPECT_NEAR(reference::largestJump(im, region), 0.1, 1e-6);
}

}  // namespace
}  // namespace puff::reference_test
