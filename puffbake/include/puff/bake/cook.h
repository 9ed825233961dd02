// Cooking: an atlas, ramp, gradient, detail video or black-body ramp rewritten as Puff's cooked
// images (".puffimg", core/image.h), which puff::core reads with no image library. A game that ships
// cooked assets links neither puff::io nor OpenImageIO. Cooking keeps every value: each image is
// stored in the type its file held (8-bit, 16-bit, half or float) with its "puff:" attributes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include <puff/core/error.h>

namespace puff::bake {

struct Cooked {
  std::vector<std::filesystem::path> files;  ///< every file written, the sidecar last for an atlas
  std::uintmax_t bytesRead = 0;              ///< the source files' size
  std::uintmax_t bytesWritten = 0;           ///< the cooked files' size
};

/// Cooks the atlas described by `sidecar` into `outSidecar` (a .json path): every map level
/// becomes a .puffimg beside it, named as the level's file with the extension changed; the sidecar
/// is the source's JSON with only the level file names changed; a `--lod auto` mesh is copied
/// beside it. All or nothing: the files appear together, and nothing existing is touched on an
/// error. Errors: what loading the atlas reports, an output that would replace the source sidecar.
Result<Cooked> cookAtlas(const std::filesystem::path& sidecar, const std::filesystem::path& outSidecar);

/// Cooks one image file into `out` (a .puffimg path): same size, channels, pixel values, stored
/// type and "puff:" attributes. Written whole or not at all.
Result<Cooked> cookImage(const std::filesystem::path& in, const std::filesystem::path& out);

}  // namespace puff::bake
