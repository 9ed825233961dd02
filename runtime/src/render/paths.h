// The render paths puff::render makes itself. Private to puff::render.
#pragma once

#include <memory>

#include <puff/core/error.h>
#include <puff/render/path.h>
#include <puff/scene/geometry.h>
#include <puff/scene/scene.h>

namespace puff::render::detail {

/// Nailboards, outlines, shadow volumes and the media pass. Needs GL 4.5.
Result<std::unique_ptr<Path>> createCelPath(const scene::Scene& scene, const scene::SceneGeometry& geometry);
/// The GL 1.x fixed-function path (see SceneRenderer::create for `contextFramebuffer`).
Result<std::unique_ptr<Path>> createFixedPath(const scene::Scene& scene, const scene::SceneGeometry& geometry,
                                              bool contextFramebuffer);

}  // namespace puff::render::detail
