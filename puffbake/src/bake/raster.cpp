#include <puff/bake/raster.h>

#include <algorithm>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include <puff/core/shader.h>
#include <puff/gl_api.h>

namespace puff::bake {

namespace {
struct Vertex {
  glm::vec3 position, normal, color;
};

// Reads `attachment` of `fbo` (size x size texels of T, `format` floats each) into `dst`, row 0 at
// the top (GL's rows run bottom-up).
template <class T>
void readFlipped(GLuint fbo, GLenum attachment, GLenum format, int size, std::vector<T>& dst) {
  const std::size_t n = static_cast<std::size_t>(size) * size;
  std::vector<T> rows(n);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glNamedFramebufferReadBuffer(fbo, attachment);
  glReadPixels(0, 0, size, size, format, GL_FLOAT, rows.data());
  dst.resize(n);
  for (int y = 0; y < size; ++y) {
    std::copy_n(rows.begin() + static_cast<std::ptrdiff_t>(y) * size, size,
                dst.begin() + static_cast<std::ptrdiff_t>(size - 1 - y) * size);
  }
}
}  // namespace

Result<std::unique_ptr<PuffRasterizer>> PuffRasterizer::create(int samplesPerSide, RasterSides sides) {
  const bool back = sides == RasterSides::kFrontAndBack;
  GLint maxRb = 0, maxTex = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxRb);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTex);
  const int limit = std::min(maxRb, maxTex);
  if (samplesPerSide <= 0 || samplesPerSide > limit) {
    return Error{"cell size times supersampling is " + std::to_string(samplesPerSide) +
                 " samples, more than this GL's framebuffer limit of " + std::to_string(limit) +
                 ": lower --size or --supersample"};
  }
  PUFF_TRY_ASSIGN(auto program, core::buildProgram({"bake/puff.vert", "bake/puff.frag"}));
  core::Program backProgram;
  if (back) {
    PUFF_TRY_ASSIGN(backProgram, core::buildProgram({"bake/puff.vert", "bake/puff_back.frag"}));
  }

  std::unique_ptr<PuffRasterizer> r(new PuffRasterizer);
  r->size_ = samplesPerSide;
  r->program_ = std::move(program);
  r->viewRotationLoc_ = glGetUniformLocation(r->program_.get(), "uViewRotation");
  r->backProgram_ = std::move(backProgram);
  if (back) r->backViewRotationLoc_ = glGetUniformLocation(r->backProgram_.get(), "uViewRotation");

  r->normalDepthTex_ = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(r->normalDepthTex_.get(), 1, GL_RGBA32F, samplesPerSide, samplesPerSide);
  r->colorTex_ = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(r->colorTex_.get(), 1, GL_RGBA32F, samplesPerSide, samplesPerSide);
  r->depthRb_ = core::makeRenderbuffer();
  glNamedRenderbufferStorage(r->depthRb_.get(), GL_DEPTH_COMPONENT32F, samplesPerSide, samplesPerSide);
  r->fbo_ = core::makeFramebuffer();
  glNamedFramebufferTexture(r->fbo_.get(), GL_COLOR_ATTACHMENT0, r->normalDepthTex_.get(), 0);
  glNamedFramebufferTexture(r->fbo_.get(), GL_COLOR_ATTACHMENT1, r->colorTex_.get(), 0);
  glNamedFramebufferRenderbuffer(r->fbo_.get(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->depthRb_.get());
  const GLenum drawBuffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(r->fbo_.get(), 2, drawBuffers);
  std::vector<GLuint> framebuffers{r->fbo_.get()};
  if (back) {
    // The far side's pass: the least z of every fragment (GL_MIN blending, no depth test).
    r->backTex_ = core::makeTexture(GL_TEXTURE_2D);
    glTextureStorage2D(r->backTex_.get(), 1, GL_R32F, samplesPerSide, samplesPerSide);
    r->backFbo_ = core::makeFramebuffer();
    glNamedFramebufferTexture(r->backFbo_.get(), GL_COLOR_ATTACHMENT0, r->backTex_.get(), 0);
    glNamedFramebufferDrawBuffer(r->backFbo_.get(), GL_COLOR_ATTACHMENT0);
    framebuffers.push_back(r->backFbo_.get());
  }
  for (const GLuint fbo : framebuffers) {
    const GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      return Error{"bake framebuffer of " + std::to_string(samplesPerSide) + "^2 samples is incomplete (status 0x" +
                   [&] {
                     char b[16];
                     std::snprintf(b, sizeof b, "%x", status);
                     return std::string(b);
                   }() +
                   ")"};
    }
  }
  r->vao_ = core::makeVertexArray();
  r->vbo_ = core::makeBuffer();
  r->ibo_ = core::makeBuffer();
  const GLuint vao = r->vao_.get();
  glVertexArrayVertexBuffer(vao, 0, r->vbo_.get(), 0, sizeof(Vertex));
  glVertexArrayElementBuffer(vao, r->ibo_.get());
  const GLuint offsets[] = {offsetof(Vertex, position), offsetof(Vertex, normal), offsetof(Vertex, color)};
  for (GLuint a = 0; a < 3; ++a) {
    glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE, offsets[a]);
    glVertexArrayAttribBinding(vao, a, 0);
    glEnableVertexArrayAttrib(vao, a);
  }
  if (auto err = core::drainGlErrors(); !err.empty()) return Error{"GL error while setting up the baker: " + err};
  return r;
}

void PuffRasterizer::setMesh(const mesh::TriMesh& m, const glm::vec3& defaultColor) {
  std::vector<Vertex> vertices(m.positions.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    vertices[i] = {m.positions[i], m.normals[i], m.hasColors() ? m.colors[i] : defaultColor};
  }
  // Orphan and refill: a mesh per variation, uploaded once and drawn once per view.
  glNamedBufferData(vbo_.get(), static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(),
                    GL_STATIC_DRAW);
  glNamedBufferData(ibo_.get(), static_cast<GLsizeiptr>(m.triangles.size() * sizeof(glm::uvec3)), m.triangles.data(),
                    GL_STATIC_DRAW);
  indexCount_ = static_cast<GLsizei>(m.triangles.size() * 3);
}

void PuffRasterizer::render(const glm::mat3& viewRotation, int marginSamples, int contentSamples, SampleBuffer& out,
                            RasterSides sides) {
  const bool back = sides == RasterSides::kFrontAndBack;
  // Every state this pass relies on is set here; nothing is inherited.
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.get());
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);  // puff meshes may be open or oddly wound; the depth test picks the nearest
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_STENCIL_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  const float zero[4] = {0, 0, 0, 0};
  const float one = 1.0f;
  glClearNamedFramebufferfv(fbo_.get(), GL_COLOR, 0, zero);
  glClearNamedFramebufferfv(fbo_.get(), GL_COLOR, 1, zero);
  glClearNamedFramebufferfv(fbo_.get(), GL_DEPTH, 0, &one);
  // GL's window origin is the bottom-left; the content square is centred, so the same margin works.
  glViewport(marginSamples, size_ - marginSamples - contentSamples, contentSamples, contentSamples);
  // The mesh seen through the view, drawn with `program` (its uViewRotation at `location`).
  const auto drawMesh = [&](GLuint program, GLint location) {
    glUseProgram(program);
    // glm and GLSL share column-major storage: the matrix goes up as it is.
    glUniformMatrix3fv(location, 1, GL_FALSE, glm::value_ptr(viewRotation));
    glBindVertexArray(vao_.get());
    glDrawElements(GL_TRIANGLES, indexCount_, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
    glUseProgram(0);
  };
  drawMesh(program_.get(), viewRotationLoc_);

  out.size = size_;
  readFlipped(fbo_.get(), GL_COLOR_ATTACHMENT0, GL_RGBA, size_, out.normalDepth);
  readFlipped(fbo_.get(), GL_COLOR_ATTACHMENT1, GL_RGBA, size_, out.color);
  out.back.clear();
  if (back) {
    PUFF_CHECK(backFbo_.get() != 0);  // created with `back`
    // Every fragment, no depth test: the least z (the farthest crossing) stays.
    glBindFramebuffer(GL_FRAMEBUFFER, backFbo_.get());
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_MIN);
    const float none[4] = {2, 0, 0, 0};  // z lies in [-1, 1]
    glClearNamedFramebufferfv(backFbo_.get(), GL_COLOR, 0, none);
    drawMesh(backProgram_.get(), backViewRotationLoc_);
    // What the front pass set, so that the state after render() does not depend on `back`.
    glDisable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    readFlipped(backFbo_.get(), GL_COLOR_ATTACHMENT0, GL_RED, size_, out.back);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace puff::bake
