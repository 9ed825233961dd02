// The fixed state every pass starts from, and the passes before the billboards: the puff texture
// (four turned copies of the mesh, copied into one texture), the corner it draws through, and the
// opaque objects.
#include "renderer_impl.h"

#include <array>
#include <cstddef>
#include <numbers>

#include <glm/common.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>

#include "gl_calls.h"

namespace puff::fixedfunc {

using detail::DrawMesh;
using detail::extentFor;
using detail::loadMatrix;

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

}  // namespace

/// Makes `unit` active and enables exactly `target` (0: none) of the fixed-function texture targets
/// on it, with texture coordinate generation off. The targets have a precedence (cube map > 3D > 2D
/// > 1D), so a host's enable would win over ours.
void FixedRenderer::Impl::setUnitTarget(int unit, GLenum target) {
  FF_GL(glActiveTexture, GL_TEXTURE0 + unit);
  std::array<GLenum, 5> targets = {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_CUBE_MAP, 0};
  if (version.atLeast(3, 1)) targets[4] = GL_TEXTURE_RECTANGLE;
  for (GLenum t : targets) {
    if (t != 0 && t != target) FF_GL(glDisable, t);
  }
  if (target != 0) FF_GL(glEnable, target);
  for (GLenum gen : {GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R, GL_TEXTURE_GEN_Q}) FF_GL(glDisable, gen);
}

/// Sets every piece of fixed-function state the passes rely on, whatever the host left.
void FixedRenderer::Impl::resetFixedState() {
  for (GLenum cap : {GL_LIGHTING, GL_FOG, GL_BLEND, GL_STENCIL_TEST, GL_CULL_FACE, GL_POLYGON_OFFSET_FILL,
                     GL_COLOR_LOGIC_OP, GL_COLOR_MATERIAL, GL_POLYGON_STIPPLE, GL_ALPHA_TEST,
                     GL_SAMPLE_ALPHA_TO_COVERAGE, GL_NORMALIZE, GL_RESCALE_NORMAL}) {
    FF_GL(glDisable, cap);
  }
  if (version.atLeast(1, 4)) FF_GL(glDisable, GL_COLOR_SUM);
  for (GLint i = 0; i < maxClipPlanes; ++i) FF_GL(glDisable, static_cast<GLenum>(GL_CLIP_PLANE0 + i));
  for (GLint i = 0; i < maxLights; ++i) FF_GL(glDisable, static_cast<GLenum>(GL_LIGHT0 + i));
  for (GLint unit = 0; unit < maxUnits; ++unit) {
    setUnitTarget(unit, 0);
    FF_GL(glClientActiveTexture, GL_TEXTURE0 + unit);
    FF_GL(glDisableClientState, GL_TEXTURE_COORD_ARRAY);
  }
  FF_GL(glClientActiveTexture, GL_TEXTURE0);
  for (GLenum array : {GL_NORMAL_ARRAY, GL_COLOR_ARRAY, GL_INDEX_ARRAY, GL_EDGE_FLAG_ARRAY}) {
    FF_GL(glDisableClientState, array);
  }
  if (version.atLeast(1, 4)) {
    FF_GL(glDisableClientState, GL_FOG_COORD_ARRAY);
    FF_GL(glDisableClientState, GL_SECONDARY_COLOR_ARRAY);
  }
  FF_GL(glEnableClientState, GL_VERTEX_ARRAY);
  FF_GL(glPolygonMode, GL_FRONT_AND_BACK, GL_FILL);
  FF_GL(glShadeModel, GL_SMOOTH);
  FF_GL(glFrontFace, GL_CCW);
  FF_GL(glColorMask, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  FF_GL(glDepthMask, GL_TRUE);
  FF_GL(glDepthFunc, GL_LESS);
  FF_GL(glDepthRange, 0.0, 1.0);
  FF_GL(glEnable, GL_DEPTH_TEST);
  FF_GL(glEnable, GL_SCISSOR_TEST);
  // glCopyTexSubImage2D goes through the pixel transfer stage.
  for (GLenum scale : {GL_RED_SCALE, GL_GREEN_SCALE, GL_BLUE_SCALE, GL_ALPHA_SCALE}) {
    FF_GL(glPixelTransferf, scale, 1.0f);
  }
  for (GLenum bias : {GL_RED_BIAS, GL_GREEN_BIAS, GL_BLUE_BIAS, GL_ALPHA_BIAS}) FF_GL(glPixelTransferf, bias, 0.0f);
  FF_GL(glPixelTransferi, GL_MAP_COLOR, GL_FALSE);
}

/// Units 0 and 1 for K_a + C.K_L.q(N.L): unit 0 = ramp (texgen N, texture matrix row 0 = L,
/// modulated by the primary colour C.K_L), unit 1 = previous + constant K_a (alpha passes through).
/// With shading off, unit 0 is disabled and unit 1 adds K_a to the primary colour directly.
void FixedRenderer::Impl::setCelUnits(const glm::vec3& lightCamera, const glm::vec3& ambient, bool shading) {
  if (shading) {
    setUnitTarget(0, GL_TEXTURE_1D);
    FF_GL(glBindTexture, GL_TEXTURE_1D, rampTexture);
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    for (GLenum coord : {GL_S, GL_T, GL_R}) FF_GL(glTexGeni, coord, GL_TEXTURE_GEN_MODE, GL_NORMAL_MAP);
    for (GLenum gen : {GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R}) FF_GL(glEnable, gen);
    // Column-major: element [column][row]. Row 0 = (L, 0) makes s' = N.L; row 3 keeps q = 1.
    glm::mat4 m(0.0f);
    m[0][0] = lightCamera.x;
    m[1][0] = lightCamera.y;
    m[2][0] = lightCamera.z;
    m[3][3] = 1.0f;
    loadMatrix(GL_TEXTURE, m);
  } else {
    setUnitTarget(0, 0);
  }
  setUnitTarget(1, GL_TEXTURE_2D);
  FF_GL(glBindTexture, GL_TEXTURE_2D, whiteTexture);  // a unit only combines while it has a texture
  loadMatrix(GL_TEXTURE, glm::mat4(1.0f));
  FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
  FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_ADD);
  FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_SOURCE0_RGB, GL_PREVIOUS);
  FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_OPERAND0_RGB, GL_SRC_COLOR);
  FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_SOURCE1_RGB, GL_CONSTANT);
  FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_OPERAND1_RGB, GL_SRC_COLOR);
  FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_COMBINE_ALPHA, GL_REPLACE);
  FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_SOURCE0_ALPHA, GL_PREVIOUS);
  FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_OPERAND0_ALPHA, GL_SRC_ALPHA);
  FF_GL(glTexEnvf, GL_TEXTURE_ENV, GL_RGB_SCALE, 1.0f);
  FF_GL(glTexEnvf, GL_TEXTURE_ENV, GL_ALPHA_SCALE, 1.0f);
  const glm::vec4 constant(ambient, 0.0f);
  FF_GL(glTexEnvfv, GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, glm::value_ptr(constant));
  FF_GL(glActiveTexture, GL_TEXTURE0);
}

void FixedRenderer::Impl::drawMesh(const DrawMesh& mesh, const glm::vec4* colors) {
  FF_GL(glVertexPointer, 3, GL_FLOAT, 0, mesh.positions.data());
  FF_GL(glEnableClientState, GL_NORMAL_ARRAY);
  FF_GL(glNormalPointer, GL_FLOAT, 0, mesh.normals.data());
  if (colors != nullptr) {
    FF_GL(glEnableClientState, GL_COLOR_ARRAY);
    FF_GL(glColorPointer, 4, GL_FLOAT, 0, colors);
  }
  FF_GL(glDrawElements, GL_TRIANGLES, static_cast<GLsizei>(mesh.indices.size()), GL_UNSIGNED_INT, mesh.indices.data());
  if (colors != nullptr) FF_GL(glDisableClientState, GL_COLOR_ARRAY);
  FF_GL(glDisableClientState, GL_NORMAL_ARRAY);
}

// The four orientations are the mesh turned 0, 90, 180 and 270 degrees about the camera's up axis:
// the camera sees its front, right side, back and left side, four different sets of lumps. A turn
// about the view axis would only spin one silhouette in the image plane, a repetition the eye
// picks out in a dense cloud; camera up rather than world up stays a real turn for a camera looking
// straight down. The light stays fixed in camera space while the normals turn with the mesh, so
// every cell is lit from the scene's light direction.
void FixedRenderer::Impl::puffPass(const FixedFrame& frame, const FixedStyle& style, const glm::vec3& lightCamera,
                                   int cellSize) {
  const FixedViewport& vp = frame.viewport;
  FF_GL(glViewport, vp.x, vp.y, 2 * cellSize, 2 * cellSize);
  FF_GL(glScissor, vp.x, vp.y, 2 * cellSize, 2 * cellSize);
  // Alpha 0: no coverage. The colour is a puff tone (K_a + C.K_L.q(0)), not black: linear filtering
  // mixes it into the rim texels that pass the alpha test, which would otherwise darken every edge.
  const glm::vec3 rim =
      glm::clamp(frame.ambientColor + style.puffColor * frame.lightColor * (style.shading ? rampLow : glm::vec3(1.0f)),
                 glm::vec3(0.0f), glm::vec3(1.0f));
  FF_GL(glClearColor, rim.r, rim.g, rim.b, 0.0f);
  FF_GL(glClearDepth, 1.0);
  FF_GL(glClear, static_cast<GLbitfield>(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT));

  // C.K_L per vertex, alpha 1 (coverage).
  const glm::vec3 diffuse = style.puffColor * frame.lightColor;
  puffColors.resize(puff.positions.size());
  for (std::size_t i = 0; i < puffColors.size(); ++i) {
    puffColors[i] = glm::vec4(diffuse * (puff.colors.empty() ? glm::vec3(1.0f) : puff.colors[i]), 1.0f);
  }
  setCelUnits(lightCamera, frame.ambientColor, style.shading);

  const float extent = extentFor(cellSize);
  loadMatrix(GL_PROJECTION, glm::ortho(-extent, extent, -extent, extent, -2.0f, 2.0f));
  const glm::mat4 viewRotation(glm::mat3(frame.view));
  for (int k = 0; k < 4; ++k) {
    FF_GL(glViewport, vp.x + (k % 2) * cellSize, vp.y + (k / 2) * cellSize, cellSize, cellSize);
    const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), 0.5f * kPi * static_cast<float>(k), glm::vec3(0, 1, 0));
    loadMatrix(GL_MODELVIEW, turn * viewRotation);
    drawMesh(puff, puffColors.data());
  }

  FF_GL(glActiveTexture, GL_TEXTURE0);
  FF_GL(glBindTexture, GL_TEXTURE_2D, puffTexture);
  FF_GL(glCopyTexSubImage2D, GL_TEXTURE_2D, 0, 0, 0, vp.x, vp.y, 2 * cellSize, 2 * cellSize);
}

// The puff pass draws through the host's pixels: without a clear they are read back first (colour
// and depth, as floats: exact for 8-bit and 24-bit buffers) and written back after the copy.
void FixedRenderer::Impl::saveCorner(const FixedViewport& vp, int size) {
  for (GLenum p : {GL_PACK_ROW_LENGTH, GL_PACK_SKIP_PIXELS, GL_PACK_SKIP_ROWS}) FF_GL(glPixelStorei, p, 0);
  FF_GL(glPixelStorei, GL_PACK_ALIGNMENT, 4);
  FF_GL(glPixelStorei, GL_PACK_SWAP_BYTES, GL_FALSE);
  FF_GL(glPixelStorei, GL_PACK_LSB_FIRST, GL_FALSE);
  const auto n = static_cast<std::size_t>(size) * size;
  cornerColor.resize(n * 4);
  FF_GL(glReadPixels, vp.x, vp.y, size, size, GL_RGBA, GL_FLOAT, cornerColor.data());
  GLint depthBits = 0;
  FF_GL(glGetIntegerv, GL_DEPTH_BITS, &depthBits);
  cornerDepth.clear();
  if (depthBits > 0) {
    cornerDepth.resize(n);
    FF_GL(glReadPixels, vp.x, vp.y, size, size, GL_DEPTH_COMPONENT, GL_FLOAT, cornerDepth.data());
  }
}

void FixedRenderer::Impl::restoreCorner(const FixedViewport& vp, int size) {
  resetFixedState();  // no texturing, lighting, fog, blend or alpha test on the written pixels
  for (GLenum p : {GL_UNPACK_ROW_LENGTH, GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_ROWS}) FF_GL(glPixelStorei, p, 0);
  FF_GL(glPixelStorei, GL_UNPACK_ALIGNMENT, 4);
  FF_GL(glPixelStorei, GL_UNPACK_SWAP_BYTES, GL_FALSE);
  FF_GL(glPixelStorei, GL_UNPACK_LSB_FIRST, GL_FALSE);
  FF_GL(glPixelTransferf, GL_DEPTH_SCALE, 1.0f);
  FF_GL(glPixelTransferf, GL_DEPTH_BIAS, 0.0f);
  FF_GL(glPixelZoom, 1.0f, 1.0f);
  if (version.atLeast(3, 0)) FF_GL(glDisable, GL_FRAMEBUFFER_SRGB);  // the values read are the values stored
  // The raster position at the corner: NDC (-1, -1) of a viewport on it.
  FF_GL(glViewport, vp.x, vp.y, size, size);
  FF_GL(glScissor, vp.x, vp.y, size, size);
  loadMatrix(GL_PROJECTION, glm::mat4(1.0f));
  loadMatrix(GL_MODELVIEW, glm::mat4(1.0f));
  FF_GL(glRasterPos2f, -1.0f, -1.0f);
  FF_GL(glDisable, GL_DEPTH_TEST);
  FF_GL(glDrawPixels, size, size, GL_RGBA, GL_FLOAT, cornerColor.data());
  if (!cornerDepth.empty()) {
    // Depth is written only through the depth test: ALWAYS passes, colour writes off.
    FF_GL(glEnable, GL_DEPTH_TEST);
    FF_GL(glDepthFunc, GL_ALWAYS);
    FF_GL(glColorMask, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    FF_GL(glDrawPixels, size, size, GL_DEPTH_COMPONENT, GL_FLOAT, cornerDepth.data());
  }
  resetFixedState();
}

void FixedRenderer::Impl::objectPass(const FixedFrame& frame, const glm::vec3& lightCamera,
                                     const glm::vec3& lightWorld) {
  if (objects.empty()) return;
  loadMatrix(GL_PROJECTION, frame.projection);
  FF_GL(glEnable, GL_NORMALIZE);  // transforms may scale
  for (const Object& object : objects) {
    if (object.shading == ObjectShading::kCel) {
      FF_GL(glDisable, GL_LIGHTING);
      setCelUnits(lightCamera, object.albedo * frame.ambientColor, true);
      FF_GL(glColor4f, object.albedo.r * frame.lightColor.r, object.albedo.g * frame.lightColor.g,
            object.albedo.b * frame.lightColor.b, 1.0f);
    } else {
      setUnitTarget(0, 0);
      setUnitTarget(1, 0);
      FF_GL(glActiveTexture, GL_TEXTURE0);
      // albedo * K_a (light model ambient) + albedo * K_L * max(0, N.L) (light 0, directional).
      loadMatrix(GL_MODELVIEW, frame.view);  // the light position is transformed when set
      const glm::vec4 position(lightWorld, 0.0f), diffuse(frame.lightColor, 1.0f), zero(0.0f, 0.0f, 0.0f, 1.0f);
      const glm::vec4 ambient(frame.ambientColor, 1.0f), albedo(object.albedo, 1.0f);
      FF_GL(glLightfv, GL_LIGHT0, GL_POSITION, glm::value_ptr(position));
      FF_GL(glLightfv, GL_LIGHT0, GL_AMBIENT, glm::value_ptr(zero));
      FF_GL(glLightfv, GL_LIGHT0, GL_DIFFUSE, glm::value_ptr(diffuse));
      FF_GL(glLightfv, GL_LIGHT0, GL_SPECULAR, glm::value_ptr(zero));
      FF_GL(glLightf, GL_LIGHT0, GL_SPOT_CUTOFF, 180.0f);
      FF_GL(glLightModelfv, GL_LIGHT_MODEL_AMBIENT, glm::value_ptr(ambient));
      FF_GL(glLightModeli, GL_LIGHT_MODEL_TWO_SIDE, GL_FALSE);
      FF_GL(glMaterialfv, GL_FRONT_AND_BACK, GL_AMBIENT, glm::value_ptr(albedo));
      FF_GL(glMaterialfv, GL_FRONT_AND_BACK, GL_DIFFUSE, glm::value_ptr(albedo));
      FF_GL(glMaterialfv, GL_FRONT_AND_BACK, GL_SPECULAR, glm::value_ptr(zero));
      FF_GL(glMaterialfv, GL_FRONT_AND_BACK, GL_EMISSION, glm::value_ptr(zero));
      FF_GL(glEnable, GL_LIGHT0);
      FF_GL(glEnable, GL_LIGHTING);
    }
    loadMatrix(GL_MODELVIEW, frame.view * object.transform);
    drawMesh(object.mesh, nullptr);
  }
  FF_GL(glDisable, GL_LIGHTING);
  FF_GL(glDisable, GL_NORMALIZE);
  setUnitTarget(1, 0);
  setUnitTarget(0, 0);
}

}  // namespace puff::fixedfunc
