// Puff's readers of OBJ, OFF, PLY and STL (mesh_read.h).
#include "mesh_read.h"

#include <puff/core/files.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <set>
#include <string_view>
#include <unordered_map>

namespace puff::mesh::detail {

namespace fs = std::filesystem;

const char* formatName(Format f) {
  switch (f) {
    case Format::Obj:
      return "OBJ";
    case Format::Off:
      return "OFF";
    case Format::Ply:
      return "PLY";
    case Format::Stl:
      return "STL";
  }
  return "?";
}

namespace {

Error notValid(const fs::path& path, Format f, const std::string& detail = {}) {
  return Error::at(path,
                   std::string("not a valid ") + formatName(f) + " file" + (detail.empty() ? "" : " (" + detail + ")"));
}

std::string lineText(std::size_t n) { return "line " + std::to_string(n); }

// A double as a float without undefined behaviour: beyond float's range is infinite (the mesh
// check then names the vertex), NaN stays NaN.
float toFloat(double d) {
  if (std::isnan(d)) return std::numeric_limits<float>::quiet_NaN();
  if (d > FLT_MAX) return std::numeric_limits<float>::infinity();
  if (d < -FLT_MAX) return -std::numeric_limits<float>::infinity();
  return static_cast<float>(d);
}

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string_view trimLeft(std::string_view s) {
  while (!s.empty() && isBlank(s.front())) s.remove_prefix(1);
  return s;
}

std::string_view firstToken(std::string_view s) {
  s = trimLeft(s);
  std::size_t end = 0;
  while (end < s.size() && !isBlank(s[end])) ++end;
  return s.substr(0, end);
}

bool hasControlBytes(std::string_view line) {
  for (char c : line) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 && !isBlank(c)) || u == 0x7f) return true;
  }
  return false;
}

// The whitespace-separated tokens of a line.
std::vector<std::string_view> tokens(std::string_view s) {
  std::vector<std::string_view> out;
  for (std::string_view t = firstToken(s); !t.empty(); t = firstToken(s)) {
    s = trimLeft(s);
    s.remove_prefix(t.size());
    out.push_back(t);
  }
  return out;
}

// A whole token as a number (strtod's syntax, "nan" and "inf" included).
std::optional<double> number(std::string_view token) {
  if (token.empty() || token.size() > 64) return std::nullopt;
  char buf[65];
  std::memcpy(buf, token.data(), token.size());
  buf[token.size()] = '\0';
  char* end = nullptr;
  const double v = std::strtod(buf, &end);
  if (end != buf + token.size()) return std::nullopt;
  return v;
}

// A whole token as an integer within int64.
std::optional<std::int64_t> integer(std::string_view token) {
  if (token.empty() || token.size() > 32) return std::nullopt;
  char buf[33];
  std::memcpy(buf, token.data(), token.size());
  buf[token.size()] = '\0';
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(buf, &end, 10);
  if (end != buf + token.size() || errno == ERANGE) return std::nullopt;
  return v;
}

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

// ---- OBJ ----------------------------------------------------------------------------------------

// An OBJ index (1-based, or negative: relative to the `count` read so far) as 0-based; -1 when it
// names nothing (0, or before the first).
std::int64_t objIndex(std::int64_t i, std::size_t count) {
  if (i > 0) return i - 1;
  if (i < 0 && static_cast<std::uint64_t>(-(i + 1)) < count) return static_cast<std::int64_t>(count) + i;
  return -1;
}

Result<RawMesh> readObj(const fs::path& path, std::string_view text) {
  // Every statement of the OBJ spec (and the common extensions); anything else is not OBJ.
  static const std::set<std::string_view> kKeywords = {
      "v",        "vt",       "vn",     "vp",     "f",      "fo",     "l",    "p",          "o",
      "g",        "s",        "mtllib", "usemtl", "maplib", "usemap", "lod",  "shadow_obj", "trace_obj",
      "ctech",    "stech",    "cstype", "deg",    "bmat",   "step",   "curv", "curv2",      "surf",
      "parm",     "trim",     "hole",   "scrv",   "sp",     "end",    "con",  "mg",         "bevel",
      "c_interp", "d_interp", "call",   "csh",    "res"};
  RawMesh m;
  std::vector<glm::vec3> colors, fileNormals, vertexNormals;
  std::size_t colored = 0, corners = 0, cornersWithNormal = 0;
  Lines lines(text);
  std::string_view line;
  std::string joined;  // a statement continued over lines ending in a backslash
  while (lines.next(line)) {
    const std::size_t lineNo = lines.number();
    if (lineNo == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 BOM
    if (hasControlBytes(line)) return notValid(path, Format::Obj, lineText(lineNo));
    std::string_view body = line;
    while (!body.empty() && isBlank(body.back())) body.remove_suffix(1);
    if (!body.empty() && body.back() == '\\') {
      if (joined.size() + body.size() > (std::size_t{1} << 20)) return notValid(path, Format::Obj, lineText(lineNo));
      joined.append(body.substr(0, body.size() - 1)).push_back(' ');
      continue;
    }
    std::string statement;  // lives through this iteration: `line` may view it
    if (!joined.empty()) {
      statement = std::move(joined);
      joined.clear();
      statement.append(line);
      line = statement;
    }
    line = trimLeft(line);
    if (line.empty() || line.front() == '#') continue;
    const std::vector<std::string_view> t = tokens(line);
    if (!kKeywords.count(t[0])) return notValid(path, Format::Obj, lineText(lineNo));
    if (t[0] == "v") {
      // x y z, optionally w, or r g b after x y z (the vertex-colour extension).
      std::array<double, 6> v{};
      std::size_t n = 0;
      for (; n < 6 && n + 1 < t.size(); ++n) {
        const auto d = number(t[n + 1]);
        if (!d) break;
        v[n] = *d;
      }
      if (n < 3) return notValid(path, Format::Obj, lineText(lineNo));
      m.positions.emplace_back(toFloat(v[0]), toFloat(v[1]), toFloat(v[2]));
      if (n >= 6) {
        colors.emplace_back(toFloat(v[3]), toFloat(v[4]), toFloat(v[5]));
        ++colored;
      } else {
        colors.emplace_back(0.0f);
      }
      vertexNormals.emplace_back(0.0f);
    } else if (t[0] == "vn") {
      if (t.size() < 4) return notValid(path, Format::Obj, lineText(lineNo));
      std::array<float, 3> n{};
      for (int k = 0; k < 3; ++k) {
        const auto d = number(t[1 + k]);
        if (!d) return notValid(path, Format::Obj, lineText(lineNo));
        n[k] = toFloat(*d);
      }
      fileNormals.emplace_back(n[0], n[1], n[2]);
    } else if (t[0] == "f") {
      ++m.declaredFaces;
      for (std::size_t k = 1; k < t.size(); ++k) {
        // v, v/vt, v/vt/vn or v//vn
        const std::string_view tok = t[k];
        const std::size_t s1 = tok.find('/');
        const auto vi = integer(tok.substr(0, s1));
        if (!vi) return notValid(path, Format::Obj, lineText(lineNo));
        const std::int64_t v = objIndex(*vi, m.positions.size());
        m.addCorner(v);
        ++corners;
        if (s1 == std::string_view::npos) continue;
        const std::size_t s2 = tok.find('/', s1 + 1);
        if (s2 == std::string_view::npos || s2 + 1 >= tok.size()) continue;
        const auto ni = integer(tok.substr(s2 + 1));
        if (!ni) return notValid(path, Format::Obj, lineText(lineNo));
        const std::int64_t n = objIndex(*ni, fileNormals.size());
        if (v < 0 || static_cast<std::size_t>(v) >= m.positions.size() || n < 0 ||
            static_cast<std::size_t>(n) >= fileNormals.size())
          continue;
        vertexNormals[static_cast<std::size_t>(v)] = fileNormals[static_cast<std::size_t>(n)];
        ++cornersWithNormal;
      }
      m.endFace();
    }
  }
  if (!m.positions.empty() && colored == m.positions.size()) m.colors = std::move(colors);
  if (corners > 0 && cornersWithNormal == corners) m.normals = std::move(vertexNormals);
  return m;
}

// ---- OFF ----------------------------------------------------------------------------------------

// The next line with content, comments ("#" to the end of the line) removed; false at the end.
bool nextContent(Lines& lines, std::string_view& line) {
  while (lines.next(line)) {
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    if (!firstToken(line).empty()) return true;
  }
  return false;
}

// Little-endian binary values.
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

Result<RawMesh> readOff(const fs::path& path, std::string_view text) {
  Lines lines(text);
  std::string_view header;
  // The keyword is the first line with content (some writers put a comment first).
  do {
    if (!lines.next(header) || hasControlBytes(header)) return notValid(path, Format::Off);
  } while (firstToken(header).empty() || firstToken(header).front() == '#');
  const std::string_view key = firstToken(header);
  // [ST][C][N]OFF, optionally followed by BINARY.
  if (key.size() < 3 || key.substr(key.size() - 3) != "OFF") return notValid(path, Format::Off);
  std::string_view flags = key.substr(0, key.size() - 3);
  const bool texcoords = flags.substr(0, 2) == "ST";
  if (texcoords) flags.remove_prefix(2);
  const bool colors = !flags.empty() && flags.front() == 'C';
  if (colors) flags.remove_prefix(1);
  const bool normals = !flags.empty() && flags.front() == 'N';
  if (normals) flags.remove_prefix(1);
  if (!flags.empty()) return notValid(path, Format::Off, std::string(key) + ": only [ST][C][N]OFF is read");
  std::string_view rest = trimLeft(header.substr(header.find(key) + key.size()));
  RawMesh m;

  if (firstToken(rest) == "BINARY") {
    if (colors || normals || texcoords) return notValid(path, Format::Off, "binary OFF is read with positions only");
    // Counts follow the header line as 32-bit integers, little-endian as OpenMesh writes them.
    Bytes b(text.substr(lines.pos()), false);
    std::int32_t nv = 0, nf = 0, ne = 0;
    if (!b.i32(nv) || !b.i32(nf) || !b.i32(ne) || nv < 0 || nf < 0) return notValid(path, Format::Off);
    if (static_cast<std::uint64_t>(nv) * 12 > b.left())
      return notValid(path, Format::Off,
                      "the header declares " + std::to_string(nv) + " vertices; the file holds fewer");
    m.declaredFaces = static_cast<std::size_t>(nf);
    m.positions.reserve(static_cast<std::size_t>(nv));
    for (std::int32_t i = 0; i < nv; ++i) {
      float p[3];
      for (float& c : p) b.f32(c);
      m.positions.emplace_back(p[0], p[1], p[2]);
    }
    for (std::int32_t f = 0; f < nf; ++f) {
      std::int32_t n = 0;
      if (!b.i32(n)) break;  // fewer faces than declared: counted below
      if (n < 0 || static_cast<std::uint64_t>(n) * 4 > b.left())
        return notValid(path, Format::Off, "face " + std::to_string(f));
      for (std::int32_t k = 0; k < n; ++k) {
        std::int32_t v = 0;
        b.i32(v);
        m.addCorner(v);
      }
      m.endFace();
      std::int32_t nc = 0;  // the face's colour components
      if (!b.i32(nc) || nc < 0 || static_cast<std::uint64_t>(nc) * 4 > b.left())
        return notValid(path, Format::Off, "face " + std::to_string(f));
      for (std::int32_t k = 0; k < nc; ++k) {
        float ignored;
        b.f32(ignored);
      }
    }
    return m;
  }

  // ASCII: "nv nf ne" is the next content (it may share the header line).
  std::vector<std::int64_t> counts;
  std::string_view line = rest;
  if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
  if (firstToken(line).empty() && !nextContent(lines, line)) return notValid(path, Format::Off);
  for (std::string_view tok : tokens(line)) {
    const auto v = integer(tok);
    if (!v) return notValid(path, Format::Off, lineText(lines.number()));
    counts.push_back(*v);
  }
  if (counts.size() < 2 || counts[0] < 0 || counts[1] < 0) return notValid(path, Format::Off);
  const auto nv = static_cast<std::uint64_t>(counts[0]);
  m.declaredFaces = static_cast<std::size_t>(counts[1]);
  const std::size_t perVertex = 3 + (normals ? 3 : 0) + (texcoords ? 2 : 0);
  for (std::uint64_t i = 0; i < nv; ++i) {
    if (!nextContent(lines, line)) {
      return Error::at(path,
                       "the header declares " + std::to_string(nv) + " vertices; the file holds " + std::to_string(i));
    }
    if (hasControlBytes(line)) return notValid(path, Format::Off, lineText(lines.number()));
    const std::vector<std::string_view> t = tokens(line);
    std::vector<double> v;
    for (std::string_view tok : t) {
      const auto d = number(tok);
      if (!d) return notValid(path, Format::Off, lineText(lines.number()));
      v.push_back(*d);
    }
    // x y z [nx ny nz] [r g b [a]] [s t]
    const std::size_t colorValues = v.size() >= perVertex ? v.size() - perVertex : 0;
    if (v.size() < perVertex || (colors && colorValues != 3 && colorValues != 4))
      return notValid(path, Format::Off, lineText(lines.number()));
    m.positions.emplace_back(toFloat(v[0]), toFloat(v[1]), toFloat(v[2]));
    if (normals) m.normals.emplace_back(toFloat(v[3]), toFloat(v[4]), toFloat(v[5]));
    if (colors) {
      const std::size_t c = normals ? 6 : 3;
      m.colors.emplace_back(toFloat(v[c]), toFloat(v[c + 1]), toFloat(v[c + 2]));
    }
  }
  std::size_t held = 0;
  for (; held < m.declaredFaces && nextContent(lines, line); ++held) {
    if (hasControlBytes(line)) return notValid(path, Format::Off, lineText(lines.number()));
    const std::vector<std::string_view> t = tokens(line);
    const auto n = integer(t[0]);
    if (!n || *n < 0 || static_cast<std::uint64_t>(*n) >= t.size())
      return notValid(path, Format::Off, lineText(lines.number()));
    for (std::int64_t k = 1; k <= *n; ++k) {
      const auto v = integer(t[static_cast<std::size_t>(k)]);
      if (!v) return notValid(path, Format::Off, lineText(lines.number()));
      m.addCorner(*v);
    }
    m.endFace();  // anything after the corners (a face colour) is not read
  }
  if (held < m.declaredFaces) {
    return Error::at(path, "the header declares " + std::to_string(m.declaredFaces) +
                               (m.declaredFaces == 1 ? " face" : " faces") + " after " + std::to_string(nv) +
                               " vertices; the file holds " + std::to_string(held));
  }
  return m;
}

// ---- PLY ----------------------------------------------------------------------------------------

enum class PlyType { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64 };

std::optional<PlyType> plyType(std::string_view name) {
  static const std::pair<std::string_view, PlyType> kTypes[] = {
      {"char", PlyType::kI8},   {"int8", PlyType::kI8},     {"uchar", PlyType::kU8},   {"uint8", PlyType::kU8},
      {"short", PlyType::kI16}, {"int16", PlyType::kI16},   {"ushort", PlyType::kU16}, {"uint16", PlyType::kU16},
      {"int", PlyType::kI32},   {"int32", PlyType::kI32},   {"uint", PlyType::kU32},   {"uint32", PlyType::kU32},
      {"float", PlyType::kF32}, {"float32", PlyType::kF32}, {"double", PlyType::kF64}, {"float64", PlyType::kF64}};
  for (const auto& [n, t] : kTypes)
    if (n == name) return t;
  return std::nullopt;
}

std::size_t plySize(PlyType t) {
  switch (t) {
    case PlyType::kI8:
    case PlyType::kU8:
      return 1;
    case PlyType::kI16:
    case PlyType::kU16:
      return 2;
    case PlyType::kI32:
    case PlyType::kU32:
    case PlyType::kF32:
      return 4;
    case PlyType::kF64:
      return 8;
  }
  return 8;
}

bool plyIsInteger(PlyType t) { return t != PlyType::kF32 && t != PlyType::kF64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kF32;
  bool list = false;
  PlyType countType = PlyType::kU8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

// Values of a PLY body, ASCII or binary, one at a time.
class PlyValues {
 public:
  PlyValues(std::string_view body, bool ascii, bool bigEndian) : body_(body), ascii_(ascii), bytes_(body, bigEndian) {}
  bool read(PlyType t, double& v) {
    if (ascii_) {
      const std::string_view tok = nextToken();
      if (tok.empty()) return false;
      const auto d = number(tok);
      if (!d) return false;
      v = *d;
      return true;
    }
    switch (t) {
      case PlyType::kI8:
        return binary<std::int8_t>(v);
      case PlyType::kU8:
        return binary<std::uint8_t>(v);
      case PlyType::kI16:
        return binary<std::int16_t>(v);
      case PlyType::kU16:
        return binary<std::uint16_t>(v);
      case PlyType::kI32:
        return binary<std::int32_t>(v);
      case PlyType::kU32:
        return binary<std::uint32_t>(v);
      case PlyType::kF32:
        return binary<float>(v);
      case PlyType::kF64:
        return binary<double>(v);
    }
    return false;
  }
  /// At most how many values of `t` are left (ASCII: each takes at least two bytes).
  std::uint64_t mostLeft(PlyType t) const {
    return ascii_ ? (body_.size() - pos_ + 1) / 2 : bytes_.left() / plySize(t);
  }

 private:
  // One binary value of type T, in the file's byte order.
  template <class T>
  bool binary(double& v) {
    T x;
    if (!bytes_.raw(&x, sizeof x)) return false;
    v = static_cast<double>(x);
    return true;
  }
  std::string_view nextToken() {
    while (pos_ < body_.size() && std::isspace(static_cast<unsigned char>(body_[pos_]))) ++pos_;
    const std::size_t start = pos_;
    while (pos_ < body_.size() && !std::isspace(static_cast<unsigned char>(body_[pos_]))) ++pos_;
    return body_.substr(start, pos_ - start);
  }
  std::string_view body_;
  bool ascii_;
  Bytes bytes_;
  std::size_t pos_ = 0;
};

// Triangles of a strip (-1 restarts it), winding alternating as OpenGL's; the degenerate ones that
// stitch strips together are dropped.
void addStrip(const std::vector<std::int64_t>& strip, RawMesh& m) {
  std::size_t begin = 0;
  for (std::size_t i = 0; i <= strip.size(); ++i) {
    if (i < strip.size() && strip[i] >= 0) continue;
    for (std::size_t k = begin; k + 2 < i; ++k) {
      std::int64_t a = strip[k], b = strip[k + 1];
      const std::int64_t c = strip[k + 2];
      if ((k - begin) % 2 == 1) std::swap(a, b);
      if (a == b || b == c || a == c) continue;
      m.addCorner(a);
      m.addCorner(b);
      m.addCorner(c);
      m.endFace();
      ++m.declaredFaces;
    }
    begin = i + 1;
  }
}

Result<RawMesh> readPly(const fs::path& path, std::string_view text) {
  Lines lines(text);
  std::string_view line;
  const auto clean = [](std::string_view s) {
    while (!s.empty() && isBlank(s.back())) s.remove_suffix(1);  // "\r", and "ply " as some writers end it
    return s;
  };
  if (!lines.next(line) || clean(line) != "ply") return notValid(path, Format::Ply);
  std::optional<bool> ascii, bigEndian;
  std::vector<PlyElement> elements;
  bool ended = false;
  while (!ended && lines.number() < 10000 && lines.next(line)) {
    line = clean(line);
    const std::string detail = "header " + lineText(lines.number());
    if (hasControlBytes(line)) return notValid(path, Format::Ply, detail);
    const std::vector<std::string_view> t = tokens(line);
    if (t.empty()) continue;
    if (t[0] == "end_header") {
      ended = true;
    } else if (t[0] == "comment" || t[0] == "obj_info") {
    } else if (t[0] == "format") {
      if (t.size() < 2 || ascii) return notValid(path, Format::Ply, detail);
      ascii = t[1] == "ascii";
      bigEndian = t[1] == "binary_big_endian";
      if (!*ascii && !*bigEndian && t[1] != "binary_little_endian")
        return notValid(path, Format::Ply, detail + ": unknown format " + std::string(t[1].substr(0, 32)));
    } else if (t[0] == "element") {
      const auto count = t.size() == 3 ? integer(t[2]) : std::nullopt;
      if (!count || *count < 0) return notValid(path, Format::Ply, detail);
      elements.push_back({std::string(t[1]), static_cast<std::uint64_t>(*count), {}});
    } else if (t[0] == "property") {
      if (elements.empty()) return notValid(path, Format::Ply, detail);
      PlyProperty p;
      std::optional<PlyType> type, count;
      if (t.size() == 5 && t[1] == "list") {
        count = plyType(t[2]);
        type = plyType(t[3]);
        p.list = true;
        p.name = std::string(t[4]);
        if (count && !plyIsInteger(*count)) count.reset();
      } else if (t.size() == 3) {
        type = plyType(t[1]);
        count = PlyType::kU8;
        p.name = std::string(t[2]);
      }
      if (!type || !count) return notValid(path, Format::Ply, detail);
      p.type = *type;
      p.countType = *count;
      elements.back().properties.push_back(p);
    } else {
      return notValid(path, Format::Ply, detail);
    }
  }
  if (!ended) return notValid(path, Format::Ply, "no end_header");
  if (!ascii) return notValid(path, Format::Ply, "no format line");

  RawMesh m;
  PlyValues values(text.substr(lines.pos()), *ascii, *bigEndian);
  bool haveVertices = false;
  std::vector<std::int64_t> list;
  for (const PlyElement& e : elements) {
    const bool isVertex = e.name == "vertex", isFace = e.name == "face", isStrips = e.name == "tristrips";
    // Which vertex property fills what: position 0-2, normal 3-5, colour 6-8.
    std::vector<int> slot(e.properties.size(), -1);
    std::array<bool, 9> have{};
    std::array<double, 9> colorScale{};
    int listSlot = -1;
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      const PlyProperty& p = e.properties[i];
      if (isVertex && !p.list) {
        static const std::pair<std::string_view, int> kSlots[] = {
            {"x", 0},           {"y", 1},    {"z", 2}, {"nx", 3}, {"ny", 4}, {"nz", 5},          {"red", 6},
            {"green", 7},       {"blue", 8}, {"r", 6}, {"g", 7},  {"b", 8},  {"diffuse_red", 6}, {"diffuse_green", 7},
            {"diffuse_blue", 8}};
        for (const auto& [name, s] : kSlots) {
          if (p.name == name && !have[static_cast<std::size_t>(s)]) {
            slot[i] = s;
            have[static_cast<std::size_t>(s)] = true;
            // 8- and 16-bit colours are unsigned-normalized; floats are [0, 1] already.
            colorScale[static_cast<std::size_t>(s)] = p.type == PlyType::kU8    ? 1.0 / 255.0
                                                      : p.type == PlyType::kU16 ? 1.0 / 65535.0
                                                                                : 1.0;
          }
        }
      }
      if ((isFace || isStrips) && p.list && (p.name == "vertex_indices" || p.name == "vertex_index") && listSlot < 0)
        listSlot = static_cast<int>(i);
    }
    if (isVertex) {
      haveVertices = true;
      if (!have[0] || !have[1] || !have[2]) return notValid(path, Format::Ply, "vertex has no x, y and z");
    }
    if ((isFace || isStrips) && listSlot < 0)
      return notValid(path, Format::Ply, e.name + " has no vertex_indices list");
    const bool normals = isVertex && have[3] && have[4] && have[5];
    const bool colors = isVertex && have[6] && have[7] && have[8];
    if (isFace) m.declaredFaces += e.count;
    if (e.properties.empty()) continue;  // nothing to read, however many it counts
    // Every instance takes at least one value: a count beyond what is left is a lie.
    PlyType smallest = PlyType::kF64;
    for (const PlyProperty& p : e.properties)
      smallest =
          plySize(p.list ? p.countType : p.type) < plySize(smallest) ? (p.list ? p.countType : p.type) : smallest;
    if (e.count > values.mostLeft(smallest)) {
      return notValid(path, Format::Ply,
                      "the header declares " + std::to_string(e.count) + " " + e.name.substr(0, 32) +
                          " elements; the file holds fewer");
    }
    for (std::uint64_t n = 0; n < e.count; ++n) {
      std::array<double, 9> v{};
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const PlyProperty& p = e.properties[i];
        const auto truncated = [&] {
          return notValid(path, Format::Ply,
                          e.name.substr(0, 32) + " " + std::to_string(n) + ": truncated or not a number");
        };
        if (!p.list) {
          double x;
          if (!values.read(p.type, x)) return truncated();
          if (slot[i] >= 0) v[static_cast<std::size_t>(slot[i])] = x;
          continue;
        }
        double count;
        if (!values.read(p.countType, count)) return truncated();
        if (!(count >= 0) || count != std::floor(count) || count > static_cast<double>(values.mostLeft(p.type)))
          return truncated();
        list.clear();
        for (std::uint64_t k = 0; k < static_cast<std::uint64_t>(count); ++k) {
          double x;
          if (!values.read(p.type, x)) return truncated();
          // An index that is not a whole number within int64 names no vertex.
          list.push_back(x == std::floor(x) && std::abs(x) < 9.2e18 ? static_cast<std::int64_t>(x) : -2);
        }
        if (static_cast<int>(i) != listSlot) continue;
        if (isFace) {
          for (std::int64_t c : list) m.addCorner(c < 0 ? -1 : c);
          m.endFace();
        } else {
          addStrip(list, m);
        }
      }
      if (isVertex) {
        m.positions.emplace_back(toFloat(v[0]), toFloat(v[1]), toFloat(v[2]));
        if (normals) m.normals.emplace_back(toFloat(v[3]), toFloat(v[4]), toFloat(v[5]));
        if (colors)
          m.colors.emplace_back(toFloat(v[6] * colorScale[6]), toFloat(v[7] * colorScale[7]),
                                toFloat(v[8] * colorScale[8]));
      }
    }
  }
  if (!haveVertices) return notValid(path, Format::Ply, "no vertex element");
  return m;
}

// ---- STL ----------------------------------------------------------------------------------------

// STL repeats each vertex in every facet: equal positions become one vertex (-0 equals 0).
class VertexMerger {
 public:
  explicit VertexMerger(RawMesh& m) : m_(m) {}
  std::int64_t add(glm::vec3 p) {
    for (int k = 0; k < 3; ++k) p[k] += 0.0f;  // -0 -> +0
    Key key;
    std::memcpy(key.data(), &p[0], sizeof key);
    const auto [it, added] = index_.try_emplace(key, m_.positions.size());
    if (added) m_.positions.push_back(p);
    return static_cast<std::int64_t>(it->second);
  }

 private:
  using Key = std::array<std::uint32_t, 3>;
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

Result<RawMesh> readStl(const fs::path& path, std::string_view text) {
  RawMesh m;
  VertexMerger merge(m);
  if (text.size() >= 84) {
    Bytes b(text.substr(80), false);
    std::int32_t n32 = 0;
    b.i32(n32);
    const auto n = static_cast<std::uint32_t>(n32);
    // Binary STL is recognized by its exact size (many binary headers start with "solid" too), or,
    // when the file does not start with "solid" and so cannot be ASCII, by holding the facets its
    // count says, a few bytes more tolerated (some writers pad).
    const std::uint64_t need = 84 + 50 * std::uint64_t{n};
    const bool ascii = firstToken(text.substr(0, 80)).substr(0, 5) == "solid";
    if (need == text.size() || (!ascii && need < text.size() && text.size() - need < 50)) {
      m.declaredFaces = n;
      for (std::uint32_t f = 0; f < n; ++f) {
        float v[12];
        for (float& x : v) b.f32(x);
        std::uint16_t attribute;
        b.raw(&attribute, 2);
        for (int k = 1; k <= 3; ++k) m.addCorner(merge.add({v[3 * k], v[3 * k + 1], v[3 * k + 2]}));
        m.endFace();
      }
      return m;
    }
  }
  Lines lines(text);
  std::string_view line;
  // Keywords in any case ("SOLID", "Facet"), as some exporters write them.
  const auto keyword = [](std::string_view token) {
    std::string k(token.substr(0, 16));
    for (char& c : k) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return k;
  };
  if (!lines.next(line) || keyword(firstToken(line)) != "solid" || hasControlBytes(line))
    return notValid(path, Format::Stl);
  bool inFacet = false;
  while (lines.next(line)) {
    if (hasControlBytes(line)) return notValid(path, Format::Stl, lineText(lines.number()));
    const std::vector<std::string_view> words = tokens(line);
    if (words.empty()) continue;
    const std::string k = keyword(words[0]);
    const std::vector<std::string_view>& t = words;
    if (k == "facet") {
      if (inFacet) return notValid(path, Format::Stl, lineText(lines.number()));
      inFacet = true;
      ++m.declaredFaces;
    } else if (k == "vertex") {
      if (!inFacet || t.size() != 4) return notValid(path, Format::Stl, lineText(lines.number()));
      float p[3];
      for (int c = 0; c < 3; ++c) {
        const auto d = number(t[1 + static_cast<std::size_t>(c)]);
        if (!d) return notValid(path, Format::Stl, lineText(lines.number()));
        p[c] = toFloat(*d);
      }
      m.addCorner(merge.add({p[0], p[1], p[2]}));
    } else if (k == "endfacet") {
      if (!inFacet) return notValid(path, Format::Stl, lineText(lines.number()));
      inFacet = false;
      m.endFace();
    } else if (k != "outer" && k != "endloop" && k != "endsolid" && k != "solid") {
      return notValid(path, Format::Stl, lineText(lines.number()));
    }
  }
  if (inFacet) return notValid(path, Format::Stl, "the last facet has no endfacet");
  return m;
}

}  // namespace

Result<RawMesh> readRawMesh(const fs::path& path, Format format) {
  auto bytes = core::readFileBytes(path);
  if (!bytes) return bytes.error();
  const std::string& text = *bytes;
  switch (format) {
    case Format::Obj:
      return readObj(path, text);
    case Format::Off:
      return readOff(path, text);
    case Format::Ply:
      return readPly(path, text);
    case Format::Stl:
      return readStl(path, text);
  }
  return notValid(path, format);
}

}  // namespace puff::mesh::detail
