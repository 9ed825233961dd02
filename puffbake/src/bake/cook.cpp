// Cooking atlases and images into Puff's cooked images (bake/cook.h).
#include <puff/bake/cook.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include <puff/core/atlas.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/core/json_read.h>

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

// The files the atlas at `sidecar` names in its own directory (its levels and LOD meshes); nothing
// when it is not a readable atlas.
std::vector<fs::path> filesBeside(const fs::path& sidecar) {
  std::vector<fs::path> files;
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

// Reads `in` and stages its cooked copy at `target` in `tx`.
Result<void> stageImage(core::OutputTransaction& tx, const fs::path& in, const fs::path& target, Cooked& cooked) {
  core::ImageFileInfo info;
  // The limits of any image, and the channels a cooked image holds (1 to 4).
  auto image = core::readImage(in, &info, core::ImageLimits{"a cooked image"});
  if (!image) return image.error();
  const fs::path staged = tx.stage(target);
  PUFF_TRY(core::writeImage(staged, *image, info.type, info.attributes, target));
  cooked.files.push_back(target);
  cooked.bytesRead += sizeOf(in);
  cooked.bytesWritten += sizeOf(staged);
  return {};
}

bool sameFile(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::equivalent(a, b, ec)) return true;
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

}  // namespace

Result<Cooked> cookAtlas(const fs::path& sidecar, const fs::path& outSidecar) {
  auto parsed = core::jsonread::loadJsonFile(sidecar);
  if (!parsed) return parsed.error();
  json j = std::move(*parsed);
  auto desc = core::atlasFromJson(j, sidecar);
  if (!desc) return desc.error();
  if (sameFile(sidecar, outSidecar)) {
    return Error::at(outSidecar, "is the atlas being cooked; name another sidecar for the cooked atlas");
  }
  const fs::path inDir = sidecar.parent_path(), outDir = outSidecar.parent_path();
  const std::string stem = outSidecar.stem().string();
  // What the sidecar being replaced named beside it, less what the source and the new atlas use:
  // removed once the new atlas is in place, so the directory holds the new atlas whole.
  const std::vector<fs::path> stale = filesBeside(outSidecar);
  const std::vector<fs::path> sourceFiles = filesBeside(sidecar);
  Cooked cooked;
  core::OutputTransaction tx;
  PUFF_TRY(tx.prepareDirectory(outDir));
  for (const auto& [name, map] : desc->maps) {
    for (std::size_t level = 0; level < map.levels.size(); ++level) {
      const std::string cookedLevel = levelName(stem, name, level);
      const fs::path in = inDir / map.levels[level], out = outDir / cookedLevel;
      if (sameFile(in, out)) return Error::at(in, "would be replaced by its own cooked copy; name another sidecar");
      PUFF_TRY(stageImage(tx, in, out, cooked));
      j["maps"][name]["levels"][level] = cookedLevel;
    }
  }
  for (std::size_t i = 0; i < desc->sources.size(); ++i) {
    if (desc->sources[i].lodMesh.empty()) continue;
    auto from = core::lodMeshFile(*desc, i, sidecar);
    if (!from) return from.error();
    const std::string lod = stem + "_lod" + std::to_string(i) + from->extension().string();
    const fs::path to = outDir / lod;
    if (sameFile(*from, to)) return Error::at(*from, "would be replaced by its own copy; name another sidecar");
    auto mesh = core::readFileBytes(*from);
    if (!mesh) return mesh.error();
    PUFF_TRY(core::writeFileBytes(tx.stage(to), *mesh, to));
    j["sources"][i]["lodMesh"] = lod;
    cooked.files.push_back(to);
    cooked.bytesRead += mesh->size();
    cooked.bytesWritten += mesh->size();
  }
  const std::string text = j.dump(2) + "\n";
  PUFF_TRY(core::writeFileBytes(tx.stage(outSidecar), text, outSidecar));
  cooked.files.push_back(outSidecar);
  cooked.bytesRead += sizeOf(sidecar);
  cooked.bytesWritten += text.size();
  PUFF_TRY(tx.commit());
  for (const fs::path& old : stale) {
    const auto kept = [&](const fs::path& f) { return sameFile(f, old); };
    if (std::any_of(cooked.files.begin(), cooked.files.end(), kept) ||
        std::any_of(sourceFiles.begin(), sourceFiles.end(), kept)) {
      continue;
    }
    std::error_code ec;
    fs::remove(old, ec);  // best effort: the new atlas is complete without it
  }
  return cooked;
}

Result<Cooked> cookImage(const fs::path& in, const fs::path& out) {
  if (!core::isCookedImagePath(out)) {
    return Error::at(out, std::string("a cooked image's name ends in ") + core::kCookedImageExtension);
  }
  if (sameFile(in, out)) return Error::at(out, "is the image being cooked; name another file");
  Cooked cooked;
  core::OutputTransaction tx;
  PUFF_TRY(tx.prepareDirectory(out.parent_path()));
  PUFF_TRY(stageImage(tx, in, out, cooked));
  PUFF_TRY(tx.commit());
  return cooked;
}

}  // namespace puff::bake
