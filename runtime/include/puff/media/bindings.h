// The binding points the media path uses, chosen by the host (Renderer::create, Layers::create, HostLayers::create).
// No GL: a plain struct.
//
// Defaults (the shaders' own `layout(binding = N)` values; docs/media.md, "Host state"):
//
//   point              kind             default  read by
//   mediaBlock         uniform buffer   3        Renderer::draw (shaders/common/media.glsl)
//   materialBlock      uniform buffer   4        Renderer::draw
//   particles          storage buffer   0        Renderer::draw, the sorted particles
//   depth              texture unit     0        Renderer::draw, the host's linear depth, 2D
//   blackbody          texture unit     1        Renderer::draw, 1D
//   phase              texture unit     2        Renderer::draw, 2D
//   temperatureDetail  texture unit     3        Renderer::draw, 3D
//   opacityDetail      texture unit     4        Renderer::draw, 3D
//   falloff            texture unit     5        Renderer::draw (planar-textured), 2D
//   composeBlock       uniform buffer   5        Layers::compose, HostLayers::composeOver
//   opaqueColor        texture unit     0        Layers::compose, 2D
//   opaqueDepth        texture unit     1        Layers::compose, HostLayers::composeOver, 2D
//   mediaLayer         texture unit     2        Layers::compose, HostLayers::composeOver, 2D
//   mediaDepth         texture unit     3        Layers::compose, HostLayers::composeOver, 2D
//   shimmer            texture unit     4        Layers::compose, HostLayers::composeOver, 2D
//   resolveSource      texture unit     0        Layers::resolveOpaque, HostLayers::resolveHostDepth (2D or 2D
//                                                multisample, then 2D)
//   historyFirst       texture units    0-7      Layers::blendHistory: units historyFirst + slot, 2D
//   cartoonBlock       uniform buffer   3        Layers::compose with a CartoonCompose
//   cartoonFirst       texture units    5-7      Layers::compose with a CartoonCompose: 2D (the third
//                                                an unsigned integer texture), with compose's units
//
// The programs' blocks and samplers are pointed at these after linking. Points read by one call
// must differ (Renderer::draw's six units, its two uniform buffers; compose's five units and the
// cartoon's three, its two uniform buffers); calls
// may share points. create() checks them against GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS and
// GL_MAX_UNIFORM_BUFFER_BINDINGS / GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS.
#pragma once

#include <puff/core/error.h>
#include <puff/core/host_state.h>

namespace puff::media {

struct Bindings {
  unsigned mediaBlock = 3, materialBlock = 4;  ///< uniform buffer bindings (Renderer::draw)
  unsigned particles = 0;                      ///< storage buffer binding (Renderer::draw)
  unsigned depth = 0, blackbody = 1, phase = 2, temperatureDetail = 3, opacityDetail = 4, falloff = 5;  ///< units
  unsigned composeBlock = 5;  ///< uniform buffer binding (Layers::compose, HostLayers::composeOver)
  unsigned opaqueColor = 0, opaqueDepth = 1, mediaLayer = 2, mediaDepth = 3, shimmer = 4;  ///< units (compose)
  unsigned resolveSource = 0;  ///< unit (Layers::resolveOpaque, HostLayers::resolveHostDepth)
  unsigned historyFirst = 0;   ///< first of 8 consecutive units (Layers::blendHistory)
  unsigned cartoonBlock = 3;   ///< uniform buffer binding (Layers::compose, cartoon style)
  unsigned cartoonFirst = 5;   ///< first of 3 consecutive units (Layers::compose, cartoon style)
  bool operator==(const Bindings&) const = default;
};

/// The extent a core::HostStateGuard needs to save every point of `b`.
core::GuardExtent guardExtent(const Bindings& b);

/// Checks `b`: "media::Bindings.NAME: ...". Renderer::create, Layers::create and HostLayers::create return this
/// error. Needs a current GL context.
Result<void> validate(const Bindings& b);

}  // namespace puff::media
