// Cooking atlases and images into Puff's cooked images (bake/cook.h).
#include <puff/bake/cook.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include <puff/core/atlas.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/support/json_read.h>

#include "atlas_files.h"

namespace puff::bake {

namespace fs = std::filesystem;
using nlohmann::json;
using puff::Error;
using puff::Result;

namespace {

std::uintmax_t sizeOf(const fs::path& p) {
  std::error_code ec;
  const auto n = fs::file_size(p, ec);
  return ec ? 0 : n;
}

// "normalDepth" -> "normal_depth", as the baker names its map files.
std::string snakeCase(const std::string& name) {
  std::string out;
  for (char c : name) {
    if (c >= 'A' && c <= 'Z') {
      out += '_';
      out += static_cast<char>(c - 'A' + 'a');
    } else {
      out += c;
    }
  }
  return out;
}

// A cooked atlas's files are named after its own sidecar (STEM_MAP.puffimg, STEM_MAP.mipN.puffimg,
// STEM_lodI.EXT) and lie beside it: two cooked atlases share a directory without a clash, and no
// name in the source sidecar (a subdirectory, "../", an absolute path) leads a file elsewhere.
std::string levelName(const std::string& stem, const std::string& map, std::size_t level) {
  return stem + "_" + snakeCase(map) + (level == 0 ? "" : ".mip" + std::to_string(level)) + core::kCookedImageExtension;
}

// Reads `in` and stages its cooked copy at `target` in `tx`; with `byContent`, names it by its
// content (STEM_MAP.HASH.puffimg, atlas_files.h). Returns the target.
Result<fs::path> stageImage(core::OutputTransaction& tx, const fs::path& in, const fs::path& target, Cooked& cooked,
                            bool byContent) {
  core::ImageFileInfo info;
  // The limits of any image, and the channels a cooked image holds (1 to 4).
  PUFF_TRY_ASSIGN(auto image, core::readImage(in, &info, core::ImageLimits{"a cooked image"}));
  const fs::path staged = tx.stage(target);
  PUFF_TRY(core::writeImage(staged, image, info.type, info.attributes, target));
  fs::path named = target;
  if (byContent) {
    PUFF_TRY_ASSIGN(auto t, tx.nameByContent(staged));
    named = t;
  }
  cooked.files.push_back(named);
  cooked.bytesRead += sizeOf(in);
  cooked.bytesWritten += sizeOf(staged);
  return named;
}

}  // namespace

Result<Cooked> cookAtlas(const fs::path& sidecar, const fs::path& outSidecar) {
  PUFF_TRY_ASSIGN(json j, core::jsonread::loadJsonFile(sidecar));
  PUFF_TRY_ASSIGN(auto desc, core::atlasFromJson(j, sidecar));
  // Every level checked as the runtime will check it (size, channels, finite texels): a cooked
  // atlas is one a game can load, or none is written.
  if (auto atlas = core::loadAtlas(sidecar); !atlas) return atlas.error();
  if (core::sameFile(sidecar, outSidecar)) {
    return Error::at(outSidecar, "is the atlas being cooked; name another sidecar for the cooked atlas");
  }
  const fs::path inDir = sidecar.parent_path(), outDir = outSidecar.parent_path();
  const std::string stem = outSidecar.stem().string();
  // What the sidecar being replaced named beside it, less what the source and the new atlas use:
  // removed once the new atlas is in place, so the directory holds the new atlas whole.
  const std::vector<fs::path> stale = detail::filesNamedBy(outSidecar);
  const std::vector<fs::path> sourceFiles = detail::filesNamedBy(sidecar);
  Cooked cooked;
  core::OutputTransaction tx;
  PUFF_TRY(tx.prepareDirectory(outDir));
  for (const auto& [name, map] : desc.maps) {
    for (std::size_t level = 0; level < map.levels.size(); ++level) {
      const std::string cookedLevel = levelName(stem, name, level);
      const fs::path in = inDir / map.levels[level], out = outDir / cookedLevel;
      if (core::sameFile(in, out))
        return Error::at(in, "would be replaced by its own cooked copy; name another sidecar");
      PUFF_TRY_ASSIGN(auto named, stageImage(tx, in, out, cooked, true));
      j["maps"][name]["levels"][level] = named.filename().string();
    }
  }
  for (std::size_t i = 0; i < desc.sources.size(); ++i) {
    if (desc.sources[i].lodMesh.empty()) continue;
    PUFF_TRY_ASSIGN(auto from, core::lodMeshFile(desc, i, sidecar));
    const std::string lod = stem + "_lod" + std::to_string(i) + from.extension().string();
    const fs::path to = outDir / lod;
    if (core::sameFile(from, to)) return Error::at(from, "would be replaced by its own copy; name another sidecar");
    PUFF_TRY_ASSIGN(auto mesh, core::readFileBytes(from));
    const fs::path staged = tx.stage(to);
    PUFF_TRY(core::writeFileBytes(staged, mesh, to));
    PUFF_TRY_ASSIGN(auto named, tx.nameByContent(staged));
    j["sources"][i]["lodMesh"] = named.filename().string();
    cooked.files.push_back(named);
    cooked.bytesRead += mesh.size();
    cooked.bytesWritten += mesh.size();
  }
  const std::string text = j.dump(2) + "\n";
  PUFF_TRY(core::writeFileBytes(tx.stage(outSidecar), text, outSidecar));
  cooked.files.push_back(outSidecar);
  cooked.bytesRead += sizeOf(sidecar);
  cooked.bytesWritten += text.size();
  detail::removeAbandoned(outDir, stem, outSidecar);
  std::vector<fs::path> contentNamed = cooked.files;  // the levels and meshes, not the sidecar
  contentNamed.erase(std::remove(contentNamed.begin(), contentNamed.end(), outSidecar), contentNamed.end());
  detail::writePending(outDir, stem, contentNamed);
  PUFF_TRY(tx.commit());
  std::vector<fs::path> kept = cooked.files;
  kept.insert(kept.end(), sourceFiles.begin(), sourceFiles.end());
  detail::removeSuperseded(outDir, stem, stale, kept);
  return cooked;
}

Result<Cooked> cookImage(const fs::path& in, const fs::path& out) {
  if (!core::isCookedImagePath(out)) {
    return Error::at(out, std::string("a cooked image's name ends in ") + core::kCookedImageExtension);
  }
  if (core::sameFile(in, out)) return Error::at(out, "is the image being cooked; name another file");
  Cooked cooked;
  core::OutputTransaction tx;
  PUFF_TRY(tx.prepareDirectory(out.parent_path()));
  PUFF_TRY(stageImage(tx, in, out, cooked, false));  // one image: the name asked for
  PUFF_TRY(tx.commit());
  return cooked;
}

}  // namespace puff::bake
