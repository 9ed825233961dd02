// The host-state contract (docs/cel-rendering.md and docs/media.md, "Host state"): on a host whose
// GL state is deliberately hostile, every public cel and media call changes exactly the state its
// header lists (encoded below as data, one list per call), core::HostStateGuard gives all of it
// back, and binding points chosen by the host draw the same image as the defaults without touching
// the host's objects on the default points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/cel/bindings.h>
#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/cel/opaque.h>
#include <puff/cel/shadow_map.h>
#include <puff/cel/volume_clip.h>
#include <puff/core/host_state.h>
#include <puff/core/shader.h>
#include <puff/gl_api.h>
#include <puff/media/bindings.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>

#include "support/assert_ok.h"
#include "support/gl_target.h"
#include "support/sphere_atlas.h"

namespace puff {
namespace {

using Keys = std::set<std::string>;
using State = std::map<std::string, std::string>;

// ---- the snapshot: every piece of state core/host_state.h lists, and every piece any Puff call sets

constexpr int kUnits = 24;       // texture units looked at (Puff's defaults use 0-7; the chosen ones below up to 23)
constexpr int kIndexed = 16;     // uniform and storage buffer bindings looked at
constexpr int kDrawBuffers = 2;  // per-draw-buffer blend state and colour masks

struct Target {
  GLenum target, binding;
  const char* name;
};
const Target kTargets[] = {{GL_TEXTURE_1D, GL_TEXTURE_BINDING_1D, "1D"},
                           {GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D, "2D"},
                           {GL_TEXTURE_3D, GL_TEXTURE_BINDING_3D, "3D"},
                           {GL_TEXTURE_1D_ARRAY, GL_TEXTURE_BINDING_1D_ARRAY, "1DArray"},
                           {GL_TEXTURE_2D_ARRAY, GL_TEXTURE_BINDING_2D_ARRAY, "2DArray"},
                           {GL_TEXTURE_RECTANGLE, GL_TEXTURE_BINDING_RECTANGLE, "Rect"},
                           {GL_TEXTURE_CUBE_MAP, GL_TEXTURE_BINDING_CUBE_MAP, "Cube"},
                           {GL_TEXTURE_CUBE_MAP_ARRAY, GL_TEXTURE_BINDING_CUBE_MAP_ARRAY, "CubeArray"},
                           {GL_TEXTURE_BUFFER, GL_TEXTURE_BINDING_BUFFER, "Buffer"},
                           {GL_TEXTURE_2D_MULTISAMPLE, GL_TEXTURE_BINDING_2D_MULTISAMPLE, "2DMS"},
                           {GL_TEXTURE_2D_MULTISAMPLE_ARRAY, GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY, "2DMSArray"}};

std::string ints(std::initializer_list<long long> v) {
  std::string s;
  for (long long x : v) s += (s.empty() ? "" : " ") + std::to_string(x);
  return s;
}
GLint geti(GLenum e) {
  GLint v = 0;
  glGetIntegerv(e, &v);
  return v;
}

State snapshot() {
  State s;
  const auto flag = [&](const char* key, GLenum cap) { s[key] = glIsEnabled(cap) ? "on" : "off"; };
  s["program"] = ints({geti(GL_CURRENT_PROGRAM)});
  s["vao"] = ints({geti(GL_VERTEX_ARRAY_BINDING)});
  s["fbo.draw"] = ints({geti(GL_DRAW_FRAMEBUFFER_BINDING)});
  s["fbo.read"] = ints({geti(GL_READ_FRAMEBUFFER_BINDING)});
  s["buffer.array"] = ints({geti(GL_ARRAY_BUFFER_BINDING)});
  s["buffer.uniform"] = ints({geti(GL_UNIFORM_BUFFER_BINDING)});
  s["buffer.storage"] = ints({geti(GL_SHADER_STORAGE_BUFFER_BINDING)});
  for (GLuint i = 0; i < kIndexed; ++i) {
    GLint b = 0;
    GLint64 start = 0, size = 0;
    glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, i, &b);
    glGetInteger64i_v(GL_UNIFORM_BUFFER_START, i, &start);
    glGetInteger64i_v(GL_UNIFORM_BUFFER_SIZE, i, &size);
    s["ubo[" + std::to_string(i) + "]"] = ints({b, start, size});
    glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, i, &b);
    glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, i, &start);
    glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, i, &size);
    s["ssbo[" + std::to_string(i) + "]"] = ints({b, start, size});
  }
  const GLint active = geti(GL_ACTIVE_TEXTURE);
  s["active_texture"] = ints({active});
  for (int u = 0; u < kUnits; ++u) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(u));
    const std::string unit = "[" + std::to_string(u) + "]";
    for (const Target& t : kTargets) s["tex" + unit + "." + t.name] = ints({geti(t.binding)});
    s["sampler" + unit] = ints({geti(GL_SAMPLER_BINDING)});
  }
  glActiveTexture(static_cast<GLenum>(active));
  for (GLuint i = 0; i < kDrawBuffers; ++i) {
    const std::string d = "[" + std::to_string(i) + "]";
    s["blend" + d] = glIsEnabledi(GL_BLEND, i) ? "on" : "off";
    GLint f[4], e[2];
    glGetIntegeri_v(GL_BLEND_SRC_RGB, i, &f[0]);
    glGetIntegeri_v(GL_BLEND_DST_RGB, i, &f[1]);
    glGetIntegeri_v(GL_BLEND_SRC_ALPHA, i, &f[2]);
    glGetIntegeri_v(GL_BLEND_DST_ALPHA, i, &f[3]);
    glGetIntegeri_v(GL_BLEND_EQUATION_RGB, i, &e[0]);
    glGetIntegeri_v(GL_BLEND_EQUATION_ALPHA, i, &e[1]);
    s["blend_func" + d] = ints({f[0], f[1], f[2], f[3]});
    s["blend_eq" + d] = ints({e[0], e[1]});
    GLboolean m[4];
    glGetBooleani_v(GL_COLOR_WRITEMASK, i, m);
    s["colormask" + d] = ints({m[0], m[1], m[2], m[3]});
  }
  GLfloat c[4];
  glGetFloatv(GL_BLEND_COLOR, c);
  s["blend_color"] =
      std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) + " " + std::to_string(c[3]);
  flag("depth.test", GL_DEPTH_TEST);
  s["depth.func"] = ints({geti(GL_DEPTH_FUNC)});
  GLboolean dm = GL_FALSE;
  glGetBooleanv(GL_DEPTH_WRITEMASK, &dm);
  s["depth.mask"] = ints({dm});
  GLdouble range[2];
  glGetDoublev(GL_DEPTH_RANGE, range);
  s["depth.range"] = std::to_string(range[0]) + " " + std::to_string(range[1]);
  flag("depth.clamp", GL_DEPTH_CLAMP);
  flag("stencil.test", GL_STENCIL_TEST);
  s["stencil.front.func"] = ints({geti(GL_STENCIL_FUNC), geti(GL_STENCIL_VALUE_MASK)});
  s["stencil.back.func"] = ints({geti(GL_STENCIL_BACK_FUNC), geti(GL_STENCIL_BACK_VALUE_MASK)});
  // The reference reads back clamped to the bound draw framebuffer's stencil bits.
  s["stencil.front.ref"] = ints({geti(GL_STENCIL_REF)});
  s["stencil.back.ref"] = ints({geti(GL_STENCIL_BACK_REF)});
  s["stencil.front.op"] =
      ints({geti(GL_STENCIL_FAIL), geti(GL_STENCIL_PASS_DEPTH_FAIL), geti(GL_STENCIL_PASS_DEPTH_PASS)});
  s["stencil.back.op"] =
      ints({geti(GL_STENCIL_BACK_FAIL), geti(GL_STENCIL_BACK_PASS_DEPTH_FAIL), geti(GL_STENCIL_BACK_PASS_DEPTH_PASS)});
  s["stencil.front.writemask"] = ints({geti(GL_STENCIL_WRITEMASK)});
  s["stencil.back.writemask"] = ints({geti(GL_STENCIL_BACK_WRITEMASK)});
  flag("cull", GL_CULL_FACE);
  s["cull.face"] = ints({geti(GL_CULL_FACE_MODE)});
  s["front_face"] = ints({geti(GL_FRONT_FACE)});
  flag("srgb", GL_FRAMEBUFFER_SRGB);
  flag("scissor", GL_SCISSOR_TEST);
  GLint box[4];
  glGetIntegerv(GL_SCISSOR_BOX, box);
  s["scissor.box"] = ints({box[0], box[1], box[2], box[3]});
  glGetIntegerv(GL_VIEWPORT, box);
  s["viewport"] = ints({box[0], box[1], box[2], box[3]});
  flag("polygon_offset.fill", GL_POLYGON_OFFSET_FILL);
  flag("polygon_offset.line", GL_POLYGON_OFFSET_LINE);
  flag("polygon_offset.point", GL_POLYGON_OFFSET_POINT);
  GLfloat po[2];
  glGetFloatv(GL_POLYGON_OFFSET_FACTOR, &po[0]);
  glGetFloatv(GL_POLYGON_OFFSET_UNITS, &po[1]);
  s["polygon_offset"] = std::to_string(po[0]) + " " + std::to_string(po[1]);
  GLint pm[2] = {0, 0};
  glGetIntegerv(GL_POLYGON_MODE, pm);
  s["polygon_mode"] = ints({pm[0]});
  flag("alpha_to_coverage", GL_SAMPLE_ALPHA_TO_COVERAGE);
  flag("alpha_to_one", GL_SAMPLE_ALPHA_TO_ONE);
  flag("sample_coverage", GL_SAMPLE_COVERAGE);
  flag("sample_shading", GL_SAMPLE_SHADING);
  flag("sample_mask", GL_SAMPLE_MASK);
  flag("multisample", GL_MULTISAMPLE);
  flag("rasterizer_discard", GL_RASTERIZER_DISCARD);
  flag("primitive_restart", GL_PRIMITIVE_RESTART);
  flag("primitive_restart_fixed", GL_PRIMITIVE_RESTART_FIXED_INDEX);
  flag("dither", GL_DITHER);
  flag("logic_op", GL_COLOR_LOGIC_OP);
  flag("program_point_size", GL_PROGRAM_POINT_SIZE);
  flag("cube_seamless", GL_TEXTURE_CUBE_MAP_SEAMLESS);
  s["pack_alignment"] = ints({geti(GL_PACK_ALIGNMENT)});
  s["unpack_alignment"] = ints({geti(GL_UNPACK_ALIGNMENT)});
  return s;
}

Keys differences(const State& a, const State& b) {
  Keys out;
  for (const auto& [k, v] : a) {
    if (b.at(k) != v) out.insert(k);
  }
  return out;
}

std::string describe(const Keys& keys, const State& before, const State& after) {
  std::string s;
  for (const std::string& k : keys) s += "  " + k + ": " + before.at(k) + " -> " + after.at(k) + "\n";
  return s.empty() ? "  (none)\n" : s;
}

// ---- the hostile host ----------------------------------------------------------------------------

// Objects of the host's own, bound everywhere Puff might bind and more, and every switch set to
// something Puff does not leave.
struct HostileHost {
  core::Program program;
  core::VertexArray vao = core::makeVertexArray();
  std::vector<core::Buffer> buffers;
  std::vector<core::Texture> textures;  // one per target in kTargets order (rect, cube array and buffer: none)
  GLuint sampler = 0;
  core::Framebuffer readFbo = core::makeFramebuffer();

  HostileHost() {
    // Any program that is not one of Puff's renderers' (the output view's, built anew).
    auto p = core::buildProgram({"media/fullscreen.vert", "output/view.frag"});
    EXPECT_OK(p);
    if (p) program = std::move(*p);
    for (int i = 0; i < 2 * kIndexed + 3; ++i) {
      buffers.push_back(core::makeBuffer());
      glNamedBufferStorage(buffers.back().get(), 1024, nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    const auto make = [&](GLenum target) {
      core::Texture t = core::makeTexture(target);
      switch (target) {
        case GL_TEXTURE_1D:
          glTextureStorage1D(t.get(), 1, GL_RGBA8, 4);
          break;
        case GL_TEXTURE_2D:
        case GL_TEXTURE_1D_ARRAY:
        case GL_TEXTURE_CUBE_MAP:
          glTextureStorage2D(t.get(), 1, GL_RGBA8, 4, 4);
          break;
        case GL_TEXTURE_3D:
        case GL_TEXTURE_2D_ARRAY:
          glTextureStorage3D(t.get(), 1, GL_RGBA8, 4, 4, 4);
          break;
        case GL_TEXTURE_2D_MULTISAMPLE:
          glTextureStorage2DMultisample(t.get(), 2, GL_RGBA8, 4, 4, GL_TRUE);
          break;
        default:
          break;
      }
      return t;
    };
    for (GLenum t : {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_1D_ARRAY, GL_TEXTURE_2D_ARRAY,
                     GL_TEXTURE_CUBE_MAP, GL_TEXTURE_2D_MULTISAMPLE}) {
      textures.push_back(make(t));
    }
    glCreateSamplers(1, &sampler);
    glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GL_MIRRORED_REPEAT);
  }
  ~HostileHost() { glDeleteSamplers(1, &sampler); }
  HostileHost(const HostileHost&) = delete;
  HostileHost& operator=(const HostileHost&) = delete;

  // The host's bindings of its objects: on every texture unit and indexed buffer binding looked at.
  void bindObjects() const {
    glUseProgram(program.get());
    glBindVertexArray(vao.get());
    for (GLuint i = 0; i < kIndexed; ++i) {
      // Ranges on odd indices, whole buffers on even ones.
      if (i % 2) {
        glBindBufferRange(GL_UNIFORM_BUFFER, i, buffers[i].get(), 256, 512);
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, i, buffers[kIndexed + i].get(), 256, 512);
      } else {
        glBindBufferBase(GL_UNIFORM_BUFFER, i, buffers[i].get());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, i, buffers[kIndexed + i].get());
      }
    }
    glBindBuffer(GL_UNIFORM_BUFFER, buffers[2 * kIndexed].get());
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[2 * kIndexed + 1].get());
    glBindBuffer(GL_ARRAY_BUFFER, buffers[2 * kIndexed + 2].get());
    for (int u = 0; u < kUnits; ++u) {
      glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(u));
      for (const core::Texture& t : textures) {
        GLint target = 0;
        glGetTextureParameteriv(t.get(), GL_TEXTURE_TARGET, &target);
        glBindTexture(static_cast<GLenum>(target), t.get());
      }
      glBindSampler(static_cast<GLuint>(u), sampler);
    }
    glActiveTexture(GL_TEXTURE5);
  }

  // `drawFbo` and `size`: the framebuffer Puff draws into (the host's) and its size.
  void apply(GLuint drawFbo, int size) const {
    bindObjects();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, drawFbo);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo.get());
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_CONSTANT_COLOR, GL_ONE_MINUS_DST_ALPHA, GL_SRC_COLOR, GL_DST_ALPHA);
    glBlendEquationSeparate(GL_MAX, GL_FUNC_REVERSE_SUBTRACT);
    glBlendColor(0.1f, 0.2f, 0.3f, 0.4f);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    glDepthRange(0.2, 0.8);
    glEnable(GL_DEPTH_CLAMP);
    glEnable(GL_STENCIL_TEST);
    glStencilFuncSeparate(GL_FRONT, GL_LEQUAL, 3, 0x0F);
    glStencilFuncSeparate(GL_BACK, GL_GEQUAL, 5, 0xF0);
    glStencilOpSeparate(GL_FRONT, GL_INCR, GL_INVERT, GL_DECR);
    glStencilOpSeparate(GL_BACK, GL_REPLACE, GL_ZERO, GL_DECR_WRAP);
    glStencilMaskSeparate(GL_FRONT, 0x3C);
    glStencilMaskSeparate(GL_BACK, 0xC3);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT);
    glFrontFace(GL_CW);
    glEnable(GL_FRAMEBUFFER_SRGB);
    glEnable(GL_SCISSOR_TEST);
    glScissor(3, 5, size / 2, size / 3);
    glViewport(2, 3, size - 7, size - 11);
    glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glEnable(GL_POLYGON_OFFSET_LINE);
    glEnable(GL_POLYGON_OFFSET_POINT);
    glPolygonOffset(1.5f, 2.5f);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    glEnable(GL_SAMPLE_ALPHA_TO_ONE);
    glEnable(GL_SAMPLE_COVERAGE);
    glEnable(GL_SAMPLE_SHADING);
    glEnable(GL_SAMPLE_MASK);
    glDisable(GL_MULTISAMPLE);
    glEnable(GL_RASTERIZER_DISCARD);
    glEnable(GL_PRIMITIVE_RESTART);
    glEnable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
    glDisable(GL_DITHER);
    glEnable(GL_COLOR_LOGIC_OP);
    glLogicOp(GL_XOR);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 8);
  }
};

// ---- what the headers say each call leaves (nailboards.h's and layers.h's terms) -----------------

Keys operator+(Keys a, const Keys& b) {
  a.insert(b.begin(), b.end());
  return a;
}
std::string unit(unsigned u, const char* target) { return "tex[" + std::to_string(u) + "]." + target; }
std::string sampler(unsigned u) { return "sampler[" + std::to_string(u) + "]"; }
std::string ubo(unsigned i) { return "ubo[" + std::to_string(i) + "]"; }
std::string ssbo(unsigned i) { return "ssbo[" + std::to_string(i) + "]"; }
Keys texture(unsigned u, const char* target) { return {unit(u, target), sampler(u)}; }
// Every target of unit u that the hostile host binds (glBindTextureUnit(u, 0) clears them all).
Keys wholeUnit(unsigned u) {
  Keys k;
  for (const char* t : {"1D", "2D", "3D", "1DArray", "2DArray", "Cube", "2DMS"}) k.insert(unit(u, t));
  return k;
}

// "the pass state" (resetPassState)
const Keys kPassState = {"blend[0]",
                         "blend[1]",
                         "cull",
                         "scissor",
                         "depth.clamp",
                         "polygon_offset.fill",
                         "alpha_to_coverage",
                         "rasterizer_discard",
                         "primitive_restart",
                         "primitive_restart_fixed",
                         "polygon_mode",
                         "depth.range",
                         "depth.test"};
// "write masks on"
const Keys kWriteMasks = {"depth.mask", "colormask[0]", "colormask[1]", "stencil.front.writemask",
                          "stencil.back.writemask"};
const Keys kNoProgram = {"program", "vao"};
Keys atlas(const cel::Bindings& b) {
  return texture(b.atlasPacked, "2D") + texture(b.atlasColor, "2D") + texture(b.atlasBack, "2D") +
         texture(b.shadowProfile, "2D") + Keys{ssbo(b.particles), ssbo(b.cells)};
}
// A draw framebuffer without a stencil buffer bound: the stored stencil reference is untouched, but
// GL_STENCIL_REF reads back clamped to its 0 stencil bits (the host's 3 and 5 read as 0).
const Keys kStencilRefReads = {"stencil.front.ref", "stencil.back.ref"};
// Layers' "full-screen state" (GL_FRAMEBUFFER_SRGB, on in the hostile host, is left alone everywhere)
const Keys kFullscreen = {"depth.test",  "stencil.test", "blend[0]",           "blend[1]",
                          "cull",        "scissor",      "rasterizer_discard", "alpha_to_coverage",
                          "sample_mask", "polygon_mode", "colormask[0]",       "colormask[1]"};

// ---- the fixture ---------------------------------------------------------------------------------

constexpr int kPx = 64;

std::shared_ptr<cel::TriangleMesh> groundMesh() {
  auto m = std::make_shared<cel::TriangleMesh>();
  m->positions = {{-4, 0, -4}, {4, 0, -4}, {4, 0, 4}, {-4, 0, 4}};
  m->normals.assign(4, glm::vec3(0, 1, 0));
  m->indices = {0, 2, 1, 0, 3, 2};
  return m;
}

cel::Frame eyeFrame() {
  cel::Camera cam;
  cam.position = glm::vec3(0.0f, 4.0f, 8.0f);
  cam.target = glm::vec3(0.0f, 0.5f, 0.0f);
  cam.nearPlane = 1.0f;
  cam.farPlane = 30.0f;
  cel::Frame f = cel::Frame::fromCamera(cam, kPx, kPx);
  f.light.direction = glm::vec3(0.3f, 1.0f, 0.2f);
  f.ambientColor = glm::vec3(0.3f);
  return f;
}

std::vector<cel::Particle> puffs() {
  std::vector<cel::Particle> ps;
  for (int i = 0; i < 3; ++i) {
    cel::Particle p;
    p.position = glm::vec3(-1.2f + 1.2f * i, 1.2f + 0.3f * i, 0.2f * i);
    p.size = 1.4f;
    ps.push_back(p);
  }
  return ps;
}

// Everything the cel calls need, made with one set of bindings.
struct CelKit {
  cel::Bindings b;
  std::unique_ptr<cel::NailboardRenderer> nailboards;
  std::unique_ptr<cel::OpaqueRenderer> opaque;
  std::unique_ptr<cel::FrameBlock> block;
  std::unique_ptr<cel::ShadowMap> shadowMap;
  std::unique_ptr<cel::Ramp> ramp;
  std::unique_ptr<cel::Gradient> gradient;

  explicit CelKit(const core::Atlas& atlas, const cel::Bindings& bindings = {}) : b(bindings) {
    auto nb = cel::NailboardRenderer::create(b);
    EXPECT_OK(nb);
    nailboards = std::move(*nb);
    EXPECT_OK(nailboards->setAtlas(atlas));
    auto op = cel::OpaqueRenderer::create(b);
    EXPECT_OK(op);
    opaque = std::move(*op);
    cel::OpaqueObject ground;
    ground.name = "ground";
    ground.mesh = groundMesh();
    cel::OpaqueObject box = ground;
    box.name = "wall";
    box.transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.6f, -1.5f)) *
                    glm::rotate(glm::mat4(1.0f), 1.3f, glm::vec3(1, 0, 0)) *
                    glm::scale(glm::mat4(1.0f), glm::vec3(0.25f));
    box.albedo = glm::vec3(0.4f, 0.6f, 0.9f);
    EXPECT_OK(opaque->setObjects({ground, box}));
    block = std::make_unique<cel::FrameBlock>(b);
    shadowMap = std::make_unique<cel::ShadowMap>(b);
    ramp = std::make_unique<cel::Ramp>(cel::Ramp::twoTone());
    core::Image g(2, 2, 3);
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x)
        for (int c = 0; c < 3; ++c) g.at(x, y, c) = 0.2f + 0.3f * static_cast<float>(y) + 0.1f * static_cast<float>(c);
    auto gr = cel::Gradient::create(g, "test gradient");
    EXPECT_OK(gr);
    gradient = std::make_unique<cel::Gradient>(std::move(*gr));
    nailboards->upload(puffs());
  }
};

GLuint framebufferOf(const test::OffscreenTarget& target) {
  target.bind();
  return static_cast<GLuint>(geti(GL_DRAW_FRAMEBUFFER_BINDING));
}

class HostState : public test::SphereAtlasTest {
 protected:
  static void SetUpTestSuite() { setUpSphereAtlas(true); }
  // The context is shared with the suites that run next: the hostile state must not outlive the
  // test. The guard itself puts it back (on every draw buffer and every unit the tests touch).
  void SetUp() override {
    SphereAtlasTest::SetUp();
    suiteGuard_ = std::make_unique<core::HostStateGuard>(core::GuardExtent{28, kIndexed, kIndexed, 8});
  }
  void TearDown() override {
    suiteGuard_.reset();
    // The host's objects are gone: nothing of theirs may stay bound in the shared context (llvmpipe
    // crashes in OSMesaMakeCurrent at exit when a deleted framebuffer stays the draw target).
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glUseProgram(0);
    glBindVertexArray(0);
    for (GLuint unit = 0; unit < 28; ++unit) glBindSampler(unit, 0);
    glFinish();
    SphereAtlasTest::TearDown();
  }
  std::unique_ptr<core::HostStateGuard> suiteGuard_;

  struct Case {
    std::string name;
    std::function<void()> call;
    Keys leaves;                           // the header's list, as keys
    std::function<void()> host = nullptr;  // changes to the hostile state, so every listed item differs
    core::GuardExtent extent{};
  };

  // Runs `c` on the hostile host twice: without the guard (the differences must be exactly
  // c.leaves) and inside a HostStateGuard (no difference at all).
  void check(const Case& c, const test::OffscreenTarget& target, const HostileHost& host) {
    SCOPED_TRACE(c.name);
    host.apply(framebufferOf(target), target.size());
    if (c.host) c.host();
    const State before = snapshot();
    c.call();
    const State after = snapshot();
    const Keys changed = differences(before, after);
    Keys unexpected, missing;
    std::set_difference(changed.begin(), changed.end(), c.leaves.begin(), c.leaves.end(),
                        std::inserter(unexpected, unexpected.end()));
    std::set_difference(c.leaves.begin(), c.leaves.end(), changed.begin(), changed.end(),
                        std::inserter(missing, missing.end()));
    EXPECT_TRUE(unexpected.empty()) << c.name << " changed what its header does not list:\n"
                                    << describe(unexpected, before, after);
    EXPECT_TRUE(missing.empty()) << c.name << " left unchanged what its header lists:\n"
                                 << describe(missing, before, before);

    host.apply(framebufferOf(target), target.size());
    if (c.host) c.host();
    const State guardedBefore = snapshot();
    EXPECT_EQ(guardedBefore, before);  // the hostile state is reproducible
    {
      core::HostStateGuard guard(c.extent);
      c.call();
    }
    const State guardedAfter = snapshot();
    const Keys left = differences(guardedBefore, guardedAfter);
    EXPECT_TRUE(left.empty()) << c.name << " inside a HostStateGuard still changed:\n"
                              << describe(left, guardedBefore, guardedAfter);
    EXPECT_EQ(core::drainGlErrors(), "") << c.name;
  }
};

TEST_F(HostState, CelCallsLeaveWhatTheirHeadersList) {
  test::OffscreenTarget target(kPx);
  ASSERT_TRUE(target.complete());
  HostileHost host;
  CelKit kit(*atlas_);
  const cel::Bindings& b = kit.b;
  const cel::Frame frame = eyeFrame();
  cel::Style style;
  style.outlines = true;
  cel::Bounds receivers = cel::particleBounds(puffs());
  for (std::size_t i = 0; i < kit.opaque->count(); ++i) receivers.add(kit.opaque->worldBounds(i));
  const cel::VolumeClip clip = cel::volumeClip(frame, receivers);
  ASSERT_FALSE(clip.everything);
  ASSERT_FALSE(clip.nothing);
  kit.shadowMap->prepare(frame, receivers, style);
  core::drainGlErrors();

  // The cel passes leave the depth test on and the stencil test off: the host's are the opposite.
  const auto celHost = [] {
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_STENCIL_TEST);
  };
  // The shadowed pass leaves the stencil test on: here the host's is off.
  const auto shadowedHost = [] {
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_STENCIL_TEST);
  };
  const Keys lit = kPassState + kWriteMasks + kNoProgram + Keys{"depth.func", "stencil.test"};
  const Keys stencilFunc = {"stencil.front.func", "stencil.back.func", "stencil.front.ref",
                            "stencil.back.ref",   "stencil.front.op",  "stencil.back.op"};
  const Keys shadowed = kPassState + kWriteMasks + kNoProgram + stencilFunc + Keys{"depth.func", "stencil.test"};
  const Keys volumes =
      kPassState + kWriteMasks + kNoProgram + stencilFunc + Keys{"depth.func", "stencil.test", "scissor.box"};

  const std::vector<Case> cases = {
      {"FrameBlock::upload", [&] { kit.block->upload(frame); }, {ubo(b.frameBlock)}},
      {"FrameBlock::bind", [&] { kit.block->bind(); }, {ubo(b.frameBlock)}},
      {"Ramp::bind", [&] { kit.ramp->bind(b); }, texture(b.ramp, "1D")},
      {"Gradient::bind", [&] { kit.gradient->bind(b); }, texture(b.gradient, "2D")},
      {"NailboardRenderer::upload", [&] { kit.nailboards->upload(puffs()); }, {}},
      {"NailboardRenderer::drawNailboards(kLit)", [&] { kit.nailboards->drawNailboards(style, cel::ShadePass::kLit); },
       lit + atlas(b), celHost},
      {"NailboardRenderer::drawNailboards(kLit, no outlines)",
       [&] {
         cel::Style s = style;
         s.outlines = false;
         kit.nailboards->drawNailboards(s, cel::ShadePass::kLit);
       },
       lit + atlas(b), celHost},
      {"NailboardRenderer::drawNailboards(kShadowed)",
       [&] { kit.nailboards->drawNailboards(style, cel::ShadePass::kShadowed); }, shadowed + atlas(b), shadowedHost},
      {"NailboardRenderer::drawNailboards(kDepthOnly)",
       [&] { kit.nailboards->drawNailboards(style, cel::ShadePass::kDepthOnly); }, lit + atlas(b), celHost},
      {"NailboardRenderer::drawBaseline", [&] { kit.nailboards->drawBaseline(style); }, lit + atlas(b), celHost},
      {"NailboardRenderer::drawShadowVolumes",
       [&] { kit.nailboards->drawShadowVolumes(style, glm::vec4(0, 1, 0, 0), clip); }, volumes + atlas(b), celHost},
      {"NailboardRenderer::drawShadowCasters", [&] { kit.nailboards->drawShadowCasters(style, frame); }, lit + atlas(b),
       celHost},
      {"OpaqueRenderer::draw(kLit)", [&] { kit.opaque->draw(cel::ShadePass::kLit); }, lit + Keys{"front_face"},
       celHost},
      {"OpaqueRenderer::draw(kShadowed)", [&] { kit.opaque->draw(cel::ShadePass::kShadowed); },
       shadowed + Keys{"front_face"}, shadowedHost},
      {"OpaqueRenderer::draw(kDepthOnly)", [&] { kit.opaque->draw(cel::ShadePass::kDepthOnly); },
       lit + Keys{"front_face"}, celHost},
      {"OpaqueRenderer::drawShadowVolumes", [&] { kit.opaque->drawShadowVolumes(style, glm::vec4(0.0f), clip); },
       volumes + Keys{"front_face"}, celHost},
      {"OpaqueRenderer::drawCasters", [&] { kit.opaque->drawCasters(); }, lit, celHost},
      {"ShadowMap::prepare", [&] { kit.shadowMap->prepare(frame, receivers, style); }, {}},
      {"ShadowMap::beginCasters", [&] { kit.shadowMap->beginCasters(); },
       Keys{"fbo.draw", "viewport", "scissor", "rasterizer_discard", "depth.mask", "colormask[0]", "colormask[1]",
            ubo(b.frameBlock)} +
           wholeUnit(b.shadowMapDepth) + wholeUnit(b.shadowMapIds) + kStencilRefReads},
      {"ShadowMap::bind", [&] { kit.shadowMap->bind(); },
       texture(b.shadowMapDepth, "2D") + texture(b.shadowMapIds, "2D")},
  };
  for (const Case& c : cases) check(c, target, host);
}

TEST_F(HostState, MediaCallsLeaveWhatTheirHeadersList) {
  test::OffscreenTarget target(kPx);
  HostileHost host;
  auto renderer = media::Renderer::create();
  ASSERT_OK(renderer);
  auto layers = media::Layers::create(kPx, kPx, 1, 0.5f);
  ASSERT_OK(layers);
  media::Layers& ly = **layers;
  ly.setHistorySlots(2);
  const media::Bindings b;
  media::Frame f;
  f.view = glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0), glm::vec3(0, 1, 0));
  f.projection = glm::perspective(glm::radians(45.0f), 1.0f, 0.5f, 50.0f);
  f.nearPlane = 0.5f;
  f.farPlane = 50.0f;
  f.width = kPx;
  f.height = kPx;
  std::vector<media::Particle> ps(3);
  for (int i = 0; i < 3; ++i) {
    ps[static_cast<std::size_t>(i)].position = glm::vec3(-1.0f + i, 0.0f, -0.5f * i);
    ps[static_cast<std::size_t>(i)].material = static_cast<std::uint32_t>(i);
  }
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture outColor = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(outColor.get(), 1, GL_RGBA16F, kPx, kPx);
  glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, outColor.get(), 0);
  const int vp[4] = {0, 0, kPx, kPx};
  const std::vector<media::ExplosionLight> lights(1);
  const std::vector<int> slots = {0, 1};
  const std::vector<float> weights = {0.5f, 0.5f};

  // The media draw leaves the depth and stencil tests off: the host's are on (the default hostile state).
  const Keys draw = kNoProgram + Keys{"blend[0]",     "blend[1]",        "blend_func[0]",      "blend_func[1]",
                                      "blend_eq[0]",  "blend_eq[1]",     "depth.test",         "stencil.test",
                                      "cull",         "scissor",         "alpha_to_coverage",  "rasterizer_discard",
                                      "depth.clamp",  "polygon_mode",    "depth.mask",         "colormask[0]",
                                      "colormask[1]", ubo(b.mediaBlock), ubo(b.materialBlock), ssbo(b.particles)} +
                    texture(b.depth, "2D") + texture(b.blackbody, "1D") + texture(b.phase, "2D") +
                    texture(b.temperatureDetail, "3D") + texture(b.opacityDetail, "3D") + texture(b.falloff, "2D");
  const auto drawCase = [&](media::Method m) {
    return Case{"Renderer::draw(" + std::string(media::toString(m)) + ")",
                [&, m] { (*renderer)->draw(ly.layerFrame(f), ps, m, ly.mediaDepth(), true); }, draw};
  };
  const std::vector<Case> cases = {
      drawCase(media::Method::kPlanar),
      drawCase(media::Method::kSpherical),
      drawCase(media::Method::kPlanarTextured),
      {"Layers::resolveOpaque", [&] { ly.resolveOpaque(); },
       kFullscreen + kNoProgram +
           Keys{unit(b.resolveSource, "2DMS"), unit(b.resolveSource, "2D"), sampler(b.resolveSource)}},
      {"Layers::beginMedia", [&] { ly.beginMedia(); },
       Keys{"fbo.draw", "viewport", "scissor", "rasterizer_discard", "colormask[0]", "colormask[1]"} +
           kStencilRefReads},
      {"Layers::compose", [&] { ly.compose(out.get(), vp, f, lights, media::ComposeSettings{}); },
       Keys{"fbo.draw", "viewport", ubo(b.composeBlock)} + kStencilRefReads + kFullscreen + kNoProgram +
           texture(b.opaqueColor, "2D") + texture(b.opaqueDepth, "2D") + texture(b.mediaLayer, "2D") +
           texture(b.mediaDepth, "2D") + texture(b.shimmer, "2D")},
      {"Layers::blendHistory", [&] { ly.blendHistory(out.get(), vp, slots, weights); },
       Keys{"fbo.draw", "viewport"} + kStencilRefReads + kFullscreen + kNoProgram + texture(b.historyFirst, "2D") +
           texture(b.historyFirst + 1, "2D")},
  };
  for (const Case& c : cases) check(c, target, host);

  // Media in the host's frame (createForHost): its depth texture read, the layer blended onto its
  // colour.
  auto hostLayers = media::Layers::createForHost(kPx, kPx, 0.5f);
  ASSERT_OK(hostLayers);
  media::Layers& hl = **hostLayers;
  core::Texture hostDepth = core::makeTexture(GL_TEXTURE_2D),
                hostDepthMs = core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE);
  glTextureStorage2D(hostDepth.get(), 1, GL_DEPTH24_STENCIL8, kPx, kPx);
  glTextureStorage2DMultisample(hostDepthMs.get(), 4, GL_DEPTH24_STENCIL8, kPx, kPx, GL_TRUE);
  media::HostDepth single, multi;
  single.texture = hostDepth.get();
  single.space = {core::DepthConvention::kStandard, core::ClipDepth::kNegativeOneToOne, f.projection, f.nearPlane,
                  f.farPlane};
  multi = single;
  multi.texture = hostDepthMs.get();
  const std::vector<Case> hostCases = {
      {"Layers::resolveHostDepth(2D)", [&] { EXPECT_OK(hl.resolveHostDepth(single)); },
       kFullscreen + kNoProgram + Keys{unit(b.resolveSource, "2D"), sampler(b.resolveSource)}},
      {"Layers::resolveHostDepth(2D multisample)", [&] { EXPECT_OK(hl.resolveHostDepth(multi)); },
       kFullscreen + kNoProgram +
           Keys{unit(b.resolveSource, "2DMS"), unit(b.resolveSource, "2D"), sampler(b.resolveSource)}},
      {"Layers::composeOver", [&] { EXPECT_OK(hl.composeOver(out.get(), vp, f, lights, media::ComposeSettings{})); },
       Keys{"fbo.draw", "viewport", ubo(b.composeBlock), "blend_func[0]", "blend_eq[0]"} + kStencilRefReads +
           kFullscreen + kNoProgram + texture(b.opaqueDepth, "2D") + texture(b.mediaLayer, "2D") +
           texture(b.mediaDepth, "2D") + texture(b.shimmer, "2D")},
  };
  for (const Case& c : hostCases) check(c, target, host);
}

// ---- chosen binding points -----------------------------------------------------------------------

cel::Bindings chosenCel() {
  cel::Bindings b;
  b.frameBlock = 7;
  b.particles = 5;
  b.cells = 3;
  b.ramp = 9;
  b.gradient = 12;
  b.atlasPacked = 10;
  b.atlasColor = 11;
  b.atlasBack = 8;
  b.shadowProfile = 13;
  b.shadowMapDepth = 14;
  b.shadowMapIds = 15;
  return b;
}

media::Bindings chosenMedia() {
  media::Bindings b;
  b.mediaBlock = 9;
  b.materialBlock = 10;
  b.particles = 6;
  b.depth = 8;
  b.blackbody = 9;
  b.phase = 10;
  b.temperatureDetail = 11;
  b.opacityDetail = 12;
  b.falloff = 13;
  b.composeBlock = 11;
  b.opaqueColor = 14;
  b.opaqueDepth = 15;
  b.mediaLayer = 16;
  b.mediaDepth = 17;
  b.shimmer = 18;
  b.resolveSource = 19;
  b.historyFirst = 20;  // 20-27: beyond kUnits, which is fine: nothing is compared there
  return b;
}

// A whole cel frame: opaque objects and nailboards lit, shadows by the map and by volumes.
std::vector<glm::vec4> celFrame(CelKit& kit, const test::OffscreenTarget& target) {
  cel::Frame frame = eyeFrame();
  cel::Style style;
  style.shadows = true;
  const std::vector<cel::Particle> ps = puffs();
  cel::Bounds casters = cel::particleBounds(ps);
  for (std::size_t i = 0; i < kit.opaque->count(); ++i) casters.add(kit.opaque->worldBounds(i));
  kit.nailboards->upload(ps);
  // The map: casters from the light, then the eye's lit passes looking it up.
  kit.shadowMap->prepare(frame, casters, style);
  kit.shadowMap->beginCasters();
  kit.nailboards->drawShadowCasters(style, frame);
  kit.opaque->drawCasters();
  target.clear(glm::vec4(0.9f, 0.95f, 1.0f, 1.0f));
  frame.shadow = kit.shadowMap->lookup();
  frame.ambientGradient = true;
  kit.block->upload(frame);
  kit.ramp->bind(kit.b);
  kit.gradient->bind(kit.b);
  kit.shadowMap->bind();
  kit.opaque->draw(cel::ShadePass::kLit);
  kit.nailboards->drawNailboards(style, cel::ShadePass::kLit);
  // Volumes on top (stencil), and the shadowed pass.
  const cel::VolumeClip clip = cel::volumeClip(frame, casters);
  kit.nailboards->drawShadowVolumes(style, glm::vec4(0, 1, 0, 0), clip);
  kit.opaque->drawShadowVolumes(style, glm::vec4(0, 1, 0, 0), clip);
  kit.opaque->draw(cel::ShadePass::kShadowed);
  kit.nailboards->drawNailboards(style, cel::ShadePass::kShadowed);
  return target.readLinear();
}

// The host's objects on the default points (and every other one looked at) stay bound while Puff
// draws on its chosen ones: the keys of the defaults' points.
Keys defaultPoints() {
  Keys k;
  for (unsigned u = 0; u < 8; ++u) {
    for (const Target& t : kTargets) k.insert(unit(u, t.name));
    k.insert(sampler(u));
  }
  for (unsigned i = 0; i < 6; ++i) k.insert(ubo(i));
  for (unsigned i = 0; i < 2; ++i) k.insert(ssbo(i));
  return k;
}

TEST_F(HostState, ChosenCelBindingsDrawTheSameFrameAndLeaveTheDefaultsAlone) {
  test::OffscreenTarget target(kPx);
  HostileHost host;
  std::vector<glm::vec4> reference;
  {
    CelKit kit(*atlas_);
    reference = celFrame(kit, target);
  }
  CelKit kit(*atlas_, chosenCel());
  host.bindObjects();  // the host's own objects everywhere; the state switches stay as GL's defaults
  const State before = snapshot();
  const std::vector<glm::vec4> chosen = celFrame(kit, target);
  const State after = snapshot();
  ASSERT_EQ(chosen.size(), reference.size());
  int differing = 0, lit = 0;
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    if (chosen[i] != reference[i]) ++differing;
    if (reference[i] != reference[0]) ++lit;
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(lit, kPx * kPx / 10);  // the frame holds something: ground, wall, puffs, shadows
  const Keys touched = differences(before, after);
  for (const std::string& k : defaultPoints()) {
    EXPECT_EQ(touched.count(k), 0u) << k << ": " << before.at(k) << " -> " << after.at(k);
  }
  EXPECT_EQ(core::drainGlErrors(), "");
}

std::vector<glm::vec4> mediaFrame(const media::Bindings& b) {
  auto renderer = media::Renderer::create({}, b);
  EXPECT_OK(renderer);
  auto layers = media::Layers::create(kPx, kPx, 1, 0.5f, b);
  EXPECT_OK(layers);
  media::Layers& ly = **layers;
  media::Frame f;
  f.view = glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0), glm::vec3(0, 1, 0));
  f.projection = glm::perspective(glm::radians(45.0f), 1.0f, 0.5f, 50.0f);
  f.nearPlane = 0.5f;
  f.farPlane = 50.0f;
  f.width = kPx;
  f.height = kPx;
  // The opaque pass: grey, a wall at linear depth 0.1 over the left half, the background beyond.
  const GLuint opaque = ly.opaqueFramebuffer();
  const float grey[4] = {0.3f, 0.3f, 0.3f, 1.0f};
  glClearNamedFramebufferfv(opaque, GL_COLOR, 0, grey);
  glClearNamedFramebufferfi(opaque, GL_DEPTH_STENCIL, 0, 1.0f, 0);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, opaque);
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 0, kPx / 2, kPx);
  glClearNamedFramebufferfi(opaque, GL_DEPTH_STENCIL, 0, 0.1f, 0);
  glDisable(GL_SCISSOR_TEST);
  ly.resolveOpaque();
  std::vector<media::Particle> ps(4);
  for (int i = 0; i < 4; ++i) {
    media::Particle& p = ps[static_cast<std::size_t>(i)];
    p.position = glm::vec3(-1.2f + 0.8f * i, 0.2f * i, -0.4f * i);
    p.radius = 0.9f;
    p.material = static_cast<std::uint32_t>(i % 3);
    p.seed = static_cast<std::uint32_t>(i);
  }
  ly.beginMedia();
  (*renderer)->draw(ly.layerFrame(f), ps, media::Method::kSpherical, ly.mediaDepth(), true);
  media::ExplosionLight light;
  light.center = glm::vec3(0.0f, 0.0f, -1.0f);
  light.radius = 3.0f;
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, kPx, kPx);
  glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  const int vp[4] = {0, 0, kPx, kPx};
  media::ComposeSettings cs;
  cs.shimmerPixels = 2.0f;
  ly.compose(out.get(), vp, f, std::span(&light, 1), cs);
  std::vector<glm::vec4> px(static_cast<std::size_t>(kPx) * kPx);
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(glm::vec4)), px.data());
  // And the motion blur of two history slots composed the same way.
  ly.setHistorySlots(2);
  ly.compose(ly.historyFramebuffer(0), vp, f, {}, cs);
  ly.compose(ly.historyFramebuffer(1), vp, f, std::span(&light, 1), cs);
  const std::vector<int> slots = {0, 1};
  const std::vector<float> weights = {0.25f, 0.75f};
  ly.blendHistory(out.get(), vp, slots, weights);
  std::vector<glm::vec4> blurred(px.size());
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(blurred.size() * sizeof(glm::vec4)),
                    blurred.data());
  px.insert(px.end(), blurred.begin(), blurred.end());
  return px;
}

TEST_F(HostState, ChosenMediaBindingsDrawTheSameFrameAndLeaveTheDefaultsAlone) {
  HostileHost host;
  const std::vector<glm::vec4> reference = mediaFrame({});
  host.bindObjects();
  const State before = snapshot();
  const std::vector<glm::vec4> chosen = mediaFrame(chosenMedia());
  const State after = snapshot();
  ASSERT_EQ(chosen.size(), reference.size());
  int differing = 0, medium = 0;
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    if (chosen[i] != reference[i]) ++differing;
    if (glm::vec3(reference[i]) != glm::vec3(reference[0])) ++medium;
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(medium, kPx * kPx / 10);  // the particles show
  const Keys touched = differences(before, after);
  for (const std::string& k : defaultPoints()) {
    EXPECT_EQ(touched.count(k), 0u) << k << ": " << before.at(k) << " -> " << after.at(k);
  }
  EXPECT_EQ(core::drainGlErrors(), "");
}

TEST_F(HostState, BindingsAreValidated) {
  cel::Bindings same;
  same.gradient = same.ramp;
  auto r = cel::NailboardRenderer::create(same);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message,
            "cel::Bindings.gradient and cel::Bindings.ramp: both use texture unit 0; they must differ");
  auto o = cel::OpaqueRenderer::create(same);
  ASSERT_FALSE(o);
  EXPECT_EQ(o.error().message, r.error().message);

  cel::Bindings storage;
  storage.cells = storage.particles;
  auto s = cel::NailboardRenderer::create(storage);
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("cel::Bindings.cells and cel::Bindings.particles"), std::string::npos);

  GLint maxUnits = 0, maxUniform = 0;
  glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &maxUnits);
  glGetIntegerv(GL_MAX_UNIFORM_BUFFER_BINDINGS, &maxUniform);
  cel::Bindings far;
  far.atlasColor = static_cast<unsigned>(maxUnits);
  auto f = cel::NailboardRenderer::create(far);
  ASSERT_FALSE(f);
  EXPECT_EQ(f.error().message, "cel::Bindings.atlasColor: texture unit " + std::to_string(maxUnits) +
                                   " is beyond this GL's " + std::to_string(maxUnits) + " (0 to " +
                                   std::to_string(maxUnits - 1) + ")");
  cel::Bindings farBlock;
  farBlock.frameBlock = static_cast<unsigned>(maxUniform);
  EXPECT_FALSE(cel::validate(farBlock));
  farBlock.frameBlock = static_cast<unsigned>(maxUniform - 1);
  EXPECT_TRUE(cel::validate(farBlock));

  media::Bindings m;
  m.falloff = m.depth;
  auto mr = media::Renderer::create({}, m);
  ASSERT_FALSE(mr);
  EXPECT_EQ(mr.error().message,
            "media::Bindings.falloff and media::Bindings.depth: both use texture unit 0; they must differ");
  media::Bindings history;
  history.historyFirst = static_cast<unsigned>(maxUnits - 7);  // its 8 units reach one past the last
  auto ml = media::Layers::create(16, 16, 1, 0.5f, history);
  ASSERT_FALSE(ml);
  EXPECT_NE(ml.error().message.find("media::Bindings.historyFirst: texture unit " + std::to_string(maxUnits)),
            std::string::npos);
  // Points of different calls may share (the defaults do: unit 0 is read by draw and by compose).
  EXPECT_TRUE(media::validate(media::Bindings{}));
  EXPECT_TRUE(cel::validate(chosenCel()));
  EXPECT_TRUE(media::validate(chosenMedia()));
}

// The guard's extent follows the chosen points.
TEST_F(HostState, GuardExtentCoversChosenPoints) {
  const core::GuardExtent c = cel::guardExtent(chosenCel());
  EXPECT_EQ(c.textureUnits, 16);
  EXPECT_EQ(c.uniformBuffers, 8);
  EXPECT_EQ(c.storageBuffers, 6);
  const core::GuardExtent m = media::guardExtent(chosenMedia());
  EXPECT_EQ(m.textureUnits, 28);
  EXPECT_EQ(m.uniformBuffers, 12);
  EXPECT_EQ(m.storageBuffers, 7);
  const core::GuardExtent both = c.cover(m);
  EXPECT_EQ(both.textureUnits, 28);
  EXPECT_EQ(both.storageBuffers, 7);
  // The defaults' extent is the guard's default.
  const core::GuardExtent d = cel::guardExtent({}).cover(media::guardExtent({}));
  const core::GuardExtent g;
  EXPECT_EQ(d.textureUnits, g.textureUnits);
  EXPECT_EQ(d.uniformBuffers, g.uniformBuffers);
  EXPECT_EQ(d.storageBuffers, g.storageBuffers);
}

}  // namespace
}  // namespace puff
