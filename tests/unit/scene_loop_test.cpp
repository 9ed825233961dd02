// A scene as a loop (animation.period): read and written, refused where something would not repeat
// (named by its pointer), and passed to both simulators so frame f + period is frame f.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include <puff/scene/evaluate.h>
#include <puff/scene/geometry.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

namespace puff::scene {
namespace {

// A steady plume of puffs and of fire, beside a table and a lamp: everything here repeats.
constexpr const char* kLoop = R"({
  "atlas": "a.json",
  "particles": [{"position": [0, 1, 0], "size": 0.5}],
  "emitters": [{"count": 20, "seed": 3, "radius": 2}],
  "objects": [{"type": "plane", "name": "table", "scale": [10, 1, 10]},
              {"type": "sphere", "name": "lamp", "translate": [0, 0.5, 0]}],
  "animation": {"fps": 24, "frames": 48, "period": 24},
  "simulation": {"preroll": 2,
                 "forces": {"buoyancy": 1, "drag": 1, "turbulence": {"strength": 0.5, "speed": 3}},
                 "emitters": [{"rate": 40, "velocity": [0, 1, 0], "lifetime": 1.5, "seed": 5, "attach": "lamp"}]},
  "media": {"emitters": [{"material": "fire", "rate": 30, "lifetime": 1.7, "seed": 2, "duration": 0.3}],
            "lights": [{"intensity": [{"time": 0, "value": 2}, {"time": 1, "value": 2}]}],
            "motionBlur": {"frames": 2}}
})";

nlohmann::json loop() { return nlohmann::json::parse(kLoop); }

std::string refusal(const nlohmann::json& j) {
  auto s = parseScene(j, "loop.json");
  return s ? std::string("accepted") : s.error().message;
}

TEST(SceneLoop, ThePeriodIsReadCheckedAndWritten) {
  auto s = parseScene(loop(), "loop.json");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->animation.period, 24);
  EXPECT_EQ(toJson(*s)["animation"]["period"], 24);
  EXPECT_TRUE(sceneWarnings(*s).empty()) << "a loop fills its own preroll";
  // A loop that may reach its budget: 40 births a second living 1.5 s in a 1 s loop hold up to
  // 40 x 2 = 80 puffs.
  s->simulation->maxParticles = 79;
  ASSERT_EQ(sceneWarnings(*s).size(), 1u);
  EXPECT_EQ(sceneWarnings(*s)[0],
            "/simulation/maxParticles: the loop's emitters may hold up to 80 particles at once, more than this "
            "budget (79): the births it drops fall differently each period, so the loop does not repeat");
  s->simulation->maxParticles = 80;
  EXPECT_TRUE(sceneWarnings(*s).empty());
  auto j = loop();
  j["animation"]["period"] = -1;
  EXPECT_EQ(refusal(j), "loop.json: /animation/period: expected an integer in [0, 100000], got -1");
  j["animation"]["period"] = 2.5;
  EXPECT_NE(refusal(j).find("/animation/period: expected an integer"), std::string::npos);
}

TEST(SceneLoop, WhatDoesNotRepeatIsNamed) {
  const std::string tail = " does not repeat every period of a loop";
  struct Case {
    const char* pointer;  // where the change goes (a JSON pointer into kLoop)
    nlohmann::json value;
    std::string error;
  };
  const nlohmann::json moving = {{{"time", 0}, {"position", {0, 0, 0}}}, {{"time", 1}, {"position", {1, 0, 0}}}};
  const nlohmann::json still = {{{"time", 0}, {"position", {0, 0, 0}}}, {{"time", 1}, {"position", {0, 0, 0}}}};
  for (const Case& c : {
           Case{"/animation/orbit", 5, "/animation/orbit: a camera that orbits" + tail},
           Case{"/animation/cameraPath", moving, "/animation/cameraPath: a camera that moves" + tail},
           Case{"/animation/targetPath", moving, "/animation/targetPath: a camera target that moves" + tail},
           Case{"/objects/1/path", moving, "/objects/1/path: an object (lamp) that moves" + tail},
           Case{"/objects/1/dynamic", {{"mass", 1}}, "/objects/1/dynamic: a rigid body (lamp) that falls" + tail},
           Case{"/particles/0/velocity", {0, 1, 0}, "/particles/0: a listed particle that moves or turns" + tail},
           Case{"/particles/0/birth", 0.5, "/particles/0: a listed particle that is born or dies" + tail},
           Case{"/particles/0/lifetime", 3, "/particles/0: a listed particle that is born or dies" + tail},
           Case{"/emitters/0/velocity", {0, 1, 0}, "/emitters/0: placed particles that move or turn do not repeat"},
           Case{"/emitters/0/lifetime", 2, "/emitters/0: placed particles that are born or die do not repeat"},
           Case{"/media/lights/0/intensity/1/value", 0, "/media/lights/0/intensity: a light whose intensity changes"},
           Case{"/simulation/emitters/0/attach", nullptr, ""},  // see below: an emitter on its own path
           Case{"/media/emitters/0/path", moving, "/media/emitters/0/path: an emitter on a path"},
       }) {
    SCOPED_TRACE(c.pointer);
    auto j = loop();
    if (c.value.is_null()) {
      j["simulation"]["emitters"][0].erase("attach");
      j["simulation"]["emitters"][0]["path"] = moving;
      EXPECT_NE(refusal(j).find("loop.json: /simulation/emitters/0/path: an emitter on a path (or attached to a "
                                "moving object) does not repeat every period of a loop"),
                std::string::npos)
          << refusal(j);
      continue;
    }
    j[nlohmann::json::json_pointer(c.pointer)] = c.value;
    EXPECT_NE(refusal(j).find("loop.json: " + c.error), std::string::npos) << refusal(j);
    // Without the loop, the same scene is fine.
    j["animation"]["period"] = 0;
    EXPECT_EQ(refusal(j), "accepted");
  }
  // Keys that hold still are no motion: an object's path of one place, an emitter riding on it.
  auto j = loop();
  j["objects"][1]["path"] = still;
  EXPECT_EQ(refusal(j), "accepted");
  // Detail videos play a whole number of times a period: 8 frames a second of a 16-frame video
  // over 3 s is 1.5 plays, rounded to 2 (10.67 frames a second); under half a play holds still.
  EXPECT_FLOAT_EQ(loopDetailSpeed(8.0f, 3.0, 16), 32.0f / 3.0f);
  EXPECT_FLOAT_EQ(loopDetailSpeed(7.0f, 1.0, 16), 0.0f);
  EXPECT_FLOAT_EQ(loopDetailSpeed(16.0f, 2.0, 16), 16.0f);
  EXPECT_FLOAT_EQ(loopDetailSpeed(8.0f, 0.0, 16), 8.0f) << "no loop";
  EXPECT_FLOAT_EQ(loopDetailSpeed(1000.0f, 1.0, 64), 960.0f) << "16 plays would pass the limit: 15";
  EXPECT_LE(loopDetailSpeed(media::kMaxDetailSpeed, 1.0, 64), media::kMaxDetailSpeed);
}

// The period reaches both simulators: frame f + period holds frame f's particles and media.
TEST(SceneLoop, FramesRepeatAPeriodLater) {
  auto s = parseScene(loop(), "loop.json");
  ASSERT_TRUE(s.ok());
  auto geometry = loadGeometry(*s);
  ASSERT_TRUE(geometry.ok());
  auto e = FrameEvaluator::create(*s, *geometry, 4, MediaEvaluation::kEvaluate);
  ASSERT_TRUE(e.ok()) << e.error().message;
  for (int f : {0, 5, 23}) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const FrameInputs a = (*e)->evaluate(f), b = (*e)->evaluate(f + 24);
    ASSERT_EQ(a.particles.size(), b.particles.size());
    ASSERT_GT(a.particles.size(), 21u) << "the simulation's puffs are there from frame 0";
    for (std::size_t i = 0; i < a.particles.size(); ++i) {
      EXPECT_EQ(a.particles[i].position, b.particles[i].position) << i;
      EXPECT_EQ(a.particles[i].size, b.particles[i].size) << i;
    }
    ASSERT_EQ(a.media.size(), b.media.size());
    ASSERT_GT(a.media.size(), 0u);
    for (std::size_t i = 0; i < a.media.size(); ++i) {
      EXPECT_EQ(a.media[i].position, b.media[i].position) << i;
      EXPECT_EQ(a.media[i].density, b.media[i].density) << i;
    }
  }
}

}  // namespace
}  // namespace puff::scene
