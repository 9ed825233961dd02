// Every public cel and media call on a hostile host changes exactly the GL state its header lists.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <puff/cel/bindings.h>
#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/cel/shadow_map.h>
#include <puff/cel/types.h>
#include <puff/cel/volume_clip.h>
#include <puff/core/atlas.h>
#include <puff/core/depth.h>
#include <puff/gl_api.h>
#include <puff/media/bindings.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>

#include "host_state_fixture.h"
#include "support/assert_ok.h"
#include "support/gl_target.h"
#include "support/sphere_bake.h"
#include "support/temp_dir.h"

namespace puff::host_state_test {
namespace {
// ---- what the headers say each call leaves (nailboards.h's and layers.h's terms) -----------------

Keys operator+(Keys a, const Keys& b) {
  a.insert(b.begin(), b.end());
  return a;
}
Keys texture(unsigned u, const char* target) { return {unit(u, target), sampler(u)}; }
// Every target of unit u that the hostile host binds (glBindTextureUnit(u, 0) clears them all).
Keys wholeUnit(unsigned u) {
  Keys k;
  for (const char* t : {"1D", "2D", "3D", "1DArray", "2DArray", "Cube", "2DMS"}) k.insert(unit(u, t));
  return k;
}

// "the pass state" (resetPassState)
const Keys kPassState = {"blend[0]",
                         "cull",
                         "scissor",
                         "depth.clamp",
                         "polygon_offset.fill",
                         "alpha_to_coverage",
                         "rasterizer_discard",
                         "primitive_restart",
                         "primitive_restart_fixed",
                         "polygon_mode",
                         "depth.range",
                         "depth.test"};
// "write masks on"
const Keys kWriteMasks = {"depth.mask", "colormask[0]", "stencil.front.writemask", "stencil.back.writemask"};
const Keys kNoProgram = {"program", "vao"};
Keys atlas(const cel::Bindings& b) {
  return texture(b.atlasPacked, "2D") + texture(b.atlasColor, "2D") + texture(b.atlasHull, "3D") +
         texture(b.shadowProfile, "2D") + Keys{ssbo(b.particles), ssbo(b.cells)};
}
// A draw framebuffer without a stencil buffer bound: the stored stencil reference is untouched, but
// GL_STENCIL_REF reads back clamped to its 0 stencil bits (the host's 3 and 5 read as 0).
const Keys kStencilRefReads = {"stencil.front.ref", "stencil.back.ref"};
// Layers' "full-screen state" (GL_FRAMEBUFFER_SRGB, on in the hostile host, is left alone everywhere)
const Keys kFullscreen = {"depth.test",         "stencil.test",      "blend[0]",    "cull",         "scissor",
                          "rasterizer_discard", "alpha_to_coverage", "sample_mask", "polygon_mode", "colormask[0]"};

TEST_F(HostState, CelCallsLeaveWhatTheirHeadersList) {
  test::OffscreenTarget target(kPx);
  ASSERT_TRUE(target.complete());
  HostileHost host;
  CelKit kit(*atlas_);
  const cel::Bindings& b = kit.b;
  const cel::Frame frame = eyeFrame();
  cel::Style style;
  style.outlines = true;
  cel::Bounds receivers = cel::particleBounds(puffs());
  for (std::size_t i = 0; i < kit.opaque->count(); ++i) receivers.add(kit.opaque->worldBounds(i));
  const cel::VolumeClip clip = cel::volumeClip(frame, receivers);
  ASSERT_FALSE(clip.everything);
  ASSERT_FALSE(clip.nothing);
  kit.shadowMap->prepare(frame, receivers, style);
  core::drainGlErrors();

  // The cel passes leave the depth test on and the stencil test off: the host's are the opposite.
  const auto celHost = [] {
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_STENCIL_TEST);
  };
  // The shadowed pass leaves the stencil test on: here the host's is off.
  const auto shadowedHost = [] {
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_STENCIL_TEST);
  };
  const Keys lit = kPassState + kWriteMasks + kNoProgram + Keys{"depth.func", "stencil.test"};
  const Keys stencilFunc = {"stencil.front.func", "stencil.back.func", "stencil.front.ref",
                            "stencil.back.ref",   "stencil.front.op",  "stencil.back.op"};
  const Keys shadowed = kPassState + kWriteMasks + kNoProgram + stencilFunc + Keys{"depth.func", "stencil.test"};
  const Keys volumes =
      kPassState + kWriteMasks + kNoProgram + stencilFunc + Keys{"depth.func", "stencil.test", "scissor.box"};

  const std::vector<Case> cases = {
      {"FrameBlock::upload", [&] { EXPECT_OK(kit.block->upload(frame)); }, {ubo(b.frameBlock)}},
      {"FrameBlock::bind", [&] { kit.block->bind(); }, {ubo(b.frameBlock)}},
      {"Ramp::bind", [&] { kit.ramp->bind(b); }, texture(b.ramp, "1D")},
      {"Gradient::bind", [&] { kit.gradient->bind(b); }, texture(b.gradient, "2D")},
      {"NailboardRenderer::upload", [&] { kit.nailboards->upload(puffs()); }, {}},
      {"NailboardRenderer::drawNailboards(kLit)",
       [&] {
         kit.nailboards->setLitShading(cel::LitShading::kOncePerPixel);
         kit.nailboards->drawNailboards(style, cel::ShadePass::kLit);
       },
       lit + atlas(b) + texture(b.visibility, "2D"), celHost},
      {"NailboardRenderer::drawNailboards(kLit, every layer)",
       [&] {
         kit.nailboards->setLitShading(cel::LitShading::kEveryLayer);
         kit.nailboards->drawNailboards(style, cel::ShadePass::kLit);
         kit.nailboards->setLitShading(cel::LitShading::kOncePerPixel);
       },
       lit + atlas(b), celHost},
      {"NailboardRenderer::drawNailboards(kLit, no outlines)",
       [&] {
         cel::Style s = style;
         s.outlines = false;
         kit.nailboards->drawNailboards(s, cel::ShadePass::kLit);
       },
       lit + atlas(b) + texture(b.visibility, "2D"), celHost},
      {"NailboardRenderer::drawNailboards(kShadowed)",
       [&] { kit.nailboards->drawNailboards(style, cel::ShadePass::kShadowed); },
       shadowed + atlas(b) + texture(b.visibility, "2D"), shadowedHost},
      {"NailboardRenderer::drawNailboards(kDepthOnly)",
       [&] { kit.nailboards->drawNailboards(style, cel::ShadePass::kDepthOnly); }, lit + atlas(b), celHost},
      {"NailboardRenderer::drawBaseline", [&] { kit.nailboards->drawBaseline(style); }, lit + atlas(b), celHost},
      {"NailboardRenderer::drawShadowVolumes",
       [&] { kit.nailboards->drawShadowVolumes(style, glm::vec4(0, 1, 0, 0), clip); }, volumes + atlas(b), celHost},
      {"NailboardRenderer::drawShadowCasters", [&] { kit.nailboards->drawShadowCasters(style, frame); }, lit + atlas(b),
       celHost},
      {"OpaqueRenderer::draw(kLit)", [&] { kit.opaque->draw(cel::ShadePass::kLit); }, lit + Keys{"front_face"},
       celHost},
      {"OpaqueRenderer::draw(kShadowed)", [&] { kit.opaque->draw(cel::ShadePass::kShadowed); },
       shadowed + Keys{"front_face"}, shadowedHost},
      {"OpaqueRenderer::draw(kDepthOnly)", [&] { kit.opaque->draw(cel::ShadePass::kDepthOnly); },
       lit + Keys{"front_face"}, celHost},
      {"OpaqueRenderer::drawShadowVolumes", [&] { kit.opaque->drawShadowVolumes(style, glm::vec4(0.0f), clip); },
       volumes + Keys{"front_face"}, celHost},
      {"OpaqueRenderer::drawCasters", [&] { kit.opaque->drawCasters(); }, lit, celHost},
      {"ShadowMap::prepare", [&] { kit.shadowMap->prepare(frame, receivers, style); }, {}},
      {"ShadowMap::beginCasters", [&] { kit.shadowMap->beginCasters(); },
       Keys{"fbo.draw", "viewport", "scissor", "rasterizer_discard", "depth.mask", "colormask[0]", ubo(b.frameBlock)} +
           wholeUnit(b.shadowMapDepth) + wholeUnit(b.shadowMapIds) + kStencilRefReads},
      {"ShadowMap::bind", [&] { kit.shadowMap->bind(); },
       texture(b.shadowMapDepth, "2D") + texture(b.shadowMapIds, "2D")},
  };
  for (const Case& c : cases) check(c, target, host);
}

// A guard around a lit pass that remakes Puff's visibility target (a larger viewport than the last
// frame's) gives back no name the pass deleted: the unit the old target was left on comes back empty,
// not bound to a deleted texture (an error), and the rest as the host had it.
TEST_F(HostState, AGuardGivesBackNoNameThePassDeleted) {
  test::OffscreenTarget target(kPx);
  CelKit kit(*atlas_);
  kit.nailboards->setLitShading(cel::LitShading::kOncePerPixel);
  cel::Style style;
  auto lit = [&](int size) {
    cel::Frame f = eyeFrame();
    f.viewport = {0, 0, size, size};
    target.bind();
    glViewport(0, 0, size, size);
    EXPECT_OK(kit.block->upload(f));
    kit.ramp->bind(kit.b);
    kit.nailboards->upload(puffs());
    kit.nailboards->drawNailboards(style, cel::ShadePass::kLit);
  };
  lit(kPx / 2);  // leaves its target on unit `visibility`
  GLint left = 0;
  glActiveTexture(GL_TEXTURE0 + kit.b.visibility);
  glGetIntegerv(GL_TEXTURE_BINDING_2D, &left);
  ASSERT_NE(left, 0);
  core::drainGlErrors();
  {
    core::HostStateGuard guard(cel::guardExtent(kit.b));
    lit(kPx);  // a larger viewport: the target is made again, the old one deleted
  }
  EXPECT_EQ(core::drainGlErrors(), "");
  GLint back = -1;
  glActiveTexture(GL_TEXTURE0 + kit.b.visibility);
  glGetIntegerv(GL_TEXTURE_BINDING_2D, &back);
  EXPECT_EQ(back, glIsTexture(static_cast<GLuint>(left)) ? left : 0);
  glActiveTexture(GL_TEXTURE0);
}

// The tumbling hull's passes with their occluders (HullOcclusion::kCores): what the lit pass leaves,
// the occluder target on unit `visibility` (2D), and the draw framebuffer the host had.
TEST_F(HostState, TheHullsPassesLeaveWhatTheirHeadersList) {
  test::OffscreenTarget target(kPx);
  ASSERT_TRUE(target.complete());
  HostileHost host;
  test::ScopedTempDir dir("puff_host_state_views");
  auto sidecar = test::bakeSphereAtlas(dir.path(), 4);
  ASSERT_OK(sidecar);
  auto views = core::loadAtlas(*sidecar);
  ASSERT_OK(views);
  CelKit kit(*views);
  const cel::Bindings& b = kit.b;
  std::vector<cel::Particle> tumbling = puffs();
  for (std::size_t i = 0; i < tumbling.size(); ++i) {
    tumbling[i].oriented = true;
    tumbling[i].orientation =
        glm::angleAxis(0.7f + 0.9f * static_cast<float>(i), glm::normalize(glm::vec3(1, 2, 0.5f)));
  }
  kit.nailboards->upload(tumbling);
  kit.nailboards->setHullOcclusion(cel::HullOcclusion::kCores);
  cel::Style style;
  style.outlines = true;
  style.tumble = cel::TumbleMethod::kHull;
  EXPECT_OK(kit.block->upload(eyeFrame()));
  core::drainGlErrors();
  const auto celHost = [] {
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_STENCIL_TEST);
  };
  const Keys lit = kPassState + kWriteMasks + kNoProgram + Keys{"depth.func", "stencil.test"};
  const std::vector<Case> cases = {
      {"NailboardRenderer::drawNailboards(kLit, hull)",
       [&] { kit.nailboards->drawNailboards(style, cel::ShadePass::kLit); },
       lit + atlas(b) + texture(b.visibility, "2D"), celHost},
      {"NailboardRenderer::drawNailboards(kDepthOnly, hull)",
       [&] { kit.nailboards->drawNailboards(style, cel::ShadePass::kDepthOnly); },
       lit + atlas(b) + texture(b.visibility, "2D"), celHost},
  };
  for (const Case& c : cases) check(c, target, host);
}

TEST_F(HostState, MediaCallsLeaveWhatTheirHeadersList) {
  test::OffscreenTarget target(kPx);
  HostileHost host;
  auto renderer = media::Renderer::create();
  ASSERT_OK(renderer);
  auto layers = media::Layers::create(kPx, kPx, 1, 0.5f);
  ASSERT_OK(layers);
  media::Layers& ly = **layers;
  ly.setHistorySlots(2);
  const media::Bindings b;
  media::Frame f;
  f.view = glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0), glm::vec3(0, 1, 0));
  f.projection = glm::perspective(glm::radians(45.0f), 1.0f, 0.5f, 50.0f);
  f.nearPlane = 0.5f;
  f.farPlane = 50.0f;
  f.viewport.width = kPx;
  f.viewport.height = kPx;
  std::vector<media::Particle> ps(3);
  for (int i = 0; i < 3; ++i) {
    ps[static_cast<std::size_t>(i)].position = glm::vec3(-1.0f + i, 0.0f, -0.5f * i);
    ps[static_cast<std::size_t>(i)].material = static_cast<std::uint32_t>(i);
  }
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture outColor = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(outColor.get(), 1, GL_RGBA16F, kPx, kPx);
  glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, outColor.get(), 0);
  const core::Viewport vp{0, 0, kPx, kPx};
  const std::vector<media::ExplosionLight> lights(1);
  const std::vector<int> slots = {0, 1};
  const std::vector<float> weights = {0.5f, 0.5f};

  // The media draw leaves the depth and stencil tests off: the host's are on (the default hostile state).
  const Keys draw = kNoProgram + Keys{"blend[0]",     "blend[1]",        "blend_func[0]",      "blend_func[1]",
                                      "blend_eq[0]",  "blend_eq[1]",     "depth.test",         "stencil.test",
                                      "cull",         "scissor",         "alpha_to_coverage",  "rasterizer_discard",
                                      "depth.clamp",  "polygon_mode",    "depth.mask",         "colormask[0]",
                                      "colormask[1]", ubo(b.mediaBlock), ubo(b.materialBlock), ssbo(b.particles)} +
                    texture(b.depth, "2D") + texture(b.blackbody, "1D") + texture(b.phase, "2D") +
                    texture(b.temperatureDetail, "3D") + texture(b.opacityDetail, "3D") + texture(b.falloff, "2D");
  const auto drawCase = [&](media::Method m) {
    return Case{"Renderer::draw(" + std::string(media::toString(m)) + ")",
                [&, m] { (*renderer)->draw(ly.layerFrame(f), ps, m, ly.mediaDepth(), media::Shimmer::kWritten); },
                draw};
  };
  const std::vector<Case> cases = {
      drawCase(media::Method::kPlanar),
      drawCase(media::Method::kSpherical),
      drawCase(media::Method::kPlanarTextured),
      {"Layers::resolveOpaque", [&] { ly.resolveOpaque(); },
       kFullscreen + kNoProgram +
           Keys{unit(b.resolveSource, "2DMS"), unit(b.resolveSource, "2D"), sampler(b.resolveSource)}},
      {"Layers::beginMedia", [&] { ly.beginMedia(); },
       Keys{"fbo.draw", "viewport", "scissor", "rasterizer_discard", "colormask[0]", "colormask[1]"} +
           kStencilRefReads},
      {"Layers::compose", [&] { ly.compose(out.get(), vp, f, lights, media::ComposeSettings{}); },
       Keys{"fbo.draw", "viewport", ubo(b.composeBlock)} + kStencilRefReads + kFullscreen + kNoProgram +
           texture(b.opaqueColor, "2D") + texture(b.opaqueDepth, "2D") + texture(b.mediaLayer, "2D") +
           texture(b.mediaDepth, "2D") + texture(b.shimmer, "2D")},
      {"Layers::blendHistory", [&] { ly.blendHistory(out.get(), vp, slots, weights); },
       Keys{"fbo.draw", "viewport"} + kStencilRefReads + kFullscreen + kNoProgram + texture(b.historyFirst, "2D") +
           texture(b.historyFirst + 1, "2D")},
  };
  for (const Case& c : cases) check(c, target, host);

  // Media in the host's frame (HostLayers): its depth texture read, the layer blended onto its
  // colour.
  auto hostLayers = media::HostLayers::create(kPx, kPx, 0.5f);
  ASSERT_OK(hostLayers);
  media::HostLayers& hl = **hostLayers;
  core::Texture hostDepth = core::makeTexture(GL_TEXTURE_2D),
                hostDepthMs = core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE);
  glTextureStorage2D(hostDepth.get(), 1, GL_DEPTH24_STENCIL8, kPx, kPx);
  glTextureStorage2DMultisample(hostDepthMs.get(), 4, GL_DEPTH24_STENCIL8, kPx, kPx, GL_TRUE);
  media::HostDepth single, multi;
  single.texture = hostDepth.get();
  // The host's depth: GL's standard, through the media frame's projection and planes.
  media::Frame hostFrame = f;
  hostFrame.depth = core::DepthConvention::kStandard;
  hostFrame.clipDepth = core::ClipDepth::kNegativeOneToOne;
  multi = single;
  multi.texture = hostDepthMs.get();
  const std::vector<Case> hostCases = {
      {"HostLayers::resolveHostDepth(2D)", [&] { EXPECT_OK(hl.resolveHostDepth(single, hostFrame)); },
       kFullscreen + kNoProgram + Keys{unit(b.resolveSource, "2D"), sampler(b.resolveSource)}},
      {"HostLayers::resolveHostDepth(2D multisample)", [&] { EXPECT_OK(hl.resolveHostDepth(multi, hostFrame)); },
       kFullscreen + kNoProgram +
           Keys{unit(b.resolveSource, "2DMS"), unit(b.resolveSource, "2D"), sampler(b.resolveSource)}},
      {"HostLayers::composeOver",
       [&] { EXPECT_OK(hl.composeOver(out.get(), vp, f, lights, media::ComposeSettings{})); },
       Keys{"fbo.draw", "viewport", ubo(b.composeBlock), "blend_func[0]", "blend_eq[0]"} + kStencilRefReads +
           kFullscreen + kNoProgram + texture(b.opaqueDepth, "2D") + texture(b.mediaLayer, "2D") +
           texture(b.mediaDepth, "2D") + texture(b.shimmer, "2D")},
  };
  for (const Case& c : hostCases) check(c, target, host);

  // The cartoon style over the host's frame: the field's framebuffer draws to two buffers, and
  // draw buffer 1's mask and blending (the host's) are put back after it.
  media::Settings cs;
  cs.style = media::Style::kCartoon;
  auto cartoonRenderer = media::Renderer::create(cs);
  ASSERT_OK(cartoonRenderer);
  auto cartoon = media::cartoonCompose(cs);
  ASSERT_OK(cartoon);
  auto cartoonHost = media::HostLayers::create(kPx, kPx, 0.5f);
  ASSERT_OK(cartoonHost);
  ASSERT_OK((*cartoonHost)->resolveHostDepth(single, hostFrame));
  (*cartoonHost)->beginMedia(media::Style::kCartoon);
  (*cartoonRenderer)->draw((*cartoonHost)->layerFrame(f), ps, media::Method::kSpherical, (*cartoonHost)->mediaDepth());
  const unsigned cf = b.cartoonFirst;
  check({"HostLayers::composeOver(cartoon)",
         [&] { EXPECT_OK((*cartoonHost)->composeOver(out.get(), vp, f, lights, media::ComposeSettings{}, &*cartoon)); },
         Keys{"fbo.draw", "viewport", ubo(b.composeBlock), ubo(b.cartoonBlock), "blend_func[0]", "blend_eq[0]"} +
             kStencilRefReads + kFullscreen + kNoProgram + texture(b.opaqueDepth, "2D") + texture(b.mediaLayer, "2D") +
             texture(b.mediaDepth, "2D") + texture(b.shimmer, "2D") + texture(cf, "2D") + texture(cf + 1, "2D") +
             texture(cf + 2, "2D")},
        target, host);
}

}  // namespace
}  // namespace puff::host_state_test
