// A rectangle of a framebuffer in pixels, as glViewport takes it: every Puff call that draws into a
// region of a target takes one of these.
#pragma once

namespace puff::core {

struct Viewport {
  int x = 0, y = 0, width = 0, height = 0;  ///< pixels, GL convention (origin bottom-left)
  bool operator==(const Viewport&) const = default;
};

}  // namespace puff::core
