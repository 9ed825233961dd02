#include <algorithm>
#include <string>
#include <vector>

#include <puff/core/colour.h>
#include <puff/gl_api.h>

#include "atlas_textures.h"

namespace puff::cel::detail {

const std::vector<core::Image>* findAtlasMap(const core::Atlas& atlas, const std::string& key) {
  const auto it = atlas.maps.find(key);
  return it == atlas.maps.end() || it->second.empty() ? nullptr : &it->second;
}

Result<core::Texture> uploadAtlasLevels(const core::AtlasDesc& d, std::span<const core::Image> levels,
                                        const std::string& key, int channels, GLenum internal, bool decode) {
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  if (d.width > maxSize || d.height > maxSize) {
    return Error{"the atlas is " + std::to_string(d.width) + "x" + std::to_string(d.height) +
                 " texels, more than this GL's largest texture (" + std::to_string(maxSize) +
                 "): bake it with a smaller --size or fewer --views"};
  }
  core::Texture t = core::makeTexture(GL_TEXTURE_2D, "atlas " + key);
  const GLsizei nLevels = static_cast<GLsizei>(levels.size());
  // GL_OUT_OF_MEMORY (or any error) from the storage or the uploads: a message, not a blank atlas.
  const auto cannotMake = [&](const std::string& glErrors) {
    return Error{"cannot make the atlas " + key + " texture (" + std::to_string(d.width) + "x" +
                 std::to_string(d.height) + ", " + std::to_string(nLevels) + (nLevels == 1 ? " level" : " levels") +
                 "): " + glErrors};
  };
  glTextureStorage2D(t.get(), nLevels, internal, d.width, d.height);
  // Checked before the levels are converted below, which takes as much memory again on the CPU: out
  // of memory here would otherwise become std::bad_alloc there, naming nothing.
  if (const std::string e = core::drainGlErrors(); !e.empty()) return cannotMake(e);
  for (GLsizei l = 0; l < nLevels; ++l) {
    const core::Image& im = levels[static_cast<std::size_t>(l)];
    const int w = std::max(1, d.width >> l), h = std::max(1, d.height >> l);
    if (im.width != w || im.height != h) {
      return Error{"atlas " + key + " level " + std::to_string(l) + " is " + std::to_string(im.width) + "x" +
                   std::to_string(im.height) + ", expected " + std::to_string(w) + "x" + std::to_string(h)};
    }
    std::vector<float> px(static_cast<std::size_t>(w) * h * channels);
    for (std::size_t i = 0; i < static_cast<std::size_t>(w) * h; ++i) {
      for (int c = 0; c < channels; ++c) {
        const float v = im.pixels[i * im.channels + std::min(c, im.channels - 1)];
        px[i * channels + c] = decode && c < 3 ? static_cast<float>(core::srgbToLinear(double{v})) : v;
      }
    }
    // Rows go up as stored (top first): texture t = 0 is the atlas's top row, as in cellUv.
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(t.get(), l, 0, 0, w, h, channels == 4 ? GL_RGBA : GL_RED, GL_FLOAT, px.data());
  }
  if (const std::string e = core::drainGlErrors(); !e.empty()) return cannotMake(e);
  glTextureParameteri(t.get(), GL_TEXTURE_BASE_LEVEL, 0);
  glTextureParameteri(t.get(), GL_TEXTURE_MAX_LEVEL, nLevels - 1);
  glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, nLevels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
  glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

}  // namespace puff::cel::detail
