// What a viewer sees of a SceneRenderer frame: renderFrame gives scene-linear RGBA; tests that
// assert display values (Eq. 2's palette, golden PNGs) look at it through a view transform.
#pragma once

#include <puff/core/colour.h>
#include <puff/core/image.h>

namespace puff::test {

inline core::Image display(const core::Image& linear, core::ViewTransform view = core::ViewTransform::kStandard) {
  return core::viewTransform(linear, view);
}

}  // namespace puff::test
