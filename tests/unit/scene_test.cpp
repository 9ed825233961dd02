// Scene files: every field optional, every mistake named by its JSON pointer, presets, and the frame
// evaluation checked against the motion it promises (scene_roundtrip_test.cpp: the round trip).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <sys/stat.h>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <puff/scene/evaluate.h>
#include <puff/scene/geometry.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>
#include <puff/support/json_read.h>

#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using puff::scene::EmitterSpec;
using puff::scene::ObjectSpec;
using puff::scene::Scene;

const fs::path kFile = "art/scenes/x.json";

Scene parseOk(const std::string& text, const fs::path& artDir = {}) {
  auto s = puff::scene::parseScene(json::parse(text), kFile, artDir);
  EXPECT_OK(s);
  return s.ok() ? *s : Scene{};
}

std::string parseError(const json& j, const fs::path& artDir = {}) {
  auto s = puff::scene::parseScene(j, kFile, artDir);
  EXPECT_FALSE(s.ok());
  return s.ok() ? std::string() : s.error().message;
}
std::string parseError(const std::string& text) { return parseError(json::parse(text)); }

void expectSameParticle(const puff::cel::Particle& a, const puff::cel::Particle& b) {
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.size, b.size);
  EXPECT_EQ(a.variation, b.variation);
  EXPECT_EQ(a.oriented, b.oriented);
  EXPECT_EQ(a.orientation, b.orientation);
}

TEST(Scene, EmptyObjectGivesTheDocumentedDefaults) {
  const Scene s = parseOk("{}");
  EXPECT_EQ(s.file, kFile);
  EXPECT_EQ(s.width, 640);
  EXPECT_EQ(s.height, 480);
  EXPECT_EQ(s.samples, 4);
  EXPECT_EQ(s.background, glm::vec3(1.0f));
  const puff::cel::Camera camera;
  EXPECT_EQ(s.camera.position, camera.position);
  EXPECT_EQ(s.camera.fovYDegrees, camera.fovYDegrees);
  EXPECT_EQ(s.camera.farPlane, camera.farPlane);
  EXPECT_EQ(s.light.direction, puff::cel::Light{}.direction);
  EXPECT_EQ(s.ambientColor, glm::vec3(0.25f));
  EXPECT_TRUE(s.ambientGradient.empty());
  EXPECT_TRUE(s.ramp.empty());
  EXPECT_FALSE(s.rampSmooth);
  EXPECT_TRUE(s.atlas.empty());
  EXPECT_TRUE(s.stylePreset.empty());
  const puff::cel::Style style;
  EXPECT_EQ(s.style.outlines, style.outlines);
  EXPECT_EQ(s.style.shading, style.shading);
  EXPECT_EQ(s.style.shadows, style.shadows);
  EXPECT_EQ(s.style.outlineWidth, style.outlineWidth);
  EXPECT_TRUE(s.particles.empty());
  EXPECT_TRUE(s.emitters.empty());
  EXPECT_TRUE(s.objects.empty());
  EXPECT_EQ(s.animation.fps, 24.0f);
  EXPECT_EQ(s.animation.frames, 1);
  EXPECT_EQ(s.animation.orbitDegreesPerSecond, 0.0f);
}

TEST(Scene, DefaultsInsideListsComeFromTheSpecStructs) {
  const Scene s =
      parseOk(R"({"atlas": "a.json", "particles": [{}], "emitters": [{}], "objects": [{}, {"type": "box"}]})");
  ASSERT_EQ(s.particles.size(), 1u);
  EXPECT_EQ(s.particles[0].size, 1.0f);
  EXPECT_EQ(s.particles[0].lifetime, 0.0f);
  ASSERT_EQ(s.emitters.size(), 1u);
  EXPECT_EQ(s.emitters[0].count, 100);
  EXPECT_EQ(s.emitters[0].shape, EmitterSpec::Shape::kSphere);
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0].type, ObjectSpec::Type::kPlane);
  EXPECT_EQ(s.objects[0].name, "objects/0");
  EXPECT_EQ(s.objects[1].name, "objects/1");
  EXPECT_TRUE(s.objects[0].cel);
}

TEST(Scene, ValuesAreRead) {
  const Scene s = parseOk(R"({
    "output": {"width": 320, "height": 200.0, "samples": 8, "background": "#ff8000"},
    "camera": {"position": [1, 2, 3], "target": [0, 1, 0], "fovY": 0, "orthoHeight": 5, "near": 0.5, "far": 50},
    "light": {"direction": [0, 1, 0], "color": [1, 0.5, 0.25]},
    "ambient": {"color": [0.1, 0.2, 0.3]},
    "ramp": {"image": "ramps/three.png", "smooth": true},
    "objects": [{"type": "sphere", "name": "ball", "translate": [0, 1, 0], "rotate": [0, 90, 0],
                 "scale": [2, 2, 2], "albedo": "#808080", "shading": "smooth"}],
    "animation": {"fps": 30, "frames": 48, "orbit": 15}
  })");
  EXPECT_EQ(s.width, 320);
  EXPECT_EQ(s.height, 200);
  EXPECT_EQ(s.samples, 8);
  EXPECT_EQ(s.background, glm::vec3(1.0f, 128.0f / 255.0f, 0.0f));
  EXPECT_EQ(s.camera.position, glm::vec3(1, 2, 3));
  EXPECT_EQ(s.camera.fovYDegrees, 0.0f);
  EXPECT_EQ(s.camera.orthoHeight, 5.0f);
  EXPECT_EQ(s.light.color, glm::vec3(1.0f, 0.5f, 0.25f));
  EXPECT_EQ(s.ramp, fs::path("art/scenes/ramps/three.png"));
  EXPECT_TRUE(s.rampSmooth);
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].type, ObjectSpec::Type::kSphere);
  EXPECT_EQ(s.objects[0].name, "ball");
  EXPECT_FALSE(s.objects[0].cel);
  EXPECT_EQ(s.objects[0].rotateDegrees, glm::vec3(0, 90, 0));
  EXPECT_EQ(s.animation.fps, 30.0f);
  EXPECT_EQ(s.animation.frames, 48);
  EXPECT_EQ(s.animation.orbitDegreesPerSecond, 15.0f);
}

TEST(Scene, PathsResolveAgainstTheSceneDirectoryAndTheArtDirectory) {
  const Scene s = parseOk(R"({"atlas": "${PUFF_ART}/default/puff.json", "ramp": "../ramps/two-tone.png",
                              "ambient": {"gradient": "/abs/gradient.png"},
                              "objects": [{"type": "mesh", "mesh": "rock.obj"}]})",
                          "build/art");
  EXPECT_EQ(s.atlas, fs::path("build/art/default/puff.json"));
  EXPECT_EQ(s.ramp, fs::path("art/ramps/two-tone.png"));  // lexically normal
  EXPECT_EQ(s.ambientGradient, fs::path("/abs/gradient.png"));
  EXPECT_EQ(s.objects[0].mesh, fs::path("art/scenes/rock.obj"));
  // "" means none (the built-in ramp).
  EXPECT_TRUE(parseOk(R"({"ramp": ""})").ramp.empty());
}

TEST(Scene, ErrorsNameTheFileThePointerWhatWasExpectedAndWhatCame) {
  const std::string f = kFile.string() + ": ";
  const std::pair<const char*, std::string> cases[] = {
      {R"({"camera": {"fovY": "wide"}})",
       "/camera/fovY: expected a number in (0, 180), or 0 for orthographic, got \"wide\""},
      {R"({"camera": {"fovY": 180}})", "/camera/fovY: expected a number in (0, 180), or 0 for orthographic, got 180"},
      {R"({"camera": {"near": 0}})", "/camera/near: expected a number > 0, got 0"},
      {R"({"camera": {"near": 1, "far": 0.5}})", "/camera/far: expected a number > near (1), got 0.5"},
      {R"({"camera": {"near": 200}})", "/camera/near: expected a number < far (100), got 200"},
      {R"({"camera": {"up": [0, 0, 2]}})",
       "/camera/up: expected a direction not parallel to the view direction (target - position), got [0,0,2]"},
      {R"({"camera": {"up": [0, 0, 0]}})",
       "/camera/up: expected a direction not parallel to the view direction (target - position), got [0,0,0]"},
      {R"({"camera": {"target": [0, 0, 5]}})",
       "/camera/target: expected a point apart from the camera's other point (position != target), got [0,0,5]"},
      {R"({"camera": {"position": [1, 2]}})", "/camera/position: expected an array of 3 numbers, got [1,2]"},
      {R"({"camera": {"position": [1, "x", 3]}})", "/camera/position/1: expected a number, got \"x\""},
      {R"({"camera": {"fov": 30}})",
       "/camera/fov: unknown key, expected one of position, target, up, fovY, orthoHeight, near, far (did you mean "
       "\"fovY\"?)"},
      {R"({"camra": {}})",
       "/camra: unknown key, expected one of output, camera, light, ambient, ramp, atlas, atlasLevel, "
       "particleFraction, style, particles, emitters, "
       "objects, rigidBodies, animation, simulation, fixed, media (did you mean \"camera\"?)"},
      {R"({"output": {"width": 0}})", "/output/width: expected an integer in [1, 16384], got 0"},
      {R"({"output": {"height": 16385}})", "/output/height: expected an integer in [1, 16384], got 16385"},
      {R"({"output": {"width": 640.5}})", "/output/width: expected an integer in [1, 16384], got 640.5"},
      {R"({"output": {"width": "640"}})", "/output/width: expected an integer in [1, 16384], got \"640\""},
      {R"({"output": {"samples": 3}})", "/output/samples: expected 1, 2, 4 or 8, got 3"},
      {R"({"output": {"background": [1.5, 0, 0]}})", "/output/background/0: expected a number in [0, 1], got 1.5"},
      {R"({"output": {"background": "#12345g"}})",
       "/output/background: expected a colour: [r, g, b] in [0, 1] or \"#rrggbb\", got \"#12345g\""},
      {R"({"output": []})", "/output: expected an object, got []"},
      {R"({"light": {"direction": [0, 0, 0]}})",
       "/light/direction: expected a non-zero direction toward the light, got [0,0,0]"},
      {R"({"ambient": {"gradient": 3}})", "/ambient/gradient: expected a path (a string), got 3"},
      {R"({"ramp": 7})", "/ramp: expected a ramp image path or an object {\"image\", \"smooth\"}, got 7"},
      {R"({"ramp": {"smooth": "yes"}})", "/ramp/smooth: expected true or false, got \"yes\""},
      {R"({"style": {"preset": "watercolour"}})",
       "/style/preset: expected one of outlines, cel, cel-shadows, ink, solid, got \"watercolour\""},
      {R"({"style": {"alignment": "sideways"}})",
       "/style/alignment: expected one of view-plane, viewpoint, axial, got \"sideways\""},
      {R"({"style": {"shadowBias": 2}})", "/style/shadowBias: expected a number in [0, 1], got 2"},
      {R"({"style": {"tumble": "spin"}})", "/style/tumble: expected one of hull, blend, got \"spin\""},
      {R"({"style": {"outlineWidth": -1}})", "/style/outlineWidth: expected a number in [0, 64], got -1"},
      {R"({"atlas": "a.json", "particles": [{"variation": 256}]})",
       "/particles/0/variation: expected an integer in [0, 255], got 256"},
      {R"({"atlas": "a.json", "particles": [{}, {"size": -1}]})", "/particles/1/size: expected a number >= 0, got -1"},
      {R"({"atlas": "a.json", "particles": [{"orientation": {"axis": [0, 0, 0], "degrees": 3}}]})",
       "/particles/0/orientation/axis: expected a non-zero rotation axis, got [0,0,0]"},
      {R"({"atlas": "a.json", "particles": [{"lifetime": -2}]})",
       "/particles/0/lifetime: expected a number >= 0, got -2"},
      {R"({"particles": {}})", "/particles: expected an array of particles, got {}"},
      {R"({"particles": [{}]})", "/atlas: expected an atlas sidecar path (the scene has particles), got none"},
      {R"({"emitters": [{"count": 5}]})", "/atlas: expected an atlas sidecar path (the scene has particles), got none"},
      {R"({"atlas": "a.json", "emitters": [{"count": 1000001}]})",
       "/emitters/0/count: expected an integer in [0, 1000000], got 1000001"},
      {R"({"atlas": "a.json", "emitters": [{"count": -1}]})",
       "/emitters/0/count: expected an integer in [0, 1000000], got -1"},
      {R"({"atlas": "a.json", "particles": [{}], "emitters": [{"count": 1000000}, {"count": 1000000}]})",
       "/emitters/1/count: the scene's particles (listed and emitted) come to 2000001 here; at most 2000000 are "
       "allowed"},
      {R"({"atlas": "a.json", "emitters": [{"sizeMin": 2, "sizeMax": 1}]})",
       "/emitters/0/sizeMax: expected a number >= sizeMin (2), got 1"},
      {R"({"atlas": "a.json", "emitters": [{"sizeMin": 2}]})",
       "/emitters/0/sizeMin: expected a number <= sizeMax (1), got 2"},
      {R"({"atlas": "a.json", "emitters": [{"shape": "torus"}]})",
       "/emitters/0/shape: expected one of sphere, box, cone, got \"torus\""},
      {R"({"atlas": "a.json", "emitters": [{"variations": [0, 300]}]})",
       "/emitters/0/variations/1: expected an integer in [0, 255], got 300"},
      {R"({"atlas": "a.json", "emitters": [{"seed": -1}]})",
       "/emitters/0/seed: expected an integer in [0, 4294967295], got -1"},
      {R"({"atlas": "a.json", "emitters": [{"halfExtent": [1, -1, 1]}]})",
       "/emitters/0/halfExtent/1: expected a number >= 0, got -1"},
      {R"({"atlas": "a.json", "emitters": [{"sizeFalloff": 1.5}]})",
       "/emitters/0/sizeFalloff: expected a number in [0, 1], got 1.5"},
      {R"({"objects": [{"type": "mesh"}]})",
       "/objects/0/mesh: expected a mesh file (OBJ, OFF, PLY or STL) for type \"mesh\", got none"},
      {R"({"objects": [{"type": "plane", "mesh": "m.obj"}]})",
       "/objects/0/mesh: expected no mesh (or \"\") unless type is \"mesh\", got \"m.obj\""},
      {R"({"objects": [{"type": "cylinder"}]})",
       "/objects/0/type: expected one of plane, box, sphere, mesh, got \"cylinder\""},
      {R"({"objects": [{"scale": [1, 0, 1]}]})", "/objects/0/scale/1: expected a number > 0, got 0"},
      {R"({"objects": [{"shading": "flat"}]})", "/objects/0/shading: expected one of cel, smooth, got \"flat\""},
      {R"({"animation": {"fps": 0}})", "/animation/fps: expected a number in (0, 1000], got 0"},
      {R"({"animation": {"frames": 0}})", "/animation/frames: expected an integer in [1, 10000000], got 0"},
      {R"({"animation": {"orbit": null}})", "/animation/orbit: expected a number, got null"},
      {R"({"atlas": "${PUFF_ART}/a.json"})",
       "/atlas: \"${PUFF_ART}\" needs an art directory, and none was given (--art-dir)"},
      {R"({"a/b~c": 1})",
       "/a~1b~0c: unknown key, expected one of output, camera, light, ambient, ramp, atlas, atlasLevel, "
       "particleFraction, style, particles, "
       "emitters, objects, rigidBodies, animation, simulation, fixed, media"},
      {R"([1, 2])", "expected a JSON object at the top level, got [1,2]"},
  };
  for (const auto& [text, expected] : cases) EXPECT_EQ(parseError(std::string(text)), f + expected) << text;
}

TEST(Scene, NonFiniteNumbersAreRejected) {
  json j = {{"camera", {{"position", {0.0, std::numeric_limits<double>::quiet_NaN(), 5.0}}}}};
  EXPECT_EQ(parseError(j), kFile.string() + ": /camera/position/1: expected a number, got a non-finite number");
  j = {{"light", {{"direction", {0.0, std::numeric_limits<double>::infinity(), 0.0}}}}};
  EXPECT_EQ(parseError(j), kFile.string() + ": /light/direction/1: expected a number, got a non-finite number");
  // Finite as a double, infinite as a float.
  j = {{"animation", {{"orbit", 1e300}}}};
  EXPECT_EQ(parseError(j), kFile.string() + ": /animation/orbit: expected a number, got 1e+300");
}

class SceneFiles : public ::testing::Test {
 protected:
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  puff::test::ScopedTempDir dir_{"scene_test"};
};

TEST_F(SceneFiles, SyntaxErrorsGiveLineAndColumn) {
  const fs::path p = write("bad.json", "{\n  \"output\": {\"width\": 3,}\n}\n");
  auto s = puff::scene::loadScene(p);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message.rfind(p.string() + ":2:25: ", 0), 0u) << s.error().message;
  EXPECT_NE(s.error().message.find("syntax error"), std::string::npos) << s.error().message;

  const fs::path q = write("bad2.json", "{\"a\": tru}");
  s = puff::scene::loadScene(q);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message.rfind(q.string() + ":1:10: ", 0), 0u) << s.error().message;

  const fs::path empty = write("empty.json", "");
  s = puff::scene::loadScene(empty);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message.rfind(empty.string() + ":1:1: ", 0), 0u) << s.error().message;
}

TEST_F(SceneFiles, OverflowingNumbersInTheFileAreRejected) {
  const fs::path p = write("big.json", R"({"camera": {"fovY": 1e999}})");
  auto s = puff::scene::loadScene(p);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message, p.string() + ":1:21: number 1e999 is out of range");
}

TEST_F(SceneFiles, MissingFileSaysCannotRead) {
  auto s = puff::scene::loadScene(dir_ / "nope.json");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message, (dir_ / "nope.json").string() + ": cannot read: No such file or directory");
  s = puff::scene::loadScene(dir_.path());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message, dir_.path().string() + ": cannot read: is a directory");
}

TEST_F(SceneFiles, LoadedPathsAreRelativeToTheFile) {
  const fs::path p = write("s.json", R"({"atlas": "puff.json", "emitters": [{"count": 1}]})");
  auto s = puff::scene::loadScene(p);
  ASSERT_OK(s);
  EXPECT_EQ(s->atlas, dir_ / "puff.json");
  EXPECT_EQ(s->file, p);
}

TEST(Scene, PresetsSetTheStyleAndExplicitFieldsWin) {
  const auto names = puff::scene::stylePresetNames();
  EXPECT_EQ(names, (std::vector<std::string>{"outlines", "cel", "cel-shadows", "ink", "solid"}));
  for (const std::string& name : names) {
    auto style = puff::scene::stylePreset(name);
    ASSERT_TRUE(style.ok()) << name;
    EXPECT_TRUE(style->outlines) << name;  // every preset draws outlines
    const Scene s = parseOk(R"({"style": {"preset": ")" + name + R"("}})");
    EXPECT_EQ(s.stylePreset, name);
    EXPECT_EQ(s.style.shading, style->shading);
    EXPECT_EQ(s.style.shadows, style->shadows);
    EXPECT_EQ(s.style.outlineWidth, style->outlineWidth);
  }
  EXPECT_FALSE(puff::scene::stylePreset("outlines")->shading);
  EXPECT_TRUE(puff::scene::stylePreset("cel")->shading);
  EXPECT_FALSE(puff::scene::stylePreset("cel")->shadows);
  EXPECT_TRUE(puff::scene::stylePreset("cel-shadows")->shadows);
  EXPECT_TRUE(puff::scene::stylePreset("cel-shadows")->shading);
  EXPECT_FALSE(puff::scene::stylePreset("ink")->shading);
  EXPECT_EQ(puff::scene::stylePreset("ink")->outlineColor, glm::vec3(0.0f));
  EXPECT_FALSE(puff::scene::stylePreset("solid")->shading);
  auto bad = puff::scene::stylePreset("nope");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("outlines, cel, cel-shadows, ink, solid"), std::string::npos);

  // The preset applies first whatever the key order; explicit fields override it.
  const Scene s = parseOk(R"({"style": {"shadows": false, "preset": "cel-shadows", "outlineWidth": 5,
                                        "alignment": "axial"}})");
  EXPECT_FALSE(s.style.shadows);
  EXPECT_TRUE(s.style.shading);
  EXPECT_EQ(s.style.outlineWidth, 5.0f);
  EXPECT_EQ(s.style.alignment, puff::cel::Alignment::kAxial);
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

// ---- the "simulation" section -------------------------------------------------------------------

TEST(SceneSimulation, ReadsForcesEmittersAndPathsAndRoundTrips) {
  const Scene s = parseOk(R"({
    "atlas": "a.json",
    "animation": {"fps": 30},
    "objects": [{"type": "plane", "scale": [5, 1, 5], "friction": 0.25}, {"type": "box", "collide": false}],
    "simulation": {
      "substeps": 3, "preroll": 1.5, "maxParticles": 5000, "collisionRadius": 0.25, "integrator": "forward-euler",
      "forces": {"gravity": [0, -1, 0], "buoyancy": 2, "drag": 5, "wind": [1, 0, 0],
                 "windVolumes": [{"center": [0, 1, 0], "halfExtent": [1, 2, 3], "velocity": [0, 0, 4], "feather": 0.5}],
                 "turbulence": {"strength": 0.3, "scale": 2, "speed": 0.1, "seed": 9},
                 "vortices": [{"position": [1, 2, 3], "axis": [0, 0, 1], "strength": -2, "radius": 0.3, "falloff": 4,
                               "length": 2, "path": [{"time": 0, "position": [0, 0, 0]}, {"time": 2, "position": [4, 0, 0]}],
                               "shedInterval": 0.1, "shedLifetime": 0.5}]},
      "emitters": [{"shape": "disc", "position": [0, 1, 0], "radius": 0.2, "normal": [1, 0, 0], "rate": 50,
                    "start": 0.5, "duration": 2.5, "seed": 4, "velocity": [0, 2, 0], "spread": 15, "speedSpread": 0.1,
                    "inheritVelocity": 0.5, "density": 2, "sizeMin": 0.3, "sizeMax": 0.6, "lifetime": 4,
                    "lifetimeSpread": 0.2, "variations": [1, 2], "oriented": true, "spin": 1,
                    "path": [{"time": 0, "position": [0, 0, 0]}, {"time": 1, "position": [0, 0, 5]}]}]
    }
  })");
  ASSERT_TRUE(s.simulation.has_value());
  const puff::sim::Settings& sim = *s.simulation;
  EXPECT_EQ(sim.fps, 30.0f);
  EXPECT_EQ(sim.substeps, 3);
  EXPECT_EQ(sim.preroll, 1.5f);
  EXPECT_EQ(sim.maxParticles, 5000u);
  EXPECT_EQ(sim.integrator, puff::sim::Integrator::kForwardEuler);
  EXPECT_EQ(sim.forces.windVolumes.at(0).halfExtent, glm::vec3(1, 2, 3));
  EXPECT_EQ(sim.forces.turbulence.seed, 9u);
  ASSERT_EQ(sim.forces.vortices.size(), 1u);
  EXPECT_EQ(sim.forces.vortices[0].path.points.at(1), glm::vec3(4, 0, 0));
  EXPECT_EQ(sim.forces.vortices[0].shedInterval, 0.1f);
  ASSERT_EQ(sim.emitters.size(), 1u);
  EXPECT_EQ(sim.emitters[0].shape, puff::sim::Emitter::Shape::kDisc);
  EXPECT_EQ(sim.emitters[0].variations, (std::vector<int>{1, 2}));
  EXPECT_EQ(sim.emitters[0].spreadDegrees, 15.0f);

  // Colliders come from the objects that collide, placed as they are drawn.
  auto settings = puff::scene::simulationSettings(s, *puff::scene::loadGeometry(s));
  ASSERT_OK(settings);
  ASSERT_EQ((*settings)->colliders.size(), 1u);
  EXPECT_EQ((*settings)->colliders[0].type, puff::sim::Collider::Type::kPlane);
  EXPECT_EQ((*settings)->colliders[0].halfExtent, glm::vec3(5, 0, 5));
  EXPECT_EQ((*settings)->colliders[0].friction, 0.25f);

  // toJson writes every field; reading it back gives the same scene.
  auto again = puff::scene::parseScene(puff::scene::toJson(s), kFile);
  ASSERT_OK(again);
  EXPECT_EQ(puff::scene::toJson(*again), puff::scene::toJson(s));
  EXPECT_EQ(again->simulation->emitters[0].path.times, sim.emitters[0].path.times);
}

TEST(SceneSimulation, ImpossibleValuesNameTheField) {
  const std::string f = kFile.string() + ": ";
  const std::pair<const char*, const char*> cases[] = {
      {R"({"atlas": "a.json", "simulation": {"emitters": [{"rate": -1}]}})",
       "/simulation/emitters/0/rate: expected particles per second in [0, 1e+07], got -1"},
      {R"({"atlas": "a.json", "simulation": {"emitters": [{"lifetime": 0}]}})",
       "/simulation/emitters/0/lifetime: expected a lifetime in seconds > 0, got 0"},
      {R"({"atlas": "a.json", "simulation": {"emitters": [{"sizeMin": 2, "sizeMax": 1}]}})",
       "/simulation/emitters/0/sizeMax: expected a size >= sizeMin (2), got 1"},
      {R"({"simulation": {"maxParticles": 1000000000000}})",
       "/simulation/maxParticles: expected a particle budget in [0, 20000000] (about 64 bytes each; more would not "
       "fit in memory), got 1000000000000"},
      {R"({"simulation": {"forces": {"drag": -3}}})",
       "/simulation/forces/drag: expected a number in [0, 1e+06], got -3"},
      {R"({"simulation": {"forces": {"vortices": [{"axis": [0, 0, 0]}]}}})",
       "/simulation/forces/vortices/0/axis: expected a non-zero direction, got [0,0,0]"},
      {R"({"simulation": {"forces": {"vortices": [{"radius": 0}]}}})",
       "/simulation/forces/vortices/0/radius: expected a number in [0.0001, 1e+06], got 0"},
      {R"({"simulation": {"forces": {"turbulence": {"scale": 0}}}})",
       "/simulation/forces/turbulence/scale: expected a number in [0.0001, 1e+06], got 0"},
      {R"({"simulation": {"forces": {"wind": [1e9, 0, 0]}}})",
       "/simulation/forces/wind/0: expected a number in [-1e+06, 1e+06], got 1000000000.0"},
      {R"({"simulation": {"forces": {"vortices": [{"path": [{"time": 1, "position": [0, 0, 0]},
                                                            {"time": 1, "position": [1, 0, 0]}]}]}}})",
       "/simulation/forces/vortices/0/path/1/time: expected a time after the previous key (1), got 1"},
      {R"({"simulation": {"substeps": 0}})", "/simulation/substeps: expected an integer in [1, 1000], got 0"},
      {R"({"simulation": {"integrator": "rk4"}})",
       "/simulation/integrator: expected one of exponential, forward-euler, got \"rk4\""},
      {R"({"simulation": {"emitters": [{"shape": "cone"}]}})",
       "/simulation/emitters/0/shape: expected one of point, sphere, disc, got \"cone\""},
      {R"({"simulation": {"forces": {"drgg": 1}}})",
       "/simulation/forces/drgg: unknown key, expected one of gravity, buoyancy, up, drag, wind, windVolumes, "
       "turbulence, vortices (did you mean \"drag\"?)"},
      {R"({"simulation": {"emitters": [{}]}})",
       "/atlas: expected an atlas sidecar path (the scene has particles), got none"},
      {R"({"objects": [{"friction": 2}]})", "/objects/0/friction: expected a number in [0, 1], got 2"},
  };
  for (const auto& [text, expected] : cases) EXPECT_EQ(parseError(std::string(text)), f + expected) << text;
}

TEST(SceneSimulation, VorticesAndEmittersRideOnMovingObjects) {
  const Scene s = parseOk(R"({
    "atlas": "a.json",
    "objects": [{"type": "box", "name": "plane body", "translate": [0, 5, 0],
                 "path": [{"time": 0, "position": [-10, 0, 0]}, {"time": 4, "position": [10, 0, 0]}]},
                {"type": "sphere", "name": "still"}],
    "simulation": {"forces": {"vortices": [{"attach": "plane body", "position": [1, 0, 0]}]},
                   "emitters": [{"attach": "still", "position": [0, 2, 0]}]}
  })");
  const puff::sim::Vortex& v = s.simulation->forces.vortices.at(0);
  // The object's path, offset by where the object stands; the vortex's position is on top.
  EXPECT_EQ(v.path.at(2.0) + v.position, glm::vec3(1, 5, 0));
  EXPECT_EQ(v.path.at(4.0) + v.position, glm::vec3(11, 5, 0));
  EXPECT_EQ(s.simulation->emitters.at(0).path.at(7.0) + s.simulation->emitters.at(0).position, glm::vec3(0, 2, 0));
  // The object is drawn where the path puts it, and collides there.
  const glm::mat4 at1 = puff::scene::objectTransform(s.objects[0], 1.0);
  EXPECT_EQ(glm::vec3(at1[3]), glm::vec3(-5, 5, 0));
  auto settings = puff::scene::simulationSettings(s, *puff::scene::loadGeometry(s));
  ASSERT_TRUE(settings.ok());
  EXPECT_EQ((*settings)->colliders.at(0).path.at(1.0) + (*settings)->colliders[0].center, glm::vec3(-5, 5, 0));
  // Written back as the link, and read again to the same thing.
  const json j = puff::scene::toJson(s);
  EXPECT_EQ(j["simulation"]["forces"]["vortices"][0]["attach"], "plane body");
  EXPECT_TRUE(j["simulation"]["forces"]["vortices"][0]["path"].empty());
  auto again = puff::scene::parseScene(j, kFile);
  ASSERT_OK(again);
  EXPECT_EQ(puff::scene::toJson(*again), j);

  EXPECT_EQ(
      parseError(
          std::string(R"({"objects": [{"name": "a"}], "simulation": {"forces": {"vortices": [{"attach": "b"}]}}})")),
      kFile.string() + ": /simulation/forces/vortices/0/attach: expected the name of a scene object (a), got \"b\"");
}

TEST(SceneSimulation, ColliderAndAttachProblemsNameTheObject) {
  // An object that is fine to draw but too far out to simulate: named by the object, not by a
  // collider list the file does not have.
  const Scene far =
      parseOk(R"({"objects": [{"type": "box", "collide": false}, {"type": "sphere", "translate": [3e6, 0, 0]}],
                                "simulation": {}})");
  auto settings = puff::scene::simulationSettings(far, *puff::scene::loadGeometry(far));
  ASSERT_FALSE(settings.ok());
  EXPECT_EQ(settings.error().message,
            kFile.string() + ": /objects/1 (as a collider): expected a number in [-1e+06, 1e+06], got 3e+06");
  EXPECT_EQ(parseError(std::string(
                R"({"objects": [{"name": "a"}, {"name": "a"}], "simulation": {"emitters": [{"attach": "a"}]}})")),
            kFile.string() +
                ": /simulation/emitters/0/attach: \"a\" names more than one object; give the object a "
                "unique name");
}

TEST(SceneFixed, ReadsTheFixedPathSettingsAndRejectsBadOnes) {
  const Scene s = parseOk(R"({"fixed": {"puff": "../puffs/p.obj", "outlineScale": 1.25, "outlineOffset": 0.5,
                                        "cellSize": 64}})");
  EXPECT_EQ(s.fixed.puff, fs::path("art/puffs/p.obj"));
  EXPECT_EQ(s.fixed.outlineScale, 1.25f);
  EXPECT_EQ(s.fixed.outlineOffset, 0.5f);
  EXPECT_EQ(s.fixed.cellSize, 64);
  auto again = puff::scene::parseScene(puff::scene::toJson(s), kFile);
  ASSERT_OK(again);
  EXPECT_EQ(again->fixed.puff, s.fixed.puff);
  EXPECT_EQ(again->fixed.cellSize, 64);
  EXPECT_EQ(parseError(std::string(R"({"fixed": {"cellSize": 100}})")),
            kFile.string() + ": /fixed/cellSize: expected 32, 64, 128 or 256, got 100");
  EXPECT_EQ(parseError(std::string(R"({"fixed": {"outlineScale": 0.5}})")),
            kFile.string() + ": /fixed/outlineScale: expected a number in [1, 4], got 0.5");
}

namespace {

// A scene nested 70,000 levels deep must not crash the tools (as an error message that dumps the
// value recursively would). Nesting is limited before parsing, and messages never print a value whole.
TEST(Scene, DeepNestingIsRefusedBeforeParsingAndMessagesStayShort) {
  puff::test::ScopedTempDir dir("puff_deep_json");
  const auto loadError = [&](const std::string& text) {
    const fs::path file = dir / "deep.json";
    std::ofstream(file, std::ios::binary) << text;
    auto s = puff::scene::loadScene(file);
    EXPECT_FALSE(s.ok());
    return s.ok() ? std::string() : s.error().message;
  };
  const std::string deep = "{\"camera\": " + std::string(70000, '[') + std::string(70000, ']') + "}";
  EXPECT_EQ(loadError(deep), (dir / "deep.json").string() + ":1:139: nested more than 128 arrays and objects deep");
  // 128 levels (two objects, 126 arrays) parse, and the error is about the value, printed short.
  const std::string ok = "{\"camera\": {\"position\": " + std::string(126, '[') + std::string(126, ']') + "}}";
  EXPECT_EQ(loadError(ok), (dir / "deep.json").string() +
                               ": /camera/position: expected an array of 3 numbers, got an array of 1 elements");
  // Brackets inside strings do not count.
  const std::string quoted = "{\"camra\": \"" + std::string(300, '[') + "\\\"\"}";
  EXPECT_NE(loadError(quoted).find("/camra: unknown key"), std::string::npos);
  // A value built deeper than any file may hold is still described in a few words.
  json value = 1;
  for (int i = 0; i < 100000; ++i) value = json::array({std::move(value)});
  EXPECT_EQ(puff::core::jsonread::describe(value), "an array of 1 elements");
  EXPECT_EQ(puff::core::jsonread::describe(json::array({1, json::array({2, 3})})), "[1,[2,3]]");
  EXPECT_EQ(puff::core::jsonread::describe(std::string(1000, 'x')), std::string(1, '"') + std::string(44, 'x') + "...");
  // Not regular files: a FIFO would block the read.
  ASSERT_EQ(::mkfifo((dir / "fifo.json").c_str(), 0600), 0);
  auto fifo = puff::scene::loadScene(dir / "fifo.json");
  ASSERT_FALSE(fifo.ok());
  EXPECT_EQ(fifo.error().message, (dir / "fifo.json").string() + ": cannot read: not a regular file");
}

}  // namespace
