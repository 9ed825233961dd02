// Puff's STL reader: binary or ASCII facets, their corners merged into shared vertices.
#include <array>
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mesh_read_formats.h"

namespace puff::mesh::detail {

namespace fs = std::filesystem;

namespace {

// The file as binary STL, or nothing when it is not. Binary STL is recognized by its exact size
// (many binary headers start with "solid" too), or, when the file does not start with "solid" and so
// cannot be ASCII, by holding the facets its count says, a few bytes more tolerated (some writers
// pad).
std::optional<RawMesh> readBinaryStl(std::string_view text) {
  if (text.size() < 84) return std::nullopt;
  Bytes b(text.substr(80), false);
  std::int32_t n32 = 0;
  b.i32(n32);
  const auto n = static_cast<std::uint32_t>(n32);
  const std::uint64_t need = 84 + 50 * std::uint64_t{n};
  const bool ascii = firstToken(text.substr(0, 80)).substr(0, 5) == "solid";
  if (need != text.size() && (ascii || need >= text.size() || text.size() - need >= 50)) return std::nullopt;
  RawMesh m;
  VertexMerger merge(m);
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

// A keyword in lower case: keywords are read in any case ("SOLID", "Facet"), as some exporters
// write them.
std::string keyword(std::string_view token) {
  std::string k(token.substr(0, 16));
  for (char& c : k) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return k;
}

// A "vertex x y z" line's tokens as a corner of the facet; false when they are not that.
bool readAsciiVertex(const std::vector<std::string_view>& t, VertexMerger& merge, RawMesh& m) {
  if (t.size() != 4) return false;
  float p[3];
  for (int c = 0; c < 3; ++c) {
    const auto d = number(t[1 + static_cast<std::size_t>(c)]);
    if (!d) return false;
    p[c] = toFloat(*d);
  }
  m.addCorner(merge.add({p[0], p[1], p[2]}));
  return true;
}

// ASCII STL: "solid", then facets of "vertex" lines between "facet" and "endfacet".
Result<RawMesh> readAsciiStl(const fs::path& path, std::string_view text) {
  RawMesh m;
  VertexMerger merge(m);
  Lines lines(text);
  std::string_view line;
  if (!lines.next(line) || keyword(firstToken(line)) != "solid" || hasControlBytes(line))
    return notValid(path, Format::Stl);
  bool inFacet = false;
  while (lines.next(line)) {
    if (hasControlBytes(line)) return notValid(path, Format::Stl, lineText(lines.number()));
    const std::vector<std::string_view> t = tokens(line);
    if (t.empty()) continue;
    const std::string k = keyword(t[0]);
    if (k == "facet") {
      if (inFacet) return notValid(path, Format::Stl, lineText(lines.number()));
      inFacet = true;
      ++m.declaredFaces;
    } else if (k == "vertex") {
      if (!inFacet || !readAsciiVertex(t, merge, m)) return notValid(path, Format::Stl, lineText(lines.number()));
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

Result<RawMesh> readStl(const fs::path& path, std::string_view text) {
  if (std::optional<RawMesh> binary = readBinaryStl(text)) return std::move(*binary);
  return readAsciiStl(path, text);
}

}  // namespace puff::mesh::detail
