// Binding points chosen by the host draw the same frames as the defaults and leave the defaults' objects alone.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/cel/bindings.h>
#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/cel/opaque.h>
#include <puff/cel/shadow_map.h>
#include <puff/cel/types.h>
#include <puff/cel/volume_clip.h>
#include <puff/core/binding_base.h>
#include <puff/core/host_state.h>
#include <puff/gl_api.h>
#include <puff/media/bindings.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>

#include "host_state_fixture.h"
#include "support/assert_ok.h"
#include "support/gl_target.h"

namespace puff::host_state_test {
namespace {
// ---- chosen binding points -----------------------------------------------------------------------

// Points chosen one by one, none on a default one (uniform buffers 8-13, storage buffers 4-5, units
// 16-24: core::BindingBase{} and its spans), in another order than the defaults'.
cel::Bindings chosenCel() {
  cel::Bindings b;
  b.frameBlock = 7;
  b.particles = 2;
  b.cells = 3;
  b.particleNext = 1;
  b.ramp = 9;
  b.gradient = 12;
  b.atlasPacked = 10;
  b.atlasColor = 11;
  b.atlasHull = 8;
  b.shadowProfile = 13;
  b.shadowMapDepth = 14;
  b.shadowMapIds = 15;
  b.visibility = 6;
  return b;
}

media::Bindings chosenMedia() {
  media::Bindings b;
  b.mediaBlock = 1;
  b.materialBlock = 2;
  b.particles = 1;
  b.depth = 8;
  b.blackbody = 9;
  b.phase = 10;
  b.temperatureDetail = 11;
  b.opacityDetail = 12;
  b.falloff = 13;
  b.composeBlock = 3;
  b.opaqueColor = 14;
  b.opaqueDepth = 15;
  b.mediaLayer = 0;
  b.mediaDepth = 1;
  b.shimmer = 2;
  b.resolveSource = 3;
  b.historyFirst = 25;  // 25-32: beyond kUnits, which is fine: nothing is compared there
  b.cartoonBlock = 4;
  b.cartoonFirst = 5;
  return b;
}

// A whole cel frame: opaque objects and nailboards lit, shadows by the map and by volumes.
std::vector<glm::vec4> celFrame(CelKit& kit, const test::OffscreenTarget& target) {
  cel::Frame frame = eyeFrame();
  cel::Style style;
  style.shadows = true;
  const std::vector<cel::Particle> ps = puffs();
  cel::Bounds casters = cel::particleBounds(ps);
  for (std::size_t i = 0; i < kit.opaque->count(); ++i) casters.add(kit.opaque->worldBounds(i));
  kit.nailboards->upload(ps);
  // The map: casters from the light, then the eye's lit passes looking it up.
  kit.shadowMap->prepare(frame, casters, style);
  kit.shadowMap->beginCasters();
  kit.nailboards->drawShadowCasters(style, frame);
  kit.opaque->drawCasters();
  target.clear(glm::vec4(0.9f, 0.95f, 1.0f, 1.0f));
  frame.shadow = kit.shadowMap->lookup();
  frame.ambientGradient = true;
  EXPECT_OK(kit.block->upload(frame));
  kit.ramp->bind(kit.b);
  kit.gradient->bind(kit.b);
  kit.shadowMap->bind();
  kit.opaque->draw(cel::ShadePass::kLit);
  kit.nailboards->drawNailboards(style, cel::ShadePass::kLit);
  // Volumes on top (stencil), and the shadowed pass.
  const cel::VolumeClip clip = cel::volumeClip(frame, casters);
  kit.nailboards->drawShadowVolumes(style, glm::vec4(0, 1, 0, 0), clip);
  kit.opaque->drawShadowVolumes(style, glm::vec4(0, 1, 0, 0), clip);
  kit.opaque->draw(cel::ShadePass::kShadowed);
  kit.nailboards->drawNailboards(style, cel::ShadePass::kShadowed);
  return target.readLinear();
}

// The host's objects on the default points (and every other one looked at) stay bound while Puff
// draws on its chosen ones: the keys of the defaults' points.
Keys defaultPoints() {
  const core::BindingBase base;
  Keys k;
  for (unsigned u = base.textureUnit; u < base.textureUnit + core::kTextureUnitSpan; ++u) {
    for (const Target& t : kTargets) k.insert(unit(u, t.name));
    k.insert(sampler(u));
  }
  for (unsigned i = base.uniformBuffer; i < base.uniformBuffer + core::kUniformBufferSpan; ++i) k.insert(ubo(i));
  for (unsigned i = base.storageBuffer; i < base.storageBuffer + core::kStorageBufferSpan; ++i) k.insert(ssbo(i));
  return k;
}

TEST_F(HostState, ChosenCelBindingsDrawTheSameFrameAndLeaveTheDefaultsAlone) {
  test::OffscreenTarget target(kPx);
  HostileHost host;
  std::vector<glm::vec4> reference;
  {
    CelKit kit(*atlas_);
    reference = celFrame(kit, target);
  }
  CelKit kit(*atlas_, chosenCel());
  host.bindObjects();  // the host's own objects everywhere; the state switches stay as GL's defaults
  const State before = snapshot();
  const std::vector<glm::vec4> chosen = celFrame(kit, target);
  const State after = snapshot();
  ASSERT_EQ(chosen.size(), reference.size());
  int differing = 0, lit = 0;
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    if (chosen[i] != reference[i]) ++differing;
    if (reference[i] != reference[0]) ++lit;
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(lit, kPx * kPx / 10);  // the frame holds something: ground, wall, puffs, shadows
  const Keys touched = differences(before, after);
  for (const std::string& k : defaultPoints()) {
    EXPECT_EQ(touched.count(k), 0u) << k << ": " << before.at(k) << " -> " << after.at(k);
  }
  EXPECT_EQ(core::drainGlErrors(), "");
}

std::vector<glm::vec4> mediaFrame(const media::Bindings& b) {
  auto renderer = media::Renderer::create({}, b);
  EXPECT_OK(renderer);
  auto layers = media::Layers::create(kPx, kPx, 1, 0.5f, b);
  EXPECT_OK(layers);
  media::Layers& ly = **layers;
  media::Frame f;
  f.view = glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0), glm::vec3(0, 1, 0));
  f.projection = glm::perspective(glm::radians(45.0f), 1.0f, 0.5f, 50.0f);
  f.nearPlane = 0.5f;
  f.farPlane = 50.0f;
  f.viewport.width = kPx;
  f.viewport.height = kPx;
  // The opaque pass: grey, a wall at linear depth 0.1 over the left half, the background beyond.
  const GLuint opaque = ly.opaqueFramebuffer();
  const float grey[4] = {0.3f, 0.3f, 0.3f, 1.0f};
  glClearNamedFramebufferfv(opaque, GL_COLOR, 0, grey);
  glClearNamedFramebufferfi(opaque, GL_DEPTH_STENCIL, 0, 1.0f, 0);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, opaque);
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 0, kPx / 2, kPx);
  glClearNamedFramebufferfi(opaque, GL_DEPTH_STENCIL, 0, 0.1f, 0);
  glDisable(GL_SCISSOR_TEST);
  ly.resolveOpaque();
  std::vector<media::Particle> ps(4);
  for (int i = 0; i < 4; ++i) {
    media::Particle& p = ps[static_cast<std::size_t>(i)];
    p.position = glm::vec3(-1.2f + 0.8f * i, 0.2f * i, -0.4f * i);
    p.radius = 0.9f;
    p.material = static_cast<std::uint32_t>(i % 3);
    p.seed = static_cast<std::uint32_t>(i);
  }
  ly.beginMedia();
  (*renderer)->draw(ly.layerFrame(f), ps, media::Method::kSpherical, ly.mediaDepth(), media::Shimmer::kWritten);
  media::ExplosionLight light;
  light.center = glm::vec3(0.0f, 0.0f, -1.0f);
  light.radius = 3.0f;
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, kPx, kPx);
  glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  const core::Viewport vp{0, 0, kPx, kPx};
  media::ComposeSettings cs;
  cs.shimmerPixels = 2.0f;
  ly.compose(out.get(), vp, f, std::span(&light, 1), cs);
  std::vector<glm::vec4> px(static_cast<std::size_t>(kPx) * kPx);
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(glm::vec4)), px.data());
  // And the motion blur of two history slots composed the same way.
  ly.setHistorySlots(2);
  ly.compose(ly.historyFramebuffer(0), vp, f, {}, cs);
  ly.compose(ly.historyFramebuffer(1), vp, f, std::span(&light, 1), cs);
  const std::vector<int> slots = {0, 1};
  const std::vector<float> weights = {0.25f, 0.75f};
  ly.blendHistory(out.get(), vp, slots, weights);
  std::vector<glm::vec4> blurred(px.size());
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(blurred.size() * sizeof(glm::vec4)),
                    blurred.data());
  px.insert(px.end(), blurred.begin(), blurred.end());
  return px;
}

TEST_F(HostState, ChosenMediaBindingsDrawTheSameFrameAndLeaveTheDefaultsAlone) {
  HostileHost host;
  const std::vector<glm::vec4> reference = mediaFrame({});
  host.bindObjects();
  const State before = snapshot();
  const std::vector<glm::vec4> chosen = mediaFrame(chosenMedia());
  const State after = snapshot();
  ASSERT_EQ(chosen.size(), reference.size());
  int differing = 0, medium = 0;
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    if (chosen[i] != reference[i]) ++differing;
    if (glm::vec3(reference[i]) != glm::vec3(reference[0])) ++medium;
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(medium, kPx * kPx / 10);  // the particles show
  const Keys touched = differences(before, after);
  for (const std::string& k : defaultPoints()) {
    EXPECT_EQ(touched.count(k), 0u) << k << ": " << before.at(k) << " -> " << after.at(k);
  }
  EXPECT_EQ(core::drainGlErrors(), "");
}

// One base of each kind moves every point: each is its base plus the offset its header lists, and a
// frame drawn at moved bases (clear of the defaults) is the defaults' to the bit.
TEST_F(HostState, BindingBasesMoveEveryPoint) {
  const core::BindingBase moved{.uniformBuffer = 1, .storageBuffer = 2, .textureUnit = 30};
  const cel::Bindings c = cel::Bindings::at(moved);
  EXPECT_EQ(c.frameBlock, 1u);
  EXPECT_EQ(c.particles, 2u);  // off the shaders' own layout(binding) values (0, 1): they must be pointed
  EXPECT_EQ(c.cells, 3u);
  EXPECT_EQ(c.ramp, 30u);
  EXPECT_EQ(c.shadowMapIds, 37u);
  EXPECT_EQ(c.visibility, 38u);
  EXPECT_EQ(cel::Bindings{}, cel::Bindings::at(core::BindingBase{}));
  const media::Bindings m = media::Bindings::at(moved);
  EXPECT_EQ(m.mediaBlock, 4u);
  EXPECT_EQ(m.composeBlock, 6u);
  EXPECT_EQ(m.particles, 2u);
  EXPECT_EQ(m.depth, 30u);
  EXPECT_EQ(m.cartoonFirst, 35u);
  EXPECT_EQ(media::Bindings{}, media::Bindings::at(core::BindingBase{}));
  // The defaults keep clear of the points engines take first: nothing below 4 of any kind.
  for (const unsigned p : {cel::Bindings{}.frameBlock, cel::Bindings{}.particles, cel::Bindings{}.ramp,
                           media::Bindings{}.mediaBlock, media::Bindings{}.cartoonBlock, media::Bindings{}.particles,
                           media::Bindings{}.depth, media::Bindings{}.resolveSource})
    EXPECT_GE(p, 4u);

  test::OffscreenTarget target(kPx);
  std::vector<glm::vec4> reference, atBases;
  {
    CelKit kit(*atlas_);
    reference = celFrame(kit, target);
  }
  CelKit kit(*atlas_, c);
  atBases = celFrame(kit, target);
  EXPECT_TRUE(atBases == reference) << "the cel frame at moved bases differs from the defaults'";
  EXPECT_TRUE(mediaFrame(m) == mediaFrame(media::Bindings{})) << "the media frame at moved bases differs";
  EXPECT_EQ(core::drainGlErrors(), "");
}

TEST_F(HostState, BindingsAreValidated) {
  cel::Bindings same;
  same.gradient = same.ramp;
  auto r = cel::NailboardRenderer::create(same);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message,
            "cel::Bindings.gradient and cel::Bindings.ramp: both use texture unit 16; they must differ");
  auto o = cel::OpaqueRenderer::create(same);
  ASSERT_FALSE(o);
  EXPECT_EQ(o.error().message, r.error().message);

  cel::Bindings storage;
  storage.cells = storage.particles;
  auto s = cel::NailboardRenderer::create(storage);
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("cel::Bindings.cells and cel::Bindings.particles"), std::string::npos);

  GLint maxUnits = 0, maxUniform = 0;
  glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &maxUnits);
  glGetIntegerv(GL_MAX_UNIFORM_BUFFER_BINDINGS, &maxUniform);
  cel::Bindings far;
  far.atlasColor = static_cast<unsigned>(maxUnits);
  auto f = cel::NailboardRenderer::create(far);
  ASSERT_FALSE(f);
  EXPECT_EQ(f.error().message, "cel::Bindings.atlasColor: texture unit " + std::to_string(maxUnits) +
                                   " is beyond this GL's " + std::to_string(maxUnits) + " (0 to " +
                                   std::to_string(maxUnits - 1) + ")");
  cel::Bindings farBlock;
  farBlock.frameBlock = static_cast<unsigned>(maxUniform);
  EXPECT_FALSE(cel::validate(farBlock));
  farBlock.frameBlock = static_cast<unsigned>(maxUniform - 1);
  EXPECT_TRUE(cel::validate(farBlock));

  media::Bindings m;
  m.falloff = m.depth;
  auto mr = media::Renderer::create({}, m);
  ASSERT_FALSE(mr);
  EXPECT_EQ(mr.error().message,
            "media::Bindings.falloff and media::Bindings.depth: both use texture unit 16; they must differ");
  media::Bindings history;
  history.historyFirst = static_cast<unsigned>(maxUnits - 7);  // its 8 units reach one past the last
  auto ml = media::Layers::create(16, 16, 1, 0.5f, history);
  ASSERT_FALSE(ml);
  EXPECT_NE(ml.error().message.find("media::Bindings.historyFirst: texture unit " + std::to_string(maxUnits)),
            std::string::npos);
  // Points of different calls may share (the defaults do: unit 16 is read by draw and by compose).
  EXPECT_TRUE(media::validate(media::Bindings{}));
  EXPECT_TRUE(cel::validate(chosenCel()));
  EXPECT_TRUE(media::validate(chosenMedia()));
}

// The guard's extent follows the chosen points.
TEST_F(HostState, GuardExtentCoversChosenPoints) {
  const core::GuardExtent c = cel::guardExtent(chosenCel());
  EXPECT_EQ(c.textureUnits, 16);
  EXPECT_EQ(c.uniformBuffers, 8);
  EXPECT_EQ(c.storageBuffers, 4);
  const core::GuardExtent m = media::guardExtent(chosenMedia());
  EXPECT_EQ(m.textureUnits, 33);
  EXPECT_EQ(m.uniformBuffers, 5);
  EXPECT_EQ(m.storageBuffers, 2);
  const core::GuardExtent both = c.cover(m);
  EXPECT_EQ(both.textureUnits, 33);
  EXPECT_EQ(both.uniformBuffers, 8);
  EXPECT_EQ(both.storageBuffers, 4);
  // The defaults' extent is the guard's default.
  const core::GuardExtent d = cel::guardExtent({}).cover(media::guardExtent({}));
  const core::GuardExtent g;
  EXPECT_EQ(d.textureUnits, g.textureUnits);
  EXPECT_EQ(d.uniformBuffers, g.uniformBuffers);
  EXPECT_EQ(d.storageBuffers, g.storageBuffers);
}

}  // namespace
}  // namespace puff::host_state_test
