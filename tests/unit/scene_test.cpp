// Scene files: every field optional, every mistake named by its JSON pointer, presets, and the
// "simulation" and "fixed" sections (scene_evaluate_test.cpp: the frame evaluation;
// scene_roundtrip_test.cpp: the round trip).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <sys/stat.h>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <puff/scene/evaluate.h>
#include <puff/scene/geometry.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>
#include <puff/support/json_read.h>

#include "scene_test_helpers.h"
#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using puff::scene::EmitterSpec;
using puff::scene::ObjectSpec;
using puff::scene::Scene;
using puff::test::kFile;
using puff::test::parseOk;

std::string parseError(const json& j, const fs::path& artDir = {}) {
  auto s = puff::scene::parseScene(j, kFile, artDir);
  EXPECT_FALSE(s.ok());
  return s.ok() ? std::string() : s.error().message;
}
std::string parseError(const std::string& text) { return parseError(json::parse(text)); }

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

// "#rgb" is CSS's shorthand: each digit doubled, either case.
TEST(Scene, ShortHexColoursDoubleEachDigit) {
  EXPECT_EQ(parseOk(R"({"output": {"background": "#fA0"}})").background,
            parseOk(R"({"output": {"background": "#ffaa00"}})").background);
  EXPECT_EQ(parseOk(R"({"output": {"background": "#fff"}})").background, glm::vec3(1.0f));
  EXPECT_EQ(parseOk(R"({"output": {"background": "#102"}})").background, glm::vec3(17.0f, 0.0f, 34.0f) / 255.0f);
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
       "/output/background: expected a colour: [r, g, b] in [0, 1], \"#rrggbb\" or \"#rgb\", got \"#12345g\""},
      {R"({"output": {"background": "#fa"}})",
       "/output/background: expected a colour: [r, g, b] in [0, 1], \"#rrggbb\" or \"#rgb\", got \"#fa\""},
      {R"({"output": {"background": "#fag"}})",
       "/output/background: expected a colour: [r, g, b] in [0, 1], \"#rrggbb\" or \"#rgb\", got \"#fag\""},
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
      // A name that is a typo of one gets the nearest (at most two edits, case aside); one nothing is
      // near gets the list alone.
      {R"({"style": {"preset": "cel-shadow"}})",
       "/style/preset: expected one of outlines, cel, cel-shadows, ink, solid, got \"cel-shadow\" (did you mean "
       "\"cel-shadows\"?)"},
      {R"({"style": {"shadowMethod": "Mapp"}})",
       "/style/shadowMethod: expected one of volumes, map, got \"Mapp\" (did you mean \"map\"?)"},
      {R"({"style": {"alignment": "view_plane"}})",
       "/style/alignment: expected one of view-plane, viewpoint, axial, got \"view_plane\" (did you mean "
       "\"view-plane\"?)"},
      {R"({"objects": [{"type": "sper"}]})",
       "/objects/0/type: expected one of plane, box, sphere, mesh, got \"sper\" (did you mean \"sphere\"?)"},
      {R"({"objects": [{"type": "cube"}]})", "/objects/0/type: expected one of plane, box, sphere, mesh, got \"cube\""},
      {R"({"style": {"hullFromPixels": -1}})", "/style/hullFromPixels: expected a number in [0, 4096], got -1"},
      {R"({"style": {"hullFromPixels": 5000}})", "/style/hullFromPixels: expected a number in [0, 4096], got 5000"},
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
       "/objects/0/mesh: expected a mesh file (OBJ, OFF, PLY, STL or glTF 2.0 (.gltf, .glb)) for type \"mesh\", got "
       "none"},
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
