// Where shadow volumes can change anything: the receivers' box (the puffs' particles and the opaque
// objects, world space) seen by the frame, as a scissor rectangle (window pixels) and a range of
// the depth buffer's STORED depth (the frame's convention, common/frame.glsl's storeDepth: the range
// of linear depth [0, 1] the box covers, converted). Stencil counts outside the rectangle, or at
// pixels whose stored depth lies outside the range, never reach a receiver, so the volume passes
// skip them: a scissor test everywhere, and GL_EXT_depth_bounds_test where the GL has it (not Mesa
// llvmpipe), which rejects a pixel by its STORED depth before the fragment shader runs.
#pragma once

#include <puff/cel/frame.h>
#include <puff/cel/shadow_map.h>

namespace puff::cel {

struct VolumeClip {
  bool everything = true;                  ///< no clipping (no receivers' box given, or it reaches behind the eye)
  bool nothing = false;                    ///< the receivers are off screen or outside the depth range: draw nothing
  Viewport scissor;                        ///< window pixels, inside the frame's viewport
  float depthMin = 0.0f, depthMax = 1.0f;  ///< stored depth (the frame's convention), [0, 1]
};

/// The clip of `receivers` in `frame` (a pure function; no GL). An empty box clips nothing.
VolumeClip volumeClip(const Frame& frame, const Bounds& receivers);

/// Sets the scissor (and the depth bounds, where GL_EXT_depth_bounds_test is there) for a volume
/// pass; endVolumeClip turns both off. Needs a current GL context.
void beginVolumeClip(const VolumeClip& clip);
void endVolumeClip();
/// Whether the current GL has GL_EXT_depth_bounds_test (as glad loaded it).
bool hasDepthBoundsTest();

}  // namespace puff::cel
