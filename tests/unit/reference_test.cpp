// The exact media reference (puff/reference/media_reference.h) and the image metrics
// (puff/reference/metrics.h): first against closed forms, then the GPU media path against the
// reference on a small scene of overlapping smoke, fire and dust.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/bake/detail.h>
#include <puff/core/blackbody.h>
#include <puff/gl_api.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>
#include <puff/reference/media_reference.h>
#include <puff/reference/metrics.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/media_target.h"

namespace puff {
namespace {

using reference::MediaReferenceInput;

constexpr int kSize = 65;  // odd: the centre pixel's ray is the view axis
constexpr int kCentre = kSize / 2;

// A camera at the origin looking down -z.
media::Frame axisFrame(int w, int h, float nearPlane = 0.5f, float farPlane = 50.0f) {
  media::Frame f;
  f.projection =
      glm::perspective(glm::radians(40.0f), static_cast<float>(w) / static_cast<float>(h), nearPlane, farPlane);
  f.nearPlane = nearPlane;
  f.farPlane = farPlane;
  f.width = w;
  f.height = h;
  f.lightDirection = glm::vec3(0.0f, 0.6f, 0.8f);
  f.lightColor = glm::vec3(0.9f, 0.8f, 0.7f);
  f.ambient = glm::vec3(0.2f, 0.25f, 0.3f);
  return f;
}

double linearDepth(const media::Frame& f, double distance) {
  return (distance - f.nearPlane) / (f.farPlane - f.nearPlane);
}

media::Material plain(float tau, float albedo = 0.6f) {
  media::Material m;
  m.name = "plain";
  m.albedo = albedo;
  m.density = tau;
  m.color = glm::vec3(1.0f, 0.5f, 0.25f);
  m.g = 0.3f;
  m.detail = 0.0f;
  return m;
}

media::Particle sphereAt(glm::vec3 c, float r, std::uint32_t material = 0) {
  media::Particle p;
  p.position = c;
  p.radius = r;
  p.material = material;
  return p;
}

// a * color * (ambient + light * 4 pi P): what a non-emissive material scatters along `dir`.
glm::dvec3 scattered(const media::Frame& f, const media::Material& m, const glm::dvec3& dir,
                     media::PhaseModel model = media::PhaseModel::kCornetteShanks) {
  const glm::dvec3 l = glm::normalize(glm::dvec3(f.lightDirection));  // view = identity
  const double p4pi = 4.0 * std::numbers::pi * media::phase(model, glm::dot(l, dir), m.g);
  return static_cast<double>(m.albedo) * glm::dvec3(m.color) *
         (glm::dvec3(f.ambient) + glm::dvec3(f.lightColor) * p4pi);
}

glm::dvec3 pixel(const core::Image& im, int x, int glRow) {
  const int y = im.height - 1 - glRow;
  return {im.at(x, y, 0), im.at(x, y, 1), im.at(x, y, 2)};
}

core::Image render(const MediaReferenceInput& in, core::Image* layer = nullptr) {
  auto image = reference::renderMediaReference(in, layer);
  EXPECT_OK(image);
  return image.ok() ? std::move(*image) : core::Image();
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
  in.frame.orthographic = true;
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

// ---- the GPU media path against the reference -------------------------------------------------------

constexpr int kW = 96, kH = 64;
constexpr float kWallDistance = 6.0f;  // a wall behind the right part of the image, through the cloud
constexpr int kWallFrom = 60;          // first column of the wall
// Multiples of 1/255; the RGBA16F opaque layer holds them to within 2e-4.
const glm::vec3 kSky(0.4f, 0.6f, 0.8f), kWall(0.6f, 0.4f, 0.2f);

class ReferenceGpu : public test::MediaRendererTest {};

// The scene's frame: a turned camera (so the view transform matters) looking into the cloud.
media::Frame cloudFrame() {
  media::Frame f;
  f.view = glm::lookAt(glm::vec3(0.4f, 0.3f, 0.0f), glm::vec3(0.0f, 0.0f, -6.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  f.projection = glm::perspective(glm::radians(45.0f), static_cast<float>(kW) / kH, 0.5f, 50.0f);
  f.nearPlane = 0.5f;
  f.farPlane = 50.0f;
  f.width = kW;
  f.height = kH;
  f.lightDirection = glm::vec3(0.4f, 1.0f, 0.3f);
  f.lightColor = glm::vec3(1.0f, 0.95f, 0.9f);
  f.ambient = glm::vec3(0.25f);
  return f;
}

// smoke, fire, dust (g 0.4) and a fire that turns into smoke over its life.
std::vector<media::Material> cloudMaterials() {
  media::Material dust = media::dustMaterial();
  dust.g = 0.4f;
  media::Material turning = media::fireMaterial();
  turning.name = "fire-to-smoke";
  turning.becomes = 0;
  turning.transitionStart = 0.2f;
  turning.transitionEnd = 0.8f;
  return {media::smokeMaterial(), media::fireMaterial(), dust, turning};
}

// 30 overlapping particles from a fixed LCG (no <random>: its distributions differ between libraries).
std::vector<media::Particle> cloudParticles() {
  std::uint32_t s = 12345u;
  auto next = [&s] {
    s = s * 1664525u + 1013904223u;
    return static_cast<float>(s >> 8) / 16777216.0f;
  };
  std::vector<media::Particle> ps;
  for (int i = 0; i < 30; ++i) {
    media::Particle p;
    // One draw a statement, z first: the order the measurements below were made in (a call's
    // arguments are evaluated in an order each compiler picks).
    const float z = next(), y = next(), x = next();
    p.position = glm::vec3(-2.2f + 4.4f * x, -1.3f + 2.6f * y, -7.5f + 3.0f * z);
    p.radius = 0.5f + 0.8f * next();
    p.material = static_cast<std::uint32_t>(i % 4);
    p.life = next();
    p.density = 0.6f + 0.8f * next();
    p.seed = s;
    ps.push_back(p);
  }
  return ps;
}

struct Opaque {
  std::vector<glm::vec3> color;
  std::vector<float> depth;
};

// The opaque layer the GPU draws (sky at infinity, the wall at kWallDistance), row 0 at the bottom.
Opaque cloudOpaque(const media::Frame& f, bool wall) {
  Opaque o;
  o.color.assign(kW * kH, kSky);
  o.depth.assign(kW * kH, 1.0f);
  if (wall) {
    for (int j = 0; j < kH; ++j)
      for (int i = kWallFrom; i < kW; ++i) {
        o.color[static_cast<std::size_t>(j) * kW + i] = kWall;
        o.depth[static_cast<std::size_t>(j) * kW + i] = static_cast<float>(linearDepth(f, kWallDistance));
      }
  }
  return o;
}

// The opaque layer alone as an image (row 0 at the top): the background coverage is measured against.
core::Image opaqueImage(const Opaque& o) {
  core::Image im(kW, kH, 4, 1.0f);
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i)
      for (int c = 0; c < 3; ++c) im.at(i, kH - 1 - j, c) = o.color[static_cast<std::size_t>(j) * kW + i][c];
  return im;
}

// Draws the scene through media::Layers at full resolution and reads the composed image back.
core::Image drawGpu(media::Renderer& r, const media::Frame& f, const Opaque& opaque, bool wall,
                    std::span<const media::Particle> particles, media::Method method) {
  auto layers = media::Layers::create(kW, kH, 1, 1.0f);
  EXPECT_OK(layers);
  const GLuint fbo = (*layers)->opaqueFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  const glm::vec4 sky(kSky, 1.0f), wallColor(kWall, 1.0f);
  glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &sky.x);
  glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
  if (wall) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(kWallFrom, 0, kW - kWallFrom, kH);
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &wallColor.x);
    glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, opaque.depth[kW - 1], 0);
    glDisable(GL_SCISSOR_TEST);
  }
  (*layers)->resolveOpaque();
  (*layers)->beginMedia();
  r.draw((*layers)->layerFrame(f), particles, method, (*layers)->mediaDepth());
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, kW, kH);
  glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  const int vp[4] = {0, 0, kW, kH};
  (*layers)->compose(out.get(), vp, f, {}, media::ComposeSettings{});
  std::vector<glm::vec4> px(static_cast<std::size_t>(kW) * kH);
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(glm::vec4)), px.data());
  EXPECT_EQ(core::drainGlErrors(), "");
  core::Image im(kW, kH, 4);
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i)
      for (int c = 0; c < 4; ++c) im.at(i, kH - 1 - j, c) = px[static_cast<std::size_t>(j) * kW + i][c];
  return im;
}

// Draws straight into an RGBA32F target cleared to the opaque colours (the blend then leaves
// opaque * T + M in it, as the composition computes): the shader's arithmetic without the 16-bit
// layer, against an R32F depth texture holding exactly the reference's depths.
core::Image drawFloatTarget(media::Renderer& r, const media::Frame& f, const Opaque& opaque, bool wall,
                            std::span<const media::Particle> particles, media::Method method) {
  core::Framebuffer fbo = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D), depth = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, kW, kH);
  glTextureStorage2D(depth.get(), 1, GL_R32F, kW, kH);
  glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(depth.get(), 0, 0, 0, kW, kH, GL_RED, GL_FLOAT, opaque.depth.data());
  const glm::vec4 sky(kSky, 1.0f), wallColor(kWall, 1.0f);
  glDisable(GL_SCISSOR_TEST);
  glClearNamedFramebufferfv(fbo.get(), GL_COLOR, 0, &sky.x);
  if (wall) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(kWallFrom, 0, kW - kWallFrom, kH);
    glClearNamedFramebufferfv(fbo.get(), GL_COLOR, 0, &wallColor.x);
    glDisable(GL_SCISSOR_TEST);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.get());
  glViewport(0, 0, kW, kH);
  r.draw(f, particles, method, depth.get());
  std::vector<glm::vec4> px(static_cast<std::size_t>(kW) * kH);
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(glm::vec4)), px.data());
  EXPECT_EQ(core::drainGlErrors(), "");
  core::Image im(kW, kH, 4);
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i)
      for (int c = 0; c < 3; ++c) im.at(i, kH - 1 - j, c) = px[static_cast<std::size_t>(j) * kW + i][c];
  return im;
}

core::Image drawReference(const media::Frame& f, const Opaque& opaque, std::span<const media::Particle> particles,
                          std::span<const media::Material> materials, const core::DetailVideo* temperature = nullptr,
                          const core::DetailVideo* opacity = nullptr, bool viewAxisOrder = false) {
  MediaReferenceInput in;
  in.viewAxisOrder = viewAxisOrder;
  in.frame = f;
  in.particles = particles;
  in.materials = materials;
  in.opaqueColor = opaque.color;
  in.opaqueDepth = opaque.depth;
  in.temperatureDetail = temperature;
  in.opacityDetail = opacity;
  return render(in);
}

// The pixels the wall covers, in core::Image order (row 0 at the top).
std::vector<bool> wallRegion() {
  std::vector<bool> m(kW * kH, false);
  for (int y = 0; y < kH; ++y)
    for (int x = kWallFrom; x < kW; ++x) m[static_cast<std::size_t>(y) * kW + x] = true;
  return m;
}

TEST_F(ReferenceGpu, TheShaderComputesTheReferenceModel) {
  // In a float target, composited in the renderer's own order (viewAxisOrder), the spherical
  // billboards must equal the reference up to 32-bit arithmetic and the GPU's tables: the phase
  // table (512 x 256, bilinear), the 1024-texel black-body ramp and the detail videos held as
  // 16-bit floats. Measured on llvmpipe: RMSE 7.5e-6 / max 4.3e-5 without detail, 1.35e-5 / 1.4e-4
  // with both videos, whose detail changes the image by RMSE 0.017 / max 0.11 (so a wrong hash,
  // window, row flip or time offset would show 1000 times over).
  const media::Frame f = cloudFrame();
  const auto particles = cloudParticles();
  auto materials = cloudMaterials();
  ASSERT_TRUE(renderer_->setMaterials(materials).ok());
  renderer_->setDetail(nullptr, nullptr);
  for (bool wall : {false, true}) {
    SCOPED_TRACE(wall ? "wall" : "no wall");
    const Opaque o = cloudOpaque(f, wall);
    const core::Image gpu = drawFloatTarget(*renderer_, f, o, wall, particles, media::Method::kSpherical);
    const core::Image ref = drawReference(f, o, particles, materials, nullptr, nullptr, true);
    const reference::ImageError e = reference::imageError(gpu, ref);
    std::printf("float target, no detail, %s: rmse %.2e max %.2e\n", wall ? "wall" : "no wall", e.rmse, e.maxAbs);
    EXPECT_LT(e.rmse, 5e-5);
    EXPECT_LT(e.maxAbs, 5e-4);
  }

  bake::DetailSpec spec;
  spec.size = 32;
  spec.frames = 8;
  spec.frequency = 2;
  spec.octaves = 3;
  auto temperature = bake::generateDetailVideo(spec);
  spec.seed = 7;
  auto opacity = bake::generateDetailVideo(spec);
  ASSERT_TRUE(temperature.ok() && opacity.ok());
  // Smoke with full density detail turns into dust.
  materials[3] = media::smokeMaterial();
  materials[3].becomes = 2;
  materials[3].detail = 1.0f;
  ASSERT_TRUE(renderer_->setMaterials(materials).ok());
  renderer_->setDetail(&*temperature, &*opacity);
  media::Frame later = f;
  later.time = 1.3f;
  for (bool wall : {false, true}) {
    SCOPED_TRACE(wall ? "wall" : "no wall");
    const Opaque o = cloudOpaque(later, wall);
    const core::Image gpu = drawFloatTarget(*renderer_, later, o, wall, particles, media::Method::kSpherical);
    const core::Image ref = drawReference(later, o, particles, materials, &*temperature, &*opacity, true);
    const core::Image plain = drawReference(later, o, particles, materials, nullptr, nullptr, true);
    const reference::ImageError e = reference::imageError(gpu, ref), detail = reference::imageError(plain, ref);
    std::printf("float target, detail videos, %s: rmse %.2e max %.2e (the videos change it by rmse %.4f)\n",
                wall ? "wall" : "no wall", e.rmse, e.maxAbs, detail.rmse);
    EXPECT_LT(e.rmse, 5e-5);
    EXPECT_LT(e.maxAbs, 1e-3);
    EXPECT_GT(detail.rmse, 0.01);
  }
  renderer_->setDetail(nullptr, nullptr);
}

// Curves over life give each particle its own tint and temperature. The shader takes
// them as the reference does (float target, the renderer's order: as TheShaderComputesTheReferenceModel),
// and they change the image by far more than the two differ. A tint of 0 leaves only what the medium
// absorbs, exactly as materials that neither scatter nor emit, on the textured billboards too; a
// particle's own temperature is exactly the material's T0 set to it.
TEST_F(ReferenceGpu, ParticlesTintsAndTemperaturesAreTheReferenceModels) {
  const media::Frame f = cloudFrame();
  const auto materials = cloudMaterials();
  ASSERT_TRUE(renderer_->setMaterials(materials).ok());
  renderer_->setDetail(nullptr, nullptr);
  const Opaque o = cloudOpaque(f, false);
  auto particles = cloudParticles();
  const auto plain = particles;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const float k = static_cast<float>(i) / static_cast<float>(particles.size());
    particles[i].tint = glm::vec3(1.0f - 0.8f * k, 0.3f + 0.5f * k, 0.6f);
    particles[i].temperature = i % 3 == 0 ? 0.0f : 1200.0f + 2400.0f * k;  // a third keep the material's
  }
  const core::Image gpu = drawFloatTarget(*renderer_, f, o, false, particles, media::Method::kSpherical);
  const core::Image ref = drawReference(f, o, particles, materials, nullptr, nullptr, true);
  const core::Image untinted = drawReference(f, o, plain, materials, nullptr, nullptr, true);
  const reference::ImageError e = reference::imageError(gpu, ref), change = reference::imageError(untinted, ref);
  std::printf("tints and temperatures: GPU against the reference rmse %.2e max %.2e (they change it by rmse %.4f)\n",
              e.rmse, e.maxAbs, change.rmse);
  EXPECT_LT(e.rmse, 5e-5);
  EXPECT_LT(e.maxAbs, 5e-4);
  EXPECT_GT(change.rmse, 0.02);

  std::vector<media::Material> dark = materials;
  for (media::Material& m : dark) {
    m.albedo = 0.0f;
    m.emission = 0.0f;
  }
  std::vector<media::Particle> black = plain, hot = plain;
  for (media::Particle& p : black) p.tint = glm::vec3(0.0f);
  for (media::Particle& p : hot) p.temperature = 1800.0f;
  std::vector<media::Material> at1800 = materials;
  for (media::Material& m : at1800) m.temperature = 1800.0f;
  for (media::Method method : {media::Method::kSpherical, media::Method::kPlanarTextured}) {
    SCOPED_TRACE(std::string(media::toString(method)));
    const core::Image tintedBlack = drawFloatTarget(*renderer_, f, o, false, black, method);
    const core::Image heated = drawFloatTarget(*renderer_, f, o, false, hot, method);
    ASSERT_TRUE(renderer_->setMaterials(dark).ok());
    const core::Image absorbing = drawFloatTarget(*renderer_, f, o, false, plain, method);
    ASSERT_TRUE(renderer_->setMaterials(at1800).ok());
    const core::Image materialHeat = drawFloatTarget(*renderer_, f, o, false, plain, method);
    ASSERT_TRUE(renderer_->setMaterials(materials).ok());
    const core::Image own = drawFloatTarget(*renderer_, f, o, false, plain, method);
    EXPECT_EQ(reference::imageError(tintedBlack, absorbing).maxAbs, 0.0) << "a tint of 0: only absorption";
    EXPECT_EQ(reference::imageError(heated, materialHeat).maxAbs, 0.0) << "its own T0 is the material's set to it";
    EXPECT_GT(reference::imageError(own, absorbing).rmse, 0.02) << "the cloud scatters and emits";
    EXPECT_GT(reference::imageError(own, heated).rmse, 0.005) << "1800 K is not the materials' temperature";
  }
}

TEST_F(ReferenceGpu, SphericalBillboardsMatchTheReferenceAndPlanarOnesDoNotAtAWall) {
  // The whole GPU path (media::Renderer + media::Layers at scale 1: RGBA16F opaque colour, depth24
  // resolved to R32F, RGBA16F layer, composition) against the exact reference, 30 overlapping
  // particles of smoke, fire, dust and fire turning into smoke, no detail video. Measured on
  // llvmpipe (RMSE / max):
  //   spherical, no wall  6.0e-4 / 0.0101      spherical, wall  4.5e-4 / 0.0098 (wall region 2.6e-4)
  //   planar, no wall     6.0e-4 / 0.0101      planar, wall     1.03e-2 / 0.119 (wall region 1.7e-2)
  // What the spherical error is made of (no wall):
  //   - order: the reference composited in the GPU's view-axis order instead of per ray differs
  //     from the exact one by 4.8e-4 / 0.0106: overlapping spheres whose centres' depth order is
  //     not their order along every ray;
  //   - the 16-bit float layer: the GPU against that view-axis-order reference, 4.1e-4 / 0.0026,
  //     darker on average by 2.7e-4 (llvmpipe's half-float blending looks like it rounds toward
  //     zero); in a float target the same comparison gives 7.5e-6 (TheShaderComputesTheReferenceModel);
  //   - the half-float (RGBA16F) opaque colour: the sky and wall round by at most 2e-4 (any colour
  //     in [0, 1] by at most 2.5e-4), times the transmittance;
  //   - the depth24 opaque depth: about 3e-6 world units at 6, far below everything else.
  // Thresholds: 2.5 times the measured RMSE, 3 times the largest order difference.
  const media::Frame f = cloudFrame();
  const auto materials = cloudMaterials();
  const auto particles = cloudParticles();
  ASSERT_TRUE(renderer_->setMaterials(materials).ok());
  renderer_->setDetail(nullptr, nullptr);
  const Opaque bare = cloudOpaque(f, false), walled = cloudOpaque(f, true);

  const core::Image refBare = drawReference(f, bare, particles, materials);
  const core::Image refWall = drawReference(f, walled, particles, materials);
  const core::Image sphericalBare = drawGpu(*renderer_, f, bare, false, particles, media::Method::kSpherical);
  const core::Image sphericalWall = drawGpu(*renderer_, f, walled, true, particles, media::Method::kSpherical);
  const core::Image planarBare = drawGpu(*renderer_, f, bare, false, particles, media::Method::kPlanar);
  const core::Image planarWall = drawGpu(*renderer_, f, walled, true, particles, media::Method::kPlanar);

  // The scene is not empty: most of the image is medium (3967 of 6144 pixels).
  const core::Image bareOpaque = opaqueImage(bare), wallOpaque = opaqueImage(walled);
  const std::vector<bool> covered = reference::coverageMask(refBare, bareOpaque);
  EXPECT_GT(std::count(covered.begin(), covered.end(), true), kW * kH / 2);

  const std::vector<bool> region = wallRegion();
  const reference::ImageError sphBare = reference::imageError(sphericalBare, refBare);
  const reference::ImageError sphWall = reference::imageError(sphericalWall, refWall);
  const reference::ImageError sphRegion = reference::imageError(sphericalWall, refWall, region);
  const reference::ImageError plaBare = reference::imageError(planarBare, refBare);
  const reference::ImageError plaWall = reference::imageError(planarWall, refWall);
  const reference::ImageError plaRegion = reference::imageError(planarWall, refWall, region);
  const reference::ImageError order =
      reference::imageError(drawReference(f, bare, particles, materials, nullptr, nullptr, true), refBare);
  const double iouSpherical = reference::coverageIoU(sphericalWall, refWall, wallOpaque);
  const double iouPlanar = reference::coverageIoU(planarWall, refWall, wallOpaque);
  std::printf("spherical: no wall rmse %.2e (psnr %.1f dB) max %.4f; wall rmse %.2e max %.4f, wall region %.2e\n",
              sphBare.rmse, sphBare.psnr, sphBare.maxAbs, sphWall.rmse, sphWall.maxAbs, sphRegion.rmse);
  std::printf("planar:    no wall rmse %.2e (psnr %.1f dB) max %.4f; wall rmse %.2e max %.4f, wall region %.2e\n",
              plaBare.rmse, plaBare.psnr, plaBare.maxAbs, plaWall.rmse, plaWall.maxAbs, plaRegion.rmse);
  std::printf("view-axis order alone: rmse %.2e max %.4f; coverage IoU spherical %.4f planar %.4f\n", order.rmse,
              order.maxAbs, iouSpherical, iouPlanar);

  for (const reference::ImageError& e : {sphBare, sphWall}) {
    EXPECT_LT(e.rmse, 1.5e-3);
    EXPECT_LT(e.maxAbs, 0.03);
  }
  // Away from surfaces planar billboards shade exactly like spherical ones.
  EXPECT_NEAR(plaBare.rmse, sphBare.rmse, 1e-5);
  // The wall cuts planar billboards whole: an error 23 times the spherical one, 66 times where the
  // wall is; the smoke's coverage IoU drops from 0.998 to 0.919.
  EXPECT_GT(plaWall.rmse, 10.0 * sphWall.rmse);
  EXPECT_GT(plaRegion.rmse, 0.01);
  EXPECT_GT(iouSpherical, 0.99);
  EXPECT_LT(iouPlanar, 0.95);
}

TEST_F(ReferenceGpu, TheGpuSortsByTheViewAxisTheReferenceAlongEachRay) {
  // ReferenceAnalytic.OverlappingSpheresCompositeInTheirOrderAlongTheRay's two spheres on the GPU:
  // it draws B over A everywhere (B's centre is nearer the camera plane), so on the rays where A's
  // chord comes first it equals the view-axis-order reference, not the exact one.
  media::Material ma = plain(0.8f), mb = plain(1.5f);
  ma.color = glm::vec3(1.0f, 0.0f, 0.0f);
  mb.color = glm::vec3(0.0f, 0.0f, 1.0f);
  const std::vector<media::Material> mats = {ma, mb};
  const media::Particle ps[] = {sphereAt({0, 0, -10}, 5.0f, 0), sphereAt({4, 0, -9}, 1.0f, 1)};
  ASSERT_TRUE(renderer_->setMaterials(mats).ok());
  renderer_->setDetail(nullptr, nullptr);
  media::Frame f = axisFrame(kW, kH);
  f.projection = glm::perspective(glm::radians(70.0f), static_cast<float>(kW) / kH, 0.5f, 50.0f);
  const Opaque o = cloudOpaque(f, false);
  const core::Image gpu = drawFloatTarget(*renderer_, f, o, false, ps, media::Method::kSpherical);
  const core::Image exact = drawReference(f, o, ps, mats);
  const core::Image viewAxis = drawReference(f, o, ps, mats, nullptr, nullptr, true);
  const reference::ImageError toViewAxis = reference::imageError(gpu, viewAxis);
  const reference::ImageError toExact = reference::imageError(gpu, exact);
  std::printf("two spheres: GPU against the view-axis order rmse %.2e, against the per-ray order rmse %.4f max %.4f\n",
              toViewAxis.rmse, toExact.rmse, toExact.maxAbs);
  EXPECT_LT(toViewAxis.rmse, 5e-5);
  EXPECT_GT(toExact.maxAbs, 0.05);
}

TEST_F(ReferenceGpu, GpuOpacityStaysContinuousAsFireStartsTurningIntoSmoke) {
  // Emitters upload detail 0 (as their albedo), like the reference. A shader that applies the
  // opacity detail only while the mixed emissive weight is below 1, with the mixed `detail` field
  // (for fire, 0.5 by default, otherwise unused), makes tau jump by 1 + 0.5 (2 D - 1) the moment fire
  // starts turning into smoke: with D = 0.1 everywhere the centre pixel goes from
  // (0.5601, 0.4458, 0.4184) at life 0.2499 to (0.5102, 0.4938, 0.5372) at 0.2501.
  media::Material fire = media::fireMaterial(), smoke = media::smokeMaterial();
  fire.becomes = 1;
  fire.transitionStart = 0.25f;
  fire.transitionEnd = 0.75f;
  fire.burn = 0.0f;
  smoke.detail = 1.0f;
  const std::vector<media::Material> mats = {fire, smoke};
  ASSERT_TRUE(renderer_->setMaterials(mats).ok());
  core::DetailVideo dark;
  dark.width = dark.height = 4;
  dark.frames = 1;
  dark.values.assign(16, 0.1f);
  renderer_->setDetail(nullptr, &dark);
  const media::Frame f = axisFrame(kW, kH);
  const Opaque o = cloudOpaque(f, false);
  for (float life : {0.2499f, 0.2501f, 0.5f}) {
    SCOPED_TRACE(life);
    media::Particle p = sphereAt({0, 0, -5}, 1.0f);
    p.life = life;
    const core::Image gpu = drawFloatTarget(*renderer_, f, o, false, std::span(&p, 1), media::Method::kSpherical);
    const core::Image ref = drawReference(f, o, std::span(&p, 1), mats, nullptr, &dark, true);
    EXPECT_LT(reference::imageError(gpu, ref).maxAbs, 1e-3);
  }
  renderer_->setDetail(nullptr, nullptr);
}

}  // namespace
}  // namespace puff
