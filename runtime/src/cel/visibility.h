// Internal: the nailboards' visibility target, Puff's own framebuffer for the lit pass's pre-pass
// (NailboardRenderer::drawNailboards): per pixel the nearest particle's id and the depth it stores,
// for the deferred shading pass that shades that particle alone. Never attached to a host's
// framebuffer.
#pragma once

#include <cstddef>
#include <span>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <puff/cel/frame.h>
#include <puff/core/gl.h>
#include <puff/core/viewport.h>
#include <puff/gl_api.h>

namespace puff::cel::detail {

/// The depth format of `framebuffer`'s depth buffer: GL_DEPTH_COMPONENT16, 24, 32 (normalized) or
/// 32F (float; also when it has none, or one of another kind).
GLenum hostDepthFormat(GLuint framebuffer);

/// One step of a depth buffer of `format` (hostDepthFormat's): 2^-bits for the normalized formats,
/// and for a float one its step just below 1 (2^-24), the coarsest a depth in [0.5, 1] is stored at.
float depthStep(GLenum format);

/// The screen rectangle a batch's quads reach (as shaders/cel/screen_rect.vert draws it): the world
/// box [lo, hi] projected by `viewProjection`, padded by `padPixels`, within `viewport`; all of it
/// where a corner lies at or behind the eye. Its area in pixels (0: off the screen).
double reachedPixels(const glm::mat4& viewProjection, const glm::vec3& lo, const glm::vec3& hi, float padPixels,
                     const core::Viewport& viewport);

/// The quads' summed screen area, pixels: each `drawn` (centre, diameter) a square as
/// shaders/cel/nailboard_vs.glsl sizes it, `halfCell` diameters from its centre or, for a puff so
/// small that its ink band (`bandPixels`) reaches past that, half a diameter and the band, seen at
/// its centre's clip w (`scaleY`: the projection's [1][1]); from every `stride`-th of them, times
/// `stride`. Quads at or behind the eye count as the whole viewport.
double quadPixels(std::span<const glm::vec4> drawn, std::size_t stride, float halfCell, float bandPixels,
                  const glm::mat4& viewProjection, float scaleY, const core::Viewport& viewport);

class VisibilityTarget {
 public:
  /// Makes (or remakes, when the viewport outgrows it or the samples change) a target of `samples`
  /// per pixel spanning `viewport` from the framebuffer's origin, so its pixels are the host's
  /// pixels at the same viewport; binds it as the draw framebuffer and clears it: ids 0, depth
  /// clearDepth(convention). Needs the scissor test and rasterizer discard off, depth and draw
  /// buffer 0's colour writes on (they limit clears).
  /// Its depth buffer is `depthFormat` (hostDepthFormat: the host's, so that two particles tie
  /// where they tie on the host's buffer and the same one wins).
  /// False, binding nothing, where the framebuffer it makes is not complete.
  bool begin(const core::Viewport& viewport, int samples, GLenum depthFormat, DepthConvention convention);
  /// The RG32UI texture (2D, or 2D multisample): x the particle id + 1 (0: none), y the bits of the
  /// float depth stored.
  GLuint texture() const { return ids_.get(); }

 private:
  core::Framebuffer fbo_;
  core::Texture ids_;
  core::Renderbuffer depth_;
  int width_ = 0, height_ = 0, samples_ = 0;
  GLenum depthFormat_ = 0;
  bool complete_ = false;
};

// The tumbling hull's occluders (NailboardRenderer: drawn before the hull, read by its fragments):
// per pixel the view depth of the nearest disc of a hull-drawn puff's core (shaders/cel/hull_occluder.*),
// single-sampled (the discs stop a pixel and a half inside the cores). Puff's own framebuffer, never
// attached to a host's.
class OccluderTarget {
 public:
  /// Makes (or remakes, when the viewport outgrows it) a target spanning `viewport` from the
  /// framebuffer's origin; binds it as the draw framebuffer and clears it: depths kNone, and the depth
  /// buffer clearDepth(convention). Needs what VisibilityTarget::begin needs. False, binding nothing,
  /// where the framebuffer it makes is not complete.
  bool begin(const core::Viewport& viewport, DepthConvention convention);
  /// The R32F texture (2D): view depth, world units; kNone where no disc lies.
  GLuint texture() const { return depths_.get(); }
  static constexpr float kNone = 3.0e38f;

 private:
  core::Framebuffer fbo_;
  core::Texture depths_;
  core::Renderbuffer depth_;
  int width_ = 0, height_ = 0;
  bool complete_ = false;
};

}  // namespace puff::cel::detail
