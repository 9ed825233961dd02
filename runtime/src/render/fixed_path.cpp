// The fixed-function path (puff::fixedfunc, McGuire & Fein §4.4) drawing a scene within its limits.
#include <algorithm>
#include <optional>

#include <puff/core/atlas.h>
#include <puff/core/gl.h>
#include <puff/core/image.h>
#include <puff/fixedfunc/renderer.h>
#include <puff/gl_api.h>
#include <puff/mesh/mesh.h>
#include <puff/scene/evaluate.h>

#include "paths.h"

namespace puff::render::detail {

namespace fs = std::filesystem;

// The fixed path's puff: the scene's, else the mesh the atlas's first variation was baked from: its
// level of detail when puffbake --lod auto chose one (in the source's normalized space, so it is
// loaded as it is), else the source mesh file.
Result<mesh::TriMesh> fixedPuffMesh(const scene::Scene& scene, const core::Atlas* atlas) {
  fs::path file = scene.fixed.puff;
  if (file.empty()) {
    const bool particles = scene::hasParticles(scene);
    // A scene of objects (and media, which this path does not draw) needs no puff: any will do.
    if (!atlas && !particles) return mesh::generateSphere(mesh::SphereParams{});
    if (!atlas) return Error::at(scene.file, "/fixed/puff: no puff mesh and no atlas to take one from");
    if (!atlas->desc.sources.empty() && !atlas->desc.sources[0].lodMesh.empty()) {
      // Only this path draws it: the nailboards and the reference load the atlas without it.
      auto lod = core::lodMeshFile(atlas->desc, 0, scene.atlas);
      if (!lod) return lod.error();
      return mesh::loadMesh(*lod, nullptr, mesh::Normalize::kNo);
    }
    if (atlas->desc.sources.empty() || atlas->desc.sources[0].path.empty()) {
      return Error::at(scene.file,
                       "/fixed/puff: the atlas's first variation was generated, not loaded from a mesh "
                       "file; name the puff mesh in /fixed/puff");
    }
    file = atlas->desc.sources[0].path;
    if (file.is_relative()) file = scene.atlas.parent_path() / file;
  }
  return mesh::loadMesh(file);
}

namespace {

class FixedPath final : public Path {
 public:
  static Result<std::unique_ptr<Path>> create(const scene::Scene& scene, const scene::SceneGeometry& geometry,
                                              bool contextFramebuffer) {
    std::unique_ptr<FixedPath> p(new FixedPath());
    std::optional<core::Atlas> atlas;  // for the variation count and the default puff
    if (!scene.atlas.empty()) {
      auto loaded = core::loadAtlas(scene.atlas);
      if (!loaded) return loaded.error();
      atlas = std::move(*loaded);
      p->variations_ = std::max(1, atlas->desc.variations);
    }
    auto puff = fixedPuffMesh(scene, atlas ? &*atlas : nullptr);
    if (!puff) return puff.error();
    // A mesh without vertex colours is drawn in the colour the atlas was baked with (puffbake
    // --color, a display value like Eq. 2's C), as the nailboards draw it.
    if (atlas && !atlas->desc.sources.empty() && !puff->hasColors()) {
      p->puffColor_ = atlas->desc.sources[0].defaultColor;
    }
    // The puff texture is drawn through the frame's own pixels (2 x 2 cells): a small frame gets
    // smaller cells.
    int cellSize = scene.fixed.cellSize;
    while (cellSize > 8 && 2 * cellSize > std::min(scene.width, scene.height)) cellSize /= 2;
    if (2 * cellSize > std::min(scene.width, scene.height)) {
      return Error::at(scene.file, "/output: the fixed-function path needs a frame of at least 16 x 16 pixels");
    }
    auto fixed = fixedfunc::FixedRenderer::create(*puff, cellSize);
    if (!fixed) return fixed.error();
    p->fixed_ = std::move(*fixed);
    if (!scene.ramp.empty()) {
      auto ramp = core::readImage(scene.ramp);
      if (!ramp) return ramp.error();
      if (auto ok = p->fixed_->setRamp(*ramp); !ok) return Error::at(scene.ramp, ok.error().message);
    }
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
      const scene::ObjectSpec& o = scene.objects[i];
      fixedfunc::FixedObject obj;
      obj.mesh = *geometry.shapes[i];
      obj.transform = scene::objectTransform(o);
      obj.albedo = o.albedo;
      obj.shading = o.cel ? fixedfunc::ObjectShading::kCel : fixedfunc::ObjectShading::kSmooth;
      p->objects_.push_back(std::move(obj));
      p->objectsMove_ |= !o.path.empty();
    }
    if (auto ok = p->fixed_->setObjects(p->objects_); !ok) return Error::at(scene.file, ok.error().message);
    // One sample: the fixed path copies the framebuffer into its puff texture (no multisampled copy).
    const bool haveFbo = glCreateFramebuffers && glNamedRenderbufferStorageMultisample && glBlitNamedFramebuffer;
    GLint alphaBits = 0;
    glGetIntegerv(GL_ALPHA_BITS, &alphaBits);  // of the context's own framebuffer (OpenGL 1.0)
    core::drainGlErrors();
    if ((contextFramebuffer || !haveFbo) && alphaBits > 0) {
      p->contextFramebuffer_ = true;
    } else if (!haveFbo) {
      return Error{
          "the fixed-function path needs a framebuffer with alpha, and this context has neither one of its "
          "own nor framebuffer objects"};
    }
    return std::unique_ptr<Path>(std::move(p));
  }

  RenderPath kind() const override { return RenderPath::kFixed; }
  TargetNeeds targetNeeds() const override { return {1, contextFramebuffer_, true, true}; }
  int variations() const override { return variations_; }

  // The puff texture's cells are sized from the frame, so the frame's size is part of what it made.
  bool needsRebuild(const scene::Scene& a, const scene::Scene& b) const override {
    return a.fixed.puff != b.fixed.puff || a.fixed.cellSize != b.fixed.cellSize || a.width != b.width ||
           a.height != b.height || a.ramp != b.ramp || a.atlas != b.atlas || a.objects != b.objects ||
           scene::hasParticles(a) != scene::hasParticles(b);
  }

  Result<void> draw(const PathFrame& frame) override {
    const scene::Scene& s = frame.scene;
    const cel::Camera& cam = frame.inputs.camera;
    const cel::Viewport& viewport = frame.viewport;
    fixedfunc::FixedFrame f;
    f.view = cam.view();
    f.projection = cam.projection(static_cast<float>(viewport.width) / static_cast<float>(viewport.height));
    f.viewport = {viewport.x, viewport.y, viewport.width, viewport.height};
    f.lightDirection = s.light.direction;
    f.lightColor = s.light.color;
    f.ambientColor = s.ambientColor;  // the fixed path has no ambient gradient
    f.background = glm::vec4(s.background, 1.0f);
    if (objectsMove_) {
      for (std::size_t i = 0; i < s.objects.size(); ++i)
        objects_[i].transform = scene::objectTransform(s.objects[i], frame.inputs.time);
      auto moved = fixed_->setObjects(objects_);
      PUFF_CHECK(moved.ok());  // the scene's checks keep transforms finite and invertible
    }
    std::vector<fixedfunc::Billboard> billboards;
    billboards.reserve(frame.inputs.particles.size());
    for (const cel::Particle& p : frame.inputs.particles) billboards.push_back({p.position, p.size, p.variation});
    fixedfunc::FixedStyle style;
    style.outlines = s.style.outlines;
    style.shading = s.style.shading;
    style.outlineScale = s.fixed.outlineScale;
    style.outlineOffset = s.fixed.outlineOffset;
    style.puffColor = puffColor_;
    // A cel renderer in the same context (puffrender --compare) may have left its program and
    // vertex array bound; the fixed path draws only with neither. Never in a context-framebuffer
    // frame, which makes OpenGL 1.x calls only.
    if (!contextFramebuffer_) {
      if (glUseProgram) glUseProgram(0);
      if (glBindVertexArray) glBindVertexArray(0);
    }
    return fixed_->drawFrame(f, billboards, style);
  }

 private:
  FixedPath() = default;
  std::unique_ptr<fixedfunc::FixedRenderer> fixed_;
  std::vector<fixedfunc::FixedObject> objects_;
  bool objectsMove_ = false;
  bool contextFramebuffer_ = false;
  int variations_ = 0;         // 0: no atlas, no particles
  glm::vec3 puffColor_{1.0f};  // C (display value): the atlas's bake colour for a mesh without colours
};

}  // namespace

Result<std::unique_ptr<Path>> createFixedPath(const scene::Scene& scene, const scene::SceneGeometry& geometry,
                                              bool contextFramebuffer) {
  return FixedPath::create(scene, geometry, contextFramebuffer);
}

}  // namespace puff::render::detail
