// The tumbling hull's occluders (cel::HullOcclusion::kCores): each hull-drawn puff's
// core drawn as a disc into Puff's own target before the hull, so that the hull's fragments behind
// another puff's core skip their march. A sphere puff's core is the sphere less a few grid steps of
// its field, its disc centred where the puff is drawn at the depth of its centre; and dropping the
// fragments behind the discs changes no pixel and no depth, whatever the camera, the viewport and the
// shade pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/core/atlas.h>
#include <puff/core/colour.h>
#include <puff/gl_api.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/gl_target.h"
#include "support/linear_frame.h"
#include "support/sphere_bake.h"
#include "support/temp_dir.h"

namespace puff {
namespace {

constexpr int kPx = 128;          // the target's side
constexpr float kWorld = 8.0f;    // the orthographic view's height: 16 px a unit
constexpr float kNoDisc = 1e38f;  // above this, the occluder target holds no disc

// A 4 x 4-view bake of the sphere, for oriented puffs drawn by the hull.
class HullOccluders : public test::GlTest {
 protected:
  static void SetUpTestSuite() {
    GlTest::SetUpTestSuite();
    dir_.emplace("puff_hull_occluders");
    auto sidecar = test::bakeSphereAtlas(dir_->path(), 4);
    ASSERT_OK(sidecar);
    auto atlas = core::loadAtlas(*sidecar);
    ASSERT_OK(atlas);
    atlas_ = std::make_unique<core::Atlas>(std::move(*atlas));
  }
  static void TearDownTestSuite() {
    atlas_.reset();
    dir_.reset();
    GlTest::TearDownTestSuite();
  }
  void SetUp() override {
    GlTest::SetUp();
    ASSERT_NE(atlas_, nullptr);
    auto r = cel::NailboardRenderer::create();
    ASSERT_OK(r);
    renderer_ = std::move(*r);
    ASSERT_OK(renderer_->setAtlas(*atlas_));
    block_ = std::make_unique<cel::FrameBlock>();
    target_ = std::make_unique<test::OffscreenTarget>(kPx);
    ramp_ = std::make_unique<cel::Ramp>(cel::Ramp::twoTone());
  }
  void TearDown() override {
    renderer_.reset();
    block_.reset();
    target_.reset();
    ramp_.reset();
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    GlTest::TearDown();
  }

  static cel::Frame frame(bool perspective, const cel::Viewport& viewport) {
    cel::Camera cam;
    cam.position = glm::vec3(0, 0, 10);
    cam.target = glm::vec3(0);
    cam.fovYDegrees = perspective ? 50.0f : 0.0f;
    cam.orthoHeight = kWorld;
    cam.nearPlane = 1.0f;
    cam.farPlane = 21.0f;
    cel::Frame f = test::linearFrame(cam, viewport.width, viewport.height);
    f.viewport = viewport;
    f.light.direction = glm::vec3(0.3f, 0.8f, 0.5f);
    f.light.color = core::srgbToLinear(glm::vec3(0.6f));
    f.ambient = core::srgbToLinear(glm::vec3(0.2f));
    return f;
  }

  // Draws `ps` (the hull on all) in one pass and reads the target back.
  void draw(const cel::Frame& f, const std::vector<cel::Particle>& ps, cel::ShadePass pass, bool occluders,
            bool upperLeft, std::vector<glm::vec4>& color, std::vector<float>& depth) {
    draw(f, ps, pass, occluders ? cel::HullOcclusion::kCores : cel::HullOcclusion::kNone, upperLeft, color, depth);
  }
  void draw(const cel::Frame& f, const std::vector<cel::Particle>& ps, cel::ShadePass pass,
            cel::HullOcclusion occlusion, bool upperLeft, std::vector<glm::vec4>& color, std::vector<float>& depth) {
    cel::Style style;
    style.tumble = cel::TumbleMethod::kHull;
    target_->clear(glm::vec4(0.9f, 0.95f, 1.0f, 1.0f), 1.0f);
    if (upperLeft) glClipControl(GL_UPPER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glViewport(f.viewport.x, f.viewport.y, f.viewport.width, f.viewport.height);
    EXPECT_OK(block_->upload(f));
    ramp_->bind();
    renderer_->upload(ps);
    renderer_->setHullOcclusion(occlusion);
    renderer_->drawNailboards(style, pass);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    color = target_->readColor();
    depth = target_->readDepth();
  }

  // The occluder target as the last pass left it on unit `visibility` (its pixels, row by row, and
  // its width).
  static std::vector<float> occluderTexels(int& width) {
    GLint texture = 0;
    glActiveTexture(GL_TEXTURE0 + cel::Bindings{}.visibility);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &texture);
    glActiveTexture(GL_TEXTURE0);
    width = 0;
    if (texture == 0) return {};
    GLint height = 0;
    glGetTextureLevelParameteriv(static_cast<GLuint>(texture), 0, GL_TEXTURE_WIDTH, &width);
    glGetTextureLevelParameteriv(static_cast<GLuint>(texture), 0, GL_TEXTURE_HEIGHT, &height);
    std::vector<float> texels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    glGetTextureImage(static_cast<GLuint>(texture), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(texels.size() * 4),
                      texels.data());
    return texels;
  }

  static inline std::optional<test::ScopedTempDir> dir_;
  static inline std::unique_ptr<core::Atlas> atlas_;
  std::unique_ptr<cel::NailboardRenderer> renderer_;
  std::unique_ptr<cel::FrameBlock> block_;
  std::unique_ptr<test::OffscreenTarget> target_;
  std::unique_ptr<cel::Ramp> ramp_;
};

// 60 oriented spheres from a fixed-seed LCG, overlapping (stacked several deep at the centre), turned
// every way, some past the viewport's edges.
std::vector<cel::Particle> spheres() {
  std::uint32_t state = 2024u;
  auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
  };
  std::vector<cel::Particle> ps;
  for (int i = 0; i < 60; ++i) {
    cel::Particle p;
    p.position = glm::vec3(-4.5f + 9.0f * next(), -4.5f + 9.0f * next(), -3.0f + 6.0f * next());
    p.size = 1.0f + 2.0f * next();
    p.oriented = true;
    p.orientation = glm::angleAxis(6.2832f * next(), glm::normalize(glm::vec3(next() - 0.5f, next() - 0.5f, 0.3f)));
    ps.push_back(p);
  }
  return ps;
}

// One sphere 64 px across at the centre, turned: its core is the sphere less the grid steps of its
// field the core keeps clear of (sqrt 3 of them, and one for where the deepest grid point lies), its
// disc that less a pixel and a half, centred on the puff, at the view depth of the sphere's centre
// within a grid step.
TEST_F(HullOccluders, ASpheresDiscIsItsCoreLessAPixelAndAHalfAtItsCentresDepth) {
  const float diameter = 64.0f, size = diameter / 16.0f;
  cel::Particle p;
  p.size = size;
  p.oriented = true;
  p.orientation = glm::angleAxis(0.9f, glm::normalize(glm::vec3(1, 2, 0.5f)));
  std::vector<glm::vec4> color;
  std::vector<float> depth;
  draw(frame(false, {0, 0, kPx, kPx}), {p}, cel::ShadePass::kLit, true, false, color, depth);
  int width = 0;
  const std::vector<float> texels = occluderTexels(width);
  ASSERT_GE(width, kPx);
  const float voxel = 1.0f / static_cast<float>(core::hullFieldLayout(atlas_->desc).side);
  const float outer = 0.5f * diameter - 1.5f, inner = (0.5f - (std::sqrt(3.0f) + 2.0f) * voxel) * diameter - 1.5f;
  int inside = 0, wrongDepth = 0, outsideInner = 0, pastOuter = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const float r = std::hypot(x + 0.5f - kPx / 2.0f, y + 0.5f - kPx / 2.0f);
      const float v = texels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + x];
      const bool disc = v < kNoDisc;
      if (r < inner - 0.75f) {
        inside += disc ? 1 : 0;
        outsideInner += disc ? 0 : 1;
        if (disc && std::abs(v - 10.0f) > voxel * size + 1e-4f) ++wrongDepth;
      }
      if (r > outer + 0.75f && disc) ++pastOuter;
    }
  }
  EXPECT_GT(inside, 0);
  EXPECT_EQ(outsideInner, 0) << "pixels within " << inner << " px of the centre with no disc";
  EXPECT_EQ(pastOuter, 0) << "disc pixels farther than " << outer << " px from the centre";
  EXPECT_EQ(wrongDepth, 0) << "disc pixels not at the centre's depth, 10";
}

// Dropping the fragments behind the discs: the same colour and depth at every pixel as marching every
// fragment, in each shade pass, orthographic and perspective, at an offset viewport and with the clip
// origin at the upper left; where the discs hide a good share of the spheres.
TEST_F(HullOccluders, DroppingHiddenFragmentsChangesNoPixel) {
  struct Setting {
    const char* name;
    bool perspective;
    cel::Viewport viewport;
    bool upperLeft;
  };
  const Setting settings[] = {{"orthographic", false, {0, 0, kPx, kPx}, false},
                              {"perspective, offset viewport", true, {16, 24, 96, 80}, false},
                              {"perspective, clip origin upper left", true, {0, 0, kPx, kPx}, true}};
  const std::vector<cel::Particle> ps = spheres();
  for (const Setting& s : settings) {
    for (const cel::ShadePass pass : {cel::ShadePass::kLit, cel::ShadePass::kDepthOnly}) {
      SCOPED_TRACE(std::string(s.name) + (pass == cel::ShadePass::kLit ? ", lit" : ", depth only"));
      const cel::Frame f = frame(s.perspective, s.viewport);
      std::vector<glm::vec4> colorOn, colorOff;
      std::vector<float> depthOn, depthOff;
      draw(f, ps, pass, true, s.upperLeft, colorOn, depthOn);
      int width = 0;
      const std::vector<float> texels = occluderTexels(width);
      draw(f, ps, pass, false, s.upperLeft, colorOff, depthOff);
      ASSERT_EQ(colorOn.size(), colorOff.size());
      int covered = 0, discs = 0, differ = 0;
      for (int y = 0; y < kPx; ++y) {
        for (int x = 0; x < kPx; ++x) {
          const std::size_t i = static_cast<std::size_t>(y) * kPx + static_cast<std::size_t>(x);
          covered += depthOff[i] < 1.0f ? 1 : 0;
          discs += texels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + x] < kNoDisc ? 1 : 0;
          differ += colorOn[i] != colorOff[i] || depthOn[i] != depthOff[i] ? 1 : 0;
        }
      }
      EXPECT_GT(covered, s.viewport.width * s.viewport.height / 2);
      EXPECT_GT(discs, covered / 3) << "the discs cover " << discs << " of " << covered << " covered pixels";
      EXPECT_EQ(differ, 0) << "of " << covered << " covered pixels";
    }
  }
}

// kAuto draws the occluders where the quads stack (kOccludersMinOverdraw: the spheres, about twice
// over their rectangle) and not for one puff alone (nothing for a core to hide).
TEST_F(HullOccluders, TheRendererDrawsThemWhereThePuffsStack) {
  cel::Particle one;
  one.size = 4.0f;
  one.oriented = true;
  const cel::Frame f = frame(false, {0, 0, kPx, kPx});
  for (const bool stacked : {true, false}) {
    SCOPED_TRACE(stacked ? "60 spheres" : "one sphere");
    glBindTextureUnit(cel::Bindings{}.visibility, 0);
    std::vector<glm::vec4> color;
    std::vector<float> depth;
    draw(f, stacked ? spheres() : std::vector<cel::Particle>{one}, cel::ShadePass::kLit, cel::HullOcclusion::kAuto,
         false, color, depth);
    int width = 0;
    const std::vector<float> texels = occluderTexels(width);
    EXPECT_EQ(!texels.empty(), stacked);
  }
}

}  // namespace
}  // namespace puff
