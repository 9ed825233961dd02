#include <puff/core/shader.h>
#include <puff/gl_api.h>
#include <puff/render/view.h>
#include <puff/shader_contract.h>

namespace puff::render {

Result<ViewPass> ViewPass::create() {
  PUFF_TRY_ASSIGN(auto program, core::buildProgram({"media/fullscreen.vert", "output/view.frag"}));
  ViewPass v;
  v.program_ = std::move(program);
  v.vao_ = core::makeVertexArray("view: vertex array");
  return v;
}

void ViewPass::draw(GLuint linear, const cel::Viewport& viewport, core::ViewTransform view) const {
  const core::DebugGroup group("view transform");
  const GLuint p = program_.get();
  glProgramUniform1i(p, shader::loc::kViewTransform, view == core::ViewTransform::kFilmic ? 1 : 0);
  glProgramUniform2f(p, shader::loc::kViewOrigin, static_cast<float>(viewport.x), static_cast<float>(viewport.y));
  glProgramUniform1f(p, shader::loc::kViewKnee, static_cast<float>(core::kFilmicKnee));
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_FRAMEBUFFER_SRGB);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glUseProgram(p);
  glBindTextureUnit(0, linear);
  glBindVertexArray(vao_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
}

}  // namespace puff::render
