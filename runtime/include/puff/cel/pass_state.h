// GL state shared by the cel passes (nailboards, shadow casters and volumes, opaque objects). Each
// pass sets every state it relies on, never trusting what the previous pass or the host left. Public
// so that a pass drawn alongside them (the cel reference in puff::eval, a host's own) sets the same
// state.
#pragma once

#include <puff/cel/nailboards.h>
#include <puff/core/gl.h>

namespace puff::cel {

/// The state every cel pass starts from: no blending on draw buffer 0 (the only one a pass draws;
/// core::DrawBufferZero), no culling, scissor, depth clamp, polygon
/// offset, alpha-to-coverage, rasterizer discard or primitive restart; filled polygons; depth range
/// [0, 1] (the window depth every depth convention assumes); depth test on. GL_FRAMEBUFFER_SRGB is
/// left as the host has it (the shaders write scene-linear colour; docs/colour.md).
void resetPassState();

/// Depth, stencil and colour state of `pass`: kLit depth nearer + write; kShadowed depth EQUAL, no
/// depth write, stencil != 0, stencil writes off; kDepthOnly depth nearer + write, no colour.
/// "Nearer" is nearerDepthFunc(boundDepthConvention()): LESS, or GREATER for reversed-z.
/// Returns the pass number the opaque objects' uPass uniform takes (0, 1, 2; the nailboards compile
/// one program per pass instead).
int applyShadePass(ShadePass pass);

/// Write masks back on (depth, draw buffer 0's colour, stencil), as GL starts: a host's glClear
/// after a pass that turned them off must not be silently masked. Other draw buffers' masks are the
/// host's.
void restoreWriteMasks();

}  // namespace puff::cel
