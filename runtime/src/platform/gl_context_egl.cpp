// EGL without a window system: Mesa's surfaceless platform, or, where that is missing (the
// NVIDIA driver), the device platform, which is how a headless GPU is reached. The context has no
// config and no surface (EGL_KHR_no_config_context, EGL_KHR_surfaceless_context): it renders
// into FBOs only. Only libEGL is linked; GL comes through eglGetProcAddress.
#include <puff/gl_api.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <puff/platform/gl_context.h>

#include "gl_backends.h"

namespace puff::core {

namespace {

GLADapiproc loadEgl(const char* name) { return eglGetProcAddress(name); }

const char* eglErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
      return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
      return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
      return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
      return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
      return "EGL_CONTEXT_LOST";
#ifdef EGL_BAD_DEVICE_EXT
    case EGL_BAD_DEVICE_EXT:
      return "EGL_BAD_DEVICE_EXT";
#endif
  }
  return "unknown EGL error";
}

/// "eglInitialize failed (EGL_NOT_INITIALIZED)": reads and clears the thread's EGL error.
std::string eglFailure(const char* call) {
  const EGLint error = eglGetError();
  char hex[16];
  std::snprintf(hex, sizeof hex, "0x%04x", static_cast<unsigned>(error));
  return std::string(call) + " failed (" + eglErrorName(error) + ", " + hex + ")";
}

bool hasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    const bool startOk = p == list || p[-1] == ' ';
    const bool endOk = p[n] == ' ' || p[n] == '\0';
    if (startOk && endOk) return true;
  }
  return false;
}

// eglGetPlatformDisplay returns one EGLDisplay per (platform, device) for the whole process, and
// eglTerminate ends every context on it, including a host application's. So displays are
// initialized once and never terminated; Mesa and NVIDIA clean up at process exit. (Terminating
// with our last context also made Mesa unload and reload its driver for each context.)
class EglGlContext final : public GlContext {
 public:
  EglGlContext(EGLDisplay display, EGLContext context)
      : GlContext(GlBackend::kEgl), display_(display), context_(context) {}

  ~EglGlContext() override {
    if (eglGetCurrentContext() == context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    // Frees this thread's EGL state once nothing of ours is current; eglGetCurrentContext
    // would otherwise keep it alive until the thread exits.
    if (eglGetCurrentContext() == EGL_NO_CONTEXT) eglReleaseThread();
  }

  bool bind() { return eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) == EGL_TRUE; }

  void makeCurrent() override {
    PUFF_CHECK(bind());
    PUFF_CHECK(detail::loadGl(GlBackend::kEgl, loadEgl) != 0);
  }
  void swapBuffers() override {}
  bool pollEvents() override { return false; }
  void* nativeWindow() override { return nullptr; }

 private:
  EGLDisplay display_;
  EGLContext context_;
};

/// An initialized display on `platform`, or an error naming the call that failed.
Result<EGLDisplay> openDisplay(PFNEGLGETPLATFORMDISPLAYEXTPROC getPlatformDisplay, EGLenum platform,
                               void* nativeDisplay) {
  EGLDisplay display = getPlatformDisplay(platform, nativeDisplay, nullptr);
  if (display == EGL_NO_DISPLAY) return Error{eglFailure("eglGetPlatformDisplayEXT")};
  EGLint major = 0, minor = 0;
  // Initializing an initialized display is a no-op, so every context creation may call it.
  if (eglInitialize(display, &major, &minor) != EGL_TRUE) return Error{eglFailure("eglInitialize")};
  return display;
}

Result<std::unique_ptr<GlContext>> createOnDisplay(EGLDisplay display, const GlContextOptions& options) {
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) return Error{eglFailure("eglBindAPI(EGL_OPENGL_API)")};

  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  if (!hasExtension(extensions, "EGL_KHR_surfaceless_context"))
    return Error{"display lacks EGL_KHR_surfaceless_context"};
  // Without EGL_KHR_no_config_context, any OpenGL-capable config does: we never draw to a surface.
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!hasExtension(extensions, "EGL_KHR_no_config_context") &&
      !hasExtension(extensions, "EGL_MESA_configless_context")) {
    const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint count = 0;
    if (eglChooseConfig(display, configAttribs, &config, 1, &count) != EGL_TRUE || count < 1)
      return Error{eglFailure("eglChooseConfig(EGL_OPENGL_BIT)")};
  }

  // Attribute lists read as key, value pairs.
  // clang-format off
  const EGLint contextAttribs[] = {
      EGL_CONTEXT_MAJOR_VERSION, options.major,
      EGL_CONTEXT_MINOR_VERSION, options.minor,
      EGL_CONTEXT_OPENGL_PROFILE_MASK, options.profile == GlProfile::kCore
                                           ? EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT
                                           : EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT,
      EGL_NONE,
  };
  // clang-format on
  EGLContext raw = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
  if (raw == EGL_NO_CONTEXT) return Error{eglFailure("eglCreateContext")};
  auto context = std::make_unique<EglGlContext>(display, raw);
  if (!context->bind()) return Error{eglFailure("eglMakeCurrent(EGL_NO_SURFACE)")};
  if (detail::loadGl(GlBackend::kEgl, loadEgl) == 0) return Error{"glad could not load GL through eglGetProcAddress"};
  return std::unique_ptr<GlContext>(std::move(context));
}

}  // namespace

namespace detail {

Result<std::unique_ptr<GlContext>> createEglContext(const GlContextOptions& options) {
  const std::string what = "egl: cannot create a " + versionName(options) + " context: ";
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);  // client extensions
  if (client == nullptr) return Error{what + eglFailure("eglQueryString(EGL_EXTENSIONS)")};
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (getPlatformDisplay == nullptr || !hasExtension(client, "EGL_EXT_platform_base"))
    return Error{what + "EGL_EXT_platform_base is not available"};

  // PUFF_EGL_PLATFORM=device skips surfaceless, to exercise the path a headless NVIDIA GPU takes.
  const char* forced = std::getenv("PUFF_EGL_PLATFORM");
  const std::string only = forced != nullptr ? forced : "";
  if (!only.empty() && only != "surfaceless" && only != "device")
    return Error{what + "PUFF_EGL_PLATFORM: unknown value \"" + only + "\" (accepted: surfaceless, device)"};

  std::vector<std::string> tried;  // one entry per platform attempt, for the error message
  if (only != "device") {
    if (hasExtension(client, "EGL_MESA_platform_surfaceless")) {
      Result<EGLDisplay> display = openDisplay(getPlatformDisplay, EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY);
      if (display) {
        auto context = createOnDisplay(*display, options);
        if (context) return context;
        tried.push_back("surfaceless: " + context.error().message);
      } else {
        tried.push_back("surfaceless: " + display.error().message);
      }
    } else {
      tried.push_back("surfaceless: EGL_MESA_platform_surfaceless is not available");
    }
  }
  if (only != "surfaceless") {
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (queryDevices == nullptr || !hasExtension(client, "EGL_EXT_platform_device")) {
      tried.push_back("device: EGL_EXT_platform_device is not available");
    } else {
      EGLDeviceEXT devices[16];
      EGLint count = 0;
      if (queryDevices(16, devices, &count) != EGL_TRUE) {
        tried.push_back("device: " + eglFailure("eglQueryDevicesEXT"));
      } else if (count == 0) {
        tried.push_back("device: eglQueryDevicesEXT found no devices");
      }
      // The first device that gives a context wins; the first failure is the one reported.
      for (EGLint i = 0; i < count; ++i) {
        Result<EGLDisplay> display = openDisplay(getPlatformDisplay, EGL_PLATFORM_DEVICE_EXT, devices[i]);
        std::string problem;
        if (display) {
          auto context = createOnDisplay(*display, options);
          if (context) return context;
          problem = context.error().message;
        } else {
          problem = display.error().message;
        }
        if (i == 0) tried.push_back("device 0 of " + std::to_string(count) + ": " + problem);
      }
    }
  }
  std::string message = what;
  for (std::size_t i = 0; i < tried.size(); ++i) message += (i ? "; " : "") + tried[i];
  return Error{message};
}

}  // namespace detail
}  // namespace puff::core
