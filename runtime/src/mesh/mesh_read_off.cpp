// Puff's OFF reader: [ST][C][N]OFF in ASCII, and binary OFF with positions only.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "mesh_read_formats.h"

namespace puff::mesh::detail {

namespace fs = std::filesystem;

namespace {

// The next line with content, comments ("#" to the end of the line) removed; false at the end.
bool nextContent(Lines& lines, std::string_view& line) {
  while (lines.next(line)) {
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    if (!firstToken(line).empty()) return true;
  }
  return false;
}

// What the header line says: which values each vertex has beyond its position, and what follows
// the keyword on the line.
struct OffHeader {
  bool texcoords = false, colors = false, normals = false;
  std::string_view rest;
};

// The header line: the first line with content (some writers put a comment first), whose keyword is
// [ST][C][N]OFF.
Result<OffHeader> readOffHeader(const fs::path& path, Lines& lines) {
  std::string_view header;
  do {
    if (!lines.next(header) || hasControlBytes(header)) return notValid(path, Format::Off);
  } while (firstToken(header).empty() || firstToken(header).front() == '#');
  const std::string_view key = firstToken(header);
  if (key.size() < 3 || key.substr(key.size() - 3) != "OFF") return notValid(path, Format::Off);
  OffHeader h;
  std::string_view flags = key.substr(0, key.size() - 3);
  h.texcoords = flags.substr(0, 2) == "ST";
  if (h.texcoords) flags.remove_prefix(2);
  h.colors = !flags.empty() && flags.front() == 'C';
  if (h.colors) flags.remove_prefix(1);
  h.normals = !flags.empty() && flags.front() == 'N';
  if (h.normals) flags.remove_prefix(1);
  if (!flags.empty()) return notValid(path, Format::Off, std::string(key) + ": only [ST][C][N]OFF is read");
  h.rest = trimLeft(header.substr(header.find(key) + key.size()));
  return h;
}

// One face of binary OFF after its corner count `n`: the corners, then its colour components, which
// are skipped. False when they are more than the file holds.
bool readBinaryFace(Bytes& b, std::int32_t n, RawMesh& m) {
  if (n < 0 || static_cast<std::uint64_t>(n) * 4 > b.left()) return false;
  for (std::int32_t k = 0; k < n; ++k) {
    std::int32_t v = 0;
    b.i32(v);
    m.addCorner(v);
  }
  m.endFace();
  std::int32_t nc = 0;  // the face's colour components
  if (!b.i32(nc) || nc < 0 || static_cast<std::uint64_t>(nc) * 4 > b.left()) return false;
  for (std::int32_t k = 0; k < nc; ++k) {
    float ignored;
    b.f32(ignored);
  }
  return true;
}

// Binary OFF's body (`data`, after the header line): counts as 32-bit integers, little-endian as
// OpenMesh writes them, then the vertices and faces.
Result<RawMesh> readBinaryOff(const fs::path& path, std::string_view data) {
  Bytes b(data, false);
  std::int32_t nv = 0, nf = 0, ne = 0;
  if (!b.i32(nv) || !b.i32(nf) || !b.i32(ne) || nv < 0 || nf < 0) return notValid(path, Format::Off);
  if (static_cast<std::uint64_t>(nv) * 12 > b.left())
    return notValid(path, Format::Off, "the header declares " + std::to_string(nv) + " vertices; the file holds fewer");
  RawMesh m;
  m.declaredFaces = static_cast<std::size_t>(nf);
  m.positions.reserve(static_cast<std::size_t>(nv));
  for (std::int32_t i = 0; i < nv; ++i) {
    float p[3];
    for (float& c : p) b.f32(c);
    m.positions.emplace_back(p[0], p[1], p[2]);
  }
  for (std::int32_t f = 0; f < nf; ++f) {
    std::int32_t n = 0;
    if (!b.i32(n)) break;  // fewer faces than declared: counted when the mesh is built
    if (!readBinaryFace(b, n, m)) return notValid(path, Format::Off, "face " + std::to_string(f));
  }
  return m;
}

// One vertex line of ASCII OFF: x y z [nx ny nz] [r g b [a]] [s t]. False when it is not that.
bool readAsciiVertex(std::string_view line, const OffHeader& h, RawMesh& m) {
  if (hasControlBytes(line)) return false;
  std::vector<double> v;
  for (std::string_view tok : tokens(line)) {
    const auto d = number(tok);
    if (!d) return false;
    v.push_back(*d);
  }
  const std::size_t perVertex = 3 + (h.normals ? 3 : 0) + (h.texcoords ? 2 : 0);
  const std::size_t colorValues = v.size() >= perVertex ? v.size() - perVertex : 0;
  if (v.size() < perVertex || (h.colors && colorValues != 3 && colorValues != 4)) return false;
  m.positions.emplace_back(toFloat(v[0]), toFloat(v[1]), toFloat(v[2]));
  if (h.normals) m.normals.emplace_back(toFloat(v[3]), toFloat(v[4]), toFloat(v[5]));
  if (h.colors) {
    const std::size_t c = h.normals ? 6 : 3;
    m.colors.emplace_back(toFloat(v[c]), toFloat(v[c + 1]), toFloat(v[c + 2]));
  }
  return true;
}

// One face line of ASCII OFF: n, then n corners; anything after them (a face colour) is not read.
// False when it is not that.
bool readAsciiFace(std::string_view line, std::size_t lineNo, RawMesh& m) {
  if (hasControlBytes(line)) return false;
  const std::vector<std::string_view> t = tokens(line);
  const auto n = integer(t[0]);
  if (!n || *n < 0 || static_cast<std::uint64_t>(*n) >= t.size()) return false;
  for (std::int64_t k = 1; k <= *n; ++k) {
    const auto v = integer(t[static_cast<std::size_t>(k)]);
    if (!v) return false;
    m.addCorner(*v);
  }
  m.endFace(lineNo);
  return true;
}

// ASCII OFF after the keyword: "nv nf ne" as the next content (it may share the header line), then
// the vertex lines and the face lines.
Result<RawMesh> readAsciiOff(const fs::path& path, Lines& lines, const OffHeader& h) {
  std::string_view line = h.rest;
  if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
  if (firstToken(line).empty() && !nextContent(lines, line)) return notValid(path, Format::Off);
  std::vector<std::int64_t> counts;
  for (std::string_view tok : tokens(line)) {
    const auto v = integer(tok);
    if (!v) return notValid(path, Format::Off, lineText(lines.number()));
    counts.push_back(*v);
  }
  if (counts.size() < 2 || counts[0] < 0 || counts[1] < 0) return notValid(path, Format::Off);
  RawMesh m;
  const auto nv = static_cast<std::uint64_t>(counts[0]);
  m.declaredFaces = static_cast<std::size_t>(counts[1]);
  for (std::uint64_t i = 0; i < nv; ++i) {
    if (!nextContent(lines, line)) {
      return Error::at(path,
                       "the header declares " + std::to_string(nv) + " vertices; the file holds " + std::to_string(i));
    }
    if (!readAsciiVertex(line, h, m)) return notValid(path, Format::Off, lineText(lines.number()));
  }
  std::size_t held = 0;
  for (; held < m.declaredFaces && nextContent(lines, line); ++held)
    if (!readAsciiFace(line, lines.number(), m)) return notValid(path, Format::Off, lineText(lines.number()));
  if (held < m.declaredFaces) {
    return Error::at(path, "the header declares " + std::to_string(m.declaredFaces) +
                               (m.declaredFaces == 1 ? " face" : " faces") + " after " + std::to_string(nv) +
                               " vertices; the file holds " + std::to_string(held));
  }
  return m;
}

}  // namespace

Result<RawMesh> readOff(const fs::path& path, std::string_view text) {
  Lines lines(text);
  PUFF_TRY_ASSIGN(const OffHeader header, readOffHeader(path, lines));
  if (firstToken(header.rest) == "BINARY") {
    if (header.colors || header.normals || header.texcoords)
      return notValid(path, Format::Off, "binary OFF is read with positions only");
    return readBinaryOff(path, text.substr(lines.pos()));
  }
  return readAsciiOff(path, lines, header);
}

}  // namespace puff::mesh::detail
