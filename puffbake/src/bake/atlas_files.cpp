// Replacing an atlas whole (atlas_files.h).
#include "atlas_files.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <fstream>

#include <puff/core/atlas.h>
#include <puff/core/files.h>
#include <puff/support/json_read.h>

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

std::string pendingPrefix(const std::string& stem) { return "." + stem + ".pending-"; }

bool contains(const std::vector<fs::path>& files, const fs::path& f) {
  return std::any_of(files.begin(), files.end(), [&](const fs::path& k) { return core::sameFile(k, f); });
}

}  // namespace

void writePending(const fs::path& dir, const std::string& stem, const std::vector<fs::path>& files) {
  std::string list;
  for (const fs::path& f : files) list += f.filename().string() + "\n";
  std::ofstream(dir / (pendingPrefix(stem) + std::to_string(::getpid())), std::ios::binary | std::ios::trunc) << list;
}

void removeAbandoned(const fs::path& dir, const std::string& stem, const fs::path& sidecar) {
  const std::string prefix = pendingPrefix(stem);
  const std::vector<fs::path> current = filesNamedBy(sidecar);
  std::error_code ec;
  for (fs::directory_iterator it(dir.empty() ? fs::path(".") : dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    char* after = nullptr;
    const long pid = std::strtol(name.c_str() + prefix.size(), &after, 10);
    if (pid <= 0 || *after != '\0' || pid == ::getpid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to ask
    std::ifstream in(it->path());
    std::string line;
    while (std::getline(in, line)) {
      // One plain name per line, in this directory (the list is Puff's own; anything else is skipped).
      if (line.empty() || line.find('/') != std::string::npos || line == "." || line == "..") continue;
      const fs::path file = it->path().parent_path() / line;
      std::error_code e;
      if (!contains(current, file) && !core::sameFile(file, sidecar)) fs::remove(file, e);
    }
    in.close();
    std::error_code e;
    fs::remove(it->path(), e);
  }
}

void removeSuperseded(const fs::path& dir, const std::string& stem, const std::vector<fs::path>& replaced,
                      const std::vector<fs::path>& kept) {
  std::error_code ec;
  for (const fs::path& old : replaced) {
    if (!contains(kept, old)) fs::remove(old, ec);
  }
  fs::remove(dir / (pendingPrefix(stem) + std::to_string(::getpid())), ec);
}

}  // namespace puff::bake::detail
