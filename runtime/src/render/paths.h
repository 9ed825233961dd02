// The render paths puff::render makes itself. Private to puff::render.
#pragma once

#include <memory>

#include <puff/core/atlas.h>
#include <puff/core/error.h>
#include <puff/mesh/mesh.h>
#include <puff/render/path.h>
#include <puff/scene/geometry.h>
#include <puff/scene/scene.h>

namespace puff::render::detail {

/// Nailboards, outlines, shadows (the shadow map or the volumes) and the media pass. Needs GL 4.5.
Result<std::unique_ptr<Path>> createCelPath(const scene::Scene& scene, const scene::SceneGeometry& geometry);
/// The GL 1.x fixed-function path, drawing into `target` where the context allows.
Result<std::unique_ptr<Path>> createFixedPath(const scene::Scene& scene, const scene::SceneGeometry& geometry,
                                              DrawTarget target);
/// The one puff mesh the fixed path draws: `scene.fixed.puff` when set; else, with an atlas, the
/// level of detail its first variation was baked from (sources[0].lodMesh, written by puffbake --lod
/// auto), else that variation's source mesh file; with neither an atlas nor particles, a sphere.
/// Errors name the scene (no mesh to take) or the mesh file.
Result<mesh::TriMesh> fixedPuffMesh(const scene::Scene& scene, const core::Atlas* atlas);

}  // namespace puff::render::detail
