// GL contexts, kept apart from rendering: a renderer draws into whatever context is current.
// Three backends behind one interface: OSMesa (headless default), EGL surfaceless (headless,
// and the way to a real GPU without X), GLFW (a real window). All load GL through glad.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <puff/core/error.h>

namespace puff::core {

enum class GlBackend { kOSMesa, kEgl, kGlfw };

/// "osmesa", "egl", "glfw".
std::string_view toString(GlBackend backend);
/// Parses "osmesa" | "egl" | "glfw" (case-insensitive); nothing for any other name.
std::optional<GlBackend> parseGlBackend(std::string_view name);

enum class GlProfile { kCore, kCompatibility };

struct GlContextOptions {
  /// Unset means: the PUFF_GL environment variable if set ("osmesa", "egl", "glfw"), else OSMesa
  /// (EGL in a build without OSMesa).
  std::string backend;
  GlProfile profile = GlProfile::kCore;
  int major = 4, minor = 5;  ///< requested version; 4.5 is the most Mesa's llvmpipe gives
  /// Size of the default framebuffer (window size for GLFW, OSMesa's buffer). Headless backends
  /// have no default framebuffer worth drawing into: render into an FBO.
  int width = 64, height = 64;
  bool visible = false;  ///< GLFW only: show the window
  std::string title = "puff";
};

class GlContext {
 public:
  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  /// Makes this context current on the calling thread (contexts are current after creation).
  virtual void makeCurrent() = 0;
  /// Presents the default framebuffer (GLFW); a no-op for headless backends.
  virtual void swapBuffers() = 0;
  /// GLFW: processes window events and returns true once the user asked to close. Else false.
  virtual bool pollEvents() = 0;
  /// The GLFW window (GLFWwindow*), or nullptr for headless backends.
  virtual void* nativeWindow() = 0;

  GlBackend backend() const { return backend_; }
  /// e.g. "osmesa: 4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string describe() const;

 protected:
  explicit GlContext(GlBackend backend) : backend_(backend) {}

 private:
  GlBackend backend_;
};

/// Creates a context, makes it current and loads GL through glad. Failure (backend not built,
/// no display, version not available, ...) is an Error with one line saying which backend failed
/// and why; it never crashes or exits.
Result<std::unique_ptr<GlContext>> createGlContext(const GlContextOptions& options = {});

}  // namespace puff::core
