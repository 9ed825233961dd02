#include <puff/core/atlas.h>

#include <puff/core/files.h>

namespace puff::core {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json vec3Json(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }

// Reads typed fields with errors that carry the JSON pointer of the field.
class Reader {
 public:
  Reader(const fs::path& file) : file_(file) {}

  template <class T>
  Result<T> get(const json& obj, const std::string& key, const std::string& where) const {
    const std::string ptr = where + "/" + key;
    if (!obj.is_object() || !obj.contains(key)) return fail(ptr, "missing");
    try {
      return obj.at(key).get<T>();
    } catch (const json::exception&) {
      return fail(ptr, "has the wrong type");
    }
  }
  Error fail(const std::string& ptr, const std::string& what) const {
    return Error::at(file_, (ptr.empty() ? "/" : ptr) + ": " + what);
  }

 private:
  fs::path file_;
};

#define PUFF_READ(var, T, obj, key, where)             \
  do {                                                 \
    auto readResult_ = reader.get<T>(obj, key, where); \
    if (!readResult_) return readResult_.error();      \
    var = *readResult_;                                \
  } while (0)

using Rect = std::array<int, 4>;

Result<glm::vec3> readVec3(const Reader& reader, const json& obj, const std::string& key, const std::string& where) {
  auto arr = reader.get<std::vector<float>>(obj, key, where);
  if (!arr) return arr.error();
  if (arr->size() != 3) return reader.fail(where + "/" + key, "must have 3 numbers");
  return glm::vec3((*arr)[0], (*arr)[1], (*arr)[2]);
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
    sources.push_back(o);
  }
  j["sources"] = sources;
  return j;
}

Result<AtlasDesc> atlasFromJson(const json& j, const fs::path& file) {
  Reader reader(file);
  if (!j.is_object()) return reader.fail("", "not a JSON object");
  AtlasDesc d;
  PUFF_READ(d.formatVersion, int, j, "formatVersion", "");
  if (d.formatVersion != kAtlasFormatVersion) {
    return reader.fail("/formatVersion", "is " + std::to_string(d.formatVersion) + ", this build reads " +
                                             std::to_string(kAtlasFormatVersion));
  }
  PUFF_READ(d.fileFormat, std::string, j, "fileFormat", "");
  PUFF_READ(d.width, int, j, "width", "");
  PUFF_READ(d.height, int, j, "height", "");
  PUFF_READ(d.columns, int, j, "columns", "");
  PUFF_READ(d.rows, int, j, "rows", "");
  PUFF_READ(d.cellSize, int, j, "cellSize", "");
  PUFF_READ(d.margin, int, j, "margin", "");
  PUFF_READ(d.contentSize, int, j, "contentSize", "");
  PUFF_READ(d.supersample, int, j, "supersample", "");
  PUFF_READ(d.depthScale, float, j, "depthScale", "");
  PUFF_READ(d.flangeTexels, float, j, "flangeTexels", "");
  PUFF_READ(d.distanceRange, float, j, "distanceRange", "");
  PUFF_READ(d.alphaThreshold, float, j, "alphaThreshold", "");
  PUFF_READ(d.mipLevels, int, j, "mipLevels", "");
  PUFF_READ(d.variations, int, j, "variations", "");
  PUFF_READ(d.views, int, j, "views", "");
  PUFF_READ(d.viewGrid, int, j, "viewGrid", "");
  PUFF_READ(d.viewLayout, std::string, j, "viewLayout", "");

  if (d.fileFormat != "png" && d.fileFormat != "exr") return reader.fail("/fileFormat", "must be \"png\" or \"exr\"");
  if (d.cellSize <= 0 || d.cellSize > 16384) return reader.fail("/cellSize", "must be in [1, 16384]");
  if (d.columns <= 0 || d.rows <= 0 || d.columns > 16384 || d.rows > 16384) {
    return reader.fail("/columns", "columns and rows must be in [1, 16384]");
  }
  if (static_cast<long long>(d.width) != static_cast<long long>(d.columns) * d.cellSize ||
      static_cast<long long>(d.height) != static_cast<long long>(d.rows) * d.cellSize) {
    return reader.fail("/width", "width and height must be columns and rows times cellSize");
  }
  if (d.margin < 0 || d.contentSize != d.cellSize - 2 * d.margin || d.contentSize <= 0) {
    return reader.fail("/contentSize", "must equal cellSize - 2 * margin and be positive");
  }
  if (d.variations <= 0 || d.variations > 65536) return reader.fail("/variations", "must be in [1, 65536]");
  if (d.viewGrid <= 0 || d.viewGrid > 64 || d.views != d.viewGrid * d.viewGrid) {
    return reader.fail("/views", "must be viewGrid squared, viewGrid in [1, 64]");
  }
  if (d.viewLayout != "hemioct" && d.viewLayout != "oct")
    return reader.fail("/viewLayout", "must be \"hemioct\" or \"oct\"");
  // Cells stay apart at every level only if each level halves the cell exactly.
  if (d.mipLevels <= 0 || d.mipLevels > 15 || d.cellSize % (1 << (d.mipLevels - 1)) != 0) {
    return reader.fail("/mipLevels", "must be in [1, 15] with cellSize divisible by 2^(mipLevels-1)");
  }
  if (!(d.distanceRange > 0)) return reader.fail("/distanceRange", "must be positive");

  if (!j.contains("cells") || !j["cells"].is_array()) return reader.fail("/cells", "missing or not an array");
  const json& cells = j["cells"];
  if (cells.size() != static_cast<std::size_t>(d.variations * d.views)) {
    return reader.fail("/cells", "must hold variations * views entries");
  }
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::string where = "/cells/" + std::to_string(i);
    AtlasCell c;
    PUFF_READ(c.variation, int, cells[i], "variation", where);
    PUFF_READ(c.view, int, cells[i], "view", where);
    PUFF_READ(c.rect, Rect, cells[i], "rect", where);
    auto dir = readVec3(reader, cells[i], "viewDir", where);
    if (!dir) return dir.error();
    auto up = readVec3(reader, cells[i], "viewUp", where);
    if (!up) return up.error();
    c.viewDir = *dir;
    c.viewUp = *up;
    if (c.variation * d.views + c.view != static_cast<int>(i))
      return reader.fail(where, "cells must be variation-major");
    const auto& r = c.rect;
    if (r[0] < 0 || r[1] < 0 || r[2] != d.cellSize || r[3] != d.cellSize || r[0] + r[2] > d.width ||
        r[1] + r[3] > d.height) {
      return reader.fail(where + "/rect", "lies outside the atlas or is not cellSize square");
    }
    d.cells.push_back(c);
  }
  if (!j.contains("sources") || !j["sources"].is_array() ||
      j["sources"].size() != static_cast<std::size_t>(d.variations)) {
    return reader.fail("/sources", "must hold one entry per variation");
  }
  for (std::size_t i = 0; i < j["sources"].size(); ++i) {
    const json& s = j["sources"][i];
    const std::string where = "/sources/" + std::to_string(i);
    AtlasSource src;
    if (s.contains("path")) {
      PUFF_READ(src.path, std::string, s, "path", where);
      PUFF_READ(src.hash, std::string, s, "hash", where);
    } else {
      PUFF_READ(src.generator, std::string, s, "generator", where);
      src.params = s.value("params", json::object());
    }
    PUFF_READ(src.faces, std::size_t, s, "faces", where);
    PUFF_READ(src.facesBaked, std::size_t, s, "facesBaked", where);
    if (s.contains("defaultColor")) {
      auto c = readVec3(reader, s, "defaultColor", where);
      if (!c) return c.error();
      for (int k = 0; k < 3; ++k) {
        if (!((*c)[k] >= 0.0f && (*c)[k] <= 1.0f))
          return reader.fail(where + "/defaultColor", "components must be in [0, 1]");
      }
      src.defaultColor = *c;
    }
    d.sources.push_back(src);
  }
  if (!j.contains("maps") || !j["maps"].is_object()) return reader.fail("/maps", "missing or not an object");
  for (const char* name : {"normalDepth", "color", "distance"}) {
    const std::string where = std::string("/maps/") + name;
    AtlasMap m;
    if (!j["maps"].contains(name)) return reader.fail(where, "missing");
    PUFF_READ(m.levels, std::vector<std::string>, j["maps"][name], "levels", where);
    if (m.levels.size() != static_cast<std::size_t>(d.mipLevels))
      return reader.fail(where + "/levels", "must list mipLevels files");
    d.maps[name] = m;
  }
  return d;
}

Result<AtlasDesc> loadAtlasDesc(const fs::path& sidecar) {
  auto bytes = readFileBytes(sidecar);
  if (!bytes) return bytes.error();
  json j = json::parse(*bytes, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return Error::at(sidecar, "not valid JSON");
  return atlasFromJson(j, sidecar);
}

Result<Atlas> loadAtlas(const fs::path& sidecar) {
  auto desc = loadAtlasDesc(sidecar);
  if (!desc) return desc.error();
  Atlas atlas;
  atlas.desc = *desc;
  for (const auto& [name, m] : desc->maps) {
    auto& levels = atlas.maps[name];
    for (std::size_t level = 0; level < m.levels.size(); ++level) {
      const fs::path file = sidecar.parent_path() / m.levels[level];
      auto img = readImage(file);
      if (!img) return img.error();
      const int w = std::max(1, desc->width >> level), h = std::max(1, desc->height >> level);
      if (img->width != w || img->height != h) {
        return Error::at(file, "is " + std::to_string(img->width) + "x" + std::to_string(img->height) +
                                   ", the sidecar says " + std::to_string(w) + "x" + std::to_string(h));
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
  std::size_t bytes = 0;
  for (int level = 0; level < d.mipLevels; ++level) {
    const std::size_t texels = static_cast<std::size_t>(std::max(1, d.width >> level)) *
                               static_cast<std::size_t>(std::max(1, d.height >> level));
    bytes += texels * (4 + 4 + 2);
  }
  return bytes;
}

}  // namespace puff::core
