// Internal: the tumbling hull's field (shaders/cel/hull_march.glsl reads it; NailboardRenderer::setAtlas
// builds and uploads it for an atlas of several views).
//
// An oriented puff lies inside what every baked view bounds: the view's silhouette swept along its
// direction (the distance map) and before its far side (the back map), and inside its unit sphere.
// The intersection is a hull of all the views, close to the puff where the views are many, and it does
// not depend on where the eye is: it is sampled once per variation on a grid over the puff's cube,
// each point holding the largest of the bounds' distances there (about the distance to the hull,
// diameters; > 0 outside). The eye ray is marched through it with one filtered read a step.
// The views' front surfaces are left out: a texel holds the mean height of the surface it covers, less
// than the surface's highest point where the surface is steep in that view, so a view's front cuts
// into the puff that other views see face on (coverage IoU 0.91 against 0.985 without them, a
// lumpy puff over the oct 7 x 7 sweep). A bay that faces the eye stays filled: the hit is drawn there.
#pragma once

#include <vector>

#include <glm/vec4.hpp>

#include <puff/core/atlas.h>
#include <puff/core/error.h>
#include <puff/core/gl.h>

namespace puff::cel::detail {

// The field's largest value (diameters): a point farther out stores this, as does one whose bounds
// reach it before every view is read. A lower bound of the distance stays a safe step; a miss this
// near the hull or nearer is measured on the screen near the ink's edge (hull_march.glsl,
// screenDistance), so a puff whose ink and pixel reach past it (puffs under about 12 px with 2 px of
// ink) measures every miss there.
constexpr float kHullFieldReach = 0.25f;

struct HullField {
  core::HullFieldLayout layout;
  std::vector<float> values;  ///< the 3D texture's texels, x fastest, then y, then z; diameters
  /// Each variation's core: a ball inside its hull as the shader's filtered reads draw it (every
  /// grid cell the ball touches has all eight corners inside), centred on the grid's deepest point:
  /// puff-space centre (x, y, z) and radius (w), diameters. Radius 0: none.
  std::vector<glm::vec4> cores;
};

// A one-view atlas has no field: its cores are empty balls.
struct HullFieldTexture {
  core::Texture texture;         // none (0) for a one-view atlas
  std::vector<glm::vec4> cores;  // one a variation (HullField::cores)
};

// The field of every variation of `atlas` (several views; its "distance" map, and its "back" map if
// it has one, the same size) on core::hullFieldLayout's grid, from the maps' level 0 at 8 bits (the
// distance as the packed map holds it), the silhouettes' radius table `radii` (ShadowProfiles)
// beyond the distance map's range. Runs on every core.
HullField buildHullField(const core::Atlas& atlas, const std::vector<float>& radii);

// The field of a multi-view atlas as a 3D R16F texture, filtered linearly and clamped at its edges
// (the reader keeps to each variation's grid, shaders/cel/hull_march.glsl), and its cores; none (0)
// for a one-view atlas. Checks the back map (one channel, the distance map's size) and the GL's 3D texture size
// before building. Needs a current GL context; an error names the GL's (out of memory).
Result<HullFieldTexture> hullFieldTexture(const core::Atlas& atlas, const std::vector<float>& radii);

}  // namespace puff::cel::detail
