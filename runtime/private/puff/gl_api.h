// Puff's own GL entry points, for Puff's sources only (libraries, apps, tests): never installed,
// never included by a public header. glad 2, generated at configure time with every global symbol
// renamed (puff_glad_glX, puffGladLoadGL: cmake/glad.cmake), so that a host's own loader (glad,
// GLEW, epoxy) links beside it. The pointers are loaded by puff::core::initGl (a host's
// getProcAddress) or by createGlContext (Puff's own contexts).
#pragma once

#include <puff/glad/gl.h>

#include <string_view>
#include <vector>

#include <puff/core/gl.h>

namespace puff::core {
/// Whether the current context names objects and passes for a capture: KHR_debug (GL 4.3 or the
/// extension). The fixed path's GL 1.x contexts have neither.
bool hasDebugNames();
/// Labels object `name` (GL_PROGRAM, GL_TEXTURE, GL_BUFFER, GL_FRAMEBUFFER, GL_RENDERBUFFER,
/// GL_VERTEX_ARRAY) "puff: WHAT" where hasDebugNames(); nothing otherwise.
void labelObject(GLenum kind, GLuint name, std::string_view what);
/// A pass in a capture: a debug group "puff: PASS" pushed for the object's life where
/// hasDebugNames() (nothing otherwise). No GL state changes.
class DebugGroup {
 public:
  explicit DebugGroup(std::string_view pass);
  ~DebugGroup();
  DebugGroup(const DebugGroup&) = delete;
  DebugGroup& operator=(const DebugGroup&) = delete;

 private:
  bool pushed_ = false;
};

/// While it lives, the bound draw framebuffer draws to its draw buffer 0 alone: a host's framebuffer
/// with more colour attachments enabled (a G-buffer, a velocity target) is given its first alone
/// (glNamedFramebufferDrawBuffers) and its own draw buffers back at the end, so a pass writes no
/// attachment but the first, whatever the others' write masks. The default framebuffer and one
/// drawing to one buffer are left alone. "First" is the framebuffer's draw buffer 0: a host that
/// set it to GL_NONE gets no colour from Puff. Queries the draw framebuffer binding and its draw
/// buffers (up to GL_MAX_DRAW_BUFFERS).
class DrawBufferZero {
 public:
  DrawBufferZero();
  ~DrawBufferZero();
  DrawBufferZero(const DrawBufferZero&) = delete;
  DrawBufferZero& operator=(const DrawBufferZero&) = delete;

 private:
  GLuint framebuffer_ = 0;
  std::vector<GLenum> saved_;  // the host's draw buffers (empty: nothing to restore)
};
}  // namespace puff::core

namespace puff::core::detail {
/// Loads Puff's pointers through `load` unless they already came from `loader` (which of
/// puff::platform's backends hands them out: each hands out its own); returns glad's version number,
/// 0 on failure. initGl forgets the loader (a host's pointers come from none). Defined in core/gl.cpp.
int loadGl(int loader, GLADloadfunc load);
/// Forgets that `loader` loaded the pointers (a backend whose library is about to unload).
void forgetGlLoader(int loader);
}  // namespace puff::core::detail
