// The plain values the cel path speaks and a scene file describes: camera, light, viewport, a
// particle, the style. No GL: puff::scene and tools include this without a context.
#pragma once

#include <string_view>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <puff/core/error.h>
#include <puff/core/frame.h>
#include <puff/core/viewport.h>

namespace puff::cel {

struct Camera {
  glm::vec3 position{0.0f, 0.0f, 5.0f};  ///< world space
  glm::vec3 target{0.0f};                ///< point looked at
  glm::vec3 up{0.0f, 1.0f, 0.0f};        ///< world up hint; must not be parallel to target - position
  float fovYDegrees = 45.0f;             ///< vertical field of view, (0, 180); 0 means orthographic
  float orthoHeight = 2.0f;              ///< world-space height of the view when orthographic
  float nearPlane = 0.1f;                ///< > 0
  float farPlane = 100.0f;               ///< > nearPlane

  glm::mat4 view() const;
  glm::mat4 projection(float aspect) const;  ///< aspect = width / height
  bool operator==(const Camera&) const = default;
};

/// The directional light: K_L, scene-linear (core/frame.h).
using Light = core::Light;

using core::Viewport;

/// One particle as a host or simulator holds it.
struct Particle {
  glm::vec3 position{0.0f};  ///< world space, centre of the puff
  float size = 1.0f;         ///< world-space diameter of the puff; >= 0 (0 draws nothing)
  int variation = 0;         ///< atlas variation, [0, 255]; taken modulo the atlas's variations
  /// false: the puff always shows its front view, upright on the billboard (the paper's particles).
  /// true: `orientation` turns the puff in the world; a multi-view atlas shows it from the side
  /// the camera sees, blending the nearest baked views, so it tumbles in 3D.
  bool oriented = false;
  glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};  ///< puff space -> world; unit quaternion
  /// Multiplies the puff's colour C in Eq. 2 (K_a + C K_L q): scene-linear, each channel in [0, 1]
  /// (clamped), white = untinted. Eq. 2 takes it encoded (core::linearToSrgb), drawn with 7 bits
  /// a channel of the display value (steps of 1/127).
  glm::vec3 tint{1.0f};
};

/// How a billboard turns toward the camera (Real-Time Rendering §10.6).
enum class Alignment {
  kViewPlane,  ///< parallel to the image plane, screen up (the paper's; default)
  kViewpoint,  ///< facing the camera position, world up projected
  kAxial,      ///< rotates only about world up (y), facing the camera
};
std::string_view toString(Alignment a);

/// How a cel frame draws shadows (docs/cel-rendering.md, "Shadows").
enum class ShadowMethod {
  /// McGuire & Fein's billboard shadow volumes counted in the stencil buffer (§4.3): exact to the
  /// puff's silhouette at any distance, but each volume fills its whole prism on screen, twice.
  kVolumes,
  /// The puffs (and opaque objects) drawn from the light as nailboards into a light-space depth map
  /// with per-caster ids (cel::ShadowMap); receivers look it up in their lit pass. One extra pass
  /// over the casters at the map's resolution; shadows are as sharp as the map's texels.
  kMap,
};
std::string_view toString(ShadowMethod m);

/// How an oriented puff (one that tumbles) is drawn from a multi-view atlas between its baked views
/// (docs/cel-rendering.md, "Tumbling puffs").
enum class TumbleMethod {
  /// The eye ray marched through the hull of all the views (each view's silhouette swept along it and
  /// its far side bound the puff), sampled once per atlas: lumps keep their place and the ink its width
  /// between views. A few times the frame time of kBlend (docs/report/hull-costs.md);
  /// Style::hullFromPixels keeps it to the puffs large enough to need it.
  kHull,
  /// The four nearest views' maps turned to the billboard and blended: one read per view, but between
  /// views the silhouette is a blend of four and lumps are off by a few pixels.
  kBlend,
};
std::string_view toString(TumbleMethod m);

/// Style::hullFromPixels's largest value.
inline constexpr float kMaxHullFromPixels = 4096.0f;

/// The Fig. 8 progression and its knobs. Every effect toggles on its own.
struct Style {
  bool outlines = true;          ///< black flange (§4.2); off = the body's silhouette only
  float outlineWidth = 2.0f;     ///< pixels on screen, from the baked distance field; >= 0
  glm::vec3 outlineColor{0.0f};  ///< the ink, scene-linear, each in [0, 1]
  bool shading = true;           ///< Eq. 2 with q(max(0, N.L)); off = flat K_a + C * K_L
  bool shadows = false;          ///< shadows, by shadowMethod (the map, or the volumes of §4.3)
  /// How unoriented puffs' billboards face the camera; oriented ones always face the eye (their
  /// billboard only carries the rays the hull is marched along).
  Alignment alignment = Alignment::kViewPlane;
  /// Shadows start this far (in puff diameters) past the puff's own far side (as its depth map
  /// gives it), by either method, so a puff does not shadow itself. [0, 1].
  float shadowBias = 0.05f;
  /// World-space length of each shadow along the light; > 0. Volumes measure it from the puff's
  /// centre (a closed object's from its far side), the map from where the shadow starts (a
  /// puff's far side plus the bias, an object's near surface). Longer
  /// volumes cost fill rate; the map's cost does not depend on it.
  float shadowLength = 20.0f;
  /// The map by default: as close to the cel reference's exact shadows as the volumes on the art
  /// scenes, at a fraction of their cost (docs/cel-rendering.md, "Shadows: two methods").
  ShadowMethod shadowMethod = ShadowMethod::kMap;
  /// kMap: the map's texels per screen pixel of the casters' footprint (ShadowMap::chooseSize);
  /// [0.125, 4]. Smaller is cheaper and blockier.
  float shadowMapScale = 1.0f;
  /// Oriented puffs on a multi-view atlas: the hull by default (the closer to the puff's mesh).
  TumbleMethod tumble = TumbleMethod::kHull;
  /// With kHull: only oriented puffs at least this many pixels across on screen (one diameter at
  /// the puff's centre; in the shadow map's pass, texels of the map) take the hull, smaller ones
  /// the blend, whose error shrinks with the puff (docs/cel-rendering.md, "Hull or blend, puff by
  /// puff"). 0: every oriented puff takes the hull. [0, kMaxHullFromPixels].
  float hullFromPixels = 0.0f;
  bool operator==(const Style&) const = default;
};

/// Which colour a nailboard pass writes.
enum class ShadePass {
  kLit,        ///< Eq. 2 in full; depth test LESS (GREATER for reversed-z), depth written
  kShadowed,   ///< ambient only, depth test EQUAL, stencil != 0, no depth write (step 5 above)
  kDepthOnly,  ///< depth only (no colour), e.g. for a host's own shadow or depth pre-pass
};

}  // namespace puff::cel
