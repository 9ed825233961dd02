// Puff's PLY reader: the header, then vertex, face and tristrips elements, ASCII or binary of either
// byte order.
#include <array>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mesh_read_formats.h"

namespace puff::mesh::detail {

namespace fs = std::filesystem;

namespace {

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

// What the header declares: the body's encoding (set together by the format line) and its elements.
struct PlyHeader {
  std::optional<bool> ascii, bigEndian;
  std::vector<PlyElement> elements;
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

// A header line without its trailing blanks: "\r", and "ply " as some writers end it.
std::string_view trimRight(std::string_view s) {
  while (!s.empty() && isBlank(s.back())) s.remove_suffix(1);
  return s;
}

// A property line's tokens ("property TYPE NAME" or "property list COUNT TYPE NAME"); nothing when
// they are neither, or a list's count is not an integer type.
std::optional<PlyProperty> plyProperty(const std::vector<std::string_view>& t) {
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
  if (!type || !count) return std::nullopt;
  p.type = *type;
  p.countType = *count;
  return p;
}

// The header, from "ply" to "end_header" (within the first 10000 lines), which must name a format.
Result<PlyHeader> readPlyHeader(const fs::path& path, Lines& lines) {
  std::string_view line;
  if (!lines.next(line) || trimRight(line) != "ply") return notValid(path, Format::Ply);
  PlyHeader h;
  bool ended = false;
  while (!ended && lines.number() < 10000 && lines.next(line)) {
    line = trimRight(line);
    const std::string detail = "header " + lineText(lines.number());
    if (hasControlBytes(line)) return notValid(path, Format::Ply, detail);
    const std::vector<std::string_view> t = tokens(line);
    if (t.empty()) continue;
    if (t[0] == "end_header") {
      ended = true;
    } else if (t[0] == "comment" || t[0] == "obj_info") {
    } else if (t[0] == "format") {
      if (t.size() < 2 || h.ascii) return notValid(path, Format::Ply, detail);
      h.ascii = t[1] == "ascii";
      h.bigEndian = t[1] == "binary_big_endian";
      if (!*h.ascii && !*h.bigEndian && t[1] != "binary_little_endian")
        return notValid(path, Format::Ply, detail + ": unknown format " + std::string(t[1].substr(0, 32)));
    } else if (t[0] == "element") {
      const auto count = t.size() == 3 ? integer(t[2]) : std::nullopt;
      if (!count || *count < 0) return notValid(path, Format::Ply, detail);
      h.elements.push_back({std::string(t[1]), static_cast<std::uint64_t>(*count), {}});
    } else if (t[0] == "property") {
      if (h.elements.empty()) return notValid(path, Format::Ply, detail);
      const std::optional<PlyProperty> p = plyProperty(t);
      if (!p) return notValid(path, Format::Ply, detail);
      h.elements.back().properties.push_back(*p);
    } else {
      return notValid(path, Format::Ply, detail);
    }
  }
  if (!ended) return notValid(path, Format::Ply, "no end_header");
  if (!h.ascii) return notValid(path, Format::Ply, "no format line");
  return h;
}

// What an element's properties are read into: which vertex property fills what (position 0-2,
// normal 3-5, colour 6-8, the first of each name) and which list holds a face's or strip's corners.
struct PlyLayout {
  bool isVertex = false, isFace = false, isStrips = false;
  std::vector<int> slot;  // per property: its vertex slot, or -1
  std::array<bool, 9> have{};
  std::array<double, 9> colorScale{};
  int listSlot = -1;

  bool normals() const { return isVertex && have[3] && have[4] && have[5]; }
  bool colors() const { return isVertex && have[6] && have[7] && have[8]; }
};

PlyLayout plyLayout(const PlyElement& e) {
  static const std::pair<std::string_view, int> kSlots[] = {
      {"x", 0},           {"y", 1},    {"z", 2}, {"nx", 3}, {"ny", 4}, {"nz", 5},          {"red", 6},
      {"green", 7},       {"blue", 8}, {"r", 6}, {"g", 7},  {"b", 8},  {"diffuse_red", 6}, {"diffuse_green", 7},
      {"diffuse_blue", 8}};
  PlyLayout l;
  l.isVertex = e.name == "vertex";
  l.isFace = e.name == "face";
  l.isStrips = e.name == "tristrips";
  l.slot.assign(e.properties.size(), -1);
  for (std::size_t i = 0; i < e.properties.size(); ++i) {
    const PlyProperty& p = e.properties[i];
    if (l.isVertex && !p.list) {
      for (const auto& [name, s] : kSlots) {
        if (p.name == name && !l.have[static_cast<std::size_t>(s)]) {
          l.slot[i] = s;
          l.have[static_cast<std::size_t>(s)] = true;
          // 8- and 16-bit colours are unsigned-normalized; floats are [0, 1] already.
          l.colorScale[static_cast<std::size_t>(s)] = p.type == PlyType::kU8    ? 1.0 / 255.0
                                                      : p.type == PlyType::kU16 ? 1.0 / 65535.0
                                                                                : 1.0;
        }
      }
    }
    if ((l.isFace || l.isStrips) && p.list && (p.name == "vertex_indices" || p.name == "vertex_index") &&
        l.listSlot < 0)
      l.listSlot = static_cast<int>(i);
  }
  return l;
}

// The smallest type any of an element's values has (a list's count included).
PlyType smallestType(const PlyElement& e) {
  PlyType smallest = PlyType::kF64;
  for (const PlyProperty& p : e.properties)
    smallest = plySize(p.list ? p.countType : p.type) < plySize(smallest) ? (p.list ? p.countType : p.type) : smallest;
  return smallest;
}

// A PLY body read element by element into a mesh.
class PlyBody {
 public:
  PlyBody(const fs::path& path, std::string_view body, bool ascii, bool bigEndian)
      : path_(path), values_(body, ascii, bigEndian) {}

  // Every instance of `e`, after checking that the element has what its name needs and that the
  // file can hold the count it declares.
  Result<void> element(const PlyElement& e) {
    const PlyLayout l = plyLayout(e);
    if (l.isVertex) {
      haveVertices_ = true;
      if (!l.have[0] || !l.have[1] || !l.have[2]) return notValid(path_, Format::Ply, "vertex has no x, y and z");
    }
    if ((l.isFace || l.isStrips) && l.listSlot < 0)
      return notValid(path_, Format::Ply, e.name + " has no vertex_indices list");
    if (l.isFace) m_.declaredFaces += e.count;
    if (e.properties.empty()) return {};  // nothing to read, however many it counts
    // Every instance takes at least one value: a count beyond what is left is a lie.
    if (e.count > values_.mostLeft(smallestType(e))) {
      return notValid(path_, Format::Ply,
                      "the header declares " + std::to_string(e.count) + " " + e.name.substr(0, 32) +
                          " elements; the file holds fewer");
    }
    for (std::uint64_t n = 0; n < e.count; ++n) {
      if (!instance(e, l)) {
        return notValid(path_, Format::Ply,
                        e.name.substr(0, 32) + " " + std::to_string(n) + ": truncated or not a number");
      }
    }
    return {};
  }

  bool haveVertices() const { return haveVertices_; }
  RawMesh take() { return std::move(m_); }

 private:
  // One instance of `e`: a vertex's position, normal and colour, a face's polygon or a strip's
  // triangles. False when a value is missing or not a number.
  bool instance(const PlyElement& e, const PlyLayout& l) {
    std::array<double, 9> v{};
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      const PlyProperty& p = e.properties[i];
      if (!p.list) {
        double x;
        if (!values_.read(p.type, x)) return false;
        if (l.slot[i] >= 0) v[static_cast<std::size_t>(l.slot[i])] = x;
        continue;
      }
      if (!readList(p)) return false;
      if (static_cast<int>(i) != l.listSlot) continue;
      if (l.isFace) {
        for (std::int64_t c : list_) m_.addCorner(c < 0 ? -1 : c);
        m_.endFace();
      } else {
        addStrip(list_, m_);
      }
    }
    if (l.isVertex) {
      m_.positions.emplace_back(toFloat(v[0]), toFloat(v[1]), toFloat(v[2]));
      if (l.normals()) m_.normals.emplace_back(toFloat(v[3]), toFloat(v[4]), toFloat(v[5]));
      if (l.colors())
        m_.colors.emplace_back(toFloat(v[6] * l.colorScale[6]), toFloat(v[7] * l.colorScale[7]),
                               toFloat(v[8] * l.colorScale[8]));
    }
    return true;
  }

  // A list property's count and values, into list_. False when they are missing, not numbers, or
  // the count is not a whole number the rest of the file can hold.
  bool readList(const PlyProperty& p) {
    double count;
    if (!values_.read(p.countType, count)) return false;
    if (!(count >= 0) || count != std::floor(count) || count > static_cast<double>(values_.mostLeft(p.type)))
      return false;
    list_.clear();
    for (std::uint64_t k = 0; k < static_cast<std::uint64_t>(count); ++k) {
      double x;
      if (!values_.read(p.type, x)) return false;
      // An index that is not a whole number within int64 names no vertex.
      list_.push_back(x == std::floor(x) && std::abs(x) < 9.2e18 ? static_cast<std::int64_t>(x) : -2);
    }
    return true;
  }

  const fs::path& path_;
  PlyValues values_;
  RawMesh m_;
  std::vector<std::int64_t> list_;
  bool haveVertices_ = false;
};

}  // namespace

Result<RawMesh> readPly(const fs::path& path, std::string_view text) {
  Lines lines(text);
  PUFF_TRY_ASSIGN(const PlyHeader header, readPlyHeader(path, lines));
  PlyBody body(path, text.substr(lines.pos()), *header.ascii, *header.bigEndian);
  for (const PlyElement& e : header.elements) PUFF_TRY(body.element(e));
  if (!body.haveVertices()) return notValid(path, Format::Ply, "no vertex element");
  return body.take();
}

}  // namespace puff::mesh::detail
