// The smoke simulator: analytic checks of each force and of the integrator, collisions, dissipation,
// determinism, and bad or extreme input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include <puff/sim/simulator.h>

#include "../../runtime/src/sim/curl_noise.h"
#include "support/assert_ok.h"

using namespace puff;
using sim::Emitter;
using sim::Settings;
using sim::Simulator;

namespace {

// One particle, born at t = 0.5 / rate inside the first step... made simpler: an emitter with a
// tiny window so exactly one particle is born, at rest at the origin, living `lifetime` seconds.
Settings oneParticle(float lifetime = 1000.0f, glm::vec3 velocity = glm::vec3(0.0f)) {
  Settings s;
  s.fps = 24.0f;
  s.substeps = 1;
  Emitter e;
  e.rate = 1000.0f;
  e.start = 0.0f;
  e.duration = 0.001f;  // one birth, at 0.0005 s
  e.velocity = velocity;
  e.sizeMin = e.sizeMax = 1.0f;
  e.lifetime = lifetime;
  s.emitters.push_back(e);
  return s;
}

std::unique_ptr<Simulator> make(const Settings& s, int variations = 1) {
  auto r = Simulator::create(s, variations);
  EXPECT_OK(r);
  return r ? std::move(*r) : nullptr;
}

}  // namespace

TEST(Simulator, DragDecayIsExactForAnyStep) {
  // dv/dt = -k v has v(t) = v0 exp(-k t): the exponential integrator reproduces it for any k h.
  for (float drag : {0.5f, 24.0f, 100.0f}) {
    Settings s = oneParticle(1000.0f, glm::vec3(10.0f, 0.0f, 0.0f));
    s.forces.drag = drag;
    auto sim = make(s);
    sim->step();  // birth (moved ballistically to the end of the step)
    ASSERT_EQ(sim->size(), 1u);
    const float v0 = sim->particle(0).velocity.x;
    const double t0 = sim->time();
    for (int i = 0; i < 12; ++i) sim->step();
    const double expected = v0 * std::exp(-static_cast<double>(drag) * (sim->time() - t0));
    EXPECT_NEAR(sim->particle(0).velocity.x, expected, 1e-5 * expected) << "drag " << drag;
  }
}

TEST(Simulator, TinyDragIsTheBallisticLimit) {
  // The integrator never divides by the drag: 1e-3 down to a denormal drag gives the drag-0 motion.
  auto run = [](float drag) {
    Settings s = oneParticle(1000.0f, glm::vec3(1.0f, 2.0f, 0.0f));
    s.substeps = 4;
    s.forces.gravity = glm::vec3(0.0f, -9.8f, 0.0f);
    s.forces.drag = drag;
    auto sim = make(s);
    sim->advanceToFrame(48);
    EXPECT_EQ(sim->size(), 1u);
    return sim->particle(0);
  };
  const sim::ParticleState ballistic = run(0.0f);
  for (float drag : {1e-3f, 1e-5f, 1e-8f, 1e-40f}) {
    const sim::ParticleState p = run(drag);
    EXPECT_NEAR(p.velocity.y, ballistic.velocity.y, 2e-3f * std::abs(ballistic.velocity.y) + 1e-5f) << drag;
    EXPECT_NEAR(p.position.y, ballistic.position.y, 2e-3f * std::abs(ballistic.position.y) + 1e-5f) << drag;
  }
  // Forces act from the first whole step after the birth step: 2 s less one step of gravity.
  EXPECT_NEAR(ballistic.velocity.y, 2.0f - 9.8f * (2.0f - 1.0f / 96.0f), 1e-3f);
}

TEST(Simulator, ForwardEulerDivergesWherePuffStaysBounded) {
  // drag * step = 60 / 24 = 2.5 > 2: forward Euler multiplies the velocity error by |1 - 2.5| = 1.5
  // per step; the exponential integrator by exp(-2.5).
  const glm::vec3 wind(1.0f, 0.0f, 0.0f);
  for (auto integrator : {sim::Integrator::kForwardEuler, sim::Integrator::kExponential}) {
    Settings s = oneParticle(1000.0f, glm::vec3(0.0f, 5.0f, 0.0f));
    s.forces.drag = 60.0f;
    s.forces.wind = wind;
    s.integrator = integrator;
    auto sim = make(s);
    sim::StepStats st;
    sim->step(&st);
    ASSERT_EQ(sim->size(), 1u);
    const float error0 = glm::length(sim->particle(0).velocity - wind);
    float worst = error0;
    for (int i = 0; i < 400 && sim->size() == 1; ++i) {
      sim->step(&st);
      if (sim->size() == 1) worst = std::max(worst, glm::length(sim->particle(0).velocity - wind));
    }
    if (integrator == sim::Integrator::kForwardEuler) {
      // Diverged: grew by orders of magnitude, or overflowed and was removed as non-finite.
      EXPECT_TRUE(worst > 1e6f * error0 || st.nonFinite == 1) << "worst " << worst;
    } else {
      ASSERT_EQ(sim->size(), 1u);
      EXPECT_LE(worst, error0 * 1.0001f);
      EXPECT_LT(glm::length(sim->particle(0).velocity - wind), 1e-5f);  // and it settles on the air
    }
  }
}

TEST(Simulator, GravityWithDragReachesTerminalVelocity) {
  Settings s = oneParticle();
  s.forces.gravity = glm::vec3(0.0f, -9.81f, 0.0f);
  s.forces.drag = 4.0f;
  auto sim = make(s);
  for (int i = 0; i < 24 * 6; ++i) sim->step();  // 24 time constants
  EXPECT_NEAR(sim->particle(0).velocity.y, -9.81f / 4.0f, 1e-4f);
}

TEST(Simulator, WithoutDragMotionIsBallisticAndExact) {
  Settings s = oneParticle(1000.0f, glm::vec3(1.0f, 2.0f, 0.0f));
  s.forces.gravity = glm::vec3(0.0f, -10.0f, 0.0f);
  s.forces.drag = 0.0f;
  auto sim = make(s);
  sim->step();
  const sim::ParticleState a = sim->particle(0);
  for (int i = 0; i < 24; ++i) sim->step();
  const float t = 1.0f;  // 24 steps of 1/24 s
  const glm::vec3 expected = a.position + a.velocity * t + 0.5f * glm::vec3(0.0f, -10.0f, 0.0f) * t * t;
  EXPECT_LT(glm::length(sim->particle(0).position - expected), 1e-4f);
}

TEST(Simulator, BuoyancyIsProportionalToDensity) {
  // Terminal upward speed buoyancy * density / drag, density falling linearly with age.
  Settings s = oneParticle(100.0f);
  s.emitters[0].density = 2.0f;
  s.forces.buoyancy = 3.0f;
  s.forces.drag = 10.0f;
  auto sim = make(s);
  for (int i = 0; i < 48; ++i) sim->step();
  const sim::ParticleState p = sim->particle(0);
  EXPECT_NEAR(p.density, 2.0f * (1.0f - static_cast<float>(sim->time() - 0.0005) / 100.0f), 1e-4f);
  // The target moves as the density falls: it lags by about (d target / dt) / drag.
  EXPECT_NEAR(p.velocity.y, 3.0f * p.density / 10.0f, 1e-3f);
}

TEST(Simulator, VortexSwirlPeaksAtStrengthAroundTheAxis) {
  Settings s;
  sim::Vortex v;
  v.position = glm::vec3(1.0f, 0.0f, 2.0f);
  v.axis = glm::vec3(0.0f, 0.0f, 3.0f);  // normalized on use
  v.strength = 5.0f;
  v.radius = 0.4f;
  s.forces.vortices.push_back(v);
  auto sim = make(s);
  // Tangential, counter-clockwise about +z, peaking at strength at r = 1.12092 core radii.
  const float rPeak = 1.12092f * 0.4f;
  const glm::vec3 u = sim->airVelocity(v.position + glm::vec3(rPeak, 0.0f, 0.7f));
  EXPECT_NEAR(u.x, 0.0f, 1e-6f);
  EXPECT_NEAR(u.z, 0.0f, 1e-6f);
  EXPECT_NEAR(u.y, 5.0f, 1e-3f);
  // Lamb-Oseen: ~ 1/r far out, ~ r inside the core.
  const float far = sim->airVelocity(v.position + glm::vec3(0.0f, 8.0f, 0.0f)).x;
  EXPECT_NEAR(far, -5.0f * 0.4f / 0.638172f / 8.0f, 1e-4f);
  const float inner = glm::length(sim->airVelocity(v.position + glm::vec3(0.004f, 0.0f, 0.0f)));
  EXPECT_NEAR(inner, 5.0f / 0.638172f * 0.004f / 0.4f, 1e-4f);
  EXPECT_EQ(glm::length(sim->airVelocity(v.position)), 0.0f);  // on the axis

  // A falloff ends the swirl; a length bounds it along the axis.
  s.forces.vortices[0].falloff = 1.0f;
  s.forces.vortices[0].length = 1.0f;
  auto bounded = make(s);
  EXPECT_LT(glm::length(bounded->airVelocity(v.position + glm::vec3(0.0f, 5.0f, 0.0f))), 1e-9f);
  EXPECT_LT(glm::length(bounded->airVelocity(v.position + glm::vec3(rPeak, 0.0f, 3.0f))), 1e-9f);
  EXPECT_NEAR(glm::length(bounded->airVelocity(v.position + glm::vec3(rPeak, 0.0f, 0.0f))),
              5.0f * std::exp(-rPeak * rPeak), 1e-3f);
}

TEST(Simulator, ParticlesCarriedByAVortexCircleIt) {
  // With strong drag a particle follows the air: it goes round the axis at a near-constant radius.
  Settings s = oneParticle();
  s.emitters[0].position = glm::vec3(1.0f, 0.0f, 0.0f);
  s.substeps = 8;
  s.forces.drag = 200.0f;
  sim::Vortex v;
  v.axis = glm::vec3(0.0f, 1.0f, 0.0f);
  v.strength = 2.0f;
  v.radius = 0.5f;
  s.forces.vortices.push_back(v);
  auto sim = make(s);
  float lo = 1e9f, hi = 0.0f, turned = 0.0f;
  glm::vec3 last(1.0f, 0.0f, 0.0f);
  for (int i = 0; i < 24 * 8 * 5; ++i) {
    sim->step();
    const glm::vec3 p = sim->particle(0).position;
    const float r = std::hypot(p.x, p.z);
    lo = std::min(lo, r), hi = std::max(hi, r);
    turned += std::atan2(last.x * p.z - last.z * p.x, last.x * p.x + last.z * p.z);
    last = p;
  }
  // 1.54 units/s at r = 1 (two core radii): a turn takes 4.1 s.
  EXPECT_GT(std::abs(turned), 2.0f * 3.14159f);
  // A particle lagging the air drifts outward by about v^2 / (r drag) = 0.012 units/s.
  EXPECT_GT(lo, 0.99f);
  EXPECT_LT(hi, 1.1f);
}

TEST(Simulator, WindVolumesBlowInsideAndFeatherOut) {
  Settings s;
  s.forces.wind = glm::vec3(0.1f, 0.0f, 0.0f);
  sim::WindVolume w;
  w.center = glm::vec3(0.0f);
  w.halfExtent = glm::vec3(1.0f);
  w.velocity = glm::vec3(0.0f, 0.0f, 4.0f);
  w.feather = 1.0f;
  s.forces.windVolumes.push_back(w);
  auto sim = make(s);
  EXPECT_EQ(sim->airVelocity(glm::vec3(0.5f, 0.0f, 0.0f)), glm::vec3(0.1f, 0.0f, 4.0f));
  EXPECT_EQ(sim->airVelocity(glm::vec3(2.5f, 0.0f, 0.0f)), glm::vec3(0.1f, 0.0f, 0.0f));
  EXPECT_NEAR(sim->airVelocity(glm::vec3(1.5f, 0.0f, 0.0f)).z, 2.0f, 1e-6f);  // smoothstep(0.5)
}

TEST(Simulator, TurbulenceIsDivergenceFree) {
  // The analytic curl field has zero divergence; the lattice the simulator samples stays close to
  // it, where the gradient of the same noise (a field with no curl) has divergence of order 1.
  const puff::sim::detail::CurlField field(7);
  const puff::sim::detail::GradientNoise potential(7 * 3 + 1, 4);
  const float e = 1e-3f;
  auto divergence = [&](auto&& f, const glm::vec3& p) {
    return ((f(p + glm::vec3(e, 0, 0)).x - f(p - glm::vec3(e, 0, 0)).x) +
            (f(p + glm::vec3(0, e, 0)).y - f(p - glm::vec3(0, e, 0)).y) +
            (f(p + glm::vec3(0, 0, e)).z - f(p - glm::vec3(0, 0, e)).z)) /
           (2.0f * e);
  };
  auto exact = [&](const glm::vec3& p) { return field.exact(p); };
  auto lattice = [&](const glm::vec3& p) { return field.sample(p); };
  auto gradient = [&](const glm::vec3& p) {
    glm::vec3 g;
    potential.eval(p * 4.0f, &g);
    return g;
  };
  double divExact = 0, divLattice = 0, divGradient = 0, speedExact = 0, speedGradient = 0;
  std::uint32_t h = 12345;
  auto next = [&] {
    h = h * 1664525u + 1013904223u;
    return static_cast<float>(h >> 8) / 16777216.0f;
  };
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    const float z = next(), y = next(), x = next();  // one draw a statement, z first
    const glm::vec3 p(x, y, z);
    divExact += std::pow(divergence(exact, p), 2.0f);
    divLattice += std::pow(divergence(lattice, p), 2.0f);
    divGradient += std::pow(divergence(gradient, p), 2.0f);
    speedExact += glm::dot(exact(p), exact(p));
    speedGradient += glm::dot(gradient(p), gradient(p));
  }
  // Divergence relative to speed / feature size (1/4 of a tile): dimensionless.
  const double relExact = std::sqrt(divExact / speedExact) / 4.0;
  const double relLattice = std::sqrt(divLattice / speedExact) / 4.0;
  const double relGradient = std::sqrt(divGradient / speedGradient) / 4.0;
  EXPECT_LT(relExact, 1e-3);
  EXPECT_GT(relGradient, 0.5);
  EXPECT_LT(relLattice, 0.1 * relGradient);
}

TEST(Simulator, DissipationShrinksLinearlyToNothing) {
  Settings s = oneParticle(2.0f);
  s.emitters[0].sizeMin = s.emitters[0].sizeMax = 3.0f;
  s.forces.drag = 0.0f;
  auto sim = make(s);
  float last = 3.0f;
  int steps = 0;
  for (; steps < 200; ++steps) {
    sim->step();
    if (sim->size() == 0) break;
    const sim::ParticleState p = sim->particle(0);
    const float age = static_cast<float>(sim->time() - 0.0005);
    EXPECT_NEAR(p.size, 3.0f * (1.0f - age / 2.0f), 1e-4f);
    EXPECT_LE(p.size, last);
    last = p.size;
  }
  EXPECT_EQ(steps, 48);        // gone when its 2 s are up (48 steps of 1/24 s)
  EXPECT_LT(last, 3.0f / 40);  // and its last size was a sliver: no pop
}

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
