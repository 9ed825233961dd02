#include <puff/core/atlas.h>

#include <array>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include <puff/core/files.h>
#include <puff/core/limits.h>
#include <puff/support/json_read.h>

namespace puff::core {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json vec3Json(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }

// The sidecar's fields, read with the scene's reader (support/json_read.h): a missing field is
// "/pointer: missing", a wrong one "/pointer: expected ..., got ...".
using namespace jsonread;

const json& member(const json& obj, const char* key, const std::string& where) {
  if (!obj.is_object() || !obj.contains(key)) failText(where + "/" + key, "missing");
  return obj.at(key);
}
int intField(const json& obj, const char* key, const std::string& where) {
  return static_cast<int>(readInteger(member(obj, key, where), where + "/" + key, std::numeric_limits<int>::min(),
                                      std::numeric_limits<int>::max(), "an integer"));
}
std::size_t countField(const json& obj, const char* key, const std::string& where) {
  return static_cast<std::size_t>(readInteger(member(obj, key, where), where + "/" + key, 0,
                                              std::numeric_limits<long long>::max(), "a count (an integer >= 0)"));
}
float floatField(const json& obj, const char* key, const std::string& where) {
  return readFloat(member(obj, key, where), where + "/" + key);
}
std::string stringField(const json& obj, const char* key, const std::string& where) {
  return readString(member(obj, key, where), where + "/" + key);
}
glm::vec3 vec3Field(const json& obj, const char* key, const std::string& where) {
  return readVec3(member(obj, key, where), where + "/" + key);
}

using Rect = std::array<int, 4>;

Rect rectField(const json& obj, const char* key, const std::string& where) {
  const json& v = member(obj, key, where);
  const std::string ptr = where + "/" + key;
  if (!v.is_array() || v.size() != 4) fail(ptr, "[x, y, width, height]", v);
  Rect r;
  for (std::size_t k = 0; k < 4; ++k) {
    r[k] = static_cast<int>(readInteger(v[k], child(ptr, k), std::numeric_limits<int>::min(),
                                        std::numeric_limits<int>::max(), "an integer"));
  }
  return r;
}

std::vector<std::string> stringsField(const json& obj, const char* key, const std::string& where) {
  const json& v = member(obj, key, where);
  const std::string ptr = where + "/" + key;
  if (!v.is_array()) fail(ptr, "an array of file names", v);
  std::vector<std::string> out;
  for (std::size_t k = 0; k < v.size(); ++k) out.push_back(readString(v[k], child(ptr, k)));
  return out;
}

void check(bool ok, const std::string& ptr, const std::string& what) {
  if (!ok) failText(ptr, what);
}

AtlasDesc readLayout(const json& j) {
  AtlasDesc d;
  d.formatVersion = intField(j, "formatVersion", "");
  check(d.formatVersion == kAtlasFormatVersion, "/formatVersion",
        "is " + std::to_string(d.formatVersion) + ", this build reads " + std::to_string(kAtlasFormatVersion));
  d.fileFormat = stringField(j, "fileFormat", "");
  for (auto [field, key] : {std::pair{&d.width, "width"},
                            {&d.height, "height"},
                            {&d.columns, "columns"},
                            {&d.rows, "rows"},
                            {&d.cellSize, "cellSize"},
                            {&d.margin, "margin"},
                            {&d.contentSize, "contentSize"},
                            {&d.supersample, "supersample"}}) {
    *field = intField(j, key, "");
  }
  d.depthScale = floatField(j, "depthScale", "");
  d.flangeTexels = floatField(j, "flangeTexels", "");
  d.distanceRange = floatField(j, "distanceRange", "");
  d.alphaThreshold = floatField(j, "alphaThreshold", "");
  d.mipLevels = intField(j, "mipLevels", "");
  d.variations = intField(j, "variations", "");
  d.views = intField(j, "views", "");
  d.viewGrid = intField(j, "viewGrid", "");
  d.viewLayout = stringField(j, "viewLayout", "");
  return d;
}

void checkLayout(const AtlasDesc& d) {
  check(d.fileFormat == "png" || d.fileFormat == "exr", "/fileFormat", "must be \"png\" or \"exr\"");
  const std::string range = "[1, " + std::to_string(kMaxImageSize) + "]";
  check(d.cellSize > 0 && d.cellSize <= kMaxImageSize, "/cellSize", "must be in " + range);
  check(d.columns > 0 && d.rows > 0 && d.columns <= kMaxImageSize && d.rows <= kMaxImageSize, "/columns",
        "columns and rows must be in " + range);
  check(d.width <= kMaxAtlasSide && d.height <= kMaxAtlasSide, "/width",
        "width and height must be at most " + std::to_string(kMaxAtlasSide) + " texels");
  check(static_cast<long long>(d.width) == static_cast<long long>(d.columns) * d.cellSize &&
            static_cast<long long>(d.height) == static_cast<long long>(d.rows) * d.cellSize,
        "/width", "width and height must be columns and rows times cellSize");
  check(d.margin >= 0 && d.contentSize == d.cellSize - 2 * d.margin && d.contentSize > 0, "/contentSize",
        "must equal cellSize - 2 * margin and be positive");
  check(d.variations > 0 && d.variations <= 65536, "/variations", "must be in [1, 65536]");
  check(d.viewGrid > 0 && d.viewGrid <= 64 && d.views == d.viewGrid * d.viewGrid, "/views",
        "must be viewGrid squared, viewGrid in [1, 64]");
  check(d.viewLayout == "hemioct" || d.viewLayout == "oct", "/viewLayout", "must be \"hemioct\" or \"oct\"");
  // Cells stay apart at every level only if each level halves the cell exactly.
  check(d.mipLevels > 0 && d.mipLevels <= 15 && d.cellSize % (1 << (d.mipLevels - 1)) == 0, "/mipLevels",
        "must be in [1, 15] with cellSize divisible by 2^(mipLevels-1)");
  // Ranges no baker writes outside; values past them (depthScale 0, distanceRange 1e-38 or 1e38,
  // alphaThreshold 7, flangeTexels -50) would draw nothing or NaN, so they are refused.
  check(d.distanceRange >= 1e-3f && d.distanceRange <= 65536.0f, "/distanceRange",
        "must be in [0.001, 65536] texels, got " + std::to_string(d.distanceRange));
  check(d.depthScale > 0.0f && d.depthScale <= 64.0f, "/depthScale",
        "must be in (0, 64] puff diameters, got " + std::to_string(d.depthScale));
  check(d.alphaThreshold > 0.0f && d.alphaThreshold < 1.0f, "/alphaThreshold",
        "must be in (0, 1), got " + std::to_string(d.alphaThreshold));
  check(d.flangeTexels >= 0.0f && d.flangeTexels <= static_cast<float>(d.cellSize), "/flangeTexels",
        "must be in [0, cellSize] texels, got " + std::to_string(d.flangeTexels));
  check(d.supersample >= 1 && d.supersample <= 64, "/supersample", "must be in [1, 64]");
}

// A unit vector within 1e-3 (the baker writes them normalized in float).
bool unit(const glm::vec3& v) { return std::abs(glm::length(v) - 1.0f) <= 1e-3f; }

void readCells(const json& j, AtlasDesc& d) {
  check(j.contains("cells") && j["cells"].is_array(), "/cells", "missing or not an array");
  const json& cells = j["cells"];
  check(cells.size() == static_cast<std::size_t>(d.variations * d.views), "/cells",
        "must hold variations * views entries");
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::string where = "/cells/" + std::to_string(i);
    AtlasCell c;
    c.variation = intField(cells[i], "variation", where);
    c.view = intField(cells[i], "view", where);
    c.rect = rectField(cells[i], "rect", where);
    c.viewDir = vec3Field(cells[i], "viewDir", where);
    c.viewUp = vec3Field(cells[i], "viewUp", where);
    check(c.variation >= 0 && c.variation < d.variations, where + "/variation", "must be in [0, variations)");
    check(c.view >= 0 && c.view < d.views, where + "/view", "must be in [0, views)");
    check(c.variation * d.views + c.view == static_cast<int>(i), where, "cells must be variation-major");
    check(unit(c.viewDir), where + "/viewDir", "must be a unit vector");
    check(unit(c.viewUp) && std::abs(glm::dot(c.viewDir, c.viewUp)) <= 1e-3f, where + "/viewUp",
          "must be a unit vector perpendicular to viewDir");
    const auto& r = c.rect;
    check(r[0] >= 0 && r[1] >= 0 && r[2] == d.cellSize && r[3] == d.cellSize && r[0] + r[2] <= d.width &&
              r[1] + r[3] <= d.height,
          where + "/rect", "lies outside the atlas or is not cellSize square");
    d.cells.push_back(c);
  }
}

void readSources(const json& j, AtlasDesc& d) {
  check(
      j.contains("sources") && j["sources"].is_array() && j["sources"].size() == static_cast<std::size_t>(d.variations),
      "/sources", "must hold one entry per variation");
  for (std::size_t i = 0; i < j["sources"].size(); ++i) {
    const json& s = j["sources"][i];
    const std::string where = "/sources/" + std::to_string(i);
    AtlasSource src;
    if (s.contains("path")) {
      src.path = stringField(s, "path", where);
      src.hash = stringField(s, "hash", where);
    } else {
      src.generator = stringField(s, "generator", where);
      src.params = s.value("params", json::object());
    }
    src.faces = countField(s, "faces", where);
    src.facesBaked = countField(s, "facesBaked", where);
    if (s.contains("defaultColor")) {
      const glm::vec3 c = vec3Field(s, "defaultColor", where);
      for (int k = 0; k < 3; ++k) {
        check(c[k] >= 0.0f && c[k] <= 1.0f, where + "/defaultColor", "components must be in [0, 1]");
      }
      src.defaultColor = c;
    }
    if (s.contains("lodMesh")) {
      src.lodMesh = stringField(s, "lodMesh", where);
      check(!src.lodMesh.empty(), where + "/lodMesh", "must name a mesh file");
    }
    d.sources.push_back(src);
  }
}

void readMaps(const json& j, AtlasDesc& d) {
  check(j.contains("maps") && j["maps"].is_object(), "/maps", "missing or not an object");
  for (const char* name : {"normalDepth", "color", "distance"}) {
    const std::string where = std::string("/maps/") + name;
    check(j["maps"].contains(name), where, "missing");
    AtlasMap m;
    m.levels = stringsField(j["maps"][name], "levels", where);
    check(m.levels.size() == static_cast<std::size_t>(d.mipLevels), where + "/levels", "must list mipLevels files");
    d.maps[name] = m;
  }
  // Optional: puffbake writes it for multi-view atlases; one-view atlases, and atlases without it, load.
  if (j["maps"].contains("back")) {
    AtlasMap m;
    m.levels = stringsField(j["maps"]["back"], "levels", "/maps/back");
    check(m.levels.size() == static_cast<std::size_t>(d.mipLevels), "/maps/back/levels", "must list mipLevels files");
    d.maps["back"] = m;
  }
}

}  // namespace

json toJson(const AtlasDesc& d) {
  json j;
  j["formatVersion"] = d.formatVersion;
  j["fileFormat"] = d.fileFormat;
  j["width"] = d.width;
  j["height"] = d.height;
  j["columns"] = d.columns;
  j["rows"] = d.rows;
  j["cellSize"] = d.cellSize;
  j["margin"] = d.margin;
  j["contentSize"] = d.contentSize;
  j["supersample"] = d.supersample;
  j["depthScale"] = d.depthScale;
  j["flangeTexels"] = d.flangeTexels;
  j["distanceRange"] = d.distanceRange;
  j["alphaThreshold"] = d.alphaThreshold;
  j["mipLevels"] = d.mipLevels;
  j["variations"] = d.variations;
  j["views"] = d.views;
  j["viewGrid"] = d.viewGrid;
  j["viewLayout"] = d.viewLayout;
  j["encoding"] = {
      {"normalDepth",
       "rgba = ((N+1)/2, d+0.5); N camera-space unit normal, d offset toward the viewer in puff diameters"},
      {"color", "rgb = diffuse colour (sRGB), a = coverage dilated by the flange (straight alpha)"},
      {"distance", "signed distance to the silhouette in level-0 texels, outside positive: (v-0.5)*2*distanceRange"}};
  if (d.maps.count("back")) {
    j["encoding"]["back"] =
        "v = b+0.5; b the offset toward the viewer (puff diameters) of the farthest point where the texel's rays "
        "cross the puff, else 0 (no bound)";
  }
  json maps = json::object();
  for (const auto& [name, m] : d.maps) maps[name] = {{"levels", m.levels}};
  j["maps"] = maps;
  json cells = json::array();
  for (const auto& c : d.cells) {
    cells.push_back({{"variation", c.variation},
                     {"view", c.view},
                     {"rect", c.rect},
                     {"viewDir", vec3Json(c.viewDir)},
                     {"viewUp", vec3Json(c.viewUp)}});
  }
  j["cells"] = cells;
  json sources = json::array();
  for (const auto& s : d.sources) {
    json o;
    if (!s.path.empty()) {
      o["path"] = s.path;
      o["hash"] = s.hash;
    } else {
      o["generator"] = s.generator;
      o["params"] = s.params;
    }
    o["faces"] = s.faces;
    o["facesBaked"] = s.facesBaked;
    o["defaultColor"] = vec3Json(s.defaultColor);
    if (!s.lodMesh.empty()) o["lodMesh"] = s.lodMesh;
    sources.push_back(o);
  }
  j["sources"] = sources;
  return j;
}

Result<AtlasDesc> atlasFromJson(const json& j, const fs::path& file) {
  return jsonread::catchFailure(file, [&] {
    if (!j.is_object()) jsonread::failText("/", "not a JSON object");
    AtlasDesc d = readLayout(j);
    checkLayout(d);
    readCells(j, d);
    readSources(j, d);
    readMaps(j, d);
    return d;
  });
}

Result<AtlasDesc> loadAtlasDesc(const fs::path& sidecar) {
  // Parsed as a scene is: one error with the line and column, the JSON limits checked first.
  PUFF_TRY_ASSIGN(auto j, jsonread::loadJsonFile(sidecar));
  return atlasFromJson(j, sidecar);
}

Result<fs::path> lodMeshFile(const AtlasDesc& desc, std::size_t i, const fs::path& sidecar) {
  PUFF_CHECK(i < desc.sources.size() && !desc.sources[i].lodMesh.empty());
  const fs::path file = lodMeshPath(desc.sources[i], sidecar);
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {
    return Error::at(sidecar, "/sources/" + std::to_string(i) + "/lodMesh: " + file.string() +
                                  " does not exist (the level of detail the atlas was baked from; re-bake it)");
  }
  return file;
}

fs::path lodMeshPath(const AtlasSource& source, const fs::path& sidecar) {
  if (source.lodMesh.empty()) return {};
  const fs::path file = source.lodMesh;
  return file.is_relative() ? sidecar.parent_path() / file : file;
}

Result<Atlas> loadAtlas(const fs::path& sidecar) {
  PUFF_TRY_ASSIGN(auto desc, loadAtlasDesc(sidecar));
  Atlas atlas;
  atlas.desc = desc;
  for (const auto& [name, m] : desc.maps) {
    auto& levels = atlas.maps[name];
    for (std::size_t level = 0; level < m.levels.size(); ++level) {
      const fs::path file = sidecar.parent_path() / m.levels[level];
      const int w = std::max(1, desc.width >> level), h = std::max(1, desc.height >> level);
      // The level's own size is the limit: a file that claims more is refused before decoding.
      const ImageLimits limits{"this atlas level (the sidecar's size)", w, h, 4, 1ll << 28, kMaxAtlasMapFileBytes};
      auto img = readImage(file, nullptr, limits);
      if (!img && imageCodec() == nullptr && !isCookedImagePath(file)) {
        // Cooking the map alone would not help: the sidecar names the map's file.
        return Error::at(sidecar, "its maps are not cooked images (" + m.levels[level] +
                                      "), and this program reads no other format: cook the atlas with `puffbake "
                                      "cook " +
                                      sidecar.string() +
                                      " -o OUT.json` and load OUT.json, or link "
                                      "puff::io and call puff::io::useOpenImageIO() first");
      }
      if (!img) return img.error();
      if (img->width != w || img->height != h) {
        return Error::at(file, "is " + std::to_string(img->width) + "x" + std::to_string(img->height) +
                                   ", the sidecar says " + std::to_string(w) + "x" + std::to_string(h));
      }
      // Each map's own channels: a level that names another map's file is refused here.
      const int channels = name == "distance" || name == "back" ? 1 : 4;
      if (img->channels != channels) {
        return Error::at(file, "has " + std::to_string(img->channels) + " channel(s), but the " + name + " map has " +
                                   std::to_string(channels) + " (does the sidecar name the right file?)");
      }
      for (std::size_t k = 0; k < img->pixels.size(); ++k) {
        if (!std::isfinite(img->pixels[k])) {
          const std::size_t texel = k / static_cast<std::size_t>(channels);
          return Error::at(file, "texel (" + std::to_string(texel % static_cast<std::size_t>(w)) + ", " +
                                     std::to_string(texel / static_cast<std::size_t>(w)) + ") is not finite");
        }
      }
      levels.push_back(std::move(*img));
    }
  }
  return atlas;
}

int deepestAtlasLevel(const AtlasDesc& desc) {
  int level = 0;
  while (level + 1 < desc.mipLevels && desc.cellSize % (2 << level) == 0 && desc.margin % (2 << level) == 0) ++level;
  return level;
}

Result<Atlas> atlasFromLevel(const Atlas& atlas, int level) {
  const AtlasDesc& d = atlas.desc;
  const int deepest = deepestAtlasLevel(d);
  if (level < 0 || level > deepest) {
    return Error{"atlas level " + std::to_string(level) + " is not in [0, " + std::to_string(deepest) +
                 "] (this atlas has " + std::to_string(d.mipLevels) + " mip levels of " + std::to_string(d.cellSize) +
                 "-texel cells with " + std::to_string(d.margin) + "-texel margins)"};
  }
  if (level == 0) return atlas;
  const int k = 1 << level;
  Atlas out;
  AtlasDesc& n = out.desc;
  n = d;
  n.width = std::max(1, d.width >> level);
  n.height = std::max(1, d.height >> level);
  n.cellSize = d.cellSize / k;
  n.margin = d.margin / k;
  n.contentSize = n.cellSize - 2 * n.margin;
  n.flangeTexels = d.flangeTexels / static_cast<float>(k);
  n.distanceRange = d.distanceRange / static_cast<float>(k);
  n.mipLevels = d.mipLevels - level;
  for (AtlasCell& c : n.cells) {
    for (int& v : c.rect) v /= k;
  }
  for (auto& [name, m] : n.maps) m.levels.erase(m.levels.begin(), m.levels.begin() + level);
  for (const auto& [name, levels] : atlas.maps) {
    if (levels.size() != static_cast<std::size_t>(d.mipLevels)) {
      return Error{"atlas map \"" + name + "\" holds " + std::to_string(levels.size()) + " levels, the sidecar says " +
                   std::to_string(d.mipLevels)};
    }
    out.maps[name].assign(levels.begin() + level, levels.end());
  }
  return out;
}

std::size_t atlasTextureBytes(const AtlasDesc& d) {
  // The packed normal/depth/distance texture (RGBA8) and the colour texture (SRGB8_ALPHA8, or
  // RGBA16F for an exr atlas, whose colours are decoded to linear half floats on upload).
  const std::size_t texelBytes = 4 + (d.fileFormat == "exr" ? 8 : 4);
  std::size_t bytes = 0;
  for (int level = 0; level < d.mipLevels; ++level) {
    const std::size_t texels = static_cast<std::size_t>(std::max(1, d.width >> level)) *
                               static_cast<std::size_t>(std::max(1, d.height >> level));
    bytes += texels * texelBytes;
  }
  // The tumbling hull's field (R16F) of a multi-view atlas.
  if (d.views > 1) {
    const HullFieldLayout f = hullFieldLayout(d);
    bytes += static_cast<std::size_t>(f.width()) * static_cast<std::size_t>(f.side) *
             static_cast<std::size_t>(f.depth()) * 2;
  }
  return bytes;
}

HullFieldLayout hullFieldLayout(const AtlasDesc& d) {
  constexpr int kMost = 2048;  // GL 4.5's least GL_MAX_3D_TEXTURE_SIZE
  const int variations = std::max(1, d.variations);
  HullFieldLayout f;
  f.side = std::clamp(d.contentSize / 2, 32, 96);
  while (f.side > 1 && (kMost / f.side) * (kMost / f.side) < variations) --f.side;
  f.perColumn = std::min(variations, kMost / f.side);
  f.columns = (variations + f.perColumn - 1) / f.perColumn;
  return f;
}

}  // namespace puff::core
