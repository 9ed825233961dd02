// The media pass of the cel path: fire, smoke and dust drawn as spherical billboards into the
// low-resolution layer and composed over the opaque pass (puff::media). Private to puff::render.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include <puff/core/error.h>
#include <puff/core/gl.h>
#include <puff/gl_api.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>
#include <puff/render/path.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/scene.h>

namespace puff::render::detail {

class MediaPass {
 public:
  /// The media renderer with the scene's materials and detail videos. Needs GL 4.5. Errors name the
  /// scene field or the detail video.
  static Result<std::unique_ptr<MediaPass>> create(const scene::Scene& scene);
  ~MediaPass();

  /// The reload rule: what create loaded (settings, materials, detail videos) and what the layers
  /// were made with (samples, resolution).
  static bool needsRebuild(const scene::Scene& current, const scene::Scene& next);

  /// The layers for a viewport of this size, made on first use and again when the size changes.
  Result<media::Layers*> layers(const scene::Scene& scene, const cel::Viewport& viewport);
  /// Draws the frame's media over the opaque pass already in the layers and composes the result
  /// into `target` at `viewport`.
  void draw(const scene::Scene& scene, const scene::FrameInputs& inputs, const cel::Viewport& viewport, GLuint target,
            FrameStats& stats);
  void setFillRateFloor(bool on);
  /// The passes over the whole frame instead of the media's coverage (SceneRenderer::setMediaOverWholeFrame).
  void setOverWholeFrame(bool on) { overWholeFrame_ = on; }
  Result<MediaFrameInputs> lastFrame() const;

 private:
  MediaPass() = default;
  std::unique_ptr<media::Renderer> renderer_;
  std::unique_ptr<media::Layers> layers_;
  std::vector<media::Particle> particles_;  // of the last frame drawn
  std::optional<media::Frame> lastFrame_;   // the full-size frame of the last draw
  bool overWholeFrame_ = false;
  std::optional<media::CartoonCompose> cartoon_;  // the cartoon style's compose, when the scene has it
};

}  // namespace puff::render::detail
