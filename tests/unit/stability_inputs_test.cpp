// Stability at the limits of what Puff accepts: particle budgets far below what is asked for, and
// the zero-size and non-finite inputs the headers promise to refuse or to survive
// (stability_test.cpp is the index of the stability tests).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <puff/cel/frame.h>
#include <puff/core/gl.h>
#include <puff/core/image.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>
#include <puff/sim/simulator.h>

#include "stability_test_helpers.h"
#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/media_target.h"

namespace puff {
namespace {

using test::kInf;
using test::kNaN;
using test::plainMaterial;

// ---- budgets ----------------------------------------------------------------------------------

// A million births per second on a budget of a thousand: exactly 1000 alive after every step once
// the first step filled it, every other birth counted as dropped, nothing grows past the budget;
// with short lives the dead are replaced and the books still balance.
TEST(StabilityBudget, AMillionBirthsPerSecondOnABudgetOfAThousand) {
  for (float lifetime : {100.0f, 0.25f}) {
    SCOPED_TRACE(lifetime);
    sim::Settings s;
    s.fps = 24.0f;
    s.substeps = 4;
    s.maxParticles = 1000;
    sim::Emitter e;
    e.shape = sim::Emitter::Shape::kSphere;
    e.radius = 1.0f;
    e.rate = 1e6f;
    e.lifetime = lifetime;
    s.emitters.push_back(e);
    auto sim = sim::Simulator::create(s);
    ASSERT_OK(sim);
    sim::StepStats st;
    const int steps = 2 * 24 * 4;  // 2 s
    for (int i = 0; i < steps; ++i) {
      (*sim)->step(&st);
      ASSERT_EQ((*sim)->size(), 1000u) << "step " << i;
      ASSERT_EQ(st.born - st.died, (*sim)->size());
    }
    std::printf("lifetime %.2f s: born %zu, died %zu, dropped %zu\n", lifetime, st.born, st.died, st.dropped);
    EXPECT_EQ(st.born + st.dropped, 2'000'000u);  // every birth of 2 s at 1e6/s, born or dropped
    EXPECT_EQ(st.nonFinite, 0u);
    if (lifetime > 10.0f) {
      EXPECT_EQ(st.born, 1000u);
      EXPECT_EQ(st.died, 0u);
    } else {
      EXPECT_EQ(st.born, 8000u);  // lives of 0.25 s (24 steps) in 2 s: eight generations
    }
  }
}

// The parsers' budgets, at the boundary: the largest accepted, one more refused with its message.
TEST(StabilityBudget, ScenesAskingForMoreThanTheBudgetLimitAreRefused) {
  auto parse = [](const std::string& text) { return scene::parseScene(nlohmann::json::parse(text), "x.json"); };
  auto ok = parse(R"({"simulation": {"maxParticles": 20000000}})");
  ASSERT_OK(ok);
  EXPECT_EQ(ok->simulation->maxParticles, sim::kMaxParticleBudget);
  auto bad = parse(R"({"simulation": {"maxParticles": 20000001}})");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "x.json: /simulation/maxParticles: expected a particle budget in [0, 20000000] (about 64 bytes each; more "
            "would not fit in memory), got 20000001");
  ok = parse(R"({"media": {"maxParticles": 1000000}})");
  ASSERT_OK(ok);
  EXPECT_EQ(ok->media->maxParticles, 1'000'000u);
  for (const char* v : {"1000001", "-1", "1000.5"}) {
    bad = parse(std::string(R"({"media": {"maxParticles": )") + v + "}}");
    ASSERT_FALSE(bad.ok()) << v;
    EXPECT_EQ(bad.error().message,
              std::string("x.json: /media/maxParticles: expected a particle budget in [0, 1000000], got ") + v);
  }
}

class StabilityBudgetScene : public test::GlTest {};

// The same through the renderer: a media emitter asking for a million fire particles a second on
// a budget of a thousand draws exactly a thousand, and the image is finite.
TEST_F(StabilityBudgetScene, AMediaSceneDrawsItsBudgetNotTheRequest) {
  const auto j = nlohmann::json::parse(R"({
    "output": {"width": 32, "height": 24, "samples": 1, "background": [0, 0, 0]},
    "camera": {"position": [0, 0, 8], "target": [0, 0, 0], "near": 0.1, "far": 50},
    "media": {"resolution": 1, "maxParticles": 1000,
              "emitters": [{"material": "smoke", "shape": "sphere", "radius": 1, "rate": 1000000,
                            "lifetime": 100, "sizeMin": 0.2, "sizeMax": 0.4}]}
  })");
  auto scene = scene::parseScene(j, "budget.json");
  ASSERT_OK(scene);
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  render::FrameStats stats;
  auto image = (*renderer)->renderFrame(12, &stats);
  ASSERT_OK(image);
  EXPECT_EQ(stats.mediaParticles, 1000u);
  int lit = 0;
  for (float v : image->pixels) {
    ASSERT_TRUE(std::isfinite(v));
    lit += v > 0.0f ? 1 : 0;
  }
  EXPECT_GT(lit, 0);
}

// ---- inputs -----------------------------------------------------------------------------------

class StabilityInputs : public test::GlTest {};

// cel::Ramp: "Width in [2, 16384]"; cel::Gradient: 1 to 16384 a side; both refuse non-finite values.
TEST_F(StabilityInputs, RampsAndGradientsRefuseEmptyAndNonFiniteImages) {
  auto rampError = [](const core::Image& im) {
    auto r = cel::Ramp::create(im, "r.png");
    return r.ok() ? std::string("accepted") : r.error().message;
  };
  EXPECT_EQ(rampError(core::Image(0, 0, 3)), "r.png: a ramp must be 2 to 16384 pixels wide (got 0x0)");
  EXPECT_EQ(rampError(core::Image(1, 1, 3)), "r.png: a ramp must be 2 to 16384 pixels wide (got 1x1)");
  EXPECT_EQ(rampError(core::Image(4, 0, 3)), "r.png: a ramp must be 2 to 16384 pixels wide (got 4x0)");
  core::Image nanRamp(4, 1, 3, 0.5f);
  nanRamp.at(2, 0, 1) = kNaN;
  EXPECT_EQ(rampError(nanRamp), "r.png: ramp holds a non-finite value");
  nanRamp.at(2, 0, 1) = kInf;
  EXPECT_EQ(rampError(nanRamp), "r.png: ramp holds a non-finite value");

  auto gradientError = [](const core::Image& im) {
    auto g = cel::Gradient::create(im, "g.png");
    return g.ok() ? std::string("accepted") : g.error().message;
  };
  EXPECT_EQ(gradientError(core::Image(0, 0, 3)), "g.png: a gradient must be 1 to 4096 pixels on each side (got 0x0)");
  EXPECT_EQ(gradientError(core::Image(3, 0, 3)), "g.png: a gradient must be 1 to 4096 pixels on each side (got 3x0)");
  core::Image nanGradient(3, 3, 3, 0.5f);
  nanGradient.at(1, 2, 0) = kNaN;
  EXPECT_EQ(gradientError(nanGradient), "g.png: gradient holds a non-finite value");
  EXPECT_EQ(gradientError(core::Image(1, 1, 3, 0.5f)), "accepted");  // the smallest there is
  EXPECT_EQ(core::drainGlErrors(), "");
}

// media::Layers::create, Renderer::create and setMaterials refuse zero sizes, resolutions that are
// not 1/1..1/8, NaN settings and NaN materials; a refused table leaves the old one in place.
TEST_F(StabilityInputs, MediaRefusesEmptyLayersAndNonFiniteSettingsAndMaterials) {
  auto layersError = [](int w, int h, int samples, float scale) {
    auto l = media::Layers::create(w, h, samples, scale);
    return l.ok() ? std::string("accepted") : l.error().message;
  };
  EXPECT_EQ(layersError(0, 64, 1, 1.0f), "media layers: size 0x64 outside 1..16384");
  EXPECT_EQ(layersError(64, 0, 1, 1.0f), "media layers: size 64x0 outside 1..16384");
  EXPECT_EQ(layersError(16385, 64, 1, 1.0f), "media layers: size 16385x64 outside 1..16384");
  for (float scale : {0.0f, 0.3f, -0.5f, kNaN, kInf}) {
    EXPECT_EQ(layersError(64, 64, 1, scale).rfind("media resolution: expected 1, 0.5, 0.25 or 0.125, got ", 0), 0u)
        << scale;
  }
  EXPECT_NE(layersError(64, 64, 0, 1.0f).find("0 samples per pixel asked"), std::string::npos);
  EXPECT_EQ(layersError(1, 1, 1, 0.125f), "accepted");  // 1 x 1 at 1/8: the layer is still 1 x 1

  media::Settings settings;
  settings.exposure = kNaN;
  auto r = media::Renderer::create(settings);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "exposure: expected a number in [0, 10000], got nan");
  settings = {};
  settings.minKelvin = kNaN;
  r = media::Renderer::create(settings);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("minKelvin"), std::string::npos) << r.error().message;

  r = media::Renderer::create();
  ASSERT_OK(r);
  media::Renderer& renderer = **r;
  ASSERT_TRUE(renderer.setMaterials({plainMaterial(0.4f)}).ok());
  auto refused = [&](std::vector<media::Material> table) {
    auto ok = renderer.setMaterials(std::move(table));
    EXPECT_EQ(renderer.materials().size(), 1u);  // the old table stays
    EXPECT_EQ(renderer.materials()[0].density, 0.4f);
    return ok ? std::string("accepted") : ok.error().message;
  };
  EXPECT_EQ(refused({}), "materials: expected 1 to 32, got 0");
  EXPECT_EQ(refused(std::vector<media::Material>(33, plainMaterial(1.0f))), "materials: expected 1 to 32, got 33");
  struct Case {
    void (*change)(media::Material&);
    const char* message;
  };
  const Case cases[] = {
      {[](media::Material& m) { m.density = kNaN; }, "plain: density: expected a number in [0, 10000], got nan"},
      {[](media::Material& m) { m.density = kInf; }, "plain: density: expected a number in [0, 10000], got inf"},
      {[](media::Material& m) { m.albedo = kNaN; }, "plain: albedo: expected a number in [0, 1], got nan"},
      {[](media::Material& m) { m.g = kNaN; }, "plain: g: expected a number in [-0.95, 0.95], got nan"},
      {[](media::Material& m) { m.detailWindow = 0.0f; },
       "plain: detailWindow: expected a number in [0.001, 1], got 0"},
      {[](media::Material& m) { m.transitionEnd = kNaN; },
       "plain: transitionEnd: expected a number in [0, 1], got nan"},
  };
  for (const Case& c : cases) {
    media::Material m = plainMaterial(1.0f);
    c.change(m);
    EXPECT_EQ(refused({m}), c.message);
  }
  EXPECT_EQ(core::drainGlErrors(), "");
}

// sim::validate (and so Simulator::create and setForces) refuses NaN and zero sizes where it says
// so, naming the field; the pointers are relative to the Settings.
TEST(StabilityInputsSim, NonFiniteAndZeroSizedSettingsAreRefusedNamingTheField) {
  struct Case {
    void (*change)(sim::Settings&);
    const char* message;
  };
  const Case cases[] = {
      {[](sim::Settings& s) { s.fps = 0.0f; }, "/fps: expected a number in (0, 10000], got 0"},
      {[](sim::Settings& s) { s.fps = kNaN; }, "/fps: expected a number in (0, 10000], got a non-finite number"},
      {[](sim::Settings& s) { s.emitters[0].position.y = kNaN; },
       "/emitters/0/position/1: expected a number in [-1e+06, 1e+06], got a non-finite number"},
      {[](sim::Settings& s) { s.emitters[0].rate = kInf; },
       "/emitters/0/rate: expected a number in [0, 1e+07], got a non-finite number"},
      {[](sim::Settings& s) { s.emitters[0].lifetime = kNaN; },
       "/emitters/0/lifetime: expected a number in (0, 1e+06], got a non-finite number"},
      {[](sim::Settings& s) { s.emitters[0].sizeMax = kNaN; },
       "/emitters/0/sizeMax: expected a number in [0.5, 1e+06], got a non-finite number"},
      {[](sim::Settings& s) {
         s.emitters[0].shape = sim::Emitter::Shape::kDisc;
         s.emitters[0].normal = glm::vec3(0.0f);
       },
       "/emitters/0/normal: expected a non-zero direction, got [0, 0, 0]"},
      {[](sim::Settings& s) {
         s.emitters[0].path.times = {0.0f, kNaN};
         s.emitters[0].path.points = {glm::vec3(0.0f), glm::vec3(1.0f)};
       },
       "/emitters/0/path/1/time: expected a number in [-1e+06, 1e+06], got a non-finite number"},
      {[](sim::Settings& s) {
         s.forces.vortices.emplace_back();
         s.forces.vortices[0].radius = 0.0f;
       },
       "/forces/vortices/0/radius: expected a number in [0.0001, 1e+06], got 0"},
      {[](sim::Settings& s) {
         s.forces.windVolumes.emplace_back();
         s.forces.windVolumes[0].halfExtent.y = kNaN;
       },
       "/forces/windVolumes/0/halfExtent/1: expected a number in [0, 1e+06], got a non-finite number"},
      {[](sim::Settings& s) {
         sim::Collider c;
         c.type = sim::Collider::Type::kSphere;
         c.halfExtent = glm::vec3(kNaN);
         s.colliders.push_back(c);
       },
       "/colliders/0/halfExtent/0: expected a number in [0, 1e+06], got a non-finite number"},
      {[](sim::Settings& s) {
         sim::Collider c;
         c.rotation = glm::quat(0.0f, 0.0f, 0.0f, 0.0f);
         s.colliders.push_back(c);
       },
       "/colliders/0/rotation: expected a rotation (a non-zero quaternion)"},
      {[](sim::Settings& s) {
         sim::Collider c;
         c.type = sim::Collider::Type::kMesh;  // no triangles
         s.colliders.push_back(c);
       },
       "/colliders/0: a mesh collider needs triangles"},
  };
  for (const Case& c : cases) {
    sim::Settings s;
    s.emitters.push_back(sim::Emitter{});
    c.change(s);
    auto r = sim::validate(s);
    ASSERT_FALSE(r.ok()) << c.message;
    EXPECT_EQ(r.error().message, c.message);
    auto created = sim::Simulator::create(s);
    ASSERT_FALSE(created.ok());
    EXPECT_EQ(created.error().message, c.message);
  }
  // Live edits: NaN forces are refused and the old ones kept.
  auto sim = sim::Simulator::create(sim::Settings{});
  ASSERT_TRUE(sim.ok());
  sim::Forces nanGravity;
  nanGravity.gravity.x = kNaN;
  auto r = (*sim)->setForces(nanGravity);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "/forces/gravity/0: expected a number in [-1e+06, 1e+06], got a non-finite number");
  EXPECT_EQ((*sim)->settings().forces.gravity, glm::vec3(0.0f));
}

// Zero sizes the headers accept must work: particles of size 0 born at the exact centre of a
// sphere collider and of a box collider, and on a plane of zero extent (every direction from the
// centre is degenerate: the sphere pushes out along `up`), a collider of zero size; nothing goes
// non-finite, and zero-size puffs and media particles draw nothing.
TEST(StabilityInputsSim, ZeroSizesAndDegenerateContactsStayFinite) {
  for (auto type : {sim::Collider::Type::kSphere, sim::Collider::Type::kBox, sim::Collider::Type::kPlane}) {
    for (float extent : {0.0f, 0.5f}) {
      SCOPED_TRACE(std::to_string(static_cast<int>(type)) + " extent " + std::to_string(extent));
      sim::Settings s;
      s.collisionRadius = 1.0f;
      sim::Emitter e;
      e.position = glm::vec3(0.0f);  // at the collider's centre
      e.velocity = glm::vec3(0.0f);
      e.sizeMin = e.sizeMax = 0.0f;
      e.radius = 0.0f;
      e.rate = 500.0f;
      e.lifetime = 10.0f;
      s.emitters.push_back(e);
      e.sizeMin = e.sizeMax = 0.2f;  // and a second emitter of small particles at the same place
      s.emitters.push_back(e);
      sim::Collider c;
      c.type = type;
      c.halfExtent = glm::vec3(extent);
      s.colliders.push_back(c);
      auto sim = sim::Simulator::create(s);
      ASSERT_OK(sim);
      sim::StepStats st;
      (*sim)->advanceToFrame(24, &st);
      ASSERT_GT((*sim)->size(), 900u);
      EXPECT_EQ(st.nonFinite, 0u);
      for (std::size_t i = 0; i < (*sim)->size(); ++i) {
        const sim::ParticleState p = (*sim)->particle(i);
        ASSERT_TRUE(std::isfinite(p.position.x) && std::isfinite(p.position.y) && std::isfinite(p.position.z));
        ASSERT_TRUE(std::isfinite(p.velocity.x) && std::isfinite(p.velocity.y) && std::isfinite(p.velocity.z));
        if (type == sim::Collider::Type::kSphere && extent > 0.0f) {
          // Out of the ball by its own radius, along `up` from the exact centre.
          ASSERT_GE(glm::length(p.position), extent + 0.5f * p.size - 1e-4f);
        }
      }
    }
  }
}

}  // namespace
}  // namespace puff
