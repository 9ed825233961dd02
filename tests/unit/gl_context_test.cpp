// GL contexts: each backend gives a 4.5 context that really draws (pixels read back, not just a
// non-null handle), errors are one readable line, and backends can live side by side.
#include <gtest/gtest.h>

#include <puff/core/gl.h>
#include <puff/gl_api.h>
#include <puff/platform/gl_context.h>

#include <dlfcn.h>

#include <array>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "support/assert_ok.h"

namespace puff::core {
namespace {

using Rgba = std::array<unsigned char, 4>;

/// Sets or unsets an environment variable for one scope, restoring the old value after.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value)
      setenv(name, value, 1);
    else
      unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_)
      setenv(name_, old_->c_str(), 1);
    else
      unsetenv(name_);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

GLuint compileStage(GLenum type, const char* source) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  EXPECT_EQ(ok, GL_TRUE) << "inline test shader failed to compile";
  return shader;
}

/// A program that draws the triangle (-1,-1) (1,-1) (-1,1), i.e. the lower-left half of the
/// viewport, in opaque red. No buffers: positions come from gl_VertexID.
Program triangleProgram() {
  const char* vs = R"(#version 450 core
const vec2 kCorners[3] = vec2[3](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(-1.0, 1.0));
void main() { gl_Position = vec4(kCorners[gl_VertexID], 0.0, 1.0); })";
  const char* fs = R"(#version 450 core
out vec4 oColor;
void main() { oColor = vec4(1.0, 0.0, 0.0, 1.0); })";
  ShaderObject v(compileStage(GL_VERTEX_SHADER, vs));
  ShaderObject f(compileStage(GL_FRAGMENT_SHADER, fs));
  Program program(glCreateProgram());
  glAttachShader(program.get(), v.get());
  glAttachShader(program.get(), f.get());
  glLinkProgram(program.get());
  GLint ok = GL_FALSE;
  glGetProgramiv(program.get(), GL_LINK_STATUS, &ok);
  EXPECT_EQ(ok, GL_TRUE) << "inline test program failed to link";
  return program;
}

/// Clears the bound draw framebuffer to blue and draws the red triangle over w x h pixels.
void clearAndDrawTriangle(int w, int h) {
  Program program = triangleProgram();
  VertexArray vao = makeVertexArray();  // core profile draws need a VAO even without attributes
  glViewport(0, 0, w, h);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glClearColor(0.0f, 0.0f, 1.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glUseProgram(program.get());
  glBindVertexArray(vao.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
}

std::vector<unsigned char> readPixels(int w, int h) {
  std::vector<unsigned char> pixels(static_cast<std::size_t>(w) * h * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  return pixels;
}

Rgba at(const std::vector<unsigned char>& pixels, int w, int x, int y) {
  const std::size_t i = (static_cast<std::size_t>(y) * w + x) * 4;
  return {pixels[i], pixels[i + 1], pixels[i + 2], pixels[i + 3]};
}

constexpr Rgba kRed = {255, 0, 0, 255};
constexpr Rgba kBlue = {0, 0, 255, 255};

/// Asserts the picture clearAndDrawTriangle makes: red below the diagonal, blue above it.
void expectTrianglePicture(const std::vector<unsigned char>& pixels, int w, int h) {
  EXPECT_EQ(at(pixels, w, 2, 2), kRed) << "inside the triangle (lower left)";
  EXPECT_EQ(at(pixels, w, w / 4, h / 4), kRed);
  EXPECT_EQ(at(pixels, w, w - 3, h - 3), kBlue) << "outside the triangle (upper right): the clear colour";
  EXPECT_EQ(at(pixels, w, 3 * w / 4, 3 * h / 4), kBlue);
  // Exactly half the pixels, give or take the diagonal, are covered.
  int red = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) red += at(pixels, w, x, y) == kRed;
  EXPECT_NEAR(red, w * h / 2, w + h);
}

/// Renders the triangle into a fresh RGBA8 FBO of the current context and checks the pixels.
void expectFboTriangle(int w = 32, int h = 32) {
  Renderbuffer color = makeRenderbuffer();
  glNamedRenderbufferStorage(color.get(), GL_RGBA8, w, h);
  Framebuffer fbo = makeFramebuffer();
  glNamedFramebufferRenderbuffer(fbo.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color.get());
  ASSERT_EQ(glCheckNamedFramebufferStatus(fbo.get(), GL_FRAMEBUFFER), static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE));
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.get());
  clearAndDrawTriangle(w, h);
  const std::vector<unsigned char> pixels = readPixels(w, h);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  EXPECT_EQ(drainGlErrors(), "");
  expectTrianglePicture(pixels, w, h);
}

void expectVersionAtLeast45Core() {
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_GE(major * 10 + minor, 45) << reinterpret_cast<const char*>(glGetString(GL_VERSION));
  EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
  EXPECT_TRUE(PUFF_GLAD_GL_VERSION_4_5) << "glad loaded fewer than 4.5 entry points";
}

Result<std::unique_ptr<GlContext>> create(const char* backend, GlProfile profile = GlProfile::kCore) {
  GlContextOptions options;
  options.backend = backend;
  options.profile = profile;
  return createGlContext(options);
}

// ---- names and errors ----------------------------------------------------------------------------

TEST(GlContext, BackendNamesRoundTrip) {
  for (GlBackend b : {GlBackend::kOSMesa, GlBackend::kEgl, GlBackend::kGlfw}) {
    const std::optional<GlBackend> parsed = parseGlBackend(toString(b));
    ASSERT_TRUE(parsed);
    EXPECT_EQ(*parsed, b);
  }
  const std::optional<GlBackend> upper = parseGlBackend("EGL");
  EXPECT_FALSE(parseGlBackend("vulkan"));
  ASSERT_TRUE(upper);
  EXPECT_EQ(*upper, GlBackend::kEgl);
}

TEST(GlContext, BogusBackendNameIsAnErrorListingTheAcceptedOnes) {
  Result<std::unique_ptr<GlContext>> context = create("vulkan");
  ASSERT_FALSE(context);
  EXPECT_EQ(context.error().message, "unknown GL backend \"vulkan\" (accepted: osmesa, egl, glfw)");
}

TEST(GlContext, PuffGlEnvironmentChoosesTheBackend) {
  {
    ScopedEnv env("PUFF_GL", "directx");
    Result<std::unique_ptr<GlContext>> context = createGlContext();
    ASSERT_FALSE(context);
    EXPECT_EQ(context.error().message, "PUFF_GL: unknown GL backend \"directx\" (accepted: osmesa, egl, glfw)");
  }
  {
    ScopedEnv env("PUFF_GL", nullptr);
    Result<std::unique_ptr<GlContext>> context = createGlContext();
    ASSERT_OK(context);
    EXPECT_EQ((*context)->backend(), GlBackend::kOSMesa) << "OSMesa is the default";
  }
  {
    ScopedEnv env("PUFF_GL", "egl");
    Result<std::unique_ptr<GlContext>> context = createGlContext();
    ASSERT_OK(context);
    EXPECT_EQ((*context)->backend(), GlBackend::kEgl);
  }
}

// ---- OSMesa ----------------------------------------------------------------------------------------

TEST(GlContextOSMesa, Core45DrawsIntoAnFbo) {
  Result<std::unique_ptr<GlContext>> context = create("osmesa");
  ASSERT_OK(context);
  GlContext& gl = **context;
  EXPECT_EQ(gl.backend(), GlBackend::kOSMesa);
  EXPECT_EQ(gl.nativeWindow(), nullptr);
  EXPECT_FALSE(gl.pollEvents());
  const std::string description = gl.describe();
  EXPECT_EQ(description.rfind("osmesa: 4.", 0), 0u) << description;
  EXPECT_NE(description.find("Core Profile"), std::string::npos) << description;
  expectVersionAtLeast45Core();
  expectFboTriangle();
}

// A host that makes its own context hands Puff its getProcAddress (here OSMesa's, found the way a
// host's loader finds it): Puff's pointers come from it and draw; a failed load is an error, and
// Puff's next own context reloads its pointers.
TEST(GlLoader, InitGlLoadsPuffsPointersFromTheHostsGetProcAddress) {
  Result<std::unique_ptr<GlContext>> context = create("osmesa");
  ASSERT_OK(context);
  auto hostGetProc = reinterpret_cast<GlProcLoader>(dlsym(RTLD_DEFAULT, "OSMesaGetProcAddress"));
  ASSERT_NE(hostGetProc, nullptr);
  Result<int> version = initGl(hostGetProc);
  ASSERT_OK(version);
  EXPECT_GE(*version, 40005);
  expectFboTriangle();

  Result<int> tooOld = initGl(hostGetProc, 990000);
  ASSERT_FALSE(tooOld);
  EXPECT_EQ(tooOld.error().message, "initGl: the current context is GL 4." + std::to_string(*version % 10000) +
                                        "; Puff needs 99.0 (the cel and media paths use GL 4.5)");
  Result<int> none = initGl(nullptr);
  ASSERT_FALSE(none);
  EXPECT_EQ(none.error().message, "initGl: no getProcAddress given");
  Result<int> empty = initGl([](const char*) -> GlProc { return nullptr; });
  ASSERT_FALSE(empty);
  EXPECT_EQ(empty.error().message, "initGl: no GL context is current, or getProcAddress gave no glGetString");

  (*context)->makeCurrent();  // Puff's own context reloads the pointers the failed load cleared
  expectFboTriangle();
}

TEST(GlContextOSMesa, CompatibilityProfileHasFixedFunction) {
  Result<std::unique_ptr<GlContext>> context = create("osmesa", GlProfile::kCompatibility);
  ASSERT_OK(context);
  GLint profile = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_TRUE(profile & GL_CONTEXT_COMPATIBILITY_PROFILE_BIT);
  glMatrixMode(GL_MODELVIEW);  // GL_INVALID_OPERATION in a core context
  glLoadIdentity();
  EXPECT_EQ(drainGlErrors(), "");
}

TEST(GlContextOSMesa, UnavailableVersionIsAnError) {
  GlContextOptions options;
  options.backend = "osmesa";
  options.major = 9;
  options.minor = 9;
  Result<std::unique_ptr<GlContext>> context = createGlContext(options);
  ASSERT_FALSE(context);
  EXPECT_EQ(context.error().message.rfind("osmesa: cannot create a 9.9 core context: ", 0), 0u)
      << context.error().message;
}

TEST(GlContextOSMesa, DrainGlErrorsNamesAndClearsThem) {
  Result<std::unique_ptr<GlContext>> context = create("osmesa");
  ASSERT_OK(context);
  EXPECT_EQ(drainGlErrors(), "");
  glEnable(0x7fff);  // not a capability
  EXPECT_EQ(drainGlErrors(), "GL_INVALID_ENUM");
  EXPECT_EQ(drainGlErrors(), "") << "drained";
}

TEST(GlContextOSMesa, GlNamesAreOwnedAndMoved) {
  Result<std::unique_ptr<GlContext>> context = create("osmesa");
  ASSERT_OK(context);
  Texture a = makeTexture(GL_TEXTURE_2D);
  ASSERT_TRUE(a);
  const GLuint id = a.get();
  EXPECT_TRUE(glIsTexture(id));
  Texture b = std::move(a);
  EXPECT_FALSE(a);  // NOLINT(bugprone-use-after-move): moved-from is documented as empty
  EXPECT_EQ(b.get(), id);
  b.reset();
  EXPECT_FALSE(glIsTexture(id)) << "reset deletes the texture";
  Buffer buffer = makeBuffer();
  VertexArray vao = makeVertexArray();
  EXPECT_TRUE(glIsBuffer(buffer.get()));
  EXPECT_TRUE(glIsVertexArray(vao.get()));
  EXPECT_EQ(drainGlErrors(), "");
}

// ---- EGL -------------------------------------------------------------------------------------------

TEST(GlContextEgl, Core45DrawsIntoAnFbo) {
  // EGL surfaceless works on the machines Puff is built and tested on (Mesa, as setup.sh installs it),
  // so failing to create is a failure.
  Result<std::unique_ptr<GlContext>> context = create("egl");
  ASSERT_OK(context);
  GlContext& gl = **context;
  EXPECT_EQ(gl.backend(), GlBackend::kEgl);
  EXPECT_EQ(gl.nativeWindow(), nullptr);
  EXPECT_EQ(gl.describe().rfind("egl: 4.", 0), 0u) << gl.describe();
  expectVersionAtLeast45Core();
  expectFboTriangle();
}

TEST(GlContextEgl, DevicePlatformDrawsIntoAnFbo) {
  // The path a headless NVIDIA GPU takes; Mesa offers a software device to exercise it.
  ScopedEnv env("PUFF_EGL_PLATFORM", "device");
  Result<std::unique_ptr<GlContext>> context = create("egl");
  ASSERT_OK(context);
  expectVersionAtLeast45Core();
  expectFboTriangle();
}

TEST(GlContextEgl, CompatibilityProfile) {
  Result<std::unique_ptr<GlContext>> context = create("egl", GlProfile::kCompatibility);
  ASSERT_OK(context);
  GLint profile = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_TRUE(profile & GL_CONTEXT_COMPATIBILITY_PROFILE_BIT);
}

TEST(GlContextEgl, UnavailableVersionNamesTheFailingCall) {
  GlContextOptions options;
  options.backend = "egl";
  options.major = 9;
  options.minor = 9;
  Result<std::unique_ptr<GlContext>> context = createGlContext(options);
  ASSERT_FALSE(context);
  const std::string& message = context.error().message;
  EXPECT_EQ(message.rfind("egl: cannot create a 9.9 core context: ", 0), 0u) << message;
  EXPECT_NE(message.find("eglCreateContext failed (EGL_"), std::string::npos) << message;
}

// ---- several contexts ------------------------------------------------------------------------------

TEST(GlContext, OSMesaAndEglContextsTakeTurns) {
  // glad holds one set of function pointers; each backend's pointers only reach its own
  // contexts, so makeCurrent must switch them.
  Result<std::unique_ptr<GlContext>> osmesa = create("osmesa");
  ASSERT_OK(osmesa);
  Result<std::unique_ptr<GlContext>> egl = create("egl");
  ASSERT_OK(egl);
  for (int round = 0; round < 2; ++round) {
    for (GlContext* gl : {osmesa->get(), egl->get()}) {
      SCOPED_TRACE(std::string(toString(gl->backend())) + " round " + std::to_string(round));
      gl->makeCurrent();
      EXPECT_EQ(gl->describe().rfind(std::string(toString(gl->backend())) + ": 4.", 0), 0u) << gl->describe();
      expectFboTriangle(16, 16);
    }
  }
  // Two contexts of one backend share the display (EGL) and the loader: destroying one leaves the
  // other working.
  {
    Result<std::unique_ptr<GlContext>> egl2 = create("egl");
    ASSERT_OK(egl2);
  }
  (*egl)->makeCurrent();
  expectFboTriangle(16, 16);
}

// ---- GLFW ------------------------------------------------------------------------------------------

bool glfwRequired() {
  const char* v = std::getenv("PUFF_TEST_REQUIRE_GLFW");
  return v != nullptr && *v != '\0' && std::string(v) != "0";
}

TEST(GlContextGlfw, WindowDrawsAndReadsTheDefaultFramebuffer) {
  if (!glfwRequired() && std::getenv("DISPLAY") == nullptr && std::getenv("WAYLAND_DISPLAY") == nullptr)
    GTEST_SKIP() << "no display (DISPLAY unset); ctest runs this under Xvfb with PUFF_TEST_REQUIRE_GLFW=1";
  GlContextOptions options;
  options.backend = "glfw";
  options.width = 48;
  options.height = 40;
  options.visible = true;  // a mapped window owns its pixels; Xvfb shows it to no one
  Result<std::unique_ptr<GlContext>> context = createGlContext(options);
  ASSERT_OK(context);
  GlContext& gl = **context;
  EXPECT_EQ(gl.backend(), GlBackend::kGlfw);
  EXPECT_NE(gl.nativeWindow(), nullptr);
  EXPECT_EQ(gl.describe().rfind("glfw: 4.", 0), 0u) << gl.describe();
  expectVersionAtLeast45Core();

  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDrawBuffer(GL_BACK);
  glReadBuffer(GL_BACK);
  clearAndDrawTriangle(options.width, options.height);
  const std::vector<unsigned char> pixels = readPixels(options.width, options.height);
  EXPECT_EQ(drainGlErrors(), "");
  expectTrianglePicture(pixels, options.width, options.height);
  gl.swapBuffers();
  EXPECT_FALSE(gl.pollEvents()) << "nobody asked the window to close";
  expectFboTriangle();  // FBOs work in a window context too
}

TEST(GlContextGlfw, NoDisplayIsAnErrorNotACrash) {
  ScopedEnv display("DISPLAY", nullptr);
  ScopedEnv wayland("WAYLAND_DISPLAY", nullptr);
  Result<std::unique_ptr<GlContext>> context = create("glfw");
  ASSERT_FALSE(context);
  const std::string& message = context.error().message;
  EXPECT_EQ(message.rfind("glfw: cannot open a window: ", 0), 0u) << message;
  EXPECT_NE(message.find("DISPLAY"), std::string::npos) << "GLFW's own reason is kept: " << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line";
}

}  // namespace
}  // namespace puff::core
