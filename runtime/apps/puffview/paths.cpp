#include <puffview/paths.h>

namespace puff::view {

namespace {

// Both paths are puff::render::SceneRenderer. The fixed path sizes its puff texture from the
// frame (scene.width x scene.height, 2 x 2 cells drawn through the frame's own pixels), so it is
// built for the viewport it draws into, as puffrender builds it for the image size: a window of
// another size (or a resize) rebuilds it at that size.
class RendererPath final : public ScenePath {
 public:
  RendererPath(std::unique_ptr<render::SceneRenderer> renderer, const render::Scene& scene)
      : renderer_(std::move(renderer)), scene_(scene) {}

  void draw(int frame, const cel::Viewport& viewport, render::FrameStats* stats, const cel::Camera* camera) override {
    if (fixed()) fitTo(viewport.width, viewport.height);
    renderer_->drawFrame(frame, viewport, stats, camera);
  }

  Result<void> update(const render::Scene& scene) override {
    if (auto r = renderer_->update(sized(scene)); !r) return r;
    scene_ = scene;
    return {};
  }

  bool multisample() const override { return !fixed(); }

 private:
  bool fixed() const { return renderer_->path() == render::RenderPath::kFixed; }

  render::Scene sized(const render::Scene& scene) const {
    render::Scene s = scene;
    if (fixed() && width_ > 0) s.width = width_, s.height = height_;
    return s;
  }

  void fitTo(int width, int height) {
    if (width == width_ && height == height_) return;
    width_ = width, height_ = height;
    if (renderer_->scene().width == width && renderer_->scene().height == height) return;
    // A frame too small for the puff texture keeps the last size (drawing then fails, drawing nothing).
    (void)renderer_->update(sized(scene_));
  }

  std::unique_ptr<render::SceneRenderer> renderer_;
  render::Scene scene_;  // as edited, at the scene's own size
  int width_ = 0, height_ = 0;
};

}  // namespace

const std::vector<RenderPathInfo>& renderPaths() {
  static const std::vector<RenderPathInfo> paths = {
      {"cel", "nailboards with cel shading, outlines and billboard shadow volumes (McGuire & Fein 2006)"},
      {"fixed",
       "GL 1.x fixed function (McGuire & Fein 2006, 4.4): flat billboards of a per-frame puff texture, backing "
       "billboards for outlines; one light, uniform ambient, no shadows"},
  };
  return paths;
}

Result<std::unique_ptr<ScenePath>> createPath(const std::string& name, const render::Scene& scene) {
  if (auto path = render::parseRenderPath(name)) {
    auto renderer = render::SceneRenderer::create(scene, *path);
    if (!renderer) return renderer.error();
    return std::unique_ptr<ScenePath>(std::make_unique<RendererPath>(std::move(*renderer), scene));
  }
  std::string list;
  for (const RenderPathInfo& p : renderPaths()) list += (list.empty() ? "" : ", ") + p.name;
  return Error{"unknown render path \"" + name + "\" (available: " + list + ")"};
}

}  // namespace puff::view
