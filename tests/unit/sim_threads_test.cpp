// The simulator on several threads: the state after any number of steps is bit-identical for
// every thread count (simulator.h, "Threads"), and thread counts are validated.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <thread>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include <puff/sim/simulator.h>

#include "support/assert_ok.h"

using namespace puff;
using sim::Collider;
using sim::Emitter;
using sim::Settings;
using sim::Simulator;

namespace {

// A closed cube of side 2 * half around `center`, as triangles (outward winding).
Collider meshCube(const glm::vec3& center, float half) {
  Collider c;
  c.type = Collider::Type::kMesh;
  c.name = "cube";
  for (int i = 0; i < 8; ++i)
    c.positions.push_back(center + half * glm::vec3(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f));
  c.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
               2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return c;
}

// All six forces (two vortices, one moving and shedding a wake; a wind volume; turbulence),
// every collider type (the box rotated, the mesh moving), three emitters (one moving, one
// oriented and spinning) with short lives so particles die every step, and a budget that drops
// births: 36,000 particles, enough that 8 threads each get a share.
Settings busyScene() {
  Settings s;
  s.fps = 24.0f;
  s.substeps = 2;
  s.preroll = 0.25f;
  s.maxParticles = 36'000;
  sim::Forces& f = s.forces;
  f.gravity = glm::vec3(0.0f, -0.5f, 0.0f);
  f.buoyancy = 1.2f;
  f.drag = 3.0f;
  f.wind = glm::vec3(0.5f, 0.0f, 0.2f);
  f.windVolumes.push_back({glm::vec3(0.0f, 2.0f, 0.0f), glm::vec3(1.5f), glm::vec3(0.0f, 0.0f, 3.0f), 1.0f});
  f.turbulence = {0.7f, 0.6f, 1.0f, 7};
  sim::Vortex still;
  still.position = glm::vec3(0.0f, 2.0f, 0.0f);
  still.strength = 2.0f;
  still.radius = 0.7f;
  still.falloff = 4.0f;
  f.vortices.push_back(still);
  sim::Vortex moving;
  moving.axis = glm::vec3(1.0f, 0.0f, 0.3f);
  moving.strength = -1.5f;
  moving.radius = 0.5f;
  moving.length = 3.0f;
  moving.path.times = {0.0f, 2.0f};
  moving.path.points = {glm::vec3(-2.0f, 1.0f, 0.0f), glm::vec3(2.0f, 3.0f, 0.0f)};
  moving.shedInterval = 0.1f;
  moving.shedLifetime = 0.5f;
  f.vortices.push_back(moving);

  Emitter ball;
  ball.shape = Emitter::Shape::kSphere;
  ball.rate = 60'000.0f;
  ball.radius = 2.5f;
  ball.position = glm::vec3(0.0f, 2.0f, 0.0f);
  ball.spreadDegrees = 40.0f;
  ball.speedSpread = 0.3f;
  ball.lifetime = 0.4f;
  ball.lifetimeSpread = 0.5f;
  ball.oriented = true;
  ball.spin = 1.0f;
  ball.sizeMin = 0.2f, ball.sizeMax = 0.9f;
  s.emitters.push_back(ball);
  Emitter disc;
  disc.shape = Emitter::Shape::kDisc;
  disc.rate = 20'000.0f;
  disc.seed = 5;
  disc.path.times = {0.0f, 2.0f};
  disc.path.points = {glm::vec3(-3.0f, 0.5f, 0.0f), glm::vec3(3.0f, 0.5f, 0.0f)};
  disc.inheritVelocity = 0.5f;
  disc.lifetime = 0.8f;
  disc.velocity = glm::vec3(0.0f, -4.0f, 0.0f);  // into the ground plane
  s.emitters.push_back(disc);
  Emitter jet;  // fast, through the mesh cube
  jet.position = glm::vec3(-3.0f, 3.5f, 0.0f);
  jet.rate = 5'000.0f;
  jet.seed = 9;
  jet.velocity = glm::vec3(40.0f, 0.0f, 0.0f);
  jet.lifetime = 0.5f;
  s.emitters.push_back(jet);

  Collider ground;
  ground.halfExtent = glm::vec3(10.0f, 0.0f, 10.0f);
  ground.friction = 0.2f;
  Collider ball2;
  ball2.type = Collider::Type::kSphere;
  ball2.center = glm::vec3(1.0f, 1.0f, 0.0f);
  ball2.halfExtent = glm::vec3(0.6f);
  Collider box;
  box.type = Collider::Type::kBox;
  box.center = glm::vec3(-1.0f, 1.0f, 0.5f);
  box.halfExtent = glm::vec3(0.5f, 0.3f, 0.5f);
  box.rotation = glm::angleAxis(0.4f, glm::vec3(0.0f, 1.0f, 0.0f));
  box.friction = 0.5f;
  Collider cube = meshCube(glm::vec3(0.0f, 3.5f, 0.0f), 0.5f);
  cube.path.times = {0.0f, 2.0f};
  cube.path.points = {glm::vec3(0.0f), glm::vec3(0.0f, -1.0f, 0.0f)};
  s.colliders = {ground, ball2, box, cube};
  return s;
}

// Every field of every particle, byte for byte (memcmp: -0 and +0 differ, NaNs compare).
void expectSameBytes(const Simulator& a, const Simulator& b, int threads, int step) {
  ASSERT_EQ(a.size(), b.size()) << threads << " threads, step " << step;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const sim::ParticleState p = a.particle(i), q = b.particle(i);
    const auto same = [](const auto& x, const auto& y) { return std::memcmp(&x, &y, sizeof x) == 0; };
    ASSERT_TRUE(same(p.position, q.position) && same(p.velocity, q.velocity) && same(p.size, q.size) &&
                same(p.density, q.density) && same(p.variation, q.variation) && same(p.oriented, q.oriented) &&
                same(p.orientation, q.orientation) && same(p.birthSize, q.birthSize) && same(p.age, q.age) &&
                same(p.lifetime, q.lifetime) && same(p.emitter, q.emitter) && same(p.id, q.id))
        << "particle " << i << " differs on " << threads << " threads at step " << step;
  }
}

}  // namespace

TEST(SimulatorThreads, StateIsBitIdenticalForAnyThreadCount) {
  const Settings s = busyScene();
  auto one = Simulator::create(s, 4);
  ASSERT_OK(one);
  Simulator& reference = **one;
  EXPECT_EQ(reference.threads(), 1);
  std::vector<std::unique_ptr<Simulator>> others;
  const std::vector<int> counts = {2, 3, 8};
  for (int threads : counts) {
    Settings t = s;
    t.threads = threads;
    auto made = Simulator::create(t, 4);
    ASSERT_OK(made);
    EXPECT_EQ((*made)->threads(), threads);
    others.push_back(std::move(*made));
  }
  sim::StepStats total;
  for (int step = 1; step <= 36; ++step) {
    sim::StepStats st;
    reference.step(&st);
    total.born += st.born, total.died += st.died, total.dropped += st.dropped, total.collisions += st.collisions;
    for (std::size_t k = 0; k < others.size(); ++k) {
      sim::StepStats ot;
      others[k]->step(&ot);
      EXPECT_EQ(ot.born, st.born);
      EXPECT_EQ(ot.died, st.died);
      EXPECT_EQ(ot.dropped, st.dropped);
      EXPECT_EQ(ot.collisions, st.collisions);
      EXPECT_EQ(ot.nonFinite, st.nonFinite);
      if (step % 6 == 0) expectSameBytes(reference, *others[k], counts[k], step);
      if (HasFatalFailure()) return;
    }
  }
  // The scene does what it claims: enough particles to split 8 ways, births, deaths, dropped
  // births, contacts, and a wake shed.
  EXPECT_GT(reference.size(), 8u * 4096u);
  EXPECT_GT(total.died, 10'000u);
  EXPECT_GT(total.dropped, 0u);
  EXPECT_GT(total.collisions, 1'000u);
  EXPECT_GT(reference.liveVortices(), 2u);
}

TEST(SimulatorThreads, ChangingTheCountMidRunChangesNothing) {
  Settings s = busyScene();
  auto a = Simulator::create(s, 4), b = Simulator::create(s, 4);
  ASSERT_OK(a);
  ASSERT_OK(b);
  for (int step = 0; step < 12; ++step) {
    ASSERT_OK((*b)->setThreads(step % 4 == 3 ? 0 : 1 + step % 4));  // 1, 2, 3, hardware, ...
    (*a)->step();
    (*b)->step();
  }
  expectSameBytes(**a, **b, 0, 12);
  // advanceToFrame restarts from the start on any count and reaches the same frame.
  (*a)->advanceToFrame(3);
  ASSERT_OK((*b)->setThreads(5));
  (*b)->advanceToFrame(3);
  expectSameBytes(**a, **b, 5, 3 * s.substeps);
}

TEST(SimulatorThreads, CountsAreValidated) {
  Settings s = busyScene();
  s.threads = -1;
  auto bad = Simulator::create(s);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("/threads"), std::string::npos) << bad.error().message;
  s.threads = sim::kMaxThreads + 1;
  EXPECT_FALSE(Simulator::create(s));
  s.threads = 0;  // the hardware's count
  auto hw = Simulator::create(s);
  ASSERT_OK(hw);
  EXPECT_EQ((*hw)->threads(), static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  EXPECT_FALSE((*hw)->setThreads(-2));
  EXPECT_FALSE((*hw)->setThreads(sim::kMaxThreads + 1));
  EXPECT_EQ((*hw)->settings().threads, 0);  // refused counts change nothing
  ASSERT_OK((*hw)->setThreads(3));
  EXPECT_EQ((*hw)->threads(), 3);
  EXPECT_EQ((*hw)->settings().threads, 3);
}
