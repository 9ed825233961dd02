// Puff's own GL entry points, for Puff's sources only (libraries, apps, tests): never installed,
// never included by a public header. glad 2, generated at configure time with every global symbol
// renamed (puff_glad_glX, puffGladLoadGL: cmake/glad.cmake), so that a host's own loader (glad,
// GLEW, epoxy) links beside it. The pointers are loaded by puff::core::initGl (a host's
// getProcAddress) or by createGlContext (Puff's own contexts).
#pragma once

#include <puff/glad/gl.h>

#include <puff/core/gl.h>
