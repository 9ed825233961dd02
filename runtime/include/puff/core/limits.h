// Sizes Puff accepts, kept once for every library and tool that checks them.
#pragma once

namespace puff::core {

/// The largest side of a frame, a media layer, an atlas cell or an atlas's grid, in pixels or
/// cells: the least GL_MAX_TEXTURE_SIZE an OpenGL 4.5 context may have.
inline constexpr int kMaxImageSize = 16384;

}  // namespace puff::core
