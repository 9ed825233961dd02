// Scene -> JSON: every field, written so the reader takes it back unchanged.
#include <puff/scene/write.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <string>
#include <system_error>

namespace puff::scene {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The shortest decimal that reads back as the same float ("0.1", not "0.10000000149011612"), so
// toJson -> parseScene gives back the very same floats and the file stays readable.
json number(float f) {
  char b[32];
  auto [end, ec] = std::to_chars(b, b + sizeof b, f);
  PUFF_CHECK(ec == std::errc());
  double d = 0.0;
  std::from_chars(b, end, d);
  return d;
}

json vec3(const glm::vec3& v) { return json::array({number(v.x), number(v.y), number(v.z)}); }

json orientationJson(const glm::quat& q) {
  // In double, and the angle from atan2, which stays accurate near 0 and 180 degrees.
  double w = q.w, x = q.x, y = q.y, z = q.z;
  if (w < 0.0) w = -w, x = -x, y = -y, z = -z;  // the same rotation, the shorter way round
  const double s = std::sqrt(x * x + y * y + z * z);
  if (!(s > 0.0)) return {{"axis", vec3(glm::vec3(0.0f, 1.0f, 0.0f))}, {"degrees", 0.0}};
  const double degrees = 2.0 * std::atan2(s, w) * 180.0 / std::numbers::pi;
  return {{"axis", vec3(glm::vec3(static_cast<float>(x / s), static_cast<float>(y / s), static_cast<float>(z / s)))},
          {"degrees", number(static_cast<float>(degrees))}};
}

// A path as the scene file would say it: relative to the scene's directory where it can be.
std::string pathJson(const fs::path& p, const fs::path& sceneDir) {
  if (p.empty()) return "";
  if (!sceneDir.empty() && p.is_absolute() == sceneDir.is_absolute()) {
    const fs::path rel = p.lexically_relative(sceneDir);
    if (!rel.empty()) return rel.generic_string();
  }
  if (sceneDir.empty() || p.is_absolute()) return p.generic_string();
  return fs::absolute(p).generic_string();  // relative to the working directory, not the scene
}

json pathKeys(const sim::Path& p) {
  json out = json::array();
  for (std::size_t i = 0; i < p.times.size(); ++i)
    out.push_back({{"time", number(p.times[i])}, {"position", vec3(p.points[i])}});
  return out;
}

json lifeCurveJson(const sim::LifeCurve& c) {
  json keys = json::array();
  for (std::size_t i = 0; i < c.ages.size(); ++i) keys.push_back(json::array({number(c.ages[i]), number(c.values[i])}));
  return {{"keys", std::move(keys)}, {"interp", c.interp == sim::LifeCurve::Interp::kSmooth ? "smooth" : "linear"}};
}

json colourCurveJson(const sim::ColourCurve& c) {
  json keys = json::array();
  for (std::size_t i = 0; i < c.ages.size(); ++i) keys.push_back(json::array({number(c.ages[i]), vec3(c.values[i])}));
  return {{"keys", std::move(keys)}, {"interp", c.interp == sim::LifeCurve::Interp::kSmooth ? "smooth" : "linear"}};
}

// The curves an emitter has ({} for none: its default life).
json lifeCurvesJson(const sim::LifeCurves& c) {
  json j = json::object();
  if (!c.size.empty()) j["size"] = lifeCurveJson(c.size);
  if (!c.density.empty()) j["density"] = lifeCurveJson(c.density);
  if (!c.color.empty()) j["color"] = colourCurveJson(c.color);
  if (!c.temperature.empty()) j["temperature"] = lifeCurveJson(c.temperature);
  return j;
}

json simulationJson(const sim::Settings& s) {
  json j;
  j["substeps"] = s.substeps;
  j["preroll"] = number(s.preroll);
  j["maxParticles"] = s.maxParticles;
  j["collisionRadius"] = number(s.collisionRadius);
  j["integrator"] = s.integrator == sim::Integrator::kExponential ? "exponential" : "forward-euler";
  const sim::Forces& f = s.forces;
  json forces = {{"gravity", vec3(f.gravity)}, {"buoyancy", number(f.buoyancy)}, {"up", vec3(f.up)},
                 {"drag", number(f.drag)},     {"wind", vec3(f.wind)},           {"windVolumes", json::array()},
                 {"vortices", json::array()}};
  for (const sim::WindVolume& w : f.windVolumes) {
    forces["windVolumes"].push_back({{"center", vec3(w.center)},
                                     {"halfExtent", vec3(w.halfExtent)},
                                     {"velocity", vec3(w.velocity)},
                                     {"feather", number(w.feather)}});
  }
  forces["turbulence"] = {{"strength", number(f.turbulence.strength)},
                          {"scale", number(f.turbulence.scale)},
                          {"speed", number(f.turbulence.speed)},
                          {"seed", f.turbulence.seed}};
  for (const sim::Vortex& v : f.vortices) {
    forces["vortices"].push_back({{"position", vec3(v.position)},
                                  {"axis", vec3(v.axis)},
                                  {"strength", number(v.strength)},
                                  {"radius", number(v.radius)},
                                  {"falloff", number(v.falloff)},
                                  {"length", number(v.length)},
                                  // An attached vortex's path is its object's: written as the link.
                                  {"path", v.attach.empty() ? pathKeys(v.path) : json::array()},
                                  {"attach", v.attach},
                                  {"shedInterval", number(v.shedInterval)},
                                  {"shedLifetime", number(v.shedLifetime)}});
  }
  j["forces"] = std::move(forces);
  j["emitters"] = json::array();
  for (const sim::Emitter& e : s.emitters) {
    const char* shape = e.shape == sim::Emitter::Shape::kPoint    ? "point"
                        : e.shape == sim::Emitter::Shape::kSphere ? "sphere"
                                                                  : "disc";
    j["emitters"].push_back({{"shape", shape},
                             {"position", vec3(e.position)},
                             {"radius", number(e.radius)},
                             {"normal", vec3(e.normal)},
                             {"path", e.attach.empty() ? pathKeys(e.path) : json::array()},
                             {"attach", e.attach},
                             {"rate", number(e.rate)},
                             {"start", number(e.start)},
                             {"duration", number(e.duration)},
                             {"seed", e.seed},
                             {"velocity", vec3(e.velocity)},
                             {"spread", number(e.spreadDegrees)},
                             {"speedSpread", number(e.speedSpread)},
                             {"inheritVelocity", number(e.inheritVelocity)},
                             {"density", number(e.density)},
                             {"sizeMin", number(e.sizeMin)},
                             {"sizeMax", number(e.sizeMax)},
                             {"lifetime", number(e.lifetime)},
                             {"lifetimeSpread", number(e.lifetimeSpread)},
                             {"variations", e.variations},
                             {"oriented", e.oriented},
                             {"spin", number(e.spin)},
                             {"overLife", lifeCurvesJson(e.overLife)}});
  }
  return j;
}

json materialJson(const media::Material& m, const std::vector<media::Material>& all) {
  return {{"name", m.name},
          {"albedo", number(m.albedo)},
          {"density", number(m.density)},
          {"color", vec3(m.color)},
          {"g", number(m.g)},
          {"emissive", m.emissive},
          {"temperature", number(m.temperature)},
          {"temperatureRange", number(m.temperatureRange)},
          {"emission", number(m.emission)},
          {"burn", number(m.burn)},
          {"detail", number(m.detail)},
          {"detailWindow", number(m.detailWindow)},
          {"detailSpeed", number(m.detailSpeed)},
          {"shimmer", number(m.shimmer)},
          {"becomes", m.becomes >= 0 ? json(all[static_cast<std::size_t>(m.becomes)].name) : json()},
          {"transitionStart", number(m.transitionStart)},
          {"transitionEnd", number(m.transitionEnd)}};
}

json mediaJson(const MediaSpec& m, const fs::path& dir) {
  json j;
  j["method"] = std::string(media::toString(m.method));
  j["resolution"] = number(m.resolution);
  j["phase"] = std::string(media::toString(m.settings.phase));
  j["sort"] = std::string(media::toString(m.settings.sort));
  j["blackbody"] = {{"minKelvin", number(m.settings.minKelvin)},
                    {"maxKelvin", number(m.settings.maxKelvin)},
                    {"normalizeKelvin", number(m.settings.normalizeKelvin)}};
  j["exposure"] = number(m.settings.exposure);
  j["style"] = std::string(media::toString(m.settings.style));
  const media::CartoonStyle& c = m.settings.cartoon;
  j["cartoon"] = {{"threshold", number(c.threshold)}, {"opacityBands", c.opacityBands}};
  if (c.fireColors.empty()) {
    j["cartoon"]["fireColors"] = "blackbody";
    j["cartoon"]["fireBands"] = c.fireBands;
  } else {
    j["cartoon"]["fireColors"] = json::array();
    for (const glm::vec3& colour : c.fireColors) j["cartoon"]["fireColors"].push_back(vec3(colour));
  }
  j["cartoon"]["coolKelvin"] = number(c.coolKelvin);
  j["cartoon"]["hotKelvin"] = number(c.hotKelvin);
  j["detail"] = {{"temperature", pathJson(m.temperatureDetail, dir)}, {"opacity", pathJson(m.opacityDetail, dir)}};
  j["shimmer"] = number(m.compose.shimmerPixels);
  j["depthAware"] = m.compose.depthAware;
  j["depthTolerance"] = number(m.compose.depthTolerance);
  j["motionBlur"] = {{"frames", m.motionBlurFrames}, {"persistence", number(m.motionBlurPersistence)}};
  j["materials"] = json::array();
  for (const media::Material& mt : m.materials) {
    json x = materialJson(mt, m.materials);
    if (x["becomes"].is_null()) x.erase("becomes");
    j["materials"].push_back(std::move(x));
  }
  j["particles"] = json::array();
  for (const MediaParticleSpec& p : m.particles) {
    j["particles"].push_back({{"position", vec3(p.position)},
                              {"radius", number(p.radius)},
                              {"material", p.material},
                              {"life", number(p.life)},
                              {"density", number(p.density)},
                              {"seed", p.seed}});
  }
  sim::Settings emitters;
  for (const MediaEmitterSpec& e : m.emitters) emitters.emitters.push_back(e.emitter);
  json sim = simulationJson(emitters);
  j["emitters"] = json::array();
  for (std::size_t i = 0; i < m.emitters.size(); ++i) {
    json e = sim["emitters"][i];
    e.erase("variations");
    e.erase("oriented");
    e.erase("spin");
    e["material"] = m.emitters[i].material;
    e["growth"] = number(m.emitters[i].growth);
    j["emitters"].push_back(std::move(e));
  }
  sim::Settings forces;
  forces.forces = m.forces;
  j["forces"] = simulationJson(forces)["forces"];
  j["substeps"] = m.substeps;
  j["preroll"] = number(m.preroll);
  j["maxParticles"] = m.maxParticles;
  j["collisionRadius"] = number(m.collisionRadius);
  j["lights"] = json::array();
  for (const MediaLightSpec& l : m.lights) {
    json keys = json::array();
    for (std::size_t i = 0; i < l.times.size(); ++i)
      keys.push_back({{"time", number(l.times[i])}, {"value", number(l.intensities[i])}});
    j["lights"].push_back({{"center", vec3(l.center)},
                           {"radius", number(l.radius)},
                           {"color", vec3(l.color)},
                           {"intensity", std::move(keys)},
                           {"mode", l.modulate ? "modulate" : "additive"},
                           {"full", l.fullAtBack ? "back" : "center"}});
  }
  return j;
}

json particleJson(const ParticleSpec& p) {
  return {{"position", vec3(p.position)},
          {"size", number(p.size)},
          {"variation", p.variation},
          {"oriented", p.oriented},
          {"orientation", orientationJson(p.orientation)},
          {"velocity", vec3(p.velocity)},
          {"angularVelocity", vec3(p.angularVelocity)},
          {"birth", number(p.birth)},
          {"lifetime", number(p.lifetime)}};
}

json emitterJson(const EmitterSpec& e) {
  const char* shape = e.shape == EmitterSpec::Shape::kSphere ? "sphere"
                      : e.shape == EmitterSpec::Shape::kBox  ? "box"
                                                             : "cone";
  return {{"shape", shape},
          {"count", e.count},
          {"seed", e.seed},
          {"center", vec3(e.center)},
          {"radius", number(e.radius)},
          {"halfExtent", vec3(e.halfExtent)},
          {"end", vec3(e.end)},
          {"endRadius", number(e.endRadius)},
          {"sizeMin", number(e.sizeMin)},
          {"sizeMax", number(e.sizeMax)},
          {"sizeFalloff", number(e.sizeFalloff)},
          {"variations", e.variations},
          {"oriented", e.oriented},
          {"spin", number(e.spin)},
          {"velocity", vec3(e.velocity)},
          {"speedSpread", number(e.speedSpread)},
          {"birthSpread", number(e.birthSpread)},
          {"lifetime", number(e.lifetime)},
          {"overLife", lifeCurvesJson(e.overLife)}};
}

json objectJson(const ObjectSpec& o, const fs::path& dir) {
  const char* type = o.type == ObjectSpec::Type::kPlane    ? "plane"
                     : o.type == ObjectSpec::Type::kBox    ? "box"
                     : o.type == ObjectSpec::Type::kSphere ? "sphere"
                                                           : "mesh";
  json j = {{"type", type},
            {"name", o.name},
            {"mesh", pathJson(o.mesh, dir)},
            {"translate", vec3(o.translate)},
            {"rotate", vec3(o.rotateDegrees)},
            {"scale", vec3(o.scale)},
            {"albedo", vec3(o.albedo)},
            {"shading", o.cel ? "cel" : "smooth"},
            {"collide", o.collide},
            {"friction", number(o.friction)}};
  if (o.dynamic) {
    // Its path is the simulation's, computed again when the scene is read.
    const DynamicBody& d = *o.dynamic;
    j["dynamic"] = {{"mass", number(d.mass)},
                    {"velocity", vec3(d.velocity)},
                    {"angularVelocity", vec3(d.angularVelocity)},
                    {"friction", number(d.friction)},
                    {"restitution", number(d.restitution)}};
  } else {
    j["path"] = pathKeys(o.path);
  }
  return j;
}

}  // namespace

json toJson(const Scene& s) {
  const fs::path dir = s.file.parent_path();
  json j;
  j["output"] = {{"width", s.width},
                 {"height", s.height},
                 {"samples", s.samples},
                 {"background", s.transparent ? json("transparent") : vec3(s.background)},
                 {"plate", pathJson(s.plate, dir)}};
  if (s.view) j["output"]["view"] = std::string(core::toString(*s.view));
  if (s.alpha) j["output"]["alpha"] = std::string(core::toString(*s.alpha));
  const cel::Camera& c = s.camera;
  j["camera"] = {{"position", vec3(c.position)},
                 {"target", vec3(c.target)},
                 {"up", vec3(c.up)},
                 {"fovY", number(c.fovYDegrees)},
                 {"orthoHeight", number(c.orthoHeight)},
                 {"near", number(c.nearPlane)},
                 {"far", number(c.farPlane)}};
  j["light"] = {{"direction", vec3(s.light.direction)}, {"color", vec3(s.light.color)}};
  j["ambient"] = {{"color", vec3(s.ambientColor)}, {"gradient", pathJson(s.ambientGradient, dir)}};
  j["ramp"] = {{"image", pathJson(s.ramp, dir)}, {"smooth", s.rampSmooth}};
  j["atlas"] = pathJson(s.atlas, dir);
  j["atlasLevel"] = s.atlasLevel;
  j["particleFraction"] = number(s.particleFraction);
  const cel::Style& st = s.style;
  j["style"] = {{"outlines", st.outlines},
                {"outlineWidth", number(st.outlineWidth)},
                {"outlineColor", vec3(st.outlineColor)},
                {"shading", st.shading},
                {"shadows", st.shadows},
                {"alignment", std::string(cel::toString(st.alignment))},
                {"shadowBias", number(st.shadowBias)},
                {"shadowLength", number(st.shadowLength)},
                {"shadowMethod", std::string(cel::toString(st.shadowMethod))},
                {"shadowMapScale", number(st.shadowMapScale)},
                {"tumble", std::string(cel::toString(st.tumble))},
                {"hullFromPixels", number(st.hullFromPixels)}};
  if (!s.stylePreset.empty()) j["style"]["preset"] = s.stylePreset;
  j["particles"] = json::array();
  for (const ParticleSpec& p : s.particles) j["particles"].push_back(particleJson(p));
  j["emitters"] = json::array();
  for (const EmitterSpec& e : s.emitters) j["emitters"].push_back(emitterJson(e));
  j["objects"] = json::array();
  for (const ObjectSpec& o : s.objects) j["objects"].push_back(objectJson(o, dir));
  j["rigidBodies"] = {{"gravity", vec3(s.rigidBodies.gravity)}, {"stepsPerSecond", s.rigidBodies.stepsPerSecond}};
  j["animation"] = {{"fps", number(s.animation.fps)},
                    {"frames", s.animation.frames},
                    {"orbit", number(s.animation.orbitDegreesPerSecond)},
                    {"period", s.animation.period},
                    {"cameraPath", pathKeys(s.animation.cameraPath)},
                    {"targetPath", pathKeys(s.animation.targetPath)}};
  if (s.simulation) j["simulation"] = simulationJson(*s.simulation);
  if (s.media) j["media"] = mediaJson(*s.media, dir);
  j["fixed"] = {{"puff", pathJson(s.fixed.puff, dir)},
                {"outlineScale", number(s.fixed.outlineScale)},
                {"outlineOffset", number(s.fixed.outlineOffset)},
                {"cellSize", s.fixed.cellSize}};
  return j;
}

namespace {

void printJson(std::string& out, const json& j, int indent) {
  const std::string pad(static_cast<std::size_t>(indent) + 2, ' ');
  const bool flat = j.is_array() && std::none_of(j.begin(), j.end(), [](const auto& v) { return v.is_structured(); });
  if (j.is_object() && !j.empty()) {
    out += "{\n";
    std::size_t i = 0;
    for (const auto& item : j.items()) {
      out += pad + json(item.key()).dump() + ": ";
      printJson(out, item.value(), indent + 2);
      out += ++i < j.size() ? ",\n" : "\n";
    }
    out += std::string(static_cast<std::size_t>(indent), ' ') + "}";
  } else if (j.is_array() && !j.empty() && !flat) {
    out += "[\n";
    for (std::size_t i = 0; i < j.size(); ++i) {
      out += pad;
      printJson(out, j[i], indent + 2);
      out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += std::string(static_cast<std::size_t>(indent), ' ') + "]";
  } else if (flat && !j.empty()) {
    out += "[";
    for (std::size_t i = 0; i < j.size(); ++i) out += (i ? ", " : "") + j[i].dump();
    out += "]";
  } else {
    out += j.dump();
  }
}

}  // namespace

std::string jsonText(const json& j) {
  std::string out;
  printJson(out, j, 0);
  return out;
}

}  // namespace puff::scene
