// glTF 2.0 files for the tests, written from the specification's layout: a JSON document whose
// accessors read a binary buffer, saved as a .glb (header, JSON chunk, BIN chunk), a .gltf with a
// .bin beside it, or a .gltf with the buffer in a base64 data: URI. Each piece is an ordinary
// nlohmann::json the test may edit to break it.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

namespace puff::test {

class GltfWriter {
 public:
  GltfWriter() {
    doc_ = {{"asset", {{"version", "2.0"}, {"generator", "Puff tests"}}},
            {"scene", 0},
            {"scenes", {{{"nodes", nlohmann::json::array()}}}},
            {"nodes", nlohmann::json::array()},
            {"meshes", nlohmann::json::array()},
            {"accessors", nlohmann::json::array()},
            {"bufferViews", nlohmann::json::array()},
            {"buffers", nlohmann::json::array({{{"byteLength", 0}}})}};
  }
  nlohmann::json& doc() { return doc_; }
  const nlohmann::json& doc() const { return doc_; }
  std::string& bin() { return bin_; }

  /// An accessor over new bytes in the buffer (a bufferView of its own, 4-byte aligned).
  int accessor(const void* data, std::size_t bytes, int componentType, const char* type, std::size_t count) {
    while (bin_.size() % 4) bin_.push_back('\0');
    const std::size_t offset = bin_.size();
    bin_.append(static_cast<const char*>(data), bytes);
    doc_["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    doc_["accessors"].push_back({{"bufferView", doc_["bufferViews"].size() - 1},
                                 {"componentType", componentType},
                                 {"type", type},
                                 {"count", count}});
    doc_["buffers"][0]["byteLength"] = bin_.size();
    return static_cast<int>(doc_["accessors"].size() - 1);
  }
  int vec3s(const std::vector<glm::vec3>& v) { return accessor(v.data(), v.size() * 12, 5126, "VEC3", v.size()); }
  int vec2s(const std::vector<glm::vec2>& v) { return accessor(v.data(), v.size() * 8, 5126, "VEC2", v.size()); }
  int indices8(const std::vector<std::uint8_t>& v) { return accessor(v.data(), v.size(), 5121, "SCALAR", v.size()); }
  int indices16(const std::vector<std::uint16_t>& v) {
    return accessor(v.data(), v.size() * 2, 5123, "SCALAR", v.size());
  }
  int indices32(const std::vector<std::uint32_t>& v) {
    return accessor(v.data(), v.size() * 4, 5125, "SCALAR", v.size());
  }

  /// A mesh of one primitive; returns its index.
  int mesh(const nlohmann::json& primitive) {
    doc_["meshes"].push_back({{"primitives", {primitive}}});
    return static_cast<int>(doc_["meshes"].size() - 1);
  }
  /// A node (its "mesh", "children", transform as given); `root`: listed in the scene.
  int node(const nlohmann::json& node, bool root = true) {
    doc_["nodes"].push_back(node);
    const int index = static_cast<int>(doc_["nodes"].size() - 1);
    if (root) doc_["scenes"][0]["nodes"].push_back(index);
    return index;
  }

  void writeGlb(const std::filesystem::path& path) const {
    std::string json = doc_.dump();
    while (json.size() % 4) json.push_back(' ');
    std::string bin = bin_;
    while (bin.size() % 4) bin.push_back('\0');
    std::string out;
    auto u32 = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(0x46546C67), u32(2), u32(static_cast<std::uint32_t>(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size())));
    u32(static_cast<std::uint32_t>(json.size())), u32(0x4E4F534A), out += json;
    if (!bin.empty()) u32(static_cast<std::uint32_t>(bin.size())), u32(0x004E4942), out += bin;
    write(path, out);
  }
  /// A .gltf with the buffer in `binName` beside it.
  void writeGltf(const std::filesystem::path& path, const std::string& binName) const {
    nlohmann::json doc = doc_;
    doc["buffers"][0]["uri"] = binName;
    write(path, doc.dump(2));
    write(path.parent_path() / binName, bin_);
  }
  /// A .gltf with the buffer as a base64 data: URI.
  void writeGltfEmbedded(const std::filesystem::path& path) const {
    nlohmann::json doc = doc_;
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin_);
    write(path, doc.dump(2));
  }

  static std::string base64(const std::string& bytes) {
    static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
      std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16;
      if (i + 1 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
      if (i + 2 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 2]);
      out += kAlphabet[(v >> 18) & 63];
      out += kAlphabet[(v >> 12) & 63];
      out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
      out += i + 2 < bytes.size() ? kAlphabet[v & 63] : '=';
    }
    return out;
  }

 private:
  static void write(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
  }
  nlohmann::json doc_;
  std::string bin_;
};

}  // namespace puff::test
