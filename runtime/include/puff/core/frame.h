// What the cel and media frames share (cel::Frame and media::Frame extend it): the camera, the light,
// the ambient light, the depth convention and the viewport. A host that draws both fills one of
// these and copies it into each (cel::Frame{common}, media::Frame{common}), so one sun lights both.
//
// Colours a host passes to Puff are SCENE-LINEAR (core/colour.h): Rec. 709 primaries, linear in
// energy, >= 0 and not limited to 1. The cel path's Eq. 2 combines display values, as the paper
// does: it encodes what it is given (core::linearToSrgb) inside, the media path lights with it as it
// is. Images (ramps, gradients, atlas colour maps) keep their own encoding, display values.
//
// Binding points are not per frame: each renderer takes them once, at create time, from one
// core::BindingBase (core/bindings.h).
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <puff/core/depth.h>
#include <puff/core/viewport.h>

namespace puff::core {

/// One directional light.
struct Light {
  glm::vec3 direction{0.4f, 1.0f, 0.3f};  ///< world space, toward the light (normalized on use)
  glm::vec3 color{1.0f};                  ///< scene-linear, each >= 0 (the cel path's K_L)
  bool operator==(const Light&) const = default;
};

/// The ambient light's default, scene-linear: display 0.25 decoded (the cel paper's grey K_a).
inline constexpr float kDefaultAmbient = 0.05087609f;

struct SharedFrame {
  glm::mat4 view{1.0f};        ///< world -> camera
  glm::mat4 projection{1.0f};  ///< camera -> clip (perspective or orthographic; infinite far allowed)
  /// Linear depth's 0 and 1: the projection's near plane and, finite, its far plane (with an
  /// infinite-far projection, any finite distance past everything drawn that casts, receives or
  /// is lit).
  float nearPlane = 0.1f, farPlane = 100.0f;
  /// What the host's depth attachment stores. The default is GL's own, the window depth the host's
  /// projection writes through gl_Position (kStandard): a host that never says draws right over a
  /// standard depth buffer. Puff's own renderer says kLinear (cel/frame.h says why).
  DepthConvention depth = DepthConvention::kStandard;
  ClipDepth clipDepth = ClipDepth::kNegativeOneToOne;  ///< `projection`'s clip z range (kStandard, kReversedZ)
  /// Where in the target the frame is drawn: pixels, origin bottom-left. The media path casts its
  /// rays through these pixels' centres and reads the host's depth at the same pixels.
  Viewport viewport;
  Light light;
  /// The ambient light, scene-linear: the cel path's uniform K_a (unless a gradient replaces it),
  /// the media's isotropic in-scattered radiance.
  glm::vec3 ambient{kDefaultAmbient};

  /// Whether `projection` is orthographic: its clip w does not depend on z (a perspective
  /// projection's w row is (0, 0, -1, 0)).
  bool orthographic() const { return projection[2][3] == 0.0f; }
  /// The depth buffer's meaning in this frame.
  DepthSpace depthSpace() const { return {depth, clipDepth, projection, nearPlane, farPlane}; }
};

}  // namespace puff::core
