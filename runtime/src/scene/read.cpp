// Scene files: JSON -> Scene with every value checked (docs/scene-format.md is the reference).
#include <puff/core/number_text.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>

#include <puff/mesh/mesh.h>
#include <puff/scene/bodies.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "read_detail.h"

namespace puff::scene {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// One of `values`, as toString names each (the names live once, beside the enum).
template <class E>
E readNamed(const json& v, const std::string& ptr, std::initializer_list<E> values) {
  std::vector<std::string_view> names;
  for (E e : values) {
    if (v.is_string() && v.get<std::string>() == toString(e)) return e;
    names.push_back(toString(e));
  }
  core::jsonread::failChoice(v, ptr, names);
}

}  // namespace

namespace detail {

void readOutput(const json& j, const std::string& ptr, const Reader& r, Scene& s) {
  requireObject(j, ptr, {"width", "height", "samples", "background", "view", "alpha", "plate"});
  if (auto* v = find(j, "width")) s.width = readInt(*v, child(ptr, "width"), 1, kMaxImageSize);
  if (auto* v = find(j, "height")) s.height = readInt(*v, child(ptr, "height"), 1, kMaxImageSize);
  if (auto* v = find(j, "samples")) {
    const int n = static_cast<int>(readInteger(*v, child(ptr, "samples"), 1, 8, "1, 2, 4 or 8"));
    if (n != 1 && n != 2 && n != 4 && n != 8) fail(child(ptr, "samples"), "1, 2, 4 or 8", *v);
    s.samples = n;
  }
  if (auto* v = find(j, "background")) {
    if (v->is_string() && v->get<std::string>() == "transparent") {
      s.transparent = true;
    } else if (v->is_string() && v->get<std::string>().rfind('#', 0) != 0) {
      fail(child(ptr, "background"), "a colour ([r, g, b], \"#rrggbb\" or \"#rgb\") or \"transparent\"", *v);
    } else {
      s.background = readColor(*v, child(ptr, "background"));
    }
  }
  if (auto* v = find(j, "alpha")) {
    s.alpha = readEnum<core::AlphaMode>(
        *v, child(ptr, "alpha"),
        {{"straight", core::AlphaMode::kStraight}, {"premultiplied", core::AlphaMode::kPremultiplied}});
    // An opaque frame has alpha 1 everywhere: the choice would be silently meaningless.
    if (!s.transparent) failText(child(ptr, "alpha"), "only with \"background\": \"transparent\"");
  }
  if (auto* v = find(j, "plate")) {
    s.plate = r.readPath(*v, child(ptr, "plate"));
    if (!s.plate.empty() && s.transparent) {
      failText(child(ptr, "plate"),
               "a plate is drawn behind the frame, a transparent background leaves nothing there: use one of them");
    }
  }
  if (auto* v = find(j, "view")) {
    s.view = readEnum<core::ViewTransform>(
        *v, child(ptr, "view"),
        {{"standard", core::ViewTransform::kStandard}, {"filmic", core::ViewTransform::kFilmic}});
  }
}

void readCamera(const json& j, const std::string& ptr, cel::Camera& c) {
  requireObject(j, ptr, {"position", "target", "up", "fovY", "orthoHeight", "near", "far"});
  if (auto* v = find(j, "position")) c.position = readVec3(*v, child(ptr, "position"));
  if (auto* v = find(j, "target")) c.target = readVec3(*v, child(ptr, "target"));
  if (auto* v = find(j, "up")) c.up = readVec3(*v, child(ptr, "up"));
  if (auto* v = find(j, "fovY")) {
    // 0 is orthographic; anything else is a perspective angle.
    const std::string what = "a number in (0, 180), or 0 for orthographic";
    c.fovYDegrees = readFloat(*v, child(ptr, "fovY"), Range{0.0, 180.0, false, true}, what);
  }
  if (auto* v = find(j, "orthoHeight")) c.orthoHeight = readFloat(*v, child(ptr, "orthoHeight"), kPositive);
  if (auto* v = find(j, "near")) c.nearPlane = readFloat(*v, child(ptr, "near"), kPositive);
  if (auto* v = find(j, "far")) c.farPlane = readFloat(*v, child(ptr, "far"), kPositive);

  if (!(c.farPlane > c.nearPlane)) {
    if (auto* v = find(j, "far"))
      fail(child(ptr, "far"), "a number > near (" + core::numberText(c.nearPlane) + ")", *v);
    fail(child(ptr, "near"), "a number < far (" + core::numberText(c.farPlane) + ")", *find(j, "near"));
  }
  const glm::vec3 view = c.target - c.position;
  if (!(glm::length(view) > 0.0f)) {
    const char* key = find(j, "target") ? "target" : "position";
    fail(child(ptr, key), "a point apart from the camera's other point (position != target)", *find(j, key));
  }
  const float upLength = glm::length(c.up);
  if (!(upLength > 0.0f) || glm::length(glm::cross(glm::normalize(view), c.up / upLength)) < 1e-4f) {
    const std::string what = "a direction not parallel to the view direction (target - position)";
    if (auto* v = find(j, "up")) fail(child(ptr, "up"), what, *v);
    // The default up: the fault lies with position/target.
    const char* key = find(j, "target") ? "target" : "position";
    fail(child(ptr, key), "a point that does not put the view along up " + json{c.up.x, c.up.y, c.up.z}.dump(),
         *find(j, key));
  }
}

void readLight(const json& j, const std::string& ptr, LightSpec& l) {
  requireObject(j, ptr, {"direction", "color"});
  if (auto* v = find(j, "direction")) {
    l.direction = readVec3(*v, child(ptr, "direction"));
    if (!(glm::length(l.direction) > 0.0f)) fail(child(ptr, "direction"), "a non-zero direction toward the light", *v);
  }
  if (auto* v = find(j, "color")) l.color = readColor(*v, child(ptr, "color"));
}

void readAmbient(const json& j, const std::string& ptr, const Reader& r, Scene& s) {
  requireObject(j, ptr, {"color", "gradient"});
  if (auto* v = find(j, "color")) s.ambientColor = readColor(*v, child(ptr, "color"));
  if (auto* v = find(j, "gradient")) s.ambientGradient = r.readPath(*v, child(ptr, "gradient"));
}

void readRamp(const json& j, const std::string& ptr, const Reader& r, Scene& s) {
  if (j.is_string()) {
    s.ramp = r.readPath(j, ptr);
    return;
  }
  if (!j.is_object()) fail(ptr, "a ramp image path or an object {\"image\", \"smooth\"}", j);
  requireObject(j, ptr, {"image", "smooth"});
  if (auto* v = find(j, "image")) s.ramp = r.readPath(*v, child(ptr, "image"));
  if (auto* v = find(j, "smooth")) s.rampSmooth = readBool(*v, child(ptr, "smooth"));
}

void readStyle(const json& j, const std::string& ptr, Scene& s) {
  requireObject(j, ptr,
                {"preset", "outlines", "outlineWidth", "outlineColor", "shading", "shadows", "alignment", "shadowBias",
                 "shadowLength", "shadowMethod", "shadowMapScale", "tumble", "hullFromPixels"});
  // The preset first, whatever the key order: explicit fields then change what it set.
  if (auto* v = find(j, "preset")) {
    const std::string name = readString(*v, child(ptr, "preset"));
    auto preset = stylePreset(name);
    if (!preset) {
      const std::vector<std::string> names = stylePresetNames();
      const std::vector<std::string_view> views(names.begin(), names.end());
      core::jsonread::failChoice(*v, child(ptr, "preset"), views);
    }
    s.stylePreset = name;
    s.style = *preset;
  }
  cel::Style& st = s.style;
  if (auto* v = find(j, "outlines")) st.outlines = readBool(*v, child(ptr, "outlines"));
  if (auto* v = find(j, "outlineWidth")) st.outlineWidth = readFloat(*v, child(ptr, "outlineWidth"), Range{0.0, 64.0});
  if (auto* v = find(j, "outlineColor")) st.outlineColor = readColor(*v, child(ptr, "outlineColor"));
  if (auto* v = find(j, "shading")) st.shading = readBool(*v, child(ptr, "shading"));
  if (auto* v = find(j, "shadows")) st.shadows = readBool(*v, child(ptr, "shadows"));
  if (auto* v = find(j, "alignment")) {
    st.alignment = readNamed(*v, child(ptr, "alignment"),
                             {cel::Alignment::kViewPlane, cel::Alignment::kViewpoint, cel::Alignment::kAxial});
  }
  if (auto* v = find(j, "shadowBias")) st.shadowBias = readFloat(*v, child(ptr, "shadowBias"), kUnit);
  if (auto* v = find(j, "shadowLength")) st.shadowLength = readFloat(*v, child(ptr, "shadowLength"), kPositive);
  if (auto* v = find(j, "shadowMethod")) {
    st.shadowMethod = readNamed(*v, child(ptr, "shadowMethod"), {cel::ShadowMethod::kVolumes, cel::ShadowMethod::kMap});
  }
  if (auto* v = find(j, "shadowMapScale")) {
    st.shadowMapScale = readFloat(*v, child(ptr, "shadowMapScale"), Range{0.125, 4.0});
  }
  if (auto* v = find(j, "tumble")) {
    st.tumble = readNamed(*v, child(ptr, "tumble"), {cel::TumbleMethod::kHull, cel::TumbleMethod::kBlend});
  }
  if (auto* v = find(j, "hullFromPixels"))
    st.hullFromPixels = readFloat(*v, child(ptr, "hullFromPixels"), Range{0.0, cel::kMaxHullFromPixels});
}

// {"axis": [x, y, z], "degrees": a}
glm::quat readOrientation(const json& j, const std::string& ptr) {
  requireObject(j, ptr, {"axis", "degrees"});
  glm::vec3 axis{0.0f, 1.0f, 0.0f};
  float degrees = 0.0f;
  if (auto* v = find(j, "axis")) {
    axis = readVec3(*v, child(ptr, "axis"));
    if (!(glm::length(axis) > 0.0f)) fail(child(ptr, "axis"), "a non-zero rotation axis", *v);
  }
  if (auto* v = find(j, "degrees")) degrees = readFloat(*v, child(ptr, "degrees"));
  return glm::angleAxis(glm::radians(degrees), glm::normalize(axis));
}

ParticleSpec readParticle(const json& j, const std::string& ptr) {
  requireObject(
      j, ptr,
      {"position", "size", "variation", "oriented", "orientation", "velocity", "angularVelocity", "birth", "lifetime"});
  ParticleSpec p;
  if (auto* v = find(j, "position")) p.position = readVec3(*v, child(ptr, "position"));
  if (auto* v = find(j, "size")) p.size = readFloat(*v, child(ptr, "size"), kNonNegative);
  if (auto* v = find(j, "variation")) p.variation = readInt(*v, child(ptr, "variation"), 0, 255);
  if (auto* v = find(j, "oriented")) p.oriented = readBool(*v, child(ptr, "oriented"));
  if (auto* v = find(j, "orientation")) p.orientation = readOrientation(*v, child(ptr, "orientation"));
  if (auto* v = find(j, "velocity")) p.velocity = readVec3(*v, child(ptr, "velocity"));
  if (auto* v = find(j, "angularVelocity")) p.angularVelocity = readVec3(*v, child(ptr, "angularVelocity"));
  if (auto* v = find(j, "birth")) p.birth = readFloat(*v, child(ptr, "birth"));
  if (auto* v = find(j, "lifetime")) p.lifetime = readFloat(*v, child(ptr, "lifetime"), kNonNegative);
  return p;
}

EmitterSpec readEmitter(const json& j, const std::string& ptr) {
  requireObject(j, ptr,
                {"shape", "count", "seed", "center", "radius", "halfExtent", "end", "endRadius", "sizeMin", "sizeMax",
                 "sizeFalloff", "variations", "oriented", "spin", "velocity", "speedSpread", "birthSpread", "lifetime",
                 "overLife"});
  EmitterSpec e;
  using Shape = EmitterSpec::Shape;
  if (auto* v = find(j, "shape")) {
    e.shape = readEnum<Shape>(*v, child(ptr, "shape"),
                              {{"sphere", Shape::kSphere}, {"box", Shape::kBox}, {"cone", Shape::kCone}});
  }
  if (auto* v = find(j, "count")) e.count = readInt(*v, child(ptr, "count"), 0, kMaxEmitterCount);
  if (auto* v = find(j, "seed")) {
    e.seed = static_cast<unsigned>(readInteger(*v, child(ptr, "seed"), 0, 4294967295LL));
  }
  if (auto* v = find(j, "center")) e.center = readVec3(*v, child(ptr, "center"));
  if (auto* v = find(j, "radius")) e.radius = readFloat(*v, child(ptr, "radius"), kNonNegative);
  if (auto* v = find(j, "halfExtent")) e.halfExtent = readVec3(*v, child(ptr, "halfExtent"), kNonNegative);
  if (auto* v = find(j, "end")) e.end = readVec3(*v, child(ptr, "end"));
  if (auto* v = find(j, "endRadius")) e.endRadius = readFloat(*v, child(ptr, "endRadius"), kNonNegative);
  if (auto* v = find(j, "sizeMin")) e.sizeMin = readFloat(*v, child(ptr, "sizeMin"), kNonNegative);
  if (auto* v = find(j, "sizeMax")) e.sizeMax = readFloat(*v, child(ptr, "sizeMax"), kNonNegative);
  if (e.sizeMin > e.sizeMax) {
    if (auto* v = find(j, "sizeMax")) {
      fail(child(ptr, "sizeMax"), "a number >= sizeMin (" + core::numberText(e.sizeMin) + ")", *v);
    }
    fail(child(ptr, "sizeMin"), "a number <= sizeMax (" + core::numberText(e.sizeMax) + ")", *find(j, "sizeMin"));
  }
  if (auto* v = find(j, "sizeFalloff")) e.sizeFalloff = readFloat(*v, child(ptr, "sizeFalloff"), kUnit);
  if (auto* v = find(j, "variations")) {
    const std::string p = child(ptr, "variations");
    if (!v->is_array()) fail(p, "an array of variation numbers in [0, 255]", *v);
    for (std::size_t i = 0; i < v->size(); ++i) e.variations.push_back(readInt((*v)[i], child(p, i), 0, 255));
  }
  if (auto* v = find(j, "oriented")) e.oriented = readBool(*v, child(ptr, "oriented"));
  if (auto* v = find(j, "spin")) e.spin = readFloat(*v, child(ptr, "spin"), kNonNegative);
  if (auto* v = find(j, "velocity")) e.velocity = readVec3(*v, child(ptr, "velocity"));
  if (auto* v = find(j, "speedSpread")) e.speedSpread = readFloat(*v, child(ptr, "speedSpread"), kNonNegative);
  if (auto* v = find(j, "birthSpread")) e.birthSpread = readFloat(*v, child(ptr, "birthSpread"), kNonNegative);
  if (auto* v = find(j, "lifetime")) e.lifetime = readFloat(*v, child(ptr, "lifetime"), kNonNegative);
  // Placed particles have no density to shape (nailboards draw none), and a life only with a lifetime.
  if (auto* v = find(j, "overLife")) {
    e.overLife = readLifeCurves(*v, child(ptr, "overLife"), CurveOwner::kCelEmitter);
    if (!e.overLife.empty() && !(e.lifetime > 0.0f)) {
      failText(child(ptr, "overLife"), "curves over life need a \"lifetime\" > 0 (these particles live forever)");
    }
  }
  return e;
}

sim::Path readPath3(const json& j, const std::string& ptr) {
  // [{"time": t, "position": [x, y, z]}, ...], times increasing.
  if (!j.is_array()) fail(ptr, "an array of keys {\"time\", \"position\"}", j);
  sim::Path path;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string p = child(ptr, i);
    requireObject(j[i], p, {"time", "position"});
    const json* t = find(j[i], "time");
    const json* x = find(j[i], "position");
    if (!t) failText(child(p, "time"), "expected a time in seconds, got none");
    if (!x) failText(child(p, "position"), "expected a position [x, y, z], got none");
    const float time = readFloat(*t, child(p, "time"), kMagnitude);
    if (!path.times.empty() && !(time > path.times.back())) {
      fail(child(p, "time"), "a time after the previous key (" + core::numberText(path.times.back()) + ")", *t);
    }
    path.times.push_back(time);
    path.points.push_back(readVec3(*x, child(p, "position"), kMagnitude));
  }
  return path;
}

ObjectSpec readObject(const json& j, const std::string& ptr, std::size_t index, const Reader& r) {
  requireObject(j, ptr,
                {"type", "name", "mesh", "translate", "rotate", "scale", "albedo", "shading", "path", "collide",
                 "friction", "dynamic"});
  ObjectSpec o;
  using Type = ObjectSpec::Type;
  if (auto* v = find(j, "type")) {
    o.type = readEnum<Type>(
        *v, child(ptr, "type"),
        {{"plane", Type::kPlane}, {"box", Type::kBox}, {"sphere", Type::kSphere}, {"mesh", Type::kMesh}});
  }
  o.name = "objects/" + std::to_string(index);
  if (auto* v = find(j, "name")) {
    o.name = readString(*v, child(ptr, "name"), "a non-empty name");
    if (o.name.empty()) fail(child(ptr, "name"), "a non-empty name", *v);
  }
  if (auto* v = find(j, "mesh")) o.mesh = r.readPath(*v, child(ptr, "mesh"));
  if (o.type == Type::kMesh && o.mesh.empty()) {
    if (auto* v = find(j, "mesh"))
      fail(child(ptr, "mesh"), std::string("a mesh file (") + mesh::kMeshFormatsRead + ")", *v);
    failText(child(ptr, "mesh"),
             std::string("expected a mesh file (") + mesh::kMeshFormatsRead + ") for type \"mesh\", got none");
  }
  if (o.type != Type::kMesh && !o.mesh.empty()) {
    fail(child(ptr, "mesh"), "no mesh (or \"\") unless type is \"mesh\"", *find(j, "mesh"));
  }
  if (auto* v = find(j, "translate")) o.translate = readVec3(*v, child(ptr, "translate"));
  if (auto* v = find(j, "rotate")) o.rotateDegrees = readVec3(*v, child(ptr, "rotate"));
  if (auto* v = find(j, "scale")) o.scale = readVec3(*v, child(ptr, "scale"), kPositive);
  if (auto* v = find(j, "albedo")) o.albedo = readColor(*v, child(ptr, "albedo"));
  if (auto* v = find(j, "shading")) {
    o.cel = readEnum<bool>(*v, child(ptr, "shading"), {{"cel", true}, {"smooth", false}});
  }
  if (auto* v = find(j, "path")) o.path = readPath3(*v, child(ptr, "path"));
  if (auto* v = find(j, "collide")) o.collide = readBool(*v, child(ptr, "collide"));
  if (auto* v = find(j, "friction")) o.friction = readFloat(*v, child(ptr, "friction"), kUnit);
  if (auto* v = find(j, "dynamic")) {
    const std::string p = child(ptr, "dynamic");
    if (o.type != Type::kBox && o.type != Type::kSphere) {
      failText(p, "only a box or a sphere can be dynamic (a rigid body), this object is a " +
                      std::string(o.type == Type::kPlane ? "plane" : "mesh"));
    }
    if (!o.path.empty()) {
      failText(p, "a dynamic object moves as it is simulated: it cannot also follow a \"path\"");
    }
    requireObject(*v, p, {"mass", "velocity", "angularVelocity", "friction", "restitution"});
    // Bounded so that the rigid-body solver stays in numbers it can step (a body a millimetre to
    // 10 km across, of a gram to 1000 tonnes, at up to 10 km/s and 10,000 rad/s).
    for (int a = 0; a < 3; ++a) {
      if (!(o.scale[a] >= 1e-3f && o.scale[a] <= 1e4f)) {
        failText(child(ptr, "scale"), "a dynamic object's scale must be in [0.001, 10000] on every axis, got " +
                                          core::numberText(o.scale[a]));
      }
    }
    DynamicBody d;
    if (auto* x = find(*v, "mass")) d.mass = readFloat(*x, child(p, "mass"), Range{1e-3, 1e6});
    if (auto* x = find(*v, "velocity")) d.velocity = readVec3(*x, child(p, "velocity"), Range{-1e4, 1e4});
    if (auto* x = find(*v, "angularVelocity")) {
      d.angularVelocity = readVec3(*x, child(p, "angularVelocity"), Range{-1e4, 1e4});
    }
    if (auto* x = find(*v, "friction")) d.friction = readFloat(*x, child(p, "friction"), Range{0.0, 10.0});
    if (auto* x = find(*v, "restitution")) d.restitution = readFloat(*x, child(p, "restitution"), kUnit);
    o.dynamic = d;
  }
  return o;
}

void readRigidBodies(const json& j, const std::string& ptr, RigidBodies& b) {
  requireObject(j, ptr, {"gravity", "stepsPerSecond"});
  if (auto* v = find(j, "gravity")) b.gravity = readVec3(*v, child(ptr, "gravity"), Range{-1e4, 1e4});
  if (auto* v = find(j, "stepsPerSecond")) b.stepsPerSecond = readInt(*v, child(ptr, "stepsPerSecond"), 24, 10000);
}

void readAnimation(const json& j, const std::string& ptr, Animation& a) {
  requireObject(j, ptr, {"fps", "frames", "orbit", "cameraPath", "targetPath", "period"});
  if (auto* v = find(j, "fps")) a.fps = readFloat(*v, child(ptr, "fps"), Range{0.0, 1000.0, true, false});
  if (auto* v = find(j, "frames")) a.frames = readInt(*v, child(ptr, "frames"), 1, kMaxFrames);
  if (auto* v = find(j, "orbit")) a.orbitDegreesPerSecond = readFloat(*v, child(ptr, "orbit"));
  if (auto* v = find(j, "cameraPath")) a.cameraPath = readPath3(*v, child(ptr, "cameraPath"));
  if (auto* v = find(j, "targetPath")) a.targetPath = readPath3(*v, child(ptr, "targetPath"));
  if (auto* v = find(j, "period")) a.period = readInt(*v, child(ptr, "period"), 0, sim::kMaxPeriod);
}

// Listed particles and placed emitters; returns how many particles they come to.
long long readParticleSources(const json& j, Scene& s) {
  long long total = 0;
  if (auto* v = find(j, "particles")) {
    if (!v->is_array()) fail("/particles", "an array of particles", *v);
    if (static_cast<long long>(v->size()) > kMaxParticles) {
      fail("/particles", "at most " + std::to_string(kMaxParticles) + " particles", *v);
    }
    for (std::size_t i = 0; i < v->size(); ++i) s.particles.push_back(readParticle((*v)[i], child("/particles", i)));
    total = static_cast<long long>(s.particles.size());
  }
  if (auto* v = find(j, "emitters")) {
    if (!v->is_array()) fail("/emitters", "an array of emitters", *v);
    for (std::size_t i = 0; i < v->size(); ++i) {
      const std::string p = child("/emitters", i);
      s.emitters.push_back(readEmitter((*v)[i], p));
      total += s.emitters.back().count;
      if (total > kMaxParticles) {
        failText(child(p, "count"), "the scene's particles (listed and emitted) come to " + std::to_string(total) +
                                        " here; at most " + std::to_string(kMaxParticles) + " are allowed");
      }
    }
  }
  return total;
}

void readFixed(const json& j, const std::string& ptr, const Reader& r, FixedSettings& f) {
  requireObject(j, ptr, {"puff", "outlineScale", "outlineOffset", "cellSize"});
  if (auto* x = find(j, "puff")) f.puff = r.readPath(*x, child(ptr, "puff"));
  if (auto* x = find(j, "outlineScale")) f.outlineScale = readFloat(*x, child(ptr, "outlineScale"), Range{1.0, 4.0});
  if (auto* x = find(j, "outlineOffset"))
    f.outlineOffset = readFloat(*x, child(ptr, "outlineOffset"), kNonNegativeMagnitude);
  if (auto* x = find(j, "cellSize")) {
    const int c = static_cast<int>(readInteger(*x, child(ptr, "cellSize"), 32, 256, "32, 64, 128 or 256"));
    if (c != 32 && c != 64 && c != 128 && c != 256) fail(child(ptr, "cellSize"), "32, 64, 128 or 256", *x);
    f.cellSize = c;
  }
}

// A vortex or emitter that rides on an object follows its path (its position is an offset from
// where the object is).
void attachToObject(const std::vector<ObjectSpec>& objects, const std::string& name, sim::Path& path,
                    const std::string& ptr) {
  if (name.empty()) return;
  const auto named = [&](const ObjectSpec& o) { return o.name == name; };
  const auto it = std::find_if(objects.begin(), objects.end(), named);
  if (it == objects.end()) {
    std::string names;
    for (const ObjectSpec& o : objects) names += (names.empty() ? "" : ", ") + o.name;
    failText(ptr, "expected the name of a scene object (" + (names.empty() ? std::string("there are none") : names) +
                      "), got \"" + name + "\"");
  }
  if (std::count_if(objects.begin(), objects.end(), named) > 1)
    failText(ptr, "\"" + name + "\" names more than one object; give the object a unique name");
  if (!path.empty()) failText(ptr, "a vortex or emitter follows its own path or an object, not both");
  path = it->path;
  if (path.empty()) path = sim::Path{{0.0f}, {glm::vec3(0.0f)}, {}};
  for (glm::vec3& p : path.points) p += it->translate;
}

// The vortices and emitters of `forces` / `emitters` under `ptr` attached to their objects.
template <class EmitterOf, class Emitters>
void attachAll(const std::vector<ObjectSpec>& objects, sim::Forces& forces, Emitters& emitters, EmitterOf emitterOf,
               const std::string& ptr) {
  for (std::size_t i = 0; i < forces.vortices.size(); ++i) {
    sim::Vortex& vortex = forces.vortices[i];
    attachToObject(objects, vortex.attach, vortex.path, ptr + "/forces/vortices/" + std::to_string(i) + "/attach");
  }
  for (std::size_t i = 0; i < emitters.size(); ++i) {
    sim::Emitter& e = emitterOf(emitters[i]);
    attachToObject(objects, e.attach, e.path, ptr + "/emitters/" + std::to_string(i) + "/attach");
  }
}

void readSimulationSection(const json& j, Scene& s) {
  s.simulation = readSimulation(j, "/simulation");
  s.simulation->fps = s.animation.fps;
  attachAll(
      s.objects, s.simulation->forces, s.simulation->emitters, [](sim::Emitter& e) -> sim::Emitter& { return e; },
      "/simulation");
  // What the reader does not see (cross-field limits): the simulator's own check.
  if (auto ok = sim::validate(*s.simulation); !ok) throw Failure{"/simulation" + ok.error().message};
}

void readMediaSection(const json& j, const Reader& r, Scene& s) {
  s.media = readMedia(j, "/media", r);
  attachAll(
      s.objects, s.media->forces, s.media->emitters, [](MediaEmitterSpec& e) -> sim::Emitter& { return e.emitter; },
      "/media");
  if (!s.media->emitters.empty() || !s.media->forces.vortices.empty()) {
    sim::Settings check;
    check.forces = s.media->forces;
    for (const MediaEmitterSpec& e : s.media->emitters) check.emitters.push_back(e.emitter);
    if (auto ok = sim::validate(check); !ok) throw Failure{"/media" + ok.error().message};
  }
}

Scene readScene(const json& j, const fs::path& file, const fs::path& artDir) {
  if (!j.is_object()) throw Failure{"expected a JSON object at the top level, got " + describe(j)};
  requireObject(j, "",
                {"output", "camera", "light", "ambient", "ramp", "atlas", "atlasLevel", "particleFraction", "style",
                 "particles", "emitters", "objects", "rigidBodies", "animation", "simulation", "fixed", "media"});
  const Reader r(file, artDir);
  Scene s;
  s.file = file;
  if (auto* v = find(j, "output")) readOutput(*v, "/output", r, s);
  if (auto* v = find(j, "camera")) readCamera(*v, "/camera", s.camera);
  if (auto* v = find(j, "light")) readLight(*v, "/light", s.light);
  if (auto* v = find(j, "ambient")) readAmbient(*v, "/ambient", r, s);
  if (auto* v = find(j, "ramp")) readRamp(*v, "/ramp", r, s);
  if (auto* v = find(j, "atlas")) s.atlas = r.readPath(*v, "/atlas");
  if (auto* v = find(j, "atlasLevel")) s.atlasLevel = readInt(*v, "/atlasLevel", 0, 14);
  if (auto* v = find(j, "particleFraction")) {
    s.particleFraction = readFloat(*v, "/particleFraction", Range{0.0, 1.0, true, false});
  }
  if (auto* v = find(j, "style")) readStyle(*v, "/style", s);
  long long total = readParticleSources(j, s);
  if (auto* v = find(j, "objects")) {
    if (!v->is_array()) fail("/objects", "an array of objects", *v);
    for (std::size_t i = 0; i < v->size(); ++i) s.objects.push_back(readObject((*v)[i], child("/objects", i), i, r));
  }
  if (auto* v = find(j, "animation")) readAnimation(*v, "/animation", s.animation);
  if (auto* v = find(j, "rigidBodies")) readRigidBodies(*v, "/rigidBodies", s.rigidBodies);
  // The dynamic objects' trajectories, before anything rides on them ("attach") or collides.
  if (auto ok = simulateBodies(s); !ok) throw Failure{ok.error().message};
  if (auto* v = find(j, "fixed")) readFixed(*v, "/fixed", r, s.fixed);
  if (auto* v = find(j, "simulation")) {
    readSimulationSection(*v, s);
    if (!s.simulation->emitters.empty()) total = std::max(total, 1LL);
  }
  if (auto* v = find(j, "media")) readMediaSection(*v, r, s);
  if (auto refused = loopRefusal(s)) throw Failure{*refused};
  if (total > 0 && s.atlas.empty()) {
    if (auto* v = find(j, "atlas")) fail("/atlas", "an atlas sidecar path (the scene has particles)", *v);
    failText("/atlas", "expected an atlas sidecar path (the scene has particles), got none");
  }
  return s;
}

}  // namespace detail

std::vector<std::string> stylePresetNames() { return {"outlines", "cel", "cel-shadows", "ink", "solid"}; }

Result<cel::Style> stylePreset(const std::string& name) {
  cel::Style s;  // outlines on, shading on, shadows off: the "cel" look
  if (name == "outlines") {
    // Fig. 8a: the nailboards with their outlines, flat colour, no cel shading.
    s.shading = false;
  } else if (name == "cel") {
  } else if (name == "cel-shadows") {
    s.shadows = true;
  } else if (name == "ink") {
    // Fig. 9: a pen drawing: black ink on the flat (white) puff colour, a heavier line.
    s.shading = false;
    s.outlineColor = glm::vec3(0.0f);
    s.outlineWidth = 3.0f;
  } else if (name == "solid") {
    // Fig. 13d: flat fill with thin outlines.
    s.shading = false;
    s.outlineWidth = 1.0f;
  } else {
    std::string list;
    for (const std::string& n : stylePresetNames()) list += (list.empty() ? "" : ", ") + n;
    return Error{"unknown style preset \"" + name + "\" (expected one of " + list + ")"};
  }
  return s;
}

Result<Scene> parseScene(const json& j, const fs::path& file, const fs::path& artDir) {
  return detail::catchFailure(file, [&] { return detail::readScene(j, file, artDir); });
}

Result<Scene> loadScene(const fs::path& file, const fs::path& artDir, std::string* text) {
  PUFF_TRY_ASSIGN(auto bytes, detail::loadJsonText(file));
  PUFF_TRY_ASSIGN(auto j, detail::parseJson(bytes, file));
  auto scene = parseScene(j, file, artDir);
  if (scene && text) *text = std::move(bytes);
  return scene;
}

}  // namespace puff::scene
