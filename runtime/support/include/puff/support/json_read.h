// Reading JSON the way a person wrote it: every value checked, and every problem reported at its
// JSON pointer with what was expected and what was found ("/camera/fovY: expected a number in
// (0, 180), got \"wide\""). The scene reader and the atlas sidecar reader share it.
//
// The read* functions throw Failure on the first problem; catchFailure turns that into an Error
// naming the file, so no exception leaves a reader.
#pragma once

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <puff/core/error.h>

namespace puff::core::jsonread {

using nlohmann::json;

/// "/pointer: problem", thrown by the readers below.
struct Failure {
  std::string message;
};

/// `key` escaped for a JSON pointer ("~" -> "~0", "/" -> "~1").
std::string pointerToken(std::string_view key);
std::string child(const std::string& ptr, std::string_view key);  ///< ptr + "/" + key
std::string child(const std::string& ptr, std::size_t index);     ///< ptr + "/" + index
/// A value as the user wrote it, for "got ...": short values verbatim, long ones by kind.
std::string describe(const json& v);
/// Throws "PTR: expected EXPECTED, got <got>".
[[noreturn]] void fail(const std::string& ptr, const std::string& expected, const json& got);
/// Throws "PTR: MESSAGE".
[[noreturn]] void failText(const std::string& ptr, const std::string& message);
/// "a, b, c".
std::string join(std::initializer_list<std::string_view> names);
/// Levenshtein distance (for "did you mean").
std::size_t editDistance(std::string_view a, std::string_view b);
/// " (did you mean \"NAME\"?)" for the one of `names` nearest `got` (case-insensitive, at most two
/// edits away), or "" when none is that near. Keys and enum values both say it.
std::string didYouMean(std::string_view got, std::span<const std::string_view> names);
/// Throws "PTR: expected one of A, B, C, got <v>", with didYouMean when `v` is a string.
[[noreturn]] void failChoice(const json& v, const std::string& ptr, std::span<const std::string_view> names);
/// Checks that `j` is an object whose keys are all in `allowed`: a misspelt key is an error, never
/// silently ignored, and the nearest allowed key (at most two edits away) is suggested.
void requireObject(const json& j, const std::string& ptr, std::initializer_list<std::string_view> allowed);
/// The member `key` of object `obj`, or null.
const json* find(const json& obj, std::string_view key);

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// A numeric range with open or closed ends; either end may be infinite.
struct Range {
  double lo = -kInf, hi = kInf;
  bool loOpen = false, hiOpen = false;

  bool contains(double d) const { return (loOpen ? d > lo : d >= lo) && (hiOpen ? d < hi : d <= hi); }
  /// "a number in [0, 1]", "a number > 0", ...
  std::string text(const char* noun = "a number") const;
};

inline constexpr Range kAny{};
inline constexpr Range kNonNegative{0.0, kInf, false, false};
inline constexpr Range kPositive{0.0, kInf, true, false};
inline constexpr Range kUnit{0.0, 1.0, false, false};

/// A finite number in `range` that is also finite as a float. `expected` replaces the range's text.
float readFloat(const json& v, const std::string& ptr, const Range& range = kAny, const std::string& expected = {});
/// An integer in [lo, hi] (640.0 counts; 640.5 does not).
long long readInteger(const json& v, const std::string& ptr, long long lo, long long hi,
                      const std::string& expected = {});
int readInt(const json& v, const std::string& ptr, int lo, int hi);
bool readBool(const json& v, const std::string& ptr);
std::string readString(const json& v, const std::string& ptr, const std::string& expected = "a string");
/// [x, y, z]; the range applies to each element, reported at its own pointer.
glm::vec3 readVec3(const json& v, const std::string& ptr, const Range& range = kAny);
/// A colour: [r, g, b] in [0, 1], "#rrggbb" or "#rgb".
glm::vec3 readColor(const json& v, const std::string& ptr);
/// "#rrggbb" or "#rgb" (each digit doubled, as CSS reads it), hex digits of either case, as [0, 1]
/// display values; nothing for any other text.
std::optional<glm::vec3> parseHexColor(std::string_view text);

/// One of `names` (a string), as its value.
template <class Enum>
Enum readEnum(const json& v, const std::string& ptr, std::initializer_list<std::pair<std::string_view, Enum>> names) {
  if (v.is_string()) {
    const std::string s = v.get<std::string>();
    for (const auto& [name, value] : names) {
      if (s == name) return value;
    }
  }
  std::vector<std::string_view> list;
  for (const auto& [name, value] : names) list.push_back(name);
  failChoice(v, ptr, list);
}

/// Runs `read()` (which may throw Failure) and returns its value, or the failure as an Error
/// "FILE: /pointer: problem".
template <class Read>
auto catchFailure(const std::filesystem::path& file, Read&& read) -> Result<decltype(read())> {
  try {
    return read();
  } catch (const Failure& f) {
    return Error::at(file, f.message);
  }
}

/// Reads and parses a JSON file. Errors: "FILE: cannot read: ..." or a syntax error at
/// "FILE:LINE:COLUMN: ...".
Result<json> loadJsonFile(const std::filesystem::path& file);
/// A JSON file's text, read within loadJsonFile's limits (parseJson then parses it).
Result<std::string> loadJsonText(const std::filesystem::path& file);
/// Parses `text` (JSON that `file` holds, e.g. a GLB's JSON chunk) within the same limits as
/// loadJsonFile; errors name `file` and the line and column in `text`.
Result<json> parseJson(const std::string& text, const std::filesystem::path& file);

}  // namespace puff::core::jsonread
