// libFuzzer harness: an atlas as the runtime loads it (core::loadAtlas), beside a small baked atlas
// copied from the seeds (PUFF_FUZZ_SEED_DIR/atlas: tiny.json and the maps it names).
//   PUFF_FUZZ_ATLAS_PART == 1: the input is the sidecar (tiny.json); the maps are the baked ones.
//   PUFF_FUZZ_ATLAS_PART == 2: the input is one map level file (the first byte picks which of the
//     sidecar's files); the sidecar and the other maps are the baked ones.
#include <algorithm>
#include <vector>

#include <puff/core/atlas.h>

#include "fuzz_common.h"

namespace {

namespace fs = std::filesystem;

struct MapFile {
  fs::path path;
  std::string bytes;  // as baked, put back after each input
};

std::vector<MapFile>& mapFiles() {
  static std::vector<MapFile> files;
  return files;
}

fs::path sidecar() { return puff::fuzz::workDir() / "tiny.json"; }

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  puff::io::useOpenImageIO();
  const fs::path seeds = fs::path(PUFF_FUZZ_SEED_DIR) / "atlas";
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(seeds, ec)) {
    const fs::path to = puff::fuzz::workDir() / entry.path().filename();
    fs::copy_file(entry.path(), to, fs::copy_options::overwrite_existing, ec);
    if (ec) {
      std::fprintf(stderr, "puff fuzz: cannot copy %s: %s\n", entry.path().c_str(), ec.message().c_str());
      std::abort();
    }
  }
  auto desc = puff::core::loadAtlasDesc(sidecar());
  auto atlas = puff::core::loadAtlas(sidecar());
  if (!desc || !atlas) {
    std::fprintf(stderr, "puff fuzz: the seed atlas %s does not load\n", (seeds / "tiny.json").c_str());
    std::abort();
  }
  for (const auto& [name, map] : desc->maps) {
    for (const std::string& level : map.levels) {
      const fs::path p = puff::fuzz::workDir() / level;
      auto bytes = puff::core::readFileBytes(p);
      if (!bytes) std::abort();
      mapFiles().push_back({p, std::move(*bytes)});
    }
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
#if PUFF_FUZZ_ATLAS_PART == 1
  puff::fuzz::writeInput("tiny.json", data, size);
  puff::fuzz::expectCleanError(puff::core::loadAtlas(sidecar()));
#elif PUFF_FUZZ_ATLAS_PART == 2
  if (size < 1) return 0;
  const MapFile& map = mapFiles()[data[0] % mapFiles().size()];
  puff::fuzz::writeInput(map.path.filename().string(), data + 1, size - 1);
  puff::fuzz::expectCleanError(puff::core::loadAtlas(sidecar()));
  if (!puff::core::writeFileBytes(map.path, map.bytes)) std::abort();
#else
#error "PUFF_FUZZ_ATLAS_PART must be 1 (sidecar) or 2 (map)"
#endif
  return 0;
}
