// HostStateGuard: one capture of the host's state, and on the way out a second capture compared
// item by item, setting only what differs.
#include <puff/core/host_state.h>

#include <algorithm>
#include <array>
#include <vector>

#include <puff/core/gl.h>
#include <puff/gl_api.h>

namespace puff::core {

namespace {

constexpr std::array<GLenum, 11> kTargets = {GL_TEXTURE_1D,
                                             GL_TEXTURE_2D,
                                             GL_TEXTURE_3D,
                                             GL_TEXTURE_1D_ARRAY,
                                             GL_TEXTURE_2D_ARRAY,
                                             GL_TEXTURE_RECTANGLE,
                                             GL_TEXTURE_CUBE_MAP,
                                             GL_TEXTURE_CUBE_MAP_ARRAY,
                                             GL_TEXTURE_BUFFER,
                                             GL_TEXTURE_2D_MULTISAMPLE,
                                             GL_TEXTURE_2D_MULTISAMPLE_ARRAY};
constexpr std::array<GLenum, 11> kTargetBindings = {GL_TEXTURE_BINDING_1D,
                                                    GL_TEXTURE_BINDING_2D,
                                                    GL_TEXTURE_BINDING_3D,
                                                    GL_TEXTURE_BINDING_1D_ARRAY,
                                                    GL_TEXTURE_BINDING_2D_ARRAY,
                                                    GL_TEXTURE_BINDING_RECTANGLE,
                                                    GL_TEXTURE_BINDING_CUBE_MAP,
                                                    GL_TEXTURE_BINDING_CUBE_MAP_ARRAY,
                                                    GL_TEXTURE_BINDING_BUFFER,
                                                    GL_TEXTURE_BINDING_2D_MULTISAMPLE,
                                                    GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY};

// Capabilities saved as one enable each (GL_BLEND is per draw buffer, below).
constexpr std::array<GLenum, 22> kCaps = {GL_CULL_FACE,
                                          GL_DEPTH_TEST,
                                          GL_STENCIL_TEST,
                                          GL_SCISSOR_TEST,
                                          GL_FRAMEBUFFER_SRGB,
                                          GL_DEPTH_CLAMP,
                                          GL_POLYGON_OFFSET_FILL,
                                          GL_POLYGON_OFFSET_LINE,
                                          GL_POLYGON_OFFSET_POINT,
                                          GL_SAMPLE_ALPHA_TO_COVERAGE,
                                          GL_SAMPLE_ALPHA_TO_ONE,
                                          GL_SAMPLE_COVERAGE,
                                          GL_MULTISAMPLE,
                                          GL_RASTERIZER_DISCARD,
                                          GL_PRIMITIVE_RESTART,
                                          GL_PRIMITIVE_RESTART_FIXED_INDEX,
                                          GL_DITHER,
                                          GL_COLOR_LOGIC_OP,
                                          GL_PROGRAM_POINT_SIZE,
                                          GL_TEXTURE_CUBE_MAP_SEAMLESS,
                                          GL_SAMPLE_SHADING,
                                          GL_SAMPLE_MASK};

bool depthBounds() { return PUFF_GLAD_GL_EXT_depth_bounds_test != 0 && glDepthBoundsEXT != nullptr; }

GLint geti(GLenum e) {
  GLint v = 0;
  glGetIntegerv(e, &v);
  return v;
}

struct IndexedBuffer {
  GLint buffer = 0;
  GLint64 start = 0, size = 0;
  bool operator==(const IndexedBuffer&) const = default;
};

struct DrawBufferState {
  GLboolean blend = GL_FALSE;
  std::array<GLint, 4> func{};  // src rgb, dst rgb, src alpha, dst alpha
  std::array<GLint, 2> equation{};
  std::array<GLboolean, 4> colorMask{};
  bool operator==(const DrawBufferState&) const = default;
};

struct StencilFace {
  std::array<GLint, 7> v{};  // func, ref, value mask, fail, depth fail, depth pass, write mask
  bool operator==(const StencilFace&) const = default;
};

// Reads the first n indexed bindings of one buffer target: buffer, start and size of each.
std::vector<IndexedBuffer> captureIndexed(GLenum binding, GLenum start, GLenum size, int n) {
  std::vector<IndexedBuffer> out(static_cast<std::size_t>(std::max(0, n)));
  for (int i = 0; i < n; ++i) {
    IndexedBuffer& b = out[static_cast<std::size_t>(i)];
    glGetIntegeri_v(binding, static_cast<GLuint>(i), &b.buffer);
    glGetInteger64i_v(start, static_cast<GLuint>(i), &b.start);
    glGetInteger64i_v(size, static_cast<GLuint>(i), &b.size);
  }
  return out;
}

// Rebinds each indexed binding of `target` whose wanted state differs from what `is` read back.
// A saved texture or buffer name, or 0 where the guarded calls deleted its object: only Puff's own
// objects are deleted there (a target remade for another size, samples or format), and binding a
// deleted name is an error.
GLuint liveTexture(GLint name) {
  const auto n = static_cast<GLuint>(name);
  return n != 0 && glIsTexture(n) ? n : 0;
}
GLuint liveBuffer(GLint name) {
  const auto n = static_cast<GLuint>(name);
  return n != 0 && glIsBuffer(n) ? n : 0;
}

void applyIndexed(GLenum target, const std::vector<IndexedBuffer>& want, const std::vector<IndexedBuffer>& is) {
  for (std::size_t i = 0; i < want.size(); ++i) {
    if (want[i] == is[i]) continue;
    IndexedBuffer b = want[i];
    b.buffer = static_cast<GLint>(liveBuffer(b.buffer));
    // A whole-buffer binding reads back with size 0.
    if (b.buffer != 0 && b.size > 0) {
      glBindBufferRange(target, static_cast<GLuint>(i), static_cast<GLuint>(b.buffer), static_cast<GLintptr>(b.start),
                        static_cast<GLsizeiptr>(b.size));
    } else {
      glBindBufferBase(target, static_cast<GLuint>(i), static_cast<GLuint>(b.buffer));
    }
  }
}

// Reads the front and back stencil state, the two faces' items interleaved.
void captureStencil(StencilFace& front, StencilFace& back) {
  const GLenum frontQ[7] = {GL_STENCIL_FUNC,
                            GL_STENCIL_REF,
                            GL_STENCIL_VALUE_MASK,
                            GL_STENCIL_FAIL,
                            GL_STENCIL_PASS_DEPTH_FAIL,
                            GL_STENCIL_PASS_DEPTH_PASS,
                            GL_STENCIL_WRITEMASK};
  const GLenum backQ[7] = {GL_STENCIL_BACK_FUNC,
                           GL_STENCIL_BACK_REF,
                           GL_STENCIL_BACK_VALUE_MASK,
                           GL_STENCIL_BACK_FAIL,
                           GL_STENCIL_BACK_PASS_DEPTH_FAIL,
                           GL_STENCIL_BACK_PASS_DEPTH_PASS,
                           GL_STENCIL_BACK_WRITEMASK};
  for (int i = 0; i < 7; ++i) {
    front.v[static_cast<std::size_t>(i)] = geti(frontQ[i]);
    back.v[static_cast<std::size_t>(i)] = geti(backQ[i]);
  }
}

// Sets face f's stencil function, operations and write mask where `w` differs from `n`.
void applyStencilFace(GLenum f, const StencilFace& w, const StencilFace& n) {
  if (w.v[0] != n.v[0] || w.v[1] != n.v[1] || w.v[2] != n.v[2]) {
    glStencilFuncSeparate(f, static_cast<GLenum>(w.v[0]), w.v[1], static_cast<GLuint>(w.v[2]));
  }
  if (w.v[3] != n.v[3] || w.v[4] != n.v[4] || w.v[5] != n.v[5]) {
    glStencilOpSeparate(f, static_cast<GLenum>(w.v[3]), static_cast<GLenum>(w.v[4]), static_cast<GLenum>(w.v[5]));
  }
  if (w.v[6] != n.v[6]) glStencilMaskSeparate(f, static_cast<GLuint>(w.v[6]));
}

// Sets draw buffer d's blending and colour mask where `w` differs from `n`.
void applyDrawBuffer(GLuint d, const DrawBufferState& w, const DrawBufferState& n) {
  if (w.blend != n.blend) (w.blend ? glEnablei : glDisablei)(GL_BLEND, d);
  if (w.func != n.func) {
    glBlendFuncSeparatei(d, static_cast<GLenum>(w.func[0]), static_cast<GLenum>(w.func[1]),
                         static_cast<GLenum>(w.func[2]), static_cast<GLenum>(w.func[3]));
  }
  if (w.equation != n.equation) {
    glBlendEquationSeparatei(d, static_cast<GLenum>(w.equation[0]), static_cast<GLenum>(w.equation[1]));
  }
  if (w.colorMask != n.colorMask) glColorMaski(d, w.colorMask[0], w.colorMask[1], w.colorMask[2], w.colorMask[3]);
}

}  // namespace

GuardExtent GuardExtent::cover(const GuardExtent& o) const {
  return {std::max(textureUnits, o.textureUnits), std::max(uniformBuffers, o.uniformBuffers),
          std::max(storageBuffers, o.storageBuffers), std::max(drawBuffers, o.drawBuffers)};
}

struct HostStateGuard::Saved {
  GuardExtent extent;
  GLint program = 0, vertexArray = 0, drawFbo = 0, readFbo = 0, arrayBuffer = 0, uniformGeneric = 0, storageGeneric = 0,
        activeTexture = GL_TEXTURE0;
  std::vector<IndexedBuffer> uniform, storage;
  std::vector<std::array<GLint, kTargets.size() + 1>> units;  // per unit: each target, then the sampler
  std::vector<DrawBufferState> drawBuffers;
  std::array<GLfloat, 4> blendColor{};
  std::array<GLboolean, kCaps.size()> caps{};
  GLint depthFunc = GL_LESS;
  GLboolean depthMask = GL_TRUE;
  std::array<GLdouble, 2> depthRange{};
  GLboolean depthBoundsTest = GL_FALSE;
  std::array<GLdouble, 2> depthBoundsRange{};
  StencilFace front, back;
  GLint cullFace = GL_BACK, frontFace = GL_CCW;
  std::array<GLint, 4> viewport{}, scissor{};
  std::array<GLfloat, 2> polygonOffset{};  // factor, units
  std::array<GLint, 2> polygonMode{};
  GLint packAlignment = 4, unpackAlignment = 4;

  // Reads every item, for the units, buffers and draw buffers that `e` covers.
  void capture(const GuardExtent& e) {
    extent = e;
    captureBindings(e);
    captureTextureUnits(e);
    captureDrawBuffers(e);
    captureCapsAndDepth();
    captureStencil(front, back);
    captureRasterAndPixelStore();
  }

  // Sets every item of `this` that differs from `now` (the state as it is).
  void applyOver(const Saved& now) const {
    applyBindings(now);
    applyTextureUnits(now);
    applyDrawBuffers(now);
    applyCapsAndDepth(now);
    applyStencilFace(GL_FRONT, front, now.front);
    applyStencilFace(GL_BACK, back, now.back);
    applyRasterAndPixelStore(now);
  }

 private:
  // Reads the program, vertex array, framebuffer and buffer bindings, indexed ones included.
  void captureBindings(const GuardExtent& e) {
    program = geti(GL_CURRENT_PROGRAM);
    vertexArray = geti(GL_VERTEX_ARRAY_BINDING);
    drawFbo = geti(GL_DRAW_FRAMEBUFFER_BINDING);
    readFbo = geti(GL_READ_FRAMEBUFFER_BINDING);
    arrayBuffer = geti(GL_ARRAY_BUFFER_BINDING);
    uniformGeneric = geti(GL_UNIFORM_BUFFER_BINDING);
    storageGeneric = geti(GL_SHADER_STORAGE_BUFFER_BINDING);
    uniform =
        captureIndexed(GL_UNIFORM_BUFFER_BINDING, GL_UNIFORM_BUFFER_START, GL_UNIFORM_BUFFER_SIZE, e.uniformBuffers);
    storage = captureIndexed(GL_SHADER_STORAGE_BUFFER_BINDING, GL_SHADER_STORAGE_BUFFER_START,
                             GL_SHADER_STORAGE_BUFFER_SIZE, e.storageBuffers);
  }

  // Reads the active unit and each unit's textures and sampler, visiting the units and coming back.
  void captureTextureUnits(const GuardExtent& e) {
    activeTexture = geti(GL_ACTIVE_TEXTURE);
    units.assign(static_cast<std::size_t>(std::max(0, e.textureUnits)), {});
    for (int u = 0; u < e.textureUnits; ++u) {
      glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(u));
      auto& row = units[static_cast<std::size_t>(u)];
      for (std::size_t t = 0; t < kTargets.size(); ++t) row[t] = geti(kTargetBindings[t]);
      row[kTargets.size()] = geti(GL_SAMPLER_BINDING);
    }
    glActiveTexture(static_cast<GLenum>(activeTexture));
  }

  // Reads each draw buffer's blending and colour mask, then the blend colour.
  void captureDrawBuffers(const GuardExtent& e) {
    drawBuffers.assign(static_cast<std::size_t>(std::max(0, e.drawBuffers)), {});
    for (int i = 0; i < e.drawBuffers; ++i) {
      const auto d = static_cast<GLuint>(i);
      DrawBufferState& s = drawBuffers[static_cast<std::size_t>(i)];
      s.blend = glIsEnabledi(GL_BLEND, d);
      glGetIntegeri_v(GL_BLEND_SRC_RGB, d, &s.func[0]);
      glGetIntegeri_v(GL_BLEND_DST_RGB, d, &s.func[1]);
      glGetIntegeri_v(GL_BLEND_SRC_ALPHA, d, &s.func[2]);
      glGetIntegeri_v(GL_BLEND_DST_ALPHA, d, &s.func[3]);
      glGetIntegeri_v(GL_BLEND_EQUATION_RGB, d, &s.equation[0]);
      glGetIntegeri_v(GL_BLEND_EQUATION_ALPHA, d, &s.equation[1]);
      glGetBooleani_v(GL_COLOR_WRITEMASK, d, s.colorMask.data());
    }
    glGetFloatv(GL_BLEND_COLOR, blendColor.data());
  }

  // Reads the capabilities, then the depth function, mask, range and (where there are) bounds.
  void captureCapsAndDepth() {
    for (std::size_t c = 0; c < kCaps.size(); ++c) caps[c] = glIsEnabled(kCaps[c]);
    depthFunc = geti(GL_DEPTH_FUNC);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &depthMask);
    glGetDoublev(GL_DEPTH_RANGE, depthRange.data());
    if (depthBounds()) {
      depthBoundsTest = glIsEnabled(GL_DEPTH_BOUNDS_TEST_EXT);
      glGetDoublev(GL_DEPTH_BOUNDS_EXT, depthBoundsRange.data());
    }
  }

  // Reads culling, viewport, scissor, polygon offset and mode, and the pack and unpack alignments.
  void captureRasterAndPixelStore() {
    cullFace = geti(GL_CULL_FACE_MODE);
    frontFace = geti(GL_FRONT_FACE);
    glGetIntegerv(GL_VIEWPORT, viewport.data());
    glGetIntegerv(GL_SCISSOR_BOX, scissor.data());
    glGetFloatv(GL_POLYGON_OFFSET_FACTOR, &polygonOffset[0]);
    glGetFloatv(GL_POLYGON_OFFSET_UNITS, &polygonOffset[1]);
    polygonMode = {GL_FILL, GL_FILL};
    glGetIntegerv(GL_POLYGON_MODE, polygonMode.data());
    packAlignment = geti(GL_PACK_ALIGNMENT);
    unpackAlignment = geti(GL_UNPACK_ALIGNMENT);
  }

  // Sets the program, vertex array, framebuffer and buffer bindings that differ from `now`.
  void applyBindings(const Saved& now) const {
    if (now.program != program) glUseProgram(static_cast<GLuint>(program));
    if (now.vertexArray != vertexArray) glBindVertexArray(static_cast<GLuint>(vertexArray));
    if (now.drawFbo != drawFbo) glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(drawFbo));
    if (now.readFbo != readFbo) glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(readFbo));
    applyIndexed(GL_UNIFORM_BUFFER, uniform, now.uniform);
    applyIndexed(GL_SHADER_STORAGE_BUFFER, storage, now.storage);
    // The generic bindings after the indexed ones (glBindBufferBase/Range set them too).
    glBindBuffer(GL_UNIFORM_BUFFER, liveBuffer(static_cast<GLint>(uniformGeneric)));
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, liveBuffer(static_cast<GLint>(storageGeneric)));
    if (now.arrayBuffer != arrayBuffer) glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(arrayBuffer));
  }

  // Sets the textures and samplers of each unit that differs from `now`, then the active unit.
  void applyTextureUnits(const Saved& now) const {
    for (std::size_t u = 0; u < units.size(); ++u) {
      if (units[u] == now.units[u]) continue;
      glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(u));
      for (std::size_t t = 0; t < kTargets.size(); ++t) {
        if (units[u][t] != now.units[u][t]) glBindTexture(kTargets[t], liveTexture(static_cast<GLint>(units[u][t])));
      }
      if (units[u][kTargets.size()] != now.units[u][kTargets.size()]) {
        glBindSampler(static_cast<GLuint>(u), static_cast<GLuint>(units[u][kTargets.size()]));
      }
    }
    glActiveTexture(static_cast<GLenum>(activeTexture));
  }

  // Sets each draw buffer's blending and colour mask, then the blend colour, where they differ from `now`.
  void applyDrawBuffers(const Saved& now) const {
    for (std::size_t i = 0; i < drawBuffers.size(); ++i) {
      applyDrawBuffer(static_cast<GLuint>(i), drawBuffers[i], now.drawBuffers[i]);
    }
    if (blendColor != now.blendColor) glBlendColor(blendColor[0], blendColor[1], blendColor[2], blendColor[3]);
  }

  // Sets the capabilities, then the depth function, mask, range and bounds, where they differ from `now`.
  void applyCapsAndDepth(const Saved& now) const {
    for (std::size_t c = 0; c < kCaps.size(); ++c) {
      if (caps[c] != now.caps[c]) (caps[c] ? glEnable : glDisable)(kCaps[c]);
    }
    if (depthFunc != now.depthFunc) glDepthFunc(static_cast<GLenum>(depthFunc));
    if (depthMask != now.depthMask) glDepthMask(depthMask);
    if (depthRange != now.depthRange) glDepthRange(depthRange[0], depthRange[1]);
    if (depthBounds()) {
      if (depthBoundsTest != now.depthBoundsTest) (depthBoundsTest ? glEnable : glDisable)(GL_DEPTH_BOUNDS_TEST_EXT);
      if (depthBoundsRange != now.depthBoundsRange) glDepthBoundsEXT(depthBoundsRange[0], depthBoundsRange[1]);
    }
  }

  // Sets culling, viewport, scissor, polygon offset and mode, and the alignments that differ from `now`.
  void applyRasterAndPixelStore(const Saved& now) const {
    if (cullFace != now.cullFace) glCullFace(static_cast<GLenum>(cullFace));
    if (frontFace != now.frontFace) glFrontFace(static_cast<GLenum>(frontFace));
    if (viewport != now.viewport) glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    if (scissor != now.scissor) glScissor(scissor[0], scissor[1], scissor[2], scissor[3]);
    if (polygonOffset != now.polygonOffset) glPolygonOffset(polygonOffset[0], polygonOffset[1]);
    // A core profile sets both faces at once; a compatibility host's split modes come back as front's.
    if (polygonMode != now.polygonMode) glPolygonMode(GL_FRONT_AND_BACK, static_cast<GLenum>(polygonMode[0]));
    if (packAlignment != now.packAlignment) glPixelStorei(GL_PACK_ALIGNMENT, packAlignment);
    if (unpackAlignment != now.unpackAlignment) glPixelStorei(GL_UNPACK_ALIGNMENT, unpackAlignment);
  }
};

HostStateGuard::HostStateGuard(const GuardExtent& extent) : saved_(std::make_unique<Saved>()) {
  saved_->capture(extent);
}

HostStateGuard::~HostStateGuard() { restore(); }

void HostStateGuard::restore() {
  if (!saved_) return;
  Saved now;
  now.capture(saved_->extent);
  saved_->applyOver(now);
  saved_.reset();
}

}  // namespace puff::core
