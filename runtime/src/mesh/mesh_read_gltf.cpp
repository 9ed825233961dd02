// Puff's glTF 2.0 reader: the triangles of the default scene's meshes, each placed by its node's
// world transform, from a .glb or from a .gltf whose buffers are data: URIs or files beside it.
// Only what a puff needs is read (POSITION, NORMAL where every vertex has one, indices); materials,
// UVs, skins and morph targets are left alone. Vertices that the exporter split at UV seams (equal
// position and normal) are one vertex again, so a glTF bakes as the same mesh written as OBJ does.
// Every offset, stride and count is checked against the bytes it reads before anything is read.
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include <puff/core/files.h>
#include <puff/mesh/mesh.h>
#include <puff/support/json_read.h>
#include <puff/support/text.h>

#include "mesh_read_formats.h"

namespace puff::mesh::detail {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// The most triangles a scene may place in all. Every count in the file is checked against its
// bytes, but nodes may place one mesh any number of times: this bounds what that multiplies to
// (about as many as the largest OBJ, PLY or STL loadMesh reads holds).
constexpr std::size_t kMaxGltfTriangles = std::size_t{1} << 24;
constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A, kChunkBin = 0x004E4942;
constexpr int kFloat = 5126, kUnsignedByte = 5121, kUnsignedShort = 5123, kUnsignedInt = 5125;

// A problem, with where it is ("accessor 3: ..."); readGltf turns it into "PATH: not a valid glTF
// file (...)".
struct Problem {
  std::string detail;
};

[[noreturn]] void fail(const std::string& detail) { throw Problem{detail}; }

std::string at(std::string_view what, std::size_t index) { return std::string(what) + " " + std::to_string(index); }

// Member `key` of `obj` as an integer in [lo, hi], or `fallback` when absent.
std::int64_t integer(const json& obj, const char* key, std::int64_t lo, std::int64_t hi, std::int64_t fallback,
                     const std::string& where) {
  const auto it = obj.find(key);
  if (it == obj.end()) {
    if (fallback < lo) fail(where + ": no " + key);
    return fallback;
  }
  if (!it->is_number_integer() || it->get<std::int64_t>() < lo || it->get<std::int64_t>() > hi) {
    fail(where + ": " + key + " is not an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return it->get<std::int64_t>();
}

// Element `index` of the top-level array `name`, an object.
const json& item(const json& root, const char* name, std::int64_t index, const std::string& where) {
  const auto it = root.find(name);
  if (it == root.end() || !it->is_array() || index < 0 || static_cast<std::size_t>(index) >= it->size()) {
    fail(where + " names " + std::string(name) + " " + std::to_string(index) + ", which the file does not have");
  }
  const json& v = (*it)[static_cast<std::size_t>(index)];
  if (!v.is_object()) fail(std::string(name) + " " + std::to_string(index) + " is not an object");
  return v;
}

// The bytes of a base64 text, or nothing when it is not base64.
std::optional<std::string> base64(std::string_view text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  while (!text.empty() && text.back() == '=') text.remove_suffix(1);
  std::string out;
  out.reserve(text.size() / 4 * 3 + 3);
  std::uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    const int v = value(c);
    if (v < 0) return std::nullopt;
    bits = (bits << 6) | static_cast<std::uint32_t>(v);
    if (++count == 4) {
      out.push_back(static_cast<char>(bits >> 16)), out.push_back(static_cast<char>(bits >> 8));
      out.push_back(static_cast<char>(bits)), count = 0, bits = 0;
    }
  }
  if (count == 1) return std::nullopt;
  if (count >= 2) out.push_back(static_cast<char>(bits >> (6 * count - 8)));
  if (count == 3) out.push_back(static_cast<char>(bits >> 2));
  return out;
}

// A relative URI's path (percent-decoded), or nothing when it is not a plain relative path inside
// the glTF's folder (a scheme, an absolute path, "..", a bad escape).
std::optional<fs::path> relativeFile(std::string_view uri) {
  std::string decoded;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] != '%') {
      decoded.push_back(uri[i]);
      continue;
    }
    if (i + 2 >= uri.size() || !std::isxdigit(static_cast<unsigned char>(uri[i + 1])) ||
        !std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      return std::nullopt;
    }
    decoded.push_back(static_cast<char>(std::stoi(std::string(uri.substr(i + 1, 2)), nullptr, 16)));
    i += 2;
  }
  if (decoded.empty() || decoded.find('\0') != std::string::npos || decoded.find(':') != std::string::npos) {
    return std::nullopt;
  }
  const fs::path p(decoded);
  if (p.is_absolute()) return std::nullopt;
  for (const fs::path& part : p) {
    if (part == "..") return std::nullopt;
  }
  return p;
}

// The file's JSON and its buffers, loaded as accessors need them, all within kMaxMeshFileBytes.
class Gltf {
 public:
  Gltf(const fs::path& path, json root, std::optional<std::string_view> bin)
      : path_(path), root_(std::move(root)), bin_(bin) {}
  const json& root() const { return root_; }

  // The bytes accessor `index` reads: `count` elements of `size` bytes, `stride` apart.
  struct Span {
    const char* data;
    std::size_t count, stride;
  };
  Span accessor(std::int64_t index, int componentType, const char* type, std::size_t size, const std::string& where);

 private:
  const std::string& buffer(std::int64_t index, const std::string& where);

  fs::path path_;
  json root_;
  std::optional<std::string_view> bin_;
  std::vector<std::optional<std::string>> buffers_;
  std::uintmax_t loaded_ = 0;
};

const std::string& Gltf::buffer(std::int64_t index, const std::string& where) {
  const json& b = item(root_, "buffers", index, where);
  const std::string name = at("buffer", static_cast<std::size_t>(index));
  if (buffers_.empty()) buffers_.resize(root_["buffers"].size());
  auto& slot = buffers_[static_cast<std::size_t>(index)];
  if (slot) return *slot;
  const auto byteLength = static_cast<std::uint64_t>(integer(b, "byteLength", 1, INT64_MAX, 0, name));
  std::string bytes;
  const auto uri = b.find("uri");
  if (uri == b.end()) {
    if (index != 0 || !bin_) fail(name + " has no uri, and only a .glb's first buffer may (its BIN chunk)");
    bytes = std::string(*bin_);
  } else if (!uri->is_string()) {
    fail(name + ": uri is not a string");
  } else if (const std::string u = uri->get<std::string>(); u.rfind("data:", 0) == 0) {
    const auto comma = u.find(',');
    if (comma == std::string::npos || u.substr(0, comma).find(";base64") == std::string::npos) {
      fail(name + ": a data: uri that is not base64");
    }
    auto decoded = base64(std::string_view(u).substr(comma + 1));
    if (!decoded) fail(name + ": its data: uri is not valid base64");
    bytes = std::move(*decoded);
  } else {
    const auto file = relativeFile(u);
    if (!file) fail(name + ": uri \"" + u.substr(0, 80) + "\" is not a file beside the glTF");
    const fs::path full = path_.parent_path() / *file;
    std::error_code ec;
    const auto size = fs::file_size(full, ec);
    if (ec) fail(name + ": cannot read " + full.string());
    if (size > kMaxMeshFileBytes - loaded_) fail(name + ": " + full.string() + " is more than a mesh may read");
    auto read = core::readFileBytes(full);
    if (!read) fail(name + ": cannot read " + full.string());
    bytes = std::move(*read);
  }
  if (bytes.size() < byteLength) {
    fail(name + " holds " + std::to_string(bytes.size()) + " bytes, its byteLength says " + std::to_string(byteLength));
  }
  loaded_ += bytes.size();
  if (loaded_ > kMaxMeshFileBytes) fail(name + ": the buffers are more than a mesh may read");
  bytes.resize(byteLength);
  slot = std::move(bytes);
  return *slot;
}

Gltf::Span Gltf::accessor(std::int64_t index, int componentType, const char* type, std::size_t size,
                          const std::string& where) {
  const json& a = item(root_, "accessors", index, where);
  const std::string name = at("accessor", static_cast<std::size_t>(index));
  if (a.contains("sparse")) fail(name + " is sparse, which Puff does not read");
  if (!a.contains("bufferView")) fail(name + " has no bufferView (all zeros)");
  const auto ct = integer(a, "componentType", 0, INT32_MAX, -1, name);
  if (ct != componentType)
    fail(name + ": componentType " + std::to_string(ct) + ", expected " + std::to_string(componentType));
  if (!a.contains("type") || a["type"] != type) fail(name + ": type is not " + std::string(type));
  const auto count = static_cast<std::uint64_t>(integer(a, "count", 1, UINT32_MAX, -1, name));
  const auto offset = static_cast<std::uint64_t>(integer(a, "byteOffset", 0, UINT32_MAX, 0, name));
  const std::int64_t viewIndex = integer(a, "bufferView", 0, INT32_MAX, -1, name);
  const json& v = item(root_, "bufferViews", viewIndex, name);
  const std::string viewName = at("bufferView", static_cast<std::size_t>(viewIndex));
  const auto viewOffset = static_cast<std::uint64_t>(integer(v, "byteOffset", 0, INT64_MAX, 0, viewName));
  const auto viewLength = static_cast<std::uint64_t>(integer(v, "byteLength", 1, INT64_MAX, -1, viewName));
  const auto stride = v.contains("byteStride")
                          ? static_cast<std::uint64_t>(integer(v, "byteStride", 4, 252, 0, viewName))
                          : std::uint64_t{size};  // tightly packed
  if (stride < size)
    fail(viewName + ": byteStride " + std::to_string(stride) + " is less than " + name + "'s elements");
  const std::string& data = buffer(integer(v, "buffer", 0, INT32_MAX, -1, viewName), viewName);
  if (viewOffset > data.size() || viewLength > data.size() - viewOffset) fail(viewName + " runs past its buffer");
  if (offset > viewLength || stride * (count - 1) + size > viewLength - offset) {
    fail(name + ": " + std::to_string(count) + " elements run past " + viewName + "'s " + std::to_string(viewLength) +
         " bytes");
  }
  return {data.data() + viewOffset + offset, count, stride};
}

std::vector<glm::vec3> vec3s(Gltf& g, std::int64_t accessor, const std::string& where) {
  const Gltf::Span s = g.accessor(accessor, kFloat, "VEC3", 12, where);
  std::vector<glm::vec3> out(s.count);
  for (std::size_t i = 0; i < s.count; ++i) std::memcpy(&out[i][0], s.data + i * s.stride, 12);
  return out;
}

std::vector<std::uint32_t> indices(Gltf& g, std::int64_t accessor, const std::string& where) {
  const json& a = item(g.root(), "accessors", accessor, where);
  const auto ct = integer(a, "componentType", 0, INT32_MAX, -1, at("accessor", static_cast<std::size_t>(accessor)));
  const std::size_t size = ct == kUnsignedByte ? 1 : ct == kUnsignedShort ? 2 : 4;
  if (ct != kUnsignedByte && ct != kUnsignedShort && ct != kUnsignedInt) {
    fail(at("accessor", static_cast<std::size_t>(accessor)) + ": indices of componentType " + std::to_string(ct) +
         ", expected 5121, 5123 or 5125");
  }
  const Gltf::Span s = g.accessor(accessor, ct, "SCALAR", size, where);
  std::vector<std::uint32_t> out(s.count);
  for (std::size_t i = 0; i < s.count; ++i) {
    std::uint32_t v = 0;
    std::memcpy(&v, s.data + i * s.stride, size);  // little-endian, as glTF is
    out[i] = v;
  }
  return out;
}

// A node's transform: its matrix, or translation * rotation * scale.
glm::mat4 localTransform(const json& node, const std::string& name) {
  auto numbers = [&](const char* key, std::size_t n) -> std::optional<std::vector<float>> {
    const auto it = node.find(key);
    if (it == node.end()) return std::nullopt;
    if (!it->is_array() || it->size() != n) fail(name + ": " + key + " is not " + std::to_string(n) + " numbers");
    std::vector<float> v;
    for (const json& x : *it) {
      if (!x.is_number() || !std::isfinite(x.get<double>())) fail(name + ": " + key + " holds a non-finite value");
      v.push_back(toFloat(x.get<double>()));
    }
    return v;
  };
  if (auto m = numbers("matrix", 16)) {
    if (node.contains("translation") || node.contains("rotation") || node.contains("scale")) {
      fail(name + " has both a matrix and translation, rotation or scale (the specification allows one)");
    }
    return glm::make_mat4(m->data());  // column-major, as glTF's
  }
  glm::mat4 t(1.0f);
  if (auto v = numbers("translation", 3)) t = glm::translate(t, glm::vec3((*v)[0], (*v)[1], (*v)[2]));
  if (auto q = numbers("rotation", 4)) {
    const glm::quat r((*q)[3], (*q)[0], (*q)[1], (*q)[2]);  // glTF: x, y, z, w
    const float length = glm::length(r);
    if (!(length > 0.0f) || !std::isfinite(length)) fail(name + ": rotation is not a quaternion of non-zero length");
    t = t * glm::mat4_cast(r / length);  // unit, as the specification asks and some exporters round away
  }
  if (auto s = numbers("scale", 3)) t = glm::scale(t, glm::vec3((*s)[0], (*s)[1], (*s)[2]));
  return t;
}

// The triangles of one primitive (triangles, strip or fan; points and lines have none) as index
// triples into its vertices, strips' degenerate joins left out.
std::vector<std::uint32_t> triangles(int mode, const std::vector<std::uint32_t>& v, const std::string& name) {
  std::vector<std::uint32_t> out;
  const std::size_t n = v.size();
  if (mode == 4) {
    if (n % 3 != 0) fail(name + ": " + std::to_string(n) + " indices, not a multiple of 3");
    return v;
  }
  for (std::size_t i = 0; i + 2 < n; ++i) {
    std::uint32_t a = 0, b = 0, c = 0;
    if (mode == 5) {
      a = v[i], b = v[i + 1 + i % 2], c = v[i + 2 - i % 2];
      if (a == b || b == c || a == c) continue;
    } else {
      a = v[i + 1], b = v[i + 2], c = v[0];
    }
    out.insert(out.end(), {a, b, c});
  }
  return out;
}

glm::vec3 unitOrAsIs(glm::vec3 n) {
  const float length = glm::length(n);
  return length > 0.0f && std::isfinite(length) ? n / length : n;
}

struct Placed {
  std::int64_t mesh;
  glm::mat4 world;
};

// The meshes the default scene places (scene, else scene 0, else every root node), depth first.
std::vector<Placed> placedMeshes(const json& root) {
  std::vector<std::int64_t> roots;
  const auto nodes = root.find("nodes");
  const std::size_t nodeCount = nodes != root.end() && nodes->is_array() ? nodes->size() : 0;
  if (root.contains("scenes")) {
    const std::int64_t s = integer(root, "scene", 0, INT32_MAX, 0, "the file");
    const json& scene = item(root, "scenes", s, "scene");
    if (scene.contains("nodes") && scene["nodes"].is_array()) {
      for (const json& n : scene["nodes"]) roots.push_back(n.is_number_integer() ? n.get<std::int64_t>() : -1);
    }
  } else {
    std::vector<char> child(nodeCount, 0);
    for (std::size_t i = 0; i < nodeCount; ++i) {
      const json& c = (*nodes)[i].is_object() ? (*nodes)[i].value("children", json::array()) : json::array();
      for (const json& k : c) {
        if (k.is_number_integer() && k.get<std::int64_t>() >= 0 &&
            static_cast<std::size_t>(k.get<std::int64_t>()) < nodeCount)
          child[static_cast<std::size_t>(k.get<std::int64_t>())] = 1;
      }
    }
    for (std::size_t i = 0; i < nodeCount; ++i)
      if (!child[i]) roots.push_back(static_cast<std::int64_t>(i));
  }
  std::vector<Placed> placed;
  std::vector<char> seen(nodeCount, 0);
  std::vector<std::pair<std::int64_t, glm::mat4>> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, glm::mat4(1.0f));
  while (!stack.empty()) {
    const auto [index, parent] = stack.back();
    stack.pop_back();
    const json& node = item(root, "nodes", index, "a scene or node");
    const std::string name = at("node", static_cast<std::size_t>(index));
    if (seen[static_cast<std::size_t>(index)]) fail(name + " is reached twice (glTF's nodes form a tree)");
    seen[static_cast<std::size_t>(index)] = 1;
    const glm::mat4 world = parent * localTransform(node, name);
    if (node.contains("mesh")) placed.push_back({integer(node, "mesh", 0, INT32_MAX, -1, name), world});
    if (const auto c = node.find("children"); c != node.end()) {
      if (!c->is_array()) fail(name + ": children is not an array");
      for (auto k = c->rbegin(); k != c->rend(); ++k) {
        stack.emplace_back(k->is_number_integer() ? k->get<std::int64_t>() : -1, world);
      }
    }
  }
  return placed;
}

// Adds the placed mesh's triangle primitives to `m`.
void addMesh(Gltf& g, const Placed& p, bool normals, VertexMerger& merge, RawMesh& m, std::size_t& verticesRead) {
  const std::string meshName = at("mesh", static_cast<std::size_t>(p.mesh));
  const json& mesh = item(g.root(), "meshes", p.mesh, "a node");
  if (!mesh.contains("primitives") || !mesh["primitives"].is_array()) fail(meshName + " has no primitives");
  const bool identity = p.world == glm::mat4(1.0f);
  const float determinant = glm::determinant(glm::mat3(p.world));
  // Scaled to nothing (an exporter's way of hiding a node): it places no surface.
  if (determinant == 0.0f) return;
  const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(p.world)));
  const bool mirrored = determinant < 0.0f;
  for (std::size_t k = 0; k < mesh["primitives"].size(); ++k) {
    const json& prim = mesh["primitives"][k];
    const std::string name = meshName + " primitive " + std::to_string(k);
    if (!prim.is_object() || !prim.contains("attributes") || !prim["attributes"].is_object()) {
      fail(name + " has no attributes");
    }
    const int mode = static_cast<int>(integer(prim, "mode", 0, 6, 4, name));
    if (mode < 4) continue;  // points and lines: no surface
    const json& attributes = prim["attributes"];
    const std::int64_t positionAccessor = integer(attributes, "POSITION", 0, INT32_MAX, -1, name);
    verticesRead +=
        static_cast<std::size_t>(integer(item(g.root(), "accessors", positionAccessor, name), "count", 1, UINT32_MAX,
                                         -1, at("accessor", static_cast<std::size_t>(positionAccessor))));
    if (verticesRead > 3 * kMaxGltfTriangles) {
      fail(name + ": the scene's nodes read more than " + std::to_string(3 * kMaxGltfTriangles) +
           " vertices in all (they may place one mesh many times), more than Puff reads");
    }
    std::vector<glm::vec3> positions = vec3s(g, positionAccessor, name);
    std::vector<glm::vec3> vertexNormals;
    if (normals) vertexNormals = vec3s(g, integer(attributes, "NORMAL", 0, INT32_MAX, -1, name), name);
    if (normals && vertexNormals.size() != positions.size()) fail(name + ": NORMAL and POSITION counts differ");
    std::vector<std::uint32_t> order;
    if (prim.contains("indices")) {
      order = indices(g, integer(prim, "indices", 0, INT32_MAX, -1, name), name);
    } else {
      order.resize(positions.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
    }
    std::vector<std::int64_t> vertex(positions.size(), -1);
    const std::vector<std::uint32_t> tris = triangles(mode, order, name);
    if (tris.size() / 3 > kMaxGltfTriangles - m.faceCount()) {
      fail(name + ": the scene places more than " + std::to_string(kMaxGltfTriangles) +
           " triangles (its nodes may place one mesh many times), more than Puff reads");
    }
    for (std::size_t t = 0; t < tris.size(); t += 3) {
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t i = tris[t + static_cast<std::size_t>(mirrored ? (3 - c) % 3 : c)];
        if (i >= positions.size()) {
          fail(name + ": index " + std::to_string(i) + " names a vertex past its " + std::to_string(positions.size()));
        }
        if (vertex[i] < 0) {
          const glm::vec3 pos = identity ? positions[i] : glm::vec3(p.world * glm::vec4(positions[i], 1.0f));
          std::optional<glm::vec3> n;
          if (normals) n = identity ? vertexNormals[i] : unitOrAsIs(normalMatrix * vertexNormals[i]);
          vertex[i] = merge.add(pos, n);
        }
        m.addCorner(vertex[i]);
      }
      m.endFace();
      ++m.declaredFaces;
    }
  }
}

// Whether every triangle primitive the scene places has a NORMAL.
bool allHaveNormals(const json& root, const std::vector<Placed>& placed) {
  for (const Placed& p : placed) {
    const json& mesh = item(root, "meshes", p.mesh, "a node");
    if (!mesh.contains("primitives") || !mesh["primitives"].is_array()) return false;
    for (const json& prim : mesh["primitives"]) {
      if (!prim.is_object()) return false;
      if (const auto mode = prim.find("mode"); mode != prim.end() && mode->is_number_integer() && *mode < 4) continue;
      if (!prim.contains("attributes") || !prim["attributes"].is_object() || !prim["attributes"].contains("NORMAL"))
        return false;
    }
  }
  return true;
}

// Whether a required extension leaves the triangles as the core format gives them (materials,
// textures, lights); compression and quantization do not.
bool geometryUnchanged(const std::string& extension) {
  for (const char* prefix : {"KHR_materials_", "KHR_texture_", "KHR_lights_", "EXT_texture_"}) {
    if (extension.rfind(prefix, 0) == 0) return true;
  }
  return false;
}

// A .glb's JSON chunk and its BIN chunk, if any.
std::pair<std::string_view, std::optional<std::string_view>> glbChunks(std::string_view text) {
  auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, text.data() + at, 4);
    return v;
  };
  if (text.size() < 20) fail("shorter than a GLB header");
  if (u32(4) != 2) fail("GLB version " + std::to_string(u32(4)) + ", expected 2");
  if (u32(8) != text.size())
    fail("the GLB header says " + std::to_string(u32(8)) + " bytes, the file has " + std::to_string(text.size()));
  const std::uint64_t jsonLength = u32(12);
  if (u32(16) != kChunkJson || jsonLength > text.size() - 20) fail("the first GLB chunk is not JSON within the file");
  const std::string_view jsonChunk = text.substr(20, jsonLength);
  const std::size_t next = 20 + jsonLength;
  if (text.size() - next < 8) return {jsonChunk, std::nullopt};
  const std::uint64_t binLength = u32(next);
  if (u32(next + 4) != kChunkBin || binLength > text.size() - next - 8)
    fail("the second GLB chunk is not BIN within the file");
  return {jsonChunk, text.substr(next + 8, binLength)};
}

}  // namespace

Result<RawMesh> readGltf(const fs::path& path, std::string_view text) {
  try {
    std::string_view jsonText = text;
    std::optional<std::string_view> bin;
    const bool glb = text.size() >= 4 && std::memcmp(text.data(), &kGlbMagic, 4) == 0;
    if (!glb && core::lower(path.extension().string()) == ".glb") fail("a .glb that does not start with \"glTF\"");
    if (glb) std::tie(jsonText, bin) = glbChunks(text);
    PUFF_TRY_ASSIGN(json root, core::jsonread::parseJson(std::string(jsonText), path));
    if (!root.is_object()) fail("the JSON is not an object");
    const json asset = root.value("asset", json());
    if (!asset.is_object() || !asset.contains("version") || !asset["version"].is_string() ||
        asset["version"].get<std::string>().rfind("2.", 0) != 0) {
      fail("asset.version is not 2.x");
    }
    if (const auto req = root.find("extensionsRequired"); req != root.end() && req->is_array()) {
      for (const json& e : *req) {
        if (!e.is_string() || !geometryUnchanged(e.get<std::string>())) {
          fail("it needs the extension " + e.dump() + ", which Puff does not read (export without it)");
        }
      }
    }
    Gltf g(path, std::move(root), bin);
    const std::vector<Placed> placed = placedMeshes(g.root());
    if (placed.empty()) fail("its scene places no mesh");
    const bool normals = allHaveNormals(g.root(), placed);
    RawMesh m;
    VertexMerger merge(m);
    std::size_t verticesRead = 0;
    for (const Placed& p : placed) addMesh(g, p, normals, merge, m, verticesRead);
    return m;
  } catch (const Problem& p) {
    return notValid(path, Format::Gltf, p.detail);
  } catch (const json::exception& e) {
    return notValid(path, Format::Gltf, e.what());
  }
}

}  // namespace puff::mesh::detail
