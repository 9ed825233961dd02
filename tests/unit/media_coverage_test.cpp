// What of a frame the media can change (media::coverage): closed forms for an orthographic camera,
// and for a perspective one the box against the sphere's own projection (points of its surface,
// projected) over the positions, distances and sizes a scene can set; what draws nothing covers
// nothing; a sphere reaching the camera's plane covers the whole frame; lights as compose takes them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/media/coverage.h>

namespace puff {
namespace {

using media::PixelBox;

constexpr int kWidth = 200, kHeight = 160;  // the perspective frames
constexpr int kOrtho = 160;                 // the orthographic frame's width and height

// Orthographic: 10 pixels per world unit (x and y in [-8, 8]: the projection's scale 1/8 and the
// pixels exact in floats), looking down -z from the origin.
media::Frame orthoFrame() {
  media::Frame f;
  f.projection = glm::ortho(-8.0f, 8.0f, -8.0f, 8.0f, 0.5f, 50.0f);
  f.nearPlane = 0.5f;
  f.farPlane = 50.0f;
  f.viewport.width = kOrtho;
  f.viewport.height = kOrtho;
  return f;
}

media::Frame perspectiveFrame(float fovYDegrees) {
  media::Frame f;
  f.projection = glm::perspective(glm::radians(fovYDegrees), static_cast<float>(kWidth) / kHeight, 0.5f, 50.0f);
  f.nearPlane = 0.5f;
  f.farPlane = 50.0f;
  f.viewport.width = kWidth;
  f.viewport.height = kHeight;
  return f;
}

media::Particle particle(glm::vec3 p, float r) {
  media::Particle q;
  q.position = p;
  q.radius = r;
  return q;
}

TEST(MediaCoverage, AnOrthographicSphereCoversItsSquareGrownByAPixel) {
  // Centre (1, 0.5), radius 1: x in [0, 2] world = [80, 100] px; y in [-0.5, 1.5] = [75, 95] px.
  const media::Particle p = particle({1.0f, 0.5f, -5.0f}, 1.0f);
  EXPECT_EQ(media::coverage(orthoFrame(), std::span(&p, 1)), (PixelBox{79, 74, 101, 96}));
  // Fractional edges round out: centre (0.33, -0.27), radius 0.5 -> x [78.3, 88.3], y [72.3, 82.3].
  const media::Particle q = particle({0.33f, -0.27f, -5.0f}, 0.5f);
  EXPECT_EQ(media::coverage(orthoFrame(), std::span(&q, 1)), (PixelBox{77, 71, 90, 84}));
  // Two particles: the box holding both.
  const media::Particle both[2] = {p, q};
  EXPECT_EQ(media::coverage(orthoFrame(), both), (PixelBox{77, 71, 101, 96}));
}

// The pixel box of the sphere's projection under a perspective of the usual form (glm::perspective,
// or glm::frustum off centre): NDC x is P00 x / -z - P20, and x / -z over the sphere depends on
// (x, z) alone, a disc of radius r about (c.x, c.z) seen from the eye: its tangents from the origin
// bound it, at the centre's angle plus and minus asin(r / distance). The same for y.
PixelBox projectedSphere(const media::Frame& f, glm::vec3 c, float r) {
  auto extent = [&](double across, double depth, double scale, double shift, int size, int& lo, int& hi) {
    const double centre = std::atan2(across, depth), half = std::asin(r / std::hypot(across, depth));
    lo = static_cast<int>(std::floor(((scale * std::tan(centre - half) - shift) * 0.5 + 0.5) * size));
    hi = static_cast<int>(std::ceil(((scale * std::tan(centre + half) - shift) * 0.5 + 0.5) * size));
  };
  PixelBox b;
  extent(c.x, -c.z, f.projection[0][0], f.projection[2][0], kWidth, b.x0, b.x1);
  extent(c.y, -c.z, f.projection[1][1], f.projection[2][1], kHeight, b.y0, b.y1);
  return b;
}

int area(const PixelBox& b) { return b.empty() ? 0 : (b.x1 - b.x0) * (b.y1 - b.y0); }

TEST(MediaCoverage, APerspectiveSphereLiesInItsBoxAndTheBoxIsNotMuchLarger) {
  // Positions across the frame and past its edges, distances from just clear of the camera's plane
  // (the bound's 5 %) to far, small and large radii, narrow and wide lenses, and an off-centre
  // frustum (a host's; fov 0 below).
  int checked = 0;
  double loosest = 0.0;
  for (float fov : {20.0f, 45.0f, 90.0f, 0.0f}) {
    media::Frame f = perspectiveFrame(fov > 0.0f ? fov : 45.0f);
    if (fov == 0.0f) {
      const float n = 0.5f, t = std::tan(glm::radians(45.0f) / 2.0f) * n, a = static_cast<float>(kWidth) / kHeight;
      f.projection = glm::frustum(-0.3f * a * t, 1.7f * a * t, -1.4f * t, 0.6f * t, n, 50.0f);
    }
    if (fov == 0.0f) fov = 45.0f;
    for (float r : {0.05f, 0.3f, 1.5f}) {
      for (float dz : {1.1f * r + 0.6f, 3.0f, 8.0f, 30.0f}) {
        for (float u : {-1.2f, -0.6f, 0.0f, 0.45f, 0.9f}) {
          for (float v : {-0.8f, 0.0f, 0.7f}) {
            const float t = std::tan(glm::radians(fov) / 2.0f);
            const glm::vec3 c(u * t * dz * kWidth / kHeight, v * t * dz, -dz);
            const media::Particle p = particle(c, r);
            const PixelBox box = media::coverage(f, std::span(&p, 1));
            const PixelBox want = projectedSphere(f, c, r);  // the tangents stay within +-90 degrees here
            const PixelBox onScreen = media::grow(want, 0, kWidth, kHeight);
            SCOPED_TRACE(::testing::Message()
                         << "fov " << fov << " r " << r << " dz " << dz << " u " << u << " v " << v);
            if (onScreen.empty()) continue;  // off the frame: nothing to hold
            ++checked;
            EXPECT_LE(box.x0, onScreen.x0);
            EXPECT_LE(box.y0, onScreen.y0);
            EXPECT_GE(box.x1, onScreen.x1);
            EXPECT_GE(box.y1, onScreen.y1);
            // The box is the silhouette's own, rounded out and grown by the pixel of slack: within
            // the projection's box grown by 1 px, for every sphere (the spherical quads' box).
            const PixelBox slack = media::grow(onScreen, 1, kWidth, kHeight);
            EXPECT_GE(box.x0, slack.x0);
            EXPECT_GE(box.y0, slack.y0);
            EXPECT_LE(box.x1, slack.x1);
            EXPECT_LE(box.y1, slack.y1);
            loosest =
                std::max(loosest, static_cast<double>(area(box)) / area(media::grow(onScreen, 2, kWidth, kHeight)));
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 100);
  std::printf("the box over the projection's (grown by 2 px): at most %.2f\n", loosest);
}

TEST(MediaCoverage, WhatDrawsNothingCoversNothing) {
  const media::Frame f = perspectiveFrame(45.0f);
  const std::vector<media::Particle> none = {
      particle({0, 0, -5}, 0.0f),       // no radius
      particle({0, 0, -5}, -1.0f),      // a negative one
      particle({0, 0, 2.0f}, 1.0f),     // behind the camera, nearer than the near plane
      particle({0, 0, -60.0f}, 5.0f),   // beyond the far plane
      particle({40, 0, -5.0f}, 1.0f)};  // off the frame
  EXPECT_TRUE(media::coverage(f, none).empty());
  EXPECT_TRUE(media::coverage(f, {}).empty());
}

TEST(MediaCoverage, ASphereReachingTheCamerasPlaneCoversTheWholeFrame) {
  const media::Frame f = perspectiveFrame(45.0f);
  for (float dz : {-0.5f, 0.0f, 0.6f, 1.0f}) {  // centres behind, at and just in front of the camera
    const media::Particle p = particle({0.3f, -0.2f, -dz}, 1.05f);
    EXPECT_EQ(media::coverage(f, std::span(&p, 1)), (PixelBox{0, 0, kWidth, kHeight})) << dz;
  }
}

TEST(MediaCoverage, LightsThatShineAddTheirSpheresAsComposeTakesThem) {
  const media::Frame f = orthoFrame();
  media::ExplosionLight off;
  off.center = {-5.0f, 0.0f, -5.0f};
  off.radius = 1.0f;
  off.intensity = 0.0f;
  EXPECT_TRUE(media::coverage(f, {}, std::span(&off, 1)).empty());
  media::ExplosionLight on = off;
  on.intensity = 2.0f;
  // x [-6, -4] world = [20, 40] px, y [-1, 1] = [70, 90] px.
  EXPECT_EQ(media::coverage(f, {}, std::span(&on, 1)), (PixelBox{19, 69, 41, 91}));
  // Compose takes the first 8 that shine: a ninth adds nothing.
  std::vector<media::ExplosionLight> nine(9, on);
  nine[8].center = {5.0f, 0.0f, -5.0f};
  EXPECT_EQ(media::coverage(f, {}, nine), (PixelBox{19, 69, 41, 91}));
  nine.insert(nine.begin(), off);  // one that does not shine does not count
  EXPECT_EQ(media::coverage(f, {}, nine), (PixelBox{19, 69, 41, 91}));
}

TEST(MediaCoverage, GrowAndUniteKeepToTheFrame) {
  EXPECT_EQ(media::grow(PixelBox{2, 3, 10, 12}, 4, 12, 14), (PixelBox{0, 0, 12, 14}));
  EXPECT_TRUE(media::grow(PixelBox{}, 4, 12, 14).empty());
  EXPECT_TRUE(media::grow(PixelBox{20, 20, 30, 30}, 1, 12, 14).empty());
  EXPECT_EQ(media::unite(PixelBox{}, PixelBox{1, 2, 3, 4}), (PixelBox{1, 2, 3, 4}));
  EXPECT_EQ(media::unite(PixelBox{1, 2, 3, 4}, PixelBox{0, 5, 2, 6}), (PixelBox{0, 2, 3, 6}));
}

}  // namespace
}  // namespace puff
