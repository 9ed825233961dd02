// The scene reader's shared parts: the path reader, ranges, and the readers one file hands
// another (simulation and media live in files of their own). Private to puff::scene.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include <puff/core/limits.h>
#include <puff/scene/scene.h>
#include <puff/support/json_read.h>

namespace puff::scene::detail {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace core::jsonread;

using core::kMaxImageSize;
inline constexpr int kMaxEmitterCount = 1'000'000;
inline constexpr long long kMaxParticles = 2'000'000;
inline constexpr int kMaxFrames = 10'000'000;
inline constexpr std::string_view kArtVariable = "${PUFF_ART}";

inline const Range kMagnitude{-sim::kMaxMagnitude, sim::kMaxMagnitude};
inline const Range kNonNegativeMagnitude{0.0, sim::kMaxMagnitude};

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

/// [{"time": t, "position": [x, y, z]}, ...], times increasing.
sim::Path readPath3(const json& j, const std::string& ptr);
/// A non-zero vector.
glm::vec3 readDirection(const json& v, const std::string& ptr);
sim::Forces readForces(const json& j, const std::string& ptr);
/// Who owns a set of curves over life, which decides the curves it may have: a scene emitter of
/// cel puffs (size, color), a simulated cel emitter (size, density, color) or a media emitter (size,
/// density, color, temperature).
enum class CurveOwner { kCelEmitter, kCelSimulation, kMedia };
/// `owner`: kCelSimulation or kMedia (a media emitter is a simulation emitter's fields and more).
sim::Emitter readSimEmitter(const json& j, const std::string& ptr, CurveOwner owner = CurveOwner::kCelSimulation);
/// "overLife": {"size": CURVE, "density": CURVE, "color": COLOUR CURVE, "temperature": CURVE},
/// CURVE {"keys": [[age, value], ...], "interp": "linear" | "smooth"}, a colour curve's values
/// colours; the keys `owner` may not have are errors.
sim::LifeCurves readLifeCurves(const json& j, const std::string& ptr, CurveOwner owner);
sim::Settings readSimulation(const json& j, const std::string& ptr);
MediaSpec readMedia(const json& j, const std::string& ptr, const Reader& r);

}  // namespace puff::scene::detail
