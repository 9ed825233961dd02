#include <puff/core/number_text.h>
#include <puff/support/json_read.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include <puff/support/text.h>

namespace puff::core::jsonread {

namespace fs = std::filesystem;

std::string pointerToken(std::string_view key) {
  std::string out;
  for (char c : key) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else if (u < 0x20 || u == 0x7f) {
      // A message is one line: a control character in a key is shown as JSON writes it (\n, \u001f).
      static const char* kHex = "0123456789abcdef";
      if (c == '\n') {
        out += "\\n";
      } else if (c == '\t') {
        out += "\\t";
      } else if (c == '\r') {
        out += "\\r";
      } else {
        out += "\\u00";
        out += kHex[u >> 4];
        out += kHex[u & 15];
      }
    } else {
      out += c;
    }
  }
  return out;
}

std::string child(const std::string& ptr, std::string_view key) { return ptr + "/" + pointerToken(key); }
std::string child(const std::string& ptr, std::size_t index) { return ptr + "/" + std::to_string(index); }

namespace {

// True when `v` holds at most `budget` values, nested at most 4 deep: printing it is short work
// whatever the file holds (a value nested thousands deep is never walked, let alone dumped).
bool smallEnoughToPrint(const json& v, int depth, int& budget) {
  if (--budget < 0 || depth > 4) return false;
  if (v.is_structured()) {
    for (const json& e : v) {
      if (!smallEnoughToPrint(e, depth + 1, budget)) return false;
    }
  }
  return true;
}

}  // namespace

std::string describe(const json& v) {
  if (v.is_number_float() && !std::isfinite(v.get<double>())) return "a non-finite number";
  int budget = 16;
  if (v.is_structured() && !smallEnoughToPrint(v, 0, budget)) {
    if (v.is_array()) return "an array of " + std::to_string(v.size()) + " elements";
    return "an object with " + std::to_string(v.size()) + " keys";
  }
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

std::string didYouMean(std::string_view got, std::span<const std::string_view> names) {
  std::string_view best;
  std::size_t bestDistance = 3;  // at most two edits away
  for (std::string_view name : names) {
    const std::size_t d = editDistance(core::lower(std::string(got)), core::lower(std::string(name)));
    if (d < bestDistance) bestDistance = d, best = name;
  }
  return best.empty() ? std::string() : " (did you mean \"" + std::string(best) + "\"?)";
}

[[noreturn]] void failChoice(const json& v, const std::string& ptr, std::span<const std::string_view> names) {
  std::string list;
  for (std::string_view n : names) list += (list.empty() ? "" : ", ") + std::string(n);
  failText(ptr, "expected one of " + list + ", got " + describe(v) +
                    (v.is_string() ? didYouMean(v.get<std::string>(), names) : std::string()));
}

void requireObject(const json& j, const std::string& ptr, std::initializer_list<std::string_view> allowed) {
  if (!j.is_object()) fail(ptr.empty() ? std::string("(top level)") : ptr, "an object", j);
  for (const auto& item : j.items()) {
    const std::string& key = item.key();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    failText(child(ptr, key), "unknown key, expected one of " + join(allowed) +
                                  didYouMean(key, std::span<const std::string_view>(allowed.begin(), allowed.size())));
  }
}

const json* find(const json& obj, std::string_view key) {
  auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}

std::string Range::text(const char* noun) const {
  const bool hasLo = std::isfinite(lo), hasHi = std::isfinite(hi);
  if (!hasLo && !hasHi) return std::string(noun);
  if (!hasHi) return std::string(noun) + (loOpen ? " > " : " >= ") + core::numberText(lo);
  if (!hasLo) return std::string(noun) + (hiOpen ? " < " : " <= ") + core::numberText(hi);
  return std::string(noun) + " in " + (loOpen ? "(" : "[") + core::numberText(lo) + ", " + core::numberText(hi) +
         (hiOpen ? ")" : "]");
}

float readFloat(const json& v, const std::string& ptr, const Range& range, const std::string& expected) {
  const std::string what = expected.empty() ? range.text() : expected;
  if (!v.is_number()) fail(ptr, what, v);
  const double d = v.get<double>();
  const float f = static_cast<float>(d);
  if (!std::isfinite(d) || !std::isfinite(f) || !range.contains(d)) fail(ptr, what, v);
  return f;
}

long long readInteger(const json& v, const std::string& ptr, long long lo, long long hi, const std::string& expected) {
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

std::string readString(const json& v, const std::string& ptr, const std::string& expected) {
  if (!v.is_string()) fail(ptr, expected, v);
  return v.get<std::string>();
}

glm::vec3 readVec3(const json& v, const std::string& ptr, const Range& range) {
  // The range applies to each element; an element out of range is reported at its own pointer.
  if (!v.is_array() || v.size() != 3) fail(ptr, "an array of 3 numbers", v);
  glm::vec3 out;
  for (int i = 0; i < 3; ++i)
    out[i] = readFloat(v[static_cast<std::size_t>(i)], child(ptr, static_cast<std::size_t>(i)), range);
  return out;
}

namespace {

int hexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::optional<glm::vec3> parseHexColor(std::string_view text) {
  std::string s(text);
  if (s.size() == 4 && s[0] == '#') s = {'#', s[1], s[1], s[2], s[2], s[3], s[3]};
  if (s.size() != 7 || s[0] != '#') return std::nullopt;
  glm::vec3 c;
  for (int i = 0; i < 3; ++i) {
    const int hi = hexDigit(s[static_cast<std::size_t>(1 + 2 * i)]),
              lo = hexDigit(s[static_cast<std::size_t>(2 + 2 * i)]);
    if (hi < 0 || lo < 0) return std::nullopt;
    c[i] = static_cast<float>(hi * 16 + lo) / 255.0f;
  }
  return c;
}

glm::vec3 readColor(const json& v, const std::string& ptr) {
  static const std::string kWhat = "a colour: [r, g, b] in [0, 1], \"#rrggbb\" or \"#rgb\"";
  if (v.is_string()) {
    const auto c = parseHexColor(v.get<std::string>());
    if (!c) fail(ptr, kWhat, v);
    return *c;
  }
  if (!v.is_array() || v.size() != 3) fail(ptr, kWhat, v);
  return readVec3(v, ptr, kUnit);
}

namespace {

// "LINE:COLUMN" of byte offset `at` (0-based) in `text`.
std::string lineColumn(const std::string& text, std::size_t at) {
  at = std::min(at, text.size());
  std::size_t line = 1, lineStart = 0;
  for (std::size_t i = 0; i < at; ++i) {
    if (text[i] == '\n') ++line, lineStart = i + 1;
  }
  return std::to_string(line) + ":" + std::to_string(at - lineStart + 1);
}

// Limits of every JSON file Puff reads (scenes, atlas sidecars, mesh generators), checked before
// parsing: nothing a file holds makes a reader recurse deeper or allocate more than this.
constexpr int kMaxJsonDepth = 128;
constexpr std::uintmax_t kMaxJsonBytes = std::uintmax_t{64} << 20;

// The byte offset of the bracket that nests deeper than kMaxJsonDepth, or npos. Brackets inside
// strings do not count.
std::size_t tooDeepAt(const std::string& text) {
  int depth = 0;
  bool inString = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        inString = false;
      }
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return std::string::npos;
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

}  // namespace

Result<json> loadJsonFile(const fs::path& file) {
  PUFF_TRY_ASSIGN(auto text, loadJsonText(file));
  return parseJson(text, file);
}

Result<std::string> loadJsonText(const fs::path& file) {
  std::error_code ec;
  const auto status = fs::status(file, ec);
  if (fs::is_directory(status)) return Error::at(file, "cannot read: is a directory");
  if (fs::exists(status) && !fs::is_regular_file(status)) return Error::at(file, "cannot read: not a regular file");
  if (fs::exists(status)) {
    const auto size = fs::file_size(file, ec);
    if (!ec && size > kMaxJsonBytes) {
      return Error::at(file, "cannot read: " + std::to_string(size) + " bytes, more than a JSON file may hold (" +
                                 std::to_string(kMaxJsonBytes >> 20) + " MiB)");
    }
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) return Error::at(file, std::string("cannot read: ") + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) return Error::at(file, "cannot read: read error");
  return ss.str();
}

Result<json> parseJson(const std::string& text, const fs::path& file) {
  if (text.size() > kMaxJsonBytes) {
    return Error::at(file, "cannot read: " + std::to_string(text.size()) + " bytes of JSON, more than " +
                               std::to_string(kMaxJsonBytes >> 20) + " MiB");
  }
  if (const std::size_t at = tooDeepAt(text); at != std::string::npos) {
    return Error{file.string() + ":" + lineColumn(text, at) + ": nested more than " + std::to_string(kMaxJsonDepth) +
                 " arrays and objects deep"};
  }
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    return Error{file.string() + ":" + syntaxErrorMessage(e, text)};
  } catch (const json::exception& e) {
    return Error{file.string() + ":" + otherErrorMessage(e, text)};
  }
}

}  // namespace puff::core::jsonread
