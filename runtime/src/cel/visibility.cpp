#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "visibility.h"

namespace puff::cel::detail {

namespace {

// The size of a target spanning `viewport` from the framebuffer's origin, so that its pixels are the
// host's pixels at the same viewport.
std::pair<int, int> spanFromOrigin(const core::Viewport& viewport) {
  return {std::max(1, viewport.x + viewport.width), std::max(1, viewport.y + viewport.height)};
}

}  // namespace

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

float depthStep(GLenum format) {
  switch (format) {
    case GL_DEPTH_COMPONENT16:
      return 1.0f / 65535.0f;
    case GL_DEPTH_COMPONENT24:
      return 1.0f / 16777215.0f;
    case GL_DEPTH_COMPONENT32:
      return 1.0f / 4294967295.0f;
    default:
      return 1.0f / 16777216.0f;
  }
}

double reachedPixels(const glm::mat4& viewProjection, const glm::vec3& lo, const glm::vec3& hi, float padPixels,
                     const core::Viewport& viewport) {
  const double whole = static_cast<double>(viewport.width) * static_cast<double>(viewport.height);
  glm::vec2 a(1e30f), b(-1e30f);
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    const glm::vec4 clip = viewProjection * glm::vec4(c, 1.0f);
    if (clip.w <= 1e-6f) return whole;
    a = glm::min(a, glm::vec2(clip) / clip.w);
    b = glm::max(b, glm::vec2(clip) / clip.w);
  }
  const glm::vec2 pad(2.0f * padPixels / static_cast<float>(std::max(1, viewport.width)),
                      2.0f * padPixels / static_cast<float>(std::max(1, viewport.height)));
  a = glm::max(a - pad, glm::vec2(-1.0f));
  b = glm::min(b + pad, glm::vec2(1.0f));
  if (b.x <= a.x || b.y <= a.y) return 0.0;
  return 0.25 * static_cast<double>(b.x - a.x) * static_cast<double>(b.y - a.y) * whole;
}

double quadPixels(std::span<const glm::vec4> drawn, std::size_t stride, float halfCell, float bandPixels,
                  const glm::mat4& viewProjection, float scaleY, const core::Viewport& viewport) {
  const double whole = static_cast<double>(viewport.width) * static_cast<double>(viewport.height);
  const double pxPerNdc = 0.5 * static_cast<double>(viewport.height);
  double sum = 0.0;
  stride = std::max<std::size_t>(stride, 1);
  for (std::size_t i = 0; i < drawn.size(); i += stride) {
    const glm::vec4& p = drawn[i];
    const float w = (viewProjection * glm::vec4(glm::vec3(p), 1.0f)).w;
    if (w <= 1e-6f) {
      sum += whole;
      continue;
    }
    const double diameter = static_cast<double>(p.w * std::abs(scaleY) / w) * pxPerNdc;
    const double side = 2.0 * std::max(static_cast<double>(halfCell) * diameter, 0.5 * diameter + bandPixels);
    sum += std::min(side * side, whole);
  }
  return sum * static_cast<double>(stride);
}

bool VisibilityTarget::begin(const core::Viewport& viewport, int samples, GLenum depthFormat,
                             DepthConvention convention) {
  const auto [w, h] = spanFromOrigin(viewport);
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

bool OccluderTarget::begin(const core::Viewport& viewport, DepthConvention convention) {
  const auto [w, h] = spanFromOrigin(viewport);
  if (!fbo_ || w > width_ || h > height_) {
    width_ = std::max(w, width_);
    height_ = std::max(h, height_);
    fbo_ = core::makeFramebuffer("nailboards: hull occluders");
    depth_ = core::makeRenderbuffer("nailboards: hull occluders' depth");
    depths_ = core::makeTexture(GL_TEXTURE_2D, "nailboards: hull occluders' view depths");
    glTextureStorage2D(depths_.get(), 1, GL_R32F, width_, height_);
    glTextureParameteri(depths_.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(depths_.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glNamedRenderbufferStorage(depth_.get(), GL_DEPTH_COMPONENT32F, width_, height_);
    glNamedFramebufferTexture(fbo_.get(), GL_COLOR_ATTACHMENT0, depths_.get(), 0);
    glNamedFramebufferRenderbuffer(fbo_.get(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_.get());
    glNamedFramebufferDrawBuffer(fbo_.get(), GL_COLOR_ATTACHMENT0);
    complete_ = glCheckNamedFramebufferStatus(fbo_.get(), GL_DRAW_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  }
  if (!complete_) return false;
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_.get());
  const float none[4] = {kNone, 0.0f, 0.0f, 0.0f};
  const float far = clearDepth(convention);
  glClearNamedFramebufferfv(fbo_.get(), GL_COLOR, 0, none);
  glClearNamedFramebufferfv(fbo_.get(), GL_DEPTH, 0, &far);
  return true;
}

}  // namespace puff::cel::detail
