// What the readers of each format share (mesh_read*.cpp, private to puff::mesh): the per-format
// readers, the error they give, and the tokenizing of lines and binary values.
#pragma once

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "mesh_read.h"

namespace puff::mesh::detail {

/// Each format's reader of a whole file's bytes (`text`); `path` only names the file in errors.
Result<RawMesh> readObj(const std::filesystem::path& path, std::string_view text);
Result<RawMesh> readOff(const std::filesystem::path& path, std::string_view text);
Result<RawMesh> readPly(const std::filesystem::path& path, std::string_view text);
Result<RawMesh> readStl(const std::filesystem::path& path, std::string_view text);
/// glTF 2.0, .gltf (its buffers beside it or in data: URIs) or .glb; `path` also locates the buffers.
Result<RawMesh> readGltf(const std::filesystem::path& path, std::string_view text);

/// "PATH: not a valid FORMAT file", with " (detail)" when a detail is given.
Error notValid(const std::filesystem::path& path, Format f, const std::string& detail = {});

/// "line N".
std::string lineText(std::size_t n);

// A double as a float without undefined behaviour: beyond float's range is infinite (the mesh
// check then names the vertex), NaN stays NaN.
inline float toFloat(double d) {
  if (std::isnan(d)) return std::numeric_limits<float>::quiet_NaN();
  if (d > FLT_MAX) return std::numeric_limits<float>::infinity();
  if (d < -FLT_MAX) return -std::numeric_limits<float>::infinity();
  return static_cast<float>(d);
}

inline bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

inline std::string_view trimLeft(std::string_view s) {
  while (!s.empty() && isBlank(s.front())) s.remove_prefix(1);
  return s;
}

inline std::string_view firstToken(std::string_view s) {
  s = trimLeft(s);
  std::size_t end = 0;
  while (end < s.size() && !isBlank(s[end])) ++end;
  return s.substr(0, end);
}

/// Whether `line` holds a control byte other than a blank (or DEL).
bool hasControlBytes(std::string_view line);

// The whitespace-separated tokens of a line.
std::vector<std::string_view> tokens(std::string_view s);

// A whole token as a number (strtod's syntax, "nan" and "inf" included).
std::optional<double> number(std::string_view token);

// A whole token as an integer within int64.
std::optional<std::int64_t> integer(std::string_view token);

// Lines of a buffer ('\n'-separated; a trailing '\r' stays, as blank).
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t nl = text_.find('\n', pos_);
    const std::size_t end = nl == std::string_view::npos ? text_.size() : nl;
    line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++number_;
    return true;
  }
  std::size_t number() const { return number_; }
  std::size_t pos() const { return std::min(pos_, text_.size()); }

 private:
  std::string_view text_;
  std::size_t pos_ = 0, number_ = 0;
};

// Formats that repeat a vertex in every face that uses it (STL's facets, glTF's vertices split at
// UV seams): equal positions (and normals, when the file gives them) become one vertex; -0 equals 0.
class VertexMerger {
 public:
  explicit VertexMerger(RawMesh& m) : m_(m) {}
  std::int64_t add(glm::vec3 p) { return add(p, std::nullopt); }
  std::int64_t add(glm::vec3 p, std::optional<glm::vec3> n) {
    Key key{};
    for (int k = 0; k < 3; ++k) p[k] += 0.0f;  // -0 -> +0
    std::memcpy(key.data(), &p[0], 3 * sizeof(float));
    if (n) {
      for (int k = 0; k < 3; ++k) (*n)[k] += 0.0f;
      std::memcpy(key.data() + 3, &(*n)[0], 3 * sizeof(float));
    }
    const auto [it, added] = index_.try_emplace(key, m_.positions.size());
    if (added) {
      m_.positions.push_back(p);
      if (n) m_.normals.push_back(*n);
    }
    return static_cast<std::int64_t>(it->second);
  }

 private:
  using Key = std::array<std::uint32_t, 6>;
  struct Hash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0xcbf29ce484222325ull;
      for (std::uint32_t v : k) h = (h ^ v) * 0x100000001b3ull;
      return static_cast<std::size_t>(h);
    }
  };
  RawMesh& m_;
  std::unordered_map<Key, std::size_t, Hash> index_;
};

// Binary values in little- or big-endian byte order.
class Bytes {
 public:
  Bytes(std::string_view data, bool bigEndian) : data_(data), big_(bigEndian) {}
  std::size_t left() const { return data_.size() - pos_; }
  bool raw(void* out, std::size_t n) {
    if (left() < n) return false;
    auto* o = static_cast<unsigned char*>(out);
    for (std::size_t i = 0; i < n; ++i) o[big_ ? n - 1 - i : i] = static_cast<unsigned char>(data_[pos_ + i]);
    pos_ += n;
    return true;
  }
  bool i32(std::int32_t& v) { return raw(&v, 4); }
  bool f32(float& v) { return raw(&v, 4); }

 private:
  std::string_view data_;
  bool big_;
  std::size_t pos_ = 0;
};

}  // namespace puff::mesh::detail
