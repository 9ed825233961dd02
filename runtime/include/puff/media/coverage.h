// What of a frame the media can change: the screen rectangle the media billboards and the
// explosions' lights cover. LayersBase::setCoverage limits the layers' full-screen passes (the depth
// resolve, the layer's depth, the compose and the cartoon style's field and ink) to it, padded by
// what each pass reads around a pixel, so a small flame costs what it covers, not the whole frame.
#pragma once

#include <span>

#include <puff/media/types.h>

namespace puff::media {

/// Pixels [x0, x1) x [y0, y1) of a frame (GL's window convention: origin bottom-left, relative to
/// the frame's viewport). Empty when x0 >= x1 or y0 >= y1.
struct PixelBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x0 >= x1 || y0 >= y1; }
  bool operator==(const PixelBox&) const = default;
};

/// The smallest box holding both (an empty one adds nothing).
PixelBox unite(const PixelBox& a, const PixelBox& b);
/// `box` grown by `pixels` on every side, then cut to [0, width) x [0, height).
PixelBox grow(const PixelBox& box, int pixels, int width, int height);

/// The pixels of `frame` (its width x height) that the media drawn with `frame` can change: every
/// particle's sphere, over the box its silhouette projects into (what any method's billboard can
/// change; shaders/media/billboard.vert sizes the spherical quad by it) for a perspective
/// projection of the usual form, else over the bound billboard.vert sizes its quads by, and every
/// light that shines (intensity and radius > 0; the first 8, as compose takes them)
/// over its sphere's projection. A sphere reaching the camera's plane covers the whole frame.
/// Particles without a radius, wholly nearer than the near plane or beyond the far plane cover
/// nothing (the billboards draw nothing for them). Rounded out to whole pixels and grown by one.
PixelBox coverage(const Frame& frame, std::span<const Particle> particles, std::span<const ExplosionLight> lights = {});

}  // namespace puff::media
