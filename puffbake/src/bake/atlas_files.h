// How puffbake replaces an atlas whole (issue 17): every map level and LOD mesh is named by its
// content (core::OutputTransaction::nameByContent), the sidecar is renamed into place last, in one
// rename, and only then are the files of the atlas it replaced removed. A reader that read the old
// sidecar finds the old files (or, once they are removed, no file: an error, never a mix); a
// reader of the new sidecar finds only new files; a run killed at any rename leaves the old atlas
// or the new one whole, and files of its own that the next run removes. Private to puff::bake.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace puff::bake::detail {

/// The files the atlas at `sidecar` names in its own directory (its levels and LOD meshes; a name
/// with a directory in it is not one); nothing when there is no readable atlas there.
std::vector<std::filesystem::path> filesNamedBy(const std::filesystem::path& sidecar);

/// Whether `fileName` is a content-named file of the atlas whose sidecar is STEM.json:
/// STEM_MAP[.mipN].HASH.EXT (MAP normal_depth, color or distance; EXT png, exr or puffimg) or
/// STEM_lodN.HASH.EXT, HASH 12 lowercase hex digits.
bool isContentFileOf(const std::string& fileName, const std::string& stem);

/// Once the atlas STEM.json in `dir` is committed with the files `kept`: removes the files the
/// sidecar it replaced named (`replaced`, from filesNamedBy before the commit) and every
/// content-named file of STEM in `dir` (one a killed run left), unless `kept` holds it. Best effort:
/// the new atlas is whole without them.
void removeSuperseded(const std::filesystem::path& dir, const std::string& stem,
                      const std::vector<std::filesystem::path>& replaced,
                      const std::vector<std::filesystem::path>& kept);

}  // namespace puff::bake::detail
