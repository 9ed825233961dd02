// The cel path: opaque objects, nailboards, shadows (the shadow map, or billboard shadow volumes and
// the shadowed receivers' second pass), and the media pass composed over them.
#include <algorithm>

#include <puff/cel/nailboards.h>
#include <puff/cel/shadow_map.h>
#include <puff/core/atlas.h>
#include <puff/core/colour.h>
#include <puff/gl_api.h>
#include <puff/render/cel_scene.h>
#include <puff/scene/evaluate.h>

#include "media_pass.h"
#include "paths.h"
#include "plate_pass.h"

namespace puff::render::detail {

namespace {

class CelPath final : public Path {
 public:
  static Result<std::unique_ptr<Path>> create(const scene::Scene& scene, const scene::SceneGeometry& geometry) {
    std::unique_ptr<CelPath> p(new CelPath());
    PUFF_TRY_ASSIGN(p->nailboards_, cel::NailboardRenderer::create());
    if (!scene.atlas.empty()) {
      PUFF_TRY_ASSIGN(auto atlas, loadSceneAtlas(scene));
      if (auto oriented = checkOrientedPuffs(scene, atlas.desc); !oriented) return oriented.error();
      if (auto set = p->nailboards_->setAtlas(atlas); !set) return Error::at(scene.atlas, set.error().message);
      p->variations_ = std::max(1, atlas.desc.variations);
    } else if (scene::hasParticles(scene)) {
      return Error::at(scene.file, "/atlas: the scene has particles but names no atlas");
    }
    PUFF_TRY_ASSIGN(p->scene_, CelScene::create(scene, geometry));
    p->samples_ = scene.samples;
    if (!scene.plate.empty()) {
      PUFF_TRY_ASSIGN(auto plate, PlatePass::create(scene));
      p->plate_ = std::make_unique<PlatePass>(std::move(plate));
    }
    if (scene.media) {
      PUFF_TRY_ASSIGN(auto media, MediaPass::create(scene));
      p->media_ = std::move(media);
    }
    return std::unique_ptr<Path>(std::move(p));
  }

  RenderPath kind() const override { return RenderPath::kCel; }
  TargetNeeds targetNeeds() const override { return {samples_, false}; }
  int variations() const override { return variations_; }
  bool drawsMedia() const override { return media_ != nullptr; }

  bool needsRebuild(const scene::Scene& a, const scene::Scene& b) const override {
    return a.atlas != b.atlas || a.atlasLevel != b.atlasLevel || a.plate != b.plate || CelScene::needsRebuild(a, b) ||
           MediaPass::needsRebuild(a, b);
  }

  Result<void> draw(const PathFrame& frame) override {
    const scene::Scene& s = frame.scene;
    // A map draws the puffs and objects alone: no plate, shadows (the shadowed pass writes colour) or media.
    const bool colour = output_ == cel::FrameOutput::kColour;
    MediaPass* const media = colour ? media_.get() : nullptr;
    // With media the opaque scene goes into the layers' target first, and the composition writes
    // the caller's framebuffer.
    GLint callerFbo = 0, callerRead = 0;
    cel::Viewport celViewport = frame.viewport;
    if (media) {
      glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &callerFbo);
      glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &callerRead);
      PUFF_TRY_ASSIGN(auto layers, media->layers(s, frame.viewport));
      glBindFramebuffer(GL_FRAMEBUFFER, (layers)->opaqueFramebuffer());
      celViewport = cel::Viewport{0, 0, frame.viewport.width, frame.viewport.height};
    }
    glViewport(celViewport.x, celViewport.y, celViewport.width, celViewport.height);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glStencilMask(0xFF);
    const glm::vec3 background = core::srgbToLinear(s.background);  // a display value; the target is linear
    // Transparent: nothing, premultiplied (renderFrame takes the alpha from two backgrounds).
    const glm::vec4 clear = s.transparent ? glm::vec4(0.0f) : glm::vec4(background, 1.0f);
    glClearColor(clear.r, clear.g, clear.b, clear.a);
    glClearDepth(1.0);
    glClearStencil(0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    if (plate_ && colour) plate_->draw(celViewport);

    cel::Frame f = scene_->prepare(s, frame.inputs, frame.viewport, celViewport);
    f.output = output_;
    f.outputScale = {glm::length(frame.inputs.camera.target - frame.inputs.camera.position), ranges_.depth,
                     ranges_.motion};
    const cel::Style style = scene::celStyleFor(s);  // the ink decoded
    if (variations_ > 0) {
      const cel::DrawStats up = nailboards_->upload(frame.inputs.particles);
      frame.stats.bytesUploaded = up.bytesUploaded;
      if (output_ == cel::FrameOutput::kMotion) {
        if (frame.next.size() != frame.inputs.particles.size())
          return Error{"a motion map needs each particle's next position (" + std::to_string(frame.next.size()) +
                       " for " + std::to_string(frame.inputs.particles.size()) + " particles)"};
        nailboards_->uploadNext(frame.next);
      }
    }
    const bool shadows = style.shadows && !fillRateFloor_ && colour;
    if (shadows && style.shadowMethod == cel::ShadowMethod::kMap) {
      // The casters from the light into the map; the lit passes below look it up.
      if (!shadowMap_) shadowMap_ = std::make_unique<cel::ShadowMap>();
      cel::Bounds casters = scene_->casterBounds();
      if (variations_ > 0) casters.add(cel::particleBounds(frame.inputs.particles));
      cel::Bounds reach = scene_->objectBounds();
      reach.add(casters);
      shadowMap_->prepare(f, casters, style, reach);
      GLint target = 0;
      glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
      shadowMap_->beginCasters();
      if (variations_ > 0) nailboards_->drawShadowCasters(style, f);
      scene_->opaque().drawCasters();
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(target));
      glViewport(celViewport.x, celViewport.y, celViewport.width, celViewport.height);
      f.shadow = shadowMap_->lookup();
      shadowMap_->bind();
    }
    if (auto ok = scene_->block().upload(f); !ok) return ok;
    scene_->opaque().draw(cel::ShadePass::kLit);
    if (variations_ > 0) {
      if (fillRateFloor_) {
        nailboards_->drawBaseline(style);
      } else {
        nailboards_->drawNailboards(style, cel::ShadePass::kLit);
      }
    }
    if (shadows && style.shadowMethod == cel::ShadowMethod::kVolumes) {
      // The puffs' and the objects' volumes count into one stencil; the receivers are drawn again
      // where it is non-zero.
      // Only where a receiver can be: the puffs' and objects' box on screen and in depth.
      cel::Bounds receivers;
      if (variations_ > 0) receivers.add(cel::particleBounds(frame.inputs.particles));
      for (std::size_t i = 0; i < scene_->opaque().count(); ++i) receivers.add(scene_->opaque().worldBounds(i));
      const cel::VolumeClip clip = cel::volumeClip(f, receivers);
      if (variations_ > 0) nailboards_->drawShadowVolumes(style, scene_->floorPlane(), clip);
      scene_->opaque().drawShadowVolumes(style, scene_->floorPlane(), clip);
      scene_->opaque().draw(cel::ShadePass::kShadowed);
      if (variations_ > 0) nailboards_->drawNailboards(style, cel::ShadePass::kShadowed);
    }
    if (media) {
      media->draw(s, frame.inputs, frame.viewport, static_cast<GLuint>(callerFbo), frame.stats);
      glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(callerRead));
    }
    return {};
  }

  void setFillRateFloor(bool on) override {
    fillRateFloor_ = on;
    if (media_) media_->setFillRateFloor(on);
  }
  void setMediaOverWholeFrame(bool on) override {
    if (media_) media_->setOverWholeFrame(on);
  }
  void setLitShading(cel::LitShading shading) override { nailboards_->setLitShading(shading); }
  void setHullOcclusion(cel::HullOcclusion occlusion) override { nailboards_->setHullOcclusion(occlusion); }
  Result<void> setOutput(cel::FrameOutput output, const MapRanges& ranges) override {
    output_ = output;
    ranges_ = ranges;
    return {};
  }

  Result<media::Layers*> mediaLayers(const scene::Scene& scene, const cel::Viewport& viewport) override {
    if (!media_) return nullptr;
    return media_->layers(scene, viewport);
  }

  Result<MediaFrameInputs> lastMediaFrame() const override {
    if (!media_) return Path::lastMediaFrame();
    return media_->lastFrame();
  }

 private:
  CelPath() = default;
  std::unique_ptr<cel::NailboardRenderer> nailboards_;
  std::unique_ptr<CelScene> scene_;
  std::unique_ptr<MediaPass> media_;
  std::unique_ptr<PlatePass> plate_;           // output.plate, drawn after the clear
  std::unique_ptr<cel::ShadowMap> shadowMap_;  // made on the first frame with map shadows
  int variations_ = 0;                         // 0: no atlas, no cel particles
  int samples_ = 1;
  bool fillRateFloor_ = false;
  cel::FrameOutput output_ = cel::FrameOutput::kColour;
  MapRanges ranges_;  // how the maps scale depth and motion
};

}  // namespace

Result<std::unique_ptr<Path>> createCelPath(const scene::Scene& scene, const scene::SceneGeometry& geometry) {
  return CelPath::create(scene, geometry);
}

}  // namespace puff::render::detail
