// The binding points the cel passes use, chosen by the host (NailboardRenderer::create,
// OpaqueRenderer::create, FrameBlock, ShadowMap, Ramp::bind, Gradient::bind). No GL: a plain struct.
//
// Defaults (the shaders' own `layout(binding = N)` values; docs/cel-rendering.md, "Host state"):
//
//   point                kind             default  read by
//   frameBlock           uniform buffer   0        every cel program (shaders/common/frame.glsl)
//   particles            storage buffer   0        nailboards, shadow volumes, casters (particle.glsl)
//   cells                storage buffer   1        the same (the atlas's cell table)
//   ramp                 texture unit     0        q, 1D (Ramp::bind)
//   gradient             texture unit     1        K_a(x, y), 2D (Gradient::bind)
//   atlasPacked          texture unit     2        the atlas's normal/depth/distance map, 2D
//   atlasColor           texture unit     3        the atlas's colour map, 2D
//   atlasBack            texture unit     4        the atlas's back map, 2D (tumbling hull only)
//   shadowProfile        texture unit     5        the silhouettes' radius table, 2D
//   shadowMapDepth       texture unit     6        ShadowMap::bind, 2D depth
//   shadowMapIds         texture unit     7        ShadowMap::bind, 2D R32UI
//
// The renderers point their programs' blocks and samplers at these after linking
// (glUniformBlockBinding, glShaderStorageBlockBinding, glProgramUniform1i), so the shaders keep
// their defaults in source. The texture units must all differ (one program reads up to all eight),
// as must the two storage buffers; the uniform buffer is alone. create() checks them against the
// GL's GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, GL_MAX_UNIFORM_BUFFER_BINDINGS and
// GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS. Every object that binds (FrameBlock, Ramp, Gradient,
// ShadowMap) must be given the same Bindings as the renderers that read them.
#pragma once

#include <puff/core/error.h>
#include <puff/core/host_state.h>

namespace puff::cel {

struct Bindings {
  unsigned frameBlock = 0;  ///< uniform buffer binding of the frame's block
  unsigned particles = 0;   ///< storage buffer binding of the packed particles
  unsigned cells = 1;       ///< storage buffer binding of the atlas's cells
  unsigned ramp = 0;        ///< texture unit of the ramp q
  unsigned gradient = 1;    ///< texture unit of the ambient gradient
  unsigned atlasPacked = 2;
  unsigned atlasColor = 3;
  unsigned atlasBack = 4;
  unsigned shadowProfile = 5;
  unsigned shadowMapDepth = 6;
  unsigned shadowMapIds = 7;
  bool operator==(const Bindings&) const = default;
};

/// The extent a core::HostStateGuard needs to save every point of `b` (and the defaults' draw
/// buffers).
core::GuardExtent guardExtent(const Bindings& b);

/// Checks `b` (distinct where it must be, within the GL's limits): "cel::Bindings.NAME: ...".
/// The renderers' create() returns this error. Needs a current GL context.
Result<void> validate(const Bindings& b);

}  // namespace puff::cel
