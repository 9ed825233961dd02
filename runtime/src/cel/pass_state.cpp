
#include <puff/cel/pass_state.h>
#include <puff/gl_api.h>
#include <puff/shader_contract.h>
namespace puff::cel {

void resetPassState() {
  glDisablei(GL_BLEND, 0);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_DEPTH_CLAMP);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
  glDisable(GL_RASTERIZER_DISCARD);
  // GL_FRAMEBUFFER_SRGB stays the host's: the shaders write scene-linear values, which a float
  // target stores as they are and an sRGB target with the flag on encodes (docs/colour.md).
  glDisable(GL_PRIMITIVE_RESTART);
  glDisable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glDepthRange(0.0, 1.0);
  glEnable(GL_DEPTH_TEST);
}

int applyShadePass(ShadePass pass) {
  switch (pass) {
    case ShadePass::kLit:
      glDepthFunc(nearerDepthFunc(boundDepthConvention()));
      glDepthMask(GL_TRUE);
      glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      glDisable(GL_STENCIL_TEST);
      return shader::kPassLit;
    case ShadePass::kShadowed:
      glDepthFunc(GL_EQUAL);
      glDepthMask(GL_FALSE);
      glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      glEnable(GL_STENCIL_TEST);
      glStencilFunc(GL_NOTEQUAL, 0, 0xFF);
      glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
      glStencilMask(0x00);
      return shader::kPassShadowed;
    case ShadePass::kDepthOnly:
      glDepthFunc(nearerDepthFunc(boundDepthConvention()));
      glDepthMask(GL_TRUE);
      glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
      glDisable(GL_STENCIL_TEST);
      return shader::kPassDepthOnly;
  }
  return shader::kPassLit;
}

void restoreWriteMasks() {
  glDepthMask(GL_TRUE);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glStencilMask(0xFF);
}

}  // namespace puff::cel
