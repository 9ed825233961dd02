// The fixed-function cartoon smoke path. Every GL call goes through FF_GL (gl_calls.h); only
// OpenGL 1.0-1.5 entry points are used, and 1.4/1.5 ones only where the context has them.
#include <puff/fixedfunc/renderer.h>
#include <puff/gl_api.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>

#include "gl_calls.h"

namespace puff::fixedfunc {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

struct GlVersion {
  int major = 0, minor = 0;
  bool atLeast(int ma, int mi) const { return major > ma || (major == ma && minor >= mi); }
};

GlVersion parseVersion(const char* text) {
  GlVersion v;
  if (text != nullptr && std::sscanf(text, "%d.%d", &v.major, &v.minor) != 2) v = {};
  return v;
}

bool finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) return false;
    }
  }
  return true;
}
bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool isPowerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }

/// Half the width of a cell in mesh units: the unit sphere plus a margin of two texels, so linear
/// filtering at a cell's border never reads the neighbouring cell.
float extentFor(int cellSize) { return 1.0f + 4.0f / static_cast<float>(cellSize); }

/// Mesh data as the vertex arrays take it.
struct DrawMesh {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec3> colors;  // empty: none
  std::vector<GLuint> indices;
};

Result<DrawMesh> toDrawMesh(const mesh::TriMesh& m, const std::string& what) {
  if (m.positions.empty() || m.triangles.empty()) return Error{what + ": empty mesh"};
  if (m.normals.size() != m.positions.size()) {
    return Error{what + ": " + std::to_string(m.normals.size()) + " normals for " + std::to_string(m.positions.size()) +
                 " positions"};
  }
  if (!m.colors.empty() && m.colors.size() != m.positions.size())
    return Error{what + ": colour count unlike position count"};
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    if (!finite(m.positions[i]) || !finite(m.normals[i]))
      return Error{what + ": vertex " + std::to_string(i) + " is not finite"};
  }
  DrawMesh d;
  d.positions = m.positions;
  d.normals = m.normals;
  d.colors = m.colors;
  d.indices.reserve(m.triangles.size() * 3);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t index = m.triangles[t][k];
      if (index >= m.positions.size()) return Error{what + ": triangle " + std::to_string(t) + " index out of range"};
      d.indices.push_back(index);
    }
  }
  return d;
}

/// Texels of the ramp's middle row (the row puff::cel::Ramp uses), RGBA8 with alpha 255, resampled
/// (nearest: texel i takes source texel floor((i + 1/2) W / w)) to w = 256 texels, or the next power
/// of two >= W for a wider ramp. Why 256: the cel path samples the W-texel ramp itself, nearest, so
/// its tone changes at N.L = k / W; here they land at the texel edge nearest each, i / w, at most
/// 1/2w = 1/512 away (the next power of two >= W alone gave 1/12 for a 3-texel ramp: 1/4 instead of
/// 1/3). A wider ramp keeps w >= W, so no source texel (no band) is skipped. GL 1.x needs powers of two.
std::vector<unsigned char> rampTexels(const core::Image& ramp, int* width) {
  int w = 256;
  while (w < ramp.width) w *= 2;
  *width = w;
  const int row = ramp.height / 2;
  std::vector<unsigned char> out(static_cast<std::size_t>(w) * 4);
  auto byte = [](float v) { return static_cast<unsigned char>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  for (int i = 0; i < w; ++i) {
    const int src = std::min(ramp.width - 1, static_cast<int>((static_cast<double>(i) + 0.5) * ramp.width / w));
    for (int c = 0; c < 3; ++c) {
      out[static_cast<std::size_t>(i) * 4 + c] = byte(ramp.at(src, row, ramp.channels == 1 ? 0 : c));
    }
    out[static_cast<std::size_t>(i) * 4 + 3] = 255;
  }
  return out;
}

// ---- state save/restore ----------------------------------------------------------------------

/// Saves everything the fixed path may change and restores it on destruction. The matrices are
/// saved by value (glGet/glLoadMatrix), not pushed, so a host near the bottom of a small matrix
/// stack cannot make the path overflow it.
class StateGuard {
 public:
  explicit StateGuard(GlVersion version) : version_(version) {
    FF_GL(glGetIntegerv, GL_ACTIVE_TEXTURE, &activeTexture_);
    FF_GL(glGetIntegerv, GL_CLIENT_ACTIVE_TEXTURE, &clientActiveTexture_);
    FF_GL(glPushAttrib, GL_ALL_ATTRIB_BITS);
    FF_GL(glPushClientAttrib, GL_CLIENT_ALL_ATTRIB_BITS);
    FF_GL(glGetFloatv, GL_PROJECTION_MATRIX, glm::value_ptr(projection_));
    FF_GL(glGetFloatv, GL_MODELVIEW_MATRIX, glm::value_ptr(modelview_));
    for (int unit = 0; unit < 2; ++unit) {
      FF_GL(glActiveTexture, GL_TEXTURE0 + unit);
      FF_GL(glGetFloatv, GL_TEXTURE_MATRIX, glm::value_ptr(texture_[unit]));
    }
    // Client-side arrays and pixel uploads must not be read as offsets into a host's buffer.
    // glBindBuffer is GL 1.5; the pixel unpack binding GL 2.1.
    if (version_.atLeast(1, 5)) {
      unbind(GL_ARRAY_BUFFER, GL_ARRAY_BUFFER_BINDING, &arrayBuffer_);
      unbind(GL_ELEMENT_ARRAY_BUFFER, GL_ELEMENT_ARRAY_BUFFER_BINDING, &elementBuffer_);
    }
    if (version_.atLeast(2, 1)) {
      unbind(GL_PIXEL_UNPACK_BUFFER, GL_PIXEL_UNPACK_BUFFER_BINDING, &unpackBuffer_);
      unbind(GL_PIXEL_PACK_BUFFER, GL_PIXEL_PACK_BUFFER_BINDING, &packBuffer_);
    }
  }

  ~StateGuard() {
    FF_GL(glMatrixMode, GL_PROJECTION);
    FF_GL(glLoadMatrixf, glm::value_ptr(projection_));
    FF_GL(glMatrixMode, GL_MODELVIEW);
    FF_GL(glLoadMatrixf, glm::value_ptr(modelview_));
    FF_GL(glMatrixMode, GL_TEXTURE);
    for (int unit = 0; unit < 2; ++unit) {
      FF_GL(glActiveTexture, GL_TEXTURE0 + unit);
      FF_GL(glLoadMatrixf, glm::value_ptr(texture_[unit]));
    }
    FF_GL(glPopClientAttrib);
    FF_GL(glPopAttrib);
    // The pops restore these too; rebinding says so without relying on it.
    if (arrayBuffer_ != 0) FF_GL(glBindBuffer, GL_ARRAY_BUFFER, static_cast<GLuint>(arrayBuffer_));
    if (elementBuffer_ != 0) FF_GL(glBindBuffer, GL_ELEMENT_ARRAY_BUFFER, static_cast<GLuint>(elementBuffer_));
    if (unpackBuffer_ != 0) FF_GL(glBindBuffer, GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(unpackBuffer_));
    if (packBuffer_ != 0) FF_GL(glBindBuffer, GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(packBuffer_));
    FF_GL(glActiveTexture, static_cast<GLenum>(activeTexture_));
    FF_GL(glClientActiveTexture, static_cast<GLenum>(clientActiveTexture_));
  }

  StateGuard(const StateGuard&) = delete;
  StateGuard& operator=(const StateGuard&) = delete;

 private:
  static void unbind(GLenum target, GLenum binding, GLint* saved) {
    FF_GL(glGetIntegerv, binding, saved);
    if (*saved != 0) FF_GL(glBindBuffer, target, 0u);
  }

  GlVersion version_;
  GLint activeTexture_ = GL_TEXTURE0, clientActiveTexture_ = GL_TEXTURE0;
  glm::mat4 projection_{1.0f}, modelview_{1.0f}, texture_[2] = {glm::mat4(1.0f), glm::mat4(1.0f)};
  GLint arrayBuffer_ = 0, elementBuffer_ = 0, unpackBuffer_ = 0, packBuffer_ = 0;
};

void loadMatrix(GLenum mode, const glm::mat4& m) {
  FF_GL(glMatrixMode, mode);
  FF_GL(glLoadMatrixf, glm::value_ptr(m));
}

}  // namespace

// ---- primitive meshes ----------------------------------------------------------------------------

// ---- the renderer --------------------------------------------------------------------------------

struct FixedRenderer::Impl {
  GlVersion version;
  GLint maxUnits = 2, maxClipPlanes = 6, maxLights = 8;
  DrawMesh puff;
  struct Object {
    DrawMesh mesh;
    glm::mat4 transform;
    glm::vec3 albedo;
    ObjectShading shading;
  };
  std::vector<Object> objects;
  GLuint puffTexture = 0, rampTexture = 0, whiteTexture = 0;
  glm::vec3 rampLow{0.0f};  // q(0): the puff texture's empty texels take the darkest band's tone
  // Per-frame scratch, kept to reuse the allocations.
  std::vector<glm::vec4> puffColors;
  std::vector<glm::vec3> quadPositions;
  std::vector<glm::vec2> quadTexCoords;
  std::vector<glm::vec4> quadColors;  // the sprites' tints (only when one is tinted)
  // The host's colour and depth under the puff texture's corner (FixedFrame::clear false).
  std::vector<float> cornerColor, cornerDepth;

  void uploadRamp(const std::vector<unsigned char>& texels, int width);
  void setUnitTarget(int unit, GLenum target);
  void resetFixedState();
  void setCelUnits(const glm::vec3& lightCamera, const glm::vec3& ambient, bool shading);
  void drawMesh(const DrawMesh& mesh, const glm::vec4* colors);
  void puffPass(const FixedFrame& frame, const FixedStyle& style, const glm::vec3& lightCamera, int cellSize);
  void saveCorner(const FixedViewport& vp, int size);
  void restoreCorner(const FixedViewport& vp, int size);
  void objectPass(const FixedFrame& frame, const glm::vec3& lightCamera, const glm::vec3& lightWorld);
  void billboardPass(const FixedFrame& frame, const std::vector<Billboard>& billboards, const FixedStyle& style,
                     float extent);
};

void FixedRenderer::Impl::uploadRamp(const std::vector<unsigned char>& texels, int width) {
  rampLow = glm::vec3(texels[0], texels[1], texels[2]) / 255.0f;
  StateGuard guard(version);
  FF_GL(glActiveTexture, GL_TEXTURE0);
  FF_GL(glBindTexture, GL_TEXTURE_1D, rampTexture);
  FF_GL(glPixelStorei, GL_UNPACK_ALIGNMENT, 1);
  FF_GL(glPixelStorei, GL_UNPACK_ROW_LENGTH, 0);
  FF_GL(glPixelStorei, GL_UNPACK_SKIP_PIXELS, 0);
  FF_GL(glPixelStorei, GL_UNPACK_SKIP_ROWS, 0);
  FF_GL(glPixelStorei, GL_UNPACK_SWAP_BYTES, GL_FALSE);
  FF_GL(glPixelStorei, GL_UNPACK_LSB_FIRST, GL_FALSE);
  FF_GL(glPixelTransferf, GL_RED_SCALE, 1.0f);
  FF_GL(glPixelTransferf, GL_GREEN_SCALE, 1.0f);
  FF_GL(glPixelTransferf, GL_BLUE_SCALE, 1.0f);
  FF_GL(glPixelTransferf, GL_ALPHA_SCALE, 1.0f);
  FF_GL(glPixelTransferf, GL_RED_BIAS, 0.0f);
  FF_GL(glPixelTransferf, GL_GREEN_BIAS, 0.0f);
  FF_GL(glPixelTransferf, GL_BLUE_BIAS, 0.0f);
  FF_GL(glPixelTransferf, GL_ALPHA_BIAS, 0.0f);
  FF_GL(glPixelTransferi, GL_MAP_COLOR, GL_FALSE);
  FF_GL(glTexImage1D, GL_TEXTURE_1D, 0, GL_RGBA8, width, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
  // Nearest keeps the bands hard (as puff::cel's default); clamp to edge is the max(0, N.L).
  FF_GL(glTexParameteri, GL_TEXTURE_1D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  FF_GL(glTexParameteri, GL_TEXTURE_1D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  FF_GL(glTexParameteri, GL_TEXTURE_1D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
}

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

void FixedRenderer::Impl::billboardPass(const FixedFrame& frame, const std::vector<Billboard>& billboards,
                                        const FixedStyle& style, float extent) {
  if (billboards.empty()) return;
  const glm::mat3 rotation(frame.view);
  const glm::vec3 right(rotation[0][0], rotation[1][0], rotation[2][0]);
  const glm::vec3 up(rotation[0][1], rotation[1][1], rotation[2][1]);
  const glm::vec3 forward = -glm::vec3(rotation[0][2], rotation[1][2], rotation[2][2]);
  const glm::vec3 eye(glm::inverse(frame.view)[3]);
  const bool perspective = frame.projection[2][3] != 0.0f;

  // One quad per billboard; `offset` and `scale` make the outline billboards.
  // Each channel clamped to [0, 1]; not a number draws untinted (as the nailboards' packing does).
  const auto tintOf = [](const Billboard& b) {
    glm::vec3 t;
    for (int c = 0; c < 3; ++c) t[c] = std::isnan(b.tint[c]) ? 1.0f : std::clamp(b.tint[c], 0.0f, 1.0f);
    return t;
  };
  const bool tinted = std::any_of(billboards.begin(), billboards.end(),
                                  [&](const Billboard& b) { return tintOf(b) != glm::vec3(1.0f); });
  auto build = [&](bool outline) {
    quadPositions.clear();
    quadTexCoords.clear();
    quadColors.clear();
    for (const Billboard& b : billboards) {
      if (!(b.size > 0.0f) || !std::isfinite(b.size) || !finite(b.position)) continue;
      glm::vec3 center = b.position;
      float size = b.size;
      if (outline) {
        const float d = style.outlineOffset > 0.0f ? style.outlineOffset : b.size;
        size *= style.outlineScale;
        if (perspective) {
          // Back along the ray through the centre, so it stays centred on screen, and grown by the
          // depth ratio, so on screen it is outlineScale times the particle whatever d is.
          const glm::vec3 ray = b.position - eye;
          const float depth = glm::dot(ray, forward);
          const float length = glm::length(ray);
          if (length > 0.0f) {
            center = b.position + ray * (d / length);
            if (depth > 0.0f) size *= glm::dot(center - eye, forward) / depth;
          }
        } else {
          center = b.position + forward * d;
        }
      }
      const int cell = ((b.variation % 4) + 4) % 4;
      const glm::vec2 t0(0.5f * static_cast<float>(cell % 2), 0.5f * static_cast<float>(cell / 2));
      const glm::vec2 t1 = t0 + glm::vec2(0.5f);
      const float h = 0.5f * size * extent;
      const glm::vec3 r = right * h, u = up * h;
      quadPositions.insert(quadPositions.end(), {center - r - u, center + r - u, center + r + u, center - r + u});
      quadTexCoords.insert(quadTexCoords.end(), {t0, {t1.x, t0.y}, t1, {t0.x, t1.y}});
      if (!outline && tinted) quadColors.insert(quadColors.end(), 4, glm::vec4(tintOf(b), 1.0f));
    }
    if (quadPositions.empty()) return;
    FF_GL(glVertexPointer, 3, GL_FLOAT, 0, quadPositions.data());
    FF_GL(glTexCoordPointer, 2, GL_FLOAT, 0, quadTexCoords.data());
    if (!quadColors.empty()) {
      FF_GL(glEnableClientState, GL_COLOR_ARRAY);
      FF_GL(glColorPointer, 4, GL_FLOAT, 0, quadColors.data());
    }
    FF_GL(glDrawArrays, GL_QUADS, 0, static_cast<GLsizei>(quadPositions.size()));
    if (!quadColors.empty()) FF_GL(glDisableClientState, GL_COLOR_ARRAY);
  };

  loadMatrix(GL_PROJECTION, frame.projection);
  loadMatrix(GL_MODELVIEW, frame.view);
  setUnitTarget(1, 0);
  setUnitTarget(0, GL_TEXTURE_2D);
  loadMatrix(GL_TEXTURE, glm::mat4(1.0f));
  FF_GL(glBindTexture, GL_TEXTURE_2D, puffTexture);
  FF_GL(glEnable, GL_ALPHA_TEST);
  FF_GL(glAlphaFunc, GL_GREATER, 0.5f);
  // The texel's alpha decides coverage (the alpha test) and must not reach the frame: an opaque
  // frame has alpha 1 everywhere (docs/colour.md).
  FF_GL(glColorMask, GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
  FF_GL(glClientActiveTexture, GL_TEXTURE0);
  FF_GL(glEnableClientState, GL_TEXTURE_COORD_ARRAY);
  if (style.outlines) {
    // Black where the cell is covered: colour (0,0,0) times texel, alpha 1 times texel alpha.
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    FF_GL(glColor4f, 0.0f, 0.0f, 0.0f, 1.0f);
    build(true);
  }
  if (tinted) {
    // K_a + tint (texel - K_a) = texel * tint + K_a * (1 - tint): the texel holds K_a + C K_L q, so
    // the tint multiplies C K_L q alone, as the cel path's tint multiplies C. Alpha: the texel's.
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_INTERPOLATE);
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_SOURCE0_RGB, GL_TEXTURE);
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_OPERAND0_RGB, GL_SRC_COLOR);
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_SOURCE1_RGB, GL_CONSTANT);
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_OPERAND1_RGB, GL_SRC_COLOR);
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_SOURCE2_RGB, GL_PRIMARY_COLOR);
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_OPERAND2_RGB, GL_SRC_COLOR);
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_COMBINE_ALPHA, GL_REPLACE);
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_SOURCE0_ALPHA, GL_TEXTURE);
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_OPERAND0_ALPHA, GL_SRC_ALPHA);
    FF_GL(glTexEnvf, GL_TEXTURE_ENV, GL_RGB_SCALE, 1.0f);
    FF_GL(glTexEnvf, GL_TEXTURE_ENV, GL_ALPHA_SCALE, 1.0f);
    const glm::vec4 ambient(glm::clamp(frame.ambientColor, glm::vec3(0.0f), glm::vec3(1.0f)), 0.0f);
    FF_GL(glTexEnvfv, GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, glm::value_ptr(ambient));
  } else {
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
  }
  build(false);
  FF_GL(glDisableClientState, GL_TEXTURE_COORD_ARRAY);
  FF_GL(glDisable, GL_ALPHA_TEST);
  FF_GL(glColorMask, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

FixedRenderer::FixedRenderer(std::unique_ptr<Impl> impl, int cellSize, std::string contextVersion)
    : impl_(std::move(impl)), cellSize_(cellSize), contextVersion_(std::move(contextVersion)) {}

FixedRenderer::~FixedRenderer() {
  const GLuint names[] = {impl_->puffTexture, impl_->rampTexture, impl_->whiteTexture};
  FF_GL(glDeleteTextures, 3, names);
}

Result<std::unique_ptr<FixedRenderer>> FixedRenderer::create(const mesh::TriMesh& puff, int cellSize) {
  if (!detail::loaderReady()) return Error{"fixedfunc: no GL loaded through glad (create a context first)"};
  const char* versionText = reinterpret_cast<const char*>(FF_GL(glGetString, GL_VERSION));
  if (versionText == nullptr) return Error{"fixedfunc: no current GL context"};
  auto impl = std::make_unique<Impl>();
  impl->version = parseVersion(versionText);
  const std::string versionString = versionText;
  if (!impl->version.atLeast(1, 3)) {
    return Error{"fixedfunc: needs OpenGL >= 1.3 (GL_NORMAL_MAP texgen, texture env combine), the context is " +
                 versionString};
  }
  if (impl->version.atLeast(3, 2)) {
    GLint mask = 0;
    FF_GL(glGetIntegerv, GL_CONTEXT_PROFILE_MASK, &mask);
    if ((mask & GL_CONTEXT_CORE_PROFILE_BIT) != 0) {
      return Error{"fixedfunc: needs a compatibility-profile context, the context is core " + versionString};
    }
  } else if (impl->version.atLeast(3, 1)) {
    const char* extensions = reinterpret_cast<const char*>(FF_GL(glGetString, GL_EXTENSIONS));
    if (extensions == nullptr || std::strstr(extensions, "GL_ARB_compatibility") == nullptr) {
      return Error{"fixedfunc: needs a compatibility context, this GL 3.1 context lacks GL_ARB_compatibility"};
    }
  }
  if (!isPowerOfTwo(cellSize) || cellSize < 8 || cellSize > 1024) {
    return Error{"fixedfunc: cell size must be a power of two in [8, 1024], got " + std::to_string(cellSize)};
  }
  GLint maxTextureSize = 0;
  FF_GL(glGetIntegerv, GL_MAX_TEXTURE_SIZE, &maxTextureSize);
  FF_GL(glGetIntegerv, GL_MAX_TEXTURE_UNITS, &impl->maxUnits);
  FF_GL(glGetIntegerv, GL_MAX_CLIP_PLANES, &impl->maxClipPlanes);
  FF_GL(glGetIntegerv, GL_MAX_LIGHTS, &impl->maxLights);
  if (impl->maxUnits < 2) return Error{"fixedfunc: needs two fixed-function texture units"};
  if (maxTextureSize < 2 * cellSize) {
    return Error{"fixedfunc: cell size " + std::to_string(cellSize) + " needs a " + std::to_string(2 * cellSize) +
                 " texture, GL_MAX_TEXTURE_SIZE is " + std::to_string(maxTextureSize)};
  }
  PUFF_TRY_ASSIGN(impl->puff, toDrawMesh(puff, "fixedfunc: puff mesh"));

  {
    StateGuard guard(impl->version);
    GLuint names[3] = {0, 0, 0};
    FF_GL(glGenTextures, 3, names);
    impl->puffTexture = names[0];
    impl->rampTexture = names[1];
    impl->whiteTexture = names[2];
    FF_GL(glActiveTexture, GL_TEXTURE0);
    FF_GL(glPixelStorei, GL_UNPACK_ALIGNMENT, 1);
    FF_GL(glPixelStorei, GL_UNPACK_ROW_LENGTH, 0);
    FF_GL(glPixelStorei, GL_UNPACK_SKIP_PIXELS, 0);
    FF_GL(glPixelStorei, GL_UNPACK_SKIP_ROWS, 0);
    const std::vector<unsigned char> empty(static_cast<std::size_t>(4 * cellSize) * cellSize * 4, 0);
    FF_GL(glBindTexture, GL_TEXTURE_2D, impl->puffTexture);
    FF_GL(glTexImage2D, GL_TEXTURE_2D, 0, GL_RGBA8, 2 * cellSize, 2 * cellSize, 0, GL_RGBA, GL_UNSIGNED_BYTE,
          empty.data());
    // Linear: alpha-testing interpolated coverage at 0.5 gives smooth silhouettes when magnified.
    FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    const unsigned char white[4] = {255, 255, 255, 255};
    FF_GL(glBindTexture, GL_TEXTURE_2D, impl->whiteTexture);
    FF_GL(glTexImage2D, GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, white);
    FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  core::Image twoTone(2, 1, 1);
  twoTone.at(1, 0) = 1.0f;
  int width = 0;
  const std::vector<unsigned char> texels = rampTexels(twoTone, &width);
  impl->uploadRamp(texels, width);
  return std::unique_ptr<FixedRenderer>(new FixedRenderer(std::move(impl), cellSize, versionString));
}

Result<void> FixedRenderer::setRamp(const core::Image& ramp) {
  if (ramp.empty() || ramp.width < 1 || ramp.height < 1) return Error{"fixedfunc: ramp: empty image"};
  if (ramp.channels != 1 && ramp.channels != 3 && ramp.channels != 4) {
    return Error{"fixedfunc: ramp: " + std::to_string(ramp.channels) + " channels (expected 1, 3 or 4)"};
  }
  GLint maxTextureSize = 0;
  FF_GL(glGetIntegerv, GL_MAX_TEXTURE_SIZE, &maxTextureSize);
  int width = 0;
  const std::vector<unsigned char> texels = rampTexels(ramp, &width);
  if (width > maxTextureSize) return Error{"fixedfunc: ramp: wider than GL_MAX_TEXTURE_SIZE"};
  impl_->uploadRamp(texels, width);
  return {};
}

Result<void> FixedRenderer::setObjects(std::vector<FixedObject> objects) {
  std::vector<Impl::Object> converted;
  converted.reserve(objects.size());
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const std::string what = "fixedfunc: object #" + std::to_string(i);
    auto mesh = toDrawMesh(objects[i].mesh, what);
    if (!mesh) return mesh.error();
    if (!finite(objects[i].transform)) return Error{what + ": non-finite transform"};
    const glm::vec3 a = objects[i].albedo;
    if (!finite(a) || a.r < 0.0f || a.g < 0.0f || a.b < 0.0f) return Error{what + ": albedo must be finite and >= 0"};
    converted.push_back({std::move(*mesh), objects[i].transform, a, objects[i].shading});
  }
  impl_->objects = std::move(converted);
  return {};
}

Result<void> FixedRenderer::drawFrame(const FixedFrame& frame, const std::vector<Billboard>& billboards,
                                      const FixedStyle& style) {
  const FixedViewport& vp = frame.viewport;
  if (vp.width < 2 * cellSize_ || vp.height < 2 * cellSize_) {
    return Error{"fixedfunc: viewport " + std::to_string(vp.width) + "x" + std::to_string(vp.height) +
                 " is smaller than the puff texture pass needs (" + std::to_string(2 * cellSize_) + " square)"};
  }
  if (!finite(frame.view) || !finite(frame.projection)) return Error{"fixedfunc: non-finite view or projection"};
  if (!finite(frame.lightDirection) || glm::length(frame.lightDirection) <= 0.0f) {
    return Error{"fixedfunc: light direction must be finite and non-zero"};
  }
  if (!(style.outlineScale >= 1.0f) || !std::isfinite(style.outlineScale)) {
    return Error{"fixedfunc: outline scale must be >= 1"};
  }
  // What the path cannot draw under (all queries with GL 1.0's glGetIntegerv).
  const GlVersion& version = impl_->version;
  GLint value = 0;
  if (version.atLeast(2, 0)) {
    FF_GL(glGetIntegerv, GL_CURRENT_PROGRAM, &value);
    if (value != 0) return Error{"fixedfunc: a program is in use; unbind it (glUseProgram(0)) before drawFrame"};
  }
  if (version.atLeast(3, 0)) {
    FF_GL(glGetIntegerv, GL_VERTEX_ARRAY_BINDING, &value);
    if (value != 0) return Error{"fixedfunc: a vertex array object is bound; bind 0 before drawFrame"};
    GLint read = 0;
    FF_GL(glGetIntegerv, GL_DRAW_FRAMEBUFFER_BINDING, &value);
    FF_GL(glGetIntegerv, GL_READ_FRAMEBUFFER_BINDING, &read);
    if (value != read) return Error{"fixedfunc: the read and draw framebuffers differ (the puff pass copies back)"};
  }
  GLint drawBuffer = 0, readBuffer = 0;
  FF_GL(glGetIntegerv, GL_DRAW_BUFFER, &drawBuffer);
  FF_GL(glGetIntegerv, GL_READ_BUFFER, &readBuffer);
  if (drawBuffer != readBuffer) return Error{"fixedfunc: the read and draw buffers differ (the puff pass copies back)"};
  FF_GL(glGetIntegerv, GL_ALPHA_BITS, &value);
  if (value <= 0) return Error{"fixedfunc: the framebuffer has no alpha channel (the puff pass keeps coverage in it)"};

  const glm::vec3 lightWorld = glm::normalize(frame.lightDirection);
  const glm::vec3 lightCamera = glm::normalize(glm::mat3(frame.view) * lightWorld);

  StateGuard guard(version);
  impl_->resetFixedState();
  if (!frame.clear) impl_->saveCorner(vp, 2 * cellSize_);
  impl_->puffPass(frame, style, lightCamera, cellSize_);
  if (!frame.clear) impl_->restoreCorner(vp, 2 * cellSize_);

  FF_GL(glViewport, vp.x, vp.y, vp.width, vp.height);
  FF_GL(glScissor, vp.x, vp.y, vp.width, vp.height);
  if (frame.clear) {
    FF_GL(glClearColor, frame.background.r, frame.background.g, frame.background.b, frame.background.a);
    FF_GL(glClearDepth, 1.0);
    FF_GL(glClear, static_cast<GLbitfield>(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT));
  }
  impl_->objectPass(frame, lightCamera, lightWorld);
  impl_->billboardPass(frame, billboards, style, cellExtent());
  return {};
}

unsigned FixedRenderer::puffTexture() const { return impl_->puffTexture; }

float FixedRenderer::cellExtent() const { return extentFor(cellSize_); }

}  // namespace puff::fixedfunc
