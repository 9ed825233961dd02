// What puffview's ramp and gradient editors edit, apart from their widgets: a cel ramp as a few flat
// bands (McGuire & Fein Eq. 2's q over N·L), an ambient gradient as a colour at the top of the frame
// and one at the bottom (K_a(x, y)), each to and from the image the renderer reads. Colours are
// display values (sRGB-encoded), as the images hold them.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include <puff/core/image.h>
#include <puff/scene/scene.h>

namespace puff::view {

/// A ramp of flat bands: band i holds `colors[i]` for N·L from `starts[i]` up to the next band's start
/// (the last to 1). starts[0] is 0 and the starts rise.
struct RampBands {
  std::vector<float> starts{0.0f, 0.5f};
  std::vector<glm::vec3> colors{glm::vec3(0.0f), glm::vec3(1.0f)};
  bool operator==(const RampBands&) const = default;
};

inline constexpr int kRampWidth = 256;
inline constexpr int kMaxRampBands = 16;

/// Puts the bands in order, the first starting at 0, starts in [0, 1]; at least one band, at most
/// kMaxRampBands.
RampBands normalized(RampBands bands);
/// The ramp image: kRampWidth x 1 RGB, texel i the colour of the band holding (i + 0.5) / width.
core::Image rampImage(const RampBands& bands);
/// The bands of a ramp image (its middle row, as the renderer reads it): each run of equal texels a
/// band. A smooth ramp (more runs than kMaxRampBands) is sampled into kMaxRampBands bands.
RampBands bandsFromImage(const core::Image& image);

/// An ambient gradient from the top of the frame to its bottom.
struct VerticalGradient {
  glm::vec3 top{0.35f, 0.3f, 0.5f}, bottom{0.25f, 0.35f, 0.6f};
  bool operator==(const VerticalGradient&) const = default;
};
inline constexpr int kGradientSize = 256;
/// kGradientSize x kGradientSize RGB, row y the mix of top and bottom at (y + 0.5) / size.
core::Image gradientImage(const VerticalGradient& g);
/// The top and bottom rows' mean colours of any gradient image.
VerticalGradient gradientFromImage(const core::Image& image);

/// Drops the curves over life an edit left that the scene would refuse (scene::parseScene): a
/// temperature curve on a media emitter whose material no longer emits (switched to another,
/// made to scatter, or set to become one that does not emit). Returns whether it dropped any.
bool dropRefusedCurves(scene::Scene& scene);

}  // namespace puff::view
