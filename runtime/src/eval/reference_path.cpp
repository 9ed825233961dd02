// The cel reference as a render path of SceneRenderer: the puffs as meshes (cel_reference_gl.h)
// and, for a scene with media, the physical media reference (reference/media_physical.h) integrated
// on the CPU over the reference's own colour and depth.
#include <algorithm>
#include <optional>

#include <puff/core/atlas.h>
#include <puff/core/colour.h>
#include <puff/core/detail_video.h>
#include <puff/eval/cel_reference.h>
#include <puff/gl_api.h>
#include <puff/reference/media_physical.h>
#include <puff/render/cel_scene.h>
#include <puff/render/path.h>
#include <puff/scene/evaluate.h>

#include "cel_reference_gl.h"

namespace puff::eval {

namespace {

class ReferencePath final : public render::Path {
 public:
  static Result<std::unique_ptr<render::Path>> create(const scene::Scene& scene, const scene::SceneGeometry& geometry,
                                                      const CelReferenceOptions& options) {
    std::unique_ptr<ReferencePath> p(new ReferencePath());
    if (!scene.atlas.empty()) {
      PUFF_TRY_ASSIGN(auto atlas, render::loadSceneAtlas(scene));
      p->variations_ = std::max(1, atlas.desc.variations);
      PUFF_TRY_ASSIGN(auto meshes, detail::atlasSourceMeshes(atlas.desc, scene.atlas));
      PUFF_TRY_ASSIGN(auto ref, detail::CelReference::create(std::move(meshes), options));
      p->reference_ = std::move(ref);
    } else if (scene::hasParticles(scene)) {
      return Error::at(scene.file, "/atlas: the scene has particles but names no atlas");
    }
    PUFF_TRY_ASSIGN(p->scene_, render::CelScene::create(scene, geometry));
    if (!p->reference_) {
      // Nothing to draw but objects: the reference still supersamples them like the puffs.
      PUFF_TRY_ASSIGN(p->reference_,
                      detail::CelReference::create({mesh::generateSphere(mesh::SphereParams{})}, options));
    }
    if (scene.media) {
      p->media_ = true;
      if (!scene.media->temperatureDetail.empty()) {
        PUFF_TRY_ASSIGN(auto v, core::loadDetailVideo(scene.media->temperatureDetail));
        p->temperature_ = std::move(v);
      }
      if (!scene.media->opacityDetail.empty()) {
        PUFF_TRY_ASSIGN(p->opacity_, core::loadDetailVideo(scene.media->opacityDetail));
      }
    }
    return std::unique_ptr<render::Path>(std::move(p));
  }

  render::RenderPath kind() const override { return render::RenderPath::kReference; }
  // The reference supersamples instead of multisampling.
  render::TargetNeeds targetNeeds() const override { return {1, false}; }
  int variations() const override { return variations_; }
  bool drawsMedia() const override { return media_; }

  bool needsRebuild(const scene::Scene& a, const scene::Scene& b) const override {
    auto videos = [](const scene::Scene& s) {
      return s.media ? std::make_pair(s.media->temperatureDetail, s.media->opacityDetail)
                     : std::pair<std::filesystem::path, std::filesystem::path>{};
    };
    return a.atlas != b.atlas || a.atlasLevel != b.atlasLevel || render::CelScene::needsRebuild(a, b) ||
           a.media.has_value() != b.media.has_value() || videos(a) != videos(b);
  }

  Result<void> draw(const render::PathFrame& frame) override {
    GLint callerFbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &callerFbo);
    const cel::Viewport& viewport = frame.viewport;
    const cel::Frame f = scene_->prepare(frame.scene, frame.inputs, viewport,
                                         reference_->supersampledViewport(viewport.width, viewport.height));
    reference_->draw(f, scene_->block(), scene_->opaque(), frame.inputs.particles, scene::celStyleFor(frame.scene),
                     frame.scene.background, static_cast<GLuint>(callerFbo), viewport, scene_->casterBounds());
    if (media_) return drawMedia(frame, static_cast<GLuint>(callerFbo));
    return {};
  }

  // The physical media reference over what the cel reference drew (its colour in the caller's
  // framebuffer, its depth the nearest of each pixel's supersamples), written back over it. No
  // explosion lights, heat shimmer or motion blur: the references model none of them.
  Result<void> drawMedia(const render::PathFrame& frame, GLuint callerFbo) {
    const cel::Viewport& vp = frame.viewport;
    const std::size_t n = static_cast<std::size_t>(vp.width) * vp.height;
    std::vector<glm::vec4> rgba(n);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, callerFbo);
    if (callerFbo != 0) glNamedFramebufferReadBuffer(callerFbo, GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(vp.x, vp.y, vp.width, vp.height, GL_RGBA, GL_FLOAT, rgba.data());
    std::vector<glm::vec3> opaque(n);
    for (std::size_t i = 0; i < n; ++i) opaque[i] = glm::vec3(rgba[i]);
    const std::vector<float> depth = reference_->outputDepth();
    if (depth.size() != n) return Error{"the reference's depth does not match its viewport"};

    const scene::Scene& s = frame.scene;
    const std::vector<media::Material> materials =
        scene::linearMediaMaterials(s, temperature_ ? &*temperature_ : nullptr, opacity_ ? &*opacity_ : nullptr);
    reference::MediaReferenceInput in;
    in.frame = scene::mediaFrameFor(s, frame.inputs.camera, frame.inputs.time, vp.width, vp.height);
    in.particles = frame.inputs.media;
    in.materials = materials;
    in.settings = s.media->settings;
    in.temperatureDetail = temperature_ ? &*temperature_ : nullptr;
    in.opacityDetail = opacity_ ? &*opacity_ : nullptr;
    in.opaqueColor = opaque;
    in.opaqueDepth = depth;
    in.background = core::srgbToLinear(s.background);
    auto image = reference::renderMediaPhysical(in, reference::PhysicalOptions{});
    if (!image) return Error::at(s.file, "the physical media reference: " + image.error().message);

    // Back into the caller's framebuffer: rows bottom-up, through a float texture and a blit.
    std::vector<float> up(n * 4);
    for (int y = 0; y < vp.height; ++y) {
      for (int x = 0; x < vp.width; ++x) {
        for (int c = 0; c < 4; ++c) {
          up[(static_cast<std::size_t>(vp.height - 1 - y) * vp.width + x) * 4 + c] = image->at(x, y, c);
        }
      }
    }
    core::Texture tex = core::makeTexture(GL_TEXTURE_2D, "media reference: frame");
    glTextureStorage2D(tex.get(), 1, GL_RGBA32F, vp.width, vp.height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(tex.get(), 0, 0, 0, vp.width, vp.height, GL_RGBA, GL_FLOAT, up.data());
    core::Framebuffer read = core::makeFramebuffer("media reference: frame");
    glNamedFramebufferTexture(read.get(), GL_COLOR_ATTACHMENT0, tex.get(), 0);
    glBlitNamedFramebuffer(read.get(), callerFbo, 0, 0, vp.width, vp.height, vp.x, vp.y, vp.x + vp.width,
                           vp.y + vp.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    return {};
  }

 private:
  ReferencePath() = default;
  std::unique_ptr<detail::CelReference> reference_;
  std::unique_ptr<render::CelScene> scene_;
  int variations_ = 0;  // 0: no atlas, no puffs
  bool media_ = false;  // the scene has media: the physical reference draws them
  std::optional<core::DetailVideo> temperature_, opacity_;
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
                                                              render::DrawTarget target) {
  if (path == render::RenderPath::kReference) return createCelReference(scene);
  return render::SceneRenderer::create(scene, path, target);
}

}  // namespace puff::eval
