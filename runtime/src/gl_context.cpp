// Backend selection and the parts of GlContext every backend shares. The backends live in
// gl_context_{osmesa,egl,glfw}.cpp, each compiled only when its PUFF_HAVE_* is defined.
#include <puff/core/gl_context.h>
#include <puff/core/text.h>

#include "gl_backends.h"

#include <glad/gl.h>

#include <cctype>
#include <cstdlib>
#include <optional>

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
std::optional<GlBackend> gLoadedFor;
}  // namespace

int loadGl(GlBackend backend, GLADloadfunc load) {
  if (gLoadedFor == backend) return 1;
  const int version = gladLoadGL(load);
  if (version == 0) {
    gLoadedFor.reset();
    return 0;
  }
  gLoadedFor = backend;
  return version;
}

void forgetGlLoader(GlBackend backend) {
  if (gLoadedFor == backend) gLoadedFor.reset();
}

// The backends need the error name; kept here so all three say the same.
std::string versionName(const GlContextOptions& options) {
  return std::to_string(options.major) + "." + std::to_string(options.minor) +
         (options.profile == GlProfile::kCore ? " core" : " compatibility");
}
}  // namespace detail

namespace {
constexpr const char* kAccepted = "osmesa, egl, glfw";

using core::lower;

[[maybe_unused]] Error notBuilt(GlBackend backend, const char* option) {
  return Error{std::string(toString(backend)) + ": backend not built into this binary (configure with -D" + option +
               "=ON)"};
}

std::string glString(GLenum name) {
  if (glad_glGetString == nullptr) return "?";
  const GLubyte* s = glGetString(name);
  return s ? reinterpret_cast<const char*>(s) : "?";
}
}  // namespace

std::string_view toString(GlBackend backend) {
  switch (backend) {
    case GlBackend::kOSMesa:
      return "osmesa";
    case GlBackend::kEgl:
      return "egl";
    case GlBackend::kGlfw:
      return "glfw";
  }
  return "?";
}

Result<GlBackend> parseGlBackend(std::string_view name) {
  const std::string n = lower(name);
  if (n == "osmesa") return GlBackend::kOSMesa;
  if (n == "egl") return GlBackend::kEgl;
  if (n == "glfw") return GlBackend::kGlfw;
  return Error{"unknown GL backend \"" + std::string(name) + "\" (accepted: " + kAccepted + ")"};
}

std::string GlContext::describe() const {
  // Queries the current context: describe() is meant for the context just created or made current.
  return std::string(toString(backend_)) + ": " + glString(GL_VERSION) + ", " + glString(GL_RENDERER);
}

Result<std::unique_ptr<GlContext>> createGlContext(const GlContextOptions& options) {
  std::string name = options.backend;
  std::string origin;  // where the name came from, for the error message
  if (name.empty()) {
    const char* env = std::getenv("PUFF_GL");
    if (env != nullptr && *env != '\0') {
      name = env;
      origin = "PUFF_GL: ";
    } else {
      // The first headless backend this build has: OSMesa, else EGL (where OSMesa is gone).
#if defined(PUFF_HAVE_OSMESA)
      name = "osmesa";
#elif defined(PUFF_HAVE_EGL)
      name = "egl";
#else
      name = "glfw";
#endif
    }
  }
  Result<GlBackend> backend = parseGlBackend(name);
  if (!backend) return Error{origin + backend.error().message};

  switch (*backend) {
    case GlBackend::kOSMesa:
#ifdef PUFF_HAVE_OSMESA
      return detail::createOSMesaContext(options);
#else
      return notBuilt(*backend, "PUFF_WITH_OSMESA");
#endif
    case GlBackend::kEgl:
#ifdef PUFF_HAVE_EGL
      return detail::createEglContext(options);
#else
      return notBuilt(*backend, "PUFF_WITH_EGL");
#endif
    case GlBackend::kGlfw:
#ifdef PUFF_HAVE_GLFW
      return detail::createGlfwContext(options);
#else
      return notBuilt(*backend, "PUFF_WITH_GLFW");
#endif
  }
  return Error{"unreachable GL backend"};
}

}  // namespace puff::core
