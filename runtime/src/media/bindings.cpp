#include <algorithm>

#include <puff/core/bind_points.h>
#include <puff/gl_api.h>
#include <puff/media/bindings.h>
#include <puff/shader_contract.h>

namespace puff::media {

core::GuardExtent guardExtent(const Bindings& b) {
  core::GuardExtent e;
  const unsigned units = std::max({b.depth, b.blackbody, b.phase, b.temperatureDetail, b.opacityDetail, b.falloff,
                                   b.opaqueColor, b.opaqueDepth, b.mediaLayer, b.mediaDepth, b.shimmer, b.resolveSource,
                                   b.historyFirst + shader::kMaxBlurFrames - 1, b.cartoonFirst + 2});
  e.textureUnits = static_cast<int>(units) + 1;
  e.uniformBuffers = static_cast<int>(std::max({b.mediaBlock, b.materialBlock, b.composeBlock, b.cartoonBlock})) + 1;
  e.storageBuffers = static_cast<int>(b.particles) + 1;
  e.drawBuffers = 4;  // the cartoon style's Renderer::draw sets draw buffers 2 and 3's blending
  return e;
}

Result<void> validate(const Bindings& b) {
  const std::string what = "media::Bindings";
  const std::vector<std::pair<GLenum, std::vector<core::NamedPoint>>> groups = {
      {GL_MAX_UNIFORM_BUFFER_BINDINGS, {{"mediaBlock", b.mediaBlock}, {"materialBlock", b.materialBlock}}},
      {GL_MAX_UNIFORM_BUFFER_BINDINGS, {{"composeBlock", b.composeBlock}, {"cartoonBlock", b.cartoonBlock}}},
      {GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, {{"particles", b.particles}}},
      {GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS,
       {{"depth", b.depth},
        {"blackbody", b.blackbody},
        {"phase", b.phase},
        {"temperatureDetail", b.temperatureDetail},
        {"opacityDetail", b.opacityDetail},
        {"falloff", b.falloff}}},
      {GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS,
       {{"opaqueColor", b.opaqueColor},
        {"opaqueDepth", b.opaqueDepth},
        {"mediaLayer", b.mediaLayer},
        {"mediaDepth", b.mediaDepth},
        {"shimmer", b.shimmer},
        {"cartoonFirst", b.cartoonFirst, 3}}},
      {GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, {{"resolveSource", b.resolveSource}}},
      {GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, {{"historyFirst", b.historyFirst, shader::kMaxBlurFrames}}},
  };
  for (const auto& [limit, points] : groups) {
    if (auto ok = core::checkBindPoints(what, limit, points); !ok) return ok;
  }
  return {};
}

}  // namespace puff::media
