// The layers' passes over the media's coverage (LayersBase::setCoverage) and the cartoon style's passes.
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <puff/core/bind_points.h>

#include "layers_impl.h"

namespace puff::media {

void LayersBase::Impl::composeWithin(GLuint program, const PixelBox& box, const core::Viewport& viewport) {
  if (!covered || wholeFrame(box)) {
    drawCompose(program);
    return;
  }
  copyAround(box, viewport);
  if (box.empty()) return;
  scissorTo(box, viewport.x, viewport.y);
  drawCompose(program);
  glDisable(GL_SCISSOR_TEST);
}

void LayersBase::Impl::copyAround(const PixelBox& box, const core::Viewport& viewport) {
  for (const PixelBox& strip : around(PixelBox{0, 0, width, height}, box)) {
    scissorTo(strip, viewport.x, viewport.y);
    drawCompose(copy.get());
  }
  glDisable(GL_SCISSOR_TEST);
}

void LayersBase::Impl::makeCartoon() {
  if (cartoonMade) return;
  cartoonFire = makeTexture2D(GL_RGBA32F, mediaWidth, mediaHeight, GL_NEAREST, "cartoon media: fire");
  cartoonDepth = makeTexture2D(GL_RGBA32F, mediaWidth, mediaHeight, GL_NEAREST, "cartoon media: depth");
  glNamedFramebufferTexture(mediaFbo.get(), GL_COLOR_ATTACHMENT2, cartoonFire.get(), 0);
  glNamedFramebufferTexture(mediaFbo.get(), GL_COLOR_ATTACHMENT3, cartoonDepth.get(), 0);
  fill = makeTexture2D(GL_RGBA16F, width, height, GL_NEAREST, "cartoon media: fill");
  field = makeTexture2D(GL_RGBA32F, width, height, GL_NEAREST, "cartoon media: field");
  fieldFbo = core::makeFramebuffer("cartoon media: field");
  glNamedFramebufferTexture(fieldFbo.get(), GL_COLOR_ATTACHMENT0, fill.get(), 0);
  glNamedFramebufferTexture(fieldFbo.get(), GL_COLOR_ATTACHMENT1, field.get(), 0);
  const GLenum two[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(fieldFbo.get(), 2, two);
  for (int i = 0; i < 2; ++i) {
    seeds[i] = makeTexture2D(GL_RGBA32UI, width, height, GL_NEAREST, "cartoon media: ink seeds");
    seedFbo[i] = core::makeFramebuffer("cartoon media: ink seeds");
    glNamedFramebufferTexture(seedFbo[i].get(), GL_COLOR_ATTACHMENT0, seeds[i].get(), 0);
  }
  cartoonBlock = core::makeBuffer("cartoon media: block");
  glNamedBufferStorage(cartoonBlock.get(), sizeof(CartoonBlockData), nullptr, GL_DYNAMIC_STORAGE_BIT);
  cartoonMade = true;
}

static std::vector<int> floodSteps(float inkWidth) {
  // A jump-flooding pass of step k carries a seed k pixels; steps 2^j .. 1 reach 2^(j+1) - 1. The
  // field must reach the ink's outer edge and the fill's antialiasing pixel: width + 2.
  int step = 1;
  while (2 * step - 1 < static_cast<int>(std::ceil(inkWidth)) + 2) step *= 2;
  std::vector<int> steps;
  for (; step >= 1; step /= 2) steps.push_back(step);
  steps.push_back(1);  // "JFA+1": one more step of 1 mends most of jump flooding's misses
  return steps;
}

LayersBase::Impl::Boxes LayersBase::Impl::boxes() const {
  Boxes b;
  if (!covered || covered->empty()) return b;  // no media: every box empty
  // A pixel's taps are the layer texels up to 2 away from the one holding it (compose.glsl,
  // mediaTaps); a texel holds media where a billboard covers its centre, inside `covered`.
  b.compose = grow(*covered, 4 * factor + 1, width, height);
  PixelBox reads = b.compose;
  if (coveredStyle == Style::kCartoon) {
    // Seeds lie within a pixel of where A can be above 0, and flooding carries them at most the
    // sum of its steps: past that no pixel holds a seed, and the whole frame's passes draw the
    // opaque colour there. The flooding is exact over `inked` when it runs that far beyond it.
    int reach = 1;
    for (int step : floodSteps(coveredInk)) reach += step;
    b.inked = grow(b.compose, reach + 1, width, height);
    b.flood = grow(b.inked, reach, width, height);
    b.field = grow(b.flood, 2, width, height);  // the seed pass reads the field's gradient
    b.cleared = grow(b.flood, floodSteps(coveredInk).front(), width, height);
    reads = b.field;
  }
  b.layer = grow(PixelBox{reads.x0 / factor, reads.y0 / factor, (reads.x1 + factor - 1) / factor,
                          (reads.y1 + factor - 1) / factor},
                 3, mediaWidth, mediaHeight);
  b.resolve = PixelBox{b.layer.x0 * factor, b.layer.y0 * factor, std::min(width, b.layer.x1 * factor),
                       std::min(height, b.layer.y1 * factor)};
  return b;
}

void LayersBase::Impl::composeCartoon(GLuint target, const core::Viewport& viewport, const CartoonCompose& cartoon,
                                      bool overHost) {
  const core::DebugGroup group("cartoon media: field, ink and compose");
  const CartoonStyle& st = cartoon.style;
  CartoonBlockData d{};
  const float inkWidth = st.outlines ? st.outlineWidth : 0.0f;
  d.style =
      glm::vec4(st.threshold, static_cast<float>(st.opacityBands), static_cast<float>(fireBandCount(st)), inkWidth);
  d.ink = glm::vec4(st.outlineColor, 1.0f);
  for (std::size_t k = 0; k < cartoon.fireColors.size() && k < shader::kMaxFireBands; ++k)
    d.fireColors[k] = glm::vec4(cartoon.fireColors[k], 1.0f);
  glNamedBufferSubData(cartoonBlock.get(), 0, sizeof(d), &d);
  const GLuint blocks[2] = {block.get(), cartoonBlock.get()};
  glBindBuffersBase(GL_UNIFORM_BUFFER, bindings.composeBlock, 1, &blocks[0]);  // multi-bind: the generic binding stays
  glBindBuffersBase(GL_UNIFORM_BUFFER, bindings.cartoonBlock, 1, &blocks[1]);
  fullscreenState(1);
  glBindVertexArray(vao.get());
  const unsigned c = bindings.cartoonFirst;
  if (!overHost) core::bindTextureAndNoSampler(bindings.opaqueColor, color.get());  // a host's colour is not read
  core::bindTextureAndNoSampler(bindings.opaqueDepth, depth.get());
  core::bindTextureAndNoSampler(bindings.mediaLayer, media.get());
  core::bindTextureAndNoSampler(bindings.mediaDepth, mediaDepth.get());
  core::bindTextureAndNoSampler(bindings.shimmer, shimmer.get());

  const Boxes b = boxes();
  if (covered && b.inked.empty()) {  // no media: the opaque colour alone (over a host's, nothing)
    fieldBox = PixelBox{};
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
    glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
    if (!overHost) {
      const core::DrawBufferZero drawBuffers;  // the target's other attachments stay as they are
      copyAround(PixelBox{}, viewport);
    }
    glBindVertexArray(0);
    glUseProgram(0);
    return;
  }
  // 1. The fill and the field at the output's size: two draw buffers, the second's blending and
  // write mask (a host's, global state) put back after.
  GLboolean mask1[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
  glGetBooleani_v(GL_COLOR_WRITEMASK, 1, mask1);
  const GLboolean blend1 = glIsEnabledi(GL_BLEND, 1);
  glDisablei(GL_BLEND, 1);
  glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fieldFbo.get());
  glViewport(0, 0, width, height);
  glUseProgram(cartoonField.get());
  core::bindTextureAndNoSampler(c, cartoonFire.get());
  core::bindTextureAndNoSampler(c + 1, cartoonDepth.get());
  scissorTo(limit(b.field));
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glColorMaski(1, mask1[0], mask1[1], mask1[2], mask1[3]);
  if (blend1) glEnablei(GL_BLEND, 1);
  fieldBox = covered ? b.field : PixelBox{0, 0, width, height};
  // 2. The seeds. With a coverage, the flooding reads up to a step around its box: no seed there.
  if (covered) {
    const GLuint none[4] = {0u, 0u, 0u, 0xffffffffu};  // cartoon.glsl's kNoSeed in w
    for (const PixelBox& r : around(b.cleared, b.flood))
      for (const core::Texture& t : seeds)
        glClearTexSubImage(t.get(), 0, r.x0, r.y0, 0, r.x1 - r.x0, r.y1 - r.y0, 1, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                           none);
  }
  core::bindTextureAndNoSampler(c + 1, field.get());
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, seedFbo[0].get());
  glUseProgram(cartoonSeed.get());
  scissorTo(limit(b.flood));
  glDrawArrays(GL_TRIANGLES, 0, 3);
  // 3. Jump flooding, ping-ponging the seeds.
  int from = 0;
  glUseProgram(cartoonFlood.get());
  for (int step : floodSteps(inkWidth)) {
    core::bindTextureAndNoSampler(c + 2, seeds[from].get());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, seedFbo[1 - from].get());
    glUniform1i(shader::loc::kFloodStep, step);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    from = 1 - from;
  }
  // 4. The fill and the ink over the opaque scene (copied around the ink's box).
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  const core::DrawBufferZero drawBuffers;  // the target's other attachments stay as they are
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  glDisable(GL_SCISSOR_TEST);
  if (covered && !wholeFrame(b.inked) && !overHost) {
    copyAround(b.inked, viewport);
    glBindVertexArray(vao.get());
  }
  // Over a host: dst * src1 + src0 on RGB (cartoon_compose_over.frag, composeOver set the functions);
  // the host's alpha kept.
  if (overHost) glEnablei(GL_BLEND, 0);
  scissorTo(limit(b.inked), viewport.x, viewport.y);
  glUseProgram(overHost ? cartoonComposeOver.get() : cartoonCompose.get());
  core::bindTextureAndNoSampler(c, fill.get());
  core::bindTextureAndNoSampler(c + 2, seeds[from].get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDisable(GL_SCISSOR_TEST);
  if (overHost) glDisablei(GL_BLEND, 0);
  glBindVertexArray(0);
  glUseProgram(0);
}

void LayersBase::setCoverage(std::optional<PixelBox> covered, Style style, float inkPixels) {
  impl_->covered = covered;
  impl_->coveredStyle = style;
  impl_->coveredInk = std::max(0.0f, inkPixels);
}

}  // namespace puff::media
