// Private to puff::platform: what gl_context.cpp and the backend files share.
#pragma once

#include <memory>
#include <string>

#include <puff/gl_api.h>

#include <puff/platform/gl_context.h>

namespace puff::core::detail {

// Defined by the backend files. Each creates the context, makes it current and loads glad.
#ifdef PUFF_HAVE_OSMESA
Result<std::unique_ptr<GlContext>> createOSMesaContext(const GlContextOptions& options);
#endif
#ifdef PUFF_HAVE_EGL
Result<std::unique_ptr<GlContext>> createEglContext(const GlContextOptions& options);
#endif
#ifdef PUFF_HAVE_GLFW
Result<std::unique_ptr<GlContext>> createGlfwContext(const GlContextOptions& options);
#endif

/// Loads glad through `load` unless the pointers already come from `backend`; returns glad's
/// version number (0 on failure). core/gl.cpp says why backends reload.
inline int loadGl(GlBackend backend, GLADloadfunc load) { return loadGl(static_cast<int>(backend), load); }
/// Forgets which backend loaded glad (a backend whose library is about to unload calls this).
inline void forgetGlLoader(GlBackend backend) { forgetGlLoader(static_cast<int>(backend)); }
/// "4.5 core" / "2.1 compatibility", for messages.
std::string versionName(const GlContextOptions& options);

}  // namespace puff::core::detail
