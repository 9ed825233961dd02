// Files embedded into the binaries at build time (cmake/EmbedFiles.cmake).
#pragma once

#include <cstddef>

namespace puff::core {

/// One embedded file. Tables end with an entry whose name is nullptr.
struct EmbeddedFile {
  const char* name;  ///< path relative to the embedded root, '/'-separated, e.g. "bake/puff.frag"
  const char* data;  ///< the file's bytes (followed by a NUL that is not counted in size)
  std::size_t size;
};

/// Every file under shaders/, sorted by name.
const EmbeddedFile* embeddedShaders();

}  // namespace puff::core
