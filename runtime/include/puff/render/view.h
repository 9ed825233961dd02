// The view transform on the GPU (docs/colour.md): a scene-linear frame (a SceneRenderer's
// drawFrame into a float target) to display values in the bound framebuffer, for a window. Files
// take the CPU form, core::viewTransform, which computes the same formulas in double precision.
#pragma once

#include <puff/cel/types.h>
#include <puff/core/colour.h>
#include <puff/core/error.h>
#include <puff/core/gl.h>

namespace puff::render {

class ViewPass {
 public:
  /// Errors: the program does not build (needs GL 4.5).
  static Result<ViewPass> create();

  /// Writes viewTransform(texel) of `linear` (a single-sample texture of viewport's size, scene-linear)
  /// over `viewport` of the current draw framebuffer. Sets and leaves: program 0, no depth or stencil
  /// test, no blend, no scissor, colour writes on.
  void draw(core::GlId linear, const cel::Viewport& viewport, core::ViewTransform view) const;

 private:
  core::Program program_;
  core::VertexArray vao_;
};

}  // namespace puff::render
