// OSMesa: Mesa's software rasterizer (llvmpipe) drawing into a buffer in our memory. No display,
// no X, no EGL. GL is loaded through OSMesaGetProcAddress only: linking libGL into the same
// binary would shadow OSMesa's gl* symbols and turn every call into a silent no-op.
#include <puff/gl_api.h>  // before <GL/osmesa.h>, which would otherwise pull in the system <GL/gl.h>

#include <GL/osmesa.h>

#include <vector>

#include <puff/platform/gl_context.h>

#include "gl_backends.h"

namespace puff::core {

namespace {

GLADapiproc loadOSMesa(const char* name) { return OSMesaGetProcAddress(name); }

class OSMesaGlContext final : public GlContext {
 public:
  OSMesaGlContext(OSMesaContext context, int width, int height)
      : GlContext(GlBackend::kOSMesa),
        context_(context),
        width_(width),
        height_(height),
        buffer_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4) {}

  ~OSMesaGlContext() override {
    // Unbind first: Mesa would otherwise keep a dangling pointer to our buffer as the current
    // draw target of this thread.
    if (OSMesaGetCurrentContext() == context_) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    OSMesaDestroyContext(context_);
  }

  bool bind() { return OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, width_, height_) == GL_TRUE; }

  void makeCurrent() override {
    PUFF_CHECK(bind());
    PUFF_CHECK(detail::loadGl(GlBackend::kOSMesa, loadOSMesa) != 0);
  }
  void swapBuffers() override {}
  bool pollEvents() override { return false; }
  void* nativeWindow() override { return nullptr; }

 private:
  OSMesaContext context_;
  int width_, height_;
  std::vector<unsigned char> buffer_;  // the default framebuffer's colour, RGBA8, bottom row first
};

}  // namespace

namespace detail {

Result<std::unique_ptr<GlContext>> createOSMesaContext(const GlContextOptions& options) {
  const std::string what = "osmesa: cannot create a " + versionName(options) + " context: ";
  if (options.width <= 0 || options.height <= 0) return Error{what + "width and height must be positive"};
  // Attribute lists read as key, value pairs.
  // clang-format off
  const int attribs[] = {
      OSMESA_FORMAT, OSMESA_RGBA,
      OSMESA_DEPTH_BITS, 24,
      OSMESA_STENCIL_BITS, 8,
      OSMESA_PROFILE, options.profile == GlProfile::kCore ? OSMESA_CORE_PROFILE : OSMESA_COMPAT_PROFILE,
      OSMESA_CONTEXT_MAJOR_VERSION, options.major,
      OSMESA_CONTEXT_MINOR_VERSION, options.minor,
      0,
  };
  // clang-format on
  OSMesaContext raw = OSMesaCreateContextAttribs(attribs, nullptr);
  if (raw == nullptr) return Error{what + "OSMesaCreateContextAttribs failed (version or profile not available)"};
  auto context = std::make_unique<OSMesaGlContext>(raw, options.width, options.height);
  if (!context->bind()) return Error{what + "OSMesaMakeCurrent failed"};
  const int version = loadGl(GlBackend::kOSMesa, loadOSMesa);
  if (version == 0) return Error{what + "glad could not load GL through OSMesaGetProcAddress"};
  return std::unique_ptr<GlContext>(std::move(context));
}

}  // namespace detail
}  // namespace puff::core
