// Puff's OBJ reader: vertices (with the vertex-colour extension), normals given per corner, polygons.
#include <array>
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mesh_read_formats.h"

namespace puff::mesh::detail {

namespace fs = std::filesystem;

namespace {

// Every statement of the OBJ spec (and the common extensions); anything else is not OBJ.
bool isObjKeyword(std::string_view word) {
  static const std::set<std::string_view> kKeywords = {
      "v",        "vt",       "vn",     "vp",     "f",      "fo",     "l",    "p",          "o",
      "g",        "s",        "mtllib", "usemtl", "maplib", "usemap", "lod",  "shadow_obj", "trace_obj",
      "ctech",    "stech",    "cstype", "deg",    "bmat",   "step",   "curv", "curv2",      "surf",
      "parm",     "trim",     "hole",   "scrv",   "sp",     "end",    "con",  "mg",         "bevel",
      "c_interp", "d_interp", "call",   "csh",    "res"};
  return kKeywords.count(word) > 0;
}

// An OBJ index (1-based, or negative: relative to the `count` read so far) as 0-based; -1 when it
// names nothing (0, or before the first).
std::int64_t objIndex(std::int64_t i, std::size_t count) {
  if (i > 0) return i - 1;
  if (i < 0 && static_cast<std::uint64_t>(-(i + 1)) < count) return static_cast<std::int64_t>(count) + i;
  return -1;
}

// The mesh of an OBJ file, built statement by statement. Colours and normals are kept only when the
// file gives them for every vertex (colours) or every corner (normals).
class ObjBuilder {
 public:
  ObjBuilder() { m_.indexBase = 1; }

  // One statement's tokens, the first a keyword; false when they are not valid OBJ.
  bool statement(const std::vector<std::string_view>& t, std::size_t line) {
    if (t[0] == "v") return vertex(t);
    if (t[0] == "vn") return normal(t);
    if (t[0] == "f") return face(t, line);
    return true;
  }

  RawMesh finish() {
    if (!m_.positions.empty() && colored_ == m_.positions.size()) m_.colors = std::move(colors_);
    if (corners_ > 0 && cornersWithNormal_ == corners_) m_.normals = std::move(vertexNormals_);
    return std::move(m_);
  }

 private:
  // x y z, optionally w, or r g b after x y z (the vertex-colour extension).
  bool vertex(const std::vector<std::string_view>& t) {
    std::array<double, 6> v{};
    std::size_t n = 0;
    for (; n < 6 && n + 1 < t.size(); ++n) {
      const auto d = number(t[n + 1]);
      if (!d) break;
      v[n] = *d;
    }
    if (n < 3) return false;
    m_.positions.emplace_back(toFloat(v[0]), toFloat(v[1]), toFloat(v[2]));
    if (n >= 6) {
      colors_.emplace_back(toFloat(v[3]), toFloat(v[4]), toFloat(v[5]));
      ++colored_;
    } else {
      colors_.emplace_back(0.0f);
    }
    vertexNormals_.emplace_back(0.0f);
    return true;
  }

  bool normal(const std::vector<std::string_view>& t) {
    if (t.size() < 4) return false;
    std::array<float, 3> n{};
    for (int k = 0; k < 3; ++k) {
      const auto d = number(t[1 + k]);
      if (!d) return false;
      n[k] = toFloat(*d);
    }
    fileNormals_.emplace_back(n[0], n[1], n[2]);
    return true;
  }

  bool face(const std::vector<std::string_view>& t, std::size_t line) {
    ++m_.declaredFaces;
    for (std::size_t k = 1; k < t.size(); ++k)
      if (!corner(t[k])) return false;
    m_.endFace(line);
    return true;
  }

  // v, v/vt, v/vt/vn or v//vn; a normal given to a vertex that exists becomes that vertex's.
  bool corner(std::string_view tok) {
    const std::size_t s1 = tok.find('/');
    const auto vi = integer(tok.substr(0, s1));
    if (!vi) return false;
    const std::int64_t v = objIndex(*vi, m_.positions.size());
    m_.addCorner(v);
    ++corners_;
    if (s1 == std::string_view::npos) return true;
    const std::size_t s2 = tok.find('/', s1 + 1);
    if (s2 == std::string_view::npos || s2 + 1 >= tok.size()) return true;
    const auto ni = integer(tok.substr(s2 + 1));
    if (!ni) return false;
    const std::int64_t n = objIndex(*ni, fileNormals_.size());
    if (v < 0 || static_cast<std::size_t>(v) >= m_.positions.size() || n < 0 ||
        static_cast<std::size_t>(n) >= fileNormals_.size())
      return true;
    vertexNormals_[static_cast<std::size_t>(v)] = fileNormals_[static_cast<std::size_t>(n)];
    ++cornersWithNormal_;
    return true;
  }

  RawMesh m_;
  std::vector<glm::vec3> colors_, fileNormals_, vertexNormals_;
  std::size_t colored_ = 0, corners_ = 0, cornersWithNormal_ = 0;
};

}  // namespace

Result<RawMesh> readObj(const fs::path& path, std::string_view text) {
  ObjBuilder obj;
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
    if (!isObjKeyword(t[0]) || !obj.statement(t, lineNo)) return notValid(path, Format::Obj, lineText(lineNo));
  }
  return obj.finish();
}

}  // namespace puff::mesh::detail
