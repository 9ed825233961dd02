// The fixed-function cartoon smoke path: creating the renderer (the context's checks, its textures),
// its ramp and objects, and drawFrame's checks and passes (passes.cpp, billboards.cpp). Every GL call
// goes through FF_GL (gl_calls.h); only OpenGL 1.0-1.5 entry points are used, and 1.4/1.5 ones only
// where the context has them.
#include <puff/fixedfunc/renderer.h>
#include <puff/gl_api.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>

#include "gl_calls.h"
#include "renderer_impl.h"

namespace puff::fixedfunc {

using detail::DrawMesh;
using detail::extentFor;
using detail::finite;
using detail::GlVersion;

namespace {

GlVersion parseVersion(const char* text) {
  GlVersion v;
  if (text != nullptr && std::sscanf(text, "%d.%d", &v.major, &v.minor) != 2) v = {};
  return v;
}

bool isPowerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }

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

/// The context's version and profile: GL >= 1.3, and a compatibility context.
Result<void> checkContext(const GlVersion& version, const std::string& versionString) {
  if (!version.atLeast(1, 3)) {
    return Error{"fixedfunc: needs OpenGL >= 1.3 (GL_NORMAL_MAP texgen, texture env combine), the context is " +
                 versionString};
  }
  if (version.atLeast(3, 2)) {
    GLint mask = 0;
    FF_GL(glGetIntegerv, GL_CONTEXT_PROFILE_MASK, &mask);
    if ((mask & GL_CONTEXT_CORE_PROFILE_BIT) != 0) {
      return Error{"fixedfunc: needs a compatibility-profile context, the context is core " + versionString};
    }
  } else if (version.atLeast(3, 1)) {
    const char* extensions = reinterpret_cast<const char*>(FF_GL(glGetString, GL_EXTENSIONS));
    if (extensions == nullptr || std::strstr(extensions, "GL_ARB_compatibility") == nullptr) {
      return Error{"fixedfunc: needs a compatibility context, this GL 3.1 context lacks GL_ARB_compatibility"};
    }
  }
  return {};
}

/// The frame's own values: a viewport the puff texture fits in, finite matrices, a light direction
/// and an outline scale >= 1.
Result<void> checkFrame(const FixedFrame& frame, const FixedStyle& style, int cellSize) {
  const FixedViewport& vp = frame.viewport;
  if (vp.width < 2 * cellSize || vp.height < 2 * cellSize) {
    return Error{"fixedfunc: viewport " + std::to_string(vp.width) + "x" + std::to_string(vp.height) +
                 " is smaller than the puff texture pass needs (" + std::to_string(2 * cellSize) + " square)"};
  }
  if (!finite(frame.view) || !finite(frame.projection)) return Error{"fixedfunc: non-finite view or projection"};
  if (!finite(frame.lightDirection) || glm::length(frame.lightDirection) <= 0.0f) {
    return Error{"fixedfunc: light direction must be finite and non-zero"};
  }
  if (!(style.outlineScale >= 1.0f) || !std::isfinite(style.outlineScale)) {
    return Error{"fixedfunc: outline scale must be >= 1"};
  }
  return {};
}

/// What the path cannot draw under (all queries with GL 1.0's glGetIntegerv).
Result<void> checkHostState(const GlVersion& version) {
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
  return {};
}

}  // namespace

/// The puff texture (empty, 2*cellSize square), the ramp's name and the white texture unit 1
/// combines with.
void FixedRenderer::Impl::createTextures(int cellSize) {
  StateGuard guard(version);
  GLuint names[3] = {0, 0, 0};
  FF_GL(glGenTextures, 3, names);
  puffTexture = names[0];
  rampTexture = names[1];
  whiteTexture = names[2];
  FF_GL(glActiveTexture, GL_TEXTURE0);
  FF_GL(glPixelStorei, GL_UNPACK_ALIGNMENT, 1);
  FF_GL(glPixelStorei, GL_UNPACK_ROW_LENGTH, 0);
  FF_GL(glPixelStorei, GL_UNPACK_SKIP_PIXELS, 0);
  FF_GL(glPixelStorei, GL_UNPACK_SKIP_ROWS, 0);
  const std::vector<unsigned char> empty(static_cast<std::size_t>(4 * cellSize) * cellSize * 4, 0);
  FF_GL(glBindTexture, GL_TEXTURE_2D, puffTexture);
  FF_GL(glTexImage2D, GL_TEXTURE_2D, 0, GL_RGBA8, 2 * cellSize, 2 * cellSize, 0, GL_RGBA, GL_UNSIGNED_BYTE,
        empty.data());
  // Linear: alpha-testing interpolated coverage at 0.5 gives smooth silhouettes when magnified.
  FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  const unsigned char white[4] = {255, 255, 255, 255};
  FF_GL(glBindTexture, GL_TEXTURE_2D, whiteTexture);
  FF_GL(glTexImage2D, GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, white);
  FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  FF_GL(glTexParameteri, GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

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
  PUFF_TRY(checkContext(impl->version, versionString));
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
  impl->createTextures(cellSize);
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
    PUFF_TRY_ASSIGN(auto mesh, toDrawMesh(objects[i].mesh, what));
    if (!finite(objects[i].transform)) return Error{what + ": non-finite transform"};
    const glm::vec3 a = objects[i].albedo;
    if (!finite(a) || a.r < 0.0f || a.g < 0.0f || a.b < 0.0f) return Error{what + ": albedo must be finite and >= 0"};
    converted.push_back({std::move(mesh), objects[i].transform, a, objects[i].shading});
  }
  impl_->objects = std::move(converted);
  return {};
}

Result<void> FixedRenderer::drawFrame(const FixedFrame& frame, const std::vector<Billboard>& billboards,
                                      const FixedStyle& style) {
  PUFF_TRY(checkFrame(frame, style, cellSize_));
  const GlVersion& version = impl_->version;
  PUFF_TRY(checkHostState(version));

  const glm::vec3 lightCamera = glm::normalize(glm::mat3(frame.view) * glm::normalize(frame.lightDirection));
  const FixedViewport& vp = frame.viewport;
  StateGuard guard(version);
  impl_->resetFixedState();
  if (!frame.clear) impl_->saveCorner(vp, 2 * cellSize_);
  impl_->puffPass(frame, style, lightCamera, cellSize_);
  impl_->puffTextureDrawn = true;
  if (!frame.clear) impl_->restoreCorner(vp, 2 * cellSize_);
  drawScene(frame, billboards, style, false);
  return {};
}

Result<void> FixedRenderer::drawFloorFrame(const FixedFrame& frame, const std::vector<Billboard>& billboards) {
  const FixedStyle style;
  PUFF_TRY(checkFrame(frame, style, cellSize_));
  const GlVersion& version = impl_->version;
  PUFF_TRY(checkHostState(version));
  const FixedViewport& vp = frame.viewport;
  StateGuard guard(version);
  impl_->resetFixedState();
  if (!impl_->puffTextureDrawn) {
    if (!frame.clear) impl_->saveCorner(vp, 2 * cellSize_);
    impl_->puffPass(frame, style, glm::normalize(glm::mat3(frame.view) * glm::normalize(frame.lightDirection)),
                    cellSize_);
    impl_->puffTextureDrawn = true;
    if (!frame.clear) impl_->restoreCorner(vp, 2 * cellSize_);
  }
  drawScene(frame, billboards, style, true);
  return {};
}

void FixedRenderer::drawScene(const FixedFrame& frame, const std::vector<Billboard>& billboards,
                              const FixedStyle& style, bool bare) {
  const glm::vec3 lightWorld = glm::normalize(frame.lightDirection);
  const glm::vec3 lightCamera = glm::normalize(glm::mat3(frame.view) * lightWorld);
  const FixedViewport& vp = frame.viewport;
  FF_GL(glViewport, vp.x, vp.y, vp.width, vp.height);
  FF_GL(glScissor, vp.x, vp.y, vp.width, vp.height);
  if (frame.clear) {
    FF_GL(glClearColor, frame.background.r, frame.background.g, frame.background.b, frame.background.a);
    FF_GL(glClearDepth, 1.0);
    FF_GL(glClear, static_cast<GLbitfield>(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT));
  }
  impl_->objectPass(frame, lightCamera, lightWorld);
  impl_->billboardPass(frame, billboards, style, cellExtent(), bare);
}

unsigned FixedRenderer::puffTexture() const { return impl_->puffTexture; }

float FixedRenderer::cellExtent() const { return extentFor(cellSize_); }

}  // namespace puff::fixedfunc
