// The metrics added for judging fidelity (metrics.h): SSIM against closed forms (an image with
// itself, a constant shift, a shifted and an inverted ramp), the media mask and the clip band on
// synthetic scenes whose answers are circles. No GL.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/reference/metrics.h>

namespace puff {
namespace {

constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;

// The luminance term of SSIM for means m and n (the whole index when the contrast and structure
// terms are 1).
double luminanceTerm(double m, double n) { return (2.0 * m * n + kC1) / (m * m + n * n + kC1); }

// The window's variance of a ramp of slope k per pixel along x at a pixel whose whole window lies
// in the image: k^2 times the 1D Gaussian's second moment (sigma 1.5, 11 taps, normalized).
double rampVariance(double k) {
  double s = 0.0, m2 = 0.0;
  for (int i = -5; i <= 5; ++i) {
    const double g = std::exp(-(i * i) / (2.0 * 1.5 * 1.5));
    s += g;
    m2 += g * i * i;
  }
  return k * k * m2 / s;
}

core::Image rampImage(int w, int h, double slope, double offset) {
  core::Image im(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) im.at(x, y, c) = static_cast<float>(offset + slope * x);
  return im;
}

TEST(SsimMetric, AnImageWithItselfIsOne) {
  core::Image a(23, 17, 4);
  for (std::size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] = static_cast<float>((i * 7919) % 101) / 100.0f;
  for (double v : reference::ssimMap(a, a)) ASSERT_NEAR(v, 1.0, 1e-12);
  EXPECT_NEAR(reference::ssim(a, a), 1.0, 1e-12);
}

TEST(SsimMetric, AConstantShiftOfAConstantImageIsTheLuminanceTerm) {
  // No variance: the contrast-structure term is C2 / C2 = 1 at every pixel, edges included.
  const core::Image a(12, 9, 3, 0.5f), b(12, 9, 4, 0.625f);  // exact in floats
  const double expected = luminanceTerm(0.5, 0.625);         // (0.625 + C1) / (0.640625 + C1) = 0.97562...
  for (double v : reference::ssimMap(a, b)) ASSERT_NEAR(v, expected, 1e-9);
  EXPECT_NEAR(reference::ssim(a, b), expected, 1e-9);
}

TEST(SsimMetric, AShiftedRampKeepsItsStructureAndAnInvertedOneLosesIt) {
  const int w = 30, h = 14;
  const double k = 1.0 / 64.0, offset = 0.125, shift = 0.25;  // every value exact in floats
  const core::Image a = rampImage(w, h, k, offset);
  const core::Image shifted = rampImage(w, h, k, offset + shift);
  const core::Image inverted = rampImage(w, h, -k, 1.0 - offset);  // 1 - a
  const auto s = reference::ssimMap(a, shifted), inv = reference::ssimMap(a, inverted);
  const double var = rampVariance(k);
  // Columns whose window lies wholly inside: the window's mean is the pixel's value (the ramp is
  // linear, the window symmetric); rows do not matter (the image is constant along y).
  for (int y = 0; y < h; ++y) {
    for (int x = 5; x < w - 5; ++x) {
      const double m = offset + k * x;
      // Same variance and covariance = variance: only the means differ.
      ASSERT_NEAR(s[static_cast<std::size_t>(y) * w + x], luminanceTerm(m, m + shift), 1e-9) << x << "," << y;
      // Covariance -variance: the structure term is (C2 - 2 var) / (C2 + 2 var).
      ASSERT_NEAR(inv[static_cast<std::size_t>(y) * w + x],
                  luminanceTerm(m, 1.0 - m) * (kC2 - 2.0 * var) / (kC2 + 2.0 * var), 1e-9)
          << x << "," << y;
    }
  }
}

TEST(SsimMetric, AMaskAveragesOnlyItsPixels) {
  const int w = 32, h = 8;
  core::Image a = rampImage(w, h, 0.01, 0.2), b = a;
  for (int y = 0; y < h; ++y)
    for (int c = 0; c < 3; ++c) b.at(w - 1, y, c) = 0.9f;  // changed: the last column
  // The first 20 columns' windows (radius 5) never reach column 31.
  std::vector<bool> left(static_cast<std::size_t>(w) * h, false);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < 20; ++x) left[static_cast<std::size_t>(y) * w + x] = true;
  EXPECT_NEAR(reference::ssim(a, b, left), 1.0, 1e-12);
  EXPECT_LT(reference::ssim(a, b), 0.99);
  EXPECT_EQ(reference::ssim(a, b, std::vector<bool>(left.size(), false)), 1.0);  // no pixel counted
}

// Ink is the ink colour (every channel within the tolerance) where the bare frame is not ink: a pixel
// a hair off black is ink, one 0.2 off is not, and one already black in the bare frame is not.
TEST(InkMask, IsTheInkColourWhereTheBareFrameIsNot) {
  core::Image image(4, 1, 4), bare(4, 1, 4);
  const float shown[4][3] = {{0.05f, 0.0f, 0.08f}, {0.2f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.9f, 0.9f, 0.9f}};
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) {
      image.at(x, 0, c) = shown[x][c];
      bare.at(x, 0, c) = x == 2 ? 0.0f : 0.9f;
    }
  EXPECT_EQ(reference::inkMask(image, bare, glm::vec3(0.0f)), (std::vector<bool>{true, false, false, false}));
  // Another ink colour over a black bare frame: the grey 0.9 pixel is within 0.1 of 0.85, not within 0.04.
  const core::Image black(4, 1, 4);
  EXPECT_EQ(reference::inkMask(image, black, glm::vec3(0.85f)), (std::vector<bool>{false, false, false, true}));
  EXPECT_EQ(reference::inkMask(image, black, glm::vec3(0.85f), 0.04), (std::vector<bool>(4, false)));
}

TEST(MediaMask, MarksTransmittanceBelowOneOrRadianceAboveEpsilon) {
  core::Image layer(5, 1, 4);
  const float px[5][4] = {{0, 0, 0, 1}, {0, 0, 0, 0.99f}, {0, 0, 0, 0.999f}, {0, 0.01f, 0, 1}, {0.001f, 0, 0, 1}};
  for (int x = 0; x < 5; ++x)
    for (int c = 0; c < 4; ++c) layer.at(x, 0, c) = px[x][c];
  // epsilon = 1/510: 0.01 counts, 0.001 does not.
  EXPECT_EQ(reference::mediaMask(layer), (std::vector<bool>{false, true, false, true, false}));
  EXPECT_EQ(reference::mediaMask(layer, 1e-4), (std::vector<bool>{false, true, true, true, true}));
}

// An orthographic camera over [-2, 2]^2 looking down -z, n x n pixels: pixel (i, j)'s ray (j = 0
// the bottom row) runs along -z through ((i + 0.5) / n * 4 - 2, (j + 0.5) / n * 4 - 2).
media::Frame orthoFrame(int n, float nearPlane, float farPlane) {
  media::Frame f;
  f.projection = glm::ortho(-2.0f, 2.0f, -2.0f, 2.0f, nearPlane, farPlane);
  f.nearPlane = nearPlane;
  f.farPlane = farPlane;
  f.viewport.width = f.viewport.height = n;
  return f;
}

// The pixels (row 0 at the top) whose centre lies inside the unit disc, and the band of width w
// around them, by brute force.
std::vector<bool> unitDisc(int n) {
  std::vector<bool> m(static_cast<std::size_t>(n) * n, false);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5) / n * 4.0 - 2.0, y = (j + 0.5) / n * 4.0 - 2.0;
      m[static_cast<std::size_t>(n - 1 - j) * n + i] = x * x + y * y < 1.0;
    }
  return m;
}
std::vector<bool> dilated(const std::vector<bool>& m, int n, int w) {
  std::vector<bool> out(m.size(), false);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      for (int dy = -w; dy <= w; ++dy)
        for (int dx = -w; dx <= w; ++dx) {
          const int u = x + dx, v = y + dy;
          if (u >= 0 && v >= 0 && u < n && v < n && m[static_cast<std::size_t>(v) * n + u])
            out[static_cast<std::size_t>(y) * n + x] = true;
        }
  return out;
}

TEST(ClipBand, AWallThroughASphereClipsItsWholeDiscOnlyWhenItCutsIt) {
  // Pixel centres are odd multiples of 0.05: none lies on the unit circle.
  const int n = 40;
  const media::Frame f = orthoFrame(n, 0.1f, 20.0f);
  const media::Particle sphere{{0.0f, 0.0f, -5.0f}, 1.0f, 0, 0.0f, 1.0f, 0};
  auto wall = [&](float distance) {
    return std::vector<float>(static_cast<std::size_t>(n) * n, (distance - 0.1f) / 19.9f);
  };
  const auto disc = unitDisc(n);
  // Through the centre: every ray through the sphere enters before the wall and leaves after.
  reference::ClipBand b = reference::clipBand(wall(5.0f), std::span(&sphere, 1), f, 2);
  EXPECT_EQ(b.surface, disc);
  EXPECT_EQ(b.nearPlane, std::vector<bool>(disc.size(), false));
  EXPECT_EQ(b.band, dilated(disc, n, 2));
  EXPECT_EQ(reference::clipBand(wall(5.0f), std::span(&sphere, 1), f, 0).band, disc);
  // In front of the sphere (its front is at 4), behind it (back at 6), no surface: nothing cut.
  const std::vector<bool> none(disc.size(), false);
  for (const auto& depth : {wall(3.0f), wall(7.0f), std::vector<float>{}}) {
    b = reference::clipBand(depth, std::span(&sphere, 1), f, 2);
    EXPECT_EQ(b.surface, none);
    EXPECT_EQ(b.band, none);
  }
  // A particle of radius 0 is nothing.
  const media::Particle dot{{0.0f, 0.0f, -5.0f}, 0.0f, 0, 0.0f, 1.0f, 0};
  EXPECT_EQ(reference::clipBand(wall(5.0f), std::span(&dot, 1), f, 2).band, none);
}

TEST(ClipBand, TheNearPlaneThroughASphereClipsWhereItsPointIsInside) {
  // Orthographic: the near plane at the centre's depth clips the disc.
  const int n = 40;
  const media::Particle sphere{{0.0f, 0.0f, -5.0f}, 1.0f, 0, 0.0f, 1.0f, 0};
  reference::ClipBand b = reference::clipBand({}, std::span(&sphere, 1), orthoFrame(n, 5.0f, 20.0f), 1);
  EXPECT_EQ(b.nearPlane, unitDisc(n));
  EXPECT_EQ(b.surface, std::vector<bool>(unitDisc(n).size(), false));
  EXPECT_EQ(b.band, dilated(unitDisc(n), n, 1));
  // Perspective, 90 degrees, near 1 through the centre of a sphere of radius 0.5 at distance 1:
  // pixel (i, j)'s ray meets the near plane at (ndc_x, ndc_y, -1), inside iff ndc^2 < 0.25
  // (ndc = odd / 32: never on the circle).
  const int m = 32;
  media::Frame f;
  f.projection = glm::perspective(glm::radians(90.0f), 1.0f, 1.0f, 10.0f);
  f.nearPlane = 1.0f;
  f.farPlane = 10.0f;
  f.viewport.width = f.viewport.height = m;
  const media::Particle close{{0.0f, 0.0f, -1.0f}, 0.5f, 0, 0.0f, 1.0f, 0};
  b = reference::clipBand({}, std::span(&close, 1), f, 0);
  int inside = 0;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const double x = (i + 0.5) / m * 2.0 - 1.0, y = (j + 0.5) / m * 2.0 - 1.0;
      const bool expected = x * x + y * y < 0.25;
      inside += expected ? 1 : 0;
      ASSERT_EQ(b.nearPlane[static_cast<std::size_t>(m - 1 - j) * m + i], expected) << i << "," << j;
    }
  EXPECT_GT(inside, 100);
}

}  // namespace
}  // namespace puff
