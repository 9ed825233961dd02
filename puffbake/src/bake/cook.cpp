// Cooking atlases and images into Puff's cooked images (bake/cook.h).
#include <puff/bake/cook.h>

#include <nlohmann/json.hpp>

#include <puff/core/atlas.h>
#include <puff/core/files.h>
#include <puff/core/image.h>

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

fs::path cookedName(const fs::path& file) {
  fs::path name = file;
  name.replace_extension(core::kCookedImageExtension);
  return name;
}

// Reads `in` and stages its cooked copy at `target` in `tx`.
Result<void> stageImage(core::OutputTransaction& tx, const fs::path& in, const fs::path& target, Cooked& cooked) {
  core::ImageFileInfo info;
  auto image = core::readImage(in, &info);
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
  auto bytes = core::readFileBytes(sidecar);
  if (!bytes) return bytes.error();
  json j = json::parse(*bytes, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return Error::at(sidecar, "not valid JSON");
  auto desc = core::atlasFromJson(j, sidecar);
  if (!desc) return desc.error();
  if (sameFile(sidecar, outSidecar)) {
    return Error::at(outSidecar, "is the atlas being cooked; name another sidecar for the cooked atlas");
  }
  const fs::path inDir = sidecar.parent_path(), outDir = outSidecar.parent_path();
  Cooked cooked;
  core::OutputTransaction tx;
  PUFF_TRY(tx.prepareDirectory(outDir));
  for (const auto& [name, map] : desc->maps) {
    for (std::size_t level = 0; level < map.levels.size(); ++level) {
      const fs::path cookedLevel = cookedName(map.levels[level]);
      const fs::path in = inDir / map.levels[level], out = outDir / cookedLevel;
      if (sameFile(in, out)) return Error::at(in, "is already a cooked image (the atlas is cooked)");
      PUFF_TRY(tx.prepareDirectory(out.parent_path()));
      PUFF_TRY(stageImage(tx, in, out, cooked));
      j["maps"][name]["levels"][level] = cookedLevel.generic_string();
    }
  }
  for (std::size_t i = 0; i < desc->sources.size(); ++i) {
    const std::string& lod = desc->sources[i].lodMesh;
    if (lod.empty() || fs::path(lod).is_absolute()) continue;
    auto from = core::lodMeshFile(*desc, i, sidecar);
    if (!from) return from.error();
    const fs::path to = outDir / lod;
    if (sameFile(*from, to)) continue;
    auto mesh = core::readFileBytes(*from);
    if (!mesh) return mesh.error();
    PUFF_TRY(tx.prepareDirectory(to.parent_path()));
    PUFF_TRY(core::writeFileBytes(tx.stage(to), *mesh, to));
    cooked.files.push_back(to);
    cooked.bytesRead += mesh->size();
    cooked.bytesWritten += mesh->size();
  }
  const std::string text = j.dump(2) + "\n";
  PUFF_TRY(core::writeFileBytes(tx.stage(outSidecar), text, outSidecar));
  cooked.files.push_back(outSidecar);
  cooked.bytesRead += bytes->size();
  cooked.bytesWritten += text.size();
  PUFF_TRY(tx.commit());
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
