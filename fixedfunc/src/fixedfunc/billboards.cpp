// The billboard pass: per billboard a camera-facing quad showing a cell of the puff texture, and
// behind it (with outlines) a larger black quad of the same cell.
#include "renderer_impl.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "gl_calls.h"

namespace puff::fixedfunc {

using detail::finite;
using detail::loadMatrix;
using detail::QuadArrays;

namespace {

/// The camera's axes and position in world space, from the view matrix.
struct Camera {
  glm::vec3 right, up, forward, eye;
  bool perspective;
};

Camera cameraOf(const FixedFrame& frame) {
  const glm::mat3 rotation(frame.view);
  const glm::vec3 right(rotation[0][0], rotation[1][0], rotation[2][0]);
  const glm::vec3 up(rotation[0][1], rotation[1][1], rotation[2][1]);
  const glm::vec3 forward = -glm::vec3(rotation[0][2], rotation[1][2], rotation[2][2]);
  const glm::vec3 eye(glm::inverse(frame.view)[3]);
  const bool perspective = frame.projection[2][3] != 0.0f;
  return {right, up, forward, eye, perspective};
}

/// Each channel clamped to [0, 1]; not a number draws untinted (as the nailboards' packing does).
glm::vec3 tintOf(const Billboard& b) {
  glm::vec3 t;
  for (int c = 0; c < 3; ++c) t[c] = std::isnan(b.tint[c]) ? 1.0f : std::clamp(b.tint[c], 0.0f, 1.0f);
  return t;
}

bool anyTinted(const std::vector<Billboard>& billboards) {
  return std::any_of(billboards.begin(), billboards.end(),
                     [&](const Billboard& b) { return tintOf(b) != glm::vec3(1.0f); });
}

/// Where a quad is centred and its world-space size.
struct Placement {
  glm::vec3 center;
  float size;
};

/// The outline billboard of `b`: outlineScale times its size, pushed back by the style's offset d.
Placement outlinePlacement(const Billboard& b, const FixedStyle& style, const Camera& camera) {
  glm::vec3 center = b.position;
  float size = b.size;
  const float d = style.outlineOffset > 0.0f ? style.outlineOffset : b.size;
  size *= style.outlineScale;
  if (camera.perspective) {
    // Back along the ray through the centre, so it stays centred on screen, and grown by the
    // depth ratio, so on screen it is outlineScale times the particle whatever d is.
    const glm::vec3 ray = b.position - camera.eye;
    const float depth = glm::dot(ray, camera.forward);
    const float length = glm::length(ray);
    if (length > 0.0f) {
      center = b.position + ray * (d / length);
      if (depth > 0.0f) size *= glm::dot(center - camera.eye, camera.forward) / depth;
    }
  } else {
    center = b.position + camera.forward * d;
  }
  return {center, size};
}

/// Appends a camera-facing quad at `at`, textured with the cell `variation` picks (mod 4, made
/// non-negative); `extent` is the half-width a cell shows, in mesh units.
void appendQuad(QuadArrays& quads, const Placement& at, int variation, const Camera& camera, float extent) {
  const int cell = ((variation % 4) + 4) % 4;
  const glm::vec2 t0(0.5f * static_cast<float>(cell % 2), 0.5f * static_cast<float>(cell / 2));
  const glm::vec2 t1 = t0 + glm::vec2(0.5f);
  const float h = 0.5f * at.size * extent;
  const glm::vec3 r = camera.right * h, u = camera.up * h;
  const glm::vec3 center = at.center;
  quads.positions.insert(quads.positions.end(), {center - r - u, center + r - u, center + r + u, center - r + u});
  quads.texCoords.insert(quads.texCoords.end(), {t0, {t1.x, t0.y}, t1, {t0.x, t1.y}});
}

/// One quad per billboard with a positive, finite size at a finite position: the billboard itself,
/// or with `outline` its outline billboard. With `tinted`, the billboards' quads carry their tints.
void buildQuads(QuadArrays& quads, const std::vector<Billboard>& billboards, const FixedStyle& style,
                const Camera& camera, float extent, bool outline, bool tinted) {
  quads.positions.clear();
  quads.texCoords.clear();
  quads.colors.clear();
  for (const Billboard& b : billboards) {
    if (!(b.size > 0.0f) || !std::isfinite(b.size) || !finite(b.position)) continue;
    const Placement at = outline ? outlinePlacement(b, style, camera) : Placement{b.position, b.size};
    appendQuad(quads, at, b.variation, camera, extent);
    if (!outline && tinted) quads.colors.insert(quads.colors.end(), 4, glm::vec4(tintOf(b), 1.0f));
  }
}

/// Draws the quads from client-side arrays (nothing when there are none).
void drawQuads(const QuadArrays& quads) {
  if (quads.positions.empty()) return;
  FF_GL(glVertexPointer, 3, GL_FLOAT, 0, quads.positions.data());
  FF_GL(glTexCoordPointer, 2, GL_FLOAT, 0, quads.texCoords.data());
  if (!quads.colors.empty()) {
    FF_GL(glEnableClientState, GL_COLOR_ARRAY);
    FF_GL(glColorPointer, 4, GL_FLOAT, 0, quads.colors.data());
  }
  FF_GL(glDrawArrays, GL_QUADS, 0, static_cast<GLsizei>(quads.positions.size()));
  if (!quads.colors.empty()) FF_GL(glDisableClientState, GL_COLOR_ARRAY);
}

/// K_a + tint (texel - K_a) = texel * tint + K_a * (1 - tint): the texel holds K_a + C K_L q, so
/// the tint multiplies C K_L q alone, as the cel path's tint multiplies C. Alpha: the texel's.
void setTintCombine(const glm::vec3& ambientColor) {
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
  const glm::vec4 ambient(glm::clamp(ambientColor, glm::vec3(0.0f), glm::vec3(1.0f)), 0.0f);
  FF_GL(glTexEnvfv, GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, glm::value_ptr(ambient));
}

}  // namespace

/// The frame's camera, the puff texture alone on unit 0 with texture coordinates from an array,
/// and the alpha test that makes a texel's coverage the quad's.
void FixedRenderer::Impl::beginBillboards(const FixedFrame& frame) {
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
}

void FixedRenderer::Impl::billboardPass(const FixedFrame& frame, const std::vector<Billboard>& billboards,
                                        const FixedStyle& style, float extent, bool bare) {
  if (billboards.empty()) return;
  const Camera camera = cameraOf(frame);
  const bool tinted = !bare && anyTinted(billboards);
  beginBillboards(frame);
  if (style.outlines && !bare) {
    // Black where the cell is covered: colour (0,0,0) times texel, alpha 1 times texel alpha.
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    FF_GL(glColor4f, 0.0f, 0.0f, 0.0f, 1.0f);
    buildQuads(quads, billboards, style, camera, extent, /*outline=*/true, tinted);
    drawQuads(quads);
  }
  if (tinted) {
    setTintCombine(frame.ambientColor);
  } else {
    FF_GL(glTexEnvi, GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
  }
  buildQuads(quads, billboards, style, camera, extent, /*outline=*/false, tinted);
  drawQuads(quads);
  FF_GL(glDisableClientState, GL_TEXTURE_COORD_ARRAY);
  FF_GL(glDisable, GL_ALPHA_TEST);
  FF_GL(glColorMask, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

}  // namespace puff::fixedfunc
