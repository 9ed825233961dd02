// The cel frame of Puff's own renderer for tests that check its linear depth (cel/frame.h,
// "Depth conventions"): Frame::fromCamera with the depth convention said, kLinear, since a
// frame's default is the GL standard depth a host's projection writes.
#pragma once

#include <puff/cel/frame.h>

namespace puff::test {

inline cel::Frame linearFrame(const cel::Camera& camera, int width, int height) {
  cel::Frame f = cel::Frame::fromCamera(camera, width, height);
  f.depth = cel::DepthConvention::kLinear;
  return f;
}

}  // namespace puff::test
