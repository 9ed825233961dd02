// Nailboards against analytic expectations: packing, cel shading, outlines, flanges and billboard orientations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#define GLM_ENABLE_EXPERIMENTAL  // glm::rotation(from, to)
#include <glm/gtx/quaternion.hpp>

#include <puff/bake/baker.h>
#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/core/atlas.h>
#include <puff/core/colour.h>
#include <puff/core/image.h>
#include <puff/gl_api.h>
#include <puff/mesh/mesh.h>

#include "nailboard_fixture.h"
#include "support/assert_ok.h"
#include "support/linear_frame.h"

namespace puff::nailboard_test {
namespace {

// ---- packing (no GL) ---------------------------------------------------------------------------

// A tint is scene-linear; the record keeps its display value in 7 bits. Every code's own linear
// value packs to that code, and the midpoints between codes (in display) round up, as lround does.
TEST(ParticlePacking, ATintPacksToTheNearestDisplayCode) {
  std::vector<cel::PackedParticle> packed;
  for (int k = 0; k <= 127; ++k) {
    Particle p;
    p.tint = glm::vec3(static_cast<float>(core::srgbToLinear(k / 127.0)),
                       static_cast<float>(core::srgbToLinear(std::min(k + 0.49, 127.0) / 127.0)),
                       static_cast<float>(core::srgbToLinear(std::max(k - 0.49, 0.0) / 127.0)));
    cel::packParticles(std::span(&p, 1), packed);
    const std::uint32_t w = packed[0].w;
    EXPECT_EQ((w >> 9) & 127u, static_cast<unsigned>(k)) << "its own value";
    EXPECT_EQ((w >> 16) & 127u, static_cast<unsigned>(k)) << "just under the midpoint above";
    EXPECT_EQ((w >> 23) & 127u, static_cast<unsigned>(k)) << "just over the midpoint below";
    EXPECT_NEAR(cel::unpackParticle(packed[0], {}).tint.r, core::srgbToLinear(k / 127.0), 1e-6) << k;
  }
}

TEST(ParticlePacking, SixteenBytesRoundTripWithinQuantization) {
  std::vector<Particle> in;
  for (int i = 0; i < 200; ++i) {
    Particle p;
    p.position = glm::vec3(std::sin(i * 1.3f) * 40.0f, i * 0.05f, std::cos(i * 0.7f) * 3.0f);
    p.size = 0.01f + static_cast<float>(i) * 0.37f;
    p.variation = i % 7;
    p.oriented = (i % 2) == 1;
    p.orientation = glm::normalize(glm::quat(std::cos(i * 0.1f), std::sin(i * 0.3f), 0.2f, -std::sin(i * 0.2f)));
    // Tints over [-0.1, 1.1]: the ends clamp to [0, 1]; every other particle untinted.
    if (i % 2 == 0) p.tint = glm::vec3(-0.1f + 1.2f * i / 199.0f, 1.1f - 1.2f * i / 199.0f, 0.5f);
    in.push_back(p);
  }
  std::vector<cel::PackedParticle> packed;
  const cel::PackBounds b = cel::packParticles(in, packed);
  ASSERT_EQ(packed.size() * sizeof(cel::PackedParticle), in.size() * 16u);
  const glm::vec3 step = (b.max - b.min) / 65535.0f;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const Particle out = cel::unpackParticle(packed[i], b);
    for (int a = 0; a < 3; ++a) EXPECT_LE(std::abs(out.position[a] - in[i].position[a]), 0.5f * step[a] + 1e-5f) << i;
    EXPECT_NEAR(out.size, in[i].size, in[i].size * 1e-3f) << i;  // half float: 11 significant bits
    EXPECT_EQ(out.variation, in[i].variation);
    EXPECT_EQ(out.oriented, in[i].oriented);
    for (int c = 0; c < 3; ++c) {  // 7 bits a channel of the display value, white exactly 1
      const double display = core::linearToSrgb(double{out.tint[c]});
      EXPECT_NEAR(display, core::linearToSrgb(std::clamp(double{in[i].tint[c]}, 0.0, 1.0)), 0.5 / 127.0 + 1e-6)
          << i << " channel " << c;
      EXPECT_NEAR(display * 127.0, std::round(display * 127.0), 1e-4) << "a 7-bit code: " << i << " channel " << c;
    }
    if (i % 2 == 1) {
      EXPECT_EQ(out.tint, glm::vec3(1.0f));
    }
    if (in[i].oriented) {
      // q and -q are one rotation: compare |dot|.
      EXPECT_GT(std::abs(glm::dot(out.orientation, in[i].orientation)), 0.99999f - 2e-5f) << i;
    }
  }
}

// ---- cel shading, outlines and flanges ---------------------------------------------------------

bool isInk(const glm::vec4& c) { return c.r < 0.05f && c.g < 0.05f && c.b < 0.05f; }
bool isWhiteBg(const glm::vec4& c) { return c.r > 0.99f && c.g > 0.99f && c.b > 0.99f; }

TEST_F(Nailboards, UploadIsSixteenBytesPerParticle) {
  std::vector<Particle> ps(1000);
  const cel::DrawStats s = renderer_->upload(ps);
  EXPECT_EQ(s.bytesUploaded, 16000u);
}

// Eq. 2 with a two-tone ramp and the light toward the viewer: every body pixel is K_a + C K_L q(N.L),
// q = 1 where N.L >= 0.5, i.e. within 0.866 R of the centre, and 0 beyond.
TEST_F(Nailboards, CelShadingMatchesEquation2OnTheSphere) {
  cel::Style style;
  style.outlines = false;
  const float size = 4.0f;  // R = 2 units = 32 px
  draw(orthoFrame(), {Particle{glm::vec3(0), size}}, style);
  const auto px = target_->readColor();
  int checked = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const glm::vec2 w = pixelToWorld(x, y);
      const float r = glm::length(w) / (size / 2);
      const glm::vec4 c = px[static_cast<std::size_t>(y) * kPx + x];
      const float nz = std::sqrt(std::max(0.0f, 1.0f - r * r));  // N.L with L = +z
      if (r < 0.95f && std::abs(nz - 0.5f) > 0.03f) {
        const float expected = nz >= 0.5f ? 0.2f + 0.5f : 0.2f;
        EXPECT_NEAR(c.r, expected, 2.5f / 255.0f) << x << "," << y;
        ++checked;
      } else if (r > 1.06f) {
        EXPECT_TRUE(isWhiteBg(c)) << x << "," << y;
      }
    }
  }
  EXPECT_GT(checked, 2500);
}

// Eq. 2 in general poses, on every channel: K_a + C K_L q(N.L) with N the sphere's own normal at
// the pixel and L the light turned into the camera's frame, against rotated, tilted and rolled
// cameras, lights from several sides, a coloured light, a coloured ambient, a coloured atlas and a
// four-band ramp whose bands differ per channel. An orthographic camera looking at the puff sees
// its normal at screen offset (x, y) R as (x, y, sqrt(1 - x^2 - y^2)) in camera space whatever the
// camera's pose; what turns is L. The brightest band overflows the display's range in red: Eq. 2 is
// limited to 1 there. Pixels within 0.03 of a band's edge in N.L are skipped.
TEST_F(Nailboards, Equation2HoldsOnEveryChannelInGeneralPoses) {
  const glm::vec3 atlasColor{0.85f, 0.55f, 0.25f};  // display values
  core::Atlas coloured = *atlas_;
  for (core::Image& level : coloured.maps.at("color")) {
    for (int y = 0; y < level.height; ++y) {
      for (int x = 0; x < level.width; ++x) {
        for (int c = 0; c < 3; ++c) level.at(x, y, c) = atlasColor[c];
      }
    }
  }
  ASSERT_OK(renderer_->setAtlas(coloured));
  // q's four bands (display values): N.L in [0, 1/4), [1/4, 1/2), [1/2, 3/4), [3/4, 1].
  const glm::vec3 bands[4] = {
      {0.05f, 0.10f, 0.20f}, {0.30f, 0.40f, 0.25f}, {0.60f, 0.50f, 0.70f}, {1.0f, 0.90f, 0.80f}};
  core::Image rampImage(4, 1, 3, 0.0f);
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c) rampImage.at(i, 0, c) = bands[i][c];
  }
  auto ramp = cel::Ramp::create(rampImage, "four-band test ramp");
  ASSERT_OK(ramp);
  const glm::vec3 lightColor{0.95f, 0.6f, 0.45f}, ambient{0.3f, 0.12f, 0.2f};  // display values
  struct Pose {
    glm::vec3 eye, up;
  };
  const Pose poses[] = {{{0, 0, 1}, {0, 1, 0}},          // the plain view
                        {{1, 2, 3}, {0, 1, 0}},          // rotated and tilted
                        {{-2, 1, -1}, {0.5f, 1, 0.2f}},  // from behind, rolled
                        {{0.3f, -1, 0.2f}, {0, 0, 1}},   // from below
                        {{1, 0, 0}, {0, 1, 1}}};         // from the side, rolled 45 degrees
  const glm::vec3 lights[] = {{0.4f, 1.0f, 0.3f}, {-1.0f, 0.2f, 0.5f}, {0.2f, -0.6f, -1.0f}};
  const float R = 2.0f;  // size 4: 32 px
  cel::Style style;
  style.outlines = false;
  for (const Pose& pose : poses) {
    for (const glm::vec3& light : lights) {
      cel::Camera cam;
      cam.position = glm::normalize(pose.eye) * 10.0f;
      cam.target = glm::vec3(0);
      cam.up = pose.up;
      cam.fovYDegrees = 0.0f;
      cam.orthoHeight = kWorld;
      cam.nearPlane = 1.0f;
      cam.farPlane = 21.0f;
      cel::Frame f = test::linearFrame(cam, kPx, kPx);
      f.light.direction = light;
      f.light.color = puff::core::srgbToLinear(lightColor);
      f.ambient = puff::core::srgbToLinear(ambient);
      const glm::vec3 lView = glm::normalize(glm::mat3(f.view) * glm::normalize(light));
      target_->clear(1.0f);
      EXPECT_OK(block_->upload(f));
      ramp->bind();
      renderer_->upload(std::vector<Particle>{Particle{glm::vec3(0), 2 * R}});
      renderer_->drawNailboards(style, cel::ShadePass::kLit);
      const auto px = target_->readColor();
      int checked = 0, wrong = 0;
      for (int y = 0; y < kPx; ++y) {
        for (int x = 0; x < kPx; ++x) {
          const glm::vec2 w = pixelToWorld(x, y) / R;
          const float r2 = glm::dot(w, w);
          if (r2 > 0.92f * 0.92f) continue;
          const glm::vec3 n(w, std::sqrt(1.0f - r2));
          const float nl = glm::dot(n, lView);
          const float band = std::clamp(nl, 0.0f, 1.0f) * 4.0f;
          if (nl > 0.0f && std::abs(band - std::round(band)) < 0.12f) continue;  // 0.03 in N.L
          const glm::vec3 q = bands[std::min(3, static_cast<int>(band))];
          const glm::vec3 expected = glm::clamp(ambient + atlasColor * lightColor * q, 0.0f, 1.0f);
          const glm::vec4 c = px[static_cast<std::size_t>(y) * kPx + x];
          ++checked;
          for (int ch = 0; ch < 3; ++ch) {
            if (std::abs(c[ch] - expected[ch]) > 3.0f / 255.0f) {
              if (++wrong <= 3) {
                ADD_FAILURE() << "eye (" << pose.eye.x << ", " << pose.eye.y << ", " << pose.eye.z << "), light ("
                              << light.x << ", " << light.y << ", " << light.z << "): pixel " << x << "," << y
                              << " channel " << ch << " is " << c[ch] << ", Eq. 2 gives " << expected[ch] << " (N.L "
                              << nl << ")";
              }
            }
          }
        }
      }
      EXPECT_EQ(wrong, 0) << "of " << checked << " pixels";
      EXPECT_GT(checked, 2000);
    }
  }
}

// The ramp's clamp-to-edge gives q(max(0, N.L)): with the light behind the puff every N.L <= 0 and
// every body pixel reads the ramp's first texel, here red.
TEST_F(Nailboards, RampClampEnforcesMaxZero) {
  core::Image rampImage(4, 1, 3, 0.0f);
  rampImage.at(0, 0, 0) = 1.0f;                              // texel 0 red
  for (int x = 1; x < 4; ++x) rampImage.at(x, 0, 1) = 1.0f;  // the rest green
  auto ramp = cel::Ramp::create(rampImage, "test ramp");
  ASSERT_TRUE(ramp.ok());
  cel::Frame f = orthoFrame();
  f.light.direction = glm::vec3(0, 0, -1);
  f.light.color = glm::vec3(1.0f);
  f.ambient = puff::core::srgbToLinear(glm::vec3(0.0f));
  cel::Style style;
  style.outlines = false;
  target_->clear(1.0f);
  EXPECT_OK(block_->upload(f));
  ramp->bind();
  renderer_->upload(std::vector<Particle>{Particle{glm::vec3(0), 4.0f}});
  renderer_->drawNailboards(style, cel::ShadePass::kLit);
  const auto px = target_->readColor();
  int body = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      if (glm::length(pixelToWorld(x, y)) > 1.8f) continue;
      const glm::vec4 c = px[static_cast<std::size_t>(y) * kPx + x];
      EXPECT_GT(c.r, 0.98f);
      EXPECT_LT(c.g, 0.02f);
      ++body;
    }
  }
  EXPECT_GT(body, 2000);
}

// A sphere puff of radius R centred at distance delta behind a plane perpendicular to the view:
// its front surface pokes through where sqrt(R^2 - r^2) > delta, a disc of radius sqrt(R^2 - delta^2)
// (the curve its depth map predicts).
TEST_F(Nailboards, ParticleMeetsAPlaneAlongTheDepthMapCurve) {
  const float R = 2.0f;
  for (float delta : {0.5f, 1.0f, 1.5f}) {
    cel::Style style;
    style.outlines = false;
    const float planeZ = delta;  // particle at z = 0, plane nearer the camera by delta
    draw(orthoFrame(), {Particle{glm::vec3(0), 2 * R}}, style, depthOfZ(planeZ));
    const auto px = target_->readColor();
    int visible = 0;
    for (const glm::vec4& c : px) visible += isWhiteBg(c) ? 0 : 1;
    const float pxPerUnit = kPx / kWorld;
    const double expectedRadius = std::sqrt(R * R - delta * delta) * pxPerUnit;
    const double measuredRadius = std::sqrt(visible / std::numbers::pi);
    EXPECT_NEAR(measuredRadius, expectedRadius, 1.0) << "delta " << delta;
  }
}

// Outline texels lie on the billboard plane (d = 0), which is what lets a nearer body hide them
// (Fig. 5). A receiving plane a hair in front of the billboard plane (0.1 units, 1/40 of the
// diameter) hides the whole ink ring, while the body's front pokes through it; the same plane a hair
// behind shows the whole ring, as wide as asked.
TEST_F(Nailboards, OutlinesLieOnTheBillboardPlane) {
  cel::Style style;
  style.outlineWidth = 3.0f;
  for (float planeZ : {0.1f, -0.1f}) {
    draw(orthoFrame(), {Particle{glm::vec3(0), 4.0f}}, style, depthOfZ(planeZ));
    const auto px = target_->readColor();
    int ink = 0, body = 0;
    for (const glm::vec4& c : px) {
      ink += isInk(c) ? 1 : 0;
      body += !isInk(c) && !isWhiteBg(c) ? 1 : 0;
    }
    const double ring = std::numbers::pi * ((32.0 + 3.0) * (32.0 + 3.0) - 32.0 * 32.0);  // 3 px around 32 px
    if (planeZ > 0.0f) {
      EXPECT_EQ(ink, 0) << "ink in front of a plane 0.1 units before the billboard plane";
      EXPECT_GT(body, 2500) << "the body pokes through";
    } else {
      EXPECT_NEAR(ink, ring, 0.15 * ring);
    }
  }
}

// Fig. 5: two puffs at the same depth overlapping; the body of each is nearer than the other's
// flange, so no ink shows inside the union, while the outer outline is there.
TEST_F(Nailboards, FlangeBetweenOverlappingParticlesIsHidden) {
  cel::Style style;
  style.outlineWidth = 3.0f;
  const float R = 1.5f;
  draw(orthoFrame(), {Particle{glm::vec3(-1.0f, 0, 0), 2 * R}, Particle{glm::vec3(1.0f, 0, 0), 2 * R}}, style);
  const auto px = target_->readColor();
  int interiorInk = 0, interior = 0, outerInk = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const glm::vec2 w = pixelToWorld(x, y);
      const float da = glm::length(w - glm::vec2(-1, 0)), db = glm::length(w - glm::vec2(1, 0));
      const glm::vec4 c = px[static_cast<std::size_t>(y) * kPx + x];
      if (da < R - 0.15f && db < R - 0.15f) {  // inside both bodies: where the flanges would cross
        ++interior;
        interiorInk += isInk(c) ? 1 : 0;
      }
      if (std::min(da, db) > R + 0.03f && std::min(da, db) < R + 0.12f) outerInk += isInk(c) ? 1 : 0;
    }
  }
  EXPECT_GT(interior, 200);
  EXPECT_EQ(interiorInk, 0);
  EXPECT_GT(outerInk, 50);
}

// The outline band is as wide as asked, in pixels, within half a pixel, and the body keeps its
// silhouette within a quarter of a pixel: from the distance field up to what its baked range holds
// (range - 1 texels: 2.7 px for the 64-px puff), from the silhouette's radius table beyond. Widths
// are measured from areas (hard edges, one sample): the body's pixels give its radius
// sqrt(A / pi), body and ink together the outer radius, and the band is their difference; both
// against the sphere's R and R + width, over widths from a hairline to a wide band, fractional ones
// included, and puffs from 16 to 112 px across (every mip level the atlas has a use for). Measured:
// the body within 0.14 px (the pixel grid's own error for a 16-px disc), the band within 0.36 px.
// (The body was a fifth of a pixel small at every size while the colour map was black outside the
// silhouette: filtering at the rim mixed that black in, and it read as ink.)
TEST_F(Nailboards, OutlineWidthIsARunTimeChoice) {
  for (float R : {0.5f, 0.75f, 1.0f, 1.25f, 1.5f, 2.0f, 2.75f, 3.5f}) {  // radii 8 to 56 px
    for (float width : {1.0f, 1.5f, 2.0f, 2.5f, 3.0f, 5.0f, 8.0f, 12.0f}) {
      if (R * kPx / kWorld + width > kPx / 2 - 2) continue;  // the band must lie inside the frame
      cel::Style style;
      style.outlineWidth = width;
      style.shading = false;  // the body is flat K_a + C K_L: any pixel neither ink nor background
      draw(orthoFrame(), {Particle{glm::vec3(0), 2 * R}}, style);
      const auto px = target_->readColor();
      // The body's inner edge is antialiased (ink mixed with the body in linear light): a pixel
      // is body where it is more body than ink, brighter than their linear midpoint.
      const double flat = 0.2 + 0.5;  // K_a + C K_L, display
      const double midpoint = core::linearToSrgb(0.5 * core::srgbToLinear(flat));
      int ink = 0, body = 0;
      for (const glm::vec4& c : px) {
        if (isWhiteBg(c)) continue;
        (c.r < midpoint ? ink : body) += 1;
      }
      const double radiusPx = R * kPx / kWorld;
      const double bodyRadius = std::sqrt(body / std::numbers::pi);
      const double outerRadius = std::sqrt((body + ink) / std::numbers::pi);
      EXPECT_NEAR(bodyRadius, radiusPx, 0.25) << "R " << radiusPx << " px, width " << width;
      EXPECT_NEAR(outerRadius - bodyRadius, width, 0.5) << "R " << radiusPx << " px, width " << width;
    }
  }
}

// ---- billboard orientations --------------------------------------------------------------------

int visiblePixels(const std::vector<glm::vec4>& px) {
  int n = 0;
  for (const glm::vec4& c : px) n += (c.r > 0.99f && c.g > 0.99f && c.b > 0.99f) ? 0 : 1;
  return n;
}

// Real-Time Rendering §10.6: an axial billboard (turning only about world up) seen from 60 degrees
// above is foreshortened to half its height; a view-plane billboard is not.
TEST_F(Nailboards, AxialBillboardsForeshortenFromAbove) {
  cel::Camera cam;
  cam.position = glm::vec3(0, 10 * std::sin(glm::radians(60.0f)), 10 * std::cos(glm::radians(60.0f)));
  cam.target = glm::vec3(0);
  cam.fovYDegrees = 0.0f;
  cam.orthoHeight = kWorld;
  cam.nearPlane = 1.0f;
  cam.farPlane = 21.0f;
  cel::Frame f = test::linearFrame(cam, kPx, kPx);
  f.light.color =
      puff::core::srgbToLinear(glm::vec3(0.5f));  // lit pixels stay distinguishable from the white background
  cel::Style style;
  style.outlines = false;
  style.alignment = cel::Alignment::kViewPlane;
  draw(f, {Particle{glm::vec3(0), 4.0f}}, style);
  const int viewPlane = visiblePixels(target_->readColor());
  style.alignment = cel::Alignment::kAxial;
  draw(f, {Particle{glm::vec3(0), 4.0f}}, style);
  const int axial = visiblePixels(target_->readColor());
  EXPECT_NEAR(static_cast<double>(axial) / viewPlane, 0.5, 0.03);
}

// Off the view axis, a view-plane billboard keeps the puff round on screen; a viewpoint-oriented
// one faces the eye and is stretched along the radial direction as a real sphere is, by about
// 1/cos(theta) at angle theta off-axis.
TEST_F(Nailboards, ViewpointBillboardsDistortLikeASphere) {
  cel::Camera cam;
  cam.position = glm::vec3(0, 0, 10);
  cam.target = glm::vec3(0);
  cam.fovYDegrees = 90.0f;
  cam.nearPlane = 1.0f;
  cam.farPlane = 30.0f;
  cel::Frame f = test::linearFrame(cam, kPx, kPx);
  f.light.color = puff::core::srgbToLinear(glm::vec3(0.5f));
  const float theta = glm::radians(35.0f);
  const glm::vec3 pos(10 * std::tan(theta), 0, 0);  // in the plane z = 0, 35 degrees right of the axis
  auto extents = [&](cel::Alignment a) {
    cel::Style style;
    style.outlines = false;
    style.alignment = a;
    draw(f, {Particle{pos, 1.5f}}, style);
    const auto px = target_->readColor();
    int minX = kPx, maxX = -1, minY = kPx, maxY = -1;
    for (int y = 0; y < kPx; ++y) {
      for (int x = 0; x < kPx; ++x) {
        const glm::vec4 c = px[static_cast<std::size_t>(y) * kPx + x];
        if (c.r > 0.99f && c.g > 0.99f && c.b > 0.99f) continue;
        minX = std::min(minX, x), maxX = std::max(maxX, x), minY = std::min(minY, y), maxY = std::max(maxY, y);
      }
    }
    return glm::vec2(maxX - minX + 1, maxY - minY + 1);
  };
  const glm::vec2 plane = extents(cel::Alignment::kViewPlane);
  const glm::vec2 point = extents(cel::Alignment::kViewpoint);
  EXPECT_NEAR(plane.x / plane.y, 1.0, 0.06);
  EXPECT_NEAR(point.x / point.y, 1.0 / std::cos(theta), 0.08);
}

// A multi-view atlas of an ellipsoid (semi-axes 1, 0.5, 0.5): an oriented particle turned so the
// camera looks along one of the baked views shows that view's silhouette, whose area relative to
// the front view is sqrt(dz^2 + 0.25 dx^2) for the view direction d; an unoriented particle shows
// the front view.
TEST_F(Nailboards, OrientedParticlesShowTheBakedViewNearestTheCamera) {
  mesh::TriMesh m = mesh::generateSphere({5});
  for (glm::vec3& p : m.positions) p *= glm::vec3(1.0f, 0.5f, 0.5f);
  mesh::computeNormals(m);
  mesh::normalizeToUnitSphere(m);
  bake::BakeOptions o;
  o.cellSize = 128;
  o.viewGrid = 3;
  o.viewLayout = bake::ViewLayout::kOct;
  o.flange = {4.0f, false};
  o.outDir = dir_ / "ellipsoid";
  o.contactSheet = false;
  bake::PuffSource src;
  src.mesh = m;
  src.provenance.generator = "sphere";
  auto r = bake::bakeAtlas({src}, o);
  ASSERT_OK(r);
  auto atlas = core::loadAtlas(r->sidecar);
  ASSERT_OK(atlas);
  ASSERT_TRUE(renderer_->setAtlas(*atlas).ok());

  cel::Style style;
  style.outlines = false;
  Particle p{glm::vec3(0), 5.0f};
  draw(orthoFrame(), {p}, style);
  EXPECT_EQ(core::drainGlErrors(), "");
  const int front = visiblePixels(target_->readColor());
  // View (col 2, row 1) of the 3x3 octahedral grid looks from d = (2/3, 0, 1/3) normalized. Turn
  // the puff about y so that d points at the camera (+z).
  const glm::vec3 d = glm::normalize(glm::vec3(2.0f / 3.0f, 0.0f, 1.0f / 3.0f));
  p.oriented = true;
  p.orientation = glm::rotation(d, glm::vec3(0, 0, 1));
  draw(orthoFrame(), {p}, style);
  const int side = visiblePixels(target_->readColor());
  const double expected = std::sqrt(d.z * d.z + 0.25 * d.x * d.x);
  EXPECT_NEAR(static_cast<double>(side) / front, expected, 0.04);
}

}  // namespace
}  // namespace puff::nailboard_test
