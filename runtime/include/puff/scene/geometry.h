// The scene's objects as shapes: each object's mesh in object space, shared so that each mesh file
// is loaded once and each primitive made once. The cel path, the fixed path and the simulator's
// colliders all draw or collide with these (placed by objectTransform, evaluate.h).
#pragma once

#include <memory>
#include <vector>

#include <puff/core/error.h>
#include <puff/mesh/mesh.h>
#include <puff/scene/scene.h>

namespace puff::scene {

struct SceneGeometry {
  /// One per scene object, in order: the unit plane, box or sphere of puff::mesh (scaled by the
  /// object's transform), or the object's mesh file as loaded (normalized, as every puff mesh is).
  std::vector<std::shared_ptr<const mesh::TriMesh>> shapes;
};

/// Errors name the mesh file and why.
Result<SceneGeometry> loadGeometry(const Scene& scene);

}  // namespace puff::scene
