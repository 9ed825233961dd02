// The scene file's "media": fire, smoke and dust materials, particles, emitters and lights.
#include <puff/core/number_text.h>
#include <puff/scene/read.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <puff/shader_contract.h>

#include "read_detail.h"

namespace puff::scene::detail {

media::Material readMaterial(const json& j, const std::string& ptr, std::vector<std::string>& becomesNames) {
  requireObject(
      j, ptr,
      {"name", "preset", "albedo", "density", "color", "g", "emissive", "temperature", "temperatureRange", "emission",
       "burn", "detail", "detailWindow", "detailSpeed", "shimmer", "becomes", "transitionStart", "transitionEnd"});
  media::Material m;
  if (auto* v = find(j, "preset")) {
    m = readEnum<media::Material>(
        *v, child(ptr, "preset"),
        {{"smoke", media::smokeMaterial()}, {"dust", media::dustMaterial()}, {"fire", media::fireMaterial()}});
  }
  const json* name = find(j, "name");
  if (!name) failText(child(ptr, "name"), "expected a material name, got none");
  m.name = readString(*name, child(ptr, "name"), "a material name");
  if (m.name.empty()) fail(child(ptr, "name"), "a non-empty material name", *name);
  if (auto* v = find(j, "albedo")) m.albedo = readFloat(*v, child(ptr, "albedo"), kUnit);
  if (auto* v = find(j, "density")) m.density = readFloat(*v, child(ptr, "density"), Range{0.0, 1e4});
  if (auto* v = find(j, "color")) m.color = readColor(*v, child(ptr, "color"));
  if (auto* v = find(j, "g")) m.g = readFloat(*v, child(ptr, "g"), Range{-0.95, 0.95});
  if (auto* v = find(j, "emissive")) m.emissive = readBool(*v, child(ptr, "emissive"));
  if (auto* v = find(j, "temperature"))
    m.temperature = readFloat(*v, child(ptr, "temperature"), Range{0.0, 1e5}, "kelvin in [0, 1e+05]");
  if (auto* v = find(j, "temperatureRange"))
    m.temperatureRange = readFloat(*v, child(ptr, "temperatureRange"), Range{-1e5, 1e5});
  if (auto* v = find(j, "emission")) m.emission = readFloat(*v, child(ptr, "emission"), Range{0.0, 1e4});
  if (auto* v = find(j, "burn")) m.burn = readFloat(*v, child(ptr, "burn"), kUnit);
  if (auto* v = find(j, "detail")) m.detail = readFloat(*v, child(ptr, "detail"), kUnit);
  if (auto* v = find(j, "detailWindow")) m.detailWindow = readFloat(*v, child(ptr, "detailWindow"), Range{1e-3, 1.0});
  if (auto* v = find(j, "detailSpeed"))
    m.detailSpeed = readFloat(*v, child(ptr, "detailSpeed"), Range{0.0, media::kMaxDetailSpeed});
  if (auto* v = find(j, "shimmer")) m.shimmer = readFloat(*v, child(ptr, "shimmer"), kUnit);
  if (auto* v = find(j, "transitionStart")) m.transitionStart = readFloat(*v, child(ptr, "transitionStart"), kUnit);
  if (auto* v = find(j, "transitionEnd")) m.transitionEnd = readFloat(*v, child(ptr, "transitionEnd"), kUnit);
  if (m.transitionEnd < m.transitionStart) {
    const json* v = find(j, "transitionEnd") ? find(j, "transitionEnd") : find(j, "transitionStart");
    fail(child(ptr, find(j, "transitionEnd") ? "transitionEnd" : "transitionStart"), "transitionStart <= transitionEnd",
         *v);
  }
  becomesNames.emplace_back();
  if (auto* v = find(j, "becomes")) becomesNames.back() = readString(*v, child(ptr, "becomes"), "a material name");
  return m;
}

int materialIndex(const MediaSpec& m, const json& v, const std::string& ptr) {
  const std::string name = readString(v, ptr, "a material name");
  for (std::size_t i = 0; i < m.materials.size(); ++i)
    if (m.materials[i].name == name) return static_cast<int>(i);
  std::string names;
  for (const media::Material& mt : m.materials) names += (names.empty() ? "" : ", ") + mt.name;
  fail(ptr, "the name of a material (" + names + ")", v);
}

MediaLightSpec readMediaLight(const json& j, const std::string& ptr) {
  requireObject(j, ptr, {"center", "radius", "color", "intensity", "mode", "full"});
  MediaLightSpec l;
  if (auto* v = find(j, "center")) l.center = readVec3(*v, child(ptr, "center"), kMagnitude);
  if (auto* v = find(j, "radius")) l.radius = readFloat(*v, child(ptr, "radius"), Range{0.0, 1e6, true, false});
  if (auto* v = find(j, "color")) l.color = readColor(*v, child(ptr, "color"));
  if (auto* v = find(j, "intensity")) {
    const std::string p = child(ptr, "intensity");
    if (v->is_number()) {
      l.times = {0.0f};
      l.intensities = {readFloat(*v, p, Range{0.0, 1e4})};
    } else {
      // [{"time": t, "value": i}, ...], times increasing.
      if (!v->is_array() || v->empty()) fail(p, "a number or an array of keys {\"time\", \"value\"}", *v);
      l.times.clear(), l.intensities.clear();
      for (std::size_t i = 0; i < v->size(); ++i) {
        const std::string k = child(p, i);
        requireObject((*v)[i], k, {"time", "value"});
        const json* t = find((*v)[i], "time");
        const json* x = find((*v)[i], "value");
        if (!t) failText(child(k, "time"), "expected a time in seconds, got none");
        if (!x) failText(child(k, "value"), "expected an intensity >= 0, got none");
        const float time = readFloat(*t, child(k, "time"), kMagnitude);
        if (!l.times.empty() && !(time > l.times.back()))
          fail(child(k, "time"), "a time after the previous key (" + core::numberText(l.times.back()) + ")", *t);
        l.times.push_back(time);
        l.intensities.push_back(readFloat(*x, child(k, "value"), Range{0.0, 1e4}));
      }
    }
  }
  if (auto* v = find(j, "mode"))
    l.modulate = readEnum<bool>(*v, child(ptr, "mode"), {{"additive", false}, {"modulate", true}});
  if (auto* v = find(j, "full"))
    l.fullAtBack = readEnum<bool>(*v, child(ptr, "full"), {{"center", false}, {"back", true}});
  return l;
}

void readBlackbody(const json& v, const std::string& p, media::Settings& settings) {
  requireObject(v, p, {"minKelvin", "maxKelvin", "normalizeKelvin"});
  const Range kelvin{0.0, 1e5, true, false};
  if (auto* x = find(v, "minKelvin")) settings.minKelvin = readFloat(*x, child(p, "minKelvin"), kelvin);
  if (auto* x = find(v, "maxKelvin")) settings.maxKelvin = readFloat(*x, child(p, "maxKelvin"), kelvin);
  if (auto* x = find(v, "normalizeKelvin"))
    settings.normalizeKelvin = readFloat(*x, child(p, "normalizeKelvin"), kelvin);
  if (!(settings.maxKelvin > settings.minKelvin)) {
    const char* key = find(v, "maxKelvin") ? "maxKelvin" : "minKelvin";
    fail(child(p, key), "maxKelvin > minKelvin", *find(v, key));
  }
}

// The cartoon style's bands (types.h, CartoonStyle). Its ink is the scene's `style` outline
// (render::MediaPass takes it each frame), so it has none of its own here.
void readCartoon(const json& v, const std::string& p, media::CartoonStyle& c) {
  requireObject(v, p, {"threshold", "opacityBands", "fireColors", "fireBands", "coolKelvin", "hotKelvin"});
  if (auto* x = find(v, "threshold"))
    c.threshold = readFloat(*x, child(p, "threshold"), Range{0.0, 1.0, true, true}, "an opacity in (0, 1)");
  if (auto* x = find(v, "opacityBands")) c.opacityBands = readInt(*x, child(p, "opacityBands"), 1, 8);
  // The fire's bands: the artist's palette (the default), or "blackbody" bands, which fireBands counts
  // (fireBands alone asks for them).
  const json* colours = find(v, "fireColors");
  const json* bands = find(v, "fireBands");
  if (colours && colours->is_string()) {
    if (colours->get<std::string>() != "blackbody")
      fail(child(p, "fireColors"),
           "\"blackbody\" or an array of 1 to " + std::to_string(shader::kMaxFireBands) + " colours (the core first)",
           *colours);
    c.fireColors.clear();
  } else if (colours) {
    if (!colours->is_array() || colours->empty() || colours->size() > static_cast<std::size_t>(shader::kMaxFireBands))
      fail(child(p, "fireColors"),
           "\"blackbody\" or an array of 1 to " + std::to_string(shader::kMaxFireBands) + " colours (the core first)",
           *colours);
    if (bands)
      failText(child(p, "fireBands"), "counts black-body bands; with a fireColors palette its colours are the bands");
    c.fireColors.clear();
    for (std::size_t k = 0; k < colours->size(); ++k)
      c.fireColors.push_back(readColor((*colours)[k], child(child(p, "fireColors"), std::to_string(k))));
  } else if (bands) {
    c.fireColors.clear();
  }
  if (bands) c.fireBands = readInt(*bands, child(p, "fireBands"), 1, shader::kMaxFireBands);
  const Range kelvin{0.0, 1e5, true, false};
  if (auto* x = find(v, "coolKelvin"))
    c.coolKelvin = readFloat(*x, child(p, "coolKelvin"), Range{0.0, 1e5, true, true});
  if (auto* x = find(v, "hotKelvin")) c.hotKelvin = readFloat(*x, child(p, "hotKelvin"), kelvin);
  if (!(c.hotKelvin > c.coolKelvin)) {
    // Name the key the file has (the other may be the default), and both values.
    const char* key = find(v, "hotKelvin") ? "hotKelvin" : "coolKelvin";
    char values[96];
    std::snprintf(values, sizeof values, "hotKelvin (%g%s) must exceed coolKelvin (%g%s)", c.hotKelvin,
                  find(v, "hotKelvin") ? "" : ", the default", c.coolKelvin,
                  find(v, "coolKelvin") ? "" : ", the default");
    failText(child(p, key), values);
  }
}

// How the media are drawn: method, layer resolution, phase, sort key, black body, exposure, detail videos,
// composition and motion blur.
void readLook(const json& j, const std::string& ptr, const Reader& r, MediaSpec& m) {
  if (auto* v = find(j, "method")) {
    m.method = readEnum<media::Method>(*v, child(ptr, "method"),
                                       {{"planar", media::Method::kPlanar},
                                        {"soft-linear", media::Method::kSoftLinear},
                                        {"soft-scurve", media::Method::kSoftSCurve},
                                        {"spherical", media::Method::kSpherical},
                                        {"planar-textured", media::Method::kPlanarTextured}});
  }
  if (auto* v = find(j, "resolution")) {
    const float f = readFloat(*v, child(ptr, "resolution"), kAny, "1, 0.5, 0.25 or 0.125");
    if (f != 1.0f && f != 0.5f && f != 0.25f && f != 0.125f)
      fail(child(ptr, "resolution"), "1, 0.5, 0.25 or 0.125", *v);
    m.resolution = f;
  }
  if (auto* v = find(j, "phase")) {
    m.settings.phase = readEnum<media::PhaseModel>(*v, child(ptr, "phase"),
                                                   {{"cornette-shanks", media::PhaseModel::kCornetteShanks},
                                                    {"henyey-greenstein", media::PhaseModel::kHenyeyGreenstein}});
  }
  if (auto* v = find(j, "sort")) {
    m.settings.sort = readEnum<media::SortKey>(
        *v, child(ptr, "sort"),
        {{"view-depth", media::SortKey::kViewDepth}, {"power-distance", media::SortKey::kPowerDistance}});
  }
  if (auto* v = find(j, "blackbody")) readBlackbody(*v, child(ptr, "blackbody"), m.settings);
  if (auto* v = find(j, "exposure")) m.settings.exposure = readFloat(*v, child(ptr, "exposure"), Range{0.0, 1e4});
  if (auto* v = find(j, "style")) {
    m.settings.style = readEnum<media::Style>(
        *v, child(ptr, "style"), {{"photoreal", media::Style::kPhotoreal}, {"cartoon", media::Style::kCartoon}});
  }
  if (auto* v = find(j, "cartoon")) readCartoon(*v, child(ptr, "cartoon"), m.settings.cartoon);
  if (auto* v = find(j, "detail")) {
    const std::string p = child(ptr, "detail");
    requireObject(*v, p, {"temperature", "opacity"});
    if (auto* x = find(*v, "temperature")) m.temperatureDetail = r.readPath(*x, child(p, "temperature"));
    if (auto* x = find(*v, "opacity")) m.opacityDetail = r.readPath(*x, child(p, "opacity"));
  }
  if (auto* v = find(j, "shimmer"))
    m.compose.shimmerPixels = readFloat(*v, child(ptr, "shimmer"), Range{0.0, 1000.0}, "pixels in [0, 1000]");
  if (auto* v = find(j, "depthAware")) m.compose.depthAware = readBool(*v, child(ptr, "depthAware"));
  if (auto* v = find(j, "depthTolerance"))
    m.compose.depthTolerance = readFloat(*v, child(ptr, "depthTolerance"), Range{0.0, 10.0, true, false});
  if (auto* v = find(j, "motionBlur")) {
    const std::string p = child(ptr, "motionBlur");
    requireObject(*v, p, {"frames", "persistence"});
    if (auto* x = find(*v, "frames"))
      m.motionBlurFrames = readInt(*x, child(p, "frames"), 0, shader::kMaxBlurFrames - 1);
    if (auto* x = find(*v, "persistence"))
      m.motionBlurPersistence = readFloat(*x, child(p, "persistence"), Range{0.0, 1.0, false, true});
  }
  if (m.settings.style == media::Style::kCartoon && m.motionBlurFrames > 0) {
    failText(child(ptr, "motionBlur"),
             "motion blur blends whole frames, which stacks the cartoon style's outlines into ghosts; use it with "
             "\"style\": \"photoreal\", or set its frames to 0");
  }
}

void readMaterials(const json& v, const std::string& p, MediaSpec& m) {
  constexpr std::size_t kMost = shader::kMaxMaterials;
  if (!v.is_array() || v.empty() || v.size() > kMost)
    fail(p, "an array of 1 to " + std::to_string(kMost) + " materials", v);
  m.materials.clear();
  std::vector<std::string> becomes;
  for (std::size_t i = 0; i < v.size(); ++i) {
    m.materials.push_back(readMaterial(v[i], child(p, i), becomes));
    for (std::size_t k = 0; k + 1 < m.materials.size(); ++k)
      if (m.materials[k].name == m.materials.back().name)
        fail(child(child(p, i), "name"), "a name no other material has", *find(v[i], "name"));
  }
  for (std::size_t i = 0; i < becomes.size(); ++i) {
    if (becomes[i].empty()) continue;
    m.materials[i].becomes = materialIndex(m, *find(v[i], "becomes"), child(child(p, i), "becomes"));
  }
}

void readMediaParticles(const json& v, const std::string& p, MediaSpec& m) {
  if (!v.is_array() || v.size() > static_cast<std::size_t>(kMaxParticles))
    fail(p, "an array of at most " + std::to_string(kMaxParticles) + " particles", v);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string q = child(p, i);
    const json& x = v[i];
    requireObject(x, q, {"position", "radius", "material", "life", "density", "seed"});
    MediaParticleSpec s;
    if (auto* y = find(x, "position")) s.position = readVec3(*y, child(q, "position"), kMagnitude);
    if (auto* y = find(x, "radius")) s.radius = readFloat(*y, child(q, "radius"), kNonNegativeMagnitude);
    if (auto* y = find(x, "material")) {
      s.materialIndex = materialIndex(m, *y, child(q, "material"));
      s.material = m.materials[static_cast<std::size_t>(s.materialIndex)].name;
    } else {
      s.materialIndex = materialIndex(m, json(s.material), child(q, "material"));
    }
    if (auto* y = find(x, "life")) s.life = readFloat(*y, child(q, "life"), kUnit);
    if (auto* y = find(x, "density")) s.density = readFloat(*y, child(q, "density"), Range{0.0, 1e4});
    if (auto* y = find(x, "seed"))
      s.seed = static_cast<std::uint32_t>(readInteger(*y, child(q, "seed"), 0, 0xffffffffLL));
    m.particles.push_back(std::move(s));
  }
}

void readMediaEmitters(const json& v, const std::string& p, MediaSpec& m) {
  if (!v.is_array()) fail(p, "an array of emitters", v);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string q = child(p, i);
    json e = v[i];
    if (!e.is_object()) fail(q, "an emitter object", e);
    MediaEmitterSpec s;
    if (auto* y = find(e, "material")) {
      s.materialIndex = materialIndex(m, *y, child(q, "material"));
      s.material = m.materials[static_cast<std::size_t>(s.materialIndex)].name;
    } else {
      s.materialIndex = materialIndex(m, json(s.material), child(q, "material"));
    }
    if (auto* y = find(e, "growth")) s.growth = readFloat(*y, child(q, "growth"), Range{0.0, 100.0});
    e.erase("material");
    e.erase("growth");
    for (const char* key : {"variations", "oriented", "spin"}) {
      if (e.contains(key))
        failText(child(q, key), "unknown key: media particles are spheres (no atlas variation or orientation)");
    }
    s.emitter = readSimEmitter(e, q, CurveOwner::kMedia);
    if (!s.emitter.overLife.temperature.empty()) {
      // T0 matters only where the material emits, or the one it becomes does.
      const media::Material& mt = m.materials[static_cast<std::size_t>(s.materialIndex)];
      const bool emits = mt.emissive || (mt.becomes >= 0 && m.materials[static_cast<std::size_t>(mt.becomes)].emissive);
      if (!emits) {
        failText(child(child(q, "overLife"), "temperature"),
                 "material \"" + mt.name +
                     "\" does not emit (\"emissive\": false), so a temperature curve would change nothing");
      }
    }
    m.emitters.push_back(std::move(s));
  }
}

MediaSpec readMedia(const json& j, const std::string& ptr, const Reader& r) {
  requireObject(j, ptr, {"method",     "resolution",   "phase",           "sort",     "blackbody",  "exposure",
                         "style",      "cartoon",      "detail",          "shimmer",  "depthAware", "depthTolerance",
                         "motionBlur", "materials",    "particles",       "emitters", "forces",     "substeps",
                         "preroll",    "maxParticles", "collisionRadius", "lights"});
  MediaSpec m;
  readLook(j, ptr, r, m);
  if (auto* v = find(j, "materials")) readMaterials(*v, child(ptr, "materials"), m);
  if (auto* v = find(j, "particles")) readMediaParticles(*v, child(ptr, "particles"), m);
  if (auto* v = find(j, "emitters")) readMediaEmitters(*v, child(ptr, "emitters"), m);
  if (auto* v = find(j, "forces")) m.forces = readForces(*v, child(ptr, "forces"));
  if (auto* v = find(j, "substeps")) m.substeps = readInt(*v, child(ptr, "substeps"), 1, 1000);
  if (auto* v = find(j, "preroll")) m.preroll = readFloat(*v, child(ptr, "preroll"), Range{0.0, 3600.0});
  if (auto* v = find(j, "maxParticles")) {
    m.maxParticles = static_cast<std::size_t>(
        readInteger(*v, child(ptr, "maxParticles"), 0, 1'000'000, "a particle budget in [0, 1000000]"));
  }
  if (auto* v = find(j, "collisionRadius")) m.collisionRadius = readFloat(*v, child(ptr, "collisionRadius"), kUnit);
  if (auto* v = find(j, "lights")) {
    const std::string p = child(ptr, "lights");
    constexpr std::size_t kMost = shader::kMaxLights;
    if (!v->is_array() || v->size() > kMost) fail(p, "an array of at most " + std::to_string(kMost) + " lights", *v);
    for (std::size_t i = 0; i < v->size(); ++i) m.lights.push_back(readMediaLight((*v)[i], child(p, i)));
  }
  return m;
}

}  // namespace puff::scene::detail
