// The cel reference's GL side: puff meshes instanced at every particle, a two-pass shadow map that
// knows which puff each texel saw, true-silhouette outlines and the supersampled target. Its render
// path (reference_path.cpp) drives it; this header is private to puff::eval.
#pragma once

#include <filesystem>
#include <memory>
#include <span>
#include <vector>

#include <puff/cel/frame.h>
#include <puff/cel/opaque.h>
#include <puff/cel/shadow_map.h>  // cel::Bounds
#include <puff/cel/types.h>       // cel::Viewport
#include <puff/core/atlas.h>
#include <puff/core/error.h>
#include <puff/core/gl.h>
#include <puff/eval/cel_reference.h>
#include <puff/gl_api.h>
#include <puff/mesh/mesh.h>

namespace puff::eval::detail {

/// The puff mesh each variation of an atlas was baked from, at full detail: the file the sidecar
/// names (relative paths against the sidecar's folder; its fnv1a64 hash must match, or the atlas is
/// stale) or the generator's puff rebuilt from its recorded parameters. Normalized as the bake does.
/// Vertex colours where the mesh has them, else the source's defaultColor.
Result<std::vector<mesh::TriMesh>> atlasSourceMeshes(const core::AtlasDesc& desc, const std::filesystem::path& sidecar);

/// The world transform of a particle's puff (puff space -> world: translate, puff frame, size / 2),
/// as the nailboard programs place it: an unoriented puff wears its billboard's frame for `alignment`
/// (shaders/cel/particle.glsl billboardFrame), an oriented one its orientation.
glm::mat4 puffTransform(const cel::Particle& p, cel::Alignment alignment, const glm::mat4& view, bool orthographic);

/// Checks the options' ranges; the error names the option.
Result<void> validate(const CelReferenceOptions& options);

class CelReference {
 public:
  /// Uploads the meshes (one per variation) and builds the programs. Needs GL 4.5.
  static Result<std::unique_ptr<CelReference>> create(std::vector<mesh::TriMesh> meshes,
                                                      const CelReferenceOptions& options);
  ~CelReference();

  int supersample() const;

  /// Draws one frame into this object's supersampled target (made for `width` x `height` output
  /// pixels on first use): clear to `background`, the opaque objects lit (`opaque`, with the frame
  /// block, ramp and gradient the caller bound for a viewport of the SUPERSAMPLED size), the puffs,
  /// shadows and outlines per `style`; then box-filters it into `outputFbo` at `viewport`.
  /// `frame` must be the frame the caller uploaded (its viewport the supersampled one). The shadow map
  /// covers the puffs and `objectBounds` (the objects that fit it: CelScene::casterBounds).
  void draw(const cel::Frame& frame, cel::FrameBlock& block, cel::OpaqueRenderer& opaque,
            std::span<const cel::Particle> particles, const cel::Style& style, const glm::vec3& background,
            GLuint outputFbo, const cel::Viewport& viewport, const cel::Bounds& objectBounds = {});

  /// The last frame's linear depth at OUTPUT resolution: per output pixel the nearest of its
  /// supersamples (as the media layers resolve MSAA depth), rows bottom-up (GL order), >= 1 where
  /// nothing was drawn. Empty before the first draw.
  std::vector<float> outputDepth() const;

  /// The supersampled viewport for an output of width x height.
  cel::Viewport supersampledViewport(int width, int height) const;

 private:
  CelReference();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace puff::eval::detail
