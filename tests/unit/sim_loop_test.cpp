// A loop (Settings::period): frame f + period holds what frame f does, from frame 0 on, for every
// kind of emitter and force that stands still; what moves is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "sim_test_helpers.h"

namespace puff::test {
namespace {

// A plume (lives longer than some periods), a burst inside each period, turbulence, a vortex and a
// floor: everything a loop repeats.
sim::Settings loopScene(int period) {
  sim::Settings s;
  s.fps = 24.0f;
  s.substeps = 2;
  s.period = period;
  s.forces.buoyancy = 1.5f;
  s.forces.drag = 2.5f;
  s.forces.turbulence = {0.4f, 0.5f, 3.0f, 5};  // a loop of 24 or 41 frames drifts a tile or two
  sim::Vortex v;
  v.position = {0.8f, 1.5f, 0.0f};
  v.strength = 1.1f;
  v.falloff = 1.2f;
  s.forces.vortices.push_back(v);
  sim::Emitter plume;
  plume.shape = sim::Emitter::Shape::kDisc;
  plume.radius = 0.2f;
  plume.rate = 31.0f;
  plume.start = -3.0f;
  plume.seed = 9;
  plume.velocity = {0.3f, 1.0f, 0.0f};
  plume.spreadDegrees = 15.0f;
  plume.speedSpread = 0.3f;
  plume.lifetime = 2.6f;
  plume.lifetimeSpread = 0.2f;
  plume.oriented = true;
  plume.spin = 1.0f;
  sim::Emitter burst;
  burst.shape = sim::Emitter::Shape::kSphere;
  burst.position = {-1.0f, 0.2f, 0.0f};
  burst.rate = 90.0f;
  burst.start = 0.1f;
  burst.duration = 0.25f;
  burst.seed = 4;
  burst.velocity = {0.0f, 2.0f, 0.0f};
  burst.spreadDegrees = 60.0f;
  burst.lifetime = 0.9f;
  // Births on step boundaries (one a step, half a step after a boundary's start phase), starting
  // many periods before frame 0.
  sim::Emitter tick;
  tick.position = {0.5f, 0.1f, 0.3f};
  tick.rate = 48.0f;
  tick.start = -10.0f + 1.0f / 96.0f;
  tick.seed = 8;
  tick.velocity = {0.0f, 0.7f, 0.2f};
  tick.lifetime = 0.5f;
  s.emitters = {plume, burst, tick};
  sim::Collider floor;
  floor.name = "floor";
  floor.halfExtent = {5.0f, 1.0f, 5.0f};
  s.colliders.push_back(floor);
  return s;
}

std::vector<sim::ParticleState> stateAt(sim::Simulator& sim, int frame) {
  sim.advanceToFrame(frame);
  std::vector<sim::ParticleState> out;
  for (std::size_t i = 0; i < sim.size(); ++i) out.push_back(sim.particle(i));
  return out;
}

// The largest distance between matching particles (born in the same order), or infinity when the
// two frames do not hold the same particles.
float largestMove(const std::vector<sim::ParticleState>& a, const std::vector<sim::ParticleState>& b) {
  if (a.size() != b.size()) return INFINITY;
  float worst = 0.0f;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].id != b[i].id || a[i].emitter != b[i].emitter || a[i].age != b[i].age) return INFINITY;
    worst = std::max({worst, glm::length(a[i].position - b[i].position), std::abs(a[i].size - b[i].size)});
  }
  return worst;
}

TEST(SimLoop, EveryFrameRepeatsAPeriodLater) {
  for (int period : {1, 7, 24, 41}) {
    SCOPED_TRACE("period " + std::to_string(period));
    auto sim = make(loopScene(period));
    ASSERT_TRUE(sim);
    for (int f : {0, 3, period - 1}) {
      const auto first = stateAt(*sim, f);
      EXPECT_GT(first.size(), 20u) << "frame " << f << " is in the loop's steady state";
      // Every period splits its births between steps alike and the turbulence's phase is counted in
      // whole steps: the repeat is exact.
      for (int k : {1, 2}) EXPECT_EQ(largestMove(first, stateAt(*sim, f + k * period)), 0.0f) << "frame " << f;
    }
  }
}

TEST(SimLoop, WithoutALoopTheSameSceneDoesNotRepeat) {
  sim::Settings s = loopScene(24);
  s.period = 0;
  s.preroll = 3.0f;
  auto sim = make(s);
  ASSERT_TRUE(sim);
  const auto first = stateAt(*sim, 0);
  EXPECT_GT(largestMove(first, stateAt(*sim, 24)), 1e-2f);
}

TEST(SimLoop, BirthsAreWholeAndEvenInEachPeriod) {
  struct Case {
    float rate, duration, periodSeconds;
    int perPeriod;
  };
  // 10.4 a second for 1 s: 10; 0.2 for 1 s: still 1; 90 for 0.25 s of each second: 22.5, rounded
  // to 23; a duration longer than the period: the whole period.
  for (const Case c : {Case{10.4f, 0.0f, 1.0f, 10}, Case{0.2f, 0.0f, 1.0f, 1}, Case{90.0f, 0.25f, 1.0f, 23},
                       Case{12.0f, 5.0f, 0.5f, 6}}) {
    SCOPED_TRACE("rate " + std::to_string(c.rate) + " duration " + std::to_string(c.duration));
    sim::Settings s;
    s.fps = 24.0f;
    s.substeps = 1;
    s.period = static_cast<int>(std::lround(c.periodSeconds * s.fps));
    sim::Emitter e;
    e.rate = c.rate;
    e.duration = c.duration;
    e.start = 0.3f;
    e.lifetime = 0.1f;  // longer than a step: every birth is counted
    s.emitters.push_back(e);
    auto sim = make(s);
    ASSERT_TRUE(sim);
    for (int period = 0; period < 3; ++period) {
      sim::StepStats st;
      for (int step = 0; step < s.period; ++step) sim->step(&st);
      EXPECT_EQ(st.born, static_cast<std::size_t>(c.perPeriod)) << "period " << period;
    }
  }
}

TEST(SimLoop, TurbulenceDriftsAndComesBack) {
  sim::Settings s = loopScene(48);
  s.emitters.clear();
  auto sim = make(s);
  ASSERT_TRUE(sim);
  const glm::vec3 p(0.3f, 1.1f, -0.2f);
  sim->advanceToFrame(0);
  const glm::vec3 start = sim->airVelocity(p);
  sim->advanceToFrame(24);
  EXPECT_GT(glm::length(sim->airVelocity(p) - start), 0.05f) << "halfway round, the field has drifted";
  sim->advanceToFrame(48);
  EXPECT_LT(glm::length(sim->airVelocity(p) - start), 1e-4f);
}

TEST(SimLoop, WhatMovesIsRefused) {
  auto refused = [](const sim::Settings& s) {
    auto r = sim::Simulator::create(s);
    return r ? std::string("accepted") : r.error().message;
  };
  sim::Path moving;
  moving.times = {0.0f, 1.0f};
  moving.points = {glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f)};
  sim::Settings s = loopScene(24);
  s.emitters[1].path = moving;
  EXPECT_EQ(refused(s),
            "/emitters/1/path: an emitter on a path (or attached to a moving object) does not repeat every period "
            "of a loop");
  s = loopScene(24);
  s.forces.vortices[0].path = moving;
  EXPECT_EQ(refused(s),
            "/forces/vortices/0/path: a vortex on a path (or attached to a moving object) does not repeat every "
            "period of a loop");
  s = loopScene(24);
  s.colliders[0].path = moving;
  EXPECT_EQ(refused(s), "/colliders/0 (floor): a moving collider does not repeat every period of a loop");
  s = loopScene(-1);
  EXPECT_EQ(refused(s), "/period: expected an integer in [0, 100000] (frames in a loop), got -1");
  s = loopScene(sim::kMaxPeriod + 1);
  EXPECT_NE(refused(s).find("/period: expected an integer in [0, 100000]"), std::string::npos);
  s = loopScene(24);
  s.emitters[0].lifetime = 30000.0f;
  EXPECT_NE(refused(s).find("/emitters/0/lifetime: expected a life of at most 1e6 steps in a loop"), std::string::npos);
  // Without a loop, all of these are fine.
  s.period = 0;
  s.emitters[1].path = moving;
  s.forces.vortices[0].path = moving;
  EXPECT_EQ(refused(s), "accepted");

  // Forces set while a loop runs are held to the same rule, and the old ones kept.
  auto sim = make(loopScene(24));
  ASSERT_TRUE(sim);
  sim::Forces f = sim->settings().forces;
  f.vortices[0].path = moving;
  auto r = sim->setForces(f);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("/forces/vortices/0/path"), std::string::npos);
  EXPECT_TRUE(sim->settings().forces.vortices[0].path.empty());
}

}  // namespace
}  // namespace puff::test
