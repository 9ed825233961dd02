// Internal: the silhouettes' radius table the nailboards and their shadow volumes read
// (shaders/cel/particle.glsl, silhouetteRadius; NailboardRenderer::setAtlas uploads it).
#pragma once

#include <vector>

#include <puff/core/atlas.h>

namespace puff::cel::detail {

constexpr int kPolar = 32;  // directions of the silhouette radius table (shaders/cel/particle.glsl)

// Per cell, for the shadow volumes (whose start cap reads the depth map itself): the silhouette's radius (puff
// diameters) in kPolar directions, counter-clockwise from the cell's +x (y up), evenly spaced in diamond angle.
// Marching outward from the centre, the radius is the last crossing of the silhouette, so a puff with bays casts the
// shadow of its star-shaped hull.
struct ShadowProfiles {
  std::vector<float> radii;  ///< kPolar per cell, cell-major
};

ShadowProfiles shadowProfiles(const core::Atlas& atlas);

}  // namespace puff::cel::detail
