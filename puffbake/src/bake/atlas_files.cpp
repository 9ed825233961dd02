// Replacing an atlas whole (atlas_files.h).
#include "atlas_files.h"

#include <algorithm>
#include <cctype>

#include <puff/core/atlas.h>
#include <puff/core/json_read.h>

namespace puff::bake::detail {

namespace fs = std::filesystem;

std::vector<fs::path> filesNamedBy(const fs::path& sidecar) {
  std::vector<fs::path> files;
  std::error_code ec;
  if (!fs::is_regular_file(sidecar, ec)) return files;
  auto j = core::jsonread::loadJsonFile(sidecar);
  if (!j) return files;
  auto desc = core::atlasFromJson(*j, sidecar);
  if (!desc) return files;
  const fs::path dir = sidecar.parent_path().lexically_normal();
  const auto add = [&](const fs::path& p) {
    const fs::path file = (sidecar.parent_path() / p).lexically_normal();
    if (!p.is_absolute() && file.parent_path() == dir) files.push_back(file);
  };
  for (const auto& [name, map] : desc->maps) {
    for (const std::string& level : map.levels) add(level);
  }
  for (const core::AtlasSource& source : desc->sources) {
    if (!source.lodMesh.empty()) add(source.lodMesh);
  }
  return files;
}

namespace {

bool startsWith(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

// Removes leading digits; false when there are none.
bool digits(std::string_view& s) {
  std::size_t n = 0;
  while (n < s.size() && std::isdigit(static_cast<unsigned char>(s[n]))) ++n;
  s.remove_prefix(n);
  return n > 0;
}

// ".HASH.EXT" with HASH 12 lowercase hex digits and EXT one of `extensions`.
bool hashAndExtension(std::string_view s, std::initializer_list<std::string_view> extensions) {
  if (s.size() < 14 || s[0] != '.') return false;
  for (std::size_t i = 1; i <= 12; ++i) {
    const char c = s[i];
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  }
  s.remove_prefix(13);
  return std::find(extensions.begin(), extensions.end(), s) != extensions.end();
}

}  // namespace

bool isContentFileOf(const std::string& fileName, const std::string& stem) {
  std::string_view s = fileName;
  if (!startsWith(s, stem + "_")) return false;
  s.remove_prefix(stem.size() + 1);
  for (std::string_view map : {"normal_depth", "color", "distance"}) {
    if (!startsWith(s, map)) continue;
    std::string_view rest = s.substr(map.size());
    if (startsWith(rest, ".mip")) {
      rest.remove_prefix(4);
      if (!digits(rest)) return false;
    }
    return hashAndExtension(rest, {".png", ".exr", ".puffimg"});
  }
  if (startsWith(s, "lod")) {
    std::string_view rest = s.substr(3);
    return digits(rest) && hashAndExtension(rest, {".ply", ".obj", ".off", ".stl"});
  }
  return false;
}

void removeSuperseded(const fs::path& dir, const std::string& stem, const std::vector<fs::path>& replaced,
                      const std::vector<fs::path>& kept) {
  std::error_code ec;
  const auto isKept = [&](const fs::path& f) {
    return std::any_of(kept.begin(), kept.end(), [&](const fs::path& k) {
      std::error_code e;
      return k.lexically_normal() == f.lexically_normal() || fs::equivalent(k, f, e);
    });
  };
  for (const fs::path& old : replaced) {
    if (!isKept(old)) fs::remove(old, ec);
  }
  for (const auto& entry : fs::directory_iterator(dir.empty() ? fs::path(".") : dir, ec)) {
    std::error_code e;
    if (!entry.is_regular_file(e) || !isContentFileOf(entry.path().filename().string(), stem)) continue;
    if (!isKept(dir.empty() ? entry.path().filename() : entry.path())) fs::remove(entry.path(), e);
  }
}

}  // namespace puff::bake::detail
