// Thin RAII owners for GL objects, and the door through which Puff gets its GL entry points.
// Every owner deletes its object in the context that is current when it is destroyed: destroy GL
// objects before their context.
//
// No GL header here, nor in any public Puff header: a game includes its own loader's header (glad,
// GLEW, epoxy, GLFW's) beside Puff's. GL object names and enums appear as GlId and GlEnum, the same
// types as GLuint and GLenum.
#pragma once

#include <string>
#include <string_view>
#include <utility>

#include <puff/core/error.h>

namespace puff::core {

using GlId = unsigned int;    ///< a GL object name (GlId)
using GlEnum = unsigned int;  ///< a GL enum (GLenum)

/// A GL entry point and a loader that returns one by name: glfwGetProcAddress, eglGetProcAddress,
/// SDL_GL_GetProcAddress (cast), or a loader library's own.
using GlProc = void (*)();
using GlProcLoader = GlProc (*)(const char* name);

/// Loads Puff's own GL entry points through the host's `getProcAddress`, with the host's context
/// current. A game that makes its own context calls this once before creating any Puff renderer,
/// e.g. `puff::core::initGl(glfwGetProcAddress)`; Puff's own contexts (createGlContext) call it
/// themselves. Puff's loader is private (its symbols are prefixed puff_glad_), so the game's
/// loader, whatever it is, keeps its own pointers. Returns the GL version loaded as
/// major * 10000 + minor (40005 for 4.5), or an error when the loader gives no glGetString or the
/// context is older than 4.5 (the cel and media paths need 4.5; the fixed path alone needs 1.5:
/// pass minimum 10005 to accept it).
Result<int> initGl(GlProcLoader getProcAddress, int minimum = 40005);
/// Whether Puff's GL entry points are loaded (initGl or a Puff context). Making a GL object (the
/// make* functions below, and so every renderer, FrameBlock, Ramp...) before they are prints one
/// line saying to call initGl, and aborts.
bool glLoaded();

/// A move-only owner of one GL name. Deleter is a function taking the name.
template <void (*Delete)(GlId)>
class GlName {
 public:
  GlName() = default;
  explicit GlName(GlId id) : id_(id) {}
  GlName(GlName&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  GlName& operator=(GlName&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  GlName(const GlName&) = delete;
  GlName& operator=(const GlName&) = delete;
  ~GlName() { reset(); }

  GlId get() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_ != 0) Delete(id_);
    id_ = 0;
  }

 private:
  GlId id_ = 0;
};

namespace detail {
void deleteTexture(GlId id);
void deleteBuffer(GlId id);
void deleteFramebuffer(GlId id);
void deleteRenderbuffer(GlId id);
void deleteVertexArray(GlId id);
void deleteProgram(GlId id);
void deleteShader(GlId id);
}  // namespace detail

using Texture = GlName<detail::deleteTexture>;
using Buffer = GlName<detail::deleteBuffer>;
using Framebuffer = GlName<detail::deleteFramebuffer>;
using Renderbuffer = GlName<detail::deleteRenderbuffer>;
using VertexArray = GlName<detail::deleteVertexArray>;
using Program = GlName<detail::deleteProgram>;
using ShaderObject = GlName<detail::deleteShader>;

// glCreate*. `what` names the object in a capture (RenderDoc, apitrace): labelled "puff: WHAT" where
// the context has KHR_debug (GL 4.3, or the extension); nothing is called without it or without a name.
Texture makeTexture(GlEnum target, std::string_view what = {});
Buffer makeBuffer(std::string_view what = {});
Framebuffer makeFramebuffer(std::string_view what = {});
Renderbuffer makeRenderbuffer(std::string_view what = {});
VertexArray makeVertexArray(std::string_view what = {});

/// "" when glGetError() reports nothing, else the names of the pending errors (all drained).
std::string drainGlErrors();

}  // namespace puff::core
