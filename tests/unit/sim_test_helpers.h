// What the simulator's tests share (sim_test.cpp, sim_forces_test.cpp): settings that give one
// particle, and a simulator made from settings.
#pragma once

#include <memory>

#include <glm/vec3.hpp>

#include <puff/sim/simulator.h>

#include "support/assert_ok.h"

namespace puff::test {

// Settings whose one emitter has a window so short that exactly one particle is born (at
// 0.0005 s, inside the first step), at the origin with `velocity`, living `lifetime` seconds.
inline sim::Settings oneParticle(float lifetime = 1000.0f, glm::vec3 velocity = glm::vec3(0.0f)) {
  sim::Settings s;
  s.fps = 24.0f;
  s.substeps = 1;
  sim::Emitter e;
  e.rate = 1000.0f;
  e.start = 0.0f;
  e.duration = 0.001f;  // one birth, at 0.0005 s
  e.velocity = velocity;
  e.sizeMin = e.sizeMax = 1.0f;
  e.lifetime = lifetime;
  s.emitters.push_back(e);
  return s;
}

// A simulator of `s` (a failure to make one fails the test and gives null).
inline std::unique_ptr<sim::Simulator> make(const sim::Settings& s, int variations = 1) {
  auto r = sim::Simulator::create(s, variations);
  EXPECT_OK(r);
  return r ? std::move(*r) : nullptr;
}

}  // namespace puff::test
