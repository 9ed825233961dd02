// The black-body ramp fire is shaded with (core/blackbody.h): Planck's law, the CIE 1931 observer
// and the sRGB matrices checked against published numbers and laws of physics, not against a
// previous run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include <glm/vec2.hpp>

#include <puff/core/blackbody.h>
#include <puff/core/image.h>

#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using puff::core::BlackbodyRamp;

glm::dvec2 chromaticity(const glm::dvec3& xyz) { return glm::dvec2(xyz.x, xyz.y) / (xyz.x + xyz.y + xyz.z); }

// CIE 1931 2-degree chromaticity of Planckian radiators, as published: Wyszecki & Stiles, Color
// Science, 2nd ed. (1982), Table 1(3.11), the same values as Judd & Wyszecki, Color in Business,
// Science and Industry (1975), p. 164 (computed with c2 = 1.4388e-2 m K; 4 decimals). 2856 K is
// CIE standard illuminant A, defined as that Planckian radiator: (0.44757, 0.40745), CIE 015:2004
// Table T.3.
struct LocusPoint {
  double kelvin, x, y;
};
constexpr LocusPoint kPublishedLocus[] = {
    {1500, 0.5857, 0.3931}, {2500, 0.4770, 0.4137}, {2856, 0.44757, 0.40745},
    {3000, 0.4369, 0.4041}, {4000, 0.3805, 0.3768}, {6500, 0.3135, 0.3237},
};
// The table is rounded to 1e-4 and the 5 nm trapezoid agrees with it to about 7e-5. A bound of 5e-4 (tighter
// than the 0.002 asked for) still catches a wrong observer: the Judd-Vos modified observer puts 4000 K at
// (0.3827, 0.3820), 0.005 away.
constexpr double kLocusTolerance = 0.0005;

TEST(BlackbodyLocus, XyzMatchesThePublishedPlanckianLocus) {
  for (const LocusPoint& p : kPublishedLocus) {
    SCOPED_TRACE(std::to_string(p.kelvin) + " K");
    const glm::dvec2 xy = chromaticity(puff::core::blackbodyXYZ(p.kelvin));
    EXPECT_NEAR(xy.x, p.x, kLocusTolerance);
    EXPECT_NEAR(xy.y, p.y, kLocusTolerance);
  }
}

TEST(BlackbodyLocus, RampColoursConvertBackToThePublishedLocus) {
  auto ramp = puff::core::makeBlackbodyRamp(1000, 10000, 1024, 3200);
  ASSERT_OK(ramp);
  for (const LocusPoint& p : kPublishedLocus) {
    SCOPED_TRACE(std::to_string(p.kelvin) + " K");
    const glm::dvec2 xy = chromaticity(puff::core::linearSrgbToXyz(glm::dvec3(ramp->at(p.kelvin))));
    EXPECT_NEAR(xy.x, p.x, kLocusTolerance);
    EXPECT_NEAR(xy.y, p.y, kLocusTolerance);
  }
}

TEST(BlackbodyLocus, SrgbMatricesAreInversesAndMapD65ToWhite) {
  // IEC 61966-2-1: D65 (x, y) = (0.3127, 0.3290) with Y = 1 is RGB (1, 1, 1).
  const glm::dvec3 d65(0.3127 / 0.3290, 1.0, (1.0 - 0.3127 - 0.3290) / 0.3290);
  const glm::dvec3 rgb = puff::core::xyzToLinearSrgb(d65);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[c], 1.0, 1e-3) << c;
  for (const glm::dvec3 v : {glm::dvec3(0.2, 0.5, 0.9), glm::dvec3(1, 0, 0), glm::dvec3(0.3, -0.1, 2)}) {
    const glm::dvec3 back = puff::core::linearSrgbToXyz(puff::core::xyzToLinearSrgb(v));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], v[c], 5e-4) << c;  // the standard prints 4 decimals
  }
}

TEST(BlackbodyRamp, HotterIsBluerAndBrighter) {
  auto ramp = puff::core::makeBlackbodyRamp(1000, 10000, 256, 3200);
  ASSERT_OK(ramp);
  int negativeBlue = 0;
  for (std::size_t i = 1; i < ramp->rgb.size(); ++i) {
    SCOPED_TRACE("texel " + std::to_string(i) + ", " + std::to_string(ramp->minKelvin + 9000.0 * i / 255) + " K");
    const glm::vec3 a = ramp->rgb[i - 1], b = ramp->rgb[i];
    ASSERT_GT(a.r, 0.0f);
    // Chromaticity: along the whole locus the blue share z grows and x falls.
    const glm::dvec3 xyzA = puff::core::linearSrgbToXyz(glm::dvec3(a)),
                     xyzB = puff::core::linearSrgbToXyz(glm::dvec3(b));
    EXPECT_GT(xyzB.z / (xyzB.x + xyzB.y + xyzB.z), xyzA.z / (xyzA.x + xyzA.y + xyzA.z));
    EXPECT_LT(chromaticity(xyzB).x, chromaticity(xyzA).x);
    EXPECT_GT(xyzB.y, xyzA.y);  // and brighter
    // Display blue over red, as a shader sees it (negative components clamped): never falls, and
    // rises wherever blue is in gamut. (Unclamped b/r dips just above 1000 K, where the locus lies
    // outside sRGB and the negative blue deepens faster than red grows.)
    const float cb = std::max(b.b, 0.0f), ca = std::max(a.b, 0.0f);
    EXPECT_GE(cb / b.r, ca / a.r);
    if (a.b > 0.0f) {
      EXPECT_GT(b.b / b.r, a.b / a.r);
    }
    negativeBlue += b.b < 0.0f;
  }
  EXPECT_GT(negativeBlue, 0);
  // Fire's range (Umenhoffer Fig. 11, 2500..3200 K) is orange: red > green > blue.
  for (double t : {2500.0, 2800.0, 3200.0}) {
    const glm::vec3 c = ramp->at(t);
    EXPECT_GT(c.r, c.g);
    EXPECT_GT(c.g, c.b);
  }
  // Out-of-gamut truth is kept: at 1000 K the locus lies outside sRGB, so blue is negative.
  EXPECT_LT(ramp->rgb.front().b, 0.0f);
}

TEST(BlackbodyPlanck, PeakObeysWiensDisplacementLaw) {
  constexpr double kWien = 2.897771955e-3;  // m K, CODATA 2018
  for (double t : {1000.0, 3000.0, 5778.0, 10000.0}) {
    // Golden-section search for the maximum of the (unimodal) spectrum.
    double lo = 50e-9, hi = 20e-6;
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    for (int i = 0; i < 200; ++i) {
      const double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
      if (puff::core::planckRadiance(a, t) > puff::core::planckRadiance(b, t))
        hi = b;
      else
        lo = a;
    }
    EXPECT_NEAR(0.5 * (lo + hi) * t, kWien, kWien * 1e-6) << t << " K";
  }
}

TEST(BlackbodyPlanck, IntegratesToStefanBoltzmannAndMeetsRayleighJeans) {
  constexpr double kSigma = 5.670374419e-8;  // W m^-2 K^-4, CODATA 2018
  const double t = 3000.0;
  // pi * integral of the radiance over wavelength = sigma T^4 (log-spaced midpoint rule).
  double sum = 0.0;
  const double l0 = std::log(10e-9), l1 = std::log(1e-2);
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double u = l0 + (l1 - l0) * (i + 0.5) / n;
    const double lambda = std::exp(u);
    sum += puff::core::planckRadiance(lambda, t) * lambda * (l1 - l0) / n;
  }
  EXPECT_NEAR(M_PI * sum / (kSigma * std::pow(t, 4)), 1.0, 1e-5);
  // Long wavelengths: 2 c k T / lambda^4.
  const double lambda = 1.0;
  const double rj = 2.0 * 299792458.0 * 1.380649e-23 * t / std::pow(lambda, 4);
  EXPECT_NEAR(puff::core::planckRadiance(lambda, t) / rj, 1.0, 1e-5);
  // Far into the Wien tail the exponent overflows: no light, not NaN.
  EXPECT_EQ(puff::core::planckRadiance(360e-9, 1.0), 0.0);
}

TEST(BlackbodyRamp, NormalizationGivesLuminanceOneAtTheChosenTemperature) {
  for (double normalize : {1500.0, 3200.0, 6500.0}) {
    auto ramp = puff::core::makeBlackbodyRamp(1000, 10000, 1024, normalize);
    ASSERT_OK(ramp);
    EXPECT_NEAR(puff::core::linearSrgbToXyz(glm::dvec3(ramp->at(normalize))).y, 1.0, 1e-3) << normalize;
  }
  // A normalization temperature outside the range works too: texel 0 of [3200, 4000] is Y = 1 at 3200 K,
  // and the whole ramp is twice as bright when normalized at a temperature half as luminous.
  auto a = puff::core::makeBlackbodyRamp(3200, 4000, 2, 3200);
  auto b = puff::core::makeBlackbodyRamp(3200, 4000, 2, 2500);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_NEAR(puff::core::linearSrgbToXyz(glm::dvec3(a->rgb[0])).y, 1.0, 1e-3);
  const double ratio = puff::core::blackbodyXYZ(3200).y / puff::core::blackbodyXYZ(2500).y;
  EXPECT_NEAR(b->rgb[1].g / a->rgb[1].g, ratio, ratio * 1e-5);
}

TEST(BlackbodyRamp, AtInterpolatesLinearlyAndClamps) {
  auto ramp = puff::core::makeBlackbodyRamp(1000, 2000, 3, 1500);  // texels at 1000, 1500, 2000 K
  ASSERT_TRUE(ramp.ok());
  const auto& t = ramp->rgb;
  const glm::vec3 mid = ramp->at(1250);
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(ramp->at(1500)[c], t[1][c]);
    EXPECT_NEAR(mid[c], 0.5f * (t[0][c] + t[1][c]), 1e-6f * std::abs(t[1][c]) + 1e-7f);
    EXPECT_FLOAT_EQ(ramp->at(10)[c], t[0][c]);
    EXPECT_FLOAT_EQ(ramp->at(1e6)[c], t[2][c]);
  }
}

class BlackbodyFile : public ::testing::Test {
 protected:
  puff::test::ScopedTempDir dir_{"puff_blackbody"};
};

TEST_F(BlackbodyFile, WriteReadRoundTripIsExact) {
  auto ramp = puff::core::makeBlackbodyRamp(1000, 10000, 1024, 3200);
  ASSERT_TRUE(ramp.ok());
  const fs::path path = dir_ / "sub" / "blackbody.exr";
  ASSERT_TRUE(puff::core::writeBlackbodyRamp(path, *ramp).ok());
  // Nothing but the file: the temporary was renamed over it.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_ / "sub"), fs::directory_iterator()), 1);
  auto back = puff::core::readBlackbodyRamp(path);
  ASSERT_OK(back);
  EXPECT_EQ(back->minKelvin, 1000.0);
  EXPECT_EQ(back->maxKelvin, 10000.0);
  EXPECT_EQ(back->normalizeKelvin, 3200.0);
  ASSERT_EQ(back->rgb.size(), ramp->rgb.size());
  for (std::size_t i = 0; i < ramp->rgb.size(); ++i) ASSERT_EQ(back->rgb[i], ramp->rgb[i]) << i;
  // A fractional range survives exactly too.
  auto odd = puff::core::makeBlackbodyRamp(1234.5678, 2345.6789, 7, 1999.75);
  ASSERT_TRUE(odd.ok());
  ASSERT_TRUE(puff::core::writeBlackbodyRamp(path, *odd).ok());
  auto oddBack = puff::core::readBlackbodyRamp(path);
  ASSERT_TRUE(oddBack.ok());
  EXPECT_EQ(oddBack->minKelvin, 1234.5678);
  EXPECT_EQ(oddBack->maxKelvin, 2345.6789);
  EXPECT_EQ(oddBack->normalizeKelvin, 1999.75);
}

TEST_F(BlackbodyFile, BadFilesAreErrorsNamingTheFile) {
  auto expectError = [](const fs::path& p, const std::string& needle) {
    auto r = puff::core::readBlackbodyRamp(p);
    ASSERT_FALSE(r.ok()) << p;
    EXPECT_NE(r.error().message.find(p.string()), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
  };
  expectError(dir_ / "missing.exr", "no such file");
  puff::core::Image plain(8, 1, 3, 0.5f);
  ASSERT_TRUE(puff::core::writeImage(dir_ / "plain.exr", plain, puff::core::PixelType::kFloat).ok());
  expectError(dir_ / "plain.exr", "missing attribute puff:minKelvin");
  ASSERT_TRUE(
      puff::core::writeImage(dir_ / "square.exr", puff::core::Image(8, 8, 3), puff::core::PixelType::kFloat,
                             {{"puff:minKelvin", "1000"}, {"puff:maxKelvin", "2000"}, {"puff:normalizeKelvin", "1500"}})
          .ok());
  expectError(dir_ / "square.exr", "not a black-body ramp");
  ASSERT_TRUE(
      puff::core::writeImage(dir_ / "words.exr", plain, puff::core::PixelType::kFloat,
                             {{"puff:minKelvin", "hot"}, {"puff:maxKelvin", "2000"}, {"puff:normalizeKelvin", "1500"}})
          .ok());
  expectError(dir_ / "words.exr", "puff:minKelvin is not a number");
  ASSERT_TRUE(
      puff::core::writeImage(dir_ / "reversed.exr", plain, puff::core::PixelType::kFloat,
                             {{"puff:minKelvin", "3000"}, {"puff:maxKelvin", "2000"}, {"puff:normalizeKelvin", "1500"}})
          .ok());
  expectError(dir_ / "reversed.exr", "maxKelvin must be in");

  // Writing under a regular file fails, names the path and leaves the existing file alone.
  auto ramp = puff::core::makeBlackbodyRamp(1000, 2000, 4, 1500);
  ASSERT_TRUE(ramp.ok());
  auto w = puff::core::writeBlackbodyRamp(dir_ / "plain.exr" / "ramp.exr", *ramp);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.error().message.find("plain.exr"), std::string::npos) << w.error().message;
  EXPECT_TRUE(fs::is_regular_file(dir_ / "plain.exr"));
}

TEST(BlackbodyRamp, BadArgumentsSayWhichValueAndTheRange) {
  struct Case {
    double min, max;
    int size;
    double normalize;
    const char* needle;
  };
  const Case cases[] = {
      {0, 1000, 16, 3200, "minKelvin must be in (0, 100000), got 0"},
      {-5, 1000, 16, 3200, "minKelvin"},
      {NAN, 1000, 16, 3200, "minKelvin"},
      {1000, 1000, 16, 3200, "maxKelvin must be in (minKelvin = 1000, 100000], got 1000"},
      {1000, 2e5, 16, 3200, "maxKelvin"},
      {1000, 2000, 1, 3200, "size must be in [2, 65536] texels, got 1"},
      {1000, 2000, 65537, 3200, "size"},
      {1000, 2000, 16, 0, "normalizeKelvin must be in (0, 100000], got 0"},
      {1000, 2000, 16, 1e6, "normalizeKelvin"},
      {1000, 2000, 16, 10, "no visible light"},  // Y underflows to 0 at 10 K
      {1000, 100000, 16, 100, "32-bit floats"},  // 1e5 K is ~1e60 times as bright as 100 K
  };
  for (const Case& c : cases) {
    auto r = puff::core::makeBlackbodyRamp(c.min, c.max, c.size, c.normalize);
    ASSERT_FALSE(r.ok()) << c.needle;
    EXPECT_NE(r.error().message.find(c.needle), std::string::npos) << r.error().message;
  }
}

}  // namespace
