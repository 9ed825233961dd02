// A host whose framebuffer has more colour attachments than the one Puff draws into (a G-buffer, a
// velocity target): every Puff pass writes attachment 0 alone. The host's other attachments keep
// their contents to the bit, its draw buffers and their write masks stay as it set them, and
// attachment 0 holds exactly what a framebuffer of one attachment gets.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include <puff/cel/volume_clip.h>
#include <puff/media/coverage.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>

#include "host_state_fixture.h"
#include "support/sphere_bake.h"
#include "support/temp_dir.h"

namespace puff::host_state_test {
namespace {

constexpr int kExtra = 2;  // the host's attachments past Puff's: 1 and 2

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
  // pattern), depth to 1 and stencil to 0; bound, with attachment 1 written in full and only red
  // and blue of attachment 2 (its write masks).
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
    if (colour_.size() > 2) glColorMaski(2, GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
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
    SphereAtlasTest::TearDown();
  }

  // Draws `draw` into the host's framebuffer with and without the extra attachments.
  void expectOnlyAttachmentZero(const std::string& what, const std::function<void(const HostFramebuffer&)>& draw) {
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
    EXPECT_NE(gbuffer.halfs0(), blank.halfs0()) << "nothing was drawn";
    glBindFramebuffer(GL_FRAMEBUFFER, gbuffer.framebuffer());
    for (int i = 0; i <= kExtra; ++i)
      EXPECT_EQ(geti(GL_DRAW_BUFFER0 + static_cast<GLenum>(i)), static_cast<GLint>(GL_COLOR_ATTACHMENT0 + i))
          << "draw buffer " << i;
    GLboolean mask[4];
    glGetBooleani_v(GL_COLOR_WRITEMASK, 2, mask);
    EXPECT_EQ(ints({mask[0], mask[1], mask[2], mask[3]}), "1 0 1 0") << "the host's write mask of attachment 2";
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
    kit.block->upload(frame);
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
    kit.block->upload(eyeFrame());
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

// The photoreal media over the host's frame: its depth resolved from the host's texture, the layer
// composed over attachment 0 (dual-source blending, which allows one draw buffer on most GPUs).
TEST_F(HostTargets, MediaComposeOverWritesAttachmentZeroAlone) {
  CelKit kit(*atlas_);
  auto renderer = media::Renderer::create();
  ASSERT_OK(renderer);
  const cel::Frame cel = eyeFrame();
  media::Frame f;
  f.view = cel.view;
  f.projection = cel.projection;
  f.nearPlane = cel.nearPlane;
  f.farPlane = cel.farPlane;
  f.width = f.height = kPx;
  std::vector<media::Particle> smoke(3);
  for (std::size_t i = 0; i < smoke.size(); ++i) {
    smoke[i].position = glm::vec3(-0.8f + 0.8f * static_cast<float>(i), 0.8f, 0.5f);
    smoke[i].radius = 0.9f;
  }
  for (const bool covered : {false, true}) {
    expectOnlyAttachmentZero(
        covered ? "media, over its coverage" : "media, whole frame", [&](const HostFramebuffer& t) {
          celFrame(kit, cel::Style{}, puffs(), t);
          auto layers = media::HostLayers::create(kPx, kPx, 0.5f);
          ASSERT_OK(layers);
          media::HostDepth depth;
          depth.texture = t.depth();
          depth.space = {cel.depth, cel.clipDepth, cel.projection, cel.nearPlane, cel.farPlane};
          if (covered) (*layers)->setCoverage(media::coverage(f, smoke));
          ASSERT_OK((*layers)->resolveHostDepth(depth));
          (*layers)->beginMedia();
          (*renderer)->draw((*layers)->layerFrame(f), smoke, media::Method::kSpherical, (*layers)->mediaDepth());
          ASSERT_OK((*layers)->composeOver(t.framebuffer(), {0, 0, kPx, kPx}, f, {}, {}));
        });
  }
}

}  // namespace
}  // namespace puff::host_state_test
