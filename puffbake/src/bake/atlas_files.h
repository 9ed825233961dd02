// How puffbake replaces an atlas whole: every map level and LOD mesh is named by its
// content (core::OutputTransaction::nameByContent), the sidecar is renamed into place last, in one
// rename, and only then are the files of the atlas it replaced removed. A reader that read the old
// sidecar finds the old files (or, once they are removed, no file: an error, never a mix); a
// reader of the new sidecar finds only new files; a run killed at any rename leaves the old atlas
// or the new one whole, and files of its own, listed in its pending file, that the next run
// removes. Nothing is removed by its name's shape: only what a sidecar or a pending list names.
// Private to puff::bake.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace puff::bake::detail {

/// The files the atlas at `sidecar` names in its own directory (its levels and LOD meshes; a name
/// with a directory in it is not one); nothing when there is no readable atlas there.
std::vector<std::filesystem::path> filesNamedBy(const std::filesystem::path& sidecar);

/// Before the commit: records in DIR/.STEM.pending-PID the content-named files this run is about to
/// rename into place (`files`: never the sidecar), so that if it is killed the next run for STEM removes exactly
/// those, and never a file it did not write. Written, not renamed, and removed by
/// removeSuperseded.
void writePending(const std::filesystem::path& dir, const std::string& stem,
                  const std::vector<std::filesystem::path>& files);

/// Before a run for STEM in `dir` commits: removes the files that runs killed before their sidecar
/// was renamed listed in their .STEM.pending-PID (the process gone), unless the sidecar now in
/// place (`sidecar`) names them, and those lists.
void removeAbandoned(const std::filesystem::path& dir, const std::string& stem, const std::filesystem::path& sidecar);

/// Once the atlas STEM.json in `dir` is committed with the files `kept`: removes the files the
/// sidecar it replaced named (`replaced`, from filesNamedBy before the commit) unless `kept` holds
/// them, and this run's pending list. Best effort: the new atlas is whole without them.
void removeSuperseded(const std::filesystem::path& dir, const std::string& stem,
                      const std::vector<std::filesystem::path>& replaced,
                      const std::vector<std::filesystem::path>& kept);

}  // namespace puff::bake::detail
