// Steady pictures.
//   SteadyPacking  the 16-byte record's positions lie on a world-fixed grid: a still particle keeps
//                  its exact bits while the rest of its batch moves, and the round trip stays within
//                  the documented bound (half a power-of-two step < extent / 65534) at any distance
//                  from the origin, 10 km included.
//   SteadyImage    a still puff drawn beside a crowd that moves every frame keeps every pixel.
//   SteadyRamp     the fixed path's bands change where the cel path's do (N.L = k / W for a W-texel
//                  ramp sampled nearest), within 1/512, for ramps 3, 5 and 300 texels wide.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <puff/gl_api.h>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/core/gl.h>
#include <puff/core/random.h>
#include <puff/fixedfunc/renderer.h>
#include <puff/mesh/mesh.h>
#include <puff/platform/gl_context.h>

#include "support/assert_ok.h"
#include "support/gl_target.h"
#include "support/linear_frame.h"
#include "support/skip.h"
#include "support/sphere_atlas.h"

namespace puff {
namespace {

using cel::Particle;

// The bound nailboards.h documents, from the extent alone: step / 2 < max(extent / 65534, 2^-24).
double errorBound(double extent) { return std::max(extent / 65534.0, 0x1.0p-24); }

// Exactness of a float, bit for bit (EXPECT_EQ on floats would take -0 for +0).
std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }

// A crowd inside the box centre +- half, with one member at each of two opposite corners so the
// box is the crowd's: its extent per axis is 2 * half.
std::vector<Particle> crowd(core::SplitMix64& rng, glm::dvec3 centre, glm::dvec3 half, int n) {
  std::vector<Particle> ps;
  for (int i = 0; i < n; ++i) {
    const double uz = rng.unit(), uy = rng.unit(), ux = rng.unit();  // one draw a statement, z first
    glm::dvec3 u(ux, uy, uz);
    if (i == 0) u = glm::dvec3(0.0);
    if (i == 1) u = glm::dvec3(1.0);
    Particle p;
    p.position = glm::vec3(centre + (2.0 * u - 1.0) * half);
    p.size = 1.0f;
    ps.push_back(p);
  }
  return ps;
}

// ---- packing (no GL) ---------------------------------------------------------------------------

// A still particle among a crowd that moves (every member, the corners too, by up to 1% of the
// extent): its unpacked position is the same float bits in both batches, and the grid's step is
// the same. The extents are drawn from [0.6, 0.9] x 65534 x 2^j, inside one power-of-two bracket
// before and after the move, over scales from millimetres to kilometres and origins out to 10 km.
TEST(SteadyPacking, AStillParticleKeepsItsBitsWhileTheCrowdMoves) {
  core::SplitMix64 rng(core::mix64(22007));
  int checked = 0, moved = 0;
  for (int sweep = 0; sweep < 200; ++sweep) {
    const int j = -20 + static_cast<int>(rng.unit() * 30.0);  // steps 2^-20 .. 2^9: extents 6 cm .. 33 km
    const double bracket = 65534.0 * std::ldexp(1.0, j);
    const double hz = rng.unit(), hy = rng.unit(), hx = rng.unit();  // one draw a statement, z first
    const glm::dvec3 half = 0.5 * bracket * (0.6 + 0.3 * glm::dvec3(hx, hy, hz));
    const double far = (sweep % 4 == 0) ? 10000.0 : (sweep % 4 == 1 ? -3.5 : 0.0);
    const double cz = rng.unit(), cx = rng.unit();  // one draw a statement, z first
    const glm::dvec3 centre(far + 100.0 * cx, -far * 0.5, far * 0.25 + cz);
    std::vector<Particle> before = crowd(rng, centre, half, 64);
    std::vector<Particle> after = before;
    for (Particle& p : after) {
      const double dz = rng.unit(), dy = rng.unit(), dx = rng.unit();  // one draw a statement, z first
      const glm::dvec3 d(dx - 0.5, dy - 0.5, dz - 0.5);
      p.position = glm::vec3(glm::dvec3(p.position) + 0.02 * d * half);
    }
    // The still one, anywhere inside the box (kept 2% in from its faces, so it stays inside).
    Particle still;
    const double uz = rng.unit(), uy = rng.unit(), ux = rng.unit();  // one draw a statement, z first
    const glm::dvec3 u(ux, uy, uz);
    still.position = glm::vec3(centre + (2.0 * u - 1.0) * 0.98 * half);
    const std::size_t at = static_cast<std::size_t>(rng.unit() * 64.0);
    before.insert(before.begin() + static_cast<std::ptrdiff_t>(at), still);
    after.insert(after.begin() + static_cast<std::ptrdiff_t>(at), still);

    std::vector<cel::PackedParticle> packedBefore, packedAfter;
    const cel::PackBounds b0 = cel::packParticles(before, packedBefore);
    const cel::PackBounds b1 = cel::packParticles(after, packedAfter);
    const Particle out0 = cel::unpackParticle(packedBefore[at], b0);
    const Particle out1 = cel::unpackParticle(packedAfter[at], b1);
    SCOPED_TRACE("sweep " + std::to_string(sweep) + ", step 2^" + std::to_string(j));
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(bits(b0.step[a]), bits(b1.step[a])) << "axis " << a;
      EXPECT_EQ(bits(out0.position[a]), bits(out1.position[a])) << "axis " << a;
      moved += bits(b0.min[a]) != bits(b1.min[a]) ? 1 : 0;  // the origin did move with the crowd
    }
    ++checked;
  }
  std::printf("%d batches; the grid's origin moved on %d of %d axes\n", checked, moved, 3 * checked);
  EXPECT_GT(moved, checked);  // the test moves the box, not just its inside
}

// The round trip: every drawn position within errorBound(extent) of where it was, per axis, over
// extents from nothing to 20 km and origins out to +-10 km; and the step is the documented one (a
// power of two, extent <= 65534 steps, and no smaller power of two would do, down to 2^-24).
TEST(SteadyPacking, RoundTripWithinTheDocumentedBoundAtAnyDistance) {
  core::SplitMix64 rng(core::mix64(2207));
  double worst = 0.0;  // in units of the extent
  for (double extent : {0.0, 1e-6, 1e-3, 0.37, 1.0, 10.0, 1000.0, 4095.9, 20000.0}) {
    for (double origin : {0.0, -3.7, 123.456, 10000.0, -10000.0, 9999.5}) {
      SCOPED_TRACE("extent " + std::to_string(extent) + " origin " + std::to_string(origin));
      std::vector<Particle> ps =
          crowd(rng, glm::dvec3(origin, -0.5 * origin, origin + 1.0), glm::dvec3(0.5 * extent), 300);
      std::vector<cel::PackedParticle> packed;
      const cel::PackBounds b = cel::packParticles(ps, packed);
      for (int a = 0; a < 3; ++a) {
        // The extent the packer saw: the corners as floats.
        const double e = static_cast<double>(ps[1].position[a]) - static_cast<double>(ps[0].position[a]);
        const double step = b.step[a];
        int exponent = 0;
        EXPECT_EQ(std::frexp(step, &exponent), 0.5) << "a power of two";
        EXPECT_LE(e, 65534.0 * step);
        if (step > 0x1.0p-24) {
          EXPECT_GT(e, 65534.0 * step / 2.0) << "a finer step would do";
        }
        EXPECT_EQ(std::fmod(static_cast<double>(b.min[a]), step), 0.0) << "the origin is a grid point";
      }
      for (std::size_t i = 0; i < ps.size(); ++i) {
        const Particle out = cel::unpackParticle(packed[i], b);
        for (int a = 0; a < 3; ++a) {
          const double e = static_cast<double>(ps[1].position[a]) - static_cast<double>(ps[0].position[a]);
          const double err = std::abs(static_cast<double>(out.position[a]) - static_cast<double>(ps[i].position[a]));
          ASSERT_LE(err, errorBound(e)) << "particle " << i << " axis " << a;
          ASSERT_LE(err, 0.5 * b.step[a]) << "particle " << i << " axis " << a;
          if (e > 0.01) worst = std::max(worst, err / e);
        }
      }
    }
  }
  std::printf("worst round-trip error: %.3g of the extent (bound 1/65534 = %.3g)\n", worst, 1.0 / 65534.0);
}

// A position that is not finite, or beyond 2^125, is not drawn and does not widen the grid: the
// others pack exactly as they do without it.
TEST(SteadyPacking, AnUndrawablePositionNeitherDrawsNorWidensTheGrid) {
  const std::vector<Particle> good = {Particle{glm::vec3(-1.25f, 0.5f, 3.0f), 1.5f},
                                      Particle{glm::vec3(2.0f, -0.75f, 3.5f), 1.0f}};
  std::vector<cel::PackedParticle> reference;
  const cel::PackBounds rb = cel::packParticles(good, reference);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (const glm::vec3 bad : {glm::vec3(inf, 0, 0), glm::vec3(0, -inf, 0), glm::vec3(0, 0, nan),
                              glm::vec3(0x1.0p126f, 0, 0), glm::vec3(0, -3e38f, 0)}) {
    std::vector<Particle> ps = good;
    ps.insert(ps.begin(), Particle{bad, 2.0f});
    std::vector<cel::PackedParticle> packed;
    const cel::PackBounds b = cel::packParticles(ps, packed);
    EXPECT_EQ(cel::unpackParticle(packed[0], b).size, 0.0f);
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(bits(b.min[a]), bits(rb.min[a]));
      EXPECT_EQ(bits(b.step[a]), bits(rb.step[a]));
    }
    for (std::size_t i = 0; i < good.size(); ++i) {
      EXPECT_EQ(packed[i + 1].x, reference[i].x);
      EXPECT_EQ(packed[i + 1].y, reference[i].y);
    }
  }
}

// ---- image: a still puff beside a moving crowd -------------------------------------------------

class SteadyImage : public test::SphereAtlasTest {
 protected:
  static constexpr int kPx = 160;
  static void SetUpTestSuite() { setUpSphereAtlas(true); }
};

// A large batch, as a game's: a still puff on the left of the picture, a few crowd puffs on the
// right and the rest of the crowd off screen, spread over 1200 x 600 x 22 world units. Every crowd
// puff moves a little each frame (up to 0.1 units over the run), so the crowd's box moves. The
// still puff's pixels (the left 40% of the picture, which no crowd puff reaches) are the same in
// every frame as when it is drawn alone: the GPU puts it where the CPU's unpackParticle does, on
// a grid the crowd does not move. With the box-fitted grid this replaced, frames differ there.
TEST_F(SteadyImage, AStillPuffKeepsItsPixelsUnderAMovingCrowd) {
  auto r = cel::NailboardRenderer::create();
  ASSERT_OK(r);
  cel::NailboardRenderer& renderer = **r;
  ASSERT_OK(renderer.setAtlas(*atlas_));
  cel::FrameBlock block;
  const cel::Ramp ramp = cel::Ramp::twoTone();
  test::OffscreenTarget target(kPx);
  cel::Camera cam;
  cam.position = glm::vec3(0, 0, 10);
  cam.target = glm::vec3(0);
  cam.fovYDegrees = 40.0f;
  const cel::Frame frame = test::linearFrame(cam, kPx, kPx);
  const cel::Style style;

  auto draw = [&](const std::vector<Particle>& ps) {
    target.clear(glm::vec4(1.0f), 1.0f);
    EXPECT_OK(block.upload(frame));
    ramp.bind();
    renderer.upload(ps);
    renderer.drawNailboards(style, cel::ShadePass::kLit);
    EXPECT_EQ(core::drainGlErrors(), "");
    return target.readColor();
  };
  const int split = kPx * 2 / 5;  // columns left of this: the still puff's side
  auto region = [&](const std::vector<glm::vec4>& px, bool left, const std::vector<glm::vec4>& other) {
    int differing = 0;
    for (int y = 0; y < kPx; ++y) {
      for (int x = left ? 0 : split; x < (left ? split : kPx); ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * kPx + x;
        differing += px[i] != other[i] ? 1 : 0;
      }
    }
    return differing;
  };

  // The still puff at a position with few bits, so its grid point is itself on every grid here.
  const Particle still{glm::vec3(-2.25f, 0.5f, 0.0f), 1.5f, 0};
  const std::vector<glm::vec4> alone = draw({still});
  const std::vector<glm::vec4> blank = draw({});
  const int stillPixels = region(alone, true, blank);
  ASSERT_GT(stillPixels, 500) << "the still puff is drawn";

  // The crowd: 6 on screen at x in [1, 3], the rest off screen (|x| >= 60 or |y| >= 60), with the
  // box's corners at (+-600, +-300, -20 / 2): extents 1200, 600, 22 sit inside the brackets
  // (1024, 2048], (512, 1024], (16, 32] however the crowd moves here.
  core::SplitMix64 rng(core::mix64(7));
  std::vector<Particle> base;
  std::vector<glm::vec3> velocity;
  auto add = [&](glm::vec3 p) {
    base.push_back(Particle{p, 0.8f + 0.4f * rng.uniform(), static_cast<int>(rng.next() % 4)});
    const float vz = rng.uniform(), vy = rng.uniform(), vx = rng.uniform();  // one draw a statement, z first
    velocity.push_back(0.0125f * (glm::vec3(vx, vy, vz) - 0.5f));
  };
  add({-600.0f, -300.0f, -20.0f});
  add({600.0f, 300.0f, 2.0f});
  for (int i = 0; i < 6; ++i) add({1.0f + 0.4f * i, -2.0f + 0.8f * i, -0.5f * rng.uniform()});
  for (int i = 0; i < 400; ++i) {
    const float side = rng.uniform() < 0.5f ? -1.0f : 1.0f;
    const float along = 60.0f + 500.0f * rng.uniform(), across = 590.0f * (2.0f * rng.uniform() - 1.0f);
    const float z = -19.0f + 20.0f * rng.uniform();
    add(i % 2 ? glm::vec3(side * along, across * 0.5f, z) : glm::vec3(across, side * std::min(along, 290.0f), z));
  }

  std::vector<glm::vec4> first;
  int crowdChanged = 0;
  for (int f = 0; f < 8; ++f) {
    std::vector<Particle> ps = base;
    for (std::size_t i = 0; i < ps.size(); ++i) ps[i].position += static_cast<float>(f) * velocity[i];
    ps.insert(ps.begin() + 3, still);  // among them, not first or last
    const std::vector<glm::vec4> px = draw(ps);
    const int differing = region(px, true, alone);
    std::printf("frame %d: %d of the still puff's side's pixels differ from it drawn alone\n", f, differing);
    EXPECT_EQ(differing, 0) << "frame " << f;
    if (f == 0) {
      first = px;
      EXPECT_GT(region(px, false, blank), 300) << "the crowd's on-screen puffs are drawn";
    } else {
      crowdChanged += region(px, false, first) > 0 ? 1 : 0;
    }
  }
  EXPECT_EQ(crowdChanged, 7) << "the crowd moved on screen every frame";
}

// ---- the fixed path's ramp against the cel path's bands --------------------------------------

// A W-texel ramp sampled nearest with clamp to edge, as puff::cel::Ramp is (frame.cpp), shows
// texel floor(W s) at s = N.L: its tone changes at s = k / W wherever texels k - 1 and k differ.
// The fixed path draws a quad facing the camera through an orthographic projection whose vertex
// normals give N.L = s0 on its left edge and 1 on its right edge, covering the whole 1024-pixel-
// wide viewport. The texture coordinate s = N.L is interpolated linearly across the quad, so pixel
// column c sees s0 + (1 - s0)(c + 1/2) / 1024; each change of tone between two columns is an edge
// at the midpoint (within half a column, 0.0005). The edges are those of the closed form, in order,
// with the same tones either side, each within 1/512 (half a texel of the 256-texel resample).
class SteadyRamp : public ::testing::Test {
 protected:
  static constexpr int kWidth = 1024, kHeight = 16;  // cell size 8: the viewport needs 16 x 16
  static constexpr float kS0 = -0.02f;

  static void SetUpTestSuite() {
    core::GlContextOptions o;
    o.backend = "osmesa";  // a default framebuffer with alpha, as the fixed path needs
    o.profile = core::GlProfile::kCompatibility;
    o.major = 2;
    o.minor = 1;
    o.width = kWidth;
    o.height = kHeight;
    auto c = core::createGlContext(o);
    if (c)
      context_ = std::move(*c);
    else
      skipReason_ = c.error().message;
  }
  static void TearDownTestSuite() { context_.reset(); }
  void SetUp() override {
    if (!context_) PUFF_SKIP_UNLESS_CI("no OSMesa compatibility context: " << skipReason_);
    context_->makeCurrent();
  }

  // Tones (display values, multiples of 1/255) of the ramp's middle row per texel; the other rows
  // are 0, which the cel path never reads.
  static core::Image rampImage(const std::vector<float>& tones, int height) {
    core::Image image(static_cast<int>(tones.size()), height, 1);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < image.width; ++x)
        image.at(x, y) = y == height / 2 ? tones[static_cast<std::size_t>(x)] : 0.0f;
    }
    return image;
  }

  // Draws the quad through the fixed path with `ramp` and returns row kHeight / 2's grey per column.
  static std::vector<float> drawnTones(const core::Image& ramp) {
    mesh::TriMesh quad;
    const float nx = -std::sqrt(1.0f - kS0 * kS0);
    quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    quad.normals = {{nx, 0, kS0}, {0, 0, 1}, {0, 0, 1}, {nx, 0, kS0}};
    quad.triangles = {{0, 1, 2}, {0, 2, 3}};
    auto r = fixedfunc::FixedRenderer::create(mesh::makeSphere(8), 8);
    EXPECT_OK(r);
    if (!r.ok()) return {};
    EXPECT_OK((*r)->setRamp(ramp));
    fixedfunc::FixedObject object{quad, glm::translate(glm::mat4(1.0f), {0, 0, -1}), glm::vec3(1.0f),
                                  fixedfunc::ObjectShading::kCel};
    EXPECT_OK((*r)->setObjects({object}));
    fixedfunc::FixedFrame frame;
    frame.view = glm::mat4(1.0f);
    frame.projection = glm::ortho(-1.0f, 1.0f, -1.0f, 1.0f, 0.5f, 2.0f);
    frame.viewport = {0, 0, kWidth, kHeight};
    frame.lightDirection = {0, 0, 1};  // toward the camera: N.L = N.z
    frame.lightColor = glm::vec3(1.0f);
    frame.ambientColor = glm::vec3(0.0f);  // the pixel is q(N.L)
    fixedfunc::FixedStyle style;
    style.outlines = false;
    EXPECT_OK((*r)->drawFrame(frame, {}, style));
    std::vector<glm::vec4> row(kWidth);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, kHeight / 2, kWidth, 1, GL_RGBA, GL_FLOAT, row.data());
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    std::vector<float> grey;
    for (const glm::vec4& c : row) grey.push_back(c.r);
    return grey;
  }

  static inline std::unique_ptr<core::GlContext> context_;
  static inline std::string skipReason_;

  static void expectCelBands(const std::vector<float>& tones, int height) {
    const int w = static_cast<int>(tones.size());
    SCOPED_TRACE(std::to_string(w) + " texels");
    auto nearestTone = [&](float v) {
      float best = tones[0];
      for (float t : tones) best = std::abs(t - v) < std::abs(best - v) ? t : best;
      return best;
    };
    struct Edge {
      double s;
      float below, above;
    };
    // The closed form: edges at k / W inside the drawn range.
    std::vector<Edge> expected;
    for (int k = 1; k < w; ++k) {
      if (tones[static_cast<std::size_t>(k - 1)] != tones[static_cast<std::size_t>(k)]) {
        expected.push_back(
            {static_cast<double>(k) / w, tones[static_cast<std::size_t>(k - 1)], tones[static_cast<std::size_t>(k)]});
      }
    }
    const std::vector<float> grey = drawnTones(rampImage(tones, height));
    ASSERT_EQ(grey.size(), static_cast<std::size_t>(kWidth));
    auto sAt = [](double c) { return kS0 + (1.0 - kS0) * (c + 0.5) / kWidth; };
    std::vector<Edge> measured;
    for (int c = 1; c < kWidth; ++c) {
      const float a = nearestTone(grey[static_cast<std::size_t>(c - 1)]),
                  b = nearestTone(grey[static_cast<std::size_t>(c)]);
      ASSERT_NEAR(grey[static_cast<std::size_t>(c)], b, 1.5f / 255.0f) << "column " << c << " is a ramp tone";
      if (a != b) measured.push_back({sAt(c - 0.5), a, b});
    }
    ASSERT_EQ(measured.size(), expected.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      EXPECT_EQ(measured[i].below, expected[i].below) << "edge " << i;
      EXPECT_EQ(measured[i].above, expected[i].above) << "edge " << i;
      // Resampled nearest at texel centres, an edge moves at most half a texel of the 256: 1/512
      // (measured: 0.00171 at worst). Read at texel edges it moves up to a whole texel.
      EXPECT_NEAR(measured[i].s, expected[i].s, 1.0 / 512.0) << "edge " << i;
      worst = std::max(worst, std::abs(measured[i].s - expected[i].s));
    }
    std::printf("%d-texel ramp: %zu band edges, worst |fixed - cel| = %.5f in N.L (tolerance 1/512 = %.5f)\n", w,
                expected.size(), worst, 1.0 / 512.0);
  }
};

TEST_F(SteadyRamp, FixedBandsChangeWhereTheCelPathsDo) {
  expectCelBands({51 / 255.0f, 153 / 255.0f, 1.0f}, 1);
  expectCelBands({51 / 255.0f, 102 / 255.0f, 153 / 255.0f, 204 / 255.0f, 1.0f}, 1);
  // The middle row, as the cel path reads it.
  expectCelBands({204 / 255.0f, 51 / 255.0f, 1.0f, 102 / 255.0f, 153 / 255.0f}, 3);
  // 300 texels: bands of uneven width, one of them a single texel (1/300 in N.L, narrower than a
  // texel of a 256-texel resample: a wider ramp keeps at least its own width).
  std::vector<float> wide(300);
  for (int x = 0; x < 300; ++x) {
    wide[static_cast<std::size_t>(x)] = x < 37    ? 51 / 255.0f
                                        : x < 100 ? 153 / 255.0f
                                        : x < 151 ? 102 / 255.0f
                                        : x < 152 ? 1.0f
                                        : x < 299 ? 204 / 255.0f
                                                  : 51 / 255.0f;
  }
  expectCelBands(wide, 1);
}

}  // namespace
}  // namespace puff
