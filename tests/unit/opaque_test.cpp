// Opaque scene objects of the cel frame: the primitives' geometry, and what the renderer writes,
// checked against the analytic answer (ray/plane depth, Eq. 2 colours, a sphere's projection).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/opaque.h>
#include <puff/core/colour.h>
#include <puff/gl_api.h>
#include <puff/mesh/mesh.h>
#include <puff/render/cel_scene.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/gl_target.h"
#include "support/linear_frame.h"

namespace puff::cel {
namespace {

// The primitives (puff::mesh) as the opaque renderer takes them (puff::render).
TriangleMesh makePlane() { return *render::toTriangleMesh(mesh::makePlane()); }
TriangleMesh makeBox() { return *render::toTriangleMesh(mesh::makeBox()); }
TriangleMesh makeSphere(int segments = 48) { return *render::toTriangleMesh(mesh::makeSphere(segments)); }

constexpr int kSize = 128;
constexpr float kColorTol = 1.0f / 255.0f;

// ---- primitives (no GL) --------------------------------------------------------------------------

// Every triangle is counter-clockwise from outside: its face normal agrees with its vertex normals.
void expectWellFormed(const TriangleMesh& m) {
  ASSERT_EQ(m.normals.size(), m.positions.size());
  ASSERT_EQ(m.indices.size() % 3, 0u);
  ASSERT_FALSE(m.indices.empty());
  for (const glm::vec3& n : m.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const std::uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
    ASSERT_LT(a, m.positions.size());
    ASSERT_LT(b, m.positions.size());
    ASSERT_LT(c, m.positions.size());
    const glm::vec3 face = glm::cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
    ASSERT_GT(glm::length(face), 0.0f) << "degenerate triangle " << t / 3;
    const glm::vec3 f = glm::normalize(face);
    for (std::uint32_t v : {a, b, c}) EXPECT_GT(glm::dot(f, m.normals[v]), 0.1f) << "triangle " << t / 3;
  }
}

TEST(OpaqueMeshes, PlaneIsTheUnitSquareFacingUp) {
  const TriangleMesh m = makePlane();
  expectWellFormed(m);
  EXPECT_EQ(m.indices.size(), 6u);
  for (const glm::vec3& p : m.positions) {
    EXPECT_EQ(p.y, 0.0f);
    EXPECT_EQ(std::abs(p.x), 1.0f);
    EXPECT_EQ(std::abs(p.z), 1.0f);
  }
  for (const glm::vec3& n : m.normals) EXPECT_EQ(n, glm::vec3(0, 1, 0));
}

TEST(OpaqueMeshes, BoxHasFlatFacesOnTheUnitCube) {
  const TriangleMesh m = makeBox();
  expectWellFormed(m);
  EXPECT_EQ(m.positions.size(), 24u);
  EXPECT_EQ(m.indices.size(), 36u);
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const glm::vec3 p = m.positions[i], n = m.normals[i];
    for (int c = 0; c < 3; ++c) EXPECT_EQ(std::abs(p[c]), 1.0f);
    EXPECT_EQ(glm::dot(p, n), 1.0f) << "vertex " << i << " lies on the face its normal names";
  }
}

TEST(OpaqueMeshes, SphereVerticesLieOnTheUnitSphere) {
  for (int segments : {3, 4, 7, 48}) {
    SCOPED_TRACE(segments);
    const TriangleMesh m = makeSphere(segments);
    expectWellFormed(m);
    const int rings = std::max(2, segments / 2);
    EXPECT_EQ(m.positions.size(), static_cast<std::size_t>(2 + (rings - 1) * segments));
    EXPECT_EQ(m.indices.size(), static_cast<std::size_t>(3 * 2 * segments * (rings - 1)));
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      EXPECT_NEAR(glm::length(m.positions[i]), 1.0f, 1e-6f);
      EXPECT_NEAR(glm::distance(m.positions[i], m.normals[i]), 0.0f, 1e-6f);
    }
  }
  EXPECT_EQ(makeSphere(-5).positions.size(), makeSphere(3).positions.size()) << "segments below 3 mean 3";
}

// ---- rendering -----------------------------------------------------------------------------------

// An offscreen kSize^2 target: RGBA16F colour, 24-bit depth + 8-bit stencil.
class Target : public test::OffscreenTarget {
 public:
  Target() : OffscreenTarget(kSize, GL_RGBA16F) { EXPECT_TRUE(complete()); }
  // Binds the target and clears colour to kClear, depth to 1, stencil to 0.
  void bindAndClear() const { clear(kClear); }
  static constexpr glm::vec4 kClear{0.0f, 0.0f, 1.0f, 0.0f};
};

std::size_t at(int x, int y) { return static_cast<std::size_t>(y) * kSize + x; }

void expectColor(const glm::vec4& got, const glm::vec3& want, const char* what, int x, int y) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(got[c], want[c], kColorTol) << what << " at pixel (" << x << ", " << y << "), channel " << c;
  }
  EXPECT_EQ(got.a, 1.0f) << what << " at pixel (" << x << ", " << y << ")";
}

class OpaqueTest : public test::GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    if (HasFatalFailure()) return;
    auto r = OpaqueRenderer::create();
    ASSERT_OK(r);
    renderer_ = std::move(*r);
    block_ = std::make_unique<FrameBlock>();
    ramp_ = std::make_unique<Ramp>(Ramp::twoTone());
    target_ = std::make_unique<Target>();
  }
  void TearDown() override {
    EXPECT_EQ(core::drainGlErrors(), "");
    // GL objects go before the shared context does.
    renderer_.reset();
    block_.reset();
    ramp_.reset();
    target_.reset();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  // Uploads the frame, binds the ramp, binds and clears the target.
  void begin(const Frame& frame) {
    EXPECT_OK(block_->upload(frame));
    ramp_->bind();
    target_->bindAndClear();
  }

  void setObjects(std::vector<OpaqueObject> objects) {
    auto ok = renderer_->setObjects(std::move(objects));
    ASSERT_OK(ok);
  }

  // An orthographic camera looking straight down -y at the origin, the view `height` units tall,
  // over a viewport of `width` x `pixelsTall` pixels.
  static Frame topDown(float height = 2.0f, int width = kSize, int pixelsTall = kSize) {
    Camera c;
    c.position = {0, 5, 0};
    c.target = {0, 0, 0};
    c.up = {0, 0, -1};
    c.fovYDegrees = 0.0f;
    c.orthoHeight = height;
    c.nearPlane = 1.0f;
    c.farPlane = 9.0f;
    return test::linearFrame(c, width, pixelsTall);
  }

  static OpaqueObject object(std::string name, const TriangleMesh& mesh, glm::mat4 transform, glm::vec3 albedo,
                             bool cel = true) {
    OpaqueObject o;
    o.name = std::move(name);
    o.mesh = std::make_shared<const TriangleMesh>(mesh);
    o.transform = transform;
    o.albedo = puff::core::srgbToLinear(albedo);
    o.cel = cel;
    return o;
  }

  static constexpr glm::vec3 kAlbedo{0.8f, 0.5f, 0.3f};
  static constexpr glm::vec3 kAmbient{0.2f, 0.25f, 0.3f};
  static constexpr glm::vec3 kLightColor{0.7f, 0.6f, 0.5f};

  std::unique_ptr<OpaqueRenderer> renderer_;
  std::unique_ptr<FrameBlock> block_;
  std::unique_ptr<Ramp> ramp_;
  std::unique_ptr<Target> target_;
};

TEST_F(OpaqueTest, DepthIsTheLinearDepthOfTheRayPlaneHit) {
  Camera c;
  c.position = {0.3f, 2.0f, 6.0f};
  c.target = {0.0f, 0.0f, 0.0f};
  c.fovYDegrees = 50.0f;
  c.nearPlane = 0.5f;
  c.farPlane = 30.0f;
  const Frame frame = test::linearFrame(c, kSize, kSize);
  begin(frame);
  setObjects({object("ground", makePlane(), glm::scale(glm::mat4(1.0f), glm::vec3(50.0f, 1.0f, 50.0f)), kAlbedo)});
  renderer_->draw(ShadePass::kLit);
  const std::vector<float> depth = target_->readDepth();

  const glm::mat4 invViewProj = glm::inverse(frame.projection * frame.view);
  int ground = 0, sky = 0;
  for (int y = 2; y < kSize; y += 9) {
    for (int x = 3; x < kSize; x += 11) {
      // The pixel centre's ray, from its near-plane point toward its far-plane point.
      const glm::vec2 ndc((x + 0.5f) / kSize * 2.0f - 1.0f, (y + 0.5f) / kSize * 2.0f - 1.0f);
      glm::vec4 n = invViewProj * glm::vec4(ndc, -1.0f, 1.0f), f = invViewProj * glm::vec4(ndc, 1.0f, 1.0f);
      const glm::vec3 origin = glm::vec3(n) / n.w, dir = glm::vec3(f) / f.w - origin;
      const float t = -origin.y / dir.y;
      const float got = depth[at(x, y)];
      if (dir.y >= 0.0f || t > 1.0f) {  // above the horizon, or the plane is beyond the far plane
        EXPECT_EQ(got, 1.0f) << "sky at (" << x << ", " << y << ")";
        ++sky;
        continue;
      }
      const float want = linearDepth(frame, origin + t * dir);
      if (want > 0.98f) continue;  // too close to where the far plane cuts the ground
      EXPECT_NEAR(got, want, 2e-4f) << "ground at (" << x << ", " << y << ")";
      ++ground;
    }
  }
  EXPECT_GT(ground, 40);
  EXPECT_GT(sky, 10);
}

TEST_F(OpaqueTest, CelLightingIsAlbedoTimesAmbientPlusLightThroughTheRamp) {
  Frame frame = topDown();
  frame.ambient = puff::core::srgbToLinear(kAmbient);
  frame.light.color = puff::core::srgbToLinear(kLightColor);
  setObjects({object("ground", makePlane(), glm::mat4(1.0f), kAlbedo)});
  struct Case {
    glm::vec3 light;
    glm::vec3 want;
    const char* what;
  };
  const float cos07 = 0.7f, sin07 = std::sqrt(1.0f - cos07 * cos07);
  const float cos03 = 0.3f, sin03 = std::sqrt(1.0f - cos03 * cos03);
  const Case cases[] = {
      {{0, 1, 0}, kAlbedo * (kAmbient + kLightColor), "light along the normal"},
      {{sin07, cos07, 0}, kAlbedo * (kAmbient + kLightColor), "N.L = 0.7, in the ramp's white half"},
      {{0, cos03, sin03}, kAlbedo * kAmbient, "N.L = 0.3, in the ramp's black half"},
      {{0.2f, -1, 0}, kAlbedo * kAmbient, "light below the horizon"},
  };
  for (const Case& k : cases) {
    frame.light.direction = k.light;
    begin(frame);
    renderer_->draw(ShadePass::kLit);
    const std::vector<glm::vec4> color = target_->readColor();
    for (int y : {1, 64, 126}) {
      for (int x : {0, 40, 127}) expectColor(color[at(x, y)], k.want, k.what, x, y);
    }
  }
}

TEST_F(OpaqueTest, SmoothLightingFollowsTheCosineWithTheInverseTransposeNormal) {
  // A non-uniform scale after a rotation shears the plane's normal: only the inverse transpose
  // keeps it perpendicular to the transformed plane.
  const glm::mat4 transform = glm::scale(glm::mat4(1.0f), glm::vec3(3.0f, 1.0f, 1.0f)) *
                              glm::rotate(glm::mat4(1.0f), glm::radians(30.0f), glm::vec3(0, 0, 1));
  const glm::mat3 m(transform);
  const glm::vec3 normal = glm::normalize(glm::cross(m * glm::vec3(0, 0, 1), m * glm::vec3(1, 0, 0)));
  const glm::vec3 naive = glm::normalize(m * glm::vec3(0, 1, 0));
  Frame frame = topDown();
  frame.ambient = puff::core::srgbToLinear(kAmbient);
  frame.light.color = puff::core::srgbToLinear(kLightColor);
  frame.light.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.5f));
  const float cosTheta = glm::dot(normal, frame.light.direction);
  ASSERT_GT(cosTheta, 0.1f);
  ASSERT_GT(std::abs(glm::dot(naive, frame.light.direction) - cosTheta), 0.05f) << "the test would not tell";
  begin(frame);
  setObjects({object("tilted", makePlane(), transform, kAlbedo, /*cel=*/false)});
  renderer_->draw(ShadePass::kLit);
  const std::vector<glm::vec4> color = target_->readColor();
  const glm::vec3 want = kAlbedo * (kAmbient + kLightColor * cosTheta);
  for (int y : {20, 64, 100}) {
    for (int x : {50, 64, 80}) expectColor(color[at(x, y)], want, "smooth Lambert", x, y);
  }
}

TEST_F(OpaqueTest, PlaneSeenFromBelowTurnsItsNormalTowardTheViewer) {
  Camera c;
  c.position = {0, -5, 0};
  c.target = {0, 0, 0};
  c.up = {0, 0, 1};
  c.fovYDegrees = 0.0f;
  c.orthoHeight = 1.0f;
  c.nearPlane = 1.0f;
  c.farPlane = 9.0f;
  Frame frame = test::linearFrame(c, kSize, kSize);
  frame.ambient = puff::core::srgbToLinear(kAmbient);
  frame.light.color = puff::core::srgbToLinear(kLightColor);
  setObjects({object("ground", makePlane(), glm::mat4(1.0f), kAlbedo)});
  for (float ly : {-1.0f, 1.0f}) {
    frame.light.direction = {0, ly, 0};
    begin(frame);
    renderer_->draw(ShadePass::kLit);
    const glm::vec3 want = ly < 0 ? kAlbedo * (kAmbient + kLightColor) : kAlbedo * kAmbient;
    expectColor(target_->readColor()[at(64, 64)], want, ly < 0 ? "lit from below" : "lit from above", 64, 64);
  }
}

TEST_F(OpaqueTest, MirroringTransformKeepsNormalsOutward) {
  Camera c;
  c.fovYDegrees = 0.0f;
  c.orthoHeight = 4.0f;
  c.nearPlane = 1.0f;
  c.farPlane = 9.0f;
  Frame frame = test::linearFrame(c, kSize, kSize);
  frame.ambient = puff::core::srgbToLinear(kAmbient);
  frame.light.color = puff::core::srgbToLinear(kLightColor);
  frame.light.direction = {0, 0, 1};  // from the camera
  begin(frame);
  setObjects({object("mirrored", makeSphere(), glm::scale(glm::mat4(1.0f), glm::vec3(1, -1, 1)), kAlbedo),
              object("mirrored box", makeBox(),
                     glm::translate(glm::mat4(1.0f), glm::vec3(-1.5f, 0, 0)) *
                         glm::scale(glm::mat4(1.0f), glm::vec3(-0.25f, 0.25f, 0.25f)),
                     kAlbedo)});
  renderer_->draw(ShadePass::kLit);
  const std::vector<glm::vec4> color = target_->readColor();
  expectColor(color[at(64, 64)], kAlbedo * (kAmbient + kLightColor), "mirrored sphere facing the light", 64, 64);
  expectColor(color[at(16, 64)], kAlbedo * (kAmbient + kLightColor), "mirrored box facing the light", 16, 64);
}

TEST_F(OpaqueTest, ShadowedPassOnlyChangesStencilledPixelsToAmbient) {
  Frame frame = topDown();
  frame.ambient = puff::core::srgbToLinear(kAmbient);
  frame.light.color = puff::core::srgbToLinear(kLightColor);
  frame.light.direction = {0, 1, 0};
  begin(frame);
  setObjects({object("ground", makePlane(), glm::mat4(1.0f), kAlbedo)});
  renderer_->draw(ShadePass::kLit);
  const std::vector<float> depthBefore = target_->readDepth();
  const int rx = 32, ry = 40, rw = 64, rh = 40;
  target_->fillStencil(rx, ry, rw, rh, 1);
  renderer_->draw(ShadePass::kShadowed);
  const std::vector<glm::vec4> color = target_->readColor();
  EXPECT_EQ(target_->readDepth(), depthBefore) << "the shadowed pass must not write depth";
  const glm::vec3 lit = kAlbedo * (kAmbient + kLightColor), shadowed = kAlbedo * kAmbient;
  int wrong = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const bool inside = x >= rx && x < rx + rw && y >= ry && y < ry + rh;
      const glm::vec3 want = inside ? shadowed : lit;
      if (glm::any(glm::greaterThan(glm::abs(glm::vec3(color[at(x, y)]) - want), glm::vec3(kColorTol)))) {
        if (++wrong <= 5) ADD_FAILURE() << "pixel (" << x << ", " << y << ") inside=" << inside;
      }
    }
  }
  EXPECT_EQ(wrong, 0);
}

TEST_F(OpaqueTest, ShadowedPassMatchesTheDepthOfLitAndDepthOnlyPassesExactly) {
  // Two overlapping objects: in the shadowed pass every covered pixel must be redrawn by exactly
  // the object that won it (depth EQUAL), in its own albedo, whichever pass wrote the depth.
  Camera c;
  c.position = {0.0f, 3.0f, 5.0f};
  c.fovYDegrees = 40.0f;
  c.nearPlane = 1.0f;
  c.farPlane = 20.0f;
  Frame frame = test::linearFrame(c, kSize, kSize);
  frame.ambient = puff::core::srgbToLinear(kAmbient);
  frame.light.color = puff::core::srgbToLinear(kLightColor);
  const glm::vec3 sphereAlbedo{0.2f, 0.9f, 0.6f};
  setObjects({object("ground", makePlane(), glm::scale(glm::mat4(1.0f), glm::vec3(4.0f, 1.0f, 4.0f)), kAlbedo),
              object("ball", makeSphere(),
                     glm::translate(glm::mat4(1.0f), glm::vec3(0.2f, 0.5f, 0.3f)) *
                         glm::scale(glm::mat4(1.0f), glm::vec3(0.9f)),
                     sphereAlbedo, /*cel=*/false)});

  begin(frame);
  renderer_->draw(ShadePass::kLit);
  const std::vector<float> litDepth = target_->readDepth();
  const std::vector<glm::vec4> litColor = target_->readColor();

  begin(frame);
  renderer_->draw(ShadePass::kDepthOnly);
  EXPECT_EQ(target_->readDepth(), litDepth) << "depth-only writes the lit pass's depth";
  for (const glm::vec4& p : target_->readColor()) {
    ASSERT_EQ(p, Target::kClear) << "depth-only writes no colour";
  }

  target_->fillStencil(0, 0, kSize, kSize, 1);
  renderer_->draw(ShadePass::kShadowed);
  const std::vector<glm::vec4> color = target_->readColor();
  int covered = 0, sphere = 0, wrong = 0;
  for (std::size_t i = 0; i < color.size(); ++i) {
    if (litDepth[i] == 1.0f) {
      if (color[i] != Target::kClear) ++wrong;
      continue;
    }
    ++covered;
    // Tell the objects apart by their lit colour's green-to-red ratio (albedos differ a lot there).
    const bool isSphere = litColor[i].g > 1.5f * litColor[i].r;
    sphere += isSphere;
    const glm::vec3 want = (isSphere ? sphereAlbedo : kAlbedo) * kAmbient;
    if (glm::any(glm::greaterThan(glm::abs(glm::vec3(color[i]) - want), glm::vec3(kColorTol))) || color[i].a != 1.0f) {
      if (++wrong <= 5) ADD_FAILURE() << "pixel " << i % kSize << ", " << i / kSize;
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(covered, kSize * kSize / 4);
  EXPECT_GT(sphere, 500);
}

TEST_F(OpaqueTest, SphereSilhouetteMatchesItsOrthographicProjection) {
  // Orthographic, 4 units over 128 pixels: 32 pixels per unit. Radius 1.25 -> 40 pixels, centre
  // (0.5, -0.25) -> pixel (80, 56).
  Camera c;
  c.position = {0, 0, 5};
  c.fovYDegrees = 0.0f;
  c.orthoHeight = 4.0f;
  c.nearPlane = 1.0f;
  c.farPlane = 10.0f;
  const Frame frame = test::linearFrame(c, kSize, kSize);
  begin(frame);
  const float radius = 1.25f;
  const glm::vec3 centre{0.5f, -0.25f, 0.0f};
  constexpr int kSegments = 64;
  setObjects(
      {object("ball", makeSphere(64),
              glm::translate(glm::mat4(1.0f), centre) * glm::scale(glm::mat4(1.0f), glm::vec3(radius)), kAlbedo)});
  renderer_->draw(ShadePass::kLit);
  const std::vector<glm::vec4> color = target_->readColor();
  const std::vector<float> depth = target_->readDepth();
  const float pixelsPerUnit = kSize / 4.0f;
  const glm::vec2 centrePx = glm::vec2(kSize / 2.0f) + glm::vec2(centre) * pixelsPerUnit;
  double count = 0, sx = 0, sy = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      if (color[at(x, y)].a != 1.0f) continue;
      count += 1;
      sx += x + 0.5;
      sy += y + 0.5;
      // Depth of the sphere's front surface under the pixel centre. The mesh lies inside the sphere,
      // by at most r (1 - cos(2 pi / segments)) along the radius, which is r / z times that along z.
      const glm::vec2 d = (glm::vec2(x + 0.5f, y + 0.5f) - centrePx) / pixelsPerUnit;
      const float r2 = glm::dot(d, d);
      if (r2 < 0.8f * radius * radius) {
        const float z = std::sqrt(radius * radius - r2);
        const float want = linearDepth(frame, glm::vec3(0, 0, centre.z + z));
        const float sag = radius * (1.0f - std::cos(2.0f * std::numbers::pi_v<float> / kSegments)) * radius / z;
        const float got = depth[at(x, y)];
        EXPECT_GE(got, want - 1e-5f) << x << ", " << y << ": the mesh is inside the sphere";
        EXPECT_LE(got, want + sag / (c.farPlane - c.nearPlane) + 1e-5f) << x << ", " << y;
      }
    }
  }
  const double radiusPx = std::sqrt(count / std::numbers::pi);
  EXPECT_NEAR(radiusPx, radius * pixelsPerUnit, 0.5);
  EXPECT_NEAR(sx / count, centrePx.x, 0.25);
  EXPECT_NEAR(sy / count, centrePx.y, 0.25);
}

TEST_F(OpaqueTest, AmbientGradientIsStretchedOverTheViewport) {
  core::Image image(1, 2, 3);
  const glm::vec3 top{0.9f, 0.6f, 0.2f}, bottom{0.1f, 0.3f, 0.5f};
  for (int c = 0; c < 3; ++c) {
    image.at(0, 0, c) = top[c];
    image.at(0, 1, c) = bottom[c];
  }
  auto gradient = Gradient::create(image, "test gradient");
  ASSERT_OK(gradient);
  Frame frame = topDown();
  frame.ambientGradient = true;
  frame.light.direction = {0, -1, 0};  // ambient only
  begin(frame);
  gradient->bind();
  setObjects({object("ground", makePlane(), glm::mat4(1.0f), kAlbedo)});
  renderer_->draw(ShadePass::kLit);
  const std::vector<glm::vec4> color = target_->readColor();
  // Texel centres sit at a quarter and three quarters of the height: beyond them the colour is flat.
  expectColor(color[at(10, 120)], kAlbedo * top, "top rows", 10, 120);
  expectColor(color[at(100, 5)], kAlbedo * bottom, "bottom rows", 100, 5);
  const float t = (64.5f / kSize - 0.25f) / 0.5f;  // row 64's position between the texel centres
  // Filtering mixes light (docs/colour.md): the display values are decoded, mixed, encoded again.
  const glm::vec3 mixed = core::linearToSrgb(glm::mix(core::srgbToLinear(bottom), core::srgbToLinear(top), t));
  expectColor(color[at(64, 64)], kAlbedo * mixed, "middle row", 64, 64);
}

// The gradient spans the viewport, not the target: on a viewport wider than tall and away from the
// target's origin, each axis of the image runs over its own axis of the viewport. A 2 x 2 image,
// four colours, so that swapping, sharing or dropping either axis's scale or offset shows.
TEST_F(OpaqueTest, AmbientGradientSpansANonSquareViewportAwayFromTheOrigin) {
  const glm::vec3 corner[2][2] = {{{0.9f, 0.6f, 0.2f}, {0.2f, 0.8f, 0.4f}},   // top row: left, right
                                  {{0.1f, 0.3f, 0.5f}, {0.7f, 0.1f, 0.9f}}};  // bottom row
  core::Image image(2, 2, 3);
  for (int row = 0; row < 2; ++row)
    for (int col = 0; col < 2; ++col)
      for (int c = 0; c < 3; ++c) image.at(col, row, c) = corner[row][col][c];
  auto gradient = Gradient::create(image, "test gradient");
  ASSERT_OK(gradient);
  const Viewport vp{16, 40, 96, 48};
  Frame frame = topDown(2.0f, vp.width, vp.height);  // 4 units wide, 2 tall
  frame.viewport = vp;
  frame.ambientGradient = true;
  frame.light.direction = {0, -1, 0};  // ambient only
  begin(frame);
  glViewport(vp.x, vp.y, vp.width, vp.height);
  gradient->bind();
  // The plane, 6 x 6 units, covers the 4 x 2 units the camera sees.
  setObjects({object("ground", makePlane(), glm::scale(glm::mat4(1.0f), glm::vec3(3.0f)), kAlbedo)});
  renderer_->draw(ShadePass::kLit);
  glViewport(0, 0, kSize, kSize);
  const std::vector<glm::vec4> color = target_->readColor();

  // The bilinear lookup at (u, v) in the viewport (v up; the image's top row at v = 1), mixed in
  // linear light (docs/colour.md); texel centres at 1/4 and 3/4 of each axis.
  auto expected = [&](float u, float v) {
    const float s = std::clamp((u - 0.25f) / 0.5f, 0.0f, 1.0f), t = std::clamp((v - 0.25f) / 0.5f, 0.0f, 1.0f);
    auto lin = [&](int row, int col) { return core::srgbToLinear(corner[row][col]); };
    const glm::vec3 bottom = glm::mix(lin(1, 0), lin(1, 1), s), top = glm::mix(lin(0, 0), lin(0, 1), s);
    return kAlbedo * core::linearToSrgb(glm::mix(bottom, top, t));
  };
  for (int py = 1; py < vp.height; py += 5) {
    for (int px = 1; px < vp.width; px += 5) {
      const float u = (px + 0.5f) / vp.width, v = (py + 0.5f) / vp.height;
      expectColor(color[at(vp.x + px, vp.y + py)], expected(u, v), "inside the viewport", vp.x + px, vp.y + py);
    }
  }
  // The flat corners, where the lookup is one texel whatever the filter.
  expectColor(color[at(vp.x + 5, vp.y + 44)], kAlbedo * corner[0][0], "top left", vp.x + 5, vp.y + 44);
  expectColor(color[at(vp.x + 90, vp.y + 44)], kAlbedo * corner[0][1], "top right", vp.x + 90, vp.y + 44);
  expectColor(color[at(vp.x + 5, vp.y + 3)], kAlbedo * corner[1][0], "bottom left", vp.x + 5, vp.y + 3);
  expectColor(color[at(vp.x + 90, vp.y + 3)], kAlbedo * corner[1][1], "bottom right", vp.x + 90, vp.y + 3);
  EXPECT_EQ(color[at(vp.x - 1, vp.y + 10)], Target::kClear) << "left of the viewport";
  EXPECT_EQ(color[at(vp.x + 10, vp.y + vp.height)], Target::kClear) << "above the viewport";
}

TEST_F(OpaqueTest, DrawSetsEveryStateItReliesOn) {
  Frame frame = topDown(2.5f);
  frame.ambient = puff::core::srgbToLinear(kAmbient);
  frame.light.color = puff::core::srgbToLinear(kLightColor);
  setObjects({object("ball", makeSphere(), glm::mat4(1.0f), kAlbedo),
              object("box", makeBox(), glm::scale(glm::mat4(1.0f), glm::vec3(0.3f, 1.1f, 0.3f)), {0.3f, 0.3f, 0.9f})});
  begin(frame);
  renderer_->draw(ShadePass::kLit);
  const std::vector<glm::vec4> clean = target_->readColor();
  const std::vector<float> cleanDepth = target_->readDepth();

  begin(frame);
  // What a careless host or pass might leave behind.
  glEnable(GL_BLEND);
  glBlendFunc(GL_ZERO, GL_ONE);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_FRONT_AND_BACK);
  glFrontFace(GL_CW);
  glDepthFunc(GL_NEVER);
  glDepthMask(GL_FALSE);
  glColorMask(GL_FALSE, GL_TRUE, GL_FALSE, GL_FALSE);
  glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_NEVER, 0, 0xFF);
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 0, 1, 1);
  glEnable(GL_DEPTH_CLAMP);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(4.0f, 4.0f);
  renderer_->draw(ShadePass::kLit);
  EXPECT_EQ(target_->readColor(), clean);
  EXPECT_EQ(target_->readDepth(), cleanDepth);
  // Put back what this test changed and draw() does not reset, for the next test on the context.
  glBlendFunc(GL_ONE, GL_ZERO);
  glCullFace(GL_BACK);
  glDepthFunc(GL_LESS);
  glStencilFunc(GL_ALWAYS, 0, 0xFF);
  glPolygonOffset(0.0f, 0.0f);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_DEPTH_TEST);
}

TEST_F(OpaqueTest, SharedMeshDrawsEveryObject) {
  Frame frame = topDown(4.0f);
  frame.ambient = puff::core::srgbToLinear(kAmbient);
  frame.light.color = puff::core::srgbToLinear(kLightColor);
  frame.light.direction = {0, 1, 0};
  begin(frame);
  auto mesh = std::make_shared<const TriangleMesh>(makeBox());
  std::vector<OpaqueObject> objects;
  const glm::vec3 albedos[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 3; ++i) {
    OpaqueObject o;
    o.name = "box " + std::to_string(i);
    o.mesh = mesh;
    o.transform = glm::translate(glm::mat4(1.0f), glm::vec3(-1.2f + 1.2f * i, 0, 0)) *
                  glm::scale(glm::mat4(1.0f), glm::vec3(0.4f));
    o.albedo = puff::core::srgbToLinear(albedos[i]);
    objects.push_back(o);
  }
  objects.push_back(
      object("sphere", makeSphere(),
             glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 1.2f)) * glm::scale(glm::mat4(1.0f), glm::vec3(0.4f)),
             {1, 1, 0}));
  setObjects(std::move(objects));
  renderer_->draw(ShadePass::kLit);
  const std::vector<glm::vec4> color = target_->readColor();
  // 32 pixels per unit, x right, world z down the image (camera up is -z).
  for (int i = 0; i < 3; ++i) {
    const int x = 64 + static_cast<int>((-1.2f + 1.2f * i) * 32.0f);
    expectColor(color[at(x, 64)], albedos[i] * (kAmbient + kLightColor), "box top", x, 64);
  }
  expectColor(color[at(64, 64 - 38)], glm::vec3(1, 1, 0) * (kAmbient + kLightColor), "sphere top", 64, 26);
}

TEST_F(OpaqueTest, SetObjectsRejectsBadInputNamingTheObject) {
  const glm::mat4 one(1.0f);
  struct Case {
    std::string name;
    TriangleMesh mesh;
    glm::mat4 transform;
    glm::vec3 albedo;
    std::string problem;
  };
  TriangleMesh badIndex = makePlane();
  badIndex.indices[4] = 4;
  TriangleMesh nanPosition = makeBox();
  nanPosition.positions[7].y = std::numeric_limits<float>::quiet_NaN();
  TriangleMesh fewNormals = makePlane();
  fewNormals.normals.pop_back();
  TriangleMesh ragged = makePlane();
  ragged.indices.pop_back();
  TriangleMesh zeroNormal = makePlane();
  zeroNormal.normals[2] = glm::vec3(0.0f);
  glm::mat4 nanTransform(1.0f);
  nanTransform[3][1] = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Case> cases = {
      {"empty thing", TriangleMesh{}, one, kAlbedo, "no triangles"},
      {"bad index", badIndex, one, kAlbedo, "out of range"},
      {"nan position", nanPosition, one, kAlbedo, "position 7 is not finite"},
      {"few normals", fewNormals, one, kAlbedo, "3 normals for 4 positions"},
      {"ragged", ragged, one, kAlbedo, "not a multiple of 3"},
      {"zero normal", zeroNormal, one, kAlbedo, "normal 2 is zero"},
      {"far away", makePlane(), nanTransform, kAlbedo, "transform is not finite"},
      {"flat", makeBox(), glm::scale(one, glm::vec3(1, 0, 1)), kAlbedo, "singular"},
      {"grey", makeBox(), one, glm::vec3(0.5f, nan, 0.5f), "albedo is not finite"},
      {"dark", makeBox(), one, glm::vec3(0.5f, -0.1f, 0.5f), "albedo is negative"},
  };
  Frame frame = topDown();
  frame.light.direction = {0, 1, 0};
  setObjects({object("ground", makePlane(), one, kAlbedo)});
  for (const Case& k : cases) {
    SCOPED_TRACE(k.name);
    std::vector<OpaqueObject> objects = {object("fine", makeSphere(8), one, kAlbedo),
                                         object(k.name, k.mesh, k.transform, k.albedo)};
    auto r = renderer_->setObjects(std::move(objects));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("'" + k.name + "'"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find(k.problem), std::string::npos) << r.error().message;
  }
  OpaqueObject noMesh;
  noMesh.name = "ghost";
  auto r = renderer_->setObjects({noMesh});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, "opaque object 'ghost': has no mesh");
  OpaqueObject unnamed = object("", TriangleMesh{}, one, kAlbedo);
  r = renderer_->setObjects({object("a", makePlane(), one, kAlbedo), unnamed});
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("opaque object #1"), std::string::npos) << r.error().message;

  // A rejected set leaves the previous one in place.
  begin(frame);
  renderer_->draw(ShadePass::kLit);
  expectColor(target_->readColor()[at(64, 64)], kAlbedo * (glm::vec3(0.25f) + glm::vec3(1.0f)), "previous set", 64, 64);
}

}  // namespace
}  // namespace puff::cel
