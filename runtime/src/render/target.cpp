#include "target.h"
#include <puff/gl_api.h>

#include <algorithm>
#include <string>

namespace puff::render::detail {

namespace {

Result<Target> make(int w, int h, int samples, bool displayValues, bool data) {
  Target t;
  t.displayValues = displayValues;
  const GLenum format = displayValues ? GL_RGBA8 : data ? GL_RGBA32F : GL_RGBA16F;
  t.width = w;
  t.height = h;
  GLint maxSamples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  if (samples > maxSamples) {
    return Error{std::to_string(samples) + " samples per pixel asked, but this GL gives at most " +
                 std::to_string(maxSamples) + " (set /output/samples or --samples lower)"};
  }
  t.samples = std::max(1, samples);
  t.fbo = core::makeFramebuffer("frame target");
  t.color = core::makeRenderbuffer("frame target: colour");
  t.depthStencil = core::makeRenderbuffer("frame target: depth and stencil");
  const int s = t.samples > 1 ? t.samples : 0;
  glNamedRenderbufferStorageMultisample(t.color.get(), s, format, w, h);
  glNamedRenderbufferStorageMultisample(t.depthStencil.get(), s, GL_DEPTH24_STENCIL8, w, h);
  glNamedFramebufferRenderbuffer(t.fbo.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t.color.get());
  glNamedFramebufferRenderbuffer(t.fbo.get(), GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, t.depthStencil.get());
  if (glCheckNamedFramebufferStatus(t.fbo.get(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    return Error{"render target of " + std::to_string(w) + "x" + std::to_string(h) + " with " +
                 std::to_string(t.samples) + " samples is not supported by this GL"};
  }
  if (t.samples > 1) {
    t.resolveFbo = core::makeFramebuffer("frame target: resolved");
    t.resolveColor = core::makeRenderbuffer("frame target: resolved colour");
    glNamedRenderbufferStorage(t.resolveColor.get(), format, w, h);
    glNamedFramebufferRenderbuffer(t.resolveFbo.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t.resolveColor.get());
  }
  return t;
}

}  // namespace

Result<Target> Target::create(int w, int h, int samples, bool displayValues) {
  return make(w, h, samples, displayValues, false);
}

Result<Target> Target::createData(int w, int h, int samples) { return make(w, h, samples, false, true); }

Target Target::contextOwn(int width, int height) {
  Target t;
  t.width = width;
  t.height = height;
  t.contextFramebuffer = true;
  t.displayValues = true;  // GL 1.x: 8-bit, display values
  return t;
}

}  // namespace puff::render::detail
