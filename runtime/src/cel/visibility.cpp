#include <algorithm>

#include "visibility.h"

namespace puff::cel::detail {

GLenum hostDepthFormat(GLuint framebuffer) {
  const GLenum attachment = framebuffer == 0 ? GL_DEPTH : GL_DEPTH_ATTACHMENT;
  GLint type = GL_NONE, bits = 0, component = GL_NONE;
  glGetNamedFramebufferAttachmentParameteriv(framebuffer, attachment, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
  if (type == GL_NONE) return GL_DEPTH_COMPONENT32F;
  glGetNamedFramebufferAttachmentParameteriv(framebuffer, attachment, GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE, &bits);
  glGetNamedFramebufferAttachmentParameteriv(framebuffer, attachment, GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE,
                                             &component);
  if (component == GL_UNSIGNED_NORMALIZED && bits == 16) return GL_DEPTH_COMPONENT16;
  if (component == GL_UNSIGNED_NORMALIZED && bits == 24) return GL_DEPTH_COMPONENT24;
  if (component == GL_UNSIGNED_NORMALIZED && bits == 32) return GL_DEPTH_COMPONENT32;
  return GL_DEPTH_COMPONENT32F;
}

bool VisibilityTarget::begin(const core::Viewport& viewport, int samples, GLenum depthFormat,
                             DepthConvention convention) {
  const int w = std::max(1, viewport.x + viewport.width), h = std::max(1, viewport.y + viewport.height);
  if (!fbo_ || w > width_ || h > height_ || samples != samples_ || depthFormat != depthFormat_) {
    const bool same = samples == samples_ && depthFormat == depthFormat_;
    width_ = std::max(w, same ? width_ : 0);
    height_ = std::max(h, same ? height_ : 0);
    samples_ = samples;
    depthFormat_ = depthFormat;
    fbo_ = core::makeFramebuffer("nailboards: visibility");
    depth_ = core::makeRenderbuffer("nailboards: visibility depth");
    if (samples > 1) {
      // Fixed sample locations, as a renderbuffer beside it has.
      ids_ = core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE, "nailboards: visible ids and depths");
      glTextureStorage2DMultisample(ids_.get(), samples, GL_RG32UI, width_, height_, GL_TRUE);
      glNamedRenderbufferStorageMultisample(depth_.get(), samples, depthFormat, width_, height_);
    } else {
      ids_ = core::makeTexture(GL_TEXTURE_2D, "nailboards: visible ids and depths");
      glTextureStorage2D(ids_.get(), 1, GL_RG32UI, width_, height_);
      glTextureParameteri(ids_.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTextureParameteri(ids_.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glNamedRenderbufferStorage(depth_.get(), depthFormat, width_, height_);
    }
    glNamedFramebufferTexture(fbo_.get(), GL_COLOR_ATTACHMENT0, ids_.get(), 0);
    glNamedFramebufferRenderbuffer(fbo_.get(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_.get());
    glNamedFramebufferDrawBuffer(fbo_.get(), GL_COLOR_ATTACHMENT0);
    complete_ = glCheckNamedFramebufferStatus(fbo_.get(), GL_DRAW_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  }
  if (!complete_) return false;
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_.get());
  const GLuint none[4] = {0, 0, 0, 0};
  const float far = clearDepth(convention);
  glClearNamedFramebufferuiv(fbo_.get(), GL_COLOR, 0, none);
  glClearNamedFramebufferfv(fbo_.get(), GL_DEPTH, 0, &far);
  return true;
}

}  // namespace puff::cel::detail
