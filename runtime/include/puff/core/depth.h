// What a depth attachment stores, shared by the cel path (which writes the host's depth buffer)
// and the media path (which reads it). Puff computes every depth in LINEAR space,
// (distance - near) / (far - near) along the view axis; a host keeps one of three conventions and
// Puff converts per pixel (docs/embedding.md, "Depth"; cel/frame.h has the precision table).
#pragma once

#include <glm/mat4x4.hpp>

namespace puff::core {

/// What the depth attachment stores.
enum class DepthConvention {
  kLinear,    ///< Puff's own, the paper's: linear depth; test LESS, clear to 1
  kStandard,  ///< the projection's window depth (hyperbolic in perspective); test LESS, clear to 1
  kReversedZ  ///< the projection's window depth, near -> 1, far -> 0 (far may be infinite); GREATER, clear to 0
};

/// The clip-space z range of the host's projection and glClipControl depth mode: [-1, 1] (the GL
/// default) or [0, 1] (glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)). Not used by kLinear.
enum class ClipDepth { kNegativeOneToOne, kZeroToOne };

/// A depth buffer's meaning: the convention, the projection that wrote it (kStandard, kReversedZ:
/// its z row must depend on z and w only; infinite far allowed) and linear depth's 0 and 1.
struct DepthSpace {
  DepthConvention convention = DepthConvention::kStandard;  ///< GL's own unless the host says otherwise
  ClipDepth clipDepth = ClipDepth::kNegativeOneToOne;
  glm::mat4 projection{1.0f};
  float nearPlane = 0.1f, farPlane = 100.0f;
};

/// What the attachment stores for linear depth `linear`: `linear` itself for kLinear; otherwise
/// the projection's window depth at distance near + max(linear, 0) * (far - near), clamped to
/// [0, 1]. The shaders' storeDepth (common/frame.glsl) in float.
float storedDepth(const DepthSpace& space, float linear);

/// The inverse: the linear depth of a stored value, clamped to [0, 1] (a stored far plane, or an
/// infinite one, reads as 1). The shaders' linearFromStored (media/host_depth.glsl) in float.
float linearFromStored(const DepthSpace& space, float stored);

}  // namespace puff::core
