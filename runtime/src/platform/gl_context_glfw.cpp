// GLFW: a real window with its default framebuffer. GLFW is initialized with the first window and
// terminated with the last, so a process that only opens a window now and then holds no X
// connection in between. GLFW must be used from the main thread.
#include <puff/gl_api.h>  // before GLFW, which would otherwise include the system <GL/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <string>

#include <puff/platform/gl_context.h>

#include "gl_backends.h"

namespace puff::core {

namespace {

int gWindows = 0;        // live GlfwGlContexts; GLFW is initialized while this is > 0
std::string gLastError;  // the last message GLFW reported, e.g. "X11: The DISPLAY ... missing"

void onGlfwError(int /*code*/, const char* description) { gLastError = description ? description : "?"; }

/// The captured GLFW message, or `fallback` when GLFW said nothing; clears it.
std::string takeError(const char* fallback) {
  std::string message = gLastError.empty() ? fallback : gLastError;
  gLastError.clear();
  return message;
}

GLADapiproc loadGlfw(const char* name) { return glfwGetProcAddress(name); }

void releaseGlfw() {
  if (--gWindows == 0) {
    glfwTerminate();
    // glfwTerminate unloads the GLX library glad's pointers came from.
    detail::forgetGlLoader(GlBackend::kGlfw);
  }
}

class GlfwGlContext final : public GlContext {
 public:
  explicit GlfwGlContext(GLFWwindow* window) : GlContext(GlBackend::kGlfw), window_(window) {}

  ~GlfwGlContext() override {
    if (glfwGetCurrentContext() == window_) glfwMakeContextCurrent(nullptr);
    glfwDestroyWindow(window_);
    releaseGlfw();
  }

  void makeCurrent() override {
    glfwMakeContextCurrent(window_);
    PUFF_CHECK(detail::loadGl(GlBackend::kGlfw, loadGlfw) != 0);
  }
  void swapBuffers() override { glfwSwapBuffers(window_); }
  bool pollEvents() override {
    glfwPollEvents();
    return glfwWindowShouldClose(window_) == GLFW_TRUE;
  }
  void* nativeWindow() override { return window_; }

 private:
  GLFWwindow* window_;
};

}  // namespace

namespace detail {

Result<std::unique_ptr<GlContext>> createGlfwContext(const GlContextOptions& options) {
  if (options.width <= 0 || options.height <= 0)
    return Error{"glfw: cannot open a window: width and height must be positive"};
  if (gWindows == 0) {
    glfwSetErrorCallback(onGlfwError);  // allowed before glfwInit, and the only way to learn why it failed
    gLastError.clear();
    if (glfwInit() != GLFW_TRUE) return Error{"glfw: cannot open a window: " + takeError("glfwInit failed")};
  }
  ++gWindows;  // from here on, releaseGlfw() undoes the initialization on failure

  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, options.major);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, options.minor);
  // Profiles exist only from 3.2 on; asking for one below that is an error in GLFW.
  const bool profiles = options.major > 3 || (options.major == 3 && options.minor >= 2);
  glfwWindowHint(GLFW_OPENGL_PROFILE, !profiles                             ? GLFW_OPENGL_ANY_PROFILE
                                      : options.profile == GlProfile::kCore ? GLFW_OPENGL_CORE_PROFILE
                                                                            : GLFW_OPENGL_COMPAT_PROFILE);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_DEPTH_BITS, 24);
  glfwWindowHint(GLFW_STENCIL_BITS, 8);

  GLFWwindow* window = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (window == nullptr) {
    releaseGlfw();
    return Error{"glfw: cannot create a " + versionName(options) + " window: " + takeError("glfwCreateWindow failed")};
  }
  auto context = std::make_unique<GlfwGlContext>(window);  // owns the window and the GLFW use
  glfwMakeContextCurrent(window);
  if (loadGl(GlBackend::kGlfw, loadGlfw) == 0) return Error{"glfw: glad could not load GL through glfwGetProcAddress"};
  return std::unique_ptr<GlContext>(std::move(context));
}

}  // namespace detail
}  // namespace puff::core
