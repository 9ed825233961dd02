// The viewer's drawing: the scene and the panels into the window, reading the window back, presenting it.
#include <puff/gl_api.h>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include <puff/core/gl.h>
#include <puff/core/image.h>
#include <puff/render/view.h>
#include <puff/scene/evaluate.h>
#include <puffview/panels.h>
#include <puffview/viewer.h>

#include "viewer_impl.h"

#include <imgui_internal.h>  // ClosePopupsExceptModals

namespace puff::view {

void Viewer::Impl::makeTarget(glm::ivec2 size, int samples, bool displayValues) {
  fbo = core::makeFramebuffer();
  color = core::makeRenderbuffer();
  depthStencil = core::makeRenderbuffer();
  const int s = samples > 1 ? samples : 0;
  // Scene-linear half floats (docs/colour.md), or the fixed path's 8-bit display values.
  const GLenum format = displayValues ? GL_RGBA8 : GL_RGBA16F;
  glNamedRenderbufferStorageMultisample(color.get(), s, format, size.x, size.y);
  glNamedRenderbufferStorageMultisample(depthStencil.get(), s, GL_DEPTH24_STENCIL8, size.x, size.y);
  glNamedFramebufferRenderbuffer(fbo.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color.get());
  glNamedFramebufferRenderbuffer(fbo.get(), GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depthStencil.get());
  fboWidth = size.x, fboHeight = size.y, fboSamples = samples, fboDisplayValues = displayValues;
  resolveFbo = core::makeFramebuffer();
  resolved = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(resolved.get(), 1, GL_RGBA16F, size.x, size.y);
  glNamedFramebufferTexture(resolveFbo.get(), GL_COLOR_ATTACHMENT0, resolved.get(), 0);
}

void Viewer::drawFrame() {
  Impl& m = *impl_;
  m.context->makeCurrent();
  const glm::ivec2 window = framebufferSize();
  if (window.x <= 0 || window.y <= 0) return;  // minimized
  const cel::Viewport area = imageViewport();
  const glm::ivec2 size(area.width, area.height);

  GLint maxSamples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  const int samples = std::clamp(renderer_->targetNeeds().samples, 1, std::max(1, maxSamples));
  const bool displayValues = renderer_->targetNeeds().displayValues;
  if (!m.fbo || m.fboWidth != size.x || m.fboHeight != size.y || m.fboSamples != samples ||
      m.fboDisplayValues != displayValues) {
    m.makeTarget(size, samples, displayValues);
  }

  glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.get());
  cel::Camera camera;
  if (cameraOverride_) camera = camera_.camera(scene::cameraAt(scene_, frame_));
  render::FrameStats stats;
  auto drawn =
      renderer_->drawFrame(frame_, cel::Viewport{0, 0, size.x, size.y}, &stats, cameraOverride_ ? &camera : nullptr);
  const std::string drawError = drawn ? "" : drawn.error().message;
  if (drawError != drawError_ && !drawError.empty()) setStatus("cannot draw: " + drawError);
  drawError_ = drawError;
  stats_ = stats;

  // Into the window's back buffer: display values as they are, a scene-linear frame resolved and
  // through the scene's view transform.
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  if (!m.viewPass && !displayValues) {
    auto pass = render::ViewPass::create();
    if (!pass) {
      setStatus("cannot show the frame: " + pass.error().message);
      return;
    }
    m.viewPass = std::move(*pass);
  }
  // What the image does not cover (beside the panel, or bars where the window's shape is not the
  // image's) is a plain dark grey.
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDrawBuffer(GL_BACK);
  glViewport(0, 0, window.x, window.y);
  glClearColor(0.11f, 0.11f, 0.12f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  if (displayValues) {
    glBlitNamedFramebuffer(m.fbo.get(), 0, 0, 0, size.x, size.y, area.x, area.y, area.x + size.x, area.y + size.y,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
  } else {
    glBlitNamedFramebuffer(m.fbo.get(), m.resolveFbo.get(), 0, 0, size.x, size.y, 0, 0, size.x, size.y,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDrawBuffer(GL_BACK);
    m.viewPass->draw(m.resolved.get(), area, scene::viewTransformFor(scene_));
  }
  drawUi();
}

void Viewer::drawUi() {
  Impl& m = *impl_;
  m.uiDrawnLastFrame = uiVisible || !fileError_.empty() || !editError_.empty() || quitPrompt_ || diskPrompt_ ||
                       (autosaveOffer_ && !batch_);
  m.uiHoldsKeys = false;
  if (!m.uiDrawnLastFrame) return;
  ImGui::SetCurrentContext(m.imgui);
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  // Esc closes an open popup (a colour picker, a combo), never a prompt; the viewer's own Esc is held
  // while one is open (Impl::uiHoldsKeys).
  if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false) && !quitPrompt_ && !diskPrompt_ &&
      !autosaveOffer_)
    ImGui::ClosePopupsExceptModals();
  if (uiVisible) drawPanels(*this, m.panels);
  drawErrorOverlay(*this);
  drawPrompts();
  const ImGuiIO& io = ImGui::GetIO();
  m.uiHoldsKeys = io.WantCaptureKeyboard || io.WantTextInput || ImGui::IsAnyItemActive() ||
                  ImGui::IsPopupOpen("", ImGuiPopupFlags_AnyPopupId | ImGuiPopupFlags_AnyPopupLevel);
  ImGui::Render();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

Result<core::Image> Viewer::readWindow() {
  const glm::ivec2 size = framebufferSize();
  if (size.x <= 0 || size.y <= 0) return Error{"the window has no pixels (minimized?)"};
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size.x) * size.y * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, size.x, size.y, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
  if (const std::string errors = core::drainGlErrors(); !errors.empty())
    return Error{"GL error while reading the window: " + errors};
  core::Image image(size.x, size.y, 4);
  for (int y = 0; y < size.y; ++y) {
    const unsigned char* row = &bytes[static_cast<std::size_t>(size.y - 1 - y) * size.x * 4];
    for (int x = 0; x < size.x; ++x) {
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = row[x * 4 + c] / 255.0f;
      image.at(x, y, 3) = 1.0f;  // a window is opaque, whatever alpha the visual keeps
    }
  }
  return image;
}

void Viewer::present() {
  Impl& m = *impl_;
  m.context->swapBuffers();
  const double t = Impl::now();
  const double ms = (t - m.lastPresent) * 1000.0;
  m.lastPresent = t;
  frameMs_ = frameMs_ == 0.0 ? ms : 0.9 * frameMs_ + 0.1 * ms;
}

}  // namespace puff::view
