// The cel reference as a render path of SceneRenderer.
#include <algorithm>

#include <puff/core/atlas.h>
#include <puff/eval/cel_reference.h>
#include <puff/render/cel_scene.h>
#include <puff/render/path.h>

#include "cel_reference_gl.h"

namespace puff::eval {

namespace {

class ReferencePath final : public render::Path {
 public:
  static Result<std::unique_ptr<render::Path>> create(const scene::Scene& scene, const scene::SceneGeometry& geometry,
                                                      const CelReferenceOptions& options) {
    std::unique_ptr<ReferencePath> p(new ReferencePath());
    if (!scene.atlas.empty()) {
      auto atlas = render::loadSceneAtlas(scene);
      if (!atlas) return atlas.error();
      p->variations_ = std::max(1, atlas->desc.variations);
      auto meshes = detail::atlasSourceMeshes(atlas->desc, scene.atlas);
      if (!meshes) return meshes.error();
      auto ref = detail::CelReference::create(std::move(*meshes), options);
      if (!ref) return ref.error();
      p->reference_ = std::move(*ref);
    } else if (scene::hasParticles(scene)) {
      return Error::at(scene.file, "/atlas: the scene has particles but names no atlas");
    }
    auto celScene = render::CelScene::create(scene, geometry);
    if (!celScene) return celScene.error();
    p->scene_ = std::move(*celScene);
    if (!p->reference_) {
      // Nothing to draw but objects: the reference still supersamples them like the puffs.
      auto ref = detail::CelReference::create({mesh::generateSphere(mesh::SphereParams{})}, options);
      if (!ref) return ref.error();
      p->reference_ = std::move(*ref);
    }
    return std::unique_ptr<render::Path>(std::move(p));
  }

  render::RenderPath kind() const override { return render::RenderPath::kReference; }
  // The reference supersamples instead of multisampling.
  render::TargetNeeds targetNeeds() const override { return {1, false}; }
  int variations() const override { return variations_; }

  bool needsRebuild(const scene::Scene& a, const scene::Scene& b) const override {
    return a.atlas != b.atlas || a.atlasLevel != b.atlasLevel || render::CelScene::needsRebuild(a, b);
  }

  Result<void> draw(const render::PathFrame& frame) override {
    GLint callerFbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &callerFbo);
    const cel::Viewport& viewport = frame.viewport;
    const cel::Frame f = scene_->prepare(frame.scene, frame.inputs, viewport,
                                         reference_->supersampledViewport(viewport.width, viewport.height));
    reference_->draw(f, scene_->block(), scene_->opaque(), frame.inputs.particles, frame.scene.style,
                     frame.scene.background, static_cast<GLuint>(callerFbo), viewport);
    return {};
  }

 private:
  ReferencePath() = default;
  std::unique_ptr<detail::CelReference> reference_;
  std::unique_ptr<render::CelScene> scene_;
  int variations_ = 0;  // 0: no atlas, no puffs
};

}  // namespace

Result<std::unique_ptr<render::SceneRenderer>> createCelReference(const scene::Scene& scene,
                                                                  const CelReferenceOptions& options) {
  PUFF_TRY(detail::validate(options));
  return render::SceneRenderer::create(scene, [options](const scene::Scene& s, const scene::SceneGeometry& g) {
    return ReferencePath::create(s, g, options);
  });
}

Result<std::unique_ptr<render::SceneRenderer>> createRenderer(const scene::Scene& scene, render::RenderPath path,
                                                              bool contextFramebuffer) {
  if (path == render::RenderPath::kReference) return createCelReference(scene);
  return render::SceneRenderer::create(scene, path, contextFramebuffer);
}

}  // namespace puff::eval
