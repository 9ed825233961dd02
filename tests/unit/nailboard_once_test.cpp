// The lit pass shading each pixel once (cel::LitShading::kOncePerPixel: the visibility pre-pass,
// then the screen pass over the rectangle the quads reach) draws what shading every layer draws, at a
// host's offset viewport and with the clip origin at the upper left, perspective and orthographic,
// ink on and off, puffs reaching past the viewport and behind the eye; and the shadowed pass after
// it reads that pre-pass only while it stands for the frame drawn.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/vec3.hpp>

#include <puff/core/colour.h>

#include "nailboard_fixture.h"

namespace puff::nailboard_test {
namespace {

struct Setting {
  const char* name;
  bool perspective;
  cel::Viewport viewport;
  bool upperLeft;  // glClipControl(GL_UPPER_LEFT, ...): window y runs down the clip space's y
  bool outlines;
};

// 80 puffs from a fixed-seed LCG: overlapping, some past the viewport's edges, some tinted.
std::vector<Particle> puffs() {
  std::uint32_t state = 12345u;
  auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
  };
  std::vector<Particle> ps;
  for (int i = 0; i < 80; ++i) {
    Particle p;
    p.position = glm::vec3(-5.0f + 10.0f * next(), -4.0f + 8.0f * next(), -3.0f + 6.0f * next());
    p.size = 0.6f + 1.6f * next();
    p.tint = glm::vec3(0.5f + 0.5f * next(), 1.0f, 0.5f + 0.5f * next());
    ps.push_back(p);
  }
  // One just in front of the eye (its quad reaches behind it: the whole viewport is shaded).
  Particle near;
  near.position = glm::vec3(0.3f, 0.2f, 8.9f);
  near.size = 0.8f;
  ps.push_back(near);
  return ps;
}

class NailboardsOnce : public Nailboards {
 protected:
  cel::Frame frameFor(const Setting& s) const {
    cel::Camera cam;
    cam.position = glm::vec3(0, 0, 10);
    cam.target = glm::vec3(0);
    cam.fovYDegrees = s.perspective ? 60.0f : 0.0f;
    cam.orthoHeight = kWorld;
    cam.nearPlane = 0.5f;
    cam.farPlane = 21.0f;
    cel::Frame f = test::linearFrame(cam, s.viewport.width, s.viewport.height);
    f.viewport = s.viewport;
    f.light.direction = glm::vec3(0.3f, 0.8f, 0.5f);
    f.light.color = core::srgbToLinear(glm::vec3(0.6f));
    f.ambient = core::srgbToLinear(glm::vec3(0.2f));
    return f;
  }
  // The frame drawn one way, colour and depth read back.
  void drawWith(const Setting& s, cel::LitShading shading, std::vector<glm::vec4>& color, std::vector<float>& depth) {
    cel::Style style;
    style.outlines = s.outlines;
    target_->clear(1.0f, glm::vec3(0.9f, 0.95f, 1.0f));
    if (s.upperLeft) glClipControl(GL_UPPER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glViewport(s.viewport.x, s.viewport.y, s.viewport.width, s.viewport.height);
    EXPECT_OK(block_->upload(frameFor(s)));
    ramp_->bind();
    renderer_->upload(puffs());
    renderer_->setLitShading(shading);
    renderer_->drawNailboards(style, cel::ShadePass::kLit);
    renderer_->setLitShading(cel::LitShading::kOncePerPixel);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    color = target_->readColor();
    depth = target_->readDepth();
  }
};

TEST_F(NailboardsOnce, ShadingEachPixelOnceDrawsWhatShadingEveryLayerDraws) {
  const Setting settings[] = {
      // The offset viewport first: Puff's target is made for it (a target made larger before would hide
      // one sized without the viewport's origin).
      {"perspective, offset viewport", true, {16, 40, 96, 48}, false, true},
      {"perspective, whole target", true, {0, 0, kPx, kPx}, false, true},
      {"perspective, clip origin upper left", true, {0, 0, kPx, kPx}, true, true},
      {"perspective, offset, upper left, no ink", true, {24, 8, 80, 100}, true, false},
      {"orthographic, offset viewport", false, {16, 40, 96, 48}, false, true},
  };
  for (const Setting& s : settings) {
    SCOPED_TRACE(s.name);
    std::vector<glm::vec4> once, every;
    std::vector<float> onceDepth, everyDepth;
    drawWith(s, cel::LitShading::kOncePerPixel, once, onceDepth);
    drawWith(s, cel::LitShading::kEveryLayer, every, everyDepth);
    int covered = 0, differ = 0, depthDiffer = 0;
    for (std::size_t i = 0; i < once.size(); ++i) {
      const glm::vec3 d = glm::abs(glm::vec3(once[i]) - glm::vec3(every[i]));
      differ += std::max({d.r, d.g, d.b}) > 1.0f / 255.0f ? 1 : 0;
      depthDiffer += std::abs(onceDepth[i] - everyDepth[i]) > 1e-6f ? 1 : 0;
      covered += everyDepth[i] < 1.0f ? 1 : 0;
    }
    // Outside the viewport nothing is drawn either way; inside, the puffs cover a good part of it.
    EXPECT_GT(covered, s.viewport.width * s.viewport.height / 4);
    // A pixel may change its particle where two tie in depth or the shading point rounds across
    // an edge: a handful, never a region.
    EXPECT_LE(differ, covered / 500) << differ << " of " << covered << " covered pixels differ by more than 1/255";
    EXPECT_LE(depthDiffer, covered / 500);
  }
  EXPECT_EQ(core::drainGlErrors(), "");
}

// The shadowed pass shades the lit pass's pre-pass once per pixel only while it stands for the frame
// drawn: after another upload, another frame block or a lit pass drawn every layer, it draws every
// layer, as a renderer that never shades once draws it.
TEST_F(NailboardsOnce, TheShadowedPassReadsTheLitPassesPrePassOnlyForTheSameFrame) {
  const Setting s{"perspective", true, {0, 0, kPx, kPx}, false, true};
  const cel::Style style;
  cel::Frame moved = frameFor(s);
  moved.view = glm::translate(moved.view, glm::vec3(0.7f, 0.0f, 0.0f));
  std::vector<Particle> shifted = puffs();
  for (Particle& p : shifted) p.position.y += 0.4f;
  struct Change {
    const char* name;
    std::function<void()> between;
  };
  const Change changes[] = {
      {"another upload", [&] { renderer_->upload(shifted); }},
      {"another frame block", [&] { EXPECT_OK(block_->upload(moved)); }},
      {"a lit pass drawn every layer",
       [&] {
         renderer_->setLitShading(cel::LitShading::kEveryLayer);
         renderer_->drawNailboards(style, cel::ShadePass::kLit);
         renderer_->setLitShading(cel::LitShading::kOncePerPixel);
       }},
  };
  // And without a change it does read it (one draw: the screen pass), drawing what the shadowed
  // quads draw.
  {
    auto shadowedFrame = [&](cel::LitShading shading, std::size_t* draws) {
      target_->clear(1.0f);
      EXPECT_OK(block_->upload(frameFor(s)));
      ramp_->bind();
      renderer_->upload(puffs());
      renderer_->setLitShading(shading);
      renderer_->drawNailboards(style, cel::ShadePass::kLit);
      target_->fillStencil(0, 0, kPx, kPx, 1);
      *draws = renderer_->drawNailboards(style, cel::ShadePass::kShadowed).drawCalls;
      renderer_->setLitShading(cel::LitShading::kOncePerPixel);
      return target_->readColor();
    };
    std::size_t onceDraws = 0, everyDraws = 0;
    const auto once = shadowedFrame(cel::LitShading::kOncePerPixel, &onceDraws);
    const auto every = shadowedFrame(cel::LitShading::kEveryLayer, &everyDraws);
    EXPECT_EQ(onceDraws, 1u);
    EXPECT_EQ(everyDraws, 1u);
    int differ = 0, covered = 0;
    for (std::size_t i = 0; i < once.size(); ++i) {
      const glm::vec3 d = glm::abs(glm::vec3(once[i]) - glm::vec3(every[i]));
      differ += std::max({d.r, d.g, d.b}) > 1.0f / 255.0f ? 1 : 0;
      covered += every[i] != glm::vec4(1.0f) ? 1 : 0;
    }
    EXPECT_GT(covered, kPx * kPx / 4);
    EXPECT_LE(differ, covered / 500) << differ << " of " << covered << " pixels differ by more than 1/255";
  }
  for (const Change& c : changes) {
    SCOPED_TRACE(c.name);
    // The same lit pass (once per pixel), the change, then the shadowed pass as the renderer picks
    // it, or drawn every layer (setLitShading, which also forgets the pre-pass).
    auto frame = [&](cel::LitShading shadowed) {
      target_->clear(1.0f);
      EXPECT_OK(block_->upload(frameFor(s)));
      ramp_->bind();
      renderer_->upload(puffs());
      renderer_->drawNailboards(style, cel::ShadePass::kLit);
      c.between();
      if (shadowed == cel::LitShading::kEveryLayer) renderer_->setLitShading(shadowed);
      target_->fillStencil(0, 0, kPx, kPx, 1);  // all in shadow: the pass redraws what it passes
      renderer_->drawNailboards(style, cel::ShadePass::kShadowed);
      renderer_->setLitShading(cel::LitShading::kOncePerPixel);
      return target_->readColor();
    };
    const auto picked = frame(cel::LitShading::kOncePerPixel), every = frame(cel::LitShading::kEveryLayer);
    int differ = 0;
    for (std::size_t i = 0; i < picked.size(); ++i) differ += glm::vec3(picked[i]) != glm::vec3(every[i]) ? 1 : 0;
    EXPECT_EQ(differ, 0) << "the shadowed pass read a pre-pass drawn for another frame";
  }
  EXPECT_EQ(core::drainGlErrors(), "");
}

// kAuto shades once where the quads stack (two draws: the pre-pass and the screen pass) and every
// layer where they do not (one): a hundred puffs 1.6 px across in a 32 px square stack deep only
// with the quads their ink grows them to; four puffs far apart do not stack at all.
TEST_F(NailboardsOnce, AutoShadesOnceWhereTheQuadsStack) {
  const Setting s{"orthographic", false, {0, 0, kPx, kPx}, false, true};
  auto draws = [&](const std::vector<Particle>& ps) {
    target_->clear(1.0f);
    EXPECT_OK(block_->upload(frameFor(s)));
    ramp_->bind();
    renderer_->upload(ps);
    renderer_->setLitShading(cel::LitShading::kAuto);
    const std::size_t n = renderer_->drawNailboards(cel::Style{}, cel::ShadePass::kLit).drawCalls;
    renderer_->setLitShading(cel::LitShading::kOncePerPixel);
    return n;
  };
  std::vector<Particle> tiny;
  for (int i = 0; i < 100; ++i) {
    Particle p;
    p.position = glm::vec3(-1.0f + 0.2f * static_cast<float>(i % 10), -1.0f + 0.2f * static_cast<float>(i / 10),
                           0.01f * static_cast<float>(i));
    p.size = 0.1f;
    tiny.push_back(p);
  }
  EXPECT_EQ(draws(tiny), 2u) << "tiny puffs whose ink-grown quads stack: once per pixel";
  std::vector<Particle> apart;
  for (int i = 0; i < 4; ++i) {
    Particle p;
    p.position = glm::vec3(i % 2 == 0 ? -3.0f : 3.0f, i < 2 ? -3.0f : 3.0f, 0.0f);
    p.size = 0.6f;
    apart.push_back(p);
  }
  EXPECT_EQ(draws(apart), 1u) << "puffs far apart: every layer";
  EXPECT_EQ(core::drainGlErrors(), "");
  // Nothing read back: finish the work, which OSMesa would otherwise still run while the suite's
  // context is torn down at exit (a crash in OSMesaMakeCurrent).
  glFinish();
}

}  // namespace
}  // namespace puff::nailboard_test
