// Rigid bodies: scene objects with "dynamic" simulated with ODE (scene/bodies.h), checked
// against closed forms (free fall under semi-implicit Euler, a free spin, restitution's rebound
// height, momentum), for determinism, for what the scene format accepts, and for the smoke they
// push.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <puff/scene/bodies.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/geometry.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

#include "support/assert_ok.h"

namespace puff::scene {
namespace {

namespace fs = std::filesystem;

Scene parsed(const nlohmann::json& j) {
  auto s = parseScene(j, "bodies.json");
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return s.ok() ? *s : Scene{};
}

std::string error(const nlohmann::json& j) {
  auto s = parseScene(j, "bodies.json");
  return s.ok() ? std::string("(read)") : s.error().message;
}

// A scene of `objects`, `seconds` long at 24 fps.
nlohmann::json world(nlohmann::json objects, double seconds, nlohmann::json rigid = nullptr) {
  nlohmann::json j = {{"objects", std::move(objects)},
                      {"animation", {{"fps", 24}, {"frames", static_cast<int>(std::lround(seconds * 24))}}}};
  if (!rigid.is_null()) j["rigidBodies"] = std::move(rigid);
  return j;
}

const nlohmann::json kGround = {{"type", "plane"}, {"scale", {20, 1, 20}}};

glm::vec3 centreAt(const ObjectSpec& o, double t) { return glm::vec3(objectTransform(o, t)[3]); }

// Semi-implicit Euler (ODE's step) under gravity g: y_n = y0 + v0 t - g t^2 / 2 - g dt t / 2 exactly,
// x moves at its velocity, and a free sphere spins at its angular velocity.
TEST(RigidBodies, AFreeBodyFallsAndSpinsAsTheClosedFormSays) {
  const Scene s = parsed(world({{{"type", "sphere"},
                                 {"translate", {0, 10, 0}},
                                 {"scale", {0.5, 0.5, 0.5}},
                                 {"dynamic", {{"velocity", {1, 2, 0}}, {"angularVelocity", {0, 2, 0}}}}}},
                               1.0));
  const ObjectSpec& ball = s.objects[0];
  ASSERT_EQ(ball.path.times.size(), 241u) << "a key at 0 and after each of 240 steps";
  ASSERT_EQ(ball.path.rotations.size(), 241u);
  const double g = 9.81, dt = 1.0 / 240.0;
  for (int f = 0; f <= 24; ++f) {
    const double t = f / 24.0;
    const glm::vec3 c = centreAt(ball, t);
    EXPECT_NEAR(c.x, t, 1e-4) << "frame " << f;
    EXPECT_NEAR(c.y, 10.0 + 2.0 * t - 0.5 * g * t * t - 0.5 * g * dt * t, 2e-4) << "frame " << f;
    EXPECT_NEAR(c.z, 0.0, 1e-6);
    const glm::quat want = glm::angleAxis(static_cast<float>(2.0 * t), glm::vec3(0, 1, 0));
    EXPECT_GT(std::abs(glm::dot(ball.path.rotationAt(t), want)), 1.0f - 1e-5f) << "frame " << f;
  }
  // Before the scene starts a body holds its first place; t = 0 is where the scene put it.
  EXPECT_EQ(centreAt(ball, -1.0), glm::vec3(0, 10, 0));
}

// Dropped from rest, a ball of restitution e rises again to about e^2 of its fall (the contact's
// soft layer and the step take a little): within 10%, for e from 0.3 to 0.9; e = 0 stays down.
TEST(RigidBodies, ABallReboundsToRestitutionSquaredOfItsFall) {
  for (double e : {0.0, 0.3, 0.6, 0.9}) {
    SCOPED_TRACE("restitution " + std::to_string(e));
    const Scene s = parsed(world({kGround,
                                  {{"type", "sphere"},
                                   {"translate", {0, 2.5, 0}},
                                   {"scale", {0.5, 0.5, 0.5}},
                                   {"dynamic", {{"restitution", e}, {"friction", 0}}}}},
                                 2.0));
    const sim::Path& p = s.objects[1].path;
    // The first contact: the lowest point before the velocity turns up; then the highest after it.
    std::size_t bottom = 0;
    while (bottom + 1 < p.points.size() && p.points[bottom + 1].y <= p.points[bottom].y) ++bottom;
    float apex = p.points[bottom].y;
    for (std::size_t i = bottom; i < p.points.size(); ++i) apex = std::max(apex, p.points[i].y);
    const double fall = 2.0;  // its bottom from 2.0 above the ground to 0
    const double bottomHeight = 2.5 + p.points[bottom].y - 0.5;
    EXPECT_NEAR(bottomHeight, 0.0, 0.02) << "it stops on the ground, not in it";
    const double rise = apex - p.points[bottom].y;
    std::printf("restitution %.1f: rebound %.3f of a %.1f fall (e^2 fall %.3f)\n", e, rise, fall, e * e * fall);
    if (e == 0.0) {
      EXPECT_LT(rise, 0.01);
    } else {
      EXPECT_NEAR(rise, e * e * fall, 0.1 * e * e * fall);
    }
  }
}

// A box dropped tilted onto the ground comes to rest lying flat on it.
TEST(RigidBodies, ATiltedBoxComesToRestFlatOnTheGround) {
  const Scene s = parsed(world({kGround,
                                {{"type", "box"},
                                 {"translate", {0, 2, 0}},
                                 {"rotate", {0, 0, 30}},
                                 {"scale", {0.5, 0.25, 0.5}},
                                 {"dynamic", {{"restitution", 0.1}, {"friction", 0.8}}}}},
                               4.0));
  const ObjectSpec& box = s.objects[1];
  const glm::mat4 m = objectTransform(box, 4.0);
  const glm::vec3 c(m[3]);
  EXPECT_NEAR(c.y, 0.25, 0.02) << "resting on its broad face: the centre a half height up";
  EXPECT_LT(glm::distance(c, centreAt(box, 3.5)), 2e-3f) << "at rest";
  // Its local y axis points straight up (or down).
  const glm::vec3 up = glm::normalize(glm::vec3(m[1]));
  EXPECT_GT(std::abs(up.y), 0.999f);
}

// Two equal balls meeting head on with restitution 1 and no gravity swap velocities; momentum is
// conserved whatever the restitution.
TEST(RigidBodies, EqualBallsMeetingHeadOnConserveMomentum) {
  for (double e : {1.0, 0.5}) {
    SCOPED_TRACE("restitution " + std::to_string(e));
    const Scene s = parsed(world({{{"type", "sphere"},
                                   {"translate", {-2, 0, 0}},
                                   {"scale", {0.5, 0.5, 0.5}},
                                   {"dynamic", {{"velocity", {2, 0, 0}}, {"restitution", e}, {"friction", 0}}}},
                                  {{"type", "sphere"},
                                   {"translate", {2, 0, 0}},
                                   {"scale", {0.5, 0.5, 0.5}},
                                   {"dynamic", {{"velocity", {-2, 0, 0}}, {"restitution", e}, {"friction", 0}}}}},
                                 2.0, {{"gravity", {0, 0, 0}}}));
    const double t = 1.9, dt = 0.1;
    const float v1 = (centreAt(s.objects[0], t + dt) - centreAt(s.objects[0], t)).x / static_cast<float>(dt);
    const float v2 = (centreAt(s.objects[1], t + dt) - centreAt(s.objects[1], t)).x / static_cast<float>(dt);
    std::printf("restitution %.1f: velocities after %.3f and %.3f\n", e, v1, v2);
    EXPECT_NEAR(v1 + v2, 0.0, 0.02) << "momentum";
    EXPECT_NEAR(v1, -2.0 * e, 0.1 * 2.0) << "after the collision";
    EXPECT_NEAR(v2, 2.0 * e, 0.1 * 2.0);
  }
}

// A keyframed object is a kinematic body: it pushes a ball in its way, however heavy (100 kg here),
// and is not pushed back.
TEST(RigidBodies, AKeyframedObjectPushesABody) {
  const Scene s =
      parsed(world({{{"type", "box"},
                     {"translate", {-2, 0, 0}},
                     {"scale", {0.5, 0.5, 0.5}},
                     {"path", {{{"time", 0}, {"position", {0, 0, 0}}}, {{"time", 1}, {"position", {4, 0, 0}}}}}},
                    {{"type", "sphere"},
                     {"translate", {1, 0, 0}},
                     {"scale", {0.4, 0.4, 0.4}},
                     {"dynamic", {{"mass", 100}, {"friction", 0}}}}},
                   1.0, {{"gravity", {0, 0, 0}}}));
  EXPECT_EQ(centreAt(s.objects[0], 1.0), glm::vec3(2, 0, 0)) << "the keyframed box keeps its path";
  EXPECT_GT(centreAt(s.objects[1], 1.0).x, 2.0f + 0.5f + 0.4f - 0.02f) << "pushed at least ahead of the box";
}

// A keyframed plane is a moving floor: a box resting on it rides up with it, its bottom on the plane
// (the slab lies under the plane's square as it moves, as it does under a still one).
TEST(RigidBodies, ABoxRidesAKeyframedPlaneUp) {
  const Scene s = parsed(world(
      {{{"type", "plane"},
        {"scale", {5, 1, 5}},
        {"path", {{{"time", 0}, {"position", {0, 0, 0}}}, {{"time", 2}, {"position", {0, 1, 0}}}}}},
       {{"type", "box"}, {"translate", {0, 0.3, 0}}, {"scale", {0.3, 0.3, 0.3}}, {"dynamic", {{"restitution", 0}}}}},
      2.0));
  for (double t : {0.5, 1.0, 2.0}) {
    const float floor = centreAt(s.objects[0], t).y;
    EXPECT_NEAR(centreAt(s.objects[1], t).y, floor + 0.3f, 0.02f) << "t " << t;
  }
}

// The same scene gives bit-identical trajectories every time it is read, so a frame alone equals
// the same frame in a sequence; the trajectory is not written back, and reads back the same.
// Mesh objects collide with bodies through their triangles, scaled and turned as drawn: a ball
// dropped on a slab mesh rests on its top (a mesh object is its file moved into the unit sphere:
// this 4 x 0.2 x 4 slab becomes k times it, centred, k = 1 / sqrt(8.01), so its top is at 0.1 k, or
// 0.2 k stretched twice as tall), and on the slab tilted 20 degrees about z it rolls down towards
// -x, never sinking into it.
TEST(RigidBodies, ABallRestsOnAMeshAndRollsDownAMeshRamp) {
  const fs::path dir = fs::temp_directory_path() /
                       ("puff-bodies-mesh-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::create_directories(dir);
  const fs::path slab = dir / "slab.obj";
  {
    // A 4 x 0.2 x 4 box, y from 0 to 0.2, faces counter-clockwise from outside.
    std::FILE* f = std::fopen(slab.c_str(), "w");
    ASSERT_NE(f, nullptr);
    for (int i = 0; i < 8; ++i)
      std::fprintf(f, "v %d %g %d\n", (i & 1) ? 2 : -2, (i & 2) ? 0.2 : 0.0, (i & 4) ? 2 : -2);
    const int faces[12][3] = {{1, 5, 7}, {1, 7, 3}, {2, 4, 8}, {2, 8, 6}, {1, 2, 6}, {1, 6, 5},
                              {3, 7, 8}, {3, 8, 4}, {1, 3, 4}, {1, 4, 2}, {5, 6, 8}, {5, 8, 7}};
    for (const auto& t : faces) std::fprintf(f, "f %d %d %d\n", t[0], t[1], t[2]);
    std::fclose(f);
  }
  auto ball = [](double x, double y) {
    return nlohmann::json{{"type", "sphere"},
                          {"translate", {x, y, 0}},
                          {"scale", {0.5, 0.5, 0.5}},
                          {"dynamic", {{"restitution", 0.0}, {"friction", 0.6}}}};
  };
  for (double height : {1.0, 2.0}) {
    SCOPED_TRACE("slab scaled " + std::to_string(height) + " in y");
    const Scene s =
        parsed(world({{{"type", "mesh"}, {"mesh", slab.string()}, {"scale", {1, height, 1}}}, ball(0.3, 2.0)}, 2.0));
    const glm::vec3 c = centreAt(s.objects[1], 2.0);
    const double k = 1.0 / std::sqrt(8.01);
    EXPECT_NEAR(c.y, 0.1 * k * height + 0.5, 0.01) << "on the slab's top, not through it";
    EXPECT_NEAR(c.x, 0.3, 0.01);
  }
  // Four times as wide and deep, so the ball stays on it: its top is the plane dot(n, p) = 0.1 k.
  const Scene ramp = parsed(
      world({{{"type", "mesh"}, {"mesh", slab.string()}, {"scale", {4, 1, 4}}, {"rotate", {0, 0, 20}}}, ball(0.0, 0.7)},
            1.25));
  const glm::vec3 n(-std::sin(glm::radians(20.0f)), std::cos(glm::radians(20.0f)), 0.0f);  // the top's normal
  const float top = 0.1f / std::sqrt(8.01f);
  float deepest = 1e9f;
  for (int f = 6; f <= 30; ++f) deepest = std::min(deepest, glm::dot(n, centreAt(ramp.objects[1], f / 24.0)) - top);
  EXPECT_NEAR(deepest, 0.5f, 0.01f) << "the ball's centre stays a radius above the tilted top";
  EXPECT_LT(centreAt(ramp.objects[1], 1.25).x, -0.5f) << "it rolled down towards -x";
  // A mesh that does not load is named.
  const std::string e = error(world({{{"type", "mesh"}, {"mesh", (dir / "missing.obj").string()}}, ball(0, 2)}, 1.0));
  EXPECT_NE(e.find("/objects/0/mesh"), std::string::npos) << e;
  fs::remove_all(dir);
}

TEST(RigidBodies, TrajectoriesAreTheSameEveryTimeAndRoundTrip) {
  const nlohmann::json j = world({kGround,
                                  {{"type", "box"},
                                   {"name", "crate"},
                                   {"translate", {0, 3, 0}},
                                   {"rotate", {20, 10, 35}},
                                   {"scale", {0.4, 0.3, 0.5}},
                                   {"dynamic", {{"mass", 3}, {"angularVelocity", {1, 2, 3}}, {"restitution", 0.5}}}},
                                  {{"type", "sphere"},
                                   {"translate", {0.2, 5, 0.1}},
                                   {"scale", {0.3, 0.3, 0.3}},
                                   {"dynamic", {{"velocity", {0, -1, 0}}}}}},
                                 3.0);
  const Scene a = parsed(j), b = parsed(j);
  ASSERT_EQ(a.objects.size(), 3u);
  EXPECT_EQ(a.objects[1].path, b.objects[1].path);
  EXPECT_EQ(a.objects[2].path, b.objects[2].path);
  const nlohmann::json written = toJson(a);
  EXPECT_FALSE(written["objects"][1].contains("path")) << "the simulation is not written back";
  EXPECT_EQ(written["objects"][1]["dynamic"]["mass"], 3);
  const Scene c = parsed(written);
  EXPECT_EQ(c.objects, a.objects);
  EXPECT_EQ(c.rigidBodies, a.rigidBodies);
}

TEST(RigidBodies, BadBodiesNameTheField) {
  const auto with = [](nlohmann::json object) { return world({kGround, std::move(object)}, 1.0); };
  EXPECT_NE(error(with({{"type", "plane"}, {"dynamic", nlohmann::json::object()}}))
                .find("/objects/1/dynamic: only a box or a sphere can be dynamic"),
            std::string::npos);
  EXPECT_NE(error(with({{"type", "box"},
                        {"path", {{{"time", 0}, {"position", {0, 0, 0}}}}},
                        {"dynamic", nlohmann::json::object()}}))
                .find("/objects/1/dynamic: a dynamic object moves as it is simulated"),
            std::string::npos);
  EXPECT_NE(error(with({{"type", "box"}, {"dynamic", {{"mass", 0}}}})).find("/objects/1/dynamic/mass"),
            std::string::npos);
  EXPECT_NE(error(with({{"type", "box"}, {"dynamic", {{"restitution", 1.5}}}})).find("/objects/1/dynamic/restitution"),
            std::string::npos);
  EXPECT_NE(error(with({{"type", "box"}, {"dynamic", {{"bounce", 1}}}})).find("/objects/1/dynamic/bounce: unknown key"),
            std::string::npos);
  nlohmann::json slow = with({{"type", "box"}, {"dynamic", nlohmann::json::object()}});
  slow["rigidBodies"] = {{"stepsPerSecond", 5}};
  EXPECT_NE(error(slow).find("/rigidBodies/stepsPerSecond"), std::string::npos);
  EXPECT_NE(error(with({{"type", "box"}, {"scale", {1e-4, 1, 1}}, {"dynamic", nlohmann::json::object()}}))
                .find("/objects/1/scale: a dynamic object's scale must be in [0.001, 10000]"),
            std::string::npos);
  EXPECT_NE(
      error(with({{"type", "sphere"}, {"dynamic", {{"velocity", {1e5, 0, 0}}}}})).find("/objects/1/dynamic/velocity"),
      std::string::npos);
  // A body flung as fast as the scene allows, with a step as long as it allows, against a wall at
  // point-blank range: whatever ODE makes of it, the scene reads or fails with one line, no crash.
  const std::string flung = error(
      world({{{"type", "box"}, {"translate", {0.6, 0, 0}}, {"scale", {0.1, 5, 5}}},
             {{"type", "sphere"},
              {"scale", {1e-3, 1e-3, 1e-3}},
              {"dynamic", {{"mass", 1e6}, {"velocity", {1e4, 1e4, 1e4}}, {"angularVelocity", {1e4, -1e4, 1e4}}}}}},
            10.0, {{"stepsPerSecond", 24}, {"gravity", {1e4, 1e4, 1e4}}}));
  EXPECT_TRUE(flung == "(read)" ||
              flung.find("/objects/1/dynamic: the rigid-body simulation diverged") != std::string::npos)
      << flung;
  // A tiny fps makes an astronomical duration: refused, not a crash.
  nlohmann::json slowFrames = with({{"type", "box"}, {"dynamic", nlohmann::json::object()}});
  slowFrames["animation"] = {{"fps", 1e-20}, {"frames", 1}};
  EXPECT_NE(error(slowFrames).find("/rigidBodies: 1 dynamic objects over"), std::string::npos) << error(slowFrames);
  nlohmann::json crowd = world(nlohmann::json::array(), 0.1);
  for (int i = 0; i < 257; ++i) {
    crowd["objects"].push_back({{"type", "sphere"}, {"translate", {i, 0, 0}}, {"dynamic", nlohmann::json::object()}});
  }
  EXPECT_NE(error(crowd).find("/objects/256/dynamic: at most 256 dynamic objects"), std::string::npos);
  nlohmann::json longRun = with({{"type", "box"}, {"dynamic", nlohmann::json::object()}});
  longRun["animation"] = {{"fps", 1}, {"frames", 100000}};
  longRun["rigidBodies"] = {{"stepsPerSecond", 10000}};
  EXPECT_NE(error(longRun).find("/rigidBodies: 1 dynamic objects over"), std::string::npos) << error(longRun);
}

// Smoke collides with a dynamic body as with a keyframed one: a spinning box falling through a
// still cloud leaves no particle inside it at any frame (in the box's turned frame); without its
// collisions many are.
TEST(RigidBodies, SmokeIsKeptOutOfASpinningFallingBox) {
  const auto scene = [](bool collide) {
    nlohmann::json j = world({{{"type", "box"},
                               {"collide", collide},
                               {"translate", {0, 2.5, 0}},
                               {"scale", {0.6, 0.3, 0.4}},
                               {"dynamic", {{"angularVelocity", {0, 0, 4}}}}}},
                             1.0);
    j["atlas"] = "a.json";
    j["simulation"] = {{"substeps", 4},
                       {"collisionRadius", 0},
                       {"forces", {{"drag", 1}, {"buoyancy", 0}}},
                       {"emitters",
                        {{{"shape", "sphere"},
                          {"position", {0, 0.6, 0}},
                          {"radius", 0.9},
                          {"rate", 3000},
                          {"duration", 0.2},
                          {"velocity", {0, 0, 0}},
                          {"lifetime", 5},
                          {"seed", 4}}}}};
    return parsed(j);
  };
  int inside[2] = {0, 0}, particles = 0;
  for (bool collide : {true, false}) {
    const Scene s = scene(collide);
    auto geometry = loadGeometry(s);
    ASSERT_OK(geometry);
    auto e = FrameEvaluator::create(s, *geometry, 1, MediaEvaluation::kSkip);
    ASSERT_OK(e);
    for (int f = 0; f <= 24; ++f) {
      const FrameInputs in = (*e)->evaluate(f);
      const glm::mat4 toBox = glm::inverse(objectTransform(s.objects[0], frameTime(s, f)));
      for (const cel::Particle& p : in.particles) {
        const glm::vec3 local = glm::vec3(toBox * glm::vec4(p.position, 1.0f));  // the unit box's frame
        if (glm::all(glm::lessThan(glm::abs(local), glm::vec3(1.0f - 1e-3f)))) ++inside[collide ? 0 : 1];
        particles += collide ? 1 : 0;
      }
    }
  }
  std::printf("%d particle-frames; inside the box: %d with collisions, %d without\n", particles, inside[0], inside[1]);
  EXPECT_GT(particles, 10000);
  EXPECT_EQ(inside[0], 0) << "with collisions";
  EXPECT_GT(inside[1], 100) << "without them the falling box passes through the cloud";
}

// An edit in memory (puffview's rigid-body panel) simulates again and moves what rides on the body,
// exactly as reading the edited scene does; a refused edit changes nothing.
TEST(RigidBodies, AnEditInMemoryIsTheEditedSceneRead) {
  const auto scene = [](double vx) {
    nlohmann::json j = world({kGround,
                              {{"type", "sphere"},
                               {"name", "ball"},
                               {"translate", {0, 2, 0}},
                               {"scale", {0.4, 0.4, 0.4}},
                               {"dynamic", {{"velocity", {vx, 0, 0}}}}}},
                             1.0);
    j["atlas"] = "a.json";
    j["simulation"] = {{"emitters", {{{"attach", "ball"}, {"rate", 20}, {"lifetime", 1}}}},
                       {"forces", {{"vortices", {{{"attach", "ball"}}}}}}};
    return j;
  };
  Scene edited = parsed(scene(1.0));
  const Scene wanted = parsed(scene(3.0));
  ASSERT_NE(edited.objects[1].path, wanted.objects[1].path);
  edited.objects[1].dynamic->velocity.x = 3.0f;
  ASSERT_OK(updateBodies(edited));
  EXPECT_EQ(edited.objects[1].path, wanted.objects[1].path);
  EXPECT_EQ(edited.simulation->emitters[0].path, wanted.simulation->emitters[0].path);
  EXPECT_EQ(edited.simulation->forces.vortices[0].path, wanted.simulation->forces.vortices[0].path);
  EXPECT_EQ(edited, wanted);
  Scene refused = edited;
  refused.animation.frames = 100000000;
  refused.animation.fps = 1.0f;
  const Scene before = refused;
  EXPECT_FALSE(updateBodies(refused).ok());
  EXPECT_EQ(refused, before);
}

// The art scene (art/scenes/bouncing-ball.json, golden-tested at frame 30): its ball bounces along
// the ground, never in it, each bounce lower than the last (restitution 0.75), moving on.
TEST(RigidBodies, TheBouncingBallSceneBouncesAlongTheGround) {
  auto s = loadScene(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / "bouncing-ball.json", PUFF_ART_DIR);
  ASSERT_OK(s);
  const ObjectSpec& ball = s->objects[1];
  ASSERT_EQ(ball.name, "ball");
  const sim::Path& p = ball.path;
  std::vector<float> apexes, lows;
  for (std::size_t i = 1; i + 1 < p.points.size(); ++i) {
    const float y0 = p.points[i - 1].y, y1 = p.points[i].y, y2 = p.points[i + 1].y;
    if (y1 > y0 && y1 >= y2) apexes.push_back(ball.translate.y + y1);
    if (y1 < y0 && y1 <= y2) lows.push_back(ball.translate.y + y1);
  }
  ASSERT_GE(lows.size(), 3u) << "three bounces in three seconds";
  for (float low : lows) EXPECT_NEAR(low, 0.45f, 0.03f) << "the ball's bottom on the ground";
  for (std::size_t i = 1; i < apexes.size(); ++i) EXPECT_LT(apexes[i], apexes[i - 1]) << "bounce " << i;
  EXPECT_GT(apexes.size() > 1 ? apexes[1] : 0.0f, 1.5f) << "the first rebound rises a metre or more";
  EXPECT_GT(centreAt(ball, 3.0).x, centreAt(ball, 0.0).x + 5.0f) << "it travels";
}

}  // namespace
}  // namespace puff::scene
