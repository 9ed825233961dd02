// The smoke simulator's forces and integrator, checked analytically: drag, gravity, buoyancy,
// vortices, wind volumes, turbulence and dissipation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>

#include <puff/sim/simulator.h>

#include "../../runtime/src/sim/curl_noise.h"
#include "sim_test_helpers.h"

using namespace puff;
using puff::test::make;
using puff::test::oneParticle;
using sim::Settings;

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
