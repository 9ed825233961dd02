// A host whose framebuffer has more colour attachments than the one Puff draws into (a G-buffer, a
// velocity target): every Puff pass writes attachment 0 alone. The host's other attachments keep
// their contents to the bit, its draw buffers and their write masks stay as it set them, and
// attachment 0 holds exactly what a framebuffer of one attachment gets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <glm/common.hpp>
#include <glm/gtc/quaternion.hpp>

#include <puff/cel/volume_clip.h>
#include <puff/core/colour.h>
#include <puff/media/coverage.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>

#include "host_state_fixture.h"
#include "support/sphere_bake.h"
#include "support/temp_dir.h"

namespace puff::host_state_test {
namespace {

constexpr int kExtra = 2;  // the host's attachments past Puff's: 1 and 2

float largest(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

// The media frame of a cel frame: the same camera and planes, the fixture's size.
media::Frame mediaFrameOf(const cel::Frame& cel) {
  media::Frame f;
  f.view = cel.view;
  f.projection = cel.projection;
  f.nearPlane = cel.nearPlane;
  f.farPlane = cel.farPlane;
  f.viewport.width = f.viewport.height = kPx;
  return f;
}

// The host's framebuffer: attachment 0 scene-linear RGBA16F (Puff's), then `extra` RGBA8
// attachments filled with a pattern, and a depth-stencil texture (media reads it as the host's depth).
class HostFramebuffer {
 public:
  explicit HostFramebuffer(int extra) : fbo_(core::makeFramebuffer()), depth_(core::makeTexture(GL_TEXTURE_2D)) {
    colour_.push_back(core::makeTexture(GL_TEXTURE_2D));
    glTextureStorage2D(colour_[0].get(), 1, GL_RGBA16F, kPx, kPx);
    for (int i = 0; i < extra; ++i) {
      colour_.push_back(core::makeTexture(GL_TEXTURE_2D));
      glTextureStorage2D(colour_.back().get(), 1, GL_RGBA8, kPx, kPx);
    }
    glTextureStorage2D(depth_.get(), 1, GL_DEPTH24_STENCIL8, kPx, kPx);
    std::vector<GLenum> buffers;
    for (std::size_t i = 0; i < colour_.size(); ++i) {
      glNamedFramebufferTexture(fbo_.get(), GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i), colour_[i].get(), 0);
      buffers.push_back(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
    }
    glNamedFramebufferTexture(fbo_.get(), GL_DEPTH_STENCIL_ATTACHMENT, depth_.get(), 0);
    glNamedFramebufferDrawBuffers(fbo_.get(), static_cast<GLsizei>(buffers.size()), buffers.data());
  }

  bool complete() const { return glCheckNamedFramebufferStatus(fbo_.get(), GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE; }
  GLuint framebuffer() const { return fbo_.get(); }
  GLuint depth() const { return depth_.get(); }

  // The host's frame start: its G-buffer cleared (attachment 0 to the sky, the others to their
  // pattern), depth to 1 and stencil to 0; bound, with write masks of its own on the other
  // attachments (green and alpha of 1, red and blue of 2) and blending on for attachment 2.
  void begin() const {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.get());
    glViewport(0, 0, kPx, kPx);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glStencilMask(0xFF);
    const float sky[4] = {0.2f, 0.3f, 0.5f, 1.0f};
    glClearNamedFramebufferfv(fbo_.get(), GL_COLOR, 0, sky);
    glClearNamedFramebufferfi(fbo_.get(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
    for (std::size_t i = 1; i < colour_.size(); ++i) {
      const std::vector<std::uint8_t> p = pattern(static_cast<int>(i));
      glTextureSubImage2D(colour_[i].get(), 0, 0, 0, kPx, kPx, GL_RGBA, GL_UNSIGNED_BYTE, p.data());
    }
    if (colour_.size() > 2) {
      glColorMaski(1, GL_FALSE, GL_TRUE, GL_FALSE, GL_TRUE);
      glColorMaski(2, GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
      glEnablei(GL_BLEND, 2);
    }
  }

  // Attachment `i`'s pattern: bytes that no pass of Puff's would write by chance.
  static std::vector<std::uint8_t> pattern(int i) {
    std::vector<std::uint8_t> p(static_cast<std::size_t>(kPx) * kPx * 4);
    for (std::size_t k = 0; k < p.size(); ++k)
      p[k] = static_cast<std::uint8_t>(((k + 1) * 2654435761u * static_cast<unsigned>(i)) >> 24);
    return p;
  }
  std::vector<std::uint8_t> bytes(int i) const {
    std::vector<std::uint8_t> p(static_cast<std::size_t>(kPx) * kPx * 4);
    glGetTextureImage(colour_[static_cast<std::size_t>(i)].get(), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                      static_cast<GLsizei>(p.size()), p.data());
    return p;
  }
  std::vector<glm::vec4> floats0() const {
    std::vector<glm::vec4> p(static_cast<std::size_t>(kPx) * kPx);
    glGetTextureImage(colour_[0].get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(p.size() * sizeof(glm::vec4)),
                      p.data());
    return p;
  }
  std::vector<std::uint16_t> halfs0() const {
    std::vector<std::uint16_t> p(static_cast<std::size_t>(kPx) * kPx * 4);
    glGetTextureImage(colour_[0].get(), 0, GL_RGBA, GL_HALF_FLOAT, static_cast<GLsizei>(p.size() * 2), p.data());
    return p;
  }

 private:
  core::Framebuffer fbo_;
  std::vector<core::Texture> colour_;
  core::Texture depth_;
};

class HostTargets : public test::SphereAtlasTest {
 protected:
  // The sphere's one-view atlas (the suite's) and a 4 x 4-view bake of it for oriented puffs.
  static void SetUpTestSuite() {
    setUpSphereAtlas(true);
    views_.emplace("puff_host_targets_views");
    auto sidecar = test::bakeSphereAtlas(views_->path(), 4);
    ASSERT_OK(sidecar);
    auto atlas = core::loadAtlas(*sidecar);
    ASSERT_OK(atlas);
    viewsAtlas_ = std::make_unique<core::Atlas>(std::move(*atlas));
  }
  static void TearDownTestSuite() {
    viewsAtlas_.reset();
    views_.reset();
    SphereAtlasTest::TearDownTestSuite();
  }
  void TearDown() override {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDisable(GL_BLEND);
    SphereAtlasTest::TearDown();
  }

  // Draws `draw` into the host's framebuffer with and without the extra attachments.
  // `setsMasksBelow`: the draw buffers whose write masks and blending the calls' headers say they
  // leave on and off (1: draw buffer 0 alone; the media layer's begin and draw set 0-1, or 0-3 in the
  // cartoon style, on Puff's own framebuffer, global state): the host's own are checked above it.
  void expectOnlyAttachmentZero(const std::string& what, const std::function<void(const HostFramebuffer&)>& draw,
                                bool drawsSomething = true, unsigned setsMasksBelow = 1) {
    SCOPED_TRACE(what);
    HostFramebuffer one(0), gbuffer(kExtra), blank(0);
    ASSERT_TRUE(one.complete());
    ASSERT_TRUE(gbuffer.complete());
    blank.begin();
    one.begin();
    draw(one);
    gbuffer.begin();
    draw(gbuffer);
    EXPECT_EQ(core::drainGlErrors(), "");
    for (int i = 1; i <= kExtra; ++i)
      EXPECT_TRUE(gbuffer.bytes(i) == HostFramebuffer::pattern(i)) << "attachment " << i << " was written";
    EXPECT_TRUE(gbuffer.halfs0() == one.halfs0()) << "attachment 0 differs from a one-attachment framebuffer's";
    if (drawsSomething) {
      EXPECT_NE(gbuffer.halfs0(), blank.halfs0()) << "nothing was drawn";
    }
    glBindFramebuffer(GL_FRAMEBUFFER, gbuffer.framebuffer());
    for (int i = 0; i <= kExtra; ++i)
      EXPECT_EQ(geti(GL_DRAW_BUFFER0 + static_cast<GLenum>(i)), static_cast<GLint>(GL_COLOR_ATTACHMENT0 + i))
          << "draw buffer " << i;
    for (const auto& [i, host, blends] : {std::tuple{1u, "0 1 0 1", false}, std::tuple{2u, "1 0 1 0", true}}) {
      GLboolean mask[4];
      glGetBooleani_v(GL_COLOR_WRITEMASK, i, mask);
      const bool puffs = i < setsMasksBelow;
      EXPECT_EQ(ints({mask[0], mask[1], mask[2], mask[3]}), puffs ? "1 1 1 1" : host)
          << "write mask of attachment " << i;
      EXPECT_EQ(glIsEnabledi(GL_BLEND, i) == GL_TRUE, !puffs && blends) << "blending of attachment " << i;
    }
  }

  // A cel frame as a host draws it (shadow_map.h, nailboards.h): opaque objects and puffs, shadows
  // by `method`.
  static void celFrame(const CelKit& kit, cel::Style style, const std::vector<cel::Particle>& particles,
                       const HostFramebuffer& target) {
    cel::Frame frame = eyeFrame();
    kit.nailboards->upload(particles);
    cel::Bounds receivers = cel::particleBounds(particles);
    for (std::size_t i = 0; i < kit.opaque->count(); ++i) receivers.add(kit.opaque->worldBounds(i));
    kit.ramp->bind(kit.b);
    if (style.shadowMethod == cel::ShadowMethod::kMap) {
      kit.shadowMap->prepare(frame, receivers, style);
      kit.shadowMap->beginCasters();
      kit.nailboards->drawShadowCasters(style, frame);
      kit.opaque->drawCasters();
      glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
      glViewport(0, 0, kPx, kPx);
      frame.shadow = kit.shadowMap->lookup();
      kit.shadowMap->bind();
    }
    EXPECT_OK(kit.block->upload(frame));
    kit.opaque->draw(cel::ShadePass::kLit);
    kit.nailboards->drawNailboards(style, cel::ShadePass::kLit);
    if (style.shadowMethod == cel::ShadowMethod::kVolumes) {
      const cel::VolumeClip clip = cel::volumeClip(frame, receivers);
      kit.nailboards->drawShadowVolumes(style, glm::vec4(0, 1, 0, 0), clip);
      kit.opaque->drawShadowVolumes(style, glm::vec4(0, 1, 0, 0), clip);
      kit.opaque->draw(cel::ShadePass::kShadowed);
      kit.nailboards->drawNailboards(style, cel::ShadePass::kShadowed);
    }
  }

  static inline std::optional<test::ScopedTempDir> views_;
  static inline std::unique_ptr<core::Atlas> viewsAtlas_;
};

TEST_F(HostTargets, CelPassesWriteAttachmentZeroAlone) {
  CelKit kit(*atlas_);
  for (const cel::ShadowMethod method : {cel::ShadowMethod::kMap, cel::ShadowMethod::kVolumes}) {
    cel::Style style;
    style.shadowMethod = method;
    expectOnlyAttachmentZero(method == cel::ShadowMethod::kMap ? "map" : "volumes",
                             [&](const HostFramebuffer& t) { celFrame(kit, style, puffs(), t); });
  }
  cel::Style floor;
  expectOnlyAttachmentZero("the fill-rate floor", [&](const HostFramebuffer&) {
    EXPECT_OK(kit.block->upload(eyeFrame()));
    kit.nailboards->drawBaseline(floor);
  });
}

TEST_F(HostTargets, OrientedPuffsWriteAttachmentZeroAlone) {
  ASSERT_NE(viewsAtlas_, nullptr);
  CelKit kit(*viewsAtlas_);
  std::vector<cel::Particle> tumbling = puffs();
  for (std::size_t i = 0; i < tumbling.size(); ++i) {
    tumbling[i].oriented = true;
    tumbling[i].orientation =
        glm::angleAxis(0.7f + 0.9f * static_cast<float>(i), glm::normalize(glm::vec3(1, 2, 0.5f)));
  }
  for (const cel::TumbleMethod tumble : {cel::TumbleMethod::kHull, cel::TumbleMethod::kBlend}) {
    cel::Style style;
    style.tumble = tumble;
    expectOnlyAttachmentZero(tumble == cel::TumbleMethod::kHull ? "hull" : "blend",
                             [&](const HostFramebuffer& t) { celFrame(kit, style, tumbling, t); });
  }
}

// The media over the host's frame, photoreal and cartoon: its depth resolved from the host's
// texture, the layer composed over attachment 0 (dual-source blending, which allows one draw buffer
// on most GPUs), over the whole frame, over the media's coverage, and with an empty coverage.
TEST_F(HostTargets, MediaComposeOverWritesAttachmentZeroAlone) {
  CelKit kit(*atlas_);
  media::Settings cartoonSettings;
  cartoonSettings.style = media::Style::kCartoon;
  auto photoreal = media::Renderer::create(), cartoonRenderer = media::Renderer::create(cartoonSettings);
  ASSERT_OK(photoreal);
  ASSERT_OK(cartoonRenderer);
  auto cartoon = media::cartoonCompose(cartoonSettings);
  ASSERT_OK(cartoon);
  const cel::Frame cel = eyeFrame();
  const media::Frame f = mediaFrameOf(cel);
  std::vector<media::Particle> smoke(3);
  for (std::size_t i = 0; i < smoke.size(); ++i) {
    smoke[i].position = glm::vec3(-0.8f + 0.8f * static_cast<float>(i), 0.8f, 0.5f);
    smoke[i].radius = 0.9f;
  }
  enum class Cover { kWhole, kMedia, kEmpty };
  for (const media::Style style : {media::Style::kPhotoreal, media::Style::kCartoon}) {
    const bool isCartoon = style == media::Style::kCartoon;
    for (const Cover cover : {Cover::kWhole, Cover::kMedia, Cover::kEmpty}) {
      const std::string what =
          std::string(isCartoon ? "cartoon" : "photoreal") + (cover == Cover::kWhole   ? ", whole frame"
                                                              : cover == Cover::kMedia ? ", over its coverage"
                                                                                       : ", empty coverage");
      expectOnlyAttachmentZero(
          what,
          [&](const HostFramebuffer& t) {
            celFrame(kit, cel::Style{}, puffs(), t);
            auto layers = media::HostLayers::create(kPx, kPx, 0.5f);
            ASSERT_OK(layers);
            const media::HostDepth depth{.texture = t.depth()};
            const float ink = isCartoon ? cartoon->style.outlineWidth : 0.0f;
            if (cover == Cover::kMedia) (*layers)->setCoverage(media::coverage(f, smoke), style, ink);
            if (cover == Cover::kEmpty) (*layers)->setCoverage(media::PixelBox{}, style, ink);
            ASSERT_OK((*layers)->resolveHostDepth(depth, cel));
            (*layers)->beginMedia(style);
            (isCartoon ? *cartoonRenderer : *photoreal)
                ->draw((*layers)->layerFrame(f), smoke, media::Method::kSpherical, (*layers)->mediaDepth());
            ASSERT_OK(
                (*layers)->composeOver(t.framebuffer(), {0, 0, kPx, kPx}, f, {}, {}, isCartoon ? &*cartoon : nullptr));
          },
          cover != Cover::kEmpty, isCartoon ? 4u : 2u);
    }
  }
}

// A gamma-space host: its colour attachment RGBA8 holding display values, which its own passes
// write as they are. Puff draws into a GL_SRGB8_ALPHA8 view of the same texture with
// GL_FRAMEBUFFER_SRGB on (docs/embedding.md, "Gamma-space hosts"): GL encodes Puff's scene-linear
// colour as it stores it and decodes what it blends over, and the host keeps drawing into the RGBA8
// texture itself. The frame (a cel frame, then the photoreal media composed over it) comes within
// 3/255 of a float host's, encoded once at the end.
TEST_F(HostTargets, AGammaSpaceHostDrawsThroughAnSrgbView) {
  CelKit kit(*atlas_);
  auto renderer = media::Renderer::create();
  ASSERT_OK(renderer);
  const cel::Frame cel = eyeFrame();
  const media::Frame f = mediaFrameOf(cel);
  std::vector<media::Particle> smoke(2);
  smoke[0].position = glm::vec3(-0.5f, 0.8f, 0.5f);
  smoke[1].position = glm::vec3(0.6f, 0.6f, 0.8f);
  for (media::Particle& p : smoke) p.radius = 0.9f;
  // The host's sky, a display value: stored as it is in RGBA8, decoded in the float host.
  const glm::vec3 skyDisplay(0.45f, 0.62f, 0.85f);
  core::Texture depth = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(depth.get(), 1, GL_DEPTH24_STENCIL8, kPx, kPx);

  // Draws the frame into `colour` (bound through `fbo`); `clear` is the sky as the target stores it.
  const auto frame = [&](GLuint fbo, const glm::vec4& clear) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, kPx, kPx);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glStencilMask(0xFF);
    glDisable(GL_SCISSOR_TEST);
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &clear.x);
    glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
    kit.ramp->bind(kit.b);
    EXPECT_OK(kit.block->upload(cel));
    kit.nailboards->upload(puffs());
    kit.opaque->draw(cel::ShadePass::kLit);
    kit.nailboards->drawNailboards(cel::Style{}, cel::ShadePass::kLit);
    auto layers = media::HostLayers::create(kPx, kPx, 0.5f);
    ASSERT_OK(layers);
    const media::HostDepth d{.texture = depth.get()};
    ASSERT_OK((*layers)->resolveHostDepth(d, cel));
    (*layers)->beginMedia();
    (*renderer)->draw((*layers)->layerFrame(f), smoke, media::Method::kSpherical, (*layers)->mediaDepth());
    ASSERT_OK((*layers)->composeOver(fbo, {0, 0, kPx, kPx}, f, {}, {}));
  };
  const auto framebuffer = [&](GLuint colour) {
    core::Framebuffer fbo = core::makeFramebuffer();
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, colour, 0);
    glNamedFramebufferTexture(fbo.get(), GL_DEPTH_STENCIL_ATTACHMENT, depth.get(), 0);
    EXPECT_EQ(glCheckNamedFramebufferStatus(fbo.get(), GL_FRAMEBUFFER), static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE));
    return fbo;
  };

  // The float host: scene-linear RGBA16F, encoded to display values at the end.
  core::Texture linear = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(linear.get(), 1, GL_RGBA16F, kPx, kPx);
  const core::Framebuffer linearFbo = framebuffer(linear.get());
  frame(linearFbo.get(), glm::vec4(core::srgbToLinear(skyDisplay), 1.0f));
  std::vector<glm::vec4> floatHost(static_cast<std::size_t>(kPx) * kPx);
  glGetTextureImage(linear.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(floatHost.size() * sizeof(glm::vec4)),
                    floatHost.data());

  // The gamma-space host: RGBA8 (immutable, so a view can be made), Puff through the sRGB view.
  core::Texture display = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(display.get(), 1, GL_RGBA8, kPx, kPx);
  GLuint view = 0;
  glGenTextures(1, &view);
  glTextureView(view, GL_TEXTURE_2D, display.get(), GL_SRGB8_ALPHA8, 0, 1, 0, 1);
  {
    const core::Framebuffer srgbFbo = framebuffer(view);
    glEnable(GL_FRAMEBUFFER_SRGB);
    // The clear goes through the view too: GL encodes the scene-linear sky into the display value.
    frame(srgbFbo.get(), glm::vec4(core::srgbToLinear(skyDisplay), 1.0f));
    glDisable(GL_FRAMEBUFFER_SRGB);
  }
  glDeleteTextures(1, &view);
  std::vector<std::uint8_t> gammaHost(static_cast<std::size_t>(kPx) * kPx * 4);
  glGetTextureImage(display.get(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(gammaHost.size()),
                    gammaHost.data());
  EXPECT_EQ(core::drainGlErrors(), "");

  float worst = 0.0f;
  int puffPixels = 0;
  for (std::size_t i = 0; i < floatHost.size(); ++i) {
    const glm::vec3 want = core::linearToSrgb(glm::clamp(glm::vec3(floatHost[i]), 0.0f, 1.0f));
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(gammaHost[i * 4 + c] / 255.0f - want[c]));
    if (glm::length(want - skyDisplay) > 0.05f) ++puffPixels;
  }
  std::printf("gamma-space host through an sRGB view: worst %.2f/255 from the float host, %d of %d pixels not sky\n",
              worst * 255.0f, puffPixels, kPx * kPx);
  EXPECT_LE(worst * 255.0f, 3.0f) << "the gamma-space host's frame against the float host's, display units";
  EXPECT_GT(puffPixels, kPx * kPx / 10) << "the frame holds puffs, ground and smoke, not only sky";
}

// Cartoon fire over a host's frame (HostLayers::composeOver with a CartoonCompose) against Puff's
// own compose of the same scene and media (Layers::compose): the opaque objects (the ground, a wall)
// drawn with linear depth both ways, the cartoon layer composed over them. (Not the nailboards:
// Puff's own opaque target is a 1-sample multisample one, where their edges take alpha to coverage.) Pixels whose
// opaque scene differs between Puff's 1-sample multisample target and the host's single-sample one (geometry edges) are
// left out.
TEST_F(HostTargets, CartoonComposeOverMatchesPuffsOwnCompose) {
  CelKit kit(*atlas_);
  media::Settings settings;
  settings.style = media::Style::kCartoon;
  auto renderer = media::Renderer::create(settings);
  ASSERT_OK(renderer);
  ASSERT_TRUE((*renderer)->setMaterials({media::fireMaterial(), media::smokeMaterial()}).ok());
  auto cartoon = media::cartoonCompose(settings);
  ASSERT_OK(cartoon);
  cel::Frame cel = eyeFrame();
  cel.depth = cel::DepthConvention::kLinear;
  const media::Frame f = mediaFrameOf(cel);
  std::vector<media::Particle> fire(5);
  for (std::size_t i = 0; i < fire.size(); ++i) {
    fire[i].position = glm::vec3(-1.0f + 0.5f * static_cast<float>(i), 0.5f + 0.15f * static_cast<float>(i), 1.0f);
    fire[i].radius = 0.9f;
    fire[i].material = i % 2 == 0 ? 0u : 1u;
    fire[i].seed = static_cast<std::uint32_t>(i);
  }
  const glm::vec4 sky(0.2f, 0.3f, 0.5f, 1.0f);  // HostFramebuffer::begin's, scene-linear
  const core::Viewport vp{0, 0, kPx, kPx};
  const auto scene = [&] {
    kit.ramp->bind(kit.b);
    EXPECT_OK(kit.block->upload(cel));
    kit.opaque->draw(cel::ShadePass::kLit);
  };

  // Puff's own: the scene into Layers' opaque target, the layer composed into an RGBA16F target.
  auto own = media::Layers::create(kPx, kPx, 1, 0.5f);
  ASSERT_OK(own);
  const GLuint opaqueFbo = (*own)->opaqueFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, opaqueFbo);
  glViewport(0, 0, kPx, kPx);
  glClearNamedFramebufferfv(opaqueFbo, GL_COLOR, 0, &sky.x);
  glClearNamedFramebufferfi(opaqueFbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
  scene();
  (*own)->resolveOpaque();
  std::vector<glm::vec4> ownOpaque(static_cast<std::size_t>(kPx) * kPx);
  glGetTextureImage((*own)->opaqueColor(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(ownOpaque.size() * 16),
                    ownOpaque.data());
  (*own)->beginMedia(media::Style::kCartoon);
  (*renderer)->draw((*own)->layerFrame(f), fire, media::Method::kSpherical, (*own)->mediaDepth());
  HostFramebuffer ownOut(0);
  (*own)->compose(ownOut.framebuffer(), vp, f, {}, {}, &*cartoon);
  const std::vector<glm::vec4> ownFrame = ownOut.floats0();

  // The host's: its frame holds the scene; the layer composed over it, with and without a coverage.
  const auto hostFrame = [&](bool media, bool covered) {
    HostFramebuffer host(0);
    host.begin();
    scene();
    if (media) {
      auto layers = media::HostLayers::create(kPx, kPx, 0.5f);
      EXPECT_OK(layers);
      if (covered)
        (*layers)->setCoverage(media::coverage(f, fire), media::Style::kCartoon, cartoon->style.outlineWidth);
      const media::HostDepth d{.texture = host.depth()};
      EXPECT_OK((*layers)->resolveHostDepth(d, cel));
      (*layers)->beginMedia(media::Style::kCartoon);
      (*renderer)->draw((*layers)->layerFrame(f), fire, media::Method::kSpherical, (*layers)->mediaDepth());
      EXPECT_OK((*layers)->composeOver(host.framebuffer(), vp, f, {}, {}, &*cartoon));
    }
    return host.floats0();
  };
  const std::vector<glm::vec4> plain = hostFrame(false, false), host = hostFrame(true, false);
  EXPECT_TRUE(hostFrame(true, true) == host) << "over the media's coverage, the same frame to the bit";

  // A 4-sample host: its scene multisampled, the layer composed over every sample (resolveHostDepth
  // keeps each pixel's nearest), resolved by the host. Away from the geometry's edges, where the
  // samples agree, it is the single-sample host's frame.
  const auto multisampledFrame = [&](bool media) {
    const int samples = 4;
    core::Texture colour = core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE),
                  depth = core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE);
    glTextureStorage2DMultisample(colour.get(), samples, GL_RGBA16F, kPx, kPx, GL_TRUE);
    glTextureStorage2DMultisample(depth.get(), samples, GL_DEPTH24_STENCIL8, kPx, kPx, GL_TRUE);
    const core::Framebuffer fbo = core::makeFramebuffer();
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, colour.get(), 0);
    glNamedFramebufferTexture(fbo.get(), GL_DEPTH_STENCIL_ATTACHMENT, depth.get(), 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.get());
    glViewport(0, 0, kPx, kPx);
    glClearNamedFramebufferfv(fbo.get(), GL_COLOR, 0, &sky.x);
    glClearNamedFramebufferfi(fbo.get(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
    scene();
    if (media) {
      auto layers = media::HostLayers::create(kPx, kPx, 0.5f);
      EXPECT_OK(layers);
      const media::HostDepth d{.texture = depth.get()};
      EXPECT_OK((*layers)->resolveHostDepth(d, cel));
      (*layers)->beginMedia(media::Style::kCartoon);
      (*renderer)->draw((*layers)->layerFrame(f), fire, media::Method::kSpherical, (*layers)->mediaDepth());
      EXPECT_OK((*layers)->composeOver(fbo.get(), vp, f, {}, {}, &*cartoon));
    }
    HostFramebuffer resolved(0);
    glBlitNamedFramebuffer(fbo.get(), resolved.framebuffer(), 0, 0, kPx, kPx, 0, 0, kPx, kPx, GL_COLOR_BUFFER_BIT,
                           GL_NEAREST);
    return resolved.floats0();
  };
  const std::vector<glm::vec4> msPlain = multisampledFrame(false), ms = multisampledFrame(true);
  int msCompared = 0, msClose = 0;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    if (largest(glm::abs(glm::vec3(msPlain[i]) - glm::vec3(plain[i]))) > 1e-3f) continue;  // a geometry edge
    ++msCompared;
    msClose += largest(glm::abs(glm::vec3(ms[i]) - glm::vec3(host[i]))) <= 2.0f / 255.0f;
  }
  std::printf("cartoon over a 4-sample host: %d of %d pixels within 2/255 of the single-sample host's\n", msClose,
              msCompared);
  EXPECT_GT(msCompared, kPx * kPx * 9 / 10);
  EXPECT_GE(msClose, static_cast<int>(msCompared * 0.99));
  EXPECT_EQ(core::drainGlErrors(), "");

  int close = 0, edges = 0, changed = 0;
  float worst = 0.0f;
  for (std::size_t i = 0; i < host.size(); ++i) {
    if (glm::any(glm::greaterThan(glm::abs(glm::vec3(ownOpaque[i]) - glm::vec3(plain[i])), glm::vec3(1e-3f)))) {
      ++edges;
      continue;
    }
    const float diff = largest(glm::abs(glm::vec3(host[i]) - glm::vec3(ownFrame[i])));
    worst = std::max(worst, diff);
    if (diff > 2.0f / 255.0f && std::getenv("PUFF_DEBUG_HOST"))
      std::printf("px %d,%d host %g %g %g own %g %g %g plain %g %g %g\n", static_cast<int>(i % kPx),
                  static_cast<int>(i / kPx), host[i].r, host[i].g, host[i].b, ownFrame[i].r, ownFrame[i].g,
                  ownFrame[i].b, plain[i].r, plain[i].g, plain[i].b);
    close += diff <= 2.0f / 255.0f;
    changed += largest(glm::abs(glm::vec3(host[i]) - glm::vec3(plain[i]))) > 0.05f;
  }
  std::printf("cartoon over the host: %d edge pixels left out, %d of %d within 2/255, worst %.4f, %d changed\n", edges,
              close, static_cast<int>(host.size()) - edges, worst, changed);
  EXPECT_LT(edges, kPx * kPx / 10);
  EXPECT_GE(close, static_cast<int>((host.size() - edges) * 0.999)) << "worst " << worst;
  EXPECT_GT(changed, kPx * kPx / 20) << "the fire and its ink really drew";
}

}  // namespace
}  // namespace puff::host_state_test
