// The binding points the media path uses, chosen by the host (Renderer::create, Layers::create, HostLayers::create).
// No GL: a plain struct.
//
// Each point is its kind's base (core::BindingBase, the one the cel passes use too) plus its
// offset (Bindings::Offset, written there once); Bindings::at(base) puts them all at a host's
// bases, and the default is at(core::BindingBase{}) (docs/media.md, "Host state"):
//
//   point              kind             offset  default  read by
//   mediaBlock         uniform buffer   3       11       Renderer::draw (shaders/common/media.glsl)
//   materialBlock      uniform buffer   4       12       Renderer::draw
//   particles          storage buffer   0       4        Renderer::draw, the sorted particles
//   depth              texture unit     0       16       Renderer::draw, the host's linear depth, 2D
//   blackbody          texture unit     1       17       Renderer::draw, 1D
//   phase              texture unit     2       18       Renderer::draw, 2D
//   temperatureDetail  texture unit     3       19       Renderer::draw, 3D
//   opacityDetail      texture unit     4       20       Renderer::draw, 3D
//   falloff            texture unit     5       21       Renderer::draw (planar-textured), 2D
//   composeBlock       uniform buffer   5       13       Layers::compose, HostLayers::composeOver
//   opaqueColor        texture unit     0       16       Layers::compose, 2D
//   opaqueDepth        texture unit     1       17       Layers::compose, HostLayers::composeOver, 2D
//   mediaLayer         texture unit     2       18       Layers::compose, HostLayers::composeOver, 2D
//   mediaDepth         texture unit     3       19       Layers::compose, HostLayers::composeOver, 2D
//   shimmer            texture unit     4       20       Layers::compose, HostLayers::composeOver, 2D
//   resolveSource      texture unit     0       16       Layers::resolveOpaque, HostLayers::resolveHostDepth (2D or 2D
//                                                        multisample, then 2D)
//   historyFirst       texture units    0-7     16-23    Layers::blendHistory: units historyFirst + slot, 2D
//   cartoonBlock       uniform buffer   3       11       Layers::compose with a CartoonCompose
//   cartoonFirst       texture units    5-7     21-23    Layers::compose with a CartoonCompose: 2D (the third
//                                                        an unsigned integer texture), with compose's units
//
// The programs' blocks and samplers are pointed at these after linking (the shaders'
// `layout(binding = N)` values are never used); a host may still set a point on its own. Points
// read by one call must differ (Renderer::draw's six units, its two uniform buffers; compose's five
// units and the cartoon's three, its two uniform buffers); calls may share points. create() checks
// them against GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS and GL_MAX_UNIFORM_BUFFER_BINDINGS /
// GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS.
#pragma once

#include <puff/core/binding_base.h>
#include <puff/core/error.h>
#include <puff/core/host_state.h>

namespace puff::media {

struct Bindings {
  /// Each point's offset from its kind's base.
  struct Offset {
    static constexpr unsigned mediaBlock = 3, materialBlock = 4, composeBlock = 5, cartoonBlock = 3;  // uniform
    static constexpr unsigned particles = 0;                                                          // storage
    static constexpr unsigned depth = 0, blackbody = 1, phase = 2, temperatureDetail = 3, opacityDetail = 4,
                              falloff = 5, opaqueColor = 0, opaqueDepth = 1, mediaLayer = 2, mediaDepth = 3,
                              shimmer = 4, resolveSource = 0, historyFirst = 0, cartoonFirst = 5;  // texture units
  };
  static constexpr core::BindingBase kDefaultBase{};

  /// uniform buffer bindings (Renderer::draw)
  unsigned mediaBlock = kDefaultBase.uniformBuffer + Offset::mediaBlock;
  unsigned materialBlock = kDefaultBase.uniformBuffer + Offset::materialBlock;
  unsigned particles = kDefaultBase.storageBuffer + Offset::particles;  ///< storage buffer binding (Renderer::draw)
  /// texture units (Renderer::draw)
  unsigned depth = kDefaultBase.textureUnit + Offset::depth, blackbody = kDefaultBase.textureUnit + Offset::blackbody,
           phase = kDefaultBase.textureUnit + Offset::phase,
           temperatureDetail = kDefaultBase.textureUnit + Offset::temperatureDetail,
           opacityDetail = kDefaultBase.textureUnit + Offset::opacityDetail,
           falloff = kDefaultBase.textureUnit + Offset::falloff;
  /// uniform buffer binding (Layers::compose, HostLayers::composeOver)
  unsigned composeBlock = kDefaultBase.uniformBuffer + Offset::composeBlock;
  /// texture units (compose)
  unsigned opaqueColor = kDefaultBase.textureUnit + Offset::opaqueColor,
           opaqueDepth = kDefaultBase.textureUnit + Offset::opaqueDepth,
           mediaLayer = kDefaultBase.textureUnit + Offset::mediaLayer,
           mediaDepth = kDefaultBase.textureUnit + Offset::mediaDepth,
           shimmer = kDefaultBase.textureUnit + Offset::shimmer;
  /// unit (Layers::resolveOpaque, HostLayers::resolveHostDepth)
  unsigned resolveSource = kDefaultBase.textureUnit + Offset::resolveSource;
  /// first of 8 consecutive units (Layers::blendHistory)
  unsigned historyFirst = kDefaultBase.textureUnit + Offset::historyFirst;
  /// uniform buffer binding (Layers::compose, cartoon style)
  unsigned cartoonBlock = kDefaultBase.uniformBuffer + Offset::cartoonBlock;
  /// first of 3 consecutive units (Layers::compose, cartoon style)
  unsigned cartoonFirst = kDefaultBase.textureUnit + Offset::cartoonFirst;
  bool operator==(const Bindings&) const = default;

  /// Every point at its offset from `base`.
  static constexpr Bindings at(const core::BindingBase& base) {
    const unsigned u = base.uniformBuffer, t = base.textureUnit;
    return {.mediaBlock = u + Offset::mediaBlock,
            .materialBlock = u + Offset::materialBlock,
            .particles = base.storageBuffer + Offset::particles,
            .depth = t + Offset::depth,
            .blackbody = t + Offset::blackbody,
            .phase = t + Offset::phase,
            .temperatureDetail = t + Offset::temperatureDetail,
            .opacityDetail = t + Offset::opacityDetail,
            .falloff = t + Offset::falloff,
            .composeBlock = u + Offset::composeBlock,
            .opaqueColor = t + Offset::opaqueColor,
            .opaqueDepth = t + Offset::opaqueDepth,
            .mediaLayer = t + Offset::mediaLayer,
            .mediaDepth = t + Offset::mediaDepth,
            .shimmer = t + Offset::shimmer,
            .resolveSource = t + Offset::resolveSource,
            .historyFirst = t + Offset::historyFirst,
            .cartoonBlock = u + Offset::cartoonBlock,
            .cartoonFirst = t + Offset::cartoonFirst};
  }
};
static_assert(Bindings{} == Bindings::at(Bindings::kDefaultBase));

/// The extent a core::HostStateGuard needs to save every point of `b`.
core::GuardExtent guardExtent(const Bindings& b);

/// Checks `b`: "media::Bindings.NAME: ...". Renderer::create, Layers::create and HostLayers::create return this
/// error. Needs a current GL context.
Result<void> validate(const Bindings& b);

}  // namespace puff::media
