// Scene files round-trip through toJson whole: generated scenes set every field the writer writes
// away from its default (a field a generator leaves at its default fails, naming its JSON pointer),
// and each comes back as the same Scene.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <puff/scene/read.h>
#include <puff/scene/write.h>

#include "scene_test_helpers.h"
#include "support/assert_ok.h"

namespace {

using nlohmann::json;
using puff::scene::Scene;

using puff::test::kFile;
using puff::test::parseOk;

// The generated scenes: between them every field the writer writes is away from its default
// (GeneratedScenesSetEveryWrittenFieldAwayFromItsDefault checks that, field by field). Fields that
// exclude each other get a second scene: the first is opaque, with a plate and cartoon media; the
// second transparent, with an alpha mode and photoreal media with motion blur.
// A loop (animation.period): nothing in it moves but the simulated smoke, so it cannot be the scenes
// below, which move everything.
json loopWithEveryField() {
  return json::parse(R"({
    "atlas": "a.json",
    "particles": [{"position": [0, 1, 0], "oriented": true, "orientation": {"axis": [0, 0, 1], "degrees": 90}}],
    "animation": {"fps": 30, "frames": 60, "period": 30},
    "simulation": {"emitters": [{"rate": 12, "lifetime": 1.5, "velocity": [0, 1, 0]}]}
  })");
}

std::vector<json> scenesWithEveryField() {
  const json opaque = json::parse(R"({
    "output": {"width": 321, "height": 123, "samples": 2, "background": [0.1, 0.2, 0.3], "plate": "plate.png",
               "view": "filmic"},
    "camera": {"position": [3, 4, 5], "target": [0, 0.5, 0], "up": [0, 1, 0.1], "fovY": 33.3, "orthoHeight": 7,
               "near": 0.25, "far": 70},
    "light": {"direction": [1, 2, 3], "color": [0.9, 0.8, 0.7]},
    "ambient": {"color": [0.3, 0.2, 0.1], "gradient": "grad.png"},
    "ramp": {"image": "../ramps/q.png", "smooth": true},
    "atlas": "${PUFF_ART}/default/puff.json",
    "atlasLevel": 2,
    "particleFraction": 0.3,
    "style": {"preset": "ink", "outlines": false, "outlineWidth": 1.5, "outlineColor": [0.2, 0.1, 0],
              "shading": false, "shadows": true, "alignment": "viewpoint", "shadowBias": 0.3, "shadowLength": 12,
              "shadowMethod": "volumes", "shadowMapScale": 0.5, "tumble": "blend",
              "hullFromPixels": 40},
    "particles": [{"position": [1, 2, 3], "size": 0.7, "variation": 3, "oriented": true,
                   "orientation": {"axis": [0, 0, 1], "degrees": 90}, "velocity": [0.1, 0, 0],
                   "angularVelocity": [0, 1, 0], "birth": 0.5, "lifetime": 3}],
    "emitters": [{"shape": "cone", "count": 50, "seed": 4000000000, "center": [1, 0, 0], "radius": 0.2,
                  "halfExtent": [1, 2, 3], "end": [1, 5, 0], "endRadius": 1.5, "sizeMin": 0.2, "sizeMax": 0.9,
                  "sizeFalloff": 0.5, "variations": [1, 2], "oriented": true, "spin": 2, "velocity": [0, 1, 0],
                  "speedSpread": 0.3, "birthSpread": 2, "lifetime": 4,
                  "overLife": {"size": {"keys": [[0, 0.5], [1, 2]], "interp": "smooth"},
                               "color": {"keys": [[0.5, [0.9, 0.5, 0.1]]], "interp": "smooth"}}}],
    "objects": [{"type": "mesh", "name": "rock", "mesh": "rock.obj", "translate": [1, 0, 0], "rotate": [10, 20, 30],
                 "scale": [1, 2, 3], "albedo": [0.5, 0.4, 0.3], "shading": "smooth", "collide": false,
                 "friction": 0.25, "path": [{"time": 0.5, "position": [0, 1, 0]}, {"time": 2, "position": [4, 1, 0]}]},
                {"type": "box", "name": "crate", "translate": [0, 3, 0], "scale": [0.5, 0.5, 0.5],
                 "dynamic": {"mass": 2, "velocity": [1, 0, 0], "angularVelocity": [0, 2, 0], "friction": 0.7,
                             "restitution": 0.6}}],
    "rigidBodies": {"gravity": [0, -5, 0], "stepsPerSecond": 120},
    "animation": {"fps": 12.5, "frames": 40, "orbit": -20,
                  "cameraPath": [{"time": 1, "position": [3, 4, 6]}, {"time": 2, "position": [2, 4, 6]}],
                  "targetPath": [{"time": 1.5, "position": [0, 1, 0]}]},
    "simulation": {
      "substeps": 3, "preroll": 1.5, "maxParticles": 5000, "collisionRadius": 0.25, "integrator": "forward-euler",
      "forces": {"gravity": [0, -1, 0], "buoyancy": 2, "up": [0, 0, 1], "drag": 5, "wind": [1, 0, 0],
                 "windVolumes": [{"center": [0, 1, 0], "halfExtent": [1, 2, 3], "velocity": [0, 0, 4], "feather": 0.5}],
                 "turbulence": {"strength": 0.3, "scale": 2, "speed": 0.1, "seed": 9},
                 "vortices": [{"position": [1, 2, 3], "axis": [0, 0, 1], "strength": -2, "radius": 0.3, "falloff": 4,
                               "length": 2, "path": [{"time": 0.25, "position": [1, 0, 0]},
                                                     {"time": 2, "position": [4, 0, 0]}],
                               "shedInterval": 0.1, "shedLifetime": 0.5},
                              {"attach": "rock"}]},
      "emitters": [{"shape": "disc", "position": [0, 1, 0], "radius": 0.2, "normal": [1, 0, 0],
                    "path": [{"time": 0.5, "position": [0, 0, 1]}, {"time": 1, "position": [0, 0, 5]}],
                    "rate": 50, "start": 0.5, "duration": 2.5, "seed": 4, "velocity": [0, 2, 0], "spread": 15,
                    "speedSpread": 0.1, "inheritVelocity": 0.5, "density": 2, "sizeMin": 0.3, "sizeMax": 0.6,
                    "lifetime": 4, "lifetimeSpread": 0.2, "variations": [1, 2], "oriented": true, "spin": 1,
                    "overLife": {"size": {"keys": [[0, 0.5], [1, 3]], "interp": "smooth"},
                                 "density": {"keys": [[0.25, 2]], "interp": "smooth"},
                                 "color": {"keys": [[0, [0.2, 0.3, 0.4]], [1, [1, 1, 1]]], "interp": "smooth"}}},
                   {"attach": "rock"}]
    },
    "fixed": {"puff": "../puffs/p.obj", "outlineScale": 1.25, "outlineOffset": 0.5, "cellSize": 64},
    "media": {
      "method": "planar-textured", "resolution": 0.25, "phase": "henyey-greenstein", "sort": "power-distance",
      "blackbody": {"minKelvin": 800, "maxKelvin": 9000, "normalizeKelvin": 3000}, "exposure": 1.5,
      "style": "cartoon",
      "cartoon": {"threshold": 0.4, "opacityBands": 3, "fireBands": 4, "coolKelvin": 1500, "hotKelvin": 3500},
      "detail": {"temperature": "detail/t.mp4", "opacity": "detail/o.mp4"},
      "shimmer": 0.5, "depthAware": false, "depthTolerance": 0.05,
      "motionBlur": {"frames": 0, "persistence": 0.25},
      "materials": [{"name": "ash", "albedo": 0.3, "density": 0.5, "color": [0.9, 0.8, 0.7], "g": 0.2,
                     "emissive": true, "temperature": 2000, "temperatureRange": 500, "emission": 2, "burn": 0.5,
                     "detail": 0.25, "detailWindow": 0.5, "detailSpeed": 4, "shimmer": 0.5, "becomes": "soot",
                     "transitionStart": 0.2, "transitionEnd": 0.6},
                    {"name": "soot", "preset": "dust"}],
      "particles": [{"position": [1, 1, 1], "radius": 0.5, "material": "soot", "life": 0.5, "density": 2, "seed": 7}],
      "emitters": [{"shape": "sphere", "position": [0, 2, 0], "radius": 0.3, "normal": [0, 0, 1],
                    "path": [{"time": 0.5, "position": [1, 0, 0]}, {"time": 3, "position": [2, 0, 0]}],
                    "rate": 20, "start": 0.25, "duration": 1.5, "seed": 11, "velocity": [0, 3, 0], "spread": 30,
                    "speedSpread": 0.2, "inheritVelocity": -0.5, "density": 3, "sizeMin": 0.1, "sizeMax": 0.4,
                    "lifetime": 1.5, "lifetimeSpread": 0.3, "material": "ash", "growth": 1.5,
                    "overLife": {"size": {"keys": [[0, 0.5], [1, 2]], "interp": "smooth"},
                                 "density": {"keys": [[0.5, 0.25]], "interp": "smooth"},
                                 "color": {"keys": [[0.5, [0.5, 0.5, 0.5]]], "interp": "smooth"},
                                 "temperature": {"keys": [[0, 3000], [1, 1200]], "interp": "smooth"}}},
                   {"attach": "rock", "material": "soot"}],
      "forces": {"gravity": [0, -2, 0], "buoyancy": 3, "up": [1, 0, 0], "drag": 1, "wind": [0, 0, 1],
                 "windVolumes": [{"center": [1, 0, 0], "halfExtent": [2, 2, 2], "velocity": [1, 0, 0], "feather": 1}],
                 "turbulence": {"strength": 0.2, "scale": 3, "speed": 0.2, "seed": 5},
                 "vortices": [{"position": [0, 1, 0], "axis": [1, 0, 0], "strength": 3, "radius": 0.2, "falloff": 2,
                               "length": 1, "path": [{"time": 0.5, "position": [0, 2, 0]}],
                               "shedInterval": 0.2, "shedLifetime": 2},
                              {"attach": "rock"}]},
      "substeps": 3, "preroll": 0.5, "maxParticles": 5000, "collisionRadius": 0.25,
      "lights": [{"center": [0, 1, 0], "radius": 2, "color": [1, 0.5, 0.2],
                  "intensity": [{"time": 0.5, "value": 3}, {"time": 1, "value": 0}], "mode": "modulate",
                  "full": "back"}]
    }
  })");
  json transparent = opaque;
  transparent["output"].erase("plate");
  transparent["output"]["background"] = "transparent";
  transparent["output"]["alpha"] = "premultiplied";
  // Cartoon media refuse motion blur.
  transparent["media"]["style"] = "photoreal";
  transparent["media"]["motionBlur"]["frames"] = 3;
  return {opaque, transparent, loopWithEveryField()};
}

// What the writer writes for a scene of defaults: toJson of a minimal scene in which every optional
// section and every field the writer leaves out when unset is present, and every list holds one
// element with only the fields it needs (and, where a list's elements have optional parts, a second
// element with those: curves over life, a dynamic body, a material that becomes another). Every
// path and key list holds one key, so that a key's fields are walked too.
json writtenDefaults() {
  const json minimal = json::parse(R"({
    "output": {"view": "standard"},
    "atlas": "a.json",
    "style": {"preset": "cel"},
    "particles": [{}],
    "emitters": [{}, {"lifetime": 1, "overLife": {"size": {"keys": [[0, 1]]}, "color": {"keys": [[0, [1, 1, 1]]]}}}],
    "objects": [{"path": [{"time": 0, "position": [0, 0, 0]}]}, {"type": "box", "dynamic": {}}],
    "animation": {"cameraPath": [{"time": 0, "position": [0, 0, 0]}],
                  "targetPath": [{"time": 0, "position": [0, 0, 0]}]},
    "simulation": {
      "forces": {"windVolumes": [{}], "vortices": [{"path": [{"time": 0, "position": [0, 0, 0]}]}]},
      "emitters": [{"path": [{"time": 0, "position": [0, 0, 0]}]},
                   {"overLife": {"size": {"keys": [[0, 1]]}, "density": {"keys": [[0, 1]]},
                                 "color": {"keys": [[0, [1, 1, 1]]]}}}]
    },
    "media": {
      "materials": [{"name": "smoke"}, {"name": "fire", "emissive": true, "becomes": "smoke"}],
      "particles": [{}],
      "emitters": [{"path": [{"time": 0, "position": [0, 0, 0]}]},
                   {"material": "fire",
                    "overLife": {"size": {"keys": [[0, 1]]}, "density": {"keys": [[0, 1]]},
                                 "color": {"keys": [[0, [1, 1, 1]]]}, "temperature": {"keys": [[0, 1000]]}}}],
      "forces": {"windVolumes": [{}], "vortices": [{"path": [{"time": 0, "position": [0, 0, 0]}]}]},
      "lights": [{}]
    }
  })");
  auto opaque = puff::scene::parseScene(minimal, kFile);
  EXPECT_OK(opaque);
  if (!opaque.ok()) return {};
  json written = puff::scene::toJson(*opaque);
  // "alpha" goes only with a transparent background: its default comes from a transparent scene.
  auto transparent =
      puff::scene::parseScene(json::parse(R"({"output": {"background": "transparent", "alpha": "straight"}})"), kFile);
  EXPECT_OK(transparent);
  if (transparent.ok()) written["output"]["alpha"] = puff::scene::toJson(*transparent)["output"]["alpha"];
  return written;
}

std::string pointerTo(const std::string& parent, const std::string& key) {
  std::string escaped;
  for (char c : key) escaped += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return parent + "/" + escaped;
}

// Fails, naming the field's JSON pointer, for every leaf of `defaults` that each of `values` leaves
// at the default's value (or lacks). A list's elements in `defaults` are each walked against every
// element of the lists in `values`: a field is covered when any element of any scene sets it.
void expectEveryLeafSet(const json& defaults, const std::vector<const json*>& values, const std::string& pointer) {
  if (defaults.is_object() && !defaults.empty()) {
    for (const auto& [key, value] : defaults.items()) {
      std::vector<const json*> under;
      for (const json* v : values)
        if (v->is_object() && v->contains(key)) under.push_back(&(*v)[key]);
      expectEveryLeafSet(value, under, pointerTo(pointer, key));
    }
    return;
  }
  if (defaults.is_array() && !defaults.empty() && defaults[0].is_object()) {
    std::vector<const json*> elements;
    for (const json* v : values)
      if (v->is_array())
        for (const json& e : *v) elements.push_back(&e);
    for (std::size_t i = 0; i < defaults.size(); ++i)
      expectEveryLeafSet(defaults[i], elements, pointer + "/" + std::to_string(i));
    return;
  }
  if (values.empty()) {
    ADD_FAILURE() << pointer << ": no generated scene has this field (default " << defaults.dump()
                  << "); set it in scenesWithEveryField()";
  } else if (std::all_of(values.begin(), values.end(), [&](const json* v) { return *v == defaults; })) {
    ADD_FAILURE() << pointer << ": every generated scene leaves this field at its default " << defaults.dump()
                  << "; set it in scenesWithEveryField()";
  }
}

// A field added to Scene and to toJson fails here until scenesWithEveryField() sets it, so that the
// round trip below covers it.
TEST(Scene, GeneratedScenesSetEveryWrittenFieldAwayFromItsDefault) {
  const json defaults = writtenDefaults();
  ASSERT_FALSE(defaults.is_null());
  // toJson(Scene{}) writes every field that is not optional: the minimal scene has them all.
  const json plain = puff::scene::toJson(Scene{});
  for (const auto& [key, value] : plain.items()) EXPECT_TRUE(defaults.contains(key)) << key;
  std::vector<json> written;
  for (const json& j : scenesWithEveryField()) {
    auto s = puff::scene::parseScene(j, kFile, "build/art");
    ASSERT_OK(s);
    written.push_back(puff::scene::toJson(*s));
  }
  std::vector<const json*> values;
  for (const json& w : written) values.push_back(&w);
  expectEveryLeafSet(defaults, values, "");
}

TEST(Scene, ToJsonRoundTripsWholeScenes) {
  const std::vector<json> scenes = scenesWithEveryField();
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    SCOPED_TRACE("scenesWithEveryField()[" + std::to_string(i) + "]");
    auto a = puff::scene::parseScene(scenes[i], kFile, "build/art");
    ASSERT_OK(a);
    const json written = puff::scene::toJson(*a);
    auto b = puff::scene::parseScene(written, kFile, "build/art");
    ASSERT_OK(b) << puff::scene::jsonText(written);
    const json rewritten = puff::scene::toJson(*b);
    EXPECT_TRUE(*a == *b) << (rewritten == written
                                  ? "toJson writes both scenes the same: they differ in a field it leaves out or "
                                    "writes wrongly\n"
                                  : "toJson writes them differently: " + json::diff(written, rewritten).dump() + "\n")
                          << "read:\n"
                          << puff::scene::jsonText(written) << "\nread again:\n"
                          << puff::scene::jsonText(rewritten);
    // Writing the re-read scene gives the same JSON: nothing drifts.
    EXPECT_EQ(rewritten, written) << json::diff(written, rewritten).dump();
    // The particle's orientation is exact: sin and cos of 45 degrees round to the same float, so the
    // writer finds 90 degrees about z again (AxisAngleOrientationsComeBackAsTheSameRotation has others).
    EXPECT_EQ(written["particles"][0]["orientation"], json::parse(R"({"axis": [0, 0, 1], "degrees": 90})"));
  }

  const json written = puff::scene::toJson(*puff::scene::parseScene(scenes[0], kFile, "build/art"));
  // Numbers are written as the shortest text that reads back the same float.
  EXPECT_EQ(written["camera"]["fovY"].dump(), "33.3");
  EXPECT_EQ(written["ramp"]["image"], "../ramps/q.png");
  // The defaults round-trip too.
  auto d = puff::scene::parseScene(puff::scene::toJson(Scene{}), "");
  ASSERT_OK(d);
  EXPECT_TRUE(*d == Scene{});
  EXPECT_EQ(puff::scene::toJson(*d), puff::scene::toJson(Scene{}));
}

// Other orientations come back as the same rotation, give or take the last bit of the axis-angle
// text (the writer's angle and axis are rounded to floats).
TEST(Scene, AxisAngleOrientationsComeBackAsTheSameRotation) {
  const std::pair<glm::vec3, float> cases[] = {
      {{1, 1, 0}, 40.0f}, {{1, 2, 3}, 359.0f}, {{0, 1, 0}, 180.0f}, {{1, 0, 0}, -120.0f}, {{0, 0, 1}, 1e-3f}};
  for (const auto& [axis, degrees] : cases) {
    const json j = {
        {"atlas", "a.json"},
        {"particles", json::array({{{"orientation", {{"axis", {axis.x, axis.y, axis.z}}, {"degrees", degrees}}}}})}};
    const Scene a = parseOk(j.dump());
    auto b = puff::scene::parseScene(puff::scene::toJson(a), kFile);
    ASSERT_OK(b);
    EXPECT_NEAR(std::abs(glm::dot(a.particles.at(0).orientation, b->particles.at(0).orientation)), 1.0f, 1e-6f)
        << j.dump();
  }
}

}  // namespace
