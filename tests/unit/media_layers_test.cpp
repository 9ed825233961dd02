// Media layer composition: depth-aware upsampling, heat shimmer and explosion light over an opaque scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include <puff/gl_api.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>

#include "support/assert_ok.h"
#include "support/media_target.h"

namespace puff {
namespace {

using media::Method;

using test::plainMaterial;
using test::sphereAt;
using Camera = test::MediaCamera;

class MediaLayersTest : public test::MediaRendererTest {};

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
  f.viewport.width = w;
  f.viewport.height = h;
  const media::Particle p = sphereAt({0, 0, -6}, 2.0f);
  r.draw((*layers)->layerFrame(f), std::span(&p, 1), Method::kSpherical, (*layers)->mediaDepth(),
         media::Shimmer::kWritten);
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, w, h);
  glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  const core::Viewport vp{0, 0, w, h};
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

// The passes over what the media cover (setCoverage) draw the whole frame's passes' image to the bit
// at every layer scale, for a small dense puff beside the pole: at 1/8 a layer texel is wider than the
// puff, and the upsampling carries it past its billboard's box by up to two texels, which the box's
// padding holds (unpadded, pixels just outside the box change).
TEST_F(MediaLayersTest, PassesOverTheCoverageDrawTheWholeFramesImage) {
  ASSERT_TRUE(renderer_->setMaterials({plainMaterial(4.0f)}).ok());
  constexpr int w = 96, h = 64;
  Camera cam;
  media::Frame f = cam.frame(0);
  f.projection = glm::perspective(glm::radians(cam.fovDegrees), static_cast<float>(w) / h, cam.nearPlane, cam.farPlane);
  f.viewport.width = w;
  f.viewport.height = h;
  const media::Particle p = sphereAt({1.1f, 0.4f, -6}, 0.35f);
  const media::PixelBox box = media::coverage(f, std::span(&p, 1));
  EXPECT_LT((box.x1 - box.x0) * (box.y1 - box.y0), w * h / 20);
  for (const float scale : {1.0f, 0.5f, 0.25f, 0.125f}) {
    std::vector<glm::vec4> px[2];
    for (int covered = 0; covered < 2; ++covered) {
      auto layers = media::Layers::create(w, h, 1, scale);
      ASSERT_OK(layers);
      fillOpaque(**layers, 45, 51, cam.linear(3.0f), {0.1f, 0.1f, 0.1f, 1.0f});
      if (covered == 1) (*layers)->setCoverage(box);
      (*layers)->resolveOpaque();
      (*layers)->beginMedia();
      renderer_->draw((*layers)->layerFrame(f), std::span(&p, 1), Method::kSpherical, (*layers)->mediaDepth());
      core::Framebuffer out = core::makeFramebuffer();
      core::Texture color = core::makeTexture(GL_TEXTURE_2D);
      glTextureStorage2D(color.get(), 1, GL_RGBA32F, w, h);
      glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
      (*layers)->compose(out.get(), core::Viewport{0, 0, w, h}, f, {}, {});
      px[covered].resize(static_cast<std::size_t>(w) * h);
      glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px[covered].size() * sizeof(glm::vec4)),
                        px[covered].data());
    }
    EXPECT_EQ(px[1], px[0]) << "layer scale " << scale;
  }
  EXPECT_EQ(core::drainGlErrors(), "");
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
  const core::Viewport vp{0, 0, w, h};
  media::ComposeSettings cs;
  cs.shimmerPixels = 1.0f;
  Camera cam;
  media::Frame f = cam.frame(0);
  f.viewport.width = w, f.viewport.height = h;
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
  f.viewport.width = w;
  f.viewport.height = h;
  const std::vector<media::Particle> ps = {sphereAt({0.0f, -0.3f, -13.0f}, 2.0f), sphereAt({1.2f, -0.4f, -8.0f}, 1.5f),
                                           sphereAt({-1.5f, -0.6f, -5.0f}, 1.2f)};  // back to front
  r.draw((*layers)->layerFrame(f), ps, Method::kSpherical, (*layers)->mediaDepth(), media::Shimmer::kOff);
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, w, h);
  glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  const core::Viewport vp{0, 0, w, h};
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
