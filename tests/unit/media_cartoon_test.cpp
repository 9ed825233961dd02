// Cartoon media (media::Style::kCartoon; layers.h, "Cartoon media") against closed forms: a lone
// sphere's accumulated opacity is media::sphereOpacity along each pixel's ray, so its iso-line
// A = threshold is a circle whose radius bisection finds; the fill inside it, the ink band outside
// it and the untouched scene beyond are checked pixel by pixel, at full and half layer resolution
// and over the ink's widths. Fire bands against the photoreal renderer's own black-body colour at
// each band's centre; merging, occlusion, outlines off, and smooth motion (no flicker) too.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <puff/core/colour.h>
#include <puff/eval/budget.h>
#include <puff/gl_api.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/media_target.h"

namespace puff::media_cartoon {
namespace {

namespace fs = std::filesystem;

constexpr int kSize = 96;
const glm::vec3 kBackground(0.2f, 0.4f, 0.9f);  // scene-linear
const glm::vec3 kColour(1.0f, 0.5f, 0.25f);     // the smoke's scattered light (albedo 1, ambient 1)

using Camera = test::MediaCamera;

// The camera-space ray through a continuous screen point (pixels, row 0 at the bottom).
glm::dvec3 rayAt(const Camera& cam, double sx, double sy, int size) {
  const double t = std::tan(glm::radians(static_cast<double>(cam.fovDegrees)) / 2.0);
  return glm::normalize(glm::dvec3((sx / size * 2.0 - 1.0) * t, (sy / size * 2.0 - 1.0) * t, -1.0));
}

// The screen radius (pixels from the image centre) where a sphere centred on the view axis has
// opacity `theta`: bisection along the x axis (its opacity falls from the centre outward).
double isoRadius(const Camera& cam, double z, double r, double tau, double theta, int size) {
  double lo = 0.0, hi = size / 2.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double a = media::sphereOpacity(glm::dvec3(0.0), rayAt(cam, size / 2.0 + mid, size / 2.0, size),
                                          {0.0, 0.0, -z}, r, tau, 1e30, cam.nearPlane);
    (a >= theta ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The tier a cartoon fill draws for accumulated opacity A (types.h, CartoonStyle).
double tierOf(double A, const media::CartoonStyle& st) {
  const double x = std::clamp((A - st.threshold) / (1.0 - st.threshold), 0.0, 1.0);
  const double k = std::min(std::floor(x * st.opacityBands), st.opacityBands - 1.0);
  return st.threshold + (1.0 - st.threshold) * (k + 1.0) / st.opacityBands;
}

// Everything one cartoon frame needs: a renderer of the style, layers, an opaque pass of one colour
// (and optionally a nearer "pole" in columns [poleX0, poleX1)), and a float output.
class CartoonKit {
 public:
  CartoonKit(const media::Settings& settings, float scale, std::vector<media::Material> materials) {
    auto r = media::Renderer::create(settings);
    EXPECT_OK(r);
    renderer = std::move(*r);
    EXPECT_TRUE(renderer->setMaterials(std::move(materials)).ok());
    auto l = media::Layers::create(kSize, kSize, 1, scale);
    EXPECT_OK(l);
    layers = std::move(*l);
    auto c = media::cartoonCompose(settings);
    EXPECT_OK(c);
    cartoon = std::move(*c);
    glTextureStorage2D(color.get(), 1, GL_RGBA32F, kSize, kSize);
    glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  }

  std::vector<glm::vec4> draw(std::span<const media::Particle> particles, float backDepth = 1.0f, int poleX0 = 0,
                              int poleX1 = 0, float poleDepth = 0.0f, glm::vec3 pole = {0.1f, 0.1f, 0.1f}) {
    const GLuint fbo = layers->opaqueFramebuffer();
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    const glm::vec4 bg(kBackground, 1.0f), poleColour(pole, 1.0f);
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &bg.x);
    glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, backDepth, 0);
    if (poleX1 > poleX0) {
      glEnable(GL_SCISSOR_TEST);
      glScissor(poleX0, 0, poleX1 - poleX0, kSize);
      glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &poleColour.x);
      glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, poleDepth, 0);
      glDisable(GL_SCISSOR_TEST);
    }
    layers->resolveOpaque();
    layers->beginMedia(media::Style::kCartoon);
    const media::Frame f = camera.frame(kSize);
    renderer->draw(layers->layerFrame(f), particles, media::Method::kSpherical, layers->mediaDepth());
    const core::Viewport vp{0, 0, kSize, kSize};
    layers->compose(out.get(), vp, f, {}, media::ComposeSettings{}, &cartoon);
    std::vector<glm::vec4> px(static_cast<std::size_t>(kSize) * kSize);
    glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(glm::vec4)),
                      px.data());
    EXPECT_EQ(core::drainGlErrors(), "");
    return px;
  }

  Camera camera;
  std::unique_ptr<media::Renderer> renderer;
  std::unique_ptr<media::Layers> layers;
  media::CartoonCompose cartoon;
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
};

media::Settings cartoonSettings(float inkWidth, bool outlines = true) {
  media::Settings s;
  s.style = media::Style::kCartoon;
  s.cartoon.threshold = 0.35f;
  s.cartoon.opacityBands = 2;
  s.cartoon.outlines = outlines;
  s.cartoon.outlineWidth = inkWidth;
  s.cartoon.outlineColor = glm::vec3(0.0f);
  return s;
}

media::Material smoke(float tau) {
  media::Material m = test::plainMaterial(tau);
  m.color = kColour;
  return m;
}

// Fill share a and ink share k of a pixel over the background with fill colour `fill` and black
// ink: pixel = bg (1 - a - k) + fill a, solved from the red and blue channels.
glm::dvec2 fillAndInk(const glm::vec4& px, const glm::vec3& fill) {
  // R = bgR (1 - a - k) + fR a;  B = bgB (1 - a - k) + fB a.
  const double m00 = fill.r - kBackground.r, m01 = -kBackground.r, m10 = fill.b - kBackground.b, m11 = -kBackground.b;
  const double r0 = px.r - kBackground.r, r1 = px.b - kBackground.b;
  const double det = m00 * m11 - m01 * m10;
  return {(r0 * m11 - m01 * r1) / det, (m00 * r1 - r0 * m10) / det};
}

class CartoonMedia : public test::GlTest {};

// One sphere on the view axis: a flat disc inside the iso-line (its two opacity tiers where the
// closed form says), a black band `width` pixels wide outside it, the scene untouched beyond, at
// full and half layer resolution and for thin, medium and wide ink. The ink's area is the
// annulus's, the fill's the disc's.
TEST_F(CartoonMedia, ALoneSphereIsAFlatDiscRingedByInkAtItsIsoLine) {
  const double z = 6.0, r = 2.0, tau = 0.6;
  for (float scale : {1.0f, 0.5f}) {
    for (float width : {1.0f, 2.5f, 4.0f}) {
      SCOPED_TRACE("layer scale " + std::to_string(scale) + ", ink " + std::to_string(width) + " px");
      const media::Settings settings = cartoonSettings(width);
      CartoonKit kit(settings, scale, {smoke(static_cast<float>(tau))});
      const media::Particle p = test::sphereAt({0.0f, 0.0f, static_cast<float>(-z)}, static_cast<float>(r));
      const auto px = kit.draw(std::span(&p, 1));
      const double rho = isoRadius(kit.camera, z, r, tau, settings.cartoon.threshold, kSize);
      ASSERT_GT(rho, 10.0);
      // Half a layer texel of bilinear upsampling moves the iso-line a little: the margins grow.
      const double margin = scale < 1.0f ? 1.5 : 1.0;
      int fills = 0, inks = 0, scenes = 0;
      double inkArea = 0.0, worstFill = 0.0, worstInk = 0.0, worstScene = 0.0;
      for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
          const glm::vec4& c = px[static_cast<std::size_t>(y) * kSize + x];
          const double s = std::hypot(x + 0.5 - kSize / 2.0, y + 0.5 - kSize / 2.0) - rho;  // signed distance
          const double A = media::sphereOpacity(glm::dvec3(0.0), kit.camera.ray(x, y, kSize), {0.0, 0.0, -z}, r, tau,
                                                1e30, kit.camera.nearPlane);
          const double tier = tierOf(A, settings.cartoon);
          const glm::dvec2 ak = fillAndInk(c, kColour);
          inkArea += ak.y;
          if (s < -margin) {
            // Inside, away from the tiers' boundary (A = 0.675, which upsampling moves too).
            if (std::abs(A - 0.675) < (scale < 1.0f ? 0.03 : 0.01)) continue;
            ++fills;
            for (int i = 0; i < 3; ++i)
              worstFill = std::max(worstFill, std::abs(c[i] - (kBackground[i] * (1.0 - tier) + kColour[i] * tier)));
          } else if (s > 0.75 && s < width - 0.75) {
            ++inks;
            worstInk = std::max({worstInk, double{c.r}, double{c.g}, double{c.b}});
          } else if (s > width + margin) {
            ++scenes;
            for (int i = 0; i < 3; ++i) worstScene = std::max(worstScene, std::abs(double{c[i]} - kBackground[i]));
          }
        }
      }
      EXPECT_GT(fills, 500);
      EXPECT_GT(scenes, 1000);
      if (width >= 2.5f) {
        EXPECT_GT(inks, 50);
      }
      EXPECT_LT(worstFill, 2e-3);  // the fill texture holds half floats
      EXPECT_LT(worstInk, 1e-6);
      EXPECT_LT(worstScene, 2e-4);  // the opaque colour is a half float
      // Areas: the ink's is the annulus between rho and rho + width (antialiased edges included).
      const double annulus = std::numbers::pi * ((rho + width) * (rho + width) - rho * rho);
      EXPECT_NEAR(inkArea / annulus, 1.0, 0.015);  // measured: 1.002 to 1.006
      if (std::getenv("PUFF_TEST_VERBOSE"))
        std::printf("scale %.1f ink %.1f: ink area / annulus %.4f, worst fill %.2e, fill pixels %d ink %d\n", scale,
                    width, inkArea / annulus, worstFill, fills, inks);
    }
  }
}

// The passes over what the media cover (setCoverage with the ink's width) draw the whole frame's
// passes' image to the bit: a small dense puff on the view axis, whose iso-line lies within a pixel
// or two of its billboard's edge and whose ink reaches up to 12 px past it, at full and quarter layer
// resolution; drawn after a larger puff in the same place, whose seeds around the smaller one's box
// must not be read.
TEST_F(CartoonMedia, PassesOverTheCoverageDrawTheWholeFramesImage) {
  for (float scale : {1.0f, 0.25f}) {
    for (float width : {2.0f, 12.0f}) {
      const media::Settings settings = cartoonSettings(width);
      CartoonKit whole(settings, scale, {smoke(30.0f)}), covered(settings, scale, {smoke(30.0f)});
      const media::Particle before = test::sphereAt({0.0f, 0.0f, -6.0f}, 1.4f);
      covered.layers->setCoverage(media::coverage(covered.camera.frame(kSize), std::span(&before, 1)),
                                  media::Style::kCartoon, width);
      covered.draw(std::span(&before, 1));
      const media::Particle p = test::sphereAt({0.0f, 0.0f, -6.0f}, 0.5f);
      const media::PixelBox box = media::coverage(covered.camera.frame(kSize), std::span(&p, 1));
      EXPECT_LT((box.x1 - box.x0) * (box.y1 - box.y0), kSize * kSize / 6);  // 12 % of the frame
      covered.layers->setCoverage(box, media::Style::kCartoon, width);
      EXPECT_EQ(covered.draw(std::span(&p, 1)), whole.draw(std::span(&p, 1))) << scale << " " << width;
    }
  }
}

// Band k of the fire draws the photoreal renderer's own black-body colour at the band's centre
// temperature: five fire spheres, one below the cool end, three inside bands 0, 1, 2 and one above
// the hot end. The reference colour is the photoreal layer's M / alpha at a sphere's centre.
// Fire that is its particles' own temperature: dense, no detail, no range, no burn.
media::Material plainFire() {
  media::Material fire = media::fireMaterial();
  fire.density = 3.0f;
  fire.temperatureRange = 0.0f;
  fire.burn = 0.0f;
  fire.detail = 0.0f;
  return fire;
}

// Five fire spheres in a row across the frame, at `temperatures`.
std::vector<media::Particle> fireRow(const float (&temperatures)[5]) {
  std::vector<media::Particle> ps;
  for (int i = 0; i < 5; ++i) {
    media::Particle p = test::sphereAt({-4.0f + 2.0f * static_cast<float>(i), 0.0f, -12.0f}, 0.9f);
    p.temperature = temperatures[i];
    ps.push_back(p);
  }
  return ps;
}

TEST_F(CartoonMedia, FireBandsAreTheBlackBodyColourAtEachBandsCentre) {
  const media::Material fire = plainFire();
  media::Settings settings = cartoonSettings(2.0f);
  settings.cartoon.coolKelvin = 1400.0f;
  settings.cartoon.hotKelvin = 3200.0f;
  settings.cartoon.fireColors.clear();  // black-body bands
  settings.cartoon.fireBands = 3;       // [1400, 2000), [2000, 2600), [2600, 3200]: centres 1700, 2300, 2900
  settings.exposure = 0.7f;
  CartoonKit kit(settings, 1.0f, {fire});
  const float temperatures[5] = {1000.0f, 1600.0f, 2450.0f, 2650.0f, 6000.0f};
  const int band[5] = {0, 0, 1, 2, 2};
  const std::vector<media::Particle> ps = fireRow(temperatures);
  const auto px = kit.draw(ps);

  media::Settings photoreal = settings;
  photoreal.style = media::Style::kPhotoreal;
  auto reference = media::Renderer::create(photoreal);
  ASSERT_OK(reference);
  ASSERT_TRUE((*reference)->setMaterials({fire}).ok());
  test::MediaTarget t(33);
  Camera narrow;
  narrow.fovDegrees = 5.0f;
  for (int i = 0; i < 5; ++i) {
    SCOPED_TRACE("sphere " + std::to_string(i) + " at " + std::to_string(temperatures[i]) + " K");
    media::Particle centre = test::sphereAt({0.0f, 0.0f, -12.0f}, 0.9f);
    centre.temperature = 1700.0f + 600.0f * static_cast<float>(band[i]);
    t.clear({0, 0, 0, 1});
    t.bind();
    (*reference)->draw(narrow.frame(33), std::span(&centre, 1), media::Method::kSpherical, t.depth.get());
    const glm::vec4 m = t.read()[16 * 33 + 16];
    const glm::vec3 expected = glm::vec3(m) / (1.0f - m.a);
    // The sphere's centre pixel in the cartoon frame: project it.
    const glm::vec4 clip =
        kit.camera.frame(kSize).projection * glm::vec4(ps[static_cast<std::size_t>(i)].position, 1.0f);
    const int x = static_cast<int>((clip.x / clip.w * 0.5f + 0.5f) * kSize), y = kSize / 2;
    const glm::vec4 got = px[static_cast<std::size_t>(y) * kSize + x];
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 2e-3 * std::max(1.0f, expected[c])) << c;
  }
  // The bands differ from each other: band 2 is brighter than band 0 (hotter is brighter).
  EXPECT_GT(kit.cartoon.fireColors[2].g, kit.cartoon.fireColors[0].g * 2.0f);
}

// With a palette (the default), band k draws the artist's colour: the palette lists the core first,
// so the hottest band draws the first colour, decoded from its display value and times the
// exposure; temperatures below and above the range take the end bands. Four bands, at three
// exposures.
TEST_F(CartoonMedia, FireBandsDrawThePalettesColoursCoreFirst) {
  const media::Material fire = plainFire();
  const std::vector<glm::vec3> palette = {
      {1.0f, 0.95f, 0.6f}, {1.0f, 0.7f, 0.2f}, {0.9f, 0.35f, 0.1f}, {0.5f, 0.1f, 0.05f}};
  for (const float exposure : {0.5f, 1.0f, 1.5f}) {
    SCOPED_TRACE("exposure " + std::to_string(exposure));
    media::Settings settings = cartoonSettings(2.0f);
    settings.cartoon.coolKelvin = 1000.0f;
    settings.cartoon.hotKelvin = 3000.0f;  // bands [1000, 1500), [1500, 2000), [2000, 2500), [2500, 3000]
    settings.cartoon.fireColors = palette;
    settings.exposure = exposure;
    CartoonKit kit(settings, 1.0f, {fire});
    const float temperatures[5] = {500.0f, 1700.0f, 2200.0f, 2700.0f, 9000.0f};
    const int band[5] = {0, 1, 2, 3, 3};  // the coolest first
    const std::vector<media::Particle> ps = fireRow(temperatures);
    const auto px = kit.draw(ps);
    for (int i = 0; i < 5; ++i) {
      SCOPED_TRACE("sphere " + std::to_string(i));
      const glm::vec3 expected = core::srgbToLinear(palette[static_cast<std::size_t>(3 - band[i])]) * exposure;
      const glm::vec4 clip =
          kit.camera.frame(kSize).projection * glm::vec4(ps[static_cast<std::size_t>(i)].position, 1.0f);
      const int x = static_cast<int>((clip.x / clip.w * 0.5f + 0.5f) * kSize), y = kSize / 2;
      const glm::vec4 got = px[static_cast<std::size_t>(y) * kSize + x];
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 2e-3 * std::max(1.0f, expected[c])) << c;
    }
  }
}

// Where fire is most of what is seen it is drawn as fire, elsewhere as smoke: a fire sphere just in
// front of a smoke sphere, the fire's own opacity at the centre pixel 0.62 (the fire's share of A
// about 0.62 / (0.62 + 0.38) with the smoke opaque behind) and 0.38 (share about 0.38).
TEST_F(CartoonMedia, WhereFireIsMostOfWhatIsSeenItIsDrawnAsFire) {
  media::Material fire = media::fireMaterial();
  fire.temperatureRange = 0.0f;
  fire.burn = 0.0f;
  fire.detail = 0.0f;
  const media::Settings settings = cartoonSettings(2.0f);
  for (double share : {0.62, 0.38}) {
    SCOPED_TRACE("the fire's opacity " + std::to_string(share));
    // 1 - exp(-tau 2 r) = share at the centre (r = 1).
    fire.density = static_cast<float>(-std::log(1.0 - share) / 2.0);
    CartoonKit kit(settings, 1.0f, {fire, smoke(8.0f)});
    media::Particle front = test::sphereAt({0.0f, 0.0f, -7.0f}, 1.0f), back = test::sphereAt({0.0f, 0.0f, -9.5f}, 1.5f);
    front.material = 0;
    front.temperature = 2200.0f;  // band 1 of [1400, 3000] / 3
    back.material = 1;
    const media::Particle ps[2] = {back, front};
    const auto px = kit.draw(ps);
    const glm::vec4 centre = px[static_cast<std::size_t>(kSize / 2) * kSize + kSize / 2];
    const glm::vec3 fireColour = kit.cartoon.fireColors[1];
    const glm::vec3 expected = share > 0.5 ? fireColour : kColour;  // the top tier: opaque
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(centre[c], expected[c], 3e-3 * std::max(1.0f, expected[c])) << c;
  }
}

// Two overlapping spheres are one shape: no ink inside their union's iso-line, where each alone
// would have drawn its own outline (Fig. 5's merging).
TEST_F(CartoonMedia, OverlappingParticlesShareOneOutline) {
  const media::Settings settings = cartoonSettings(3.0f);
  const double tau = 0.6;
  CartoonKit kit(settings, 1.0f, {smoke(static_cast<float>(tau))});
  const media::Particle ps[2] = {test::sphereAt({-1.1f, 0.0f, -6.0f}, 1.6f), test::sphereAt({1.1f, 0.2f, -6.0f}, 1.6f)};
  const auto px = kit.draw(ps);
  int inside = 0, inkedInside = 0, inkedOutside = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      double t = 1.0;
      for (const media::Particle& p : ps) {
        const double a = media::sphereOpacity(glm::dvec3(0.0), kit.camera.ray(x, y, kSize), glm::dvec3(p.position),
                                              p.radius, tau, 1e30, kit.camera.nearPlane);
        t *= 1.0 - a;
      }
      const double A = 1.0 - t;
      const glm::dvec2 ak = fillAndInk(px[static_cast<std::size_t>(y) * kSize + x], kColour);
      if (A > settings.cartoon.threshold + 0.05) {
        ++inside;
        if (ak.y > 0.02) ++inkedInside;
      } else if (A < settings.cartoon.threshold - 0.05 && A > 0.0 && ak.y > 0.5) {
        ++inkedOutside;
      }
    }
  }
  EXPECT_GT(inside, 1000);
  EXPECT_EQ(inkedInside, 0);
  EXPECT_GT(inkedOutside, 50);  // the one outline is there
}

// A nearer opaque surface hides both the fill and the ink (the ink lies at the medium's depth), and
// a surface behind the medium does not.
TEST_F(CartoonMedia, ANearerSurfaceHidesTheInkAndAFartherOneDoesNot) {
  const media::Settings settings = cartoonSettings(3.0f);
  CartoonKit kit(settings, 1.0f, {smoke(0.6f)});
  const media::Particle p = test::sphereAt({0.0f, 0.0f, -6.0f}, 2.0f);
  const glm::vec3 pole(0.7f, 0.1f, 0.1f);
  // A pole at 3 (nearer than the sphere's front, 4) over columns 40-49; the rest a wall at 20.
  const auto px = kit.draw(std::span(&p, 1), kit.camera.linear(20.0f), 40, 50, kit.camera.linear(3.0f), pole);
  int poleRows = 0, inkedWall = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 40; x < 50; ++x) {
      const glm::vec4& c = px[static_cast<std::size_t>(y) * kSize + x];
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(c[i], pole[i], 1e-3) << x << "," << y;
      ++poleRows;
    }
    for (int x = 0; x < 36; ++x) inkedWall += fillAndInk(px[static_cast<std::size_t>(y) * kSize + x], kColour).y > 0.9;
  }
  EXPECT_GT(poleRows, 0);
  EXPECT_GT(inkedWall, 30);  // the wall behind the medium shows its ink
}

// An opaque surface through the medium's middle (a wall at the sphere's centre depth over the
// right half) cuts it: what is left in front of the wall is drawn, but the iso-line the cut makes is
// the wall's edge, not the medium's, and gets no ink; the medium's own rim on the left keeps its ink.
TEST_F(CartoonMedia, ASurfaceCuttingTheMediumIsNotInked) {
  const media::Settings settings = cartoonSettings(3.0f);
  CartoonKit kit(settings, 1.0f, {smoke(0.6f)});
  const media::Particle p = test::sphereAt({0.0f, 0.0f, -6.0f}, 2.0f);
  const glm::vec3 wall(0.7f, 0.6f, 0.1f);
  const auto px = kit.draw(std::span(&p, 1), 1.0f, kSize / 2, kSize, kit.camera.linear(6.0f), wall);
  // The medium's own iso-line (uncut): the wall pixels inside it are where the cut's iso-line lies.
  // (Outside it, above and below the disc, the left half's own ink reaches over the wall, rightly.)
  const double rho = isoRadius(kit.camera, 6.0, 2.0, 0.6, settings.cartoon.threshold, kSize);
  int wallInk = 0, wallPixels = 0, leftInk = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const glm::vec4& c = px[static_cast<std::size_t>(y) * kSize + x];
      const bool black = c.r < 0.05f && c.g < 0.05f && c.b < 0.05f;
      const double r = std::hypot(x + 0.5 - kSize / 2.0, y + 0.5 - kSize / 2.0);
      if (x >= kSize / 2 + 1 && r < rho - 1.0) {
        ++wallPixels;
        wallInk += black;
      } else if (x < kSize / 2 - 4) {
        leftInk += black;
      }
    }
  }
  EXPECT_GT(wallPixels, 0);
  EXPECT_EQ(wallInk, 0) << "no ink where the wall cuts the medium";
  EXPECT_GT(leftInk, 100) << "the medium's own rim keeps its ink";
}

// A wall well in front of the medium's centre (over the right half) cuts it deep: where the wall
// leaves it less than the threshold but the medium unclipped is well above it, the cut is whole
// (cartoonCut's ramp ends at threshold + (1 - threshold) / 2), and there the pixel is the bare
// wall: no ink, and no antialiased rim of fill, as a surface's own edge is drawn.
TEST_F(CartoonMedia, WhereASurfaceCutsTheMediumWhollyThePixelIsTheBareSurface) {
  const media::Settings settings = cartoonSettings(3.0f);
  CartoonKit kit(settings, 1.0f, {smoke(0.6f)});
  const media::Particle p = test::sphereAt({0.0f, 0.0f, -6.0f}, 2.0f);
  const glm::vec3 wall(0.7f, 0.6f, 0.1f);
  const auto px = kit.draw(std::span(&p, 1), 1.0f, kSize / 2, kSize, kit.camera.linear(4.8f), wall);
  std::vector<glm::vec4> field(px.size());
  glGetTextureImage(kit.layers->cartoonField(), 0, GL_RGBA, GL_FLOAT,
                    static_cast<GLsizei>(field.size() * sizeof(glm::vec4)), field.data());
  const float theta = settings.cartoon.threshold, whole = theta + 0.5f * (1.0f - theta) + 0.05f;
  int bare = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = kSize / 2 + 1; x < kSize; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * kSize + x;
      if (!(field[i].x < theta && field[i].z > whole)) continue;
      ++bare;
      // (The opaque colour is a half float: 0.7 is stored as 0.6997.)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(px[i][c], wall[c], 1e-3) << x << "," << y << " channel " << c;
    }
  }
  EXPECT_GT(bare, 100);
}

// Outlines off: no ink anywhere; the fill still ends antialiased at the iso-line (its area the disc's).
TEST_F(CartoonMedia, WithoutOutlinesTheFillEndsAtTheIsoLineUninked) {
  const media::Settings settings = cartoonSettings(3.0f, false);
  const double z = 6.0, r = 2.0, tau = 0.6;
  CartoonKit kit(settings, 1.0f, {smoke(static_cast<float>(tau))});
  const media::Particle p = test::sphereAt({0.0f, 0.0f, static_cast<float>(-z)}, static_cast<float>(r));
  const auto px = kit.draw(std::span(&p, 1));
  const double rho = isoRadius(kit.camera, z, r, tau, settings.cartoon.threshold, kSize);
  double inkArea = 0.0, outerArea = 0.0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const glm::dvec2 ak = fillAndInk(px[static_cast<std::size_t>(y) * kSize + x], kColour);
      inkArea += std::abs(ak.y);
      const double s = std::hypot(x + 0.5 - kSize / 2.0, y + 0.5 - kSize / 2.0) - rho;
      if (s > -4.0) outerArea += ak.x;  // only the outer tier reaches the rim
    }
  }
  EXPECT_LT(inkArea, 1.0);
  // The outer tier's fill between rho - 4 and the iso-line: its share times that ring's area.
  const double ring = std::numbers::pi * (rho * rho - (rho - 4.0) * (rho - 4.0));
  EXPECT_NEAR(outerArea / (ring * tierOf(0.36, settings.cartoon)), 1.0, 0.03);
}

// A sphere sliding a fifth of a pixel per frame: every pixel's fill share only rises or only falls,
// its ink share rises and falls at most once (no flicker), and the ink's centroid moves with the
// sphere in a straight line.
TEST_F(CartoonMedia, ASlidingSphereNeverFlickers) {
  media::Settings settings = cartoonSettings(2.0f);
  settings.cartoon.opacityBands = 1;  // one opaque tier: pixel = bg (1 - a - k) + colour a
  CartoonKit kit(settings, 0.5f, {smoke(0.6f)});
  const int frames = 20;
  std::vector<std::vector<glm::dvec2>> seq;
  std::vector<double> centroid;
  const double pixelsPerUnit = kSize / (2.0 * 6.0 * std::tan(glm::radians(20.0)));
  for (int f = 0; f < frames; ++f) {
    const float dx = static_cast<float>(0.2 * f / pixelsPerUnit);
    const media::Particle p = test::sphereAt({dx - 0.3f, 0.1f, -6.0f}, 2.0f);
    const auto px = kit.draw(std::span(&p, 1));
    std::vector<glm::dvec2> shares(px.size());
    double sum = 0.0, sumX = 0.0;
    for (std::size_t i = 0; i < px.size(); ++i) {
      shares[i] = fillAndInk(px[i], kColour);
      sum += shares[i].y;
      sumX += shares[i].y * (static_cast<double>(i % kSize) + 0.5);
    }
    centroid.push_back(sumX / sum);
    seq.push_back(std::move(shares));
  }
  int changing = 0, fillReversals = 0, inkReversals = 0;
  const double noise = 0.02;
  for (std::size_t i = 0; i < seq[0].size(); ++i) {
    for (int which = 0; which < 2; ++which) {
      int direction = 0, turns = 0;
      for (int f = 1; f < frames; ++f) {
        const double d = seq[static_cast<std::size_t>(f)][i][which] - seq[static_cast<std::size_t>(f - 1)][i][which];
        if (std::abs(d) < noise) continue;
        const int s = d > 0 ? 1 : -1;
        if (direction != 0 && s != direction) ++turns;
        direction = s;
      }
      if (direction != 0 && which == 0) ++changing;
      if (which == 0 && turns > 0) ++fillReversals;
      if (which == 1 && turns > 1) ++inkReversals;
    }
  }
  EXPECT_GT(changing, 40);
  EXPECT_EQ(fillReversals, 0);
  EXPECT_EQ(inkReversals, 0);
  // The centroid's path: a straight line (perspective makes the disc's image move a little faster
  // than its centre's, 0.2 px per frame), within a twentieth of a pixel.
  double sf = 0, sc = 0, sff = 0, sfc = 0;
  for (int f = 0; f < frames; ++f) {
    sf += f, sc += centroid[static_cast<std::size_t>(f)], sff += f * f,
        sfc += f * centroid[static_cast<std::size_t>(f)];
  }
  const double slope = (frames * sfc - sf * sc) / (frames * sff - sf * sf), offset = (sc - slope * sf) / frames;
  EXPECT_NEAR(slope, 0.2, 0.03);
  double worstResidual = 0.0;
  for (int f = 0; f < frames; ++f)
    worstResidual = std::max(worstResidual, std::abs(centroid[static_cast<std::size_t>(f)] - offset - slope * f));
  if (std::getenv("PUFF_TEST_VERBOSE"))
    std::printf("centroid slope %.4f px/frame, worst residual %.4f px, %d pixels change\n", slope, worstResidual,
                changing);
  for (int f = 0; f < frames; ++f) EXPECT_NEAR(centroid[static_cast<std::size_t>(f)], offset + slope * f, 0.05) << f;
}

TEST(CartoonStyle, ValidationNamesTheField) {
  media::CartoonStyle s;
  EXPECT_TRUE(media::validate(s));
  auto bad = [](auto change) {
    media::CartoonStyle c;
    change(c);
    auto r = media::validate(c);
    return r ? std::string() : r.error().message;
  };
  EXPECT_EQ(bad([](auto& c) { c.threshold = 1.0f; }), "threshold: expected an opacity in (0, 1), got 1");
  EXPECT_EQ(bad([](auto& c) { c.opacityBands = 0; }), "opacityBands: expected 1 to 8, got 0");
  EXPECT_EQ(bad([](auto& c) { c.fireBands = 9; }), "fireBands: expected 1 to 8, got 9");
  EXPECT_EQ(bad([](auto& c) { c.hotKelvin = 1000.0f; }),
            "hotKelvin: expected kelvin in (coolKelvin 1400, 100000], got 1000");
  EXPECT_EQ(bad([](auto& c) { c.outlineWidth = -1.0f; }), "outlineWidth: expected pixels in [0, 64], got -1");
  EXPECT_EQ(bad([](auto& c) { c.outlineColor.g = 2.0f; }), "outlineColor/1: expected [0, 1], got 2");
  EXPECT_EQ(media::parseStyle("cartoon"), media::Style::kCartoon);
  EXPECT_EQ(media::parseStyle("toon"), std::nullopt);
}

TEST_F(CartoonMedia, RefusedWhereItCannotBeDrawn) {
  media::Settings s = cartoonSettings(2.0f);
  s.cartoon.fireBands = 0;
  auto r = media::Renderer::create(s);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, "cartoon/fireBands: expected 1 to 8, got 0");
  // A host's frame: composeOver refuses a cartoon layer rather than draw it as photoreal.
  auto host = media::HostLayers::create(16, 16, 1.0f);
  ASSERT_OK(host);
  (*host)->beginMedia(media::Style::kCartoon);
  const core::Viewport vp{0, 0, 16, 16};
  auto over = (*host)->composeOver(0, vp, test::MediaCamera{}.frame(16), {}, {});
  ASSERT_FALSE(over);
  EXPECT_NE(over.error().message.find("cartoon style"), std::string::npos) << over.error().message;
}

// The media budget (puffrender --max-error) measures against the photoreal references: it refuses
// a cartoon scene rather than measure the style's distance from them.
TEST(CartoonScene, TheMediaBudgetRefusesACartoonScene) {
  auto s =
      scene::loadScene(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / "explosion-walls-cartoon.json", PUFF_ART_DIR);
  ASSERT_OK(s);
  const int frames[1] = {10};
  auto r = eval::measureMediaBudget(*s, frames);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("/media/style: the media budget measures the layer against the photoreal"),
            std::string::npos)
      << r.error().message;
}

// The scene format: media.style and media.cartoon read, written back and refused with pointers.
TEST(CartoonScene, StyleAndBandsReadWriteAndRefuse) {
  const nlohmann::json base = {
      {"media",
       {{"style", "cartoon"},
        {"cartoon",
         {{"threshold", 0.4}, {"opacityBands", 3}, {"fireBands", 4}, {"coolKelvin", 1200}, {"hotKelvin", 2800}}}}}};
  auto s = scene::parseScene(base, "c.json");
  ASSERT_OK(s);
  const media::Settings& m = s->media->settings;
  EXPECT_EQ(m.style, media::Style::kCartoon);
  EXPECT_FLOAT_EQ(m.cartoon.threshold, 0.4f);
  EXPECT_EQ(m.cartoon.opacityBands, 3);
  EXPECT_EQ(m.cartoon.fireBands, 4);
  EXPECT_TRUE(m.cartoon.fireColors.empty()) << "fireBands alone asks for black-body bands";
  EXPECT_FLOAT_EQ(m.cartoon.coolKelvin, 1200.0f);
  EXPECT_FLOAT_EQ(m.cartoon.hotKelvin, 2800.0f);
  auto again = scene::parseScene(scene::toJson(*s), "c.json");
  ASSERT_OK(again);
  EXPECT_EQ(again->media->settings, m);

  auto refused = [&](const char* pointer, const nlohmann::json& value) {
    nlohmann::json j = base;
    j["media"][nlohmann::json::json_pointer(pointer)] = value;
    auto r = scene::parseScene(j, "c.json");
    return r ? std::string() : r.error().message;
  };
  EXPECT_NE(refused("/style", "toon").find("c.json: /media/style:"), std::string::npos);
  EXPECT_NE(refused("/cartoon/threshold", 1.0).find("/media/cartoon/threshold"), std::string::npos);
  EXPECT_NE(refused("/cartoon/opacityBands", 9).find("/media/cartoon/opacityBands"), std::string::npos);
  EXPECT_NE(refused("/cartoon/hotKelvin", 1000).find("/media/cartoon/hotKelvin"), std::string::npos);
  EXPECT_NE(refused("/cartoon/outlineWidth", 2).find("/media/cartoon/outlineWidth"), std::string::npos);
  // Both values named, and which one is the default.
  nlohmann::json cool = base;
  cool["media"]["cartoon"] = {{"coolKelvin", 4000}};
  auto r = scene::parseScene(cool, "c.json");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message,
            "c.json: /media/cartoon/coolKelvin: hotKelvin (3000, the default) must exceed coolKelvin (4000)");
  // Motion blur would stack whole cartoon frames' outlines: refused, with the way out.
  EXPECT_NE(refused("/motionBlur", {{"frames", 2}}).find("/media/motionBlur: motion blur blends whole frames"),
            std::string::npos);
}

// The fire's palette: the default when nothing is said, read as display colours (arrays or hex),
// written back as the file gave it, "blackbody" for the black body's bands; refused with pointers
// when it is not a palette, holds too many colours, or comes with fireBands.
TEST(CartoonScene, FirePaletteReadsWritesAndRefuses) {
  auto parse = [](const nlohmann::json& cartoon) {
    return scene::parseScene({{"media", {{"style", "cartoon"}, {"cartoon", cartoon}}}}, "c.json");
  };
  auto plain = parse(nlohmann::json::object());
  ASSERT_OK(plain);
  EXPECT_EQ(plain->media->settings.cartoon.fireColors, media::defaultFireColors());
  EXPECT_EQ(media::fireBandCount(plain->media->settings.cartoon), 3);
  auto two = parse({{"fireColors", {"#fff", {1.0, 0.5, 0.0}}}});
  ASSERT_OK(two);
  EXPECT_EQ(two->media->settings.cartoon.fireColors, (std::vector<glm::vec3>{{1, 1, 1}, {1, 0.5f, 0}}));
  EXPECT_EQ(media::fireBandCount(two->media->settings.cartoon), 2);
  auto black = parse({{"fireColors", "blackbody"}, {"fireBands", 5}});
  ASSERT_OK(black);
  EXPECT_TRUE(black->media->settings.cartoon.fireColors.empty());
  EXPECT_EQ(media::fireBandCount(black->media->settings.cartoon), 5);
  for (const auto* s : {&*plain, &*two, &*black}) {
    auto again = scene::parseScene(scene::toJson(*s), "c.json");
    ASSERT_OK(again);
    EXPECT_EQ(again->media->settings.cartoon, s->media->settings.cartoon);
  }
  auto refused = [&](const nlohmann::json& cartoon) {
    auto r = parse(cartoon);
    return r ? std::string() : r.error().message;
  };
  EXPECT_NE(refused({{"fireColors", "plasma"}}).find("c.json: /media/cartoon/fireColors: expected \"blackbody\""),
            std::string::npos);
  EXPECT_NE(refused({{"fireColors", nlohmann::json::array()}}).find("/media/cartoon/fireColors"), std::string::npos);
  EXPECT_NE(refused({{"fireColors", std::vector<std::string>(9, "#f80")}}).find("/media/cartoon/fireColors"),
            std::string::npos);
  EXPECT_NE(refused({{"fireColors", {"#f80", "orange"}}}).find("/media/cartoon/fireColors/1"), std::string::npos);
  EXPECT_NE(refused({{"fireColors", {"#f80"}}, {"fireBands", 2}})
                .find("/media/cartoon/fireBands: counts black-body bands; with a fireColors palette"),
            std::string::npos);
}

}  // namespace
}  // namespace puff::media_cartoon
