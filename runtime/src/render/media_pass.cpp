#include "media_pass.h"

#include <tuple>

#include <puff/core/colour.h>
#include <puff/core/detail_video.h>
#include <puff/gl_api.h>
#include <puff/media/coverage.h>
#include <puff/scene/evaluate.h>

namespace puff::render::detail {

Result<std::unique_ptr<MediaPass>> MediaPass::create(const scene::Scene& scene) {
  const scene::MediaSpec& spec = *scene.media;
  std::unique_ptr<MediaPass> pass(new MediaPass());
  auto renderer = media::Renderer::create(spec.settings);
  if (!renderer) return Error::at(scene.file, "/media: " + renderer.error().message);
  std::optional<core::DetailVideo> temperature, opacity;
  if (!spec.temperatureDetail.empty()) {
    auto v = core::loadDetailVideo(spec.temperatureDetail);
    if (!v) return Error::at(scene.file, "/media/detail/temperature: " + v.error().message);
    temperature = std::move(*v);
  }
  if (!spec.opacityDetail.empty()) {
    auto v = core::loadDetailVideo(spec.opacityDetail);
    if (!v) return Error::at(scene.file, "/media/detail/opacity: " + v.error().message);
    opacity = std::move(*v);
  }
  (*renderer)->setDetail(temperature ? &*temperature : nullptr, opacity ? &*opacity : nullptr);
  if (auto ok = (*renderer)->setMaterials(
          scene::linearMediaMaterials(scene, temperature ? &*temperature : nullptr, opacity ? &*opacity : nullptr));
      !ok)
    return Error::at(scene.file, "/media/materials: " + ok.error().message);
  if (spec.settings.style == media::Style::kCartoon) {
    auto cartoon = media::cartoonCompose(spec.settings);
    if (!cartoon) return Error::at(scene.file, "/media/" + cartoon.error().message);
    pass->cartoon_ = std::move(*cartoon);
  }
  pass->renderer_ = std::move(*renderer);
  return pass;
}

MediaPass::~MediaPass() = default;

bool MediaPass::needsRebuild(const scene::Scene& a, const scene::Scene& b) {
  auto key = [](const scene::Scene& s) {
    const scene::MediaSpec& m = *s.media;
    return std::tie(m.settings, m.materials, m.temperatureDetail, m.opacityDetail, m.resolution, s.samples,
                    s.animation.period, s.animation.fps);
  };
  if (a.media.has_value() != b.media.has_value()) return true;
  return a.media && key(a) != key(b);
}

Result<media::Layers*> MediaPass::layers(const scene::Scene& scene, const cel::Viewport& viewport) {
  if (layers_ && layers_->width() == viewport.width && layers_->height() == viewport.height) return layers_.get();
  PUFF_TRY_ASSIGN(layers_,
                  media::Layers::create(viewport.width, viewport.height, scene.samples, scene.media->resolution));
  return layers_.get();
}

void MediaPass::draw(const scene::Scene& s, const scene::FrameInputs& inputs, const cel::Viewport& viewport,
                     GLuint target, FrameStats& stats) {
  const scene::MediaSpec& spec = *s.media;
  particles_ = inputs.media;
  // The scene's colours are display values; the media light in scene-linear (docs/colour.md).
  const media::Frame mf = scene::mediaFrameFor(s, inputs.camera, inputs.time, viewport.width, viewport.height);
  std::vector<media::ExplosionLight> lights;
  for (const scene::MediaLightSpec& l : spec.lights) {
    lights.push_back(media::ExplosionLight{l.center, l.radius, core::srgbToLinear(l.color), l.intensityAt(mf.time),
                                           l.modulate, l.fullAtBack});
  }
  const media::Style style = cartoon_ ? media::Style::kCartoon : media::Style::kPhotoreal;
  // The passes run over what the media cover (a small flame costs its own pixels, not the frame's).
  const media::PixelBox covered = overWholeFrame_ ? media::PixelBox{0, 0, mf.viewport.width, mf.viewport.height}
                                                  : media::coverage(mf, particles_, lights);
  if (overWholeFrame_) {
    layers_->setCoverage(std::nullopt);
  } else {
    layers_->setCoverage(covered, style, s.style.outlines ? s.style.outlineWidth : 0.0f);
  }
  stats.mediaCoveredPixels = covered.empty() ? 0
                                             : static_cast<std::size_t>(covered.x1 - covered.x0) *
                                                   static_cast<std::size_t>(covered.y1 - covered.y0);
  layers_->resolveOpaque();
  layers_->beginMedia(style);
  media::DrawStats ds;
  renderer_->draw(layers_->layerFrame(mf), particles_, spec.method, layers_->mediaDepth(),
                  spec.compose.shimmerPixels > 0.0f ? media::Shimmer::kWritten : media::Shimmer::kOff, &ds);
  const core::Viewport& vp = viewport;
  if (cartoon_) {
    // The ink is the cel path's: the scene's outline switch, width and colour (a display value).
    cartoon_->style.outlines = s.style.outlines;
    cartoon_->style.outlineWidth = s.style.outlineWidth;
    cartoon_->style.outlineColor = scene::celStyleFor(s).outlineColor;
  }
  layers_->compose(target, vp, mf, lights, spec.compose, cartoon_ ? &*cartoon_ : nullptr);
  lastFrame_ = mf;
  stats.mediaParticles = ds.particles;
}

void MediaPass::setFillRateFloor(bool on) { renderer_->setFillRateFloor(on); }

Result<MediaFrameInputs> MediaPass::lastFrame() const {
  if (!layers_ || !lastFrame_) return Error{"no frame with media has been drawn yet"};
  MediaFrameInputs in;
  in.frame = *lastFrame_;
  in.particles = particles_;
  const std::size_t n = static_cast<std::size_t>(layers_->width()) * static_cast<std::size_t>(layers_->height());
  in.opaqueColor.resize(n);
  in.opaqueDepth.resize(n);
  // A frame drawn over the media's coverage resolved the depth there only: the whole of it, as
  // the passes over the whole frame leave it, for the tools that read it back.
  layers_->setCoverage(std::nullopt);
  layers_->resolveOpaque();
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(layers_->opaqueColor(), 0, GL_RGB, GL_FLOAT, static_cast<GLsizei>(n * sizeof(glm::vec3)),
                    in.opaqueColor.data());
  glGetTextureImage(layers_->opaqueDepth(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(n * sizeof(float)),
                    in.opaqueDepth.data());
  if (cartoon_ && layers_->cartoonField() != 0) {
    std::vector<glm::vec2> field(n);
    glGetTextureImage(layers_->cartoonField(), 0, GL_RG, GL_FLOAT, static_cast<GLsizei>(n * sizeof(glm::vec2)),
                      field.data());
    in.cartoonOpacity.assign(n, 0.0f);
    const media::PixelBox box = layers_->cartoonFieldBox();  // beyond it, no medium
    const auto w = static_cast<std::size_t>(layers_->width());
    for (int y = box.y0; y < box.y1; ++y)
      for (int x = box.x0; x < box.x1; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x);
        in.cartoonOpacity[i] = field[i].x;
      }
  }
  if (const std::string e = core::drainGlErrors(); !e.empty()) return Error{"reading the opaque layer back: " + e};
  return in;
}

}  // namespace puff::render::detail
