// Puff's colour pipeline (docs/colour.md): every value says which space it is in.
//
//  - DISPLAY values are sRGB-encoded (IEC 61966-2-1 transfer function) in [0, 1]: what an artist
//    picks in a paint program and what a PNG holds. Colours in files are display values: ramps,
//    gradients, scene-file colours, atlas colour maps, the background. Colours passed through the
//    renderers' API are scene-linear (core/frame.h); only the fixed path's are display values.
//  - SCENE-LINEAR values are light: Rec. 709 / sRGB primaries, D65 white, linear in energy, not
//    limited to [0, 1] (fire is brighter than white). Blending, filtering, mips, MSAA resolve,
//    media lighting and composition all happen here; the render target holds them; EXR files store
//    them.
//  - The VIEW TRANSFORM turns a scene-linear frame into display values once, at the end
//    (viewTransform below, the same formulas as shaders/common/colour.glsl).
//
// Cel shading (McGuire & Fein Eq. 2) is an artist's palette operation: it combines DISPLAY values as
// the paper does, then its result is decoded to scene-linear before anything blends it.
#pragma once

#include <optional>
#include <string_view>

#include <glm/vec3.hpp>

#include <puff/core/image.h>

namespace puff::core {

/// The sRGB transfer function (IEC 61966-2-1): display value -> scene-linear and back. Defined for
/// every real: negative values are mirrored (sign kept), values above 1 follow the same power law.
double srgbToLinear(double display);
double linearToSrgb(double linear);
glm::vec3 srgbToLinear(glm::vec3 display);
glm::vec3 linearToSrgb(glm::vec3 linear);

/// Rec. 709 luminance of a scene-linear colour.
double luminance(glm::dvec3 linear);

/// How a scene-linear frame becomes display values.
enum class ViewTransform {
  /// Clip each channel to [0, 1], then sRGB-encode. Exact for everything within range: a colour
  /// whose channels are all in [0, 1] keeps its chromaticity. The default for scenes without fire.
  kStandard,
  /// Hue-preserving highlight compression, then sRGB-encode. Colours whose largest channel is at or
  /// below kFilmicKnee pass unchanged (a cel palette keeps its look); above it the largest channel m
  /// is rolled off smoothly (C1 at the knee) towards 1 and all three channels are scaled by the same
  /// factor, so the chromaticity (hue and saturation) is kept exactly where fire saturates instead
  /// of clipping per channel. The default for scenes with fire.
  kFilmic,
};
inline constexpr double kFilmicKnee = 0.8;  ///< scene-linear (display 0.906)

std::string_view toString(ViewTransform v);
std::optional<ViewTransform> parseViewTransform(std::string_view name);  ///< "standard", "filmic"

/// The filmic shoulder on the largest channel: m for m <= kFilmicKnee, else
/// k + (1 - k)(1 - exp(-(m - k) / (1 - k))): continuous with slope 1 at the knee, rising, below 1
/// for every m (in doubles it rounds to 1 once exp(-(m - k) / (1 - k)) drops below epsilon: m > 8).
double filmicShoulder(double m);

/// One scene-linear colour through the view transform: display values in [0, 1] (negative
/// components clip to 0 first: they are outside the display's gamut).
glm::dvec3 viewTransform(glm::dvec3 linear, ViewTransform view);

/// A whole scene-linear image (RGB or RGBA; alpha passes through, clamped to [0, 1]) to display.
Image viewTransform(const Image& linear, ViewTransform view);

/// How colour relates to alpha in a file with transparency.
enum class AlphaMode {
  kStraight,       ///< colour as it is where covered, alpha beside it (PNG's convention)
  kPremultiplied,  ///< colour already multiplied by alpha (EXR's convention, "over" is C + (1 - a) B)
};
std::string_view toString(AlphaMode a);
std::optional<AlphaMode> parseAlphaMode(std::string_view name);  ///< "straight", "premultiplied"

/// A PREMULTIPLIED scene-linear RGBA frame (SceneRenderer::renderFrame of a transparent scene) to
/// straight scene-linear RGBA: colour / alpha, and colour 0 where alpha is 0 (nothing to divide;
/// alpha below 1/65536 counts as 0). Alpha clamped to [0, 1].
Image unpremultiply(const Image& premultiplied);

/// A PREMULTIPLIED scene-linear RGBA frame to display RGBA for an 8-bit file: the colour is
/// un-premultiplied, put through the view transform (as an opaque frame's is), and for kPremultiplied
/// multiplied by alpha again as a display value: out = display(C / a) * a. Display values composite
/// in display space, so a straight and a premultiplied file differ exactly by that product.
Image viewTransform(const Image& premultipliedLinear, ViewTransform view, AlphaMode alpha);

/// Display-encoded image (an 8-bit read-back, a PNG) to scene-linear: RGB decoded, alpha kept.
Image decodeSrgb(const Image& display);

}  // namespace puff::core
