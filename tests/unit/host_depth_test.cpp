// The host's depth convention (cel::DepthConvention). Puff computes depth in
// linear space and stores it in the host's convention (frame.glsl's storeDepth), so a host keeps
// its own depth buffer and shaders:
//  - the conversion, on the GPU, against closed forms and against the window depth the hardware
//    gives a host's own gl_Position at the same distance, for every convention;
//  - a host scene where a wall cuts a puff (nailboards lit, with outlines, shadow volumes and the
//    shadowed pass), drawn in every convention with the wall drawn by the HOST's own shader writing
//    ordinary gl_Position depth (and again with Puff's own opaque wall in that convention), matches
//    the linear path (Puff's own opaque wall) to IoU >= 0.99 over a sweep of camera distances and
//    wall positions, and the wall really hides part of the puff;
//  - Puff told linear in a host's standard buffer (the mistake the conventions exist for) draws the
//    puff over the wall.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/cel/opaque.h>
#include <puff/cel/volume_clip.h>
#include <puff/core/bind_points.h>
#include <puff/core/colour.h>
#include <puff/core/gl.h>
#include <puff/core/shader.h>
#include <puff/gl_api.h>

#include "support/assert_ok.h"
#include "support/host_gl.h"
#include "support/sphere_atlas.h"

namespace puff {
namespace {

using namespace test;  // support/host_gl.h: the conventions, HostTarget, program

class HostDepth : public test::SphereAtlasTest {
 protected:
  static void SetUpTestSuite() { setUpSphereAtlas(true); }
  void SetUp() override {
    GlTest::SetUp();
    if (HasFatalFailure()) return;
    block_ = std::make_unique<cel::FrameBlock>();
    vao_ = core::makeVertexArray();
  }
  void TearDown() override {
    EXPECT_EQ(core::drainGlErrors(), "");
    // The next suite finds the GL as GL starts: linear passes, depth LESS, nothing bound here.
    EXPECT_OK(block_->upload(cel::Frame{}));
    glDepthFunc(GL_LESS);
    glDisable(GL_STENCIL_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glBindVertexArray(0);
    glUseProgram(0);
    block_.reset();
    vao_ = {};
  }

  std::unique_ptr<cel::FrameBlock> block_;
  core::VertexArray vao_;
};

// ---- the conversion ----------------------------------------------------------------------------

TEST(HostDepthConvention, DepthFunctionAndClearFollowTheConvention) {
  EXPECT_EQ(cel::nearerDepthFunc(DepthConvention::kLinear), static_cast<GLenum>(GL_LESS));
  EXPECT_EQ(cel::nearerDepthFunc(DepthConvention::kStandard), static_cast<GLenum>(GL_LESS));
  EXPECT_EQ(cel::nearerDepthFunc(DepthConvention::kReversedZ), static_cast<GLenum>(GL_GREATER));
  EXPECT_EQ(cel::clearDepth(DepthConvention::kLinear), 1.0f);
  EXPECT_EQ(cel::clearDepth(DepthConvention::kStandard), 1.0f);
  EXPECT_EQ(cel::clearDepth(DepthConvention::kReversedZ), 0.0f);
}

// storedDepth (the CPU twin of frame.glsl's storeDepth) against the closed forms, and the volume
// clip's depth bounds in stored depth (min and max swap for reversed-z).
TEST(HostDepthConvention, StoredDepthMatchesClosedForms) {
  const glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 0), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
  for (const Convention& c :
       {kLinear, kStandardNO, kStandardZO, kReversed, kReversedInfinite, kOrthoStandard, kOrthoReversed}) {
    const cel::Frame f = frameFor(c, view, 64);
    for (const double d : {0.1, 0.15, 0.5, 1.0, 3.0, 10.0, 40.0, 90.0, 100.0}) {
      const float linear = static_cast<float>((d - kNear) / (kFar - kNear));
      const double want = closedForm(c, d);
      EXPECT_NEAR(cel::storedDepth(f, linear), want, 2e-6 * std::max(want, 0.01)) << c.name << " at distance " << d;
    }
    // Nearer than the near plane: linear depth goes as it is (the depth buffer clamps it to 0); the
    // others store the near plane's depth.
    EXPECT_NEAR(cel::storedDepth(f, -0.5f), c.depth == DepthConvention::kLinear ? -0.5 : closedForm(c, kNear), 1e-6)
        << c.name;
    // A box from 2 to 5 units in front of the camera.
    cel::Bounds box;
    box.add(glm::vec3(-0.1f, -0.1f, -5.0f));
    box.add(glm::vec3(0.1f, 0.1f, -2.0f));
    const cel::VolumeClip clip = cel::volumeClip(f, box);
    ASSERT_FALSE(clip.everything) << c.name;
    const double a = closedForm(c, 2.0), b = closedForm(c, 5.0);
    EXPECT_NEAR(clip.depthMin, std::min(a, b), 2e-6) << c.name;
    EXPECT_NEAR(clip.depthMax, std::max(a, b), 2e-6) << c.name;
  }
  // With an infinite far plane, linear depth past Frame::farPlane still converts (nothing clips it).
  const cel::Frame f = frameFor(kReversedInfinite, view, 64);
  EXPECT_NEAR(cel::storedDepth(f, 3.0f), kNear / (kNear + 3.0 * (kFar - kNear)), 1e-9);
}

// On the GPU: a fragment writing storeDepth(linearDepth(d)) lands at the closed form's window depth,
// and at the depth the hardware gives the host's own gl_Position of a point at distance d (drawn
// with the convention's glClipControl), within 1e-6 relative (of max(depth, 0.01): reversed-z with a
// finite far plane computes n (f - d) / ((f - n) d) as a difference of nearly equal terms near the
// far plane, in the hardware's path as in Puff's).
// Planes linear depth cannot divide by are one line naming them, not a crash, and change nothing:
// the block keeps the frame and convention it had, bound where it was.
TEST_F(HostDepth, AFrameBlockRefusesPlanesItCannotDivideBy) {
  cel::Frame good;
  good.depth = cel::DepthConvention::kReversedZ;
  ASSERT_OK(block_->upload(good));
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const glm::vec2 bad[] = {{1.0f, 1.0f}, {5.0f, 1.0f}, {0.1f, inf}, {nan, 10.0f}, {-inf, 10.0f}};
  for (const glm::vec2 planes : bad) {
    cel::Frame f;
    f.nearPlane = planes.x;
    f.farPlane = planes.y;
    f.depth = cel::DepthConvention::kLinear;
    glBindBufferBase(GL_UNIFORM_BUFFER, cel::Bindings{}.frameBlock, 0);
    auto r = block_->upload(f);
    ASSERT_FALSE(r.ok()) << planes.x << ", " << planes.y;
    EXPECT_NE(r.error().message.find("FrameBlock::upload: the frame's planes"), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << "one line";
    EXPECT_EQ(cel::boundDepthConvention(), cel::DepthConvention::kReversedZ) << "the convention of the last good frame";
    GLint bound = -1;
    glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, cel::Bindings{}.frameBlock, &bound);
    EXPECT_EQ(bound, 0) << "nothing bound";
  }
  EXPECT_EQ(core::drainGlErrors(), "");
}

TEST_F(HostDepth, StoreDepthLandsAtTheProjectionsWindowDepth) {
  auto frameSource = core::preprocessShader("common/frame.glsl");
  ASSERT_OK(frameSource);
  const std::string fullscreen = R"(#version 450 core
layout(location = 0) uniform mat4 uP;
layout(location = 1) uniform float uDist;
layout(location = 2) uniform int uHost;
void main() {
  vec2 corner = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  // The host's own point at distance uDist: its clip z and w as the projection gives them.
  vec4 c = uHost != 0 ? uP * vec4(0.0, 0.0, -uDist, 1.0) : vec4(0.0, 0.0, 0.0, 1.0);
  gl_Position = vec4(corner * c.w, c.z, c.w);
}
)";
  const std::string puffFs = "#version 450 core\n" + *frameSource + R"(
layout(location = 1) uniform float uDist;
void main() { gl_FragDepth = storeDepth(linearDepth(uDist)); }
)";
  const std::string hostFs = "#version 450 core\nvoid main() {}\n";
  const core::Program puff = program(fullscreen, puffFs), host = program(fullscreen, hostFs);
  ASSERT_NE(puff.get(), 0u);
  // The frame's block where FrameBlock binds it (cel::Bindings), not at frame.glsl's layout value.
  core::assignBindPoints(puff.get(),
                         {{core::BindPoint::Kind::kUniformBlock, "FrameBlock", cel::Bindings{}.frameBlock}});
  HostTarget target(4, GL_DEPTH32F_STENCIL8);
  ASSERT_TRUE(target.complete());
  const glm::mat4 view(1.0f);
  double worstPuff = 0.0, worstHost = 0.0;
  for (const Convention& c :
       {kLinear, kStandardNO, kStandardZO, kReversed, kReversedInfinite, kOrthoStandard, kOrthoReversed}) {
    const ClipControlScope scope(c.clip);
    const cel::Frame f = frameFor(c, view, 4);
    EXPECT_OK(block_->upload(f));
    glBindVertexArray(vao_.get());
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDisable(GL_DEPTH_CLAMP);
    glDepthRange(0.0, 1.0);
    for (const double d : {0.15, 0.5, 1.0, 3.0, 10.0, 40.0, 90.0}) {
      const double want = closedForm(c, d);
      const double tol = 1e-6 * std::max(want, 0.01);
      for (const bool isHost : {false, true}) {
        // The linear convention has no host projection to draw with: the host writes linear depth.
        if (isHost && c.depth == DepthConvention::kLinear) continue;
        target.bindAndClear(glm::vec3(0.0f), 0.5f);
        const GLuint p = isHost ? host.get() : puff.get();
        glUseProgram(p);
        glProgramUniformMatrix4fv(p, 0, 1, GL_FALSE, glm::value_ptr(f.projection));
        glProgramUniform1f(p, 1, static_cast<float>(d));
        if (isHost) glProgramUniform1i(p, 2, 1);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        const float got = target.readDepth()[5];
        const double err = std::abs(got - want) / std::max(want, 0.01);
        (isHost ? worstHost : worstPuff) = std::max(isHost ? worstHost : worstPuff, err);
        EXPECT_NEAR(got, want, tol) << c.name << (isHost ? ", host's gl_Position" : ", storeDepth") << " at " << d;
      }
    }
  }
  std::printf("storeDepth vs closed form: worst %.3g relative; host gl_Position vs closed form: %.3g\n", worstPuff,
              worstHost);
  glUseProgram(0);
}

// ---- a host scene: a wall cuts a puff ----------------------------------------------------------

constexpr int kPx = 256;
constexpr glm::vec3 kBackground{0.01f, 0.06f, 0.8f};                                 // scene-linear blue
constexpr glm::vec3 kWallLit{0.45f, 0.0f, 0.0f}, kWallShadowed{0.033f, 0.0f, 0.0f};  // scene-linear

// What a pixel shows.
enum Class : unsigned char { kBg, kPuff, kWall, kWallInShadow };

Class classify(const glm::vec4& c) {
  if (c.g < 0.01f && c.b < 0.01f && c.r > 0.01f) return c.r > 0.2f ? kWall : kWallInShadow;
  if (std::abs(c.r - c.g) < 0.02f && std::abs(c.g - c.b) < 0.02f) return kPuff;  // grey body, black ink
  return kBg;
}

// The scene, scaled by s (the camera at 6 s): puff A (diameter 2 s) at the origin, cut by the wall
// z = s (c + k x / s); puff B (0.8 s) in front of the wall, up and left, its shadow on the wall.
struct Placement {
  float s, c, k;
};

class HostDepthScene : public HostDepth {
 protected:
  void SetUp() override {
    HostDepth::SetUp();
    if (HasFatalFailure()) return;
    auto n = cel::NailboardRenderer::create();
    ASSERT_OK(n);
    nailboards_ = std::move(*n);
    ASSERT_OK(nailboards_->setAtlas(*atlas_));
    auto o = cel::OpaqueRenderer::create();
    ASSERT_OK(o);
    opaque_ = std::move(*o);
    ramp_ = std::make_unique<cel::Ramp>(cel::Ramp::twoTone());
    // The host's wall: its own vertex buffer and program, gl_Position from its own uniform.
    wallProgram_ = program(R"(#version 450 core
layout(location = 0) in vec3 aPosition;
layout(location = 0) uniform mat4 uHostViewProj;
void main() { gl_Position = uHostViewProj * vec4(aPosition, 1.0); }
)",
                           R"(#version 450 core
layout(location = 1) uniform vec3 uColor;
out vec4 oColor;
void main() { oColor = vec4(uColor, 1.0); }
)");
    ASSERT_NE(wallProgram_.get(), 0u);
    wallBuffer_ = core::makeBuffer();
    glNamedBufferStorage(wallBuffer_.get(), 6 * sizeof(glm::vec3), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glVertexArrayVertexBuffer(vao_.get(), 0, wallBuffer_.get(), 0, sizeof(glm::vec3));
    glEnableVertexArrayAttrib(vao_.get(), 0);
    glVertexArrayAttribFormat(vao_.get(), 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao_.get(), 0, 0);
  }
  void TearDown() override {
    nailboards_.reset();
    opaque_.reset();
    ramp_.reset();
    wallProgram_ = {};
    wallBuffer_ = {};
    HostDepth::TearDown();
  }

  // The wall's corners: x over [-4 s, 4 s] and y over [-10 s, 10 s], off screen at every edge.
  static std::vector<glm::vec3> wallCorners(const Placement& p) {
    const auto at = [&](float x, float y) { return glm::vec3(x * p.s, y * p.s, p.s * (p.c + p.k * x)); };
    return {at(-4, -10), at(4, -10), at(4, 10), at(-4, 10)};
  }

  // Draws the frame in convention `c` and returns what each pixel shows. `wall`: draw the wall at all.
  // `puffDepth`: the convention Puff is told (c's own, but for the check that telling it wrong shows).
  // `puffWall`: the wall drawn by Puff's OpaqueRenderer (always so for linear) instead of the host.
  std::vector<Class> render(const Convention& c, const Placement& p, bool wall, bool puffWall = false) {
    return render(c, p, wall, c.depth, puffWall);
  }
  std::vector<Class> render(const Convention& c, const Placement& p, bool wall, DepthConvention puffDepth,
                            bool puffWall = false) {
    const float s = p.s;
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 6 * s), glm::vec3(0), glm::vec3(0, 1, 0));
    cel::Frame f = frameFor(c, view, kPx);
    f.depth = puffDepth;
    f.light.direction = glm::vec3(0.3f, 0.5f, 1.0f);
    f.light.color = puff::core::srgbToLinear(glm::vec3(0.5f));
    f.ambient = puff::core::srgbToLinear(glm::vec3(0.2f));
    cel::Style style;
    style.outlines = true;
    style.shading = true;
    style.shadows = true;
    style.shadowMethod = cel::ShadowMethod::kVolumes;
    style.shadowLength = 10.0f * s;
    std::vector<cel::Particle> puffs(2);
    puffs[0].position = glm::vec3(0.0f);
    puffs[0].size = 2.0f * s;
    puffs[1].position = glm::vec3(-0.9f, 0.9f, 2.4f) * s;
    puffs[1].size = 0.8f * s;

    const std::vector<glm::vec3> corners = wallCorners(p);
    const bool linear = c.depth == DepthConvention::kLinear || puffWall;
    if (linear && wall) {
      // The linear path: Puff's own opaque wall, writing linear depth (or, with puffWall, the
      // frame's convention).
      cel::TriangleMesh mesh;
      mesh.positions = corners;
      const glm::vec3 n = glm::normalize(glm::cross(corners[1] - corners[0], corners[2] - corners[0]));
      mesh.normals.assign(4, n);
      mesh.indices = {0, 1, 2, 0, 2, 3};
      cel::OpaqueObject o;
      o.name = "wall";
      o.mesh = std::make_shared<const cel::TriangleMesh>(std::move(mesh));
      o.albedo = glm::vec3(1.0f, 0.0f, 0.0f);
      EXPECT_OK(opaque_->setObjects({o}));
    } else {
      EXPECT_OK(opaque_->setObjects({}));
    }
    const std::vector<glm::vec3> tris = {corners[0], corners[1], corners[2], corners[0], corners[2], corners[3]};
    glNamedBufferSubData(wallBuffer_.get(), 0, static_cast<GLsizeiptr>(tris.size() * sizeof(glm::vec3)), tris.data());
    const glm::mat4 hostViewProj = f.projection * f.view;
    glProgramUniformMatrix4fv(wallProgram_.get(), 0, 1, GL_FALSE, glm::value_ptr(hostViewProj));
    // The host's wall pass: its own program and vertex array, its own depth state.
    const auto hostWall = [&](const glm::vec3& color, bool shadowed) {
      if (!wall || linear) return;
      glUseProgram(wallProgram_.get());
      glBindVertexArray(vao_.get());
      glProgramUniform3fv(wallProgram_.get(), 1, 1, glm::value_ptr(color));
      glEnable(GL_DEPTH_TEST);
      glDisable(GL_CULL_FACE);
      glDisable(GL_BLEND);
      if (shadowed) {
        glDepthFunc(GL_EQUAL);
        glDepthMask(GL_FALSE);
        glEnable(GL_STENCIL_TEST);
        glStencilFunc(GL_NOTEQUAL, 0, 0xFF);
        glStencilMask(0x00);
      } else {
        glDepthFunc(cel::nearerDepthFunc(c.depth));
        glDepthMask(GL_TRUE);
        glDisable(GL_STENCIL_TEST);
      }
      glDrawArrays(GL_TRIANGLES, 0, 6);
      glDisable(GL_STENCIL_TEST);
      glDepthMask(GL_TRUE);
      glStencilMask(0xFF);
      glBindVertexArray(0);
      glUseProgram(0);
    };

    HostTarget target(kPx, c.depth == DepthConvention::kReversedZ ? GL_DEPTH32F_STENCIL8 : GL_DEPTH24_STENCIL8);
    EXPECT_TRUE(target.complete());
    const ClipControlScope scope(c.clip);
    target.bindAndClear(kBackground, cel::clearDepth(c.depth));
    EXPECT_OK(block_->upload(f));
    ramp_->bind();
    hostWall(kWallLit, false);
    opaque_->draw(cel::ShadePass::kLit);
    nailboards_->upload(puffs);
    nailboards_->drawNailboards(style, cel::ShadePass::kLit);
    nailboards_->drawShadowVolumes(style);
    hostWall(kWallShadowed, true);
    opaque_->draw(cel::ShadePass::kShadowed);
    nailboards_->drawNailboards(style, cel::ShadePass::kShadowed);
    std::vector<Class> out;
    for (const glm::vec4& px : target.readLinear()) out.push_back(classify(px));
    return out;
  }

  std::unique_ptr<cel::NailboardRenderer> nailboards_;
  std::unique_ptr<cel::OpaqueRenderer> opaque_;
  std::unique_ptr<cel::Ramp> ramp_;
  core::Program wallProgram_;
  core::Buffer wallBuffer_;
};

// Intersection over union of the pixels `in` says belong, in a and b; 1 when neither has any.
double iou(const std::vector<Class>& a, const std::vector<Class>& b, bool (*in)(Class)) {
  std::size_t both = 0, either = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    both += in(a[i]) && in(b[i]);
    either += in(a[i]) || in(b[i]);
  }
  return either == 0 ? 1.0 : static_cast<double>(both) / static_cast<double>(either);
}

std::size_t count(const std::vector<Class>& a, bool (*in)(Class)) {
  return static_cast<std::size_t>(std::count_if(a.begin(), a.end(), in));
}

bool isPuff(Class c) { return c == kPuff; }
bool isWall(Class c) { return c == kWall || c == kWallInShadow; }
bool isShadowed(Class c) { return c == kWallInShadow; }

// Puff A's pixels: within 0.47 (ndc) of the image centre, where puff B never reaches.
std::size_t puffAPixels(const std::vector<Class>& a) {
  std::size_t n = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const float nx = 2.0f * (x + 0.5f) / kPx - 1.0f, ny = 2.0f * (y + 0.5f) / kPx - 1.0f;
      n += nx * nx + ny * ny < 0.47f * 0.47f && a[static_cast<std::size_t>(y) * kPx + x] == kPuff;
    }
  }
  return n;
}

TEST_F(HostDepthScene, EveryConventionMatchesTheLinearPath) {
  // Camera distances 6, 15 and 40 (the scene scaled with them, so the puffs keep their size on screen
  // while standard depth's resolution falls with the square of the distance), and walls through puff
  // A at two heights and two slopes.
  std::vector<Placement> sweep;
  for (const float s : {1.0f, 2.5f, 40.0f / 6.0f}) {
    for (const glm::vec2 ck : {glm::vec2(0.0f, 0.7f), glm::vec2(0.3f, -0.8f), glm::vec2(0.5f, 0.3f)}) {
      sweep.push_back({s, ck.x, ck.y});
    }
  }
  double worst = 1.0;
  for (const Placement& p : sweep) {
    const std::string where = "camera at " + std::to_string(6.0f * p.s) + ", wall z = s (" + std::to_string(p.c) +
                              " + " + std::to_string(p.k) + " x / s)";
    const std::vector<Class> uncut = render(kLinear, p, false);
    const std::vector<Class> reference = render(kLinear, p, true);
    // The wall really cuts puff A: part of it hidden, part of it in front.
    const double shown = static_cast<double>(puffAPixels(reference)) / static_cast<double>(puffAPixels(uncut));
    EXPECT_GT(shown, 0.05) << where;
    EXPECT_LT(shown, 0.95) << where;
    // Enough of each class that the IoU means something.
    EXPECT_GT(count(reference, isPuff), 2000u) << where;
    EXPECT_GT(count(reference, isWall), 10000u) << where;
    EXPECT_GT(count(reference, isShadowed), 200u) << where;
    for (const Convention& c : {kStandardNO, kStandardZO, kReversed, kReversedInfinite}) {
      // Puff's own opaque wall in the host's convention too (opaque.frag's storeDepth and the
      // shadowed pass's EQUAL on it), against the same reference.
      const std::vector<Class> own = render(c, p, true, true);
      EXPECT_GE(iou(reference, own, isPuff), 0.99) << c.name << ", Puff's wall, " << where;
      EXPECT_GE(iou(reference, own, isWall), 0.99) << c.name << ", Puff's wall, " << where;
      EXPECT_GE(iou(reference, own, isShadowed), 0.99) << c.name << ", Puff's wall, " << where;
      worst =
          std::min({worst, iou(reference, own, isPuff), iou(reference, own, isWall), iou(reference, own, isShadowed)});
      const std::vector<Class> got = render(c, p, true);
      const double puff = iou(reference, got, isPuff), wall = iou(reference, got, isWall),
                   shadow = iou(reference, got, isShadowed);
      EXPECT_GE(puff, 0.99) << c.name << ", " << where;
      EXPECT_GE(wall, 0.99) << c.name << ", " << where;
      EXPECT_GE(shadow, 0.99) << c.name << ", " << where;
      worst = std::min({worst, puff, wall, shadow});
      std::printf("%-20s s %.2f c %+.1f k %+.1f: shown %.3f IoU puff %.5f wall %.5f shadow %.5f\n", c.name, p.s, p.c,
                  p.k, shown, puff, wall, shadow);
    }
  }
  std::printf("worst IoU %.5f\n", worst);
}

// What the conventions exist for: Puff writing its linear depth into a host's
// standard depth buffer (told kLinear) draws the puff over the host's wall wherever they overlap.
TEST_F(HostDepthScene, LinearDepthInAStandardBufferDrawsPuffsOverTheWall) {
  const Placement p{1.0f, 0.3f, -0.8f};
  const std::vector<Class> reference = render(kLinear, p, true);
  const std::vector<Class> wrong = render(kStandardNO, p, true, DepthConvention::kLinear);
  const std::vector<Class> uncut = render(kLinear, p, false);
  const double puff = iou(reference, wrong, isPuff);
  // Every pixel of puff A shows, in front of the wall.
  EXPECT_EQ(puffAPixels(wrong), puffAPixels(uncut));
  EXPECT_LT(puff, 0.95);
  std::printf("told linear in a standard buffer: puff IoU %.4f, puff A shown %zu of %zu (linear path: %zu)\n", puff,
              puffAPixels(wrong), puffAPixels(uncut), puffAPixels(reference));
}

}  // namespace
}  // namespace puff
