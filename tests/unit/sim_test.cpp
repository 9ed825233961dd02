// The smoke simulator: emitters, collisions, determinism, and bad or extreme input
// (sim_forces_test.cpp has the forces and the integrator).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include <puff/sim/simulator.h>

#include "sim_test_helpers.h"

using namespace puff;
using puff::test::make;
using puff::test::oneParticle;
using sim::Emitter;
using sim::Settings;
using sim::Simulator;

TEST(Simulator, EmittersBornAtTheirRateWithinTheBudget) {
  Settings s;
  s.fps = 30.0f;
  s.substeps = 3;
  Emitter e;
  e.rate = 250.0f;
  e.lifetime = 100.0f;
  e.shape = Emitter::Shape::kSphere;
  e.radius = 2.0f;
  s.emitters.push_back(e);
  auto sim = make(s);
  sim->advanceToFrame(60);  // 2 s
  EXPECT_EQ(sim->size(), 500u);
  // Still air, drag k = 2, born at v0 = (0, 1, 0) somewhere in the sphere: at age a a particle
  // moves at v0 e^(-k a) and lies v0 (1 - e^(-k a)) / k above where it was born, inside the sphere,
  // give or take the substep h it was born in (drag acts from the substep's start on).
  // (A particle that ignored drag would lie up to 2 units above it.)
  const float k = s.forces.drag, h = 1.0f / (s.fps * static_cast<float>(s.substeps));
  for (std::size_t i = 0; i < sim->size(); ++i) {
    const sim::ParticleState p = sim->particle(i);
    const float decay = std::exp(-k * p.age);
    EXPECT_GE(p.velocity.y, decay - 1e-5f) << i;
    EXPECT_LE(p.velocity.y, std::exp(-k * (p.age - h)) + 1e-5f) << i;
    const glm::vec3 birth = p.position - glm::vec3(0.0f, (1.0f - decay) / k, 0.0f);
    EXPECT_LE(glm::length(birth), e.radius + h) << i << " (age " << p.age << ")";
  }
  s.maxParticles = 100;
  auto capped = make(s);
  sim::StepStats st;
  capped->advanceToFrame(60, &st);
  EXPECT_EQ(capped->size(), 100u);
  EXPECT_EQ(st.dropped, 400u);
}

TEST(Simulator, EmitterShapesPlaceParticlesInside) {
  for (auto shape : {Emitter::Shape::kPoint, Emitter::Shape::kSphere, Emitter::Shape::kDisc}) {
    Settings s;
    s.forces.drag = 0.0f;
    Emitter e;
    e.shape = shape;
    e.position = glm::vec3(1.0f, 2.0f, 3.0f);
    e.radius = 0.5f;
    e.normal = glm::vec3(0.0f, 0.0f, 1.0f);
    e.velocity = glm::vec3(0.0f);
    e.rate = 20000.0f;
    e.lifetime = 10.0f;
    s.emitters.push_back(e);
    auto sim = make(s);
    sim->step();
    ASSERT_GT(sim->size(), 200u);
    float farthest = 0.0f, offPlane = 0.0f;
    for (std::size_t i = 0; i < sim->size(); ++i) {
      const glm::vec3 d = sim->particle(i).position - e.position;
      farthest = std::max(farthest, glm::length(d));
      offPlane = std::max(offPlane, std::abs(d.z));
    }
    if (shape == Emitter::Shape::kPoint) {
      EXPECT_LT(farthest, 1e-6f);
    }
    if (shape != Emitter::Shape::kPoint) {
      EXPECT_LE(farthest, 0.5f + 1e-5f);
      EXPECT_GT(farthest, 0.4f);
    }
    if (shape == Emitter::Shape::kDisc) {
      EXPECT_LT(offPlane, 1e-6f);
    }
    if (shape == Emitter::Shape::kSphere) {
      EXPECT_GT(offPlane, 0.3f);
    }
  }
}

TEST(Simulator, SpreadKeepsDirectionsInsideTheCone) {
  Settings s;
  s.forces.drag = 0.0f;
  Emitter e;
  e.velocity = glm::vec3(0.0f, 0.0f, 2.0f);
  e.spreadDegrees = 20.0f;
  e.rate = 5000.0f;
  s.emitters.push_back(e);
  auto sim = make(s);
  sim->step();
  float widest = 0.0f;
  for (std::size_t i = 0; i < sim->size(); ++i) {
    const glm::vec3 v = sim->particle(i).velocity;
    EXPECT_NEAR(glm::length(v), 2.0f, 1e-5f);
    widest = std::max(widest, glm::degrees(std::acos(std::clamp(v.z / glm::length(v), -1.0f, 1.0f))));
  }
  EXPECT_LE(widest, 20.01f);
  EXPECT_GT(widest, 17.0f);
}

TEST(Simulator, PathEmitterLeavesAContinuousTrail) {
  // A missile at 240 units/s emitting 480 particles/s: one every 0.5 units along the path, not a
  // clump per step (a step covers 10 units).
  Settings s;
  s.fps = 24.0f;
  s.substeps = 1;
  s.forces.drag = 0.0f;
  Emitter e;
  e.velocity = glm::vec3(0.0f);
  e.rate = 480.0f;
  e.lifetime = 10.0f;
  e.path.times = {0.0f, 1.0f};
  e.path.points = {glm::vec3(0.0f), glm::vec3(240.0f, 0.0f, 0.0f)};
  s.emitters.push_back(e);
  auto sim = make(s);
  sim->advanceToFrame(12);  // half a second
  std::vector<float> xs;
  for (std::size_t i = 0; i < sim->size(); ++i) xs.push_back(sim->particle(i).position.x);
  std::sort(xs.begin(), xs.end());
  ASSERT_EQ(xs.size(), 240u);
  float gap = 0.0f;
  for (std::size_t i = 1; i < xs.size(); ++i) gap = std::max(gap, xs[i] - xs[i - 1]);
  EXPECT_NEAR(gap, 0.5f, 1e-3f);
  EXPECT_NEAR(xs.front(), 0.25f, 1e-3f);
}

TEST(Simulator, MovingVortexShedsAWake) {
  // A vortex 1 unit long rides a path from x = 0 to x = 10 over 2 s, leaving a copy every 0.25 s
  // that fades out over 1 s. It sheds only while it moves.
  Settings s;
  sim::Vortex v;
  v.path.times = {0.0f, 2.0f};
  v.path.points = {glm::vec3(0.0f), glm::vec3(10.0f, 0.0f, 0.0f)};
  v.axis = glm::vec3(1.0f, 0.0f, 0.0f);
  v.radius = 0.5f;
  v.length = 1.0f;
  v.shedInterval = 0.25f;
  v.shedLifetime = 1.0f;
  s.forces.vortices.push_back(v);
  auto sim = make(s);
  sim->advanceToFrame(24);  // 1 s: copies from 0.25, 0.5, 0.75 and 1.0 are alive
  EXPECT_EQ(sim->liveVortices(), 1u + 4u);
  sim->advanceToFrame(48);  // 2 s: the path has ended; copies from 1.25, 1.5, 1.75 are alive
  EXPECT_EQ(sim->liveVortices(), 1u + 3u);
  // The copy left at 1.75 s stays at x = 8.75, at 3/4 strength; the vortex itself is 1.25 units
  // further on, where its length envelope leaves exp(-6.25) of its swirl.
  const glm::vec3 wake(8.75f, 1.12092f * 0.5f, 0.0f);
  EXPECT_NEAR(glm::length(sim->airVelocity(wake)), 0.75f, 0.01f);
  s.forces.vortices[0].shedInterval = 0.0f;
  auto noWake = make(s);
  noWake->advanceToFrame(48);
  EXPECT_LT(glm::length(noWake->airVelocity(wake)), 0.01f);
  sim->advanceToFrame(96);  // 4 s: standing still, it sheds nothing; every copy has faded
  EXPECT_EQ(sim->liveVortices(), 1u);
}

TEST(Simulator, FrameReachedAloneEqualsTheSequence) {
  Settings s;
  s.fps = 24.0f;
  s.substeps = 3;
  s.preroll = 0.5f;
  s.forces.drag = 3.0f;
  s.forces.buoyancy = 1.0f;
  s.forces.turbulence.strength = 0.8f;
  sim::Vortex v;
  v.strength = 1.0f;
  s.forces.vortices.push_back(v);
  Emitter e;
  e.shape = Emitter::Shape::kDisc;
  e.rate = 200.0f;
  e.spreadDegrees = 30.0f;
  e.lifetime = 1.5f;
  e.lifetimeSpread = 0.3f;
  e.oriented = true;
  e.spin = 2.0f;
  s.emitters.push_back(e);
  auto a = make(s, 4), b = make(s, 4);
  for (int f = 0; f <= 20; ++f) a->advanceToFrame(f);
  b->advanceToFrame(20);
  ASSERT_EQ(a->frame(), 20);
  ASSERT_EQ(a->size(), b->size());
  ASSERT_GT(a->size(), 100u);
  for (std::size_t i = 0; i < a->size(); ++i) {
    const auto p = a->particle(i), q = b->particle(i);
    ASSERT_EQ(p.position, q.position);
    ASSERT_EQ(p.size, q.size);
    ASSERT_EQ(p.variation, q.variation);
    ASSERT_EQ(p.orientation, q.orientation);
  }
  // Going back starts over and gives the same state again.
  a->advanceToFrame(5);
  b->advanceToFrame(30);
  b->advanceToFrame(5);
  ASSERT_EQ(a->size(), b->size());
  for (std::size_t i = 0; i < a->size(); ++i) ASSERT_EQ(a->particle(i).position, b->particle(i).position);
}

TEST(Simulator, ParticlesStayOutOfPlanesSpheresAndBoxes) {
  Settings s;
  s.fps = 24.0f;
  s.substeps = 2;
  s.collisionRadius = 1.0f;
  s.forces.gravity = glm::vec3(0.0f, -20.0f, 0.0f);
  s.forces.drag = 0.5f;
  Emitter e;
  e.shape = Emitter::Shape::kSphere;
  e.position = glm::vec3(0.0f, 6.0f, 0.0f);
  e.radius = 3.0f;
  e.rate = 400.0f;
  e.duration = 1.0f;
  e.lifetime = 20.0f;
  e.sizeMin = e.sizeMax = 0.2f;
  s.emitters.push_back(e);
  sim::Collider ground;
  ground.type = sim::Collider::Type::kPlane;
  ground.halfExtent = glm::vec3(50.0f, 0.0f, 50.0f);
  sim::Collider ball;
  ball.type = sim::Collider::Type::kSphere;
  ball.center = glm::vec3(-1.5f, 1.0f, 0.0f);
  ball.halfExtent = glm::vec3(1.0f);
  sim::Collider box;
  box.type = sim::Collider::Type::kBox;
  box.center = glm::vec3(1.5f, 1.0f, 0.0f);
  box.rotation = glm::angleAxis(0.5f, glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f)));
  box.halfExtent = glm::vec3(1.0f, 0.5f, 0.8f);
  s.colliders = {ground, ball, box};
  auto sim = make(s);
  sim::StepStats st;
  for (int f = 1; f <= 72; ++f) {
    sim->advanceToFrame(f, &st);
    for (std::size_t i = 0; i < sim->size(); ++i) {
      const sim::ParticleState p = sim->particle(i);
      const float r = 0.5f * p.size;
      ASSERT_GE(p.position.y, r - 1e-4f) << "below the ground at frame " << f;
      ASSERT_GE(glm::length(p.position - ball.center), 1.0f + r - 1e-4f) << "inside the sphere";
      const glm::vec3 local = glm::conjugate(box.rotation) * (p.position - box.center);
      const glm::vec3 pen = box.halfExtent + glm::vec3(r) - glm::abs(local);
      ASSERT_FALSE(pen.x > 1e-4f && pen.y > 1e-4f && pen.z > 1e-4f) << "inside the box";
    }
  }
  EXPECT_GT(st.collisions, 1000u);
  // Resting on the ground, they lost their fall: no bounce.
  float fastest = 0.0f;
  for (std::size_t i = 0; i < sim->size(); ++i) fastest = std::max(fastest, std::abs(sim->particle(i).velocity.y));
  EXPECT_LT(fastest, 1.0f);
}

TEST(Simulator, FastParticlesDoNotTunnelThroughAMesh) {
  // A closed unit cube as triangles; particles shot through it at 600 units/s (25 units per step,
  // 12x the cube) stop at its surface.
  sim::Collider cube;
  cube.type = sim::Collider::Type::kMesh;
  for (int i = 0; i < 8; ++i)
    cube.positions.push_back(glm::vec3(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f));
  cube.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                  2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  Settings s;
  s.substeps = 1;
  s.forces.drag = 0.0f;
  Emitter e;
  e.shape = Emitter::Shape::kDisc;
  e.normal = glm::vec3(1.0f, 0.0f, 0.0f);
  e.position = glm::vec3(-20.0f, 0.0f, 0.0f);
  e.radius = 0.9f;
  e.velocity = glm::vec3(600.0f, 0.0f, 0.0f);
  e.rate = 2000.0f;
  e.duration = 0.01f;
  e.lifetime = 5.0f;
  s.emitters.push_back(e);
  s.colliders = {cube};
  auto sim = make(s);
  for (int i = 0; i < 10; ++i) sim->step();
  ASSERT_EQ(sim->size(), 20u);
  for (std::size_t i = 0; i < sim->size(); ++i) {
    const sim::ParticleState p = sim->particle(i);
    EXPECT_NEAR(p.position.x, -1.0f, 1e-3f);
    EXPECT_NEAR(p.velocity.x, 0.0f, 1e-3f);
  }
}

TEST(Simulator, RejectsImpossibleValuesNamingTheField) {
  auto message = [](const Settings& s) {
    auto r = sim::validate(s);
    return r ? std::string() : r.error().message;
  };
  Settings s = oneParticle();
  s.emitters[0].rate = -1.0f;
  EXPECT_EQ(message(s), "/emitters/0/rate: expected a number in [0, 1e+07], got -1");
  s = oneParticle();
  s.emitters[0].lifetime = 0.0f;
  EXPECT_EQ(message(s), "/emitters/0/lifetime: expected a number in (0, 1e+06], got 0");
  s = oneParticle();
  s.forces.drag = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(message(s), "/forces/drag: expected a number in [0, 1e+06], got a non-finite number");
  s = oneParticle();
  s.maxParticles = sim::kMaxParticleBudget + 1;
  EXPECT_NE(message(s).find("/maxParticles: expected at most 20000000 particles"), std::string::npos);
  s = oneParticle();
  s.forces.vortices.push_back(sim::Vortex{});
  s.forces.vortices[0].axis = glm::vec3(0.0f);
  EXPECT_EQ(message(s), "/forces/vortices/0/axis: expected a non-zero direction, got [0, 0, 0]");
  s = oneParticle();
  s.substeps = 0;
  EXPECT_EQ(message(s), "/substeps: expected an integer in [1, 1000], got 0");
  EXPECT_FALSE(Simulator::create(s).ok());
  // Live edits are refused the same way, keeping the old forces.
  auto sim = make(oneParticle());
  sim::Forces bad;
  bad.turbulence.scale = 0.0f;
  auto r = sim->setForces(bad);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "/forces/turbulence/scale: expected a number in [0.0001, 1e+06], got 0");
  EXPECT_EQ(sim->settings().forces.drag, 2.0f);
}

TEST(Simulator, ExtremeValuesNeverGiveNonFinitePositions) {
  for (auto integrator : {sim::Integrator::kExponential, sim::Integrator::kForwardEuler}) {
    Settings s;
    s.fps = 1e4f;  // and a huge step below
    s.substeps = 1;
    s.integrator = integrator;
    s.maxParticles = 5000;
    const float big = sim::kMaxMagnitude;
    s.forces.gravity = glm::vec3(big, -big, big);
    s.forces.buoyancy = big;
    s.forces.drag = big;
    s.forces.wind = glm::vec3(-big, big, big);
    s.forces.turbulence = {big, 1e-4f, 1e3f, 3};
    sim::Vortex v;
    v.strength = -big;
    v.radius = 1e-4f;
    s.forces.vortices.push_back(v);
    sim::WindVolume w;
    w.halfExtent = glm::vec3(big);
    w.velocity = glm::vec3(big);
    s.forces.windVolumes.push_back(w);
    Emitter e;
    e.shape = Emitter::Shape::kSphere;
    e.radius = big;
    e.position = glm::vec3(big);
    e.velocity = glm::vec3(big, -big, big);
    e.rate = 1e7f;
    e.density = 1e3f;
    e.sizeMax = big;
    e.lifetime = 1e6f;
    e.spin = 1e3f;
    e.oriented = true;
    s.emitters.push_back(e);
    sim::Collider ground;
    ground.halfExtent = glm::vec3(big, 0.0f, big);
    s.colliders.push_back(ground);
    for (float fps : {1e4f, 1e-2f}) {
      s.fps = fps;
      auto sim = make(s);
      sim::StepStats st;
      for (int i = 0; i < 50; ++i) {
        sim->step(&st);
        for (std::size_t k = 0; k < sim->size(); ++k) {
          const sim::ParticleState p = sim->particle(k);
          ASSERT_TRUE(std::isfinite(p.position.x) && std::isfinite(p.position.y) && std::isfinite(p.position.z));
          ASSERT_TRUE(std::isfinite(p.size));
        }
      }
      EXPECT_LE(sim->size(), 5000u);
      if (integrator == sim::Integrator::kExponential) {
        // Not by deleting them: nothing overflowed, and particles are there to check.
        EXPECT_EQ(st.nonFinite, 0u) << "fps " << fps;
        EXPECT_GT(sim->size(), 0u) << "fps " << fps;
      }
    }
  }
}

TEST(Simulator, MovingCollidersPushParticlesAside) {
  // A ball on a path sweeps through smoke at rest: at every step no particle is inside it.
  Settings s;
  s.substeps = 2;
  s.forces.drag = 0.0f;
  s.collisionRadius = 0.0f;
  Emitter e;
  e.shape = Emitter::Shape::kSphere;
  e.radius = 2.0f;
  e.velocity = glm::vec3(0.0f);
  e.rate = 24000.0f;
  e.duration = 0.02f;
  e.lifetime = 100.0f;
  s.emitters.push_back(e);
  sim::Collider ball;
  ball.type = sim::Collider::Type::kSphere;
  ball.halfExtent = glm::vec3(0.8f);
  ball.path.times = {0.0f, 2.0f};
  ball.path.points = {glm::vec3(-5.0f, 0.3f, 0.0f), glm::vec3(5.0f, 0.3f, 0.0f)};
  s.colliders.push_back(ball);
  auto sim = make(s);
  sim::StepStats st;
  for (int f = 1; f <= 48; ++f) {
    sim->advanceToFrame(f, &st);
    const glm::vec3 c = ball.path.at(sim->time());
    for (std::size_t i = 0; i < sim->size(); ++i) {
      ASSERT_GE(glm::length(sim->particle(i).position - c), 0.8f - 1e-4f) << "frame " << f;
    }
  }
  EXPECT_GT(st.collisions, 100u);
}

TEST(Simulator, SweepingMeshPushesTheSmokeItCrosses) {
  // A closed cube on a path sweeps through smoke at rest (5 units/s): no particle ends inside it.
  sim::Collider cube;
  cube.type = sim::Collider::Type::kMesh;
  for (int i = 0; i < 8; ++i)
    cube.positions.push_back(glm::vec3(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f));
  cube.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                  2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  cube.path.times = {0.0f, 4.0f};
  cube.path.points = {glm::vec3(-10.0f, 0.0f, 0.0f), glm::vec3(10.0f, 0.0f, 0.0f)};
  Settings s;
  s.substeps = 2;
  s.forces.drag = 0.0f;
  Emitter e;
  e.shape = Emitter::Shape::kSphere;
  e.radius = 0.9f;
  e.velocity = glm::vec3(0.0f);
  e.rate = 24000.0f;
  e.duration = 0.02f;
  e.lifetime = 100.0f;
  s.emitters.push_back(e);
  s.colliders = {cube};
  auto sim = make(s);
  sim::StepStats st;
  for (int f = 1; f <= 72; ++f) {
    sim->advanceToFrame(f, &st);
    const glm::vec3 c = cube.path.at(sim->time());
    for (std::size_t i = 0; i < sim->size(); ++i) {
      const glm::vec3 d = glm::abs(sim->particle(i).position - c);
      ASSERT_FALSE(d.x < 0.999f && d.y < 0.999f && d.z < 0.999f) << "inside the cube at frame " << f;
    }
  }
  EXPECT_GT(st.collisions, 100u);
}
