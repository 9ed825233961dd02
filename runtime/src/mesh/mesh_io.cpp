// Reading and writing puff meshes through OpenMesh (OBJ, OFF, PLY, STL).
//
// OpenMesh is forgiving in ways a baker must not be: it reads garbage as an empty mesh, drops
// faces it cannot add, separates non-manifold faces onto duplicated vertices, and reports all of
// that only on its own log streams. So each file is first scanned here for what it declares
// (face counts, OBJ vertex lines), and what OpenMesh built is compared with that.
#include <puff/core/text.h>
#include <puff/mesh/mesh.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

#include <glm/glm.hpp>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#pragma GCC diagnostic pop

namespace fs = std::filesystem;

namespace puff::mesh {
namespace {

struct OmTraits : OpenMesh::DefaultTraits {
  // Float colors keep full precision; Vec3f does not compile with OpenMesh 9's exporter (it has
  // no color_cast from Vec3f to Vec4ui), Vec4f does.
  using Color = OpenMesh::Vec4f;
};
using OmMesh = OpenMesh::PolyMesh_ArrayKernelT<OmTraits>;
using OmOptions = OpenMesh::IO::Options;

enum class Format { Obj, Off, Ply, Stl };

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

using core::lower;

Result<Format> formatOf(const fs::path& path) {
  const std::string ext = lower(path.extension().string());
  if (ext == ".obj") return Format::Obj;
  if (ext == ".off") return Format::Off;
  if (ext == ".ply") return Format::Ply;
  if (ext == ".stl") return Format::Stl;
  const std::string shown = ext.empty() ? "no extension" : "unsupported extension '" + path.extension().string() + "'";
  return Error::at(path, shown + " (accepted: .obj, .off, .ply, .stl)");
}

/// strerror, first letter lowered so it reads inside our one-line messages.
std::string reason(int err) {
  std::string s = std::strerror(err);
  if (!s.empty()) s[0] = char(std::tolower(static_cast<unsigned char>(s[0])));
  return s;
}

/// OpenMesh's omlog/omout/omerr are process-wide. While one of our reads or writes runs they are
/// disabled (text already buffered is dropped on flush) and afterwards put back as they were.
/// The mutex serializes our own OpenMesh IO so two threads cannot interleave the toggling.
class OmSilence {
 public:
  OmSilence() : lock_(mutex()) {
    for (std::size_t i = 0; i < kStreams; ++i) {
      wasEnabled_[i] = stream(i).is_enabled();
      stream(i).disable();
    }
  }
  ~OmSilence() {
    for (std::size_t i = 0; i < kStreams; ++i) {
      stream(i).flush();  // drops a half line written while disabled
      if (wasEnabled_[i]) stream(i).enable();
    }
  }
  OmSilence(const OmSilence&) = delete;
  OmSilence& operator=(const OmSilence&) = delete;

 private:
  static constexpr std::size_t kStreams = 3;
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static OpenMesh::mostream& stream(std::size_t i) { return i == 0 ? omlog() : i == 1 ? omout() : omerr(); }
  std::lock_guard<std::mutex> lock_;
  std::array<bool, kStreams> wasEnabled_{};
};

// ---- what the file declares ---------------------------------------------------------------------

struct Declared {
  std::size_t faces = 0;
  bool colorsOnEveryVertex = true;   // OBJ: OpenMesh leaves the others' colors uninitialized
  bool normalsOnEveryCorner = true;  // OBJ: likewise for vertices no `f a//n` reaches
  bool offComments = false;          // ASCII OFF with '#': OpenMesh reads it as an empty mesh
};

Error notValid(const fs::path& path, Format f, const std::string& detail = {}) {
  return Error::at(path,
                   std::string("not a valid ") + formatName(f) + " file" + (detail.empty() ? "" : " (" + detail + ")"));
}

std::string_view trimLeft(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  return s;
}

std::string_view firstToken(std::string_view s) {
  s = trimLeft(s);
  std::size_t end = 0;
  while (end < s.size() && !std::isspace(static_cast<unsigned char>(s[end]))) ++end;
  return s.substr(0, end);
}

bool hasControlBytes(std::string_view line) {
  for (char c : line) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 && c != '\t' && c != '\r' && c != '\v' && c != '\f') return true;
    if (u == 0x7f) return true;
  }
  return false;
}

Result<Declared> scanObj(const fs::path& path) {
  // Every statement of the OBJ spec (and the common extensions); anything else is not OBJ.
  static const std::set<std::string_view> kKeywords = {
      "v",        "vt",       "vn",     "vp",     "f",      "fo",     "l",    "p",          "o",
      "g",        "s",        "mtllib", "usemtl", "maplib", "usemap", "lod",  "shadow_obj", "trace_obj",
      "ctech",    "stech",    "cstype", "deg",    "bmat",   "step",   "curv", "curv2",      "surf",
      "parm",     "trim",     "hole",   "scrv",   "sp",     "end",    "con",  "mg",         "bevel",
      "c_interp", "d_interp", "call",   "csh",    "res"};
  std::ifstream in(path, std::ios::binary);
  Declared d;
  std::size_t vertices = 0, coloredVertices = 0, corners = 0, cornersWithNormal = 0;
  std::string line;
  for (std::size_t lineNo = 1; std::getline(in, line); ++lineNo) {
    std::string_view s = line;
    if (lineNo == 1 && s.substr(0, 3) == "\xEF\xBB\xBF") s.remove_prefix(3);  // UTF-8 BOM
    if (hasControlBytes(s)) return notValid(path, Format::Obj, "line " + std::to_string(lineNo));
    s = trimLeft(s);
    if (s.empty() || s.front() == '#' || s.front() == '\r') continue;
    const std::string_view key = firstToken(s);
    if (!kKeywords.count(key)) return notValid(path, Format::Obj, "line " + std::to_string(lineNo));
    if (key == "v") {
      // Parsed here because OpenMesh's reader silently skips a vertex it cannot parse ("nan").
      std::string rest(s.substr(key.size()));
      const char* p = rest.c_str();
      double values[7];
      int count = 0;
      for (; count < 7; ++count) {
        char* end = nullptr;
        values[count] = std::strtod(p, &end);
        if (end == p) break;
        p = end;
      }
      if (count < 3) return notValid(path, Format::Obj, "line " + std::to_string(lineNo));
      for (int i = 0; i < 3; ++i)
        if (!std::isfinite(values[i]))
          return Error::at(path, "vertex " + std::to_string(vertices) + " has a non-finite coordinate");
      if (count >= 6) ++coloredVertices;
      ++vertices;
    } else if (key == "f") {
      ++d.faces;
      std::string_view rest = s.substr(key.size());
      for (std::string_view tok = firstToken(rest); !tok.empty(); tok = firstToken(rest)) {
        rest = trimLeft(rest).substr(tok.size());
        ++corners;
        const std::size_t slash = tok.rfind('/');
        if (slash != std::string_view::npos && slash + 1 < tok.size() && tok.find('/') != slash) ++cornersWithNormal;
      }
    }
  }
  d.colorsOnEveryVertex = vertices > 0 && coloredVertices == vertices;
  d.normalsOnEveryCorner = corners > 0 && cornersWithNormal == corners;
  return d;
}

Result<Declared> scanOff(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string header;
  if (!std::getline(in, header) || hasControlBytes(header)) return notValid(path, Format::Off);
  std::string_view key = firstToken(header);
  // [ST][C][N][4][n]OFF, optionally followed by BINARY.
  if (key.size() < 3 || key.substr(key.size() - 3) != "OFF") return notValid(path, Format::Off);
  for (char c : key.substr(0, key.size() - 3))
    if (std::string_view("STCN4n").find(c) == std::string_view::npos) return notValid(path, Format::Off);
  std::string_view rest = trimLeft(std::string_view(header).substr(header.find(key) + key.size()));
  Declared d;
  if (firstToken(rest) == "BINARY") {
    // Counts follow the header line as 32-bit integers, little-endian as OpenMesh writes them.
    unsigned char b[12];
    if (!in.read(reinterpret_cast<char*>(b), sizeof b)) return notValid(path, Format::Off);
    d.faces = std::size_t(b[4]) | std::size_t(b[5]) << 8 | std::size_t(b[6]) << 16 | std::size_t(b[7]) << 24;
    return d;
  }
  // ASCII: "nv nf ne" is the next non-comment content (it may even share the header line).
  {
    std::ifstream all(path, std::ios::binary);
    d.offComments = std::find(std::istreambuf_iterator<char>(all), std::istreambuf_iterator<char>(), '#') !=
                    std::istreambuf_iterator<char>();
  }
  std::string text(rest);
  std::string line;
  std::vector<long long> counts;
  for (int guard = 0; counts.size() < 2 && guard < 1000; ++guard) {
    const std::size_t hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    const char* p = text.c_str();
    for (;;) {
      char* end = nullptr;
      const long long v = std::strtoll(p, &end, 10);
      if (end == p) break;
      counts.push_back(v);
      p = end;
    }
    if (counts.size() >= 2) break;
    if (!firstToken(p).empty() || !std::getline(in, text)) return notValid(path, Format::Off);
  }
  if (counts.size() < 2 || counts[0] < 0 || counts[1] < 0) return notValid(path, Format::Off);
  d.faces = std::size_t(counts[1]);
  // OpenMesh's reader, given fewer faces than the header counts, repeats the last one until the
  // count is reached. Every vertex and face is a line of its own (as every OFF writer puts them):
  // count what the file holds.
  std::size_t lines = 0;
  while (std::getline(in, line)) {
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    if (!firstToken(line).empty()) ++lines;
  }
  const std::size_t vertices = std::size_t(counts[0]);
  const std::size_t held = lines > vertices ? lines - vertices : 0;
  if (held < d.faces) {
    return Error::at(path, "the header declares " + std::to_string(d.faces) + (d.faces == 1 ? " face" : " faces") +
                               " after " + std::to_string(vertices) + " vertices; the file holds " +
                               std::to_string(held));
  }
  return d;
}

Result<Declared> scanPly(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  auto clean = [](std::string& s) {
    if (!s.empty() && s.back() == '\r') s.pop_back();
  };
  if (!std::getline(in, line)) return notValid(path, Format::Ply);
  clean(line);
  if (line != "ply") return notValid(path, Format::Ply);
  Declared d;
  for (int n = 0; n < 10000 && std::getline(in, line); ++n) {
    clean(line);
    if (hasControlBytes(line)) break;
    if (line == "end_header") return d;
    char element[64];
    unsigned long long count = 0;
    if (std::sscanf(line.c_str(), "element %63s %llu", element, &count) == 2 && std::string_view(element) == "face")
      d.faces = std::size_t(count);
  }
  return notValid(path, Format::Ply, "no end_header");
}

Result<Declared> scanStl(const fs::path& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  if (!ec && size >= 84) {
    unsigned char head[84];
    if (in.read(reinterpret_cast<char*>(head), sizeof head)) {
      const std::uint64_t n = std::uint64_t(head[80]) | std::uint64_t(head[81]) << 8 | std::uint64_t(head[82]) << 16 |
                              std::uint64_t(head[83]) << 24;
      // Binary STL is recognized by its exact size; many binary headers start with "solid" too.
      if (84 + 50 * n == size) return Declared{std::size_t(n), false, false};
    }
  }
  in.clear();
  in.seekg(0);
  std::string line;
  if (!std::getline(in, line) || firstToken(line) != "solid" || hasControlBytes(line))
    return notValid(path, Format::Stl);
  Declared d{0, false, false};
  std::size_t lineNo = 1;
  while (std::getline(in, line)) {
    ++lineNo;
    if (hasControlBytes(line)) return notValid(path, Format::Stl, "line " + std::to_string(lineNo));
    if (firstToken(line) == "facet") ++d.faces;
  }
  return d;
}

Result<Declared> scan(const fs::path& path, Format f) {
  switch (f) {
    case Format::Obj:
      return scanObj(path);
    case Format::Off:
      return scanOff(path);
    case Format::Ply:
      return scanPly(path);
    case Format::Stl:
      return scanStl(path);
  }
  return notValid(path, f);
}

Result<void> checkReadable(const fs::path& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)  // e.g. a parent we may not search
    return Error::at(path, "cannot open: " + reason(ec.value()));
  if (!fs::exists(st)) return Error::at(path, "cannot open: " + reason(ENOENT));
  if (fs::is_directory(st)) return Error::at(path, "cannot open: " + reason(EISDIR));
  // A FIFO would block the read and a device never ends: only regular files are meshes.
  if (!fs::is_regular_file(st)) return Error::at(path, "cannot open: not a regular file");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return Error::at(path, "cannot open: " + reason(errno));
  std::fclose(f);
  return {};
}

// ---- after reading ------------------------------------------------------------------------------

double signedVolume(const TriMesh& m) {
  // Relative to the bounding-box center, so an open mesh gets a sensible sign too.
  glm::dvec3 lo(m.positions[0]), hi(m.positions[0]);
  for (const glm::vec3& p : m.positions) {
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  const glm::dvec3 c = (lo + hi) * 0.5;
  double v = 0.0;
  for (const glm::uvec3& t : m.triangles) {
    const glm::dvec3 a = glm::dvec3(m.positions[t[0]]) - c;
    const glm::dvec3 b = glm::dvec3(m.positions[t[1]]) - c;
    const glm::dvec3 d = glm::dvec3(m.positions[t[2]]) - c;
    v += a.x * (b.y * d.z - b.z * d.y) + a.y * (b.z * d.x - b.x * d.z) + a.z * (b.x * d.y - b.y * d.x);
  }
  return v / 6.0;
}

/// Drops vertices no triangle uses, so stray OBJ points cannot shift the normalization. The kept
/// vertices stay in file order.
void removeUnreferenced(TriMesh& m) {
  std::vector<std::uint32_t> remap(m.positions.size(), 0);
  for (const glm::uvec3& t : m.triangles)
    for (int k = 0; k < 3; ++k) remap[t[k]] = 1;
  std::uint32_t next = 0;
  for (std::uint32_t& r : remap) r = r ? next++ : UINT32_MAX;
  if (next == m.positions.size()) return;
  for (glm::uvec3& t : m.triangles)
    for (int k = 0; k < 3; ++k) t[k] = remap[t[k]];
  auto apply = [&](std::vector<glm::vec3>& v) {
    if (v.empty()) return;
    std::vector<glm::vec3> out(next);
    for (std::size_t i = 0; i < remap.size(); ++i)
      if (remap[i] != UINT32_MAX) out[remap[i]] = v[i];
    v = std::move(out);
  };
  apply(m.positions);
  apply(m.normals);
  apply(m.colors);
}

bool usableNormals(const std::vector<glm::vec3>& normals) {
  for (const glm::vec3& n : normals) {
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) return false;
    const float len = glm::length(n);
    if (len < 0.9f || len > 1.1f) return false;  // unit within what a text file rounds to
  }
  return true;
}

// ---- writing ------------------------------------------------------------------------------------

glm::vec3 clampColor(glm::vec3 c) {
  for (int k = 0; k < 3; ++k) c[k] = std::isfinite(c[k]) ? std::clamp(c[k], 0.0f, 1.0f) : 0.0f;
  return c;
}

/// OpenMesh's OBJ writer refuses vertex colors, so OBJ is written here ("v x y z r g b", the
/// extension OpenMesh, MeshLab and Blender read).
bool writeObj(const TriMesh& m, const fs::path& file, bool normals) {
  std::FILE* f = std::fopen(file.c_str(), "wb");
  if (!f) return false;
  std::fprintf(f, "# puff mesh: %zu vertices, %zu triangles\n", m.positions.size(), m.triangles.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const glm::vec3& p = m.positions[i];
    if (m.hasColors()) {
      const glm::vec3 c = clampColor(m.colors[i]);
      std::fprintf(f, "v %.9g %.9g %.9g %.9g %.9g %.9g\n", p.x, p.y, p.z, c.r, c.g, c.b);
    } else {
      std::fprintf(f, "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
    }
  }
  if (normals) {
    // One normal per vertex, same index: "f a//a b//b c//c" gives every corner its vertex's normal.
    for (const glm::vec3& n : m.normals) std::fprintf(f, "vn %.9g %.9g %.9g\n", n.x, n.y, n.z);
    for (const glm::uvec3& t : m.triangles)
      std::fprintf(f, "f %u//%u %u//%u %u//%u\n", t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1, t[2] + 1, t[2] + 1);
  } else {
    for (const glm::uvec3& t : m.triangles) std::fprintf(f, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
  }
  const bool ok = !std::ferror(f);
  return std::fclose(f) == 0 && ok;
}

bool writeWithOpenMesh(const TriMesh& m, const fs::path& file, Format format, bool normals) {
  OmMesh om;
  om.request_vertex_colors();
  if (normals) om.request_vertex_normals();
  std::vector<OmMesh::VertexHandle> vh;
  vh.reserve(m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const glm::vec3& p = m.positions[i];
    vh.push_back(om.add_vertex(OmMesh::Point(p.x, p.y, p.z)));
    const glm::vec3 c = m.hasColors() ? clampColor(m.colors[i]) : glm::vec3(1.0f);
    om.set_color(vh.back(), OmMesh::Color(c.r, c.g, c.b, 1.0f));
    if (normals) om.set_normal(vh.back(), OmMesh::Normal(m.normals[i].x, m.normals[i].y, m.normals[i].z));
  }
  for (const glm::uvec3& t : m.triangles) {
    std::vector<OmMesh::VertexHandle> face = {vh[t[0]], vh[t[1]], vh[t[2]]};
    if (om.add_face(face).is_valid()) continue;
    // A face the halfedge structure refuses (non-manifold) goes on its own copies of its vertices,
    // as OpenMesh's importer does, rather than being lost from the file.
    for (auto& v : face) {
      const OmMesh::VertexHandle copy = om.add_vertex(om.point(v));
      om.set_color(copy, om.color(v));
      if (normals) om.set_normal(copy, om.normal(v));
      v = copy;
    }
    om.add_face(face);
  }
  OmOptions opt;
  switch (format) {
    case Format::Off:  // OpenMesh's OFF reader keeps float colors exactly
      if (m.hasColors()) opt += OmOptions::VertexColor | OmOptions::ColorFloat;
      break;
    case Format::Ply:  // bytes, the form every PLY tool reads (OpenMesh quantizes floats anyway)
      if (m.hasColors()) opt += OmOptions::VertexColor;
      if (normals) opt += OmOptions::VertexNormal;
      break;
    case Format::Stl:
      om.request_face_normals();
      om.update_face_normals();
      opt += OmOptions::Binary;  // exact floats, a quarter of the size
      break;
    case Format::Obj:
      break;
  }
  return OpenMesh::IO::write_mesh(om, file.string(), opt, 9);
}

/// A copy of an ASCII OFF file with comments blanked out (line structure kept), in the system
/// temp directory, removed again when this goes out of scope.
class CommentFreeOffCopy {
 public:
  explicit CommentFreeOffCopy(const fs::path& source) {
    static std::atomic<unsigned> counter{0};
    std::error_code ec;
    path_ = fs::temp_directory_path(ec) /
            ("puff-off-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".off");
    std::ifstream in(source, std::ios::binary);
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    std::string line;
    while (std::getline(in, line)) {
      const std::size_t hash = line.find('#');
      if (hash != std::string::npos) line.resize(hash);
      out << line << '\n';
    }
    ok_ = bool(out.flush());
  }
  ~CommentFreeOffCopy() {
    std::error_code ec;
    fs::remove(path_, ec);
  }
  CommentFreeOffCopy(const CommentFreeOffCopy&) = delete;
  CommentFreeOffCopy& operator=(const CommentFreeOffCopy&) = delete;
  bool ok() const { return ok_; }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
  bool ok_ = false;
};

// Reads the file into `om` with OpenMesh; `opt` says what it found.
Result<void> readOpenMesh(const fs::path& path, Format format, const Declared& declared, OmMesh& om, OmOptions& opt) {
  bool readOk = false;
  {
    // OpenMesh's OFF reader does not skip comments, though the format allows them; its stream
    // reader would lose the header's color flag, so it gets a cleaned copy as a file.
    std::optional<CommentFreeOffCopy> clean;
    if (declared.offComments) {
      clean.emplace(path);
      if (!clean->ok()) return Error::at(path, "cannot read: no room for a temporary copy");
    }
    OmSilence silence;
    readOk = OpenMesh::IO::read_mesh(om, (clean ? clean->path() : path).string(), opt);
  }
  if (!readOk || (om.n_vertices() == 0 && declared.faces > 0)) return notValid(path, format);
  return {};
}

// "1 face", "5 faces".
std::string facesText(std::size_t n) { return std::to_string(n) + (n == 1 ? " face" : " faces"); }

// Every face the file declares made it in: the number added, and in `separated` how many of them
// OpenMesh's importer put on their own vertices (non-manifold where they were: issue 17's cow and
// beetle, which real meshes are).
Result<std::size_t> checkFaces(const fs::path& path, const Declared& declared, const OmMesh& om,
                               std::size_t& separated) {
  const std::size_t added = om.n_faces();
  separated = 0;
  for (const auto fh : om.faces())
    if (om.status(fh).fixed_nonmanifold()) ++separated;
  if (declared.faces == 0 && added == 0) return Error::at(path, "no faces");
  if (added < declared.faces)
    return Error::at(path, "the file declares " + facesText(declared.faces) + ", only " + std::to_string(added) +
                               " could be added (the others repeat a vertex, refer to a missing one, or are not "
                               "in the file)");
  return added;
}

// The vertices' positions, and their colours and normals where the file gives them for every one.
void copyVertices(const OmMesh& om, bool fileColors, bool fileNormals, TriMesh& mesh) {
  mesh.positions.reserve(om.n_vertices());
  for (const auto vh : om.vertices()) {
    const OmMesh::Point& p = om.point(vh);
    mesh.positions.emplace_back(p[0], p[1], p[2]);
  }
  if (fileColors) {
    mesh.colors.reserve(om.n_vertices());
    float maxComponent = 0.0f;
    for (const auto vh : om.vertices()) {
      const OmMesh::Color& c = om.color(vh);
      mesh.colors.emplace_back(c[0], c[1], c[2]);
      for (int k = 0; k < 3; ++k)
        if (std::isfinite(c[k])) maxComponent = std::max(maxComponent, c[k]);
    }
    // Some OBJ exporters write 0..255 rather than 0..1 after "v x y z".
    const float scale = maxComponent > 1.0f ? 1.0f / 255.0f : 1.0f;
    for (glm::vec3& c : mesh.colors) c = clampColor(c * scale);
  }
  if (fileNormals) {
    mesh.normals.reserve(om.n_vertices());
    for (const auto vh : om.vertices()) {
      const OmMesh::Normal& n = om.normal(vh);
      mesh.normals.emplace_back(n[0], n[1], n[2]);
    }
  }
}

// The faces as triangles; returns each triangle's face in the file.
std::vector<std::uint32_t> triangulate(const OmMesh& om, TriMesh& mesh) {
  std::vector<std::uint32_t> sourceFace;
  mesh.triangles.reserve(om.n_faces());
  sourceFace.reserve(om.n_faces());
  std::vector<std::uint32_t> corners;
  for (const auto fh : om.faces()) {
    corners.clear();
    for (const auto vh : om.fv_range(fh)) corners.push_back(std::uint32_t(vh.idx()));
    // Fan triangulation keeps the polygon's winding and lets messages name the file's face.
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
      mesh.triangles.emplace_back(corners[0], corners[k], corners[k + 1]);
      sourceFace.push_back(std::uint32_t(fh.idx()));
    }
  }
  return sourceFace;
}

}  // namespace

Result<TriMesh> loadMesh(const fs::path& path, LoadInfo* info, Normalize normalize) {
  const Result<Format> format = formatOf(path);
  if (!format) return format.error();
  PUFF_TRY(checkReadable(path));
  const Result<Declared> declared = scan(path, *format);
  if (!declared) return declared.error();

  OmMesh om;
  om.request_vertex_colors();
  om.request_vertex_normals();
  om.request_face_status();  // the importer marks faces it had to separate as non-manifold
  OmOptions opt = OmOptions::VertexColor | OmOptions::VertexNormal;
  PUFF_TRY(readOpenMesh(path, *format, *declared, om, opt));
  std::size_t separated = 0;
  const Result<std::size_t> added = checkFaces(path, *declared, om, separated);
  if (!added) return added.error();

  TriMesh mesh;
  // STL carries neither; OpenMesh's STL reader leaves the requested flags set regardless.
  const bool fileColors = *format != Format::Stl && opt.vertex_has_color() && declared->colorsOnEveryVertex;
  const bool fileNormals = *format != Format::Stl && opt.vertex_has_normal() && declared->normalsOnEveryCorner;
  copyVertices(om, fileColors, fileNormals, mesh);
  const std::vector<std::uint32_t> sourceFace = triangulate(om, mesh);

  PUFF_TRY(validateMesh(mesh, path.string(), sourceFace));
  removeUnreferenced(mesh);

  LoadInfo li;
  li.sourceFaces = *added;
  li.sourceVertices = om.n_vertices();
  li.separatedFaces = separated;
  li.hadColors = fileColors;
  if (signedVolume(mesh) < 0.0) {
    for (glm::uvec3& t : mesh.triangles) std::swap(t[1], t[2]);
    for (glm::vec3& n : mesh.normals) n = -n;
    li.flippedInward = true;
  }
  if (normalize == Normalize::kYes) normalizeToUnitSphere(mesh);
  if (fileNormals && usableNormals(mesh.normals)) {
    for (glm::vec3& n : mesh.normals) n = glm::normalize(n);
    li.hadNormals = true;
  } else {
    computeNormals(mesh);
  }
  if (info) *info = li;
  return mesh;
}

Result<void> saveMesh(const TriMesh& mesh, const fs::path& path, SaveNormals normals) {
  const Result<Format> format = formatOf(path);
  if (!format) return format.error();
  const bool writeNormals = normals == SaveNormals::kYes;
  if (writeNormals && *format != Format::Ply && *format != Format::Obj)
    return Error::at(path, "cannot write normals: only PLY and OBJ files carry them here");
  if (writeNormals && mesh.normals.size() != mesh.positions.size())
    return Error::at(path, "cannot write: " + std::to_string(mesh.normals.size()) + " normals for " +
                               std::to_string(mesh.positions.size()) + " vertices");
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles[t][k] >= mesh.positions.size())
        return Error::at(path, "cannot write: triangle " + std::to_string(t) + " refers to vertex " +
                                   std::to_string(mesh.triangles[t][k]) + ", but there are only " +
                                   std::to_string(mesh.positions.size()));
  if (mesh.hasColors() && mesh.colors.size() != mesh.positions.size())
    return Error::at(path, "cannot write: " + std::to_string(mesh.colors.size()) + " colors for " +
                               std::to_string(mesh.positions.size()) + " vertices");

  // Same directory, so the final rename is atomic; same extension, so OpenMesh picks the writer.
  static std::atomic<unsigned> counter{0};
  const fs::path tmp = path.parent_path() / ("." + path.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                                             std::to_string(counter++) + lower(path.extension().string()));
  {
    // Opening it ourselves first gives the real reason (no such directory, permission denied).
    std::FILE* probe = std::fopen(tmp.c_str(), "wb");
    if (!probe) return Error::at(path, "cannot write: " + reason(errno));
    std::fclose(probe);
  }
  bool written = false;
  if (*format == Format::Obj) {
    written = writeObj(mesh, tmp, writeNormals);
  } else {
    OmSilence silence;
    written = writeWithOpenMesh(mesh, tmp, *format, writeNormals);
  }
  std::error_code ec;
  if (!written) {
    fs::remove(tmp, ec);
    return Error::at(path, "cannot write: writing the temporary file failed");
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    return Error::at(path, "cannot write: " + reason(ec.value()));
  }
  return {};
}

}  // namespace puff::mesh
