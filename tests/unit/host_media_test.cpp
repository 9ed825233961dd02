// Media in the host's frame (media::HostLayers). The host keeps its
// framebuffer, its colour and its depth in its own convention; Puff reads the depth texture and
// blends the media layer and the explosion light onto the host's colour:
//  - core::linearFromStored against closed forms, and as storedDepth's inverse, in every convention;
//  - resolveHostDepth on the GPU: a slanted floor and a wall drawn by the host's own shader with
//    ordinary gl_Position depth read back as linear depth matching ray-plane closed forms, for
//    every convention (standard in both clip ranges, reversed-z finite and infinite, orthographic),
//    and the nearest sample of a multisampled depth texture;
//  - composeOver against closed forms (a wall clipping a smoke sphere's chord, sky behind it) and
//    against Puff's own linear path (Layers::create, compose) over the same scene, with explosion
//    lights, at full and half resolution, in every convention;
//  - its errors: host_layers_errors_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include <puff/core/colour.h>
#include <puff/core/depth.h>
#include <puff/core/shader.h>
#include <puff/gl_api.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>

#include "support/assert_ok.h"
#include "support/host_gl.h"
#include "support/media_target.h"

namespace puff::host_media {
namespace {

using namespace test;  // support/host_gl.h: the conventions, projections, HostTarget, program

constexpr int kSize = 64;
constexpr float kOrthoHeight = 8.0f;
const std::vector<Convention> kAll = {kLinear,           kStandardNO,    kStandardZO,   kReversed,
                                      kReversedInfinite, kOrthoStandard, kOrthoReversed};

core::DepthSpace spaceFor(const Convention& c) { return {c.depth, c.clip, projection(c, kOrthoHeight), kNear, kFar}; }

double linearOf(double distance) { return (distance - kNear) / (kFar - kNear); }

// ---- the inverse conversion on the CPU ----------------------------------------------------------

TEST(HostMediaDepth, LinearFromStoredInvertsEveryConvention) {
  for (const Convention& c : kAll) {
    const core::DepthSpace s = spaceFor(c);
    for (const double d : {0.1, 0.15, 0.5, 1.0, 3.0, 10.0, 40.0, 90.0, 100.0}) {
      // The closed-form window depth reads back as the distance's linear depth: float arithmetic
      // on hyperbolic depth loses ~d / near ulps, so the tolerance is relative to d^2 / near.
      const double tol = 4e-7 * std::max(1.0, d * d / kNear / 100.0);
      EXPECT_NEAR(core::linearFromStored(s, static_cast<float>(closedForm(c, d))), linearOf(d), tol)
          << c.name << " at distance " << d;
      const float lin = static_cast<float>(linearOf(d));
      EXPECT_NEAR(core::linearFromStored(s, core::storedDepth(s, lin)), lin, tol) << c.name << " at " << d;
    }
    // The cleared buffer (nothing drawn) reads as linear 1, "no surface", in every convention; an
    // infinite far plane's 0 too. Nearer than near clamps to 0.
    const float clear = cel::clearDepth(c.depth);
    EXPECT_EQ(core::linearFromStored(s, clear), 1.0f) << c.name;
    EXPECT_EQ(core::linearFromStored(s, c.depth == DepthConvention::kReversedZ ? 1.0f : 0.0f), 0.0f) << c.name;
  }
  // The far plane's stored value is "no surface" exactly, for any planes: in float through the
  // projection it came out 1 - 9e-7 for standard depth with near 0.5, far 40 (lights lit the sky).
  for (const auto& [n, f] : {std::pair{0.5f, 40.0f}, std::pair{0.1f, 1000.0f}, std::pair{1.0f, 10.0f}}) {
    const float fov = glm::radians(60.0f);
    const core::DepthSpace spaces[] = {
        {DepthConvention::kStandard, ClipDepth::kNegativeOneToOne, glm::perspectiveRH_NO(fov, 1.5f, n, f), n, f},
        {DepthConvention::kStandard, ClipDepth::kZeroToOne, glm::perspectiveRH_ZO(fov, 1.5f, n, f), n, f},
        {DepthConvention::kReversedZ, ClipDepth::kZeroToOne, glm::perspectiveRH_ZO(fov, 1.5f, f, n), n, f},
        {DepthConvention::kReversedZ, ClipDepth::kNegativeOneToOne, glm::perspectiveRH_NO(fov, 1.5f, f, n), n, f}};
    for (const core::DepthSpace& sp : spaces) {
      const float clear = cel::clearDepth(sp.convention);
      EXPECT_EQ(core::linearFromStored(sp, clear), 1.0f) << n << " " << f;
      EXPECT_LT(core::linearFromStored(sp, core::storedDepth(sp, 0.999f)), 1.0f) << n << " " << f;
    }
  }
  // Past the finite linear scale of an infinite-far projection: clamped to 1.
  EXPECT_EQ(core::linearFromStored(spaceFor(kReversedInfinite), static_cast<float>(kNear / 500.0)), 1.0f);
}

// ---- the host's scene ---------------------------------------------------------------------------

// The host's own program: camera-space vertices through its projection (its depth as the hardware
// gives it), a flat scene-linear colour; with uLinear it writes Puff's linear depth instead (the
// linear convention, and Puff's own opaque pass).
const char* kHostVs = R"(#version 450 core
layout(location = 0) uniform mat4 uP;
layout(location = 3) uniform vec3 uCorners[4];
out float vDist;
void main() {
  const int order[6] = int[](0, 1, 2, 0, 2, 3);
  vec3 p = uCorners[order[gl_VertexID]];
  vDist = -p.z;
  gl_Position = uP * vec4(p, 1.0);
}
)";
const char* kHostFs = R"(#version 450 core
layout(location = 1) uniform vec3 uColor;
layout(location = 2) uniform vec3 uLinear;  // x: write linear depth, y: near, z: far
in float vDist;
layout(location = 0) out vec4 outColor;
void main() {
  outColor = vec4(uColor, 1.0);
  gl_FragDepth = uLinear.x > 0.5 ? (vDist - uLinear.y) / (uLinear.z - uLinear.y) : gl_FragCoord.z;
}
)";

const glm::vec3 kSky(0.4f, 0.6f, 0.9f), kWallColor(0.8f, 0.3f, 0.2f), kFloorColor(0.3f, 0.5f, 0.2f);
constexpr float kWallDistance = 5.5f, kWallRight = -0.8f, kFloorY = -1.2f;

struct Quad {
  glm::vec3 corners[4];
  glm::vec3 color;
};
// A wall facing the camera at distance 5.5 over x < -0.8, and a floor at y = -1.2 running from 1 to
// 40 units away (its depth changes across the image).
const Quad kWall{{{-30, -30, -kWallDistance},
                  {kWallRight, -30, -kWallDistance},
                  {kWallRight, 30, -kWallDistance},
                  {-30, 30, -kWallDistance}},
                 kWallColor};
const Quad kFloor{{{-30, kFloorY, -1}, {30, kFloorY, -1}, {30, kFloorY, -40}, {-30, kFloorY, -40}}, kFloorColor};

class HostMedia : public MediaRendererTest {
 protected:
  void SetUp() override {
    MediaRendererTest::SetUp();
    if (HasFatalFailure()) return;
    host_ = program(kHostVs, kHostFs);
    vao_ = core::makeVertexArray();
  }
  void TearDown() override {
    EXPECT_EQ(core::drainGlErrors(), "");
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glBindVertexArray(0);
    glUseProgram(0);
    host_ = {};
    vao_ = {};
  }

  // The host draws the floor and the wall (depth test in its convention) into the bound framebuffer.
  void drawScene(const Convention& c, bool writeLinear) {
    glUseProgram(host_.get());
    glBindVertexArray(vao_.get());
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(writeLinear ? GL_LESS : cel::nearerDepthFunc(c.depth));
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    const glm::mat4 p = projection(c, kOrthoHeight);
    glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(p));
    glUniform3f(2, writeLinear ? 1.0f : 0.0f, kNear, kFar);
    for (const Quad& q : {kFloor, kWall}) {
      glUniform3fv(1, 1, &q.color.x);
      glUniform3fv(3, 4, &q.corners[0].x);
      glDrawArrays(GL_TRIANGLES, 0, 6);
    }
    glBindVertexArray(0);
    glUseProgram(0);
  }

  static media::Frame mediaFrame(const Convention& c) {
    media::Frame f = MediaCamera{kNear, kFar, kFovY}.frame(kSize);
    f.projection = projection(c, kOrthoHeight);
    return f;
  }

  // The host's frame: its scene in its convention, then Puff's media layer and lights over it.
  std::vector<glm::vec4> hostPath(const Convention& c, float scale, std::span<const media::Particle> particles,
                                  std::span<const media::ExplosionLight> lights,
                                  std::vector<float>* linearDepth = nullptr, GLenum colorFormat = GL_RGBA16F,
                                  int targetSize = kSize, int ox = 0, int oy = 0, bool covered = false) {
    // The game's frame is targetSize^2; the view Puff sees is the kSize^2 viewport at (ox, oy).
    HostTarget target(targetSize, c.depth == DepthConvention::kReversedZ ? GL_DEPTH32F_STENCIL8 : GL_DEPTH24_STENCIL8,
                      colorFormat);
    EXPECT_TRUE(target.complete());
    target.bindAndClear(kSky, cel::clearDepth(c.depth));
    glViewport(ox, oy, kSize, kSize);
    drawScene(c, c.depth == DepthConvention::kLinear);
    auto layers = media::HostLayers::create(kSize, kSize, scale);
    EXPECT_OK(layers);
    if (!layers) return {};
    media::HostDepth depth;
    depth.texture = target.depthTexture();
    depth.x = ox;
    depth.y = oy;
    if (covered) (*layers)->setCoverage(media::coverage(mediaFrame(c), particles, lights));
    EXPECT_OK((*layers)->resolveHostDepth(depth, frameIn(spaceFor(c))));
    if (linearDepth) {
      linearDepth->resize(static_cast<std::size_t>(kSize) * kSize);
      glGetTextureImage((*layers)->opaqueDepth(), 0, GL_RED, GL_FLOAT,
                        static_cast<GLsizei>(linearDepth->size() * sizeof(float)), linearDepth->data());
    }
    const media::Frame f = mediaFrame(c);
    (*layers)->beginMedia();
    renderer_->draw((*layers)->layerFrame(f), particles, media::Method::kSpherical, (*layers)->mediaDepth());
    const core::Viewport vp{ox, oy, kSize, kSize};
    EXPECT_OK((*layers)->composeOver(target.framebuffer(), vp, f, lights, {}));
    EXPECT_EQ(core::drainGlErrors(), "");
    return target.readLinear();
  }

  // Puff's own linear path over the same scene: the opaque pass into Layers' framebuffer with
  // linear depth, resolveOpaque, compose into an RGBA16F target (the host's colour format).
  std::vector<glm::vec4> ownPath(const Convention& c, float scale, std::span<const media::Particle> particles,
                                 std::span<const media::ExplosionLight> lights, std::vector<glm::vec4>& opaque) {
    auto layers = media::Layers::create(kSize, kSize, 1, scale);
    EXPECT_OK(layers);
    if (!layers) return {};
    const GLuint fbo = (*layers)->opaqueFramebuffer();
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, kSize, kSize);
    glDisable(GL_SCISSOR_TEST);
    glDepthMask(GL_TRUE);
    const glm::vec4 sky(kSky, 1.0f);
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &sky.x);
    glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
    drawScene(c, true);
    (*layers)->resolveOpaque();
    opaque.resize(static_cast<std::size_t>(kSize) * kSize);
    glGetTextureImage((*layers)->opaqueColor(), 0, GL_RGBA, GL_FLOAT,
                      static_cast<GLsizei>(opaque.size() * sizeof(glm::vec4)), opaque.data());
    const media::Frame f = mediaFrame(c);
    (*layers)->beginMedia();
    renderer_->draw((*layers)->layerFrame(f), particles, media::Method::kSpherical, (*layers)->mediaDepth());
    HostTarget out(kSize, GL_DEPTH24_STENCIL8);
    const core::Viewport vp{0, 0, kSize, kSize};
    (*layers)->compose(out.framebuffer(), vp, f, lights, {});
    EXPECT_EQ(core::drainGlErrors(), "");
    return out.readLinear();
  }

  core::Program host_;
  core::VertexArray vao_;
};

// The camera-space ray through pixel (x, y)'s centre: origin and unit direction.
void pixelRay(const Convention& c, int x, int y, glm::dvec3& origin, glm::dvec3& dir) {
  const double nx = (x + 0.5) / kSize * 2.0 - 1.0, ny = (y + 0.5) / kSize * 2.0 - 1.0;
  if (c.orthographic) {
    origin = glm::dvec3(nx * kOrthoHeight / 2, ny * kOrthoHeight / 2, 0.0);
    dir = glm::dvec3(0, 0, -1);
    return;
  }
  const double t = std::tan(glm::radians(static_cast<double>(kFovY)) / 2.0);
  origin = glm::dvec3(0.0);
  dir = glm::normalize(glm::dvec3(nx * t, ny * t, -1.0));
}

// The distance along the view axis of the host's surface at pixel (x, y), or 0 for sky.
double surfaceDistance(const Convention& c, int x, int y) {
  glm::dvec3 o, d;
  pixelRay(c, x, y, o, d);
  double best = 0.0;
  const double tWall = (-kWallDistance - o.z) / d.z;  // the wall's plane z = -5.5
  const glm::dvec3 w = o + tWall * d;
  if (w.x < kWallRight && w.x > -30 && std::abs(w.y) < 30) best = kWallDistance;
  if (d.y < 0.0) {
    const double tFloor = (kFloorY - o.y) / d.y;
    const glm::dvec3 f = o + tFloor * d;
    if (-f.z >= 1.0 && -f.z <= 40.0 && std::abs(f.x) < 30 && (best == 0.0 || -f.z < best)) best = -f.z;
  }
  return best;
}

TEST_F(HostMedia, ResolveHostDepthGivesTheLinearDepthOfTheHostsSurfaces) {
  for (const Convention& c : kAll) {
    const ClipControlScope scope(c.clip);
    std::vector<float> lin;
    hostPath(c, 1.0f, {}, {}, &lin);
    ASSERT_EQ(lin.size(), static_cast<std::size_t>(kSize) * kSize);
    double worst = 0.0;
    int surfaces = 0, skipped = 0;
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        const double d = surfaceDistance(c, x, y);
        // Pixels where the wall's edge or the floor's far edge crosses the pixel: rasterized by
        // coverage at the centre, as computed; skip the one column at the wall's edge.
        if (surfaceDistance(c, std::max(x - 1, 0), y) != d && d == kWallDistance) {
          ++skipped;
          continue;
        }
        const double want = d == 0.0 ? 1.0 : linearOf(d);
        if (d != 0.0) ++surfaces;
        worst = std::max(worst, std::abs(lin[static_cast<std::size_t>(y) * kSize + x] - want));
      }
    }
    EXPECT_GT(surfaces, kSize * kSize / 4) << c.name;
    EXPECT_LT(skipped, kSize) << c.name;
    // 24-bit standard depth at 40 units resolves 40^2 / (0.1 * 2^24) ~ 1e-3 world units = 1e-5 linear.
    EXPECT_LT(worst, 3e-5) << c.name;
  }
}

// A game's multisampled frame: RGBA16F colour and D24S8 depth textures of `samples` samples.
struct MultisampleTarget {
  explicit MultisampleTarget(int samples)
      : fbo(core::makeFramebuffer()),
        color(core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE)),
        depth(core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE)) {
    glTextureStorage2DMultisample(color.get(), samples, GL_RGBA16F, kSize, kSize, GL_TRUE);
    glTextureStorage2DMultisample(depth.get(), samples, GL_DEPTH24_STENCIL8, kSize, kSize, GL_TRUE);
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
    glNamedFramebufferTexture(fbo.get(), GL_DEPTH_STENCIL_ATTACHMENT, depth.get(), 0);
  }
  bool complete() const { return glCheckNamedFramebufferStatus(fbo.get(), GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE; }
  core::Framebuffer fbo;
  core::Texture color, depth;
};

TEST_F(HostMedia, AMultisampledHostDepthKeepsTheNearestSample) {
  const Convention& c = kStandardNO;
  const MultisampleTarget ms(4);
  ASSERT_TRUE(ms.complete());
  const GLuint fbo = ms.fbo.get();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, kSize, kSize);
  glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
  drawScene(c, false);
  auto layers = media::HostLayers::create(kSize, kSize, 0.25f);
  ASSERT_OK(layers);
  media::HostDepth depth;
  depth.texture = ms.depth.get();
  ASSERT_OK((*layers)->resolveHostDepth(depth, frameIn(spaceFor(c))));
  std::vector<float> lin(static_cast<std::size_t>(kSize) * kSize);
  glGetTextureImage((*layers)->opaqueDepth(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(lin.size() * 4), lin.data());
  // The wall's edge: the first column whose centre misses the wall still has samples on it, and
  // its nearest is the wall's depth (the floor and sky behind lie farther).
  int wallColumns = 0, edgeColumns = 0;
  const int y = kSize / 2 + 8;  // above the floor's horizon: wall or sky
  for (int x = 0; x < kSize; ++x) {
    const float v = lin[static_cast<std::size_t>(y) * kSize + x];
    if (std::abs(v - linearOf(kWallDistance)) < 3e-5) {
      ++wallColumns;
      if (surfaceDistance(c, x, y) != kWallDistance) ++edgeColumns;
    } else {
      EXPECT_EQ(v, 1.0f) << "column " << x;  // sky
    }
  }
  EXPECT_GT(wallColumns, 10);
  EXPECT_EQ(edgeColumns, 1);  // the pixel the edge crosses keeps its nearer (wall) samples
  // The layer's depth at 1/4: each texel is the nearest of its 4 x 4 pixels.
  std::vector<float> layer(static_cast<std::size_t>((*layers)->mediaWidth()) * (*layers)->mediaHeight());
  glGetTextureImage((*layers)->mediaDepth(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(layer.size() * 4), layer.data());
  for (int ty = 0; ty < (*layers)->mediaHeight(); ++ty) {
    for (int tx = 0; tx < (*layers)->mediaWidth(); ++tx) {
      float nearest = 1.0f;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
          nearest = std::min(nearest, lin[static_cast<std::size_t>(ty * 4 + j) * kSize + tx * 4 + i]);
      EXPECT_EQ(layer[static_cast<std::size_t>(ty) * (*layers)->mediaWidth() + tx], nearest);
    }
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

// composeOver in closed form: where the wall stands inside the smoke sphere, the pixel is the wall
// seen through the sphere's chord clipped at the wall, out = wall * (1 - a) + colour * a (albedo 1,
// ambient 1, no light); over the sky, the full chord. Only right if the host's depth converted right.
TEST_F(HostMedia, ComposeOverClipsTheMediumAtTheHostsWall) {
  media::Material m = plainMaterial(0.6f);
  m.color = glm::vec3(1.0f, 0.5f, 0.25f);
  ASSERT_TRUE(renderer_->setMaterials({m}).ok());
  const media::Particle smoke = sphereAt({0, 0, -6}, 2.0f);
  for (const Convention& c : kAll) {
    const ClipControlScope scope(c.clip);
    const auto px = hostPath(c, 1.0f, std::span(&smoke, 1), {});
    ASSERT_EQ(px.size(), static_cast<std::size_t>(kSize) * kSize);
    int wallPixels = 0, skyPixels = 0;
    double worst = 0.0;
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        const double d = surfaceDistance(c, x, y);
        if (d != 0.0 && d != kWallDistance) continue;                           // the floor: below the sphere mostly
        if (d == kWallDistance && surfaceDistance(c, x + 1, y) != d) continue;  // the edge column
        glm::dvec3 o, dir;
        pixelRay(c, x, y, o, dir);
        const double a = media::sphereOpacity(o, dir, {0, 0, -6}, 2.0, 0.6, d == 0.0 ? 1e30 : d, kNear);
        if (a < 0.05) continue;
        const glm::dvec3 bg = d == 0.0 ? glm::dvec3(kSky) : glm::dvec3(kWallColor);
        (d == 0.0 ? skyPixels : wallPixels)++;
        const glm::vec4 got = px[static_cast<std::size_t>(y) * kSize + x];
        EXPECT_EQ(got.a, 1.0f) << "the host's alpha is kept";
        for (int i = 0; i < 3; ++i)
          worst = std::max(worst, std::abs(got[i] - (bg[i] * (1 - a) + glm::dvec3(m.color)[i] * a)));
      }
    }
    EXPECT_GT(wallPixels, 100) << c.name;
    EXPECT_GT(skyPixels, 100) << c.name;
    EXPECT_LT(worst, 3e-3) << c.name;  // the host's RGBA16F colour: half-float rounding
  }
}

// The same frame through the host's path and through Puff's own linear path (its opaque pass,
// resolveOpaque, compose): smoke and fire, an additive and a modulating explosion light on the
// wall and floor, at full and half resolution, in every convention.
TEST_F(HostMedia, ComposeOverMatchesPuffsOwnLinearPath) {
  media::Material smokeMat = plainMaterial(0.6f);
  smokeMat.color = glm::vec3(0.7f);
  media::Material fire = plainMaterial(1.5f);
  fire.name = "fire";
  fire.emissive = true;
  ASSERT_TRUE(renderer_->setMaterials({smokeMat, fire}).ok());
  std::vector<media::Particle> ps = {sphereAt({0, 0, -6}, 2.0f), sphereAt({-1.5f, -0.8f, -4.5f}, 0.8f)};
  ps[1].material = 1;
  media::ExplosionLight add, mul;
  add.center = {-1.5f, -0.8f, -4.5f};
  add.radius = 2.5f;
  add.intensity = 0.8f;
  mul.center = {1.0f, -1.0f, -8.0f};
  mul.radius = 3.0f;
  mul.intensity = 0.6f;
  mul.modulate = true;
  mul.color = {0.2f, 0.4f, 1.0f};
  const media::ExplosionLight lights[2] = {add, mul};
  for (const float scale : {1.0f, 0.5f}) {
    for (const Convention& c : kAll) {
      const ClipControlScope scope(c.clip);
      const auto host = hostPath(c, scale, ps, lights);
      // Over what the media cover (LayersBase::setCoverage), the same frame to the bit: these, and a
      // small puff (its box under a quarter of the frame's width) whose passes run over part of it.
      EXPECT_EQ(hostPath(c, scale, ps, lights, nullptr, GL_RGBA16F, kSize, 0, 0, true), host) << c.name;
      const media::Particle puff = sphereAt({1.5f, 0.8f, -7.0f}, 0.3f);
      const media::PixelBox box = media::coverage(mediaFrame(c), std::span(&puff, 1));
      EXPECT_TRUE(!box.empty() && box.x1 - box.x0 < kSize / 4) << c.name;
      EXPECT_EQ(hostPath(c, scale, std::span(&puff, 1), {}, nullptr, GL_RGBA16F, kSize, 0, 0, true),
                hostPath(c, scale, std::span(&puff, 1), {}))
          << c.name;
      std::vector<glm::vec4> ownOpaque;
      const auto own = ownPath(c, scale, ps, lights, ownOpaque);
      const auto plain = hostPath(c, scale, {}, {});
      ASSERT_EQ(host.size(), own.size());
      int close = 0, changed = 0, edges = 0;
      double worst = 0.0;
      for (std::size_t i = 0; i < host.size(); ++i) {
        // Puff's opaque pass is a 1-sample multisample target, which llvmpipe rasterizes at the
        // geometry's edges differently from the host's single-sample one: pixels whose opaque
        // colour differs between the two are not the composition's doing.
        if (glm::any(glm::greaterThan(glm::abs(glm::vec3(ownOpaque[i]) - glm::vec3(plain[i])), glm::vec3(1e-3f)))) {
          ++edges;
          continue;
        }
        double diff = 0.0, effect = 0.0;
        for (int k = 0; k < 3; ++k) {
          diff = std::max(diff, static_cast<double>(std::abs(host[i][k] - own[i][k])));
          effect = std::max(effect, static_cast<double>(std::abs(host[i][k] - plain[i][k])));
        }
        worst = std::max(worst, diff);
        if (diff > 0.1 && std::getenv("PUFF_DEBUG_HOST"))
          std::printf("%s px %d,%d host %g %g %g own %g %g %g plain %g %g %g\n", c.name, int(i % kSize), int(i / kSize),
                      host[i].r, host[i].g, host[i].b, own[i].r, own[i].g, own[i].b, plain[i].r, plain[i].g,
                      plain[i].b);
        if (diff <= 2.0 / 255.0) ++close;
        if (effect > 0.05) ++changed;
      }
      const std::string what = std::string(c.name) + " at scale " + std::to_string(scale);
      std::printf("%s: %d edge pixels left out, %d of %d within 2/255, worst %.4f\n", what.c_str(), edges, close,
                  static_cast<int>(host.size()) - edges, worst);
      EXPECT_LT(edges, 3 * kSize) << what;  // the wall's edge column and the floor's far edge row
      EXPECT_GE(close, static_cast<int>((host.size() - edges) * 0.999)) << what << ", worst " << worst;
      EXPECT_LT(worst, 0.05) << what;
      EXPECT_GT(changed, static_cast<int>(host.size() / 5)) << what;  // media and lights really drew
    }
  }
}

// A game whose colour target is sRGB-encoded (GL_SRGB8_ALPHA8) with GL_FRAMEBUFFER_SRGB on: its
// scene, the media and the lights are written and blended in linear and stored encoded, because
// no Puff call turns the flag off. Decoded, the frame is the float target's within 8-bit steps.
TEST_F(HostMedia, AnSrgbTargetWithTheFlagOnBlendsInLinear) {
  media::Material m = plainMaterial(0.6f);
  m.color = glm::vec3(1.0f, 0.5f, 0.25f);
  ASSERT_TRUE(renderer_->setMaterials({m}).ok());
  const media::Particle smoke = sphereAt({0, 0, -6}, 2.0f);
  media::ExplosionLight light;
  light.center = {-1.5f, -0.8f, -4.5f};
  light.radius = 2.5f;
  const ClipControlScope scope(kStandardNO.clip);
  const auto linear = hostPath(kStandardNO, 0.5f, std::span(&smoke, 1), std::span(&light, 1));
  glEnable(GL_FRAMEBUFFER_SRGB);
  const auto encoded =
      hostPath(kStandardNO, 0.5f, std::span(&smoke, 1), std::span(&light, 1), nullptr, GL_SRGB8_ALPHA8);
  glDisable(GL_FRAMEBUFFER_SRGB);
  ASSERT_EQ(linear.size(), encoded.size());
  // Decoded, each channel is the float frame's (clamped at display 1, the 8-bit target's top)
  // within 8-bit rounding of the stored scene and of the blend's result (~0.005 in linear at the
  // top of the range). Were the flag off, linear values would be stored raw and decode ~0.25 darker.
  double worst = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < linear.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double diff = std::abs(core::srgbToLinear(static_cast<double>(encoded[i][k])) -
                                   std::min(static_cast<double>(linear[i][k]), 1.0));
      worst = std::max(worst, diff);
      sum += diff;
    }
  }
  std::printf("sRGB target, decoded against the float target: worst %.4f, mean %.5f (linear)\n", worst,
              sum / (3.0 * static_cast<double>(linear.size())));
  EXPECT_LT(worst, 0.012);
  EXPECT_LT(sum / (3.0 * static_cast<double>(linear.size())), 0.004);
}

// A game that draws its view into part of a bigger framebuffer (split screen, an editor panel,
// dynamic resolution): HostDepth x/y and composeOver's viewport origin place Puff's reads and
// writes there. The region is the origin-0 frame to the last bit; outside it nothing changes.
TEST_F(HostMedia, AViewportAwayFromTheOriginReadsAndWritesItsOwnRegion) {
  media::Material m = plainMaterial(0.6f);
  m.color = glm::vec3(1.0f, 0.5f, 0.25f);
  ASSERT_TRUE(renderer_->setMaterials({m}).ok());
  const media::Particle smoke = sphereAt({0, 0, -6}, 2.0f);
  media::ExplosionLight light;
  light.center = {-1.5f, -0.8f, -4.5f};
  light.radius = 2.5f;
  constexpr int kBig = 96, kX = 13, kY = 7;
  for (const Convention& c : {kStandardNO, kReversedInfinite}) {
    const ClipControlScope scope(c.clip);
    for (const float scale : {1.0f, 0.5f}) {
      const auto atOrigin = hostPath(c, scale, std::span(&smoke, 1), std::span(&light, 1));
      const auto moved =
          hostPath(c, scale, std::span(&smoke, 1), std::span(&light, 1), nullptr, GL_RGBA16F, kBig, kX, kY);
      ASSERT_EQ(moved.size(), static_cast<std::size_t>(kBig) * kBig);
      const glm::vec4 sky = moved[0];  // outside the view: the host's clear, in half floats
      EXPECT_NEAR(sky.b, kSky.b, 1e-3f);
      int same = 0, outsideTouched = 0;
      float worst = 0.0f;
      for (int y = 0; y < kBig; ++y) {
        for (int x = 0; x < kBig; ++x) {
          const glm::vec4 got = moved[static_cast<std::size_t>(y) * kBig + x];
          const bool inside = x >= kX && x < kX + kSize && y >= kY && y < kY + kSize;
          if (inside) {
            // The same frame, up to how the host's own triangles rasterize a whole number of pixels
            // away (a few pixels' depth rounds differently).
            const glm::vec4 want = atOrigin[static_cast<std::size_t>(y - kY) * kSize + (x - kX)];
            const glm::vec3 d = glm::abs(glm::vec3(got) - glm::vec3(want));
            const float diff = std::max({d.x, d.y, d.z});
            worst = std::max(worst, diff);
            same += diff <= 1e-3f;
          } else if (got != sky) {
            ++outsideTouched;
          }
        }
      }
      std::printf("%s at scale %.2f: %d of %d pixels within 1e-3 of the origin's frame, worst %.4f\n", c.name, scale,
                  same, kSize * kSize, worst);
      EXPECT_GE(same, kSize * kSize * 99 / 100) << c.name << " at scale " << scale;
      EXPECT_LT(worst, 0.05f) << c.name << " at scale " << scale;
      EXPECT_EQ(outsideTouched, 0) << c.name << " at scale " << scale;
    }
  }
}

// Each sample of a multisampled depth counts: the wall drawn into one sample only (glSampleMaski)
// is what every pixel it covers resolves to, for each sample of 2, 4 and 8.
TEST_F(HostMedia, EverySampleOfAMultisampledDepthIsRead) {
  const Convention& c = kStandardNO;
  GLint maxDepth = 1, maxColor = 1;
  glGetIntegerv(GL_MAX_DEPTH_TEXTURE_SAMPLES, &maxDepth);
  glGetIntegerv(GL_MAX_COLOR_TEXTURE_SAMPLES, &maxColor);
  ASSERT_GE(std::min(maxDepth, maxColor), 4);
  for (const int samples : {2, 4, 8}) {
    if (samples > std::min(maxDepth, maxColor)) {
      std::printf("%d samples: this GL gives multisample depth textures of up to %d\n", samples,
                  std::min(maxDepth, maxColor));
      continue;
    }
    const MultisampleTarget ms(samples);
    ASSERT_TRUE(ms.complete());
    const GLuint fbo = ms.fbo.get();
    auto layers = media::HostLayers::create(kSize, kSize, 1.0f);
    ASSERT_OK(layers);
    for (int k = 0; k < samples; ++k) {
      glBindFramebuffer(GL_FRAMEBUFFER, fbo);
      glViewport(0, 0, kSize, kSize);
      glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
      glEnable(GL_SAMPLE_MASK);
      glSampleMaski(0, 1u << k);
      drawScene(c, false);
      glSampleMaski(0, ~0u);
      glDisable(GL_SAMPLE_MASK);
      media::HostDepth depth;
      depth.texture = ms.depth.get();
      EXPECT_OK((*layers)->resolveHostDepth(depth, frameIn(spaceFor(c))));
      std::vector<float> lin(static_cast<std::size_t>(kSize) * kSize);
      glGetTextureImage((*layers)->opaqueDepth(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(lin.size() * 4),
                        lin.data());
      int wall = 0, wrong = 0;
      for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
          // Wall pixels away from its edge (a sample's position may fall either side there).
          if (surfaceDistance(c, x, y) != kWallDistance || surfaceDistance(c, x + 1, y) != kWallDistance) continue;
          ++wall;
          wrong += std::abs(lin[static_cast<std::size_t>(y) * kSize + x] - linearOf(kWallDistance)) > 3e-5;
        }
      }
      EXPECT_GT(wall, 500) << samples << " samples, sample " << k;
      EXPECT_EQ(wrong, 0) << samples << " samples, the wall in sample " << k << " only";
    }
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

// The explosion lights apply in order: an additive light then a modulating one is
// (surface + add) * mul. Orthographic, at the pixel whose ray passes through both lights' centre
// (radial weight 1) with the wall behind their centre (depth weight 1): k = intensity exactly.
TEST_F(HostMedia, ExplosionLightsApplyInTheirOrder) {
  const Convention& c = kOrthoStandard;
  const ClipControlScope scope(c.clip);
  const int px = 10, py = 40;
  glm::dvec3 o, dir;
  pixelRay(c, px, py, o, dir);
  ASSERT_EQ(surfaceDistance(c, px, py), kWallDistance);
  media::ExplosionLight add, mul;
  add.center = glm::vec3(static_cast<float>(o.x), static_cast<float>(o.y), -4.0f);  // front 3, centre 4, wall 5.5
  add.radius = 1.0f;
  add.color = glm::vec3(0.5f);
  add.intensity = 1.0f;
  mul = add;
  mul.modulate = true;
  const media::ExplosionLight addThenMul[2] = {add, mul}, mulThenAdd[2] = {mul, add};
  const auto a = hostPath(c, 1.0f, {}, addThenMul);
  const auto b = hostPath(c, 1.0f, {}, mulThenAdd);
  const std::size_t i = static_cast<std::size_t>(py) * kSize + px;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(a[i][k], (kWallColor[k] + 0.5f) * 0.5f, 2e-3) << "channel " << k;
    EXPECT_NEAR(b[i][k], kWallColor[k] * 0.5f + 0.5f, 2e-3) << "channel " << k;
  }
}

// compose_over.frag's two outputs are the blend's two sources: index 0 and index 1 of location 0
// (a second location instead is what some drivers take and the spec leaves undefined).
TEST_F(HostMedia, TheBlendFactorIsTheSecondSourceOfLocationZero) {
  auto p = core::buildProgram({"media/fullscreen.vert", "media/compose_over.frag"});
  ASSERT_OK(p);
  for (const auto& [name, index] : {std::pair{"outColor", 0}, std::pair{"outFactor", 1}}) {
    EXPECT_EQ(glGetProgramResourceLocation(p->get(), GL_PROGRAM_OUTPUT, name), 0) << name;
    EXPECT_EQ(glGetProgramResourceLocationIndex(p->get(), GL_PROGRAM_OUTPUT, name), index) << name;
  }
}

// The same on the GPU: a cleared depth texture (nothing drawn) resolves to exactly 1 at every
// pixel, for standard and reversed-z with near 0.5, far 40, and then no light touches it.
TEST_F(HostMedia, TheClearedFarPlaneIsNoSurfaceAndNoLightTouchesIt) {
  const float n = 0.5f, f = 40.0f, fov = glm::radians(60.0f);
  struct Case {
    core::DepthSpace space;
    GLenum format;
  };
  const Case cases[] = {
      {{DepthConvention::kStandard, ClipDepth::kNegativeOneToOne, glm::perspectiveRH_NO(fov, 1.0f, n, f), n, f},
       GL_DEPTH24_STENCIL8},
      {{DepthConvention::kStandard, ClipDepth::kZeroToOne, glm::perspectiveRH_ZO(fov, 1.0f, n, f), n, f},
       GL_DEPTH32F_STENCIL8},
      {{DepthConvention::kReversedZ, ClipDepth::kZeroToOne, glm::perspectiveRH_ZO(fov, 1.0f, f, n), n, f},
       GL_DEPTH32F_STENCIL8},
      {{DepthConvention::kReversedZ, ClipDepth::kNegativeOneToOne, glm::perspectiveRH_NO(fov, 1.0f, f, n), n, f},
       GL_DEPTH24_STENCIL8}};
  for (const Case& c : cases) {
    HostTarget target(kSize, c.format);
    target.bindAndClear(kSky, cel::clearDepth(c.space.convention));
    auto layers = media::HostLayers::create(kSize, kSize, 0.5f);
    ASSERT_OK(layers);
    media::HostDepth depth;
    depth.texture = target.depthTexture();
    ASSERT_OK((*layers)->resolveHostDepth(depth, frameIn(c.space)));
    std::vector<float> lin(static_cast<std::size_t>(kSize) * kSize);
    glGetTextureImage((*layers)->opaqueDepth(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(lin.size() * 4), lin.data());
    EXPECT_EQ(std::count(lin.begin(), lin.end(), 1.0f), kSize * kSize)
        << "case " << (&c - cases) << ": " << lin[0] << ", stored " << target.readDepth()[0];
    media::Frame fr = MediaCamera{n, f, 60.0f}.frame(kSize);
    fr.projection = c.space.projection;
    media::ExplosionLight light;  // in front of the camera, its disc over the whole view
    light.center = {0, 0, -5};
    light.radius = 4.0f;
    (*layers)->beginMedia();
    const core::Viewport vp{0, 0, kSize, kSize};
    ASSERT_OK((*layers)->composeOver(target.framebuffer(), vp, fr, std::span(&light, 1), {}));
    const auto px = target.readLinear();
    int lit = 0;
    for (const glm::vec4& p : px) lit += std::abs(p.r - px[0].r) > 1e-4f || std::abs(p.r - kSky.r) > 1e-3f;
    EXPECT_EQ(lit, 0);
  }
}

}  // namespace
}  // namespace puff::host_media
