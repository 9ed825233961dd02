// Backend selection and the parts of GlContext every backend shares. The backends live in
// gl_context_{osmesa,egl,glfw}.cpp, each compiled only when its PUFF_HAVE_* is defined.
#include <puff/platform/gl_context.h>
#include <puff/support/text.h>

#include "gl_backends.h"

#include <puff/gl_api.h>

#include <cctype>
#include <cstdlib>
#include <optional>

namespace puff::core {

namespace detail {

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
  if (puff_glad_glGetString == nullptr) return "?";
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

std::optional<GlBackend> parseGlBackend(std::string_view name) {
  const std::string n = lower(name);
  if (n == "osmesa") return GlBackend::kOSMesa;
  if (n == "egl") return GlBackend::kEgl;
  if (n == "glfw") return GlBackend::kGlfw;
  return std::nullopt;
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
  const std::optional<GlBackend> backend = parseGlBackend(name);
  if (!backend) return Error{origin + "unknown GL backend \"" + name + "\" (accepted: " + kAccepted + ")"};

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
