// A scene's frames evaluated: listed particles, emitters (deterministic, inside their shapes and
// spreads) and the orbiting camera, checked against the motion the scene file promises.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include <puff/cel/types.h>
#include <puff/scene/evaluate.h>

#include "scene_test_helpers.h"

namespace {

using puff::scene::Scene;
using puff::test::parseOk;

// Every field of two particles equal.
void expectSameParticle(const puff::cel::Particle& a, const puff::cel::Particle& b) {
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.size, b.size);
  EXPECT_EQ(a.variation, b.variation);
  EXPECT_EQ(a.oriented, b.oriented);
  EXPECT_EQ(a.orientation, b.orientation);
}

TEST(Scene, ListedParticlesMoveSpinShrinkAndDieOnTime) {
  const Scene s = parseOk(R"({"atlas": "a.json", "animation": {"fps": 10, "frames": 50},
    "particles": [{"position": [1, 2, 3], "size": 2, "variation": 7, "velocity": [1, 0, -2], "birth": 1,
                   "lifetime": 2, "oriented": true, "angularVelocity": [0, 3.14159265, 0]},
                  {"position": [0, 0, 0], "size": 1}]})");
  auto at = [&](int frame) { return puff::scene::particlesAt(s, frame, 8); };
  // Before its birth only the immortal one is drawn.
  ASSERT_EQ(at(5).size(), 1u);
  EXPECT_EQ(at(5)[0].position, glm::vec3(0.0f));
  // Born at t = 1, where it was put, at size 0: it grows in over the first tenth of its life
  // (scene::celBirthGrowth, a smoothstep), so at t = 1.1 (5% of the life) it is half of its
  // shrinking size, 0.5 * 2 * 0.95, and at t = 1.2 all of it, 2 * 0.9.
  auto born = at(10);
  ASSERT_EQ(born.size(), 2u);
  EXPECT_EQ(born[0].position, glm::vec3(1, 2, 3));
  EXPECT_FLOAT_EQ(born[0].size, 0.0f);
  EXPECT_EQ(born[0].variation, 7);
  EXPECT_TRUE(born[0].oriented);
  EXPECT_NEAR(at(11)[0].size, 0.5f * 2.0f * 0.95f, 1e-5f);
  EXPECT_NEAR(at(12)[0].size, 2.0f * 0.9f, 1e-5f);
  // Halfway through its life (t = 2): moved by one second of velocity, half its size, turned 180
  // degrees about y.
  auto half = at(20);
  ASSERT_EQ(half.size(), 2u);
  EXPECT_NEAR(half[0].position.x, 2.0f, 1e-5f);
  EXPECT_NEAR(half[0].position.y, 2.0f, 1e-5f);
  EXPECT_NEAR(half[0].position.z, 1.0f, 1e-5f);
  EXPECT_NEAR(half[0].size, 1.0f, 1e-5f);
  const glm::vec3 turned = half[0].orientation * glm::vec3(1, 0, 0);
  EXPECT_NEAR(turned.x, -1.0f, 1e-5f);
  EXPECT_NEAR(turned.z, 0.0f, 1e-5f);
  // Three quarters: a quarter of its size.
  EXPECT_NEAR(at(25)[0].size, 0.5f, 1e-5f);
  // Dead at t = 3 and after.
  EXPECT_EQ(at(30).size(), 1u);
  EXPECT_EQ(at(45).size(), 1u);
  // The immortal one never shrinks.
  EXPECT_EQ(at(45)[0].size, 1.0f);
}

Scene emitterScene(const std::string& emitter) {
  return parseOk(R"({"atlas": "a.json", "animation": {"fps": 24, "frames": 100}, "emitters": [)" + emitter + "]}");
}

TEST(Scene, FramesArePureFunctionsOfTheFrameNumber) {
  const Scene s = emitterScene(R"({"shape": "sphere", "count": 500, "seed": 9, "oriented": true, "spin": 2,
    "speedSpread": 0.5, "velocity": [0, 1, 0], "birthSpread": 2, "lifetime": 1.5})");
  const auto alone = puff::scene::particlesAt(s, 37, 4);
  std::vector<puff::cel::Particle> afterOthers;
  for (int frame = 0; frame <= 37; ++frame) afterOthers = puff::scene::particlesAt(s, frame, 4);
  ASSERT_EQ(alone.size(), afterOthers.size());
  ASSERT_GT(alone.size(), 0u);
  for (std::size_t i = 0; i < alone.size(); ++i) expectSameParticle(alone[i], afterOthers[i]);
  // A copy of the scene (another process, another machine of the farm) agrees.
  const Scene copy = s;
  const auto again = puff::scene::particlesAt(copy, 37, 4);
  ASSERT_EQ(again.size(), alone.size());
  for (std::size_t i = 0; i < alone.size(); ++i) expectSameParticle(alone[i], again[i]);
}

TEST(Scene, EmittedParticleDependsOnlyOnSeedAndIndex) {
  const Scene few = emitterScene(R"({"count": 10, "seed": 3, "sizeMin": 0.1, "sizeMax": 2})");
  const Scene many = emitterScene(R"({"count": 1000, "seed": 3, "sizeMin": 0.1, "sizeMax": 2})");
  const auto a = puff::scene::particlesAt(few, 0, 4), b = puff::scene::particlesAt(many, 0, 4);
  ASSERT_EQ(a.size(), 10u);
  ASSERT_EQ(b.size(), 1000u);
  for (std::size_t i = 0; i < a.size(); ++i) expectSameParticle(a[i], b[i]);
  // Another seed gives other particles.
  const Scene other = emitterScene(R"({"count": 10, "seed": 4, "sizeMin": 0.1, "sizeMax": 2})");
  EXPECT_NE(puff::scene::particlesAt(other, 0, 4)[0].position, a[0].position);
  // Turning orientation on does not move anyone.
  const Scene oriented = emitterScene(R"({"count": 10, "seed": 3, "sizeMin": 0.1, "sizeMax": 2, "oriented": true})");
  const auto c = puff::scene::particlesAt(oriented, 0, 4);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(c[i].position, a[i].position);
    EXPECT_EQ(c[i].size, a[i].size);
    EXPECT_TRUE(c[i].oriented);
  }
}

TEST(Scene, EmittersPlaceParticlesInsideTheirShapes) {
  const int n = 4000;
  {
    const Scene s = emitterScene(R"({"shape": "sphere", "count": 4000, "center": [1, 2, 3], "radius": 2,
                                     "sizeMin": 0.5, "sizeMax": 1.5, "variations": [2, 5]})");
    const auto ps = puff::scene::particlesAt(s, 0, 8);
    ASSERT_EQ(ps.size(), static_cast<std::size_t>(n));
    glm::vec3 mean(0.0f);
    int inner = 0, two = 0;
    for (const auto& p : ps) {
      const float r = glm::length(p.position - glm::vec3(1, 2, 3));
      EXPECT_LE(r, 2.0f + 1e-5f);
      inner += r < 1.0f;  // 1/8 of the ball's volume
      EXPECT_GE(p.size, 0.5f);
      EXPECT_LE(p.size, 1.5f);
      EXPECT_TRUE(p.variation == 2 || p.variation == 5) << p.variation;
      two += p.variation == 2;
      EXPECT_FALSE(p.oriented);
      mean += p.position / static_cast<float>(n);
    }
    EXPECT_NEAR(mean.x, 1.0f, 0.1f);
    EXPECT_NEAR(mean.y, 2.0f, 0.1f);
    EXPECT_NEAR(mean.z, 3.0f, 0.1f);
    EXPECT_NEAR(inner / static_cast<double>(n), 0.125, 0.02);
    EXPECT_NEAR(two / static_cast<double>(n), 0.5, 0.05);
  }
  {
    const Scene s = emitterScene(R"({"shape": "box", "count": 4000, "center": [0, 1, 0], "halfExtent": [3, 0.5, 1],
                                     "sizeMin": 1, "sizeMax": 1, "sizeFalloff": 1})");
    const auto ps = puff::scene::particlesAt(s, 0, 3);
    ASSERT_EQ(ps.size(), static_cast<std::size_t>(n));
    int variations[3] = {};
    for (const auto& p : ps) {
      const glm::vec3 q = (p.position - glm::vec3(0, 1, 0)) / glm::vec3(3, 0.5, 1);
      const float edge = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
      EXPECT_LE(edge, 1.0f + 1e-5f);
      // Falloff 1: size 1 at the centre, 0 at the faces.
      EXPECT_NEAR(p.size, 1.0f - edge, 1e-4f);
      ASSERT_GE(p.variation, 0);
      ASSERT_LT(p.variation, 3);
      ++variations[p.variation];
    }
    for (int v : variations) EXPECT_NEAR(v / static_cast<double>(n), 1.0 / 3.0, 0.05);
  }
  {
    const Scene s = emitterScene(R"({"shape": "cone", "count": 4000, "center": [0, 0, 0], "end": [0, 0, 10],
                                     "radius": 0.5, "endRadius": 2, "velocity": [1, 0, 0], "speedSpread": 0.25})");
    const auto ps = puff::scene::particlesAt(s, 0, 1);
    ASSERT_EQ(ps.size(), static_cast<std::size_t>(n));
    for (const auto& p : ps) {
      const float along = p.position.z / 10.0f;
      EXPECT_GE(along, -1e-6f);
      EXPECT_LE(along, 1.0f + 1e-6f);
      const float r = glm::length(glm::vec2(p.position.x, p.position.y));
      EXPECT_LE(r, 0.5f + 1.5f * along + 1e-4f);
      EXPECT_EQ(p.variation, 0);
    }
  }
}

TEST(Scene, EmittedVelocitiesBirthsAndSpinsStayWithinTheirSpreads) {
  // At t = 1 s a particle born at b has moved (t - b) * v; births lie in [0, birthSpread].
  const Scene s = parseOk(R"({"atlas": "a.json", "animation": {"fps": 1, "frames": 3},
    "emitters": [{"shape": "sphere", "count": 2000, "radius": 0, "velocity": [2, 0, 0], "speedSpread": 0.5,
                  "birthSpread": 0.5, "oriented": true, "spin": 1}]})");
  const auto at0 = puff::scene::particlesAt(s, 0, 1);
  const auto at1 = puff::scene::particlesAt(s, 1, 1);
  ASSERT_EQ(at1.size(), 2000u);  // all born by t = 0.5
  EXPECT_LT(at0.size(), 2000u);  // only those born at exactly 0 are there at t = 0 (almost none)
  for (const auto& p : at1) {
    // Displacement = (1 - birth) * velocity with |velocity - (2,0,0)| <= 0.5 and birth in [0, 0.5].
    EXPECT_GE(p.position.x, 0.5f * 1.5f - 1e-4f);
    EXPECT_LE(p.position.x, 1.0f * 2.5f + 1e-4f);
    EXPECT_LE(glm::length(glm::vec2(p.position.y, p.position.z)), 0.5f + 1e-4f);
    EXPECT_TRUE(p.oriented);
    EXPECT_NEAR(glm::length(p.orientation), 1.0f, 1e-5f);
  }
}

TEST(Scene, ConeParticlesNearTheEndAreBornLaterSoTheTrailGrows) {
  const Scene s = parseOk(R"({"atlas": "a.json", "animation": {"fps": 10, "frames": 30},
    "emitters": [{"shape": "cone", "count": 3000, "center": [0, 0, 0], "end": [0, 8, 0], "radius": 0.1,
                  "endRadius": 1, "birthSpread": 2}]})");
  for (int frame : {0, 5, 10, 15, 20, 25}) {
    const float t = frame / 10.0f;
    const auto ps = puff::scene::particlesAt(s, frame, 1);
    float reach = 0.0f;
    for (const auto& p : ps) {
      // Born at s * birthSpread, s = y / 8: nothing beyond y = 8 t / 2 is alive yet.
      EXPECT_LE(p.position.y, 8.0f * t / 2.0f + 1e-3f) << "frame " << frame;
      reach = std::max(reach, p.position.y);
    }
    if (frame >= 5 && frame <= 20) {
      EXPECT_GT(reach, 8.0f * t / 2.0f - 0.1f) << "frame " << frame;  // and the trail has reached there
      EXPECT_NEAR(ps.size() / 3000.0, std::min(1.0, t / 2.0), 0.05) << "frame " << frame;
    }
  }
  EXPECT_EQ(puff::scene::particlesAt(s, 25, 1).size(), 3000u);
}

TEST(Scene, CameraOrbitsTheTargetAboutTheVerticalAxis) {
  const Scene s = parseOk(R"({"camera": {"position": [4, 2, 0], "target": [1, 1, 0]},
                             "animation": {"fps": 2, "frames": 10, "orbit": 90}})");
  const auto c0 = puff::scene::cameraAt(s, 0);
  EXPECT_EQ(c0.position, glm::vec3(4, 2, 0));
  // Frame 2 = 1 s = 90 degrees counter-clockwise seen from above: +x turns to -z.
  const auto c2 = puff::scene::cameraAt(s, 2);
  EXPECT_NEAR(c2.position.x, 1.0f, 1e-5f);
  EXPECT_NEAR(c2.position.y, 2.0f, 1e-5f);
  EXPECT_NEAR(c2.position.z, -3.0f, 1e-5f);
  EXPECT_EQ(c2.target, glm::vec3(1, 1, 0));
  EXPECT_NEAR(glm::length(c2.up - glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
  EXPECT_FLOAT_EQ(puff::scene::frameTime(s, 3), 1.5f);
  // No orbit: the scene's camera as it is.
  const Scene still = parseOk(R"({"animation": {"fps": 2, "frames": 10}})");
  EXPECT_EQ(puff::scene::cameraAt(still, 7).position, still.camera.position);
}

}  // namespace

namespace {

// A preroll simulates time before frame 0; it fills something only when an emitter starts in it.
TEST(SceneWarnings, APrerollNoEmitterFillsIsNamed) {
  using puff::scene::sceneWarnings;
  const auto sim = [](const char* preroll, const char* start) {
    return std::string(R"({"atlas": "a.json", "simulation": {"preroll": )") + preroll +
           R"(, "emitters": [{"rate": 10, "start": )" + start + "}, {\"rate\": 5}]}}";
  };
  std::vector<std::string> w = sceneWarnings(parseOk(sim("2", "0").c_str()));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0],
            "/simulation/preroll: 2 s are simulated before frame 0, but no emitter starts before 0, so they fill "
            "nothing (an emitter meant to fill them starts at -2)");
  EXPECT_TRUE(sceneWarnings(parseOk(sim("2", "-2").c_str())).empty()) << "one emitter fills it";
  EXPECT_TRUE(sceneWarnings(parseOk(sim("2", "-0.5").c_str())).empty()) << "one emitter fills part of it";
  EXPECT_TRUE(sceneWarnings(parseOk(sim("0", "0").c_str())).empty()) << "no preroll";
  w = sceneWarnings(parseOk(R"({"media": {"preroll": 1.5, "emitters": [{"material": "fire", "rate": 30}]}})"));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].rfind("/media/preroll: 1.5 s are simulated before frame 0", 0), 0u) << w[0];
  EXPECT_TRUE(sceneWarnings(parseOk("{}")).empty());
}

}  // namespace
