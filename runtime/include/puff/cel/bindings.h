// The binding points the cel passes use, chosen by the host (NailboardRenderer::create,
// OpaqueRenderer::create, FrameBlock, ShadowMap, Ramp::bind, Gradient::bind). No GL: a plain struct.
//
// Each point is its kind's base (core::BindingBase: one uniform buffer, one storage buffer and one
// texture unit base) plus its offset (Bindings::Offset, written there once). Bindings::at(base)
// puts them all at a host's bases; the default is at(core::BindingBase{}), uniform buffers from 8,
// storage buffers from 4 and texture units from 16 (docs/cel-rendering.md, "Host state"):
//
//   point                kind             offset  default  read by
//   frameBlock           uniform buffer   0       8        every cel program (shaders/common/frame.glsl)
//   particles            storage buffer   0       4        nailboards, shadow volumes, casters (particle.glsl)
//   cells                storage buffer   1       5        the same (the atlas's cell table)
//   particleNext         storage buffer   2       6        nailboards writing a motion map (each particle's
//                                                           next position and size: NailboardRenderer::upload)
//   ramp                 texture unit     0       16       q, 1D (Ramp::bind)
//   gradient             texture unit     1       17       K_a(x, y), 2D (Gradient::bind)
//   atlasPacked          texture unit     2       18       the atlas's normal/depth/distance map, 2D
//   atlasColor           texture unit     3       19       the atlas's colour map, 2D
//   atlasHull            texture unit     4       20       the atlas's hull field, 3D (tumbling hull only)
//   shadowProfile        texture unit     5       21       the silhouettes' radius table, 2D
//   shadowMapDepth       texture unit     6       22       ShadowMap::bind, 2D depth
//   shadowMapIds         texture unit     7       23       ShadowMap::bind, 2D R32UI
//   visibility           texture unit     8       24       Puff's own pre-pass target: the nailboards' visibility
//                                                           (RG32UI, 2D or 2D multisample) or the hull's occluders
//                                                           (R32F, 2D)
//
// The renderers point their programs' blocks and samplers at these after linking
// (glUniformBlockBinding, glShaderStorageBlockBinding, glProgramUniform1i): the shaders'
// `layout(binding = N)` values are never used. A host may still set a point on its own. The texture
// units must all differ (one program reads up to all nine), as must the three storage buffers; the
// uniform buffer is alone. create() checks them against the GL's GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS,
// GL_MAX_UNIFORM_BUFFER_BINDINGS and GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS. Every object that binds
// (FrameBlock, Ramp, Gradient, ShadowMap) must be given the same Bindings as the renderers that read
// them.
#pragma once

#include <puff/core/binding_base.h>
#include <puff/core/error.h>
#include <puff/core/host_state.h>

namespace puff::cel {

struct Bindings {
  /// Each point's offset from its kind's base.
  struct Offset {
    static constexpr unsigned frameBlock = 0;                              // uniform buffers
    static constexpr unsigned particles = 0, cells = 1, particleNext = 2;  // storage buffers
    static constexpr unsigned ramp = 0, gradient = 1, atlasPacked = 2, atlasColor = 3, atlasHull = 4, shadowProfile = 5,
                              shadowMapDepth = 6, shadowMapIds = 7, visibility = 8;  // texture units
  };
  static constexpr core::BindingBase kDefaultBase{};

  unsigned frameBlock = kDefaultBase.uniformBuffer + Offset::frameBlock;      ///< uniform buffer: the frame's block
  unsigned particles = kDefaultBase.storageBuffer + Offset::particles;        ///< storage buffer: the packed particles
  unsigned cells = kDefaultBase.storageBuffer + Offset::cells;                ///< storage buffer: the atlas's cells
  unsigned particleNext = kDefaultBase.storageBuffer + Offset::particleNext;  ///< storage buffer: a motion map's
  unsigned ramp = kDefaultBase.textureUnit + Offset::ramp;                    ///< texture unit: the ramp q
  unsigned gradient = kDefaultBase.textureUnit + Offset::gradient;            ///< texture unit: the ambient gradient
  unsigned atlasPacked = kDefaultBase.textureUnit + Offset::atlasPacked;
  unsigned atlasColor = kDefaultBase.textureUnit + Offset::atlasColor;
  unsigned atlasHull = kDefaultBase.textureUnit + Offset::atlasHull;
  unsigned shadowProfile = kDefaultBase.textureUnit + Offset::shadowProfile;
  unsigned shadowMapDepth = kDefaultBase.textureUnit + Offset::shadowMapDepth;
  unsigned shadowMapIds = kDefaultBase.textureUnit + Offset::shadowMapIds;
  unsigned visibility = kDefaultBase.textureUnit + Offset::visibility;  ///< texture unit: Puff's pre-pass target
  bool operator==(const Bindings&) const = default;

  /// Every point at its offset from `base`.
  static constexpr Bindings at(const core::BindingBase& base) {
    return {.frameBlock = base.uniformBuffer + Offset::frameBlock,
            .particles = base.storageBuffer + Offset::particles,
            .cells = base.storageBuffer + Offset::cells,
            .particleNext = base.storageBuffer + Offset::particleNext,
            .ramp = base.textureUnit + Offset::ramp,
            .gradient = base.textureUnit + Offset::gradient,
            .atlasPacked = base.textureUnit + Offset::atlasPacked,
            .atlasColor = base.textureUnit + Offset::atlasColor,
            .atlasHull = base.textureUnit + Offset::atlasHull,
            .shadowProfile = base.textureUnit + Offset::shadowProfile,
            .shadowMapDepth = base.textureUnit + Offset::shadowMapDepth,
            .shadowMapIds = base.textureUnit + Offset::shadowMapIds,
            .visibility = base.textureUnit + Offset::visibility};
  }
};
static_assert(Bindings{} == Bindings::at(Bindings::kDefaultBase));

/// The extent a core::HostStateGuard needs to save every point of `b` (and the defaults' draw
/// buffers).
core::GuardExtent guardExtent(const Bindings& b);

/// Checks `b` (distinct where it must be, within the GL's limits): "cel::Bindings.NAME: ...".
/// The renderers' create() returns this error. Needs a current GL context.
Result<void> validate(const Bindings& b);

}  // namespace puff::cel
