// Loading Puff's GL entry points (initGl for a host's context; detail::loadGl for Puff's own
// backends, puff::platform), and the RAII owners' deleters and creators. Creation uses direct state
// access (glCreate*), so a new name is a complete object at once and nothing needs to be bound.
#include <puff/gl_api.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace puff::core {

namespace detail {
// glad keeps one global set of function pointers, and each backend hands out its own: OSMesa gives
// Mesa's glapi stubs, EGL and GLX give glvnd's dispatch stubs, which call the vendor that owns the
// current EGL/GLX context. On an all-Mesa system both routes end in Mesa's one dispatch table and
// are interchangeable (measured with Mesa 22.3), but with another vendor's EGL (NVIDIA) OSMesa's
// stubs would not reach its contexts, nor glvnd's reach OSMesa's. So glad is reloaded whenever a
// context of a different backend becomes current. Within one backend the pointers do not depend on
// the context. Like glad itself, this is process-wide, not per thread.
namespace {
std::optional<int> gLoadedFor;  // the loader (a backend of puff::platform) the pointers came from
}  // namespace

int loadGl(int loader, GLADloadfunc load) {
  if (gLoadedFor == loader) return 1;
  const int version = puffGladLoadGL(load);
  if (version == 0) {
    gLoadedFor.reset();
    return 0;
  }
  gLoadedFor = loader;
  return version;
}

void forgetGlLoader(int loader) {
  if (gLoadedFor == loader) gLoadedFor.reset();
}
}  // namespace detail

Result<int> initGl(GlProcLoader getProcAddress, int minimum) {
  if (getProcAddress == nullptr) return Error{"initGl: no getProcAddress given"};
  // The host's pointers come from no Puff backend: a Puff context made later reloads its own.
  detail::gLoadedFor.reset();
  const int version = puffGladLoadGL(getProcAddress);
  if (version == 0) {
    return Error{"initGl: no GL context is current, or getProcAddress gave no glGetString"};
  }
  if (version < minimum) {
    return Error{"initGl: the current context is GL " + std::to_string(version / 10000) + "." +
                 std::to_string(version % 10000) + "; Puff needs " + std::to_string(minimum / 10000) + "." +
                 std::to_string(minimum % 10000) + " (the cel and media paths use GL 4.5)"};
  }
  return version;
}

namespace detail {
void deleteTexture(GlId id) { glDeleteTextures(1, &id); }
void deleteBuffer(GlId id) { glDeleteBuffers(1, &id); }
void deleteFramebuffer(GlId id) { glDeleteFramebuffers(1, &id); }
void deleteRenderbuffer(GlId id) { glDeleteRenderbuffers(1, &id); }
void deleteVertexArray(GlId id) { glDeleteVertexArrays(1, &id); }
void deleteProgram(GlId id) { glDeleteProgram(id); }
void deleteShader(GlId id) { glDeleteShader(id); }
}  // namespace detail

namespace {
// A GL object made before any context loaded Puff's pointers would call a null pointer: say why
// and stop, once, instead of crashing without a word (a host that forgot initGl).
void requireLoaded(const char* what) {
  if (puff_glad_glCreateBuffers != nullptr) return;
  std::fprintf(stderr,
               "puff: %s before Puff's GL functions were loaded: make a GL 4.5 context current and call "
               "puff::core::initGl(getProcAddress)\n",
               what);
  std::abort();
}
}  // namespace

bool hasDebugNames() { return PUFF_GLAD_GL_VERSION_4_3 || PUFF_GLAD_GL_KHR_debug; }

void labelObject(GLenum kind, GLuint name, std::string_view what) {
  if (what.empty() || name == 0 || !hasDebugNames()) return;
  const std::string text = "puff: " + std::string(what);
  glObjectLabel(kind, name, static_cast<GLsizei>(text.size()), text.data());
}

DrawBufferZero::DrawBufferZero() {
  GLint framebuffer = 0, maxDraw = 1;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
  if (framebuffer == 0) return;
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &maxDraw);
  std::vector<GLenum> buffers(static_cast<std::size_t>(std::max(maxDraw, 1)), GL_NONE);
  bool others = false;
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    GLint buffer = GL_NONE;
    glGetIntegerv(GL_DRAW_BUFFER0 + static_cast<GLenum>(i), &buffer);
    buffers[i] = static_cast<GLenum>(buffer);
    others |= i > 0 && buffer != GL_NONE;
  }
  if (!others) return;
  framebuffer_ = static_cast<GLuint>(framebuffer);
  saved_ = std::move(buffers);
  glNamedFramebufferDrawBuffers(framebuffer_, 1, saved_.data());
}

DrawBufferZero::~DrawBufferZero() {
  if (!saved_.empty()) glNamedFramebufferDrawBuffers(framebuffer_, static_cast<GLsizei>(saved_.size()), saved_.data());
}

DebugGroup::DebugGroup(std::string_view pass) : pushed_(hasDebugNames()) {
  if (!pushed_) return;
  const std::string text = "puff: " + std::string(pass);
  glPushDebugGroup(GL_DEBUG_SOURCE_APPLICATION, 0, static_cast<GLsizei>(text.size()), text.data());
}

DebugGroup::~DebugGroup() {
  if (pushed_) glPopDebugGroup();
}

bool glLoaded() { return puff_glad_glCreateBuffers != nullptr && puff_glad_glGetString != nullptr; }

Texture makeTexture(GlEnum target, std::string_view what) {
  requireLoaded("a GL texture was made");
  GlId id = 0;
  glCreateTextures(target, 1, &id);
  labelObject(GL_TEXTURE, id, what);
  return Texture(id);
}

Buffer makeBuffer(std::string_view what) {
  requireLoaded("a GL buffer was made");
  GlId id = 0;
  glCreateBuffers(1, &id);
  labelObject(GL_BUFFER, id, what);
  return Buffer(id);
}

Framebuffer makeFramebuffer(std::string_view what) {
  requireLoaded("a GL framebuffer was made");
  GlId id = 0;
  glCreateFramebuffers(1, &id);
  labelObject(GL_FRAMEBUFFER, id, what);
  return Framebuffer(id);
}

Renderbuffer makeRenderbuffer(std::string_view what) {
  requireLoaded("a GL renderbuffer was made");
  GlId id = 0;
  glCreateRenderbuffers(1, &id);
  labelObject(GL_RENDERBUFFER, id, what);
  return Renderbuffer(id);
}

VertexArray makeVertexArray(std::string_view what) {
  requireLoaded("a GL vertex array was made");
  GlId id = 0;
  glCreateVertexArrays(1, &id);
  labelObject(GL_VERTEX_ARRAY, id, what);
  return VertexArray(id);
}

namespace {
std::string glErrorName(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW:
      return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW:
      return "GL_STACK_OVERFLOW";
    case GL_CONTEXT_LOST:
      return "GL_CONTEXT_LOST";
  }
  char hex[32];
  std::snprintf(hex, sizeof hex, "GL error 0x%04x", error);
  return hex;
}
}  // namespace

std::string drainGlErrors() {
  std::string names;
  // Bounded: without a current context (or after GL_CONTEXT_LOST) glGetError may never return
  // GL_NO_ERROR. Each error flag is reported once per drain, so a few iterations cover them all.
  for (int i = 0; i < 16; ++i) {
    const GLenum error = glGetError();
    if (error == GL_NO_ERROR) break;
    if (!names.empty()) names += ", ";
    names += glErrorName(error);
    if (error == GL_CONTEXT_LOST) break;
  }
  return names;
}

}  // namespace puff::core
