// An offscreen square render target for GL tests and benchmarks: a colour renderbuffer and a
// 24-bit depth + 8-bit stencil renderbuffer, with readback helpers. Needs a current GL context.
// Colour: the cel programs write scene-linear values (docs/colour.md), so the target is RGBA16F;
// clear() takes and readColor() gives DISPLAY values (sRGB-encoded, what Eq. 2 and a viewer speak),
// readLinear() the scene-linear values as stored.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec4.hpp>

#include <puff/core/colour.h>
#include <puff/core/gl.h>
#include <puff/core/image.h>
#include <puff/gl_api.h>

namespace puff::test {

class OffscreenTarget {
 public:
  explicit OffscreenTarget(int size, GLenum colorFormat = GL_RGBA16F)
      : size_(size), fbo_(core::makeFramebuffer()), color_(core::makeRenderbuffer()), depth_(core::makeRenderbuffer()) {
    glNamedRenderbufferStorage(color_.get(), colorFormat, size, size);
    glNamedRenderbufferStorage(depth_.get(), GL_DEPTH24_STENCIL8, size, size);
    glNamedFramebufferRenderbuffer(fbo_.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_.get());
    glNamedFramebufferRenderbuffer(fbo_.get(), GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_.get());
  }

  int size() const { return size_; }
  bool complete() const { return glCheckNamedFramebufferStatus(fbo_.get(), GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE; }

  /// Binds the target for drawing and sets the viewport to all of it.
  void bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.get());
    glViewport(0, 0, size_, size_);
  }

  /// Binds, then clears colour (a display value, stored decoded), depth and stencil (write masks and
  /// scissor reset first).
  void clear(const glm::vec4& display, float depth = 1.0f, int stencil = 0) const {
    const glm::vec4 color(core::srgbToLinear(glm::vec3(display)), display.a);
    bind();
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glStencilMask(0xFF);
    glClearNamedFramebufferfv(fbo_.get(), GL_COLOR, 0, &color.x);
    glClearNamedFramebufferfi(fbo_.get(), GL_DEPTH_STENCIL, 0, depth, stencil);
  }

  /// Sets the stencil to `value` inside a rectangle (GL pixel coordinates, origin bottom-left).
  void fillStencil(int x, int y, int w, int h, int value) const {
    glEnable(GL_SCISSOR_TEST);
    glScissor(x, y, w, h);
    glStencilMask(0xFF);
    glClearNamedFramebufferiv(fbo_.get(), GL_STENCIL, 0, &value);
    glDisable(GL_SCISSOR_TEST);
  }

  /// Colour as display values (RGB sRGB-encoded, alpha as stored), row 0 at the bottom (GL order):
  /// index y * size + x.
  std::vector<glm::vec4> readColor() const {
    std::vector<glm::vec4> out = readLinear();
    for (glm::vec4& c : out) c = glm::vec4(core::linearToSrgb(glm::vec3(c)), c.a);
    return out;
  }
  /// Colour as stored (scene-linear), row 0 at the bottom.
  std::vector<glm::vec4> readLinear() const {
    std::vector<glm::vec4> out(count());
    glNamedFramebufferReadBuffer(fbo_.get(), GL_COLOR_ATTACHMENT0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, size_, size_, GL_RGBA, GL_FLOAT, out.data());
    return out;
  }
  std::vector<float> readDepth() const {
    std::vector<float> out(count());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, size_, size_, GL_DEPTH_COMPONENT, GL_FLOAT, out.data());
    return out;
  }
  std::vector<unsigned char> readStencil() const {
    std::vector<unsigned char> out(count());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, size_, size_, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, out.data());
    return out;
  }
  /// Colour as an RGB image, row 0 at the top (for writing a file).
  core::Image readImage() const {
    const std::vector<glm::vec4> px = readColor();
    core::Image im(size_, size_, 3);
    for (int y = 0; y < size_; ++y) {
      for (int x = 0; x < size_; ++x) {
        for (int c = 0; c < 3; ++c) im.at(x, size_ - 1 - y, c) = px[static_cast<std::size_t>(y) * size_ + x][c];
      }
    }
    return im;
  }

 private:
  std::size_t count() const { return static_cast<std::size_t>(size_) * size_; }
  int size_;
  core::Framebuffer fbo_;
  core::Renderbuffer color_, depth_;
};

}  // namespace puff::test
