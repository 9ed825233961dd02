#include <algorithm>

#include <puff/core/bind_points.h>
#include <puff/gl_api.h>

#include "bindings_gl.h"

namespace puff::cel {

core::GuardExtent guardExtent(const Bindings& b) {
  core::GuardExtent e;
  const unsigned units = std::max({b.ramp, b.gradient, b.atlasPacked, b.atlasColor, b.atlasHull, b.shadowProfile,
                                   b.shadowMapDepth, b.shadowMapIds, b.visibility});
  e.textureUnits = static_cast<int>(units) + 1;
  e.uniformBuffers = static_cast<int>(b.frameBlock) + 1;
  e.storageBuffers = static_cast<int>(std::max({b.particles, b.cells, b.particleNext})) + 1;
  return e;
}

Result<void> validate(const Bindings& b) {
  const std::string what = "cel::Bindings";
  if (auto ok = core::checkBindPoints(what, GL_MAX_UNIFORM_BUFFER_BINDINGS, {{"frameBlock", b.frameBlock}}); !ok) {
    return ok;
  }
  if (auto ok =
          core::checkBindPoints(what, GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS,
                                {{"particles", b.particles}, {"cells", b.cells}, {"particleNext", b.particleNext}});
      !ok) {
    return ok;
  }
  return core::checkBindPoints(what, GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS,
                               {{"ramp", b.ramp},
                                {"gradient", b.gradient},
                                {"atlasPacked", b.atlasPacked},
                                {"atlasColor", b.atlasColor},
                                {"atlasHull", b.atlasHull},
                                {"shadowProfile", b.shadowProfile},
                                {"shadowMapDepth", b.shadowMapDepth},
                                {"shadowMapIds", b.shadowMapIds},
                                {"visibility", b.visibility}});
}

namespace detail {

void assignBindPoints(GLuint program, const Bindings& b) {
  using K = core::BindPoint::Kind;
  core::assignBindPoints(program, {{K::kUniformBlock, "FrameBlock", b.frameBlock},
                                   {K::kStorageBlock, "ParticleBuffer", b.particles},
                                   {K::kStorageBlock, "AtlasCells", b.cells},
                                   {K::kStorageBlock, "ParticleNext", b.particleNext},
                                   {K::kSampler, "uRamp", b.ramp},
                                   {K::kSampler, "uGradient", b.gradient},
                                   {K::kSampler, "uPacked", b.atlasPacked},
                                   {K::kSampler, "uColor", b.atlasColor},
                                   {K::kSampler, "uHull", b.atlasHull},
                                   {K::kSampler, "uShadowProfile", b.shadowProfile},
                                   {K::kSampler, "uShadowMapDepth", b.shadowMapDepth},
                                   {K::kSampler, "uShadowMapId", b.shadowMapIds},
                                   {K::kSampler, "uVisible", b.visibility},
                                   {K::kSampler, "uOccluders", b.visibility}});
}

}  // namespace detail

}  // namespace puff::cel
