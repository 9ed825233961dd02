// The cel reference: the image nailboards approximate, drawn by a SceneRenderer like any path
// (render::RenderPath::kReference). Every particle is its actual puff mesh, shaded by Eq. 2 per
// pixel, inked around its true silhouette, with exact shadows from a shadow map that knows which
// puff each texel saw; supersampled, slow, GL 4.5, no media. docs/cel-rendering.md ("The
// reference") says what it draws and why.
#pragma once

#include <memory>

#include <puff/core/error.h>
#include <puff/render/render.h>
#include <puff/scene/scene.h>

namespace puff::eval {

/// How finely the cel reference samples.
struct CelReferenceOptions {
  int supersample = 3;       ///< samples per pixel side, box-filtered down; [1, 8]
  int shadowMapSize = 4096;  ///< texels per side of the shadow map over the puffs' bounding sphere; [256, 8192]
};

/// A renderer drawing `scene` as the cel reference, in the current GL 4.5 context. The atlas's
/// sources must still be where the sidecar says, unchanged (their hash is checked), or be its
/// generators' puffs. Errors name the file (scene, atlas, mesh) and why, or the option out of range.
Result<std::unique_ptr<render::SceneRenderer>> createCelReference(const scene::Scene& scene,
                                                                  const CelReferenceOptions& options = {});

/// A renderer for any path, the cel reference included (for tools that take a path by name); see
/// render::SceneRenderer::create for the others and `target`.
Result<std::unique_ptr<render::SceneRenderer>> createRenderer(
    const scene::Scene& scene, render::RenderPath path, render::DrawTarget target = render::DrawTarget::kOffscreen);

}  // namespace puff::eval
