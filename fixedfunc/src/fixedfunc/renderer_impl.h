// FixedRenderer's state and the helpers its passes share (renderer.cpp, passes.cpp, billboards.cpp).
#pragma once

#include <cmath>
#include <vector>

#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <puff/fixedfunc/renderer.h>
#include <puff/gl_api.h>

#include "gl_calls.h"

namespace puff::fixedfunc {
namespace detail {

struct GlVersion {
  int major = 0, minor = 0;
  bool atLeast(int ma, int mi) const { return major > ma || (major == ma && minor >= mi); }
};

inline bool finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) return false;
    }
  }
  return true;
}
inline bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// Half the width of a cell in mesh units: the unit sphere plus a margin of two texels, so linear
/// filtering at a cell's border never reads the neighbouring cell.
inline float extentFor(int cellSize) { return 1.0f + 4.0f / static_cast<float>(cellSize); }

inline void loadMatrix(GLenum mode, const glm::mat4& m) {
  FF_GL(glMatrixMode, mode);
  FF_GL(glLoadMatrixf, glm::value_ptr(m));
}

/// Mesh data as the vertex arrays take it.
struct DrawMesh {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec3> colors;  // empty: none
  std::vector<GLuint> indices;
};

/// The billboard pass's vertex arrays: four vertices per quad.
struct QuadArrays {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec2> texCoords;
  std::vector<glm::vec4> colors;  // the sprites' tints (only when one is tinted)
};

}  // namespace detail

struct FixedRenderer::Impl {
  detail::GlVersion version;
  GLint maxUnits = 2, maxClipPlanes = 6, maxLights = 8;
  detail::DrawMesh puff;
  struct Object {
    detail::DrawMesh mesh;
    glm::mat4 transform;
    glm::vec3 albedo;
    ObjectShading shading;
  };
  std::vector<Object> objects;
  GLuint puffTexture = 0, rampTexture = 0, whiteTexture = 0;
  bool puffTextureDrawn = false;  // by a puff pass: drawFloorFrame draws it once
  glm::vec3 rampLow{0.0f};        // q(0): the puff texture's empty texels take the darkest band's tone
  // Per-frame scratch, kept to reuse the allocations.
  std::vector<glm::vec4> puffColors;
  detail::QuadArrays quads;
  // The host's colour and depth under the puff texture's corner (FixedFrame::clear false).
  std::vector<float> cornerColor, cornerDepth;

  // renderer.cpp: the textures.
  void createTextures(int cellSize);
  void uploadRamp(const std::vector<unsigned char>& texels, int width);
  // passes.cpp: the fixed state and the puff-texture and object passes.
  void setUnitTarget(int unit, GLenum target);
  void resetFixedState();
  void setCelUnits(const glm::vec3& lightCamera, const glm::vec3& ambient, bool shading);
  void drawMesh(const detail::DrawMesh& mesh, const glm::vec4* colors);
  void puffPass(const FixedFrame& frame, const FixedStyle& style, const glm::vec3& lightCamera, int cellSize);
  void saveCorner(const FixedViewport& vp, int size);
  void restoreCorner(const FixedViewport& vp, int size);
  void objectPass(const FixedFrame& frame, const glm::vec3& lightCamera, const glm::vec3& lightWorld);
  // billboards.cpp: the billboard pass.
  void beginBillboards(const FixedFrame& frame);
  // `bare`: the fill-rate floor's quads (no outline, no tint).
  void billboardPass(const FixedFrame& frame, const std::vector<Billboard>& billboards, const FixedStyle& style,
                     float extent, bool bare = false);
};

}  // namespace puff::fixedfunc
