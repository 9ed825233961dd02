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

/// Cooks the atlas described by `sidecar` into `outSidecar` (a .json path, STEM.json): every map
/// level becomes STEM_MAP.puffimg or STEM_MAP.mipN.puffimg beside it (MAP: normal_depth, color,
/// distance, back), a `--lod auto` mesh STEM_lodI.EXT; the sidecar is the source's JSON with only those
/// file names changed. Files are named after the output, never after the source's names, so they
/// stay beside it and two cooked atlases share a directory.
/// All or nothing: the files appear together, and nothing existing is touched on an error. An
/// atlas already at `outSidecar` is replaced whole: once the new one is in place, the files its
/// sidecar named beside it that the new one (and the source) does not use are removed.
/// Errors: what loading the atlas reports, an image of more than 4 channels, an output that would
/// replace the source sidecar or one of its files.
Result<Cooked> cookAtlas(const std::filesystem::path& sidecar, const std::filesystem::path& outSidecar);

/// Cooks one image file into `out` (a .puffimg path): same size, channels, pixel values, stored
/// type and "puff:" attributes. Written whole or not at all.
Result<Cooked> cookImage(const std::filesystem::path& in, const std::filesystem::path& out);

}  // namespace puff::bake
