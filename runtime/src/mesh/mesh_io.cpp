// Reading puff meshes (OBJ, OFF, PLY, STL, glTF) and writing them (OBJ, OFF, PLY, STL).
//
// Files are parsed by Puff's own readers (mesh_read.h: OpenMesh's crash, hang and write out of
// bounds on malformed files); OpenMesh builds the connectivity, which finds the non-manifold faces
// to split, and writes OFF, PLY and STL. Every face the file declares must make it in.
#include <puff/mesh/mesh.h>
#include <puff/support/text.h>

#include "mesh_read.h"

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

using core::lower;
using detail::Format;
using detail::formatName;

Result<Format> formatOf(const fs::path& path) {
  const std::string ext = lower(path.extension().string());
  if (ext == ".obj") return Format::Obj;
  if (ext == ".off") return Format::Off;
  if (ext == ".ply") return Format::Ply;
  if (ext == ".stl") return Format::Stl;
  if (ext == ".gltf" || ext == ".glb") return Format::Gltf;
  const std::string shown = ext.empty() ? "no extension" : "unsupported extension '" + path.extension().string() + "'";
  return Error::at(path, shown + " (accepted: .obj, .off, .ply, .stl, .gltf, .glb)");
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

Result<void> checkReadable(const fs::path& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)  // e.g. a parent we may not search
    return Error::at(path, "cannot open: " + reason(ec.value()));
  if (!fs::exists(st)) return Error::at(path, "cannot open: " + reason(ENOENT));
  if (fs::is_directory(st)) return Error::at(path, "cannot open: " + reason(EISDIR));
  // A FIFO would block the read and a device never ends: only regular files are meshes.
  if (!fs::is_regular_file(st)) return Error::at(path, "cannot open: not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > kMaxMeshFileBytes) {
    return Error::at(path, "a mesh file of " + std::to_string(size) + " bytes is larger than Puff reads (" +
                               std::to_string(kMaxMeshFileBytes) + " bytes)");
  }
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

// LoadInfo::volumeFraction: |signedVolume| over the volume of the sphere about the bounding box's
// centre through the farthest vertex.
double volumeFraction(const TriMesh& m, double volume) {
  glm::dvec3 lo(m.positions[0]), hi(m.positions[0]);
  for (const glm::vec3& p : m.positions) lo = glm::min(lo, glm::dvec3(p)), hi = glm::max(hi, glm::dvec3(p));
  const glm::dvec3 c = (lo + hi) * 0.5;
  double r2 = 0.0;
  for (const glm::vec3& p : m.positions) r2 = std::max(r2, glm::dot(glm::dvec3(p) - c, glm::dvec3(p) - c));
  const double sphere = 4.0 / 3.0 * 3.14159265358979323846 * r2 * std::sqrt(r2);
  return sphere > 0.0 ? std::abs(volume) / sphere : 0.0;
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
      // By value: adding a vertex may move the arrays a reference would point into.
      const OmMesh::Point point = om.point(v);
      const OmMesh::Color color = om.color(v);
      const OmMesh::Normal normal = normals ? om.normal(v) : OmMesh::Normal(0.0f);
      const OmMesh::VertexHandle copy = om.add_vertex(point);
      om.set_color(copy, color);
      if (normals) om.set_normal(copy, normal);
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
    case Format::Gltf:  // refused by saveMesh
      break;
  }
  return OpenMesh::IO::write_mesh(om, file.string(), opt, 9);
}

// "1 face", "5 faces".
std::string facesText(std::size_t n) { return std::to_string(n) + (n == 1 ? " face" : " faces"); }

// Why the first face left out was (checkFaces says it).
struct Refusal {
  std::size_t face = 0;
  std::string why;
};

// The file's vertices and faces into `om`, as OpenMesh's importer would add them: a face with
// fewer than 3 corners, a corner that names no vertex, or a vertex repeated in one face is left out
// (checkFaces counts it; the first is returned); a face the halfedge structure refuses
// (non-manifold where it is, as real meshes such as the cow and the beetle are) goes onto its own
// copies of its vertices, colour and normal included, and is marked.
std::optional<Refusal> buildOpenMesh(const detail::RawMesh& raw, OmMesh& om) {
  std::optional<Refusal> first;
  auto refuse = [&](std::size_t f, std::string why) {
    if (!first) first = Refusal{f, std::move(why)};
  };
  const OmSilence silence;  // add_face logs each face it refuses
  const std::size_t n = raw.positions.size();
  const bool colors = raw.colors.size() == n, normals = raw.normals.size() == n;
  om.reserve(n, 3 * raw.faceCount(), raw.faceCount());
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3& p = raw.positions[i];
    const auto vh = om.add_vertex(OmMesh::Point(p.x, p.y, p.z));
    if (colors) om.set_color(vh, OmMesh::Color(raw.colors[i].r, raw.colors[i].g, raw.colors[i].b, 1.0f));
    if (normals) om.set_normal(vh, OmMesh::Normal(raw.normals[i].x, raw.normals[i].y, raw.normals[i].z));
  }
  std::vector<OmMesh::VertexHandle> face;
  for (std::size_t f = 0; f < raw.faceCount(); ++f) {
    face.clear();
    bool valid = raw.faceStart[f + 1] - raw.faceStart[f] >= 3;
    if (!valid) refuse(f, "has " + std::to_string(raw.faceStart[f + 1] - raw.faceStart[f]) + " corners, fewer than 3");
    for (std::size_t k = raw.faceStart[f]; valid && k < raw.faceStart[f + 1]; ++k) {
      const std::int64_t v = raw.corners[k];
      valid = v >= 0 && static_cast<std::uint64_t>(v) < n;
      if (valid) face.emplace_back(static_cast<int>(v));
      if (!valid) {
        refuse(f, v < 0 ? "refers to a vertex the file does not have (it has " + std::to_string(n) + ")"
                        : "refers to vertex " + std::to_string(v + raw.indexBase) + ", but the file has " +
                              std::to_string(n));
      }
    }
    if (!valid) continue;
    std::vector<OmMesh::VertexHandle> sorted = face;
    std::sort(sorted.begin(), sorted.end());
    if (const auto twice = std::adjacent_find(sorted.begin(), sorted.end()); twice != sorted.end()) {
      refuse(f, "repeats vertex " + std::to_string(twice->idx() + raw.indexBase));
      continue;
    }
    if (om.add_face(face).is_valid()) continue;
    for (auto& v : face) {
      // By value: adding a vertex may move the arrays a reference would point into.
      const OmMesh::Point point = om.point(v);
      const OmMesh::Color color = om.color(v);
      const OmMesh::Normal normal = om.normal(v);
      const OmMesh::VertexHandle copy = om.add_vertex(point);
      if (colors) om.set_color(copy, color);
      if (normals) om.set_normal(copy, normal);
      v = copy;
    }
    const auto fh = om.add_face(face);
    if (fh.is_valid()) om.status(fh).set_fixed_nonmanifold(true);
  }
  return first;
}

// Every face the file declares made it in: the number added, and in `separated` how many of them
// were put on their own vertices.
Result<std::size_t> checkFaces(const fs::path& path, std::size_t declared, const OmMesh& om, std::size_t& separated,
                               const std::optional<Refusal>& refused,
                               const std::function<std::string(std::size_t)>& faceName) {
  const std::size_t added = om.n_faces();
  separated = 0;
  for (const auto fh : om.faces())
    if (om.status(fh).fixed_nonmanifold()) ++separated;
  if (declared == 0 && added == 0) return Error::at(path, "no faces");
  if (added < declared) {
    const std::string start =
        "the file declares " + facesText(declared) + ", only " + std::to_string(added) + " could be added";
    if (!refused) return Error::at(path, start + " (the others are not in the file)");
    return Error::at(path, start + ": " + faceName(refused->face) + " " + refused->why);
  }
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
  // A fan triangle of zero area (three collinear corners, as a polygon with a vertex on an edge has
  // from some apexes).
  const auto flat = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const glm::vec3 &pa = mesh.positions[a], &pb = mesh.positions[b], &pc = mesh.positions[c];
    return glm::length(glm::cross(pb - pa, pc - pa)) == 0.0f;
  };
  for (const auto fh : om.faces()) {
    corners.clear();
    for (const auto vh : om.fv_range(fh)) corners.push_back(std::uint32_t(vh.idx()));
    // Fan triangulation keeps the polygon's winding and lets messages name the file's face; its
    // apex is the first corner from which no triangle is flat (else the first corner, and the mesh
    // check names the face).
    const std::size_t n = corners.size();
    std::size_t apex = 0;
    for (std::size_t s = 0; n > 3 && s < n; ++s) {
      bool ok = true;
      for (std::size_t k = 1; ok && k + 1 < n; ++k)
        ok = !flat(corners[s], corners[(s + k) % n], corners[(s + k + 1) % n]);
      if (ok) {
        apex = s;
        break;
      }
    }
    for (std::size_t k = 1; k + 1 < n; ++k) {
      mesh.triangles.emplace_back(corners[apex], corners[(apex + k) % n], corners[(apex + k + 1) % n]);
      sourceFace.push_back(std::uint32_t(fh.idx()));
    }
  }
  return sourceFace;
}

}  // namespace

Result<TriMesh> loadMesh(const fs::path& path, LoadInfo* info, Normalize normalize) {
  PUFF_TRY_ASSIGN(const Format format, formatOf(path));
  PUFF_TRY(checkReadable(path));
  PUFF_TRY_ASSIGN(const detail::RawMesh raw, detail::readRawMesh(path, format));

  OmMesh om;
  om.request_vertex_colors();
  om.request_vertex_normals();
  om.request_face_status();  // faces put on their own vertices are marked
  const std::optional<Refusal> refused = buildOpenMesh(raw, om);
  // The file's face f, with its line where the format has lines.
  const auto faceName = [&](std::size_t f) {
    const std::size_t line = f < raw.faceLine.size() ? raw.faceLine[f] : 0;
    return "face " + std::to_string(f) + (line > 0 ? " (line " + std::to_string(line) + ")" : std::string());
  };
  std::size_t separated = 0;
  PUFF_TRY_ASSIGN(const std::size_t added, checkFaces(path, raw.declaredFaces, om, separated, refused, faceName));

  TriMesh mesh;
  // The readers give colours and normals only where every vertex has them.
  const bool fileColors = !raw.colors.empty();
  const bool fileNormals = !raw.normals.empty();
  copyVertices(om, fileColors, fileNormals, mesh);
  const std::vector<std::uint32_t> sourceFace = triangulate(om, mesh);

  PUFF_TRY(detail::validateMeshNamed(mesh, path.string(), [&](std::size_t t) { return faceName(sourceFace[t]); }));
  removeUnreferenced(mesh);

  LoadInfo li;
  li.sourceFaces = added;
  li.sourceVertices = om.n_vertices();
  li.separatedFaces = separated;
  li.hadColors = fileColors;
  const double volume = signedVolume(mesh);
  li.volumeFraction = volumeFraction(mesh, volume);
  if (volume < 0.0) {
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
  PUFF_TRY_ASSIGN(const Format format, formatOf(path));
  if (format == Format::Gltf)
    return Error::at(path, "cannot write glTF: Puff reads it, and writes .obj, .off, .ply or .stl");
  const bool writeNormals = normals == SaveNormals::kYes;
  if (writeNormals && format != Format::Ply && format != Format::Obj)
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
  if (format == Format::Obj) {
    written = writeObj(mesh, tmp, writeNormals);
  } else {
    OmSilence silence;
    written = writeWithOpenMesh(mesh, tmp, format, writeNormals);
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
