#include <puffview/paths.h>

namespace puff::view {

namespace {

class CelPath final : public ScenePath {
 public:
  explicit CelPath(std::unique_ptr<render::SceneRenderer> renderer) : renderer_(std::move(renderer)) {}
  void draw(int frame, const cel::Viewport& viewport, render::FrameStats* stats, const cel::Camera* camera) override {
    renderer_->drawFrame(frame, viewport, stats, camera);
  }
  Result<void> update(const render::Scene& scene) override { return renderer_->update(scene); }

 private:
  std::unique_ptr<render::SceneRenderer> renderer_;
};

}  // namespace

const std::vector<RenderPathInfo>& renderPaths() {
  static const std::vector<RenderPathInfo> paths = {
      {"cel", "nailboards with cel shading, outlines and billboard shadow volumes (McGuire & Fein 2006)"},
  };
  return paths;
}

Result<std::unique_ptr<ScenePath>> createPath(const std::string& name, const render::Scene& scene) {
  if (name == "cel") {
    auto renderer = render::SceneRenderer::create(scene);
    if (!renderer) return renderer.error();
    return std::unique_ptr<ScenePath>(std::make_unique<CelPath>(std::move(*renderer)));
  }
  std::string list;
  for (const RenderPathInfo& p : renderPaths()) list += (list.empty() ? "" : ", ") + p.name;
  return Error{"unknown render path \"" + name + "\" (available: " + list + ")"};
}

}  // namespace puff::view
