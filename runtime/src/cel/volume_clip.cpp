#include <algorithm>
#include <cmath>

#include <puff/cel/volume_clip.h>
#include <puff/core/gl.h>
#include <puff/gl_api.h>

namespace puff::cel {

VolumeClip volumeClip(const Frame& frame, const Bounds& receivers) {
  VolumeClip c;
  if (receivers.empty()) return c;
  const glm::mat4 viewProj = frame.projection * frame.view;
  glm::vec2 lo(1e30f), hi(-1e30f);
  float dmin = 1e30f, dmax = -1e30f;
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 p((i & 1) ? receivers.hi.x : receivers.lo.x, (i & 2) ? receivers.hi.y : receivers.lo.y,
                      (i & 4) ? receivers.hi.z : receivers.lo.z);
    const glm::vec4 clip = viewProj * glm::vec4(p, 1.0f);
    // A corner at or behind the eye has no place on screen: the box may cover all of it.
    if (clip.w <= 1e-6f) return c;
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    lo = glm::min(lo, ndc);
    hi = glm::max(hi, ndc);
    const float d = linearDepth(frame, p);  // affine in the point: the corners bound the box
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
  }
  c.everything = false;
  const Viewport& v = frame.viewport;
  const auto toPixel = [](float ndc, int origin, int size) {
    return static_cast<float>(origin) + (ndc * 0.5f + 0.5f) * static_cast<float>(size);
  };
  const int x0 = std::max(v.x, static_cast<int>(std::floor(toPixel(lo.x, v.x, v.width))));
  const int y0 = std::max(v.y, static_cast<int>(std::floor(toPixel(lo.y, v.y, v.height))));
  const int x1 = std::min(v.x + v.width, static_cast<int>(std::ceil(toPixel(hi.x, v.x, v.width))));
  const int y1 = std::min(v.y + v.height, static_cast<int>(std::ceil(toPixel(hi.y, v.y, v.height))));
  c.scissor = Viewport{x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
  // The bounds test compares STORED depth: the frame's convention, whose conversion is monotonic
  // (decreasing for reversed-z, hence the min and max).
  const float s0 = storedDepth(frame, std::clamp(dmin, 0.0f, 1.0f)),
              s1 = storedDepth(frame, std::clamp(dmax, 0.0f, 1.0f));
  c.depthMin = std::min(s0, s1);
  c.depthMax = std::max(s0, s1);
  c.nothing = c.scissor.width == 0 || c.scissor.height == 0 || dmax < 0.0f || dmin > 1.0f;
  return c;
}

bool hasDepthBoundsTest() { return PUFF_GLAD_GL_EXT_depth_bounds_test != 0 && glDepthBoundsEXT != nullptr; }

void beginVolumeClip(const VolumeClip& clip) {
  if (clip.everything) return;
  glEnable(GL_SCISSOR_TEST);
  glScissor(clip.scissor.x, clip.scissor.y, clip.scissor.width, clip.scissor.height);
  if (hasDepthBoundsTest()) {
    glEnable(GL_DEPTH_BOUNDS_TEST_EXT);
    glDepthBoundsEXT(clip.depthMin, clip.depthMax);
  }
}

void endVolumeClip() {
  glDisable(GL_SCISSOR_TEST);
  if (hasDepthBoundsTest()) glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
}

}  // namespace puff::cel
