// Puff's own GL entry points, for Puff's sources only (libraries, apps, tests): never installed,
// never included by a public header. glad 2, generated at configure time with every global symbol
// renamed (puff_glad_glX, puffGladLoadGL: cmake/glad.cmake), so that a host's own loader (glad,
// GLEW, epoxy) links beside it. The pointers are loaded by puff::core::initGl (a host's
// getProcAddress) or by createGlContext (Puff's own contexts).
#pragma once

#include <puff/glad/gl.h>

#include <puff/core/gl.h>

namespace puff::core::detail {
/// Loads Puff's pointers through `load` unless they already came from `loader` (which of
/// puff::platform's backends hands them out: each hands out its own); returns glad's version number,
/// 0 on failure. initGl forgets the loader (a host's pointers come from none). Defined in core/gl.cpp.
int loadGl(int loader, GLADloadfunc load);
/// Forgets that `loader` loaded the pointers (a backend whose library is about to unload).
void forgetGlLoader(int loader);
}  // namespace puff::core::detail
