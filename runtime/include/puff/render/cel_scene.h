// What a cel frame of a scene needs besides its particles: the ramp q, the ambient gradient K_a,
// the opaque objects (moved along their paths each frame) and the frame block. The cel path and the
// cel reference (puff::eval) both draw with it, so they light the same world the same way.
#pragma once

#include <memory>
#include <optional>

#include <glm/vec4.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/opaque.h>
#include <puff/core/atlas.h>
#include <puff/core/error.h>
#include <puff/mesh/mesh.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/geometry.h>
#include <puff/scene/scene.h>

namespace puff::render {

/// The scene's atlas from its atlasLevel on. Errors name the sidecar, or /atlasLevel when the atlas
/// has no such level.
Result<core::Atlas> loadSceneAtlas(const scene::Scene& scene);

/// Oriented puffs (particles, emitters or simulator emitters with `oriented`) turn in 3D, which a
/// one-view atlas cannot show (it holds the front only: a turned puff would be a flat slab). The
/// error names the scene, the JSON pointer of the first oriented source, and the atlas.
Result<void> checkOrientedPuffs(const scene::Scene& scene, const core::AtlasDesc& atlas);

/// A puff::mesh mesh as the cel path's opaque renderer takes it.
std::shared_ptr<const cel::TriangleMesh> toTriangleMesh(const mesh::TriMesh& mesh);

class CelScene {
 public:
  /// Loads the scene's ramp (or the built-in two-tone one) and gradient and uploads its objects.
  /// Needs GL 4.5. Errors name the file (ramp, gradient) or the object.
  static Result<std::unique_ptr<CelScene>> create(const scene::Scene& scene, const scene::SceneGeometry& geometry);
  ~CelScene();

  /// The reload rule for what create loaded: the ramp, the gradient and the objects.
  static bool needsRebuild(const scene::Scene& current, const scene::Scene& next);

  /// The cel frame of `inputs` for an output of `viewport`'s size drawn at `drawViewport` (the
  /// reference supersamples): light and ambient from the scene, the ramp and gradient bound, objects
  /// on paths moved to where they are at this frame.
  cel::Frame prepare(const scene::Scene& scene, const scene::FrameInputs& inputs, const cel::Viewport& viewport,
                     const cel::Viewport& drawViewport);

  cel::OpaqueRenderer& opaque();
  cel::FrameBlock& block();
  /// The lowest horizontal plane object that does not move (shadow volumes may stop there; nothing
  /// below it is seen) as a plane equation, or all zeros when there is none.
  glm::vec4 floorPlane() const;
  /// The world box of the objects that fit the shadow map (all but planes, which would spread it
  /// over the whole ground), where they are at the last prepare. Planes still cast and receive
  /// inside it.
  cel::Bounds casterBounds() const;
  /// The world box of every object, planes included (the shadow map's depth range reaches them).
  cel::Bounds objectBounds() const;

 private:
  CelScene() = default;
  std::unique_ptr<cel::OpaqueRenderer> opaque_;
  cel::FrameBlock block_;
  std::optional<cel::Ramp> ramp_;
  std::optional<cel::Gradient> gradient_;
  glm::vec4 floorPlane_{0.0f};
  std::vector<bool> fitsShadowMap_;  // per object: not a plane
};

}  // namespace puff::render
