// The plate drawn by the programmable (cel) path: the plate stretched to the viewport, uploaded once
// per viewport size, written over the viewport after the clear. Private to puff::render.
#pragma once

#include <puff/cel/types.h>
#include <puff/core/error.h>
#include <puff/core/gl.h>
#include <puff/core/image.h>
#include <puff/scene/scene.h>

namespace puff::render::detail {

class PlatePass {
 public:
  /// Loads the scene's plate (render::loadPlate: its errors) and builds the program.
  static Result<PlatePass> create(const scene::Scene& scene);

  /// Writes the plate's scene-linear colour, alpha 1, over `viewport` of the current draw
  /// framebuffer; depth and stencil are not touched. Leaves: program 0, vertex array 0, unit 0's 2D
  /// texture, depth test, depth mask, stencil test and blend as they were.
  void draw(const cel::Viewport& viewport);

 private:
  core::Image linear_;  // the plate as read, scene-linear RGBA
  core::Program program_;
  core::VertexArray vao_;
  core::Texture texture_;  // linear_ stretched to the last viewport's size
  int width_ = 0, height_ = 0;
};

}  // namespace puff::render::detail
