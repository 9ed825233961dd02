// What HostLayers refuses: at compile time, the calls of Puff's own opaque pass (and Layers those
// of a host's frame); at run time, host depth textures it cannot read and composes it cannot draw,
// each with its one-line error and nothing drawn.
#include <gtest/gtest.h>

#include <string>
#include <type_traits>
#include <vector>

#include <puff/core/depth.h>
#include <puff/core/gl.h>
#include <puff/gl_api.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>

#include "support/assert_ok.h"
#include "support/host_gl.h"
#include "support/media_target.h"

namespace puff {
namespace {

using namespace test;  // support/host_gl.h: the conventions and projections

// Each kind of layers has only its own kind's calls: calling the other's is a compile error.
template <class L>
concept HasOwnOpaquePass = requires(L& l, const core::Viewport& vp, const media::Frame& f,
                                    const media::ComposeSettings& s) {
  l.opaqueFramebuffer();
  l.resolveOpaque();
  l.compose(0u, vp, f, {}, s);
  l.setHistorySlots(1);
};
template <class L>
concept DrawsInAHostsFrame = requires(L& l, const core::Viewport& vp, const media::Frame& f,
                                      const media::ComposeSettings& s) {
  l.resolveHostDepth(media::HostDepth{}, f);
  l.composeOver(0u, vp, f, {}, s);
};
static_assert(HasOwnOpaquePass<media::Layers> && !DrawsInAHostsFrame<media::Layers>);
static_assert(DrawsInAHostsFrame<media::HostLayers> && !HasOwnOpaquePass<media::HostLayers>);
// Neither is made but through its create (and neither is copied: each owns GL objects).
static_assert(!std::is_default_constructible_v<media::Layers> && !std::is_copy_constructible_v<media::Layers>);
static_assert(!std::is_default_constructible_v<media::HostLayers> && !std::is_copy_constructible_v<media::HostLayers>);

core::DepthSpace spaceFor(const Convention& c) { return {c.depth, c.clip, projection(c, 8.0f), kNear, kFar}; }

class HostLayersErrors : public MediaRendererTest {};

TEST_F(HostLayersErrors, ResolveHostDepthRefusesWhatItCannotRead) {
  auto layers = media::HostLayers::create(32, 32, 1.0f);
  ASSERT_OK(layers);
  core::SharedFrame frame = test::frameIn(spaceFor(kStandardNO));
  const auto refuse = [&](const media::HostDepth& d, const std::string& words) {
    auto r = (*layers)->resolveHostDepth(d, frame);
    ASSERT_FALSE(r.ok()) << words;
    EXPECT_NE(r.error().message.find(words), std::string::npos) << r.error().message;
  };
  media::HostDepth d;
  refuse(d, "is not a texture");
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, 32, 32);
  d.texture = color.get();
  refuse(d, "does not hold depth");
  core::Texture cube = core::makeTexture(GL_TEXTURE_CUBE_MAP);
  glTextureStorage2D(cube.get(), 1, GL_DEPTH_COMPONENT24, 32, 32);
  d.texture = cube.get();
  refuse(d, "not a 2D or 2D multisample texture");
  core::Texture depth = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(depth.get(), 1, GL_DEPTH24_STENCIL8, 40, 32);
  d.texture = depth.get();
  d.x = 9;  // 9 + 32 > 40
  refuse(d, "does not fit in it");
  d.x = 8;
  EXPECT_OK((*layers)->resolveHostDepth(d, frame));
  glTextureParameteri(depth.get(), GL_DEPTH_STENCIL_TEXTURE_MODE, GL_STENCIL_INDEX);
  refuse(d, "GL_DEPTH_STENCIL_TEXTURE_MODE");
  glTextureParameteri(depth.get(), GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
  glTextureParameteri(depth.get(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  refuse(d, "GL_TEXTURE_COMPARE_MODE");
  glTextureParameteri(depth.get(), GL_TEXTURE_COMPARE_MODE, GL_NONE);
  frame.farPlane = frame.nearPlane;
  refuse(d, "need 0 < near < far");
  EXPECT_EQ(core::drainGlErrors(), "");
}

TEST_F(HostLayersErrors, ComposeOverRefusesWhatItCannotDo) {
  auto host = media::HostLayers::create(16, 16, 1.0f);
  ASSERT_OK(host);
  const media::Frame f = MediaCamera{}.frame(16);
  const core::Viewport vp{0, 0, 16, 16};
  media::ComposeSettings shimmer;
  shimmer.shimmerPixels = 2.0f;
  auto r = (*host)->composeOver(0, vp, f, {}, shimmer);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("heat shimmer"), std::string::npos) << r.error().message;
  const core::Viewport wrong{0, 0, 15, 16};
  r = (*host)->composeOver(0, wrong, f, {}, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("15x16"), std::string::npos) << r.error().message;
  const core::Viewport wrongHeight{0, 0, 16, 17};
  r = (*host)->composeOver(0, wrongHeight, f, {}, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("16x17"), std::string::npos) << r.error().message;
  // Nine lights that shine: at most 8 (intensity 0 does not count).
  std::vector<media::ExplosionLight> nine(9);
  r = (*host)->composeOver(0, vp, f, nine, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("9 explosion lights, at most 8"), std::string::npos) << r.error().message;
  nine[8].intensity = 0.0f;
  EXPECT_OK((*host)->composeOver(0, vp, f, nine, {}));
  // A target with two draw buffers is no error: composeOver draws its first alone (dual-source
  // blending allows one on most GPUs) and gives it both back (tests/unit/host_targets_test.cpp).
  core::Framebuffer two = core::makeFramebuffer();
  core::Texture c0 = core::makeTexture(GL_TEXTURE_2D), c1 = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(c0.get(), 1, GL_RGBA16F, 16, 16);
  glTextureStorage2D(c1.get(), 1, GL_RGBA16F, 16, 16);
  glNamedFramebufferTexture(two.get(), GL_COLOR_ATTACHMENT0, c0.get(), 0);
  glNamedFramebufferTexture(two.get(), GL_COLOR_ATTACHMENT1, c1.get(), 0);
  const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(two.get(), 2, both);
  EXPECT_OK((*host)->composeOver(two.get(), vp, f, {}, {}));
  GLint second = GL_NONE;
  glGetIntegerv(GL_DRAW_BUFFER1, &second);
  EXPECT_EQ(second, static_cast<GLint>(GL_COLOR_ATTACHMENT1));
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  EXPECT_EQ(core::drainGlErrors(), "");
}

}  // namespace
}  // namespace puff
