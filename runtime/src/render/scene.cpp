// Scene files: JSON -> Scene with every value checked, Scene -> JSON, and the pure evaluation of a
// frame (particles, camera). docs/scene-format.md is the reference for the format.
#include <puff/render/scene.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <sstream>
#include <string_view>
#include <system_error>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <puff/mesh/mesh.h>

namespace puff::render {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr int kMaxImageSize = 16384;
constexpr int kMaxEmitterCount = 1'000'000;
constexpr long long kMaxParticles = 2'000'000;
constexpr int kMaxFrames = 10'000'000;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::string_view kArtVariable = "${PUFF_ART}";

// ---- reading ----------------------------------------------------------------------------------

// The parser stops at the first problem. A Failure carries "/pointer: problem" up to parseScene,
// which turns it into the Error value; no exception leaves this file.
struct Failure {
  std::string message;
};

std::string pointerToken(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

std::string child(const std::string& ptr, std::string_view key) { return ptr + "/" + pointerToken(key); }
std::string child(const std::string& ptr, std::size_t index) { return ptr + "/" + std::to_string(index); }

// A value as the user wrote it, for "got ...": short values verbatim, long ones by kind.
std::string describe(const json& v) {
  if (v.is_number_float() && !std::isfinite(v.get<double>())) return "a non-finite number";
  std::string text = v.dump(-1, ' ', false, json::error_handler_t::replace);
  if (text.size() <= 48) return text;
  if (v.is_array()) return "an array of " + std::to_string(v.size()) + " elements";
  if (v.is_object()) return "an object with " + std::to_string(v.size()) + " keys";
  return text.substr(0, 45) + "...";
}

[[noreturn]] void fail(const std::string& ptr, const std::string& expected, const json& got) {
  throw Failure{ptr + ": expected " + expected + ", got " + describe(got)};
}

[[noreturn]] void failText(const std::string& ptr, const std::string& message) { throw Failure{ptr + ": " + message}; }

std::string join(std::initializer_list<std::string_view> names) {
  std::string out;
  for (std::string_view n : names) {
    if (!out.empty()) out += ", ";
    out += n;
  }
  return out;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// Checks that `j` is an object whose keys are all in `allowed`: a misspelt key is an error, never
// silently ignored. Suggests the nearest allowed key for a likely typo.
void requireObject(const json& j, const std::string& ptr, std::initializer_list<std::string_view> allowed) {
  if (!j.is_object()) fail(ptr.empty() ? std::string("(top level)") : ptr, "an object", j);
  for (const auto& item : j.items()) {
    const std::string& key = item.key();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string message = "unknown key, expected one of " + join(allowed);
    std::string_view best;
    std::size_t bestDistance = 3;  // at most two edits away
    for (std::string_view name : allowed) {
      const std::size_t d = editDistance(lower(key), lower(name));
      if (d < bestDistance) bestDistance = d, best = name;
    }
    if (!best.empty()) message += " (did you mean \"" + std::string(best) + "\"?)";
    failText(child(ptr, key), message);
  }
}

const json* find(const json& obj, std::string_view key) {
  auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}

std::string formatNumber(double d) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", d);
  return b;
}

// A numeric range with open or closed ends; either end may be infinite.
struct Range {
  double lo = -kInf, hi = kInf;
  bool loOpen = false, hiOpen = false;

  bool contains(double d) const { return (loOpen ? d > lo : d >= lo) && (hiOpen ? d < hi : d <= hi); }
  std::string text(const char* noun = "a number") const {
    const bool hasLo = std::isfinite(lo), hasHi = std::isfinite(hi);
    if (!hasLo && !hasHi) return std::string(noun);
    if (!hasHi) return std::string(noun) + (loOpen ? " > " : " >= ") + formatNumber(lo);
    if (!hasLo) return std::string(noun) + (hiOpen ? " < " : " <= ") + formatNumber(hi);
    return std::string(noun) + " in " + (loOpen ? "(" : "[") + formatNumber(lo) + ", " + formatNumber(hi) +
           (hiOpen ? ")" : "]");
  }
};

constexpr Range kAny{};
constexpr Range kNonNegative{0.0, kInf, false, false};
constexpr Range kPositive{0.0, kInf, true, false};
constexpr Range kUnit{0.0, 1.0, false, false};

float readFloat(const json& v, const std::string& ptr, const Range& range = kAny, const std::string& expected = {}) {
  const std::string what = expected.empty() ? range.text() : expected;
  if (!v.is_number()) fail(ptr, what, v);
  const double d = v.get<double>();
  const float f = static_cast<float>(d);
  if (!std::isfinite(d) || !std::isfinite(f) || !range.contains(d)) fail(ptr, what, v);
  return f;
}

long long readInteger(const json& v, const std::string& ptr, long long lo, long long hi,
                      const std::string& expected = {}) {
  const std::string what =
      expected.empty() ? "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" : expected;
  if (!v.is_number()) fail(ptr, what, v);
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(hi) || static_cast<long long>(u) < lo) fail(ptr, what, v);
    return static_cast<long long>(u);
  }
  if (v.is_number_integer()) {
    const auto i = v.get<std::int64_t>();
    if (i < lo || i > hi) fail(ptr, what, v);
    return i;
  }
  const double d = v.get<double>();  // 640.0 is an integer; 640.5 is not
  if (!std::isfinite(d) || d != std::floor(d) || d < static_cast<double>(lo) || d > static_cast<double>(hi)) {
    fail(ptr, what, v);
  }
  return static_cast<long long>(d);
}

int readInt(const json& v, const std::string& ptr, int lo, int hi) {
  return static_cast<int>(readInteger(v, ptr, lo, hi));
}

bool readBool(const json& v, const std::string& ptr) {
  if (!v.is_boolean()) fail(ptr, "true or false", v);
  return v.get<bool>();
}

std::string readString(const json& v, const std::string& ptr, const std::string& expected = "a string") {
  if (!v.is_string()) fail(ptr, expected, v);
  return v.get<std::string>();
}

glm::vec3 readVec3(const json& v, const std::string& ptr, const Range& range = kAny) {
  // The range applies to each element; an element out of range is reported at its own pointer.
  if (!v.is_array() || v.size() != 3) fail(ptr, "an array of 3 numbers", v);
  glm::vec3 out;
  for (int i = 0; i < 3; ++i)
    out[i] = readFloat(v[static_cast<std::size_t>(i)], child(ptr, static_cast<std::size_t>(i)), range);
  return out;
}

int hexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// [r, g, b] in [0, 1] or "#rrggbb".
glm::vec3 readColor(const json& v, const std::string& ptr) {
  static const std::string kWhat = "a colour: [r, g, b] in [0, 1] or \"#rrggbb\"";
  if (v.is_string()) {
    const std::string s = v.get<std::string>();
    glm::vec3 c;
    bool ok = s.size() == 7 && s[0] == '#';
    for (int i = 0; ok && i < 3; ++i) {
      const int hi = hexDigit(s[static_cast<std::size_t>(1 + 2 * i)]),
                lo = hexDigit(s[static_cast<std::size_t>(2 + 2 * i)]);
      ok = hi >= 0 && lo >= 0;
      if (ok) c[i] = static_cast<float>(hi * 16 + lo) / 255.0f;
    }
    if (!ok) fail(ptr, kWhat, v);
    return c;
  }
  if (!v.is_array() || v.size() != 3) fail(ptr, kWhat, v);
  return readVec3(v, ptr, kUnit);
}

template <class Enum>
Enum readEnum(const json& v, const std::string& ptr, std::initializer_list<std::pair<std::string_view, Enum>> names) {
  std::string list;
  for (const auto& [name, value] : names) list += (list.empty() ? "" : ", ") + std::string(name);
  const std::string what = "one of " + list;
  if (!v.is_string()) fail(ptr, what, v);
  const std::string s = v.get<std::string>();
  for (const auto& [name, value] : names) {
    if (s == name) return value;
  }
  fail(ptr, what, v);
}

class Reader {
 public:
  Reader(const fs::path& file, const fs::path& artDir) : dir_(file.parent_path()), artDir_(artDir) {}

  // A path as written: "" is none; "${PUFF_ART}/x" lies in the art directory; a relative path is
  // relative to the scene file's directory.
  fs::path readPath(const json& v, const std::string& ptr) const {
    const std::string s = readString(v, ptr, "a path (a string)");
    if (s.empty()) return {};
    if (s.rfind(kArtVariable, 0) == 0) {
      if (artDir_.empty()) failText(ptr, "\"${PUFF_ART}\" needs an art directory, and none was given (--art-dir)");
      std::string rest = s.substr(kArtVariable.size());
      while (!rest.empty() && rest.front() == '/') rest.erase(rest.begin());
      return (rest.empty() ? artDir_ : artDir_ / rest).lexically_normal();
    }
    // Lexically normal, so a path written back by toJson reads back as the same path.
    const fs::path p(s);
    return (p.is_absolute() ? p : dir_ / p).lexically_normal();
  }

 private:
  fs::path dir_, artDir_;
};

void readOutput(const json& j, const std::string& ptr, Scene& s) {
  requireObject(j, ptr, {"width", "height", "samples", "background"});
  if (auto* v = find(j, "width")) s.width = readInt(*v, child(ptr, "width"), 1, kMaxImageSize);
  if (auto* v = find(j, "height")) s.height = readInt(*v, child(ptr, "height"), 1, kMaxImageSize);
  if (auto* v = find(j, "samples")) {
    const int n = static_cast<int>(readInteger(*v, child(ptr, "samples"), 1, 8, "1, 2, 4 or 8"));
    if (n != 1 && n != 2 && n != 4 && n != 8) fail(child(ptr, "samples"), "1, 2, 4 or 8", *v);
    s.samples = n;
  }
  if (auto* v = find(j, "background")) s.background = readColor(*v, child(ptr, "background"));
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
    if (auto* v = find(j, "far")) fail(child(ptr, "far"), "a number > near (" + formatNumber(c.nearPlane) + ")", *v);
    fail(child(ptr, "near"), "a number < far (" + formatNumber(c.farPlane) + ")", *find(j, "near"));
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

void readLight(const json& j, const std::string& ptr, cel::Light& l) {
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
                 "shadowLength"});
  // The preset first, whatever the key order: explicit fields then change what it set.
  if (auto* v = find(j, "preset")) {
    const std::string name = readString(*v, child(ptr, "preset"));
    auto preset = stylePreset(name);
    if (!preset) {
      std::string list;
      for (const std::string& n : stylePresetNames()) list += (list.empty() ? "" : ", ") + n;
      fail(child(ptr, "preset"), "one of " + list, *v);
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
    const std::string what = "one of view-plane, viewpoint, axial";
    const std::string name = readString(*v, child(ptr, "alignment"), what);
    auto a = cel::parseAlignment(name);
    if (!a) fail(child(ptr, "alignment"), what, *v);
    st.alignment = *a;
  }
  if (auto* v = find(j, "shadowBias")) st.shadowBias = readFloat(*v, child(ptr, "shadowBias"), kUnit);
  if (auto* v = find(j, "shadowLength")) st.shadowLength = readFloat(*v, child(ptr, "shadowLength"), kPositive);
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
  requireObject(
      j, ptr,
      {"shape", "count", "seed", "center", "radius", "halfExtent", "end", "endRadius", "sizeMin", "sizeMax",
       "sizeFalloff", "variations", "oriented", "spin", "velocity", "speedSpread", "birthSpread", "lifetime"});
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
      fail(child(ptr, "sizeMax"), "a number >= sizeMin (" + formatNumber(e.sizeMin) + ")", *v);
    }
    fail(child(ptr, "sizeMin"), "a number <= sizeMax (" + formatNumber(e.sizeMax) + ")", *find(j, "sizeMin"));
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
  return e;
}

const Range kMagnitude{-sim::kMaxMagnitude, sim::kMaxMagnitude};
const Range kNonNegativeMagnitude{0.0, sim::kMaxMagnitude};

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
      fail(child(p, "time"), "a time after the previous key (" + formatNumber(path.times.back()) + ")", *t);
    }
    path.times.push_back(time);
    path.points.push_back(readVec3(*x, child(p, "position"), kMagnitude));
  }
  return path;
}

ObjectSpec readObject(const json& j, const std::string& ptr, std::size_t index, const Reader& r) {
  requireObject(
      j, ptr,
      {"type", "name", "mesh", "translate", "rotate", "scale", "albedo", "shading", "path", "collide", "friction"});
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
    if (auto* v = find(j, "mesh")) fail(child(ptr, "mesh"), "a mesh file (OBJ, OFF, PLY or STL)", *v);
    failText(child(ptr, "mesh"), "expected a mesh file (OBJ, OFF, PLY or STL) for type \"mesh\", got none");
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
  return o;
}

void readAnimation(const json& j, const std::string& ptr, Animation& a) {
  requireObject(j, ptr, {"fps", "frames", "orbit", "cameraPath", "targetPath"});
  if (auto* v = find(j, "fps")) a.fps = readFloat(*v, child(ptr, "fps"), Range{0.0, 1000.0, true, false});
  if (auto* v = find(j, "frames")) a.frames = readInt(*v, child(ptr, "frames"), 1, kMaxFrames);
  if (auto* v = find(j, "orbit")) a.orbitDegreesPerSecond = readFloat(*v, child(ptr, "orbit"));
  if (auto* v = find(j, "cameraPath")) a.cameraPath = readPath3(*v, child(ptr, "cameraPath"));
  if (auto* v = find(j, "targetPath")) a.targetPath = readPath3(*v, child(ptr, "targetPath"));
}

// ---- simulation -------------------------------------------------------------------------------

glm::vec3 readDirection(const json& v, const std::string& ptr) {
  const glm::vec3 d = readVec3(v, ptr, kMagnitude);
  if (!(glm::length(d) > 0.0f)) fail(ptr, "a non-zero direction", v);
  return d;
}

sim::Vortex readVortex(const json& j, const std::string& ptr) {
  requireObject(j, ptr,
                {"position", "axis", "strength", "radius", "falloff", "length", "path", "attach", "shedInterval",
                 "shedLifetime"});
  sim::Vortex v;
  if (auto* x = find(j, "position")) v.position = readVec3(*x, child(ptr, "position"), kMagnitude);
  if (auto* x = find(j, "axis")) v.axis = readDirection(*x, child(ptr, "axis"));
  if (auto* x = find(j, "strength")) v.strength = readFloat(*x, child(ptr, "strength"), kMagnitude);
  if (auto* x = find(j, "radius")) v.radius = readFloat(*x, child(ptr, "radius"), Range{1e-4, sim::kMaxMagnitude});
  if (auto* x = find(j, "falloff")) v.falloff = readFloat(*x, child(ptr, "falloff"), kNonNegativeMagnitude);
  if (auto* x = find(j, "length")) v.length = readFloat(*x, child(ptr, "length"), kNonNegativeMagnitude);
  if (auto* x = find(j, "path")) v.path = readPath3(*x, child(ptr, "path"));
  if (auto* x = find(j, "attach")) v.attach = readString(*x, child(ptr, "attach"), "the name of a scene object");
  if (auto* x = find(j, "shedInterval")) {
    v.shedInterval = readFloat(*x, child(ptr, "shedInterval"), Range{0.0, 1e4},
                               "0 (no shedding) or a number of seconds in [0.001, 10000]");
    if (v.shedInterval > 0.0f && v.shedInterval < 1e-3f)
      fail(child(ptr, "shedInterval"), "0 (no shedding) or a number of seconds in [0.001, 10000]", *x);
  }
  if (auto* x = find(j, "shedLifetime"))
    v.shedLifetime = readFloat(*x, child(ptr, "shedLifetime"), Range{0.0, 1e4, true, false});
  return v;
}

sim::Forces readForces(const json& j, const std::string& ptr) {
  requireObject(j, ptr, {"gravity", "buoyancy", "up", "drag", "wind", "windVolumes", "turbulence", "vortices"});
  sim::Forces f;
  if (auto* v = find(j, "gravity")) f.gravity = readVec3(*v, child(ptr, "gravity"), kMagnitude);
  if (auto* v = find(j, "buoyancy")) f.buoyancy = readFloat(*v, child(ptr, "buoyancy"), kMagnitude);
  if (auto* v = find(j, "up")) f.up = readDirection(*v, child(ptr, "up"));
  if (auto* v = find(j, "drag")) f.drag = readFloat(*v, child(ptr, "drag"), kNonNegativeMagnitude);
  if (auto* v = find(j, "wind")) f.wind = readVec3(*v, child(ptr, "wind"), kMagnitude);
  if (auto* v = find(j, "windVolumes")) {
    const std::string p = child(ptr, "windVolumes");
    if (!v->is_array()) fail(p, "an array of wind volumes", *v);
    for (std::size_t i = 0; i < v->size(); ++i) {
      const std::string q = child(p, i);
      const json& w = (*v)[i];
      requireObject(w, q, {"center", "halfExtent", "velocity", "feather"});
      sim::WindVolume vol;
      if (auto* x = find(w, "center")) vol.center = readVec3(*x, child(q, "center"), kMagnitude);
      if (auto* x = find(w, "halfExtent")) vol.halfExtent = readVec3(*x, child(q, "halfExtent"), kNonNegativeMagnitude);
      if (auto* x = find(w, "velocity")) vol.velocity = readVec3(*x, child(q, "velocity"), kMagnitude);
      if (auto* x = find(w, "feather")) vol.feather = readFloat(*x, child(q, "feather"), kNonNegativeMagnitude);
      f.windVolumes.push_back(vol);
    }
  }
  if (auto* v = find(j, "turbulence")) {
    const std::string p = child(ptr, "turbulence");
    requireObject(*v, p, {"strength", "scale", "speed", "seed"});
    sim::Turbulence& t = f.turbulence;
    if (auto* x = find(*v, "strength")) t.strength = readFloat(*x, child(p, "strength"), kNonNegativeMagnitude);
    if (auto* x = find(*v, "scale")) t.scale = readFloat(*x, child(p, "scale"), Range{1e-4, sim::kMaxMagnitude});
    if (auto* x = find(*v, "speed")) t.speed = readFloat(*x, child(p, "speed"), Range{0.0, 1e3});
    if (auto* x = find(*v, "seed"))
      t.seed = static_cast<std::uint32_t>(readInteger(*x, child(p, "seed"), 0, 0xffffffffLL));
  }
  if (auto* v = find(j, "vortices")) {
    const std::string p = child(ptr, "vortices");
    if (!v->is_array()) fail(p, "an array of vortices", *v);
    for (std::size_t i = 0; i < v->size(); ++i) f.vortices.push_back(readVortex((*v)[i], child(p, i)));
  }
  return f;
}

sim::Emitter readSimEmitter(const json& j, const std::string& ptr) {
  requireObject(j, ptr, {"shape",          "position",        "radius",   "normal",  "path",     "attach",
                         "rate",           "start",           "duration", "seed",    "velocity", "spread",
                         "speedSpread",    "inheritVelocity", "density",  "sizeMin", "sizeMax",  "lifetime",
                         "lifetimeSpread", "variations",      "oriented", "spin"});
  sim::Emitter e;
  using Shape = sim::Emitter::Shape;
  if (auto* v = find(j, "shape")) {
    e.shape = readEnum<Shape>(*v, child(ptr, "shape"),
                              {{"point", Shape::kPoint}, {"sphere", Shape::kSphere}, {"disc", Shape::kDisc}});
  }
  if (auto* v = find(j, "position")) e.position = readVec3(*v, child(ptr, "position"), kMagnitude);
  if (auto* v = find(j, "radius")) e.radius = readFloat(*v, child(ptr, "radius"), kNonNegativeMagnitude);
  if (auto* v = find(j, "normal")) e.normal = readDirection(*v, child(ptr, "normal"));
  if (auto* v = find(j, "path")) e.path = readPath3(*v, child(ptr, "path"));
  if (auto* v = find(j, "attach")) e.attach = readString(*v, child(ptr, "attach"), "the name of a scene object");
  if (auto* v = find(j, "rate"))
    e.rate = readFloat(*v, child(ptr, "rate"), Range{0.0, 1e7}, "particles per second in [0, 1e+07]");
  if (auto* v = find(j, "start")) e.start = readFloat(*v, child(ptr, "start"), kMagnitude);
  if (auto* v = find(j, "duration"))
    e.duration = readFloat(*v, child(ptr, "duration"), kNonNegativeMagnitude, "seconds >= 0 (0: never stops)");
  if (auto* v = find(j, "seed"))
    e.seed = static_cast<std::uint32_t>(readInteger(*v, child(ptr, "seed"), 0, 0xffffffffLL));
  if (auto* v = find(j, "velocity")) e.velocity = readVec3(*v, child(ptr, "velocity"), kMagnitude);
  if (auto* v = find(j, "spread")) e.spreadDegrees = readFloat(*v, child(ptr, "spread"), Range{0.0, 180.0});
  if (auto* v = find(j, "speedSpread")) e.speedSpread = readFloat(*v, child(ptr, "speedSpread"), kUnit);
  if (auto* v = find(j, "inheritVelocity"))
    e.inheritVelocity = readFloat(*v, child(ptr, "inheritVelocity"), Range{-10.0, 10.0});
  if (auto* v = find(j, "density")) e.density = readFloat(*v, child(ptr, "density"), Range{0.0, 1e3, true, false});
  if (auto* v = find(j, "sizeMin")) e.sizeMin = readFloat(*v, child(ptr, "sizeMin"), kNonNegativeMagnitude);
  if (auto* v = find(j, "sizeMax")) e.sizeMax = readFloat(*v, child(ptr, "sizeMax"), kNonNegativeMagnitude);
  if (e.sizeMin > e.sizeMax) {
    if (auto* v = find(j, "sizeMax"))
      fail(child(ptr, "sizeMax"), "a size >= sizeMin (" + formatNumber(e.sizeMin) + ")", *v);
    fail(child(ptr, "sizeMin"), "a size <= sizeMax (" + formatNumber(e.sizeMax) + ")", *find(j, "sizeMin"));
  }
  if (auto* v = find(j, "lifetime"))
    e.lifetime = readFloat(*v, child(ptr, "lifetime"), Range{0.0, 1e6, true, false}, "a lifetime in seconds > 0");
  if (auto* v = find(j, "lifetimeSpread"))
    e.lifetimeSpread = readFloat(*v, child(ptr, "lifetimeSpread"), Range{0.0, 1.0, false, true});
  if (auto* v = find(j, "variations")) {
    const std::string p = child(ptr, "variations");
    if (!v->is_array()) fail(p, "an array of variation numbers in [0, 255]", *v);
    for (std::size_t i = 0; i < v->size(); ++i) e.variations.push_back(readInt((*v)[i], child(p, i), 0, 255));
  }
  if (auto* v = find(j, "oriented")) e.oriented = readBool(*v, child(ptr, "oriented"));
  if (auto* v = find(j, "spin")) e.spin = readFloat(*v, child(ptr, "spin"), Range{0.0, 1e3});
  return e;
}

sim::Settings readSimulation(const json& j, const std::string& ptr) {
  requireObject(j, ptr, {"substeps", "preroll", "maxParticles", "collisionRadius", "integrator", "forces", "emitters"});
  sim::Settings s;
  if (auto* v = find(j, "substeps")) s.substeps = readInt(*v, child(ptr, "substeps"), 1, 1000);
  if (auto* v = find(j, "preroll")) s.preroll = readFloat(*v, child(ptr, "preroll"), Range{0.0, 3600.0});
  if (auto* v = find(j, "maxParticles")) {
    s.maxParticles = static_cast<std::size_t>(
        readInteger(*v, child(ptr, "maxParticles"), 0, static_cast<long long>(sim::kMaxParticleBudget),
                    "a particle budget in [0, " + std::to_string(sim::kMaxParticleBudget) +
                        "] (about 64 bytes each; more would not fit in memory)"));
  }
  if (auto* v = find(j, "collisionRadius")) s.collisionRadius = readFloat(*v, child(ptr, "collisionRadius"), kUnit);
  if (auto* v = find(j, "integrator")) {
    s.integrator = readEnum<sim::Integrator>(
        *v, child(ptr, "integrator"),
        {{"exponential", sim::Integrator::kExponential}, {"forward-euler", sim::Integrator::kForwardEuler}});
  }
  if (auto* v = find(j, "forces")) s.forces = readForces(*v, child(ptr, "forces"));
  if (auto* v = find(j, "emitters")) {
    const std::string p = child(ptr, "emitters");
    if (!v->is_array()) fail(p, "an array of emitters", *v);
    for (std::size_t i = 0; i < v->size(); ++i) s.emitters.push_back(readSimEmitter((*v)[i], child(p, i)));
  }
  return s;
}

// ---- media --------------------------------------------------------------------------------------

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
  if (auto* v = find(j, "detailSpeed")) m.detailSpeed = readFloat(*v, child(ptr, "detailSpeed"), Range{0.0, 1e3});
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
          fail(child(k, "time"), "a time after the previous key (" + formatNumber(l.times.back()) + ")", *t);
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

MediaSpec readMedia(const json& j, const std::string& ptr, const Reader& r) {
  requireObject(j, ptr,
                {"method", "resolution", "phase", "blackbody", "exposure", "detail", "shimmer", "depthAware",
                 "depthTolerance", "motionBlur", "materials", "particles", "emitters", "forces", "substeps", "preroll",
                 "maxParticles", "collisionRadius", "lights"});
  MediaSpec m;
  if (auto* v = find(j, "method")) {
    m.method = readEnum<media::Method>(*v, child(ptr, "method"),
                                       {{"planar", media::Method::kPlanar},
                                        {"soft-linear", media::Method::kSoftLinear},
                                        {"soft-scurve", media::Method::kSoftSCurve},
                                        {"spherical", media::Method::kSpherical}});
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
  if (auto* v = find(j, "blackbody")) {
    const std::string p = child(ptr, "blackbody");
    requireObject(*v, p, {"minKelvin", "maxKelvin", "normalizeKelvin"});
    const Range kelvin{0.0, 1e5, true, false};
    if (auto* x = find(*v, "minKelvin")) m.settings.minKelvin = readFloat(*x, child(p, "minKelvin"), kelvin);
    if (auto* x = find(*v, "maxKelvin")) m.settings.maxKelvin = readFloat(*x, child(p, "maxKelvin"), kelvin);
    if (auto* x = find(*v, "normalizeKelvin"))
      m.settings.normalizeKelvin = readFloat(*x, child(p, "normalizeKelvin"), kelvin);
    if (!(m.settings.maxKelvin > m.settings.minKelvin)) {
      const char* key = find(*v, "maxKelvin") ? "maxKelvin" : "minKelvin";
      fail(child(p, key), "maxKelvin > minKelvin", *find(*v, key));
    }
  }
  if (auto* v = find(j, "exposure")) m.settings.exposure = readFloat(*v, child(ptr, "exposure"), Range{0.0, 1e4});
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
    if (auto* x = find(*v, "frames")) m.motionBlurFrames = readInt(*x, child(p, "frames"), 0, 7);
    if (auto* x = find(*v, "persistence"))
      m.motionBlurPersistence = readFloat(*x, child(p, "persistence"), Range{0.0, 1.0, false, true});
  }
  if (auto* v = find(j, "materials")) {
    const std::string p = child(ptr, "materials");
    if (!v->is_array() || v->empty() || v->size() > 32) fail(p, "an array of 1 to 32 materials", *v);
    m.materials.clear();
    std::vector<std::string> becomes;
    for (std::size_t i = 0; i < v->size(); ++i) {
      m.materials.push_back(readMaterial((*v)[i], child(p, i), becomes));
      for (std::size_t k = 0; k + 1 < m.materials.size(); ++k)
        if (m.materials[k].name == m.materials.back().name)
          fail(child(child(p, i), "name"), "a name no other material has", *find((*v)[i], "name"));
    }
    for (std::size_t i = 0; i < becomes.size(); ++i) {
      if (becomes[i].empty()) continue;
      m.materials[i].becomes = materialIndex(m, *find((*v)[i], "becomes"), child(child(p, i), "becomes"));
    }
  }
  if (auto* v = find(j, "particles")) {
    const std::string p = child(ptr, "particles");
    if (!v->is_array() || v->size() > static_cast<std::size_t>(kMaxParticles))
      fail(p, "an array of at most " + std::to_string(kMaxParticles) + " particles", *v);
    for (std::size_t i = 0; i < v->size(); ++i) {
      const std::string q = child(p, i);
      const json& x = (*v)[i];
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
  if (auto* v = find(j, "emitters")) {
    const std::string p = child(ptr, "emitters");
    if (!v->is_array()) fail(p, "an array of emitters", *v);
    for (std::size_t i = 0; i < v->size(); ++i) {
      const std::string q = child(p, i);
      json e = (*v)[i];
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
      s.emitter = readSimEmitter(e, q);
      m.emitters.push_back(std::move(s));
    }
  }
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
    if (!v->is_array() || v->size() > 8) fail(p, "an array of at most 8 lights", *v);
    for (std::size_t i = 0; i < v->size(); ++i) m.lights.push_back(readMediaLight((*v)[i], child(p, i)));
  }
  return m;
}

Scene readScene(const json& j, const fs::path& file, const fs::path& artDir) {
  if (!j.is_object()) throw Failure{"expected a JSON object at the top level, got " + describe(j)};
  requireObject(j, "",
                {"output", "camera", "light", "ambient", "ramp", "atlas", "atlasLevel", "particleFraction", "style",
                 "particles", "emitters", "objects", "animation", "simulation", "fixed", "media"});
  const Reader r(file, artDir);
  Scene s;
  s.file = file;
  if (auto* v = find(j, "output")) readOutput(*v, "/output", s);
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
  if (auto* v = find(j, "objects")) {
    if (!v->is_array()) fail("/objects", "an array of objects", *v);
    for (std::size_t i = 0; i < v->size(); ++i) s.objects.push_back(readObject((*v)[i], child("/objects", i), i, r));
  }
  if (auto* v = find(j, "animation")) readAnimation(*v, "/animation", s.animation);
  if (auto* v = find(j, "fixed")) {
    const std::string ptr = "/fixed";
    requireObject(*v, ptr, {"puff", "outlineScale", "outlineOffset", "cellSize"});
    if (auto* x = find(*v, "puff")) s.fixed.puff = r.readPath(*x, child(ptr, "puff"));
    if (auto* x = find(*v, "outlineScale"))
      s.fixed.outlineScale = readFloat(*x, child(ptr, "outlineScale"), Range{1.0, 4.0});
    if (auto* x = find(*v, "outlineOffset"))
      s.fixed.outlineOffset = readFloat(*x, child(ptr, "outlineOffset"), kNonNegativeMagnitude);
    if (auto* x = find(*v, "cellSize")) {
      const int c = static_cast<int>(readInteger(*x, child(ptr, "cellSize"), 32, 256, "32, 64, 128 or 256"));
      if (c != 32 && c != 64 && c != 128 && c != 256) fail(child(ptr, "cellSize"), "32, 64, 128 or 256", *x);
      s.fixed.cellSize = c;
    }
  }
  // Vortices and emitters that ride on an object follow its path (their position is an offset
  // from where the object is).
  auto resolve = [&](const std::string& name, sim::Path& path, const std::string& ptr) {
    if (name.empty()) return;
    const auto it =
        std::find_if(s.objects.begin(), s.objects.end(), [&](const ObjectSpec& o) { return o.name == name; });
    if (it == s.objects.end()) {
      std::string names;
      for (const ObjectSpec& o : s.objects) names += (names.empty() ? "" : ", ") + o.name;
      failText(ptr, "expected the name of a scene object (" + (names.empty() ? std::string("there are none") : names) +
                        "), got \"" + name + "\"");
    }
    if (std::count_if(s.objects.begin(), s.objects.end(), [&](const ObjectSpec& o) { return o.name == name; }) > 1)
      failText(ptr, "\"" + name + "\" names more than one object; give the object a unique name");
    if (!path.empty()) failText(ptr, "a vortex or emitter follows its own path or an object, not both");
    path = it->path;
    if (path.empty()) path = sim::Path{{0.0f}, {glm::vec3(0.0f)}};
    for (glm::vec3& p : path.points) p += it->translate;
  };
  if (auto* v = find(j, "simulation")) {
    s.simulation = readSimulation(*v, "/simulation");
    s.simulation->fps = s.animation.fps;
    for (std::size_t i = 0; i < s.simulation->forces.vortices.size(); ++i) {
      sim::Vortex& vortex = s.simulation->forces.vortices[i];
      resolve(vortex.attach, vortex.path, "/simulation/forces/vortices/" + std::to_string(i) + "/attach");
    }
    for (std::size_t i = 0; i < s.simulation->emitters.size(); ++i) {
      sim::Emitter& e = s.simulation->emitters[i];
      resolve(e.attach, e.path, "/simulation/emitters/" + std::to_string(i) + "/attach");
    }
    // What the reader does not see (cross-field limits): the simulator's own check.
    if (auto ok = sim::validate(*s.simulation); !ok) throw Failure{"/simulation" + ok.error().message};
    if (!s.simulation->emitters.empty()) total = std::max(total, 1LL);
  }
  if (auto* v = find(j, "media")) {
    s.media = readMedia(*v, "/media", r);
    for (std::size_t i = 0; i < s.media->forces.vortices.size(); ++i) {
      sim::Vortex& vortex = s.media->forces.vortices[i];
      resolve(vortex.attach, vortex.path, "/media/forces/vortices/" + std::to_string(i) + "/attach");
    }
    for (std::size_t i = 0; i < s.media->emitters.size(); ++i) {
      sim::Emitter& e = s.media->emitters[i].emitter;
      resolve(e.attach, e.path, "/media/emitters/" + std::to_string(i) + "/attach");
    }
    if (!s.media->emitters.empty() || !s.media->forces.vortices.empty()) {
      sim::Settings check;
      check.forces = s.media->forces;
      for (const MediaEmitterSpec& e : s.media->emitters) check.emitters.push_back(e.emitter);
      if (auto ok = sim::validate(check); !ok) throw Failure{"/media" + ok.error().message};
    }
  }
  if (total > 0 && s.atlas.empty()) {
    if (auto* v = find(j, "atlas")) fail("/atlas", "an atlas sidecar path (the scene has particles)", *v);
    failText("/atlas", "expected an atlas sidecar path (the scene has particles), got none");
  }
  return s;
}

// "LINE:COLUMN" of byte offset `at` (0-based) in `text`.
std::string lineColumn(const std::string& text, std::size_t at) {
  at = std::min(at, text.size());
  std::size_t line = 1, lineStart = 0;
  for (std::size_t i = 0; i < at; ++i) {
    if (text[i] == '\n') ++line, lineStart = i + 1;
  }
  return std::to_string(line) + ":" + std::to_string(at - lineStart + 1);
}

// nlohmann's parse_error knows the byte offset; editors want line and column.
std::string syntaxErrorMessage(const json::parse_error& e, const std::string& text) {
  // what(): "[json.exception.parse_error.101] parse error at line 3, column 5: syntax error ..."
  std::string what = e.what();
  if (auto colon = what.find(": "); colon != std::string::npos) what = what.substr(colon + 2);
  return lineColumn(text, e.byte == 0 ? 0 : e.byte - 1) + ": " + what;
}

// Other parser exceptions carry no position: "number overflow parsing '1e999'" names the text,
// which is found again to point at it.
std::string otherErrorMessage(const json::exception& e, const std::string& text) {
  std::string what = e.what();
  if (auto close = what.find("] "); close != std::string::npos) what = what.substr(close + 2);
  const auto open = what.find('\''), close = what.rfind('\'');
  if (open != std::string::npos && close > open + 1) {
    const std::string token = what.substr(open + 1, close - open - 1);
    if (auto at = text.find(token); at != std::string::npos) {
      if (what.rfind("number overflow", 0) == 0) what = "number " + token + " is out of range";
      return lineColumn(text, at) + ": " + what;
    }
  }
  return " " + what;
}

// ---- writing ----------------------------------------------------------------------------------

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
                             {"spin", number(e.spin)}});
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
  j["blackbody"] = {{"minKelvin", number(m.settings.minKelvin)},
                    {"maxKelvin", number(m.settings.maxKelvin)},
                    {"normalizeKelvin", number(m.settings.normalizeKelvin)}};
  j["exposure"] = number(m.settings.exposure);
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

// ---- evaluation -------------------------------------------------------------------------------

// splitmix64 (Steele, Lea & Flood 2014): small and fully specified, so every standard library and
// machine draws the same numbers (std::uniform_*_distribution promises no such thing).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(mix(seed)) {}
  std::uint64_t next() {
    state_ += 0x9E3779B97F4A7C15ull;
    return mix(state_);
  }
  /// [0, 1), 24 bits.
  float uniform() { return static_cast<float>(next() >> 40) * 0x1.0p-24f; }

 private:
  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::uint64_t state_;
};

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

glm::vec3 unitDirection(float u1, float u2) {
  const float z = 1.0f - 2.0f * u1;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = kTwoPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Uniform in the unit ball (three draws, no rejection, so every particle uses the same count).
glm::vec3 unitBall(Rng& rng) {
  const float u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
  return unitDirection(u1, u2) * std::cbrt(u3);
}

// Moves, spins and shrinks a particle to time t; false when it is not alive then.
bool evolve(const ParticleSpec& p, float t, cel::Particle& out) {
  if (t < p.birth) return false;
  const float age = t - p.birth;
  float size = p.size;
  if (p.lifetime > 0.0f) {
    if (age >= p.lifetime) return false;
    size *= std::max(0.0f, 1.0f - age / p.lifetime);
  }
  out.position = p.position + p.velocity * age;
  out.size = size;
  out.variation = p.variation;
  out.oriented = p.oriented;
  const float speed = glm::length(p.angularVelocity);
  glm::quat q = p.orientation;
  if (speed > 0.0f && age > 0.0f) q = glm::angleAxis(speed * age, p.angularVelocity / speed) * q;
  out.orientation = glm::normalize(q);
  return true;
}

// Particle `index` of emitter `e`, at birth. Its numbers come from its own stream, seeded from the
// emitter's seed and the index only, so it never depends on the other particles or on the frame.
// Every particle draws the same numbers in the same order, whatever the options.
ParticleSpec emit(const EmitterSpec& e, int index, int variations) {
  Rng rng((static_cast<std::uint64_t>(e.seed) << 32) | static_cast<std::uint32_t>(index));
  ParticleSpec p;
  // Position (3 draws) and how far out in the shape it lies, r/R in [0, 1].
  const float u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
  float edge = 0.0f;
  float along = 0.0f;  // cone: the parameter s along the segment
  switch (e.shape) {
    case EmitterSpec::Shape::kSphere:
      edge = std::cbrt(u3);
      p.position = e.center + e.radius * edge * unitDirection(u1, u2);
      break;
    case EmitterSpec::Shape::kBox: {
      const glm::vec3 q = 2.0f * glm::vec3(u1, u2, u3) - 1.0f;
      edge = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
      p.position = e.center + e.halfExtent * q;
      break;
    }
    case EmitterSpec::Shape::kCone: {
      along = u1;
      const glm::vec3 axis = e.end - e.center;
      const float length = glm::length(axis);
      const glm::vec3 n = length > 0.0f ? axis / length : glm::vec3(0.0f, 1.0f, 0.0f);
      const glm::vec3 helper = std::abs(n.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
      const glm::vec3 b1 = glm::normalize(glm::cross(n, helper)), b2 = glm::cross(n, b1);
      edge = std::sqrt(u2);  // uniform over the disc
      const float radius = e.radius + (e.endRadius - e.radius) * along;
      const float phi = kTwoPi * u3;
      p.position = e.center + axis * along + radius * edge * (std::cos(phi) * b1 + std::sin(phi) * b2);
      break;
    }
  }
  p.size = (e.sizeMin + (e.sizeMax - e.sizeMin) * rng.uniform()) * (1.0f - e.sizeFalloff * edge);
  const float v = rng.uniform();
  if (e.variations.empty()) {
    p.variation = std::min(static_cast<int>(v * static_cast<float>(variations)), variations - 1);
  } else {
    const int n = static_cast<int>(e.variations.size());
    p.variation = e.variations[static_cast<std::size_t>(std::min(static_cast<int>(v * static_cast<float>(n)), n - 1))];
  }
  p.variation = std::clamp(p.variation, 0, 255);
  p.velocity = e.velocity + e.speedSpread * unitBall(rng);
  const float b = rng.uniform();
  p.birth = (e.shape == EmitterSpec::Shape::kCone ? along : b) * e.birthSpread;
  // A uniformly random rotation (Shoemake 1992).
  const float q1 = rng.uniform(), q2 = kTwoPi * rng.uniform(), q3 = kTwoPi * rng.uniform();
  const float a = std::sqrt(1.0f - q1), c = std::sqrt(q1);
  const glm::quat random(c * std::cos(q3), a * std::sin(q2), a * std::cos(q2), c * std::sin(q3));
  const glm::vec3 spin = e.spin * unitBall(rng);
  p.oriented = e.oriented;
  if (e.oriented) {
    p.orientation = glm::normalize(random);
    p.angularVelocity = spin;
  }
  p.lifetime = e.lifetime;
  return p;
}

}  // namespace

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
  try {
    return readScene(j, file, artDir);
  } catch (const Failure& f) {
    return Error::at(file, f.message);
  }
}

Result<Scene> loadScene(const fs::path& file, const fs::path& artDir) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) return Error::at(file, "cannot read: is a directory");
  std::ifstream in(file, std::ios::binary);
  if (!in) return Error::at(file, std::string("cannot read: ") + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) return Error::at(file, "cannot read: read error");
  const std::string text = ss.str();
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    return Error{file.string() + ":" + syntaxErrorMessage(e, text)};
  } catch (const json::exception& e) {
    return Error{file.string() + ":" + otherErrorMessage(e, text)};
  }
  return parseScene(j, file, artDir);
}

json toJson(const Scene& s) {
  const fs::path dir = s.file.parent_path();
  json j;
  j["output"] = {{"width", s.width}, {"height", s.height}, {"samples", s.samples}, {"background", vec3(s.background)}};
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
  j["particleFraction"] = s.particleFraction;
  const cel::Style& st = s.style;
  j["style"] = {{"outlines", st.outlines},
                {"outlineWidth", number(st.outlineWidth)},
                {"outlineColor", vec3(st.outlineColor)},
                {"shading", st.shading},
                {"shadows", st.shadows},
                {"alignment", std::string(cel::toString(st.alignment))},
                {"shadowBias", number(st.shadowBias)},
                {"shadowLength", number(st.shadowLength)}};
  if (!s.stylePreset.empty()) j["style"]["preset"] = s.stylePreset;
  j["particles"] = json::array();
  for (const ParticleSpec& p : s.particles) {
    j["particles"].push_back({{"position", vec3(p.position)},
                              {"size", number(p.size)},
                              {"variation", p.variation},
                              {"oriented", p.oriented},
                              {"orientation", orientationJson(p.orientation)},
                              {"velocity", vec3(p.velocity)},
                              {"angularVelocity", vec3(p.angularVelocity)},
                              {"birth", number(p.birth)},
                              {"lifetime", number(p.lifetime)}});
  }
  j["emitters"] = json::array();
  for (const EmitterSpec& e : s.emitters) {
    const char* shape = e.shape == EmitterSpec::Shape::kSphere ? "sphere"
                        : e.shape == EmitterSpec::Shape::kBox  ? "box"
                                                               : "cone";
    j["emitters"].push_back({{"shape", shape},
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
                             {"lifetime", number(e.lifetime)}});
  }
  j["objects"] = json::array();
  for (const ObjectSpec& o : s.objects) {
    const char* type = o.type == ObjectSpec::Type::kPlane    ? "plane"
                       : o.type == ObjectSpec::Type::kBox    ? "box"
                       : o.type == ObjectSpec::Type::kSphere ? "sphere"
                                                             : "mesh";
    j["objects"].push_back({{"type", type},
                            {"name", o.name},
                            {"mesh", pathJson(o.mesh, dir)},
                            {"translate", vec3(o.translate)},
                            {"rotate", vec3(o.rotateDegrees)},
                            {"scale", vec3(o.scale)},
                            {"albedo", vec3(o.albedo)},
                            {"shading", o.cel ? "cel" : "smooth"},
                            {"path", pathKeys(o.path)},
                            {"collide", o.collide},
                            {"friction", number(o.friction)}});
  }
  j["animation"] = {{"fps", number(s.animation.fps)},
                    {"frames", s.animation.frames},
                    {"orbit", number(s.animation.orbitDegreesPerSecond)},
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

float frameTime(const Scene& scene, int frame) {
  return static_cast<float>(static_cast<double>(frame) / static_cast<double>(scene.animation.fps));
}

std::vector<cel::Particle> particlesAt(const Scene& scene, int frame, int variations) {
  variations = std::clamp(variations, 1, 256);
  const float t = frameTime(scene, frame);
  std::size_t capacity = scene.particles.size();
  for (const EmitterSpec& e : scene.emitters) capacity += static_cast<std::size_t>(std::max(0, e.count));
  std::vector<cel::Particle> out;
  out.reserve(capacity);
  cel::Particle p;
  for (const ParticleSpec& spec : scene.particles) {
    if (evolve(spec, t, p)) out.push_back(p);
  }
  const float f = scene.particleFraction;
  const float grow = f < 1.0f ? std::cbrt(1.0f / f) : 1.0f;
  for (const EmitterSpec& e : scene.emitters) {
    const int count = f < 1.0f && e.count > 0 ? std::max(1, static_cast<int>(std::lround(e.count * f))) : e.count;
    for (int i = 0; i < count; ++i) {
      ParticleSpec spec = emit(e, i, variations);
      spec.size *= grow;
      if (evolve(spec, t, p)) out.push_back(p);
    }
  }
  return out;
}

glm::mat4 objectTransform(const ObjectSpec& o, double t) {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), o.translate + o.path.at(t));
  // XYZ Euler angles applied X first: M = T * Rz * Ry * Rx * S.
  m = glm::rotate(m, glm::radians(o.rotateDegrees.z), glm::vec3(0, 0, 1));
  m = glm::rotate(m, glm::radians(o.rotateDegrees.y), glm::vec3(0, 1, 0));
  m = glm::rotate(m, glm::radians(o.rotateDegrees.x), glm::vec3(1, 0, 0));
  return glm::scale(m, o.scale);
}

namespace {

// The scene's colliding objects as colliders of `s` (checked, named by their object).
Result<void> addColliders(const Scene& scene, sim::Settings& s) {
  s.colliders.clear();
  for (const ObjectSpec& o : scene.objects) {
    if (!o.collide) continue;
    sim::Collider c;
    c.name = o.name;
    c.center = o.translate;
    c.rotation = glm::angleAxis(glm::radians(o.rotateDegrees.z), glm::vec3(0, 0, 1)) *
                 glm::angleAxis(glm::radians(o.rotateDegrees.y), glm::vec3(0, 1, 0)) *
                 glm::angleAxis(glm::radians(o.rotateDegrees.x), glm::vec3(1, 0, 0));
    c.friction = o.friction;
    c.path = o.path;
    switch (o.type) {
      case ObjectSpec::Type::kPlane:
        c.type = sim::Collider::Type::kPlane;
        c.halfExtent = glm::vec3(o.scale.x, 0.0f, o.scale.z);
        break;
      case ObjectSpec::Type::kBox:
        c.type = sim::Collider::Type::kBox;
        c.halfExtent = o.scale;
        break;
      case ObjectSpec::Type::kSphere:
        // A stretched sphere collides as the sphere around it.
        c.type = sim::Collider::Type::kSphere;
        c.halfExtent = glm::vec3(std::max({o.scale.x, o.scale.y, o.scale.z}));
        break;
      case ObjectSpec::Type::kMesh: {
        auto loaded = mesh::loadMesh(o.mesh);
        if (!loaded) return loaded.error();
        c.type = sim::Collider::Type::kMesh;
        ObjectSpec still = o;  // the vertices where the object stands; the collider's path moves them
        still.path = {};
        const glm::mat4 m = objectTransform(still);
        c.center = glm::vec3(0.0f);
        c.positions.reserve(loaded->positions.size());
        for (const glm::vec3& v : loaded->positions) c.positions.push_back(glm::vec3(m * glm::vec4(v, 1.0f)));
        for (const glm::uvec3& t : loaded->triangles) c.indices.insert(c.indices.end(), {t.x, t.y, t.z});
        break;
      }
    }
    s.colliders.push_back(std::move(c));
  }
  // A collider that fails the simulator's checks is named by the object it came from.
  std::size_t k = 0;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (!scene.objects[i].collide) continue;
    sim::Settings one;
    one.colliders = {s.colliders[k++]};
    if (auto ok = sim::validate(one); !ok) {
      std::string what = ok.error().message;
      what = what.substr(std::min(what.find(':'), what.size()));  // drop "/colliders/0/field"
      return Error::at(scene.file, "/objects/" + std::to_string(i) + " (as a collider)" + what);
    }
  }
  return {};
}

}  // namespace

Result<std::optional<sim::Settings>> simulationSettings(const Scene& scene) {
  if (!scene.simulation) return std::optional<sim::Settings>{};
  sim::Settings s = *scene.simulation;
  s.fps = scene.animation.fps;
  if (auto ok = addColliders(scene, s); !ok) return ok.error();
  if (auto ok = sim::validate(s); !ok) return Error::at(scene.file, "/simulation" + ok.error().message);
  return std::optional<sim::Settings>(std::move(s));
}

Result<std::optional<sim::Settings>> mediaSimulationSettings(const Scene& scene) {
  if (!scene.media || scene.media->emitters.empty()) return std::optional<sim::Settings>{};
  const MediaSpec& m = *scene.media;
  sim::Settings s;
  s.fps = scene.animation.fps;
  s.substeps = m.substeps;
  s.preroll = m.preroll;
  s.maxParticles = m.maxParticles;
  s.collisionRadius = m.collisionRadius;
  s.forces = m.forces;
  for (const MediaEmitterSpec& e : m.emitters) s.emitters.push_back(e.emitter);
  if (auto ok = addColliders(scene, s); !ok) return ok.error();
  if (auto ok = sim::validate(s); !ok) return Error::at(scene.file, "/media" + ok.error().message);
  return std::optional<sim::Settings>(std::move(s));
}

float MediaLightSpec::intensityAt(double t) const {
  if (intensities.empty()) return 0.0f;
  if (t <= times.front()) return intensities.front();
  if (t >= times.back()) return intensities.back();
  const auto it = std::upper_bound(times.begin(), times.end(), static_cast<float>(t));
  const std::size_t k = static_cast<std::size_t>(it - times.begin());
  const double f = (t - times[k - 1]) / (times[k] - times[k - 1]);
  return static_cast<float>(intensities[k - 1] + f * (intensities[k] - intensities[k - 1]));
}

cel::Camera cameraAt(const Scene& scene, int frame) {
  cel::Camera c = scene.camera;
  const double t = frameTime(scene, frame);
  if (!scene.animation.cameraPath.empty()) c.position = scene.animation.cameraPath.at(t);
  if (!scene.animation.targetPath.empty()) c.target = scene.animation.targetPath.at(t);
  if (!(glm::length(c.target - c.position) > 0.0f)) c.target = c.position + glm::vec3(0.0f, 0.0f, -1.0f);
  const float degrees = scene.animation.orbitDegreesPerSecond * frameTime(scene, frame);
  if (degrees == 0.0f) return c;
  // Turn about the vertical (world y) axis through the target; up turns with the camera.
  const glm::quat turn = glm::angleAxis(glm::radians(std::fmod(degrees, 360.0f)), glm::vec3(0.0f, 1.0f, 0.0f));
  c.position = c.target + turn * (c.position - c.target);
  c.up = turn * c.up;
  return c;
}

}  // namespace puff::render
