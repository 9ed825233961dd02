// Internal: an atlas's maps as the nailboards' textures (NailboardRenderer::setAtlas).
#pragma once

#include <span>
#include <string>
#include <vector>

#include <puff/core/atlas.h>
#include <puff/core/error.h>
#include <puff/core/gl.h>
#include <puff/gl_api.h>

namespace puff::cel::detail {

// The levels of map `key` of `atlas`; none where it has no such map or the map has no level.
const std::vector<core::Image>* findAtlasMap(const core::Atlas& atlas, const std::string& key);

// `levels` as a 2D texture of `channels` (4 or 1) in `internal`, every level, filtered linearly
// between levels and clamped at its edges. `decode`: the levels hold display values (the atlas
// colour map) and `internal` is a float format: RGB is decoded to scene-linear here (8-bit maps use
// GL_SRGB8_ALPHA8, which decodes on read instead). An error names the map and the GL's error, or a
// level of the wrong size, or an atlas larger than the GL's largest texture.
Result<core::Texture> uploadAtlasLevels(const core::AtlasDesc& d, std::span<const core::Image> levels,
                                        const std::string& key, int channels, GLenum internal, bool decode = false);

}  // namespace puff::cel::detail
