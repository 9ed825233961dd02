// The offscreen target a SceneRenderer draws into and reads frames back from. Private to puff::render.
#pragma once

#include <puff/core/error.h>
#include <puff/core/gl.h>

namespace puff::render::detail {

// Colour + depth/stencil, multisampled when asked, with a single-sample resolve target to read
// back from. Colour is RGBA16F scene-linear, or RGBA8 display values for a path that writes those
// (TargetNeeds::displayValues).
struct Target {
  int width = 0, height = 0, samples = 1;
  /// No framebuffer objects in this context (GL before 4.5's direct state access: the fixed path
  /// in an old context): frames go to the context's own framebuffer, which must be at least this
  /// size (puffrender creates it so).
  bool contextFramebuffer = false;
  bool displayValues = false;  ///< RGBA8 holding display values (else RGBA16F scene-linear)
  core::Framebuffer fbo, resolveFbo;
  core::Renderbuffer color, depthStencil, resolveColor;

  /// Errors: more samples than this GL gives, or a size it does not support.
  static Result<Target> create(int width, int height, int samples, bool displayValues = false);
  /// An RGBA32F target for maps (data), otherwise as create.
  static Result<Target> createData(int width, int height, int samples);
  /// The context's own framebuffer, `width` x `height` of it.
  static Target contextOwn(int width, int height);
};

}  // namespace puff::render::detail
