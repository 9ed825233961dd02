// A game's own GL setup beside an installed Puff: its own EGL context (surfaceless), its own glad
// loader (generated for this program with glad's ordinary glad_glX names), its own framebuffer and
// clear, and Puff's nailboards drawn into it after puff::core::initGl hands Puff the game's
// getProcAddress. Links both loaders into one program: it fails to link if Puff's loader were not
// private. Then the same frame again with Puff's binding points moved (one base of each kind,
// cel::Bindings::at). Exit 0 when Puff drew a puff in the middle of the game's frame, left its
// corners, and drew the same pixels at the moved bases.
#include <glad/gl.h>  // the game's loader, first: it must not meet another GL header

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstddef>
#include <cstdio>
#include <vector>

#include <puff/bake/baker.h>
#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/core/atlas.h>
#include <puff/core/binding_base.h>
#include <puff/core/gl.h>
#include <puff/io/openimageio.h>

namespace {
int fail(const char* what) {
  std::fprintf(stderr, "host_loader: %s\n", what);
  return 1;
}
GLADapiproc eglLoad(const char* name) { return reinterpret_cast<GLADapiproc>(eglGetProcAddress(name)); }
puff::core::GlProc puffLoad(const char* name) { return reinterpret_cast<puff::core::GlProc>(eglGetProcAddress(name)); }
}  // namespace

int main(int argc, char** argv) {
  puff::io::useOpenImageIO();  // the atlas is baked and read as PNG
  if (argc != 2) return 2;
  // ---- the game's context: EGL surfaceless, GL 4.5 core --------------------------------------
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (getPlatformDisplay == nullptr) return fail("no eglGetPlatformDisplayEXT");
  EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY || eglInitialize(display, nullptr, nullptr) != EGL_TRUE)
    return fail("no surfaceless EGL display");
  eglBindAPI(EGL_OPENGL_API);
  const EGLint attribs[] = {
      EGL_CONTEXT_MAJOR_VERSION,           4,       EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
  if (context == EGL_NO_CONTEXT) return fail("eglCreateContext failed");
  if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) != EGL_TRUE)
    return fail("eglMakeCurrent failed");
  if (gladLoadGL(eglLoad) == 0) return fail("the game's glad could not load GL");

  // ---- Puff, through the game's getProcAddress ---------------------------------------------
  auto loaded = puff::core::initGl(puffLoad);
  if (!loaded) return fail(loaded.error().message.c_str());

  std::vector<puff::bake::PuffSource> sources(1);
  sources[0].mesh = puff::mesh::generateSphere({3});
  sources[0].provenance.generator = "sphere";
  puff::bake::BakeOptions options;
  options.cellSize = 32;
  options.outDir = argv[1];
  auto baked = puff::bake::bakeAtlas(sources, options);
  if (!baked) return fail(baked.error().message.c_str());
  auto atlas = puff::core::loadAtlas(baked->sidecar);
  if (!atlas) return fail(atlas.error().message.c_str());

  // ---- the game's frame: its own FBO (colour + depth/stencil), cleared to blue ---------------
  const int size = 64;
  GLuint fbo = 0, colour = 0, depth = 0;
  glGenFramebuffers(1, &fbo);
  glGenRenderbuffers(1, &colour);
  glGenRenderbuffers(1, &depth);
  glBindRenderbuffer(GL_RENDERBUFFER, colour);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, size, size);
  glBindRenderbuffer(GL_RENDERBUFFER, depth);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, size, size);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) return fail("incomplete framebuffer");
  glViewport(0, 0, size, size);
  glClearColor(0.0f, 0.0f, 1.0f, 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);

  // ---- one puff, 2 units wide, 5 units in front of the camera, drawn at Puff's binding points
  // `bindings` into the game's cleared frame, read back whole with the game's loader --------------
  const auto drawPuff = [&](const puff::cel::Bindings& bindings, std::vector<unsigned char>& pixels) -> const char* {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    auto renderer = puff::cel::NailboardRenderer::create(bindings);
    if (!renderer) return "NailboardRenderer::create failed";
    if (auto set = (*renderer)->setAtlas(*atlas); !set) return "setAtlas failed";
    puff::cel::Camera camera;
    camera.position = {0.0f, 0.0f, 5.0f};
    camera.target = {0.0f, 0.0f, 0.0f};
    puff::cel::FrameBlock block(bindings);
    // The GL standard depth: the game's.
    if (auto ok = block.upload(puff::cel::Frame::fromCamera(camera, size, size)); !ok)
      return "FrameBlock::upload failed";
    puff::cel::Ramp ramp = puff::cel::Ramp::twoTone();
    ramp.bind(bindings);
    puff::cel::Particle particle;
    particle.position = {0.0f, 0.0f, 0.0f};
    particle.size = 2.0f;
    (*renderer)->upload({&particle, 1});
    puff::cel::Style style;
    (*renderer)->drawNailboards(style, puff::cel::ShadePass::kLit);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    pixels.assign(static_cast<std::size_t>(size) * size * 4, 0);
    glReadPixels(0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    return nullptr;
  };
  std::vector<unsigned char> frame, moved;
  if (const char* error = drawPuff(puff::cel::Bindings{}, frame)) return fail(error);
  const puff::core::BindingBase elsewhere{.uniformBuffer = 3, .storageBuffer = 2, .textureUnit = 40};
  if (const char* error = drawPuff(puff::cel::Bindings::at(elsewhere), moved)) return fail(error);

  // ---- the game's frame, as it read it ----------------------------------------------------------
  const auto at = [&](int x, int y) { return &frame[(static_cast<std::size_t>(y) * size + x) * 4]; };
  const unsigned char* centre = at(size / 2, size / 2);
  const unsigned char* corner = at(1, 1);
  if (glGetError() != GL_NO_ERROR) return fail("GL error");
  std::printf("host_loader: GL %d.%d loaded by the game and by Puff; centre %d,%d,%d corner %d,%d,%d\n",
              *loaded / 10000, *loaded % 10000, centre[0], centre[1], centre[2], corner[0], corner[1], corner[2]);
  if (moved != frame) return fail("the frame at moved binding bases differs from the defaults'");
  const bool cornerIsGame = corner[0] == 0 && corner[1] == 0 && corner[2] == 255;
  const bool centreIsPuff = !(centre[0] == 0 && centre[1] == 0 && centre[2] == 255);
  eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  return cornerIsGame && centreIsPuff ? 0 : fail("Puff did not draw into the game's frame");
}
