// The programmable path's plate: a full-viewport triangle reading one texel per pixel.
#include <algorithm>
#include <vector>

#include <puff/core/shader.h>
#include <puff/gl_api.h>
#include <puff/render/plate.h>
#include <puff/shader_contract.h>

#include "plate_pass.h"

namespace puff::render::detail {

Result<PlatePass> PlatePass::create(const scene::Scene& scene) {
  PUFF_TRY_ASSIGN(auto linear, loadPlate(scene));
  PUFF_TRY_ASSIGN(auto program, core::buildProgram({"media/fullscreen.vert", "output/plate.frag"}));
  PlatePass p;
  p.linear_ = std::move(linear);
  p.program_ = std::move(program);
  p.vao_ = core::makeVertexArray("plate: vertex array");
  return p;
}

void PlatePass::draw(const cel::Viewport& viewport) {
  const core::DebugGroup group("plate");
  if (viewport.width != width_ || viewport.height != height_) {
    const core::Image sized = resizePlate(linear_, viewport.width, viewport.height);
    // GL rows go bottom-up: image row 0 (the top) is stored last.
    std::vector<float> rows(sized.pixels.size());
    const std::size_t row = static_cast<std::size_t>(sized.width) * 4;
    for (int y = 0; y < sized.height; ++y) {
      std::copy_n(&sized.pixels[static_cast<std::size_t>(y) * row], row,
                  &rows[static_cast<std::size_t>(sized.height - 1 - y) * row]);
    }
    texture_ = core::makeTexture(GL_TEXTURE_2D, "plate");
    const GLuint t = texture_.get();
    glTextureStorage2D(t, 1, GL_RGBA16F, sized.width, sized.height);
    glTextureSubImage2D(t, 0, 0, 0, sized.width, sized.height, GL_RGBA, GL_FLOAT, rows.data());
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    width_ = viewport.width;
    height_ = viewport.height;
  }
  GLboolean depthTest = glIsEnabled(GL_DEPTH_TEST), stencilTest = glIsEnabled(GL_STENCIL_TEST),
            blend = glIsEnabled(GL_BLEND), depthMask = GL_TRUE;
  glGetBooleanv(GL_DEPTH_WRITEMASK, &depthMask);
  GLint activeUnit = 0, unit0 = 0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &activeUnit);
  glActiveTexture(GL_TEXTURE0);
  glGetIntegerv(GL_TEXTURE_BINDING_2D, &unit0);

  const GLuint p = program_.get();
  glProgramUniform2f(p, shader::loc::kPlateOrigin, static_cast<float>(viewport.x), static_cast<float>(viewport.y));
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_BLEND);
  glDepthMask(GL_FALSE);
  glUseProgram(p);
  glBindTextureUnit(0, texture_.get());
  glBindVertexArray(vao_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);

  glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(unit0));
  glActiveTexture(static_cast<GLenum>(activeUnit));
  glDepthMask(depthMask);
  if (depthTest) glEnable(GL_DEPTH_TEST);
  if (stencilTest) glEnable(GL_STENCIL_TEST);
  if (blend) glEnable(GL_BLEND);
}

}  // namespace puff::render::detail
