// The plate (output.plate): a picture drawn under the frame instead of a background colour, so a
// render composites onto a hand-drawn scene (McGuire & Fein 2006, Fig. 8d).
#pragma once

#include <puff/core/error.h>
#include <puff/core/image.h>
#include <puff/scene/scene.h>

namespace puff::render {

/// What a plate file may be, checked from its header before decoding: at most 8192 x 8192 pixels,
/// 1 to 4 channels, a file of at most 512 MiB (it is resampled to the frame).
inline constexpr core::ImageLimits kPlateLimits{"a plate", 8192, 8192, 4, 1ll << 26, std::uintmax_t{512} << 20};

/// The scene's plate read and decoded: its colour is display values (sRGB-encoded, as a paint
/// program saves them; 1 channel: grey, 2: grey + alpha, 3 or 4: RGB [+ alpha]); the result is
/// scene-linear RGBA with alpha 1 (the plate is opaque: a plate's own alpha is ignored). Errors name
/// the scene, the field's JSON pointer and the file: "scene.json: /output/plate: plate.png: ...".
/// The scene must name a plate.
Result<core::Image> loadPlate(const scene::Scene& scene);

/// `linear` (scene-linear, any channel count) stretched to `width` x `height`, each axis on its own
/// (a plate of another aspect ratio is distorted, never cropped): pixel centres map to pixel centres
/// (x' = (x + 0.5) * W / width - 0.5) and each output pixel is the tent-filtered mean of the source
/// around it, the tent as wide as one output pixel in source pixels (at least 1: bilinear when
/// enlarging, an area filter when shrinking), in scene-linear light, clamped at the edges. The same
/// size returns the image as it is.
core::Image resizePlate(const core::Image& linear, int width, int height);

}  // namespace puff::render
