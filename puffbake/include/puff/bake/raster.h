// Rasterizes puff meshes with OpenGL into supersampled sample buffers (the GL half of baking).
// Needs a current GL 4.5 context; all GL objects are owned here and released on destruction.
#pragma once

#include <memory>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <puff/bake/maps.h>
#include <puff/core/error.h>
#include <puff/core/gl.h>
#include <puff/mesh/mesh.h>

namespace puff::bake {

/// Which surfaces a PuffRasterizer draws: the front alone, or the far side too (render's `back`).
enum class RasterSides { kFront, kFrontAndBack };

class PuffRasterizer {
 public:
  /// Builds the bake programs (the front surface's, and the far side's for render's `back`) and a
  /// `samplesPerSide`-square float framebuffer. Errors: the program
  /// does not build, or the size exceeds GL_MAX_RENDERBUFFER_SIZE / GL_MAX_TEXTURE_SIZE.
  /// kFrontAndBack: also the far side's program and target (render's `back`).
  static Result<std::unique_ptr<PuffRasterizer>> create(int samplesPerSide, RasterSides sides = RasterSides::kFront);

  /// Uploads a mesh; vertices without colours get `defaultColor`.
  void setMesh(const mesh::TriMesh& mesh, const glm::vec3& defaultColor);

  /// Draws the mesh seen through `viewRotation` (rows: right, up, toward viewer) so the unit
  /// square [-1,1]^2 fills the square of `contentSamples` samples starting `marginSamples` from the
  /// buffer's top-left corner, and reads the samples back. kFrontAndBack (only if created with it): also each
  /// sample's farthest crossing with the mesh (SampleBuffer::back, for the back map), in a second
  /// draw; without it SampleBuffer::back is left empty.
  void render(const glm::mat3& viewRotation, int marginSamples, int contentSamples, SampleBuffer& out,
              RasterSides sides = RasterSides::kFront);

  int samplesPerSide() const { return size_; }

 private:
  PuffRasterizer() = default;
  int size_ = 0;
  int indexCount_ = 0;
  bool hasColors_ = false;
  glm::vec3 defaultColor_{1.0f};
  core::Program program_, backProgram_;
  core::Framebuffer fbo_, backFbo_;
  core::Texture normalDepthTex_, colorTex_, backTex_;
  core::Renderbuffer depthRb_;
  core::VertexArray vao_;
  core::Buffer vbo_, ibo_;
  int viewRotationLoc_ = -1, backViewRotationLoc_ = -1;
};

}  // namespace puff::bake
