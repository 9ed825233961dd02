// The host-state tests' fixture: a snapshot of the GL state, a hostile host, and the cel calls' kit.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/cel/bindings.h>
#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/cel/opaque.h>
#include <puff/cel/shadow_map.h>
#include <puff/cel/types.h>
#include <puff/core/atlas.h>
#include <puff/core/host_state.h>
#include <puff/core/image.h>
#include <puff/core/shader.h>
#include <puff/gl_api.h>

#include "support/assert_ok.h"
#include "support/gl_target.h"
#include "support/sphere_atlas.h"

namespace puff::host_state_test {

using Keys = std::set<std::string>;
using State = std::map<std::string, std::string>;

// ---- the snapshot: every piece of state core/host_state.h lists, and every piece any Puff call sets

// Texture units looked at: the guard's default extent, which holds every default point (and the
// chosen ones of host_state_bindings_test.cpp).
inline constexpr int kUnits = core::GuardExtent{}.textureUnits;
inline constexpr int kIndexed = 16;     // uniform and storage buffer bindings looked at
inline constexpr int kDrawBuffers = 2;  // per-draw-buffer blend state and colour masks

struct Target {
  GLenum target, binding;
  const char* name;
};
inline constexpr Target kTargets[] = {
    {GL_TEXTURE_1D, GL_TEXTURE_BINDING_1D, "1D"},
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

inline std::string ints(std::initializer_list<long long> v) {
  std::string s;
  for (long long x : v) s += (s.empty() ? "" : " ") + std::to_string(x);
  return s;
}
inline GLint geti(GLenum e) {
  GLint v = 0;
  glGetIntegerv(e, &v);
  return v;
}

inline State snapshot() {
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

inline Keys differences(const State& a, const State& b) {
  Keys out;
  for (const auto& [k, v] : a) {
    if (b.at(k) != v) out.insert(k);
  }
  return out;
}

inline std::string describe(const Keys& keys, const State& before, const State& after) {
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

// The snapshot's keys of a texture unit's target, its sampler, and an indexed buffer binding.
inline std::string unit(unsigned u, const char* target) { return "tex[" + std::to_string(u) + "]." + target; }
inline std::string sampler(unsigned u) { return "sampler[" + std::to_string(u) + "]"; }
inline std::string ubo(unsigned i) { return "ubo[" + std::to_string(i) + "]"; }
inline std::string ssbo(unsigned i) { return "ssbo[" + std::to_string(i) + "]"; }

// ---- the fixture ---------------------------------------------------------------------------------

inline constexpr int kPx = 64;

inline std::shared_ptr<cel::TriangleMesh> groundMesh() {
  auto m = std::make_shared<cel::TriangleMesh>();
  m->positions = {{-4, 0, -4}, {4, 0, -4}, {4, 0, 4}, {-4, 0, 4}};
  m->normals.assign(4, glm::vec3(0, 1, 0));
  m->indices = {0, 2, 1, 0, 3, 2};
  return m;
}

inline cel::Frame eyeFrame() {
  cel::Camera cam;
  cam.position = glm::vec3(0.0f, 4.0f, 8.0f);
  cam.target = glm::vec3(0.0f, 0.5f, 0.0f);
  cam.nearPlane = 1.0f;
  cam.farPlane = 30.0f;
  cel::Frame f = cel::Frame::fromCamera(cam, kPx, kPx);
  f.light.direction = glm::vec3(0.3f, 1.0f, 0.2f);
  f.ambient = puff::core::srgbToLinear(glm::vec3(0.3f));
  return f;
}

inline std::vector<cel::Particle> puffs() {
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
    box.albedo = puff::core::srgbToLinear(glm::vec3(0.4f, 0.6f, 0.9f));
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

inline GLuint framebufferOf(const test::OffscreenTarget& target) {
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

}  // namespace puff::host_state_test
