// A host's own GL for the embedding tests: the depth conventions a game may keep, their
// projections and closed-form window depths, glClipControl scoped, a target with the depth format
// the host chooses, and a program from the host's own source.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <puff/cel/frame.h>
#include <puff/core/frame.h>
#include <puff/core/gl.h>
#include <puff/gl_api.h>

namespace puff::test {

using cel::ClipDepth;
using cel::DepthConvention;

// ---- conventions -------------------------------------------------------------------------------

inline constexpr float kNear = 0.1f, kFar = 100.0f, kFovY = 40.0f;

enum class Far { kFinite, kInfinite };

struct Convention {
  const char* name;
  DepthConvention depth;
  ClipDepth clip;
  Far far = Far::kFinite;
  bool orthographic = false;
};

// Every convention a host may keep: the paper's linear, standard in both clip z ranges, reversed-z
// with a finite and an infinite far plane, and orthographic standard and reversed.
inline const Convention kLinear{"linear", DepthConvention::kLinear, ClipDepth::kNegativeOneToOne};
inline const Convention kStandardNO{"standard_-1_1", DepthConvention::kStandard, ClipDepth::kNegativeOneToOne};
inline const Convention kStandardZO{"standard_0_1", DepthConvention::kStandard, ClipDepth::kZeroToOne};
inline const Convention kReversed{"reversed_z", DepthConvention::kReversedZ, ClipDepth::kZeroToOne};
inline const Convention kReversedInfinite{"reversed_z_infinite", DepthConvention::kReversedZ, ClipDepth::kZeroToOne,
                                          Far::kInfinite};
inline const Convention kOrthoStandard{"ortho_standard", DepthConvention::kStandard, ClipDepth::kNegativeOneToOne,
                                       Far::kFinite, true};
inline const Convention kOrthoReversed{"ortho_reversed_z", DepthConvention::kReversedZ, ClipDepth::kZeroToOne,
                                       Far::kFinite, true};

// The projection a host keeps for `c` (square viewport): glm's for the standard ones; reversed-z
// is the [0, 1] projection with near and far swapped, and its infinite-far limit by hand.
inline glm::mat4 projection(const Convention& c, float orthoHeight = 4.0f) {
  if (c.orthographic) {
    const float h = 0.5f * orthoHeight;
    if (c.depth == DepthConvention::kReversedZ) return glm::orthoRH_ZO(-h, h, -h, h, kFar, kNear);
    return c.clip == ClipDepth::kZeroToOne ? glm::orthoRH_ZO(-h, h, -h, h, kNear, kFar)
                                           : glm::orthoRH_NO(-h, h, -h, h, kNear, kFar);
  }
  const float fov = glm::radians(kFovY);
  if (c.depth == DepthConvention::kReversedZ) {
    if (c.far == Far::kFinite) return glm::perspectiveRH_ZO(fov, 1.0f, kFar, kNear);
    // clip z = near, w = -z_view: ndc = near / distance, 1 at the near plane, 0 at infinity.
    const float f = 1.0f / std::tan(0.5f * fov);
    glm::mat4 p(0.0f);
    p[0][0] = f;
    p[1][1] = f;
    p[2][3] = -1.0f;
    p[3][2] = kNear;
    return p;
  }
  return c.clip == ClipDepth::kZeroToOne ? glm::perspectiveRH_ZO(fov, 1.0f, kNear, kFar)
                                         : glm::perspectiveRH_NO(fov, 1.0f, kNear, kFar);
}

// The window depth of view distance d in convention `c`, in closed form (double).
inline double closedForm(const Convention& c, double d) {
  const double n = kNear, f = kFar;
  const double linear = (d - n) / (f - n);
  if (c.depth == DepthConvention::kLinear) return linear;
  if (c.orthographic) return c.depth == DepthConvention::kReversedZ ? 1.0 - linear : linear;
  if (c.depth == DepthConvention::kStandard) return f * (d - n) / ((f - n) * d);  // both clip z ranges
  if (c.far == Far::kInfinite) return n / d;
  return n * (f - d) / ((f - n) * d);
}

inline cel::Frame frameFor(const Convention& c, const glm::mat4& view, int size) {
  cel::Frame f;
  f.view = view;
  f.projection = projection(c);
  f.nearPlane = kNear;
  f.farPlane = kFar;  // finite even with the infinite-far projection: linear depth's 1
  f.depth = c.depth;
  f.clipDepth = c.clip;
  f.viewport = {0, 0, size, size};
  return f;
}

// glClipControl for a convention, put back as it was when the scope ends (the GL context is shared
// with the other suites).
class ClipControlScope {
 public:
  explicit ClipControlScope(ClipDepth clip) {
    glGetIntegerv(GL_CLIP_ORIGIN, &origin_);
    glGetIntegerv(GL_CLIP_DEPTH_MODE, &mode_);
    glClipControl(GL_LOWER_LEFT, clip == ClipDepth::kZeroToOne ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
  }
  ~ClipControlScope() { glClipControl(static_cast<GLenum>(origin_), static_cast<GLenum>(mode_)); }
  ClipControlScope(const ClipControlScope&) = delete;
  ClipControlScope& operator=(const ClipControlScope&) = delete;

 private:
  GLint origin_ = GL_LOWER_LEFT, mode_ = GL_NEGATIVE_ONE_TO_ONE;
};

// ---- the host's own GL: a target with the depth format it chooses, and its own program ---------

// Colour RGBA16F (scene-linear, as the cel programs write) and a depth + stencil attachment of
// `depthFormat`: GL_DEPTH24_STENCIL8, or GL_DEPTH32F_STENCIL8 (the usual reversed-z buffer). Both
// are textures, as a game keeps them when it samples its depth (Puff's media path reads it).
class HostTarget {
 public:
  HostTarget(int size, GLenum depthFormat, GLenum colorFormat = GL_RGBA16F)
      : size_(size),
        fbo_(core::makeFramebuffer()),
        color_(core::makeTexture(GL_TEXTURE_2D)),
        depth_(core::makeTexture(GL_TEXTURE_2D)) {
    glTextureStorage2D(color_.get(), 1, colorFormat, size, size);
    glTextureStorage2D(depth_.get(), 1, depthFormat, size, size);
    glNamedFramebufferTexture(fbo_.get(), GL_COLOR_ATTACHMENT0, color_.get(), 0);
    glNamedFramebufferTexture(fbo_.get(), GL_DEPTH_STENCIL_ATTACHMENT, depth_.get(), 0);
  }
  bool complete() const { return glCheckNamedFramebufferStatus(fbo_.get(), GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE; }
  GLuint framebuffer() const { return fbo_.get(); }
  GLuint depthTexture() const { return depth_.get(); }
  // Binds, sets the viewport, clears colour (scene-linear), depth and stencil 0.
  void bindAndClear(const glm::vec3& linearColor, float depth) const {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.get());
    glViewport(0, 0, size_, size_);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glStencilMask(0xFF);
    const glm::vec4 c(linearColor, 1.0f);
    glClearNamedFramebufferfv(fbo_.get(), GL_COLOR, 0, &c.x);
    glClearNamedFramebufferfi(fbo_.get(), GL_DEPTH_STENCIL, 0, depth, 0);
  }
  std::vector<glm::vec4> readLinear() const {
    std::vector<glm::vec4> out(static_cast<std::size_t>(size_) * size_);
    glGetTextureImage(color_.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(out.size() * sizeof(glm::vec4)),
                      out.data());
    return out;
  }
  std::vector<float> readDepth() const {
    std::vector<float> out(static_cast<std::size_t>(size_) * size_);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, size_, size_, GL_DEPTH_COMPONENT, GL_FLOAT, out.data());
    return out;
  }

 private:
  int size_;
  core::Framebuffer fbo_;
  core::Texture color_, depth_;
};

// A program from vertex and fragment source; an empty Program (id 0) and a test failure if it
// does not build.
inline core::Program program(const std::string& vs, const std::string& fs) {
  const auto compile = [](GLenum stage, const std::string& src) {
    const GLuint s = glCreateShader(stage);
    const char* text = src.c_str();
    glShaderSource(s, 1, &text, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      std::string log(4096, '\0');
      glGetShaderInfoLog(s, static_cast<GLsizei>(log.size()), nullptr, log.data());
      ADD_FAILURE() << "shader does not compile: " << log.c_str();
    }
    return s;
  };
  const GLuint v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
  core::Program p(glCreateProgram());
  glAttachShader(p.get(), v);
  glAttachShader(p.get(), f);
  glLinkProgram(p.get());
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p.get(), GL_LINK_STATUS, &ok);
  EXPECT_TRUE(ok) << "program does not link";
  return p;
}

/// A frame whose depth is `space` (convention, clip depth, projection, planes): what
/// HostLayers::resolveHostDepth reads of the frame it is given.
inline core::SharedFrame frameIn(const core::DepthSpace& space) {
  core::SharedFrame f;
  f.depth = space.convention;
  f.clipDepth = space.clipDepth;
  f.projection = space.projection;
  f.nearPlane = space.nearPlane;
  f.farPlane = space.farPlane;
  return f;
}

}  // namespace puff::test
