// The physical media reference (puff/reference/media_physical.h) against closed forms: a lone
// sphere's optical depth, disjoint spheres, an overlap where it and the model reference
// (media_reference.h) disagree by a known amount, the near plane and the opaque depth, burn, the
// automatic step's convergence and the input checks. No GL.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/bake/detail.h>
#include <puff/media/media.h>
#include <puff/reference/media_physical.h>
#include <puff/reference/media_reference.h>
#include <puff/reference/metrics.h>

#include "support/assert_ok.h"

namespace puff {
namespace {

using reference::MediaReferenceInput;
using reference::PhysicalOptions;
using reference::PhysicalReport;

// A 1 x 1 orthographic frame whose one ray runs from (0, 0, 0) along -z.
media::Frame rayFrame(float nearPlane = 0.5f, float farPlane = 20.0f) {
  media::Frame f;
  f.projection = glm::ortho(-0.01f, 0.01f, -0.01f, 0.01f, nearPlane, farPlane);
  f.nearPlane = nearPlane;
  f.farPlane = farPlane;
  f.viewport.width = 1;
  f.viewport.height = 1;
  f.light.direction = glm::vec3(0.0f, 0.6f, 0.8f);
  f.light.color = glm::vec3(0.9f, 0.8f, 0.7f);
  f.ambient = glm::vec3(0.2f, 0.25f, 0.3f);
  return f;
}

media::Material plain(float tau, float albedo, glm::vec3 color = glm::vec3(1.0f, 0.5f, 0.25f)) {
  media::Material m;
  m.name = "plain";
  m.albedo = albedo;
  m.density = tau;
  m.color = color;
  m.g = 0.3f;
  m.detail = 0.0f;
  return m;
}

media::Particle sphereAt(glm::vec3 c, float r, std::uint32_t material = 0, float density = 1.0f) {
  media::Particle p;
  p.position = c;
  p.radius = r;
  p.material = material;
  p.density = density;
  return p;
}

// What a non-emissive material scatters toward the eye along -z (view = identity, Cornette-Shanks).
glm::dvec3 scattered(const media::Frame& f, const media::Material& m) {
  const glm::dvec3 l = glm::normalize(glm::dvec3(f.light.direction));
  const double p4pi =
      4.0 * std::numbers::pi * media::phase(media::PhaseModel::kCornetteShanks, glm::dot(l, {0.0, 0.0, -1.0}), m.g);
  return static_cast<double>(m.albedo) * glm::dvec3(m.color) *
         (glm::dvec3(f.ambient) + glm::dvec3(f.light.color) * p4pi);
}

// The field sigma = 2 tau (1 - rho / r) integrated along a line at distance d from the centre,
// from the point nearest the centre to signed distance u along the line.
double partialDepth(double tau, double r, double d, double u) {
  if (d == 0.0) return 2.0 * tau * (u - u * std::abs(u) / (2.0 * r));
  return 2.0 * tau * (u - (u * std::sqrt(d * d + u * u) + d * d * std::asinh(u / d)) / (2.0 * r));
}

// The whole chord: 2 tau [h - (d^2 / r) ln((r + h) / d)], h = sqrt(r^2 - d^2).
double lineDepth(double tau, double r, double d) {
  const double h = std::sqrt(r * r - d * d);
  return d == 0.0 ? 2.0 * tau * r : 2.0 * tau * (h - d * d / r * std::log((r + h) / d));
}

struct Pixel {
  glm::dvec3 radiance{0.0};  // M
  double transmittance = 1.0;
};

Pixel physicalPixel(const MediaReferenceInput& in, const PhysicalOptions& options, PhysicalReport* report = nullptr) {
  core::Image layer;
  auto image = reference::renderMediaPhysical(in, options, &layer, report);
  EXPECT_OK(image);
  if (!image) return {};
  return {{layer.at(0, 0, 0), layer.at(0, 0, 1), layer.at(0, 0, 2)}, layer.at(0, 0, 3)};
}

Pixel modelPixel(const MediaReferenceInput& in) {
  core::Image layer;
  auto image = reference::renderMediaReference(in, &layer);
  EXPECT_OK(image);
  if (!image) return {};
  return {{layer.at(0, 0, 0), layer.at(0, 0, 1), layer.at(0, 0, 2)}, layer.at(0, 0, 3)};
}

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tolerance) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tolerance) << "channel " << c;
}

TEST(MediaPhysical, LoneSphereTransmittanceIsTheClosedFormOpticalDepth) {
  const media::Frame f = rayFrame();
  const std::vector<media::Material> materials{plain(0.4f, 0.6f)};
  const double r = 1.5, tau = double(0.4f) * 2.0;  // material density 0.4 times particle density 2
  for (double fraction : {0.0, 0.3, 0.7, 0.95}) {
    SCOPED_TRACE(fraction);
    const double d = static_cast<float>(fraction * r);  // the position is a float
    const std::vector<media::Particle> particles{sphereAt({static_cast<float>(d), 0.0f, -5.0f}, 1.5f, 0, 2.0f)};
    MediaReferenceInput in;
    in.frame = f;
    in.particles = particles;
    in.materials = materials;
    const double depth = lineDepth(tau, r, d);
    // A constant source S along the chord gives M = S (1 - T).
    const glm::dvec3 source = scattered(f, materials[0]);
    for (double step : {0.05, 0.0}) {
      PhysicalReport report;
      const Pixel p = physicalPixel(in, {.step = step, .tolerance = 1e-8}, &report);
      EXPECT_TRUE(report.converged);
      EXPECT_NEAR(p.transmittance, std::exp(-depth), 1e-6) << "step " << report.step;
      expectNear(p.radiance, source * (1.0 - std::exp(-depth)), 1e-6);
    }
    // The model's optical depth is tau (1 - d / r) 2 h: the same through the centre only.
    const double h = std::sqrt(r * r - d * d);
    const Pixel m = modelPixel(in);
    EXPECT_NEAR(m.transmittance, std::exp(-tau * (1.0 - d / r) * 2.0 * h), 1e-6);
    if (fraction == 0.0) {
      EXPECT_NEAR(m.transmittance, std::exp(-depth), 1e-6);
    }
  }
  // The figures the header and docs quote: 1.24 times the model's depth at d = r / 2, 4/3 at the rim.
  EXPECT_NEAR(lineDepth(1.0, 1.0, 0.5) / (0.5 * 2.0 * std::sqrt(0.75)), 1.24, 0.005);
  EXPECT_NEAR(lineDepth(1.0, 1.0, 0.9999) / (1e-4 * 2.0 * std::sqrt(1.0 - 0.9999 * 0.9999)), 4.0 / 3.0, 1e-3);
}

TEST(MediaPhysical, DisjointSpheresMultiplyTheirTransmittances) {
  const media::Frame f = rayFrame();
  const std::vector<media::Material> materials{plain(0.5f, 0.6f), plain(0.9f, 0.8f, {0.2f, 0.9f, 0.4f})};
  // Both spheres off the ray by different amounts; the far one behind the near one.
  const std::vector<media::Particle> particles{sphereAt({0.3f, 0.0f, -4.0f}, 1.0f, 0),
                                               sphereAt({0.0f, -0.8f, -9.0f}, 2.0f, 1)};
  MediaReferenceInput in;
  in.frame = f;
  in.particles = particles;
  in.materials = materials;
  const double near = lineDepth(0.5f, 1.0, 0.3f), far = lineDepth(0.9f, 2.0, 0.8f);
  const Pixel p = physicalPixel(in, {.step = 0.02});
  EXPECT_NEAR(p.transmittance, std::exp(-near) * std::exp(-far), 1e-6);
  // Each alone, and the product.
  for (int k = 0; k < 2; ++k) {
    MediaReferenceInput one = in;
    one.particles = std::span(particles).subspan(k, 1);
    EXPECT_NEAR(physicalPixel(one, {.step = 0.02}).transmittance, std::exp(-(k == 0 ? near : far)), 1e-6);
  }
  // The far sphere's light comes through the near one: M = S1 (1 - T1) + T1 S2 (1 - T2).
  const glm::dvec3 m = scattered(f, materials[0]) * (1.0 - std::exp(-near)) +
                       std::exp(-near) * scattered(f, materials[1]) * (1.0 - std::exp(-far));
  expectNear(p.radiance, m, 1e-6);
}

// sigma = 2 tau (1 - |u| / r) integrated from the sphere's entry to signed distance u from the centre.
double axisDepthFromEntry(double tau, double r, double u) {
  u = std::clamp(u, -r, r);
  const double sign = u < 0.0 ? -1.0 : 1.0;
  return 2.0 * tau * ((u + r) - (r * r + sign * u * u) / (2.0 * r));
}

TEST(MediaPhysical, OverlapsDifferFromSphereBySphereCompositingByTheIntegral) {
  const media::Frame f = rayFrame();
  // Scattering only ambient light (no light colour), albedo 1: each sphere's source is its colour
  // times the ambient.
  media::Frame flat = f;
  flat.light.color = glm::vec3(0.0f);
  flat.ambient = glm::vec3(1.0f);
  const std::vector<media::Material> materials{plain(1.0f, 1.0f, {1.0f, 0.0f, 0.0f}),
                                               plain(1.0f, 1.0f, {0.0f, 1.0f, 0.0f})};
  const double tau = 1.0, r = 1.0, alpha = 1.0 - std::exp(-2.0 * tau * r);

  // Two identical coincident spheres through their centres: the integral gives S (1 - exp(-4 tau r))
  // and compositing S alpha + (1 - alpha) S alpha = S (1 - (1 - alpha)^2): the same.
  {
    const std::vector<media::Particle> particles{sphereAt({0.0f, 0.0f, -5.0f}, 1.0f, 0),
                                                 sphereAt({0.0f, 0.0f, -5.0f}, 1.0f, 0)};
    MediaReferenceInput in;
    in.frame = flat;
    in.particles = particles;
    in.materials = materials;
    const Pixel p = physicalPixel(in, {.step = 0.02}), m = modelPixel(in);
    const glm::dvec3 expected = glm::dvec3(1.0, 0.0, 0.0) * (1.0 - std::exp(-4.0 * tau * r));
    expectNear(p.radiance, expected, 1e-6);
    expectNear(m.radiance, expected, 1e-6);
    EXPECT_NEAR(p.transmittance, std::exp(-4.0 * tau * r), 1e-6);
    EXPECT_NEAR(m.transmittance, std::exp(-4.0 * tau * r), 1e-6);
  }

  // A red sphere on [4, 6] along the ray and a green one on [5, 7]: half of each lies in the other.
  // Compositing puts all the red in front of all the green: red alpha, green (1 - alpha) alpha. In
  // the medium the red of [5, 6] is dimmed by the green there, and the green of [5, 6] is dimmed
  // only by the red's back half: M_c = Integral sigma_c(s) exp(-tau_red(s) - tau_green(s)) ds,
  // computed here by an independent midpoint rule (1e-5 steps, the kinks on the grid).
  const std::vector<media::Particle> particles{sphereAt({0.0f, 0.0f, -5.0f}, 1.0f, 0),
                                               sphereAt({0.0f, 0.0f, -6.0f}, 1.0f, 1)};
  MediaReferenceInput in;
  in.frame = flat;
  in.particles = particles;
  in.materials = materials;
  double red = 0.0, green = 0.0;
  const int n = 300000;
  const double ds = 3.0 / n;
  for (int k = 0; k < n; ++k) {
    const double s = 4.0 + (k + 0.5) * ds;
    const double uRed = s - 5.0, uGreen = s - 6.0;
    const double sigmaRed = std::abs(uRed) < r ? 2.0 * tau * (1.0 - std::abs(uRed) / r) : 0.0;
    const double sigmaGreen = std::abs(uGreen) < r ? 2.0 * tau * (1.0 - std::abs(uGreen) / r) : 0.0;
    const double t = std::exp(-axisDepthFromEntry(tau, r, uRed) - axisDepthFromEntry(tau, r, uGreen));
    red += sigmaRed * t * ds;
    green += sigmaGreen * t * ds;
  }
  const Pixel p = physicalPixel(in, {.step = 0.01}), m = modelPixel(in);
  expectNear(p.radiance, {red, green, 0.0}, 1e-6);
  expectNear(m.radiance, {alpha, (1.0 - alpha) * alpha, 0.0}, 1e-6);
  // Transmittance does not depend on the order: exp(-4 tau r) both ways.
  EXPECT_NEAR(p.transmittance, std::exp(-4.0 * tau * r), 1e-6);
  EXPECT_NEAR(m.transmittance, std::exp(-4.0 * tau * r), 1e-6);
  // The difference: integral minus compositing, per channel.
  std::printf("half overlap: integral red %.6f green %.6f, compositing red %.6f green %.6f\n", red, green, alpha,
              (1.0 - alpha) * alpha);
  EXPECT_NEAR(p.radiance.x - m.radiance.x, red - alpha, 2e-6);
  EXPECT_NEAR(p.radiance.y - m.radiance.y, green - (1.0 - alpha) * alpha, 2e-6);
  // About 0.024 each way: the red's back half lies behind green medium, the green's front half in
  // front of red medium. (The sum is 1 - T both ways: both sources are the same grey 1.)
  EXPECT_LT(red - alpha, -0.02);
  EXPECT_GT(green - (1.0 - alpha) * alpha, 0.02);
}

TEST(MediaPhysical, TheNearPlaneAndTheOpaqueDepthClipTheRay) {
  const std::vector<media::Material> materials{plain(0.7f, 0.5f)};
  const double tau = 0.7f, r = 1.5;
  for (double fraction : {0.0, 0.3, 0.7}) {
    SCOPED_TRACE(fraction);
    const float d = static_cast<float>(fraction * r);
    const double h = std::sqrt(r * r - double(d) * d);
    const std::vector<media::Particle> particles{sphereAt({d, 0.0f, -5.0f}, 1.5f)};
    // The depth as the opaque layer stores it: linear, a float.
    auto wallAt = [](const media::Frame& f, double z) {
      return static_cast<float>((z - f.nearPlane) / (f.farPlane - f.nearPlane));
    };
    auto stored = [](const media::Frame& f, float lin) {
      return f.nearPlane + double(lin) * (f.farPlane - f.nearPlane);
    };
    {  // a wall through the centre: half the chord, half the optical depth
      const media::Frame f = rayFrame(0.5f, 20.0f);
      const std::vector<float> depth{wallAt(f, 5.0)};
      MediaReferenceInput in;
      in.frame = f;
      in.particles = particles;
      in.materials = materials;
      in.opaqueDepth = depth;
      const double expected = partialDepth(tau, r, d, stored(f, depth[0]) - 5.0) - partialDepth(tau, r, d, -h);
      EXPECT_NEAR(expected, 0.5 * lineDepth(tau, r, d), 1e-5);
      EXPECT_NEAR(physicalPixel(in, {.step = 0.02}).transmittance, std::exp(-expected), 1e-6);
    }
    {  // the near plane through the centre: the other half
      const media::Frame f = rayFrame(5.0f, 20.0f);
      MediaReferenceInput in;
      in.frame = f;
      in.particles = particles;
      in.materials = materials;
      EXPECT_NEAR(physicalPixel(in, {.step = 0.02}).transmittance, std::exp(-0.5 * lineDepth(tau, r, d)), 1e-6);
    }
    {  // both: the near plane at 4.6, a wall at 5.3
      const media::Frame f = rayFrame(4.6f, 20.0f);
      const std::vector<float> depth{wallAt(f, 5.3)};
      MediaReferenceInput in;
      in.frame = f;
      in.particles = particles;
      in.materials = materials;
      in.opaqueDepth = depth;
      const double expected =
          partialDepth(tau, r, d, stored(f, depth[0]) - 5.0) - partialDepth(tau, r, d, double(4.6f) - 5.0);
      EXPECT_NEAR(physicalPixel(in, {.step = 0.02}).transmittance, std::exp(-expected), 1e-6);
    }
  }
}

TEST(MediaPhysical, BurnIsTheModelsBlendForALoneSphere) {
  // A lone sphere of any burn gives M = alpha L and T = 1 - alpha (1 - burn) with alpha = 1 -
  // exp(-tau_line): through the centre, where the two optical depths agree, exactly the model.
  const media::Frame f = rayFrame();
  media::Material fire = media::fireMaterial();
  fire.density = 0.6f;
  for (float burn : {0.0f, 0.5f, 1.0f}) {
    fire.burn = burn;
    const std::vector<media::Material> materials{fire};
    for (float d : {0.0f, 0.6f}) {
      SCOPED_TRACE(testing::Message() << "burn " << burn << " d " << d);
      const std::vector<media::Particle> particles{sphereAt({d, 0.0f, -5.0f}, 1.0f)};
      MediaReferenceInput in;
      in.frame = f;
      in.particles = particles;
      in.materials = materials;
      const double alpha = 1.0 - std::exp(-lineDepth(0.6f, 1.0, d));
      const double modelAlpha = 1.0 - std::exp(-0.6f * (1.0 - d) * 2.0 * std::sqrt(1.0 - double(d) * d));
      const Pixel p = physicalPixel(in, {.step = 0.01}), m = modelPixel(in);
      EXPECT_NEAR(p.transmittance, 1.0 - alpha * (1.0 - burn), 1e-6);
      EXPECT_NEAR(m.transmittance, 1.0 - modelAlpha * (1.0 - burn), 1e-6);
      // The same black body: M / alpha is the model's L.
      expectNear(p.radiance / alpha, m.radiance / modelAlpha, 1e-6 * m.radiance.x / modelAlpha);
      EXPECT_GT(p.radiance.x, 0.1);
    }
  }
}

// A particle's tint multiplies all the light it gives (scattered and emitted) and nothing it
// absorbs; its own temperature is the material's T0 set to it. On both references.
TEST(MediaPhysical, AParticlesTintAndTemperatureAreItsOwn) {
  const media::Frame f = rayFrame();
  const glm::vec3 tint(0.9f, 0.4f, 0.1f);
  for (bool fire : {false, true}) {
    SCOPED_TRACE(fire ? "fire" : "smoke");
    media::Material m = fire ? media::fireMaterial() : plain(0.7f, 0.6f);
    std::vector<media::Material> materials{m};
    std::vector<media::Particle> plainParticle{sphereAt({0.2f, 0.0f, -5.0f}, 1.0f)};
    std::vector<media::Particle> tinted = plainParticle, hot = plainParticle;
    tinted[0].tint = tint;
    hot[0].temperature = 1900.0f;
    MediaReferenceInput in;
    in.frame = f;
    in.materials = materials;
    for (bool physical : {false, true}) {
      SCOPED_TRACE(physical ? "physical" : "model");
      const auto pixel = [&](const std::vector<media::Particle>& ps) {
        in.particles = ps;
        return physical ? physicalPixel(in, {.step = 0.05}) : modelPixel(in);
      };
      const Pixel a = pixel(plainParticle), b = pixel(tinted), c = pixel(hot);
      ASSERT_GT(a.radiance.r, 0.01);
      expectNear(b.radiance, a.radiance * glm::dvec3(tint), 1e-6);  // the layer holds floats
      EXPECT_EQ(b.transmittance, a.transmittance);
      m.temperature = 1900.0f;
      materials[0] = m;
      in.particles = plainParticle;
      const Pixel d = physical ? physicalPixel(in, {.step = 0.05}) : modelPixel(in);
      expectNear(c.radiance, d.radiance, 1e-6);
      if (fire) {
        EXPECT_GT(std::abs(c.radiance.r - a.radiance.r), 0.01) << "1900 K is not fire's 2500 K";
      }
      m = fire ? media::fireMaterial() : plain(0.7f, 0.6f);
      materials[0] = m;
    }
  }
}

TEST(MediaPhysical, TheTemperatureTableIsExactAtTheToleranceOfTheReference) {
  // A constant temperature video of 0.5 gives T0 + T1 / 2 at every sample, as no video does; with
  // it the reference reads Le from its 0.25 K table, without it evaluates Planck's law.
  const media::Frame f = rayFrame();
  core::DetailVideo half;
  half.width = half.height = 4;
  half.frames = 2;
  half.values.assign(4 * 4 * 2, 0.5f);
  for (float t0 : {650.1f, 1234.567f, 2500.0f, 6789.1f}) {  // T = T0 + 350 K
    media::Material fire = media::fireMaterial();
    fire.temperature = t0;
    const std::vector<media::Material> materials{fire};
    const std::vector<media::Particle> particles{sphereAt({0.2f, 0.0f, -5.0f}, 1.0f)};
    MediaReferenceInput in;
    in.frame = f;
    in.particles = particles;
    in.materials = materials;
    const Pixel exact = physicalPixel(in, {.step = 0.05});
    in.temperatureDetail = &half;
    const Pixel table = physicalPixel(in, {.step = 0.05});
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(table.radiance[c], exact.radiance[c], 1e-7 * exact.radiance[c] + 1e-9);
      if (exact.radiance[c] > 0.0) worst = std::max(worst, std::abs(table.radiance[c] / exact.radiance[c] - 1.0));
    }
    std::printf("T %.2f K: table vs Planck, largest relative difference %.2e\n", t0 + 350.0, worst);
  }
}

// A small perspective frame of fire turning into smoke, dust and smoke with both detail videos,
// over a wall, with the camera in the medium's edge.
struct Cloud {
  media::Frame frame;
  std::vector<media::Material> materials;
  std::vector<media::Particle> particles;
  std::vector<float> depth;
  std::vector<glm::vec3> color;
  core::DetailVideo temperature, opacity;

  Cloud(int w, int h) {
    frame.projection =
        glm::perspective(glm::radians(40.0f), static_cast<float>(w) / static_cast<float>(h), 0.5f, 30.0f);
    frame.nearPlane = 0.5f;
    frame.farPlane = 30.0f;
    frame.viewport.width = w;
    frame.viewport.height = h;
    frame.time = 0.7f;
    media::Material fire = media::fireMaterial(), smoke = media::smokeMaterial(), dust = media::dustMaterial();
    fire.becomes = 1;
    smoke.detail = 1.0f;
    materials = {fire, smoke, dust};
    std::uint32_t seed = 11;
    for (int k = 0; k < 14; ++k) {
      media::Particle p;
      p.position = glm::vec3(-1.6f + 0.25f * k, 0.4f * std::sin(1.3f * k), -6.0f - 0.3f * (k % 5));
      p.radius = 0.6f + 0.1f * (k % 4);
      p.material = static_cast<std::uint32_t>(k % 3);
      p.life = 0.1f + 0.06f * k;
      p.seed = seed = seed * 747796405u + 2891336453u;
      particles.push_back(p);
    }
    // A wall at 6.5 over the right half, nothing on the left.
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const bool wall = i >= w / 2;
        depth.push_back(wall ? static_cast<float>((6.5 - 0.5) / (30.0 - 0.5)) : 1.0f);
        color.push_back(wall ? glm::vec3(0.3f, 0.4f, 0.5f) : glm::vec3(0.05f));
      }
    bake::DetailSpec spec;
    spec.size = 16;
    spec.frames = 4;
    spec.frequency = 2;
    spec.octaves = 2;
    temperature = *bake::generateDetailVideo(spec);
    spec.seed = 7;
    opacity = *bake::generateDetailVideo(spec);
  }

  MediaReferenceInput input() const {
    MediaReferenceInput in;
    in.frame = frame;
    in.particles = particles;
    in.materials = materials;
    in.opaqueColor = color;
    in.opaqueDepth = depth;
    in.temperatureDetail = &temperature;
    in.opacityDetail = &opacity;
    return in;
  }
};

TEST(MediaPhysical, TheAutomaticStepConverges) {
  const Cloud cloud(40, 30);
  const MediaReferenceInput in = cloud.input();
  PhysicalReport report;
  const PhysicalOptions options{.step = 0.0, .tolerance = 1e-4};
  auto image = reference::renderMediaPhysical(in, options, nullptr, &report);
  ASSERT_OK(image);
  std::printf("automatic step: %g after %d halvings (%d images), last change %.3g\n", report.step, report.halvings,
              report.images, report.lastChange);
  EXPECT_TRUE(report.converged);
  EXPECT_LT(report.lastChange, options.tolerance);
  EXPECT_GE(report.halvings, 1);
  EXPECT_EQ(report.images, report.halvings + 1);
  EXPECT_NEAR(report.step, 0.5 * 0.9 / (1 << report.halvings), 1e-6);  // starts at half the largest radius
  // The image really is that close: a step 4 times finer changes it by less again.
  auto finer = reference::renderMediaPhysical(in, {.step = report.step / 4});
  ASSERT_OK(finer);
  EXPECT_LT(reference::imageError(*image, *finer).rmse, options.tolerance);
  // The medium shows: the image is not the opaque layer.
  core::Image opaque(40, 30, 4, 1.0f);
  for (int j = 0; j < 30; ++j)
    for (int i = 0; i < 40; ++i)
      for (int c = 0; c < 3; ++c) opaque.at(i, 29 - j, c) = cloud.color[static_cast<std::size_t>(j) * 40 + i][c];
  EXPECT_GT(reference::imageError(*image, opaque).rmse, 0.05);
  // Deterministic.
  auto again = reference::renderMediaPhysical(in, options);
  ASSERT_OK(again);
  EXPECT_EQ(again->pixels, image->pixels);
  // And close to the model, though not equal (overlaps, the field's larger optical depth off the centres).
  auto model = reference::renderMediaReference(in);
  ASSERT_OK(model);
  std::printf("physical vs model: RMSE %.4f\n", reference::imageError(*image, *model).rmse);
}

TEST(MediaPhysical, BadInputIsAnError) {
  const media::Frame f = rayFrame();
  const std::vector<media::Material> materials{plain(0.5f, 0.5f)};
  const std::vector<media::Particle> particles{sphereAt({0.0f, 0.0f, -5.0f}, 1.0f)};
  MediaReferenceInput good;
  good.frame = f;
  good.particles = particles;
  good.materials = materials;
  ASSERT_OK(reference::renderMediaPhysical(good, {}));

  auto message = [](const MediaReferenceInput& in, const PhysicalOptions& o) {
    auto r = reference::renderMediaPhysical(in, o);
    return r ? std::string("ok") : r.error().message;
  };
  MediaReferenceInput in = good;
  in.frame.viewport.width = 0;
  EXPECT_NE(message(in, {}).find("frame size"), std::string::npos);
  in = good;
  in.materials = {};
  EXPECT_NE(message(in, {}).find("materials"), std::string::npos);
  const std::vector<media::Particle> stray{sphereAt({0.0f, 0.0f, -5.0f}, 1.0f, 3)};
  in = good;
  in.particles = stray;
  EXPECT_NE(message(in, {}).find("particles/0/material"), std::string::npos);
  const std::vector<float> shortDepth(2, 0.5f);
  in = good;
  in.opaqueDepth = shortDepth;
  EXPECT_NE(message(in, {}).find("opaque depth"), std::string::npos);
  in = good;
  in.viewAxisOrder = true;
  EXPECT_NE(message(in, {}).find("viewAxisOrder"), std::string::npos);
  EXPECT_NE(message(good, {.step = -1.0}).find("step"), std::string::npos);
  EXPECT_NE(message(good, {.step = std::nan("")}).find("step"), std::string::npos);
  EXPECT_NE(message(good, {.tolerance = 0.0}).find("tolerance"), std::string::npos);
  EXPECT_NE(message(good, {.maxHalvings = 25}).find("maxHalvings"), std::string::npos);
}

}  // namespace
}  // namespace puff
