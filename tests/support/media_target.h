// What the media tests share: a float media layer with an R32F linear-depth texture of the same
// size (a "wall" is that texture filled with a known depth), a camera at the origin looking down
// -z with the exact ray through each pixel centre, and a material for which the closed form holds
// (albedo 1, no detail perturbation). Needs a current GL 4.5 context.
#pragma once

#include <cmath>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/vec4.hpp>

#include <puff/core/gl.h>
#include <puff/gl_api.h>
#include <puff/media/media.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"

namespace puff::test {

struct MediaTarget {
  core::Framebuffer fbo = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D), depth = core::makeTexture(GL_TEXTURE_2D);
  int size;
  /// A size x size RGBA32F layer; the depth starts at 1 (no surface).
  explicit MediaTarget(int s) : size(s) {
    glTextureStorage2D(color.get(), 1, GL_RGBA32F, s, s);
    glTextureStorage2D(depth.get(), 1, GL_R32F, s, s);
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
    setDepth(1.0f);
  }
  /// Linear depth per pixel, row 0 at the bottom.
  void setDepth(const std::vector<float>& linear) const {
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(depth.get(), 0, 0, 0, size, size, GL_RED, GL_FLOAT, linear.data());
  }
  void setDepth(float linear) const { setDepth(std::vector<float>(static_cast<std::size_t>(size) * size, linear)); }
  void clear(const glm::vec4& c) const { glClearNamedFramebufferfv(fbo.get(), GL_COLOR, 0, &c.x); }
  void bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.get());
    glViewport(0, 0, size, size);
  }
  /// RGBA floats, row 0 at the bottom: index y * size + x.
  std::vector<glm::vec4> read() const {
    std::vector<glm::vec4> out(static_cast<std::size_t>(size) * size);
    glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(out.size() * sizeof(glm::vec4)),
                      out.data());
    return out;
  }
};

/// At the origin looking down -z, square viewport; light off, ambient 1 (scattered radiance = the
/// material's colour times its albedo).
struct MediaCamera {
  float nearPlane = 0.5f, farPlane = 50.0f, fovDegrees = 40.0f;
  media::Frame frame(int size) const {
    media::Frame f;
    f.view = glm::mat4(1.0f);
    f.projection = glm::perspective(glm::radians(fovDegrees), 1.0f, nearPlane, farPlane);
    f.nearPlane = nearPlane;
    f.farPlane = farPlane;
    f.viewport.width = f.viewport.height = size;
    f.light.color = glm::vec3(0.0f);
    f.ambient = glm::vec3(1.0f);
    return f;
  }
  /// The linear depth of a surface `distance` along the view axis.
  float linear(float distance) const { return (distance - nearPlane) / (farPlane - nearPlane); }
  /// The unit ray through pixel (x, y)'s centre (row 0 at the bottom), camera space.
  glm::dvec3 ray(int x, int y, int size) const {
    const double t = std::tan(glm::radians(static_cast<double>(fovDegrees)) / 2.0);
    const double nx = (x + 0.5) / size * 2.0 - 1.0, ny = (y + 0.5) / size * 2.0 - 1.0;
    return glm::normalize(glm::dvec3(nx * t, ny * t, -1.0));
  }
};

/// Albedo 1, extinction `tau`, no detail perturbation: the closed form holds exactly.
inline media::Material plainMaterial(float tau) {
  media::Material m;
  m.name = "plain";
  m.albedo = 1.0f;
  m.density = tau;
  m.detail = 0.0f;
  return m;
}

inline media::Particle sphereAt(glm::vec3 centre, float radius) {
  media::Particle p;
  p.position = centre;
  p.radius = radius;
  p.material = 0;
  return p;
}

/// A suite of GL tests sharing one media::Renderer (default settings), made on first use.
class MediaRendererTest : public GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    if (!renderer_) {
      auto r = media::Renderer::create();
      ASSERT_OK(r);
      renderer_ = std::move(*r);
    }
  }
  static void TearDownTestSuite() {
    renderer_.reset();  // before the context goes
    GlTest::TearDownTestSuite();
  }
  static inline std::unique_ptr<media::Renderer> renderer_;
};

}  // namespace puff::test
