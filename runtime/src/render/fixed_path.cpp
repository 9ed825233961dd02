// The fixed-function path (puff::fixedfunc, McGuire & Fein §4.4) drawing a scene within its limits.
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <puff/cel/frame.h>
#include <puff/core/atlas.h>
#include <puff/core/colour.h>
#include <puff/core/gl.h>
#include <puff/core/image.h>
#include <puff/fixedfunc/renderer.h>
#include <puff/gl_api.h>
#include <puff/mesh/mesh.h>
#include <puff/render/plate.h>
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
      PUFF_TRY_ASSIGN(auto lod, core::lodMeshFile(atlas->desc, 0, scene.atlas));
      return mesh::loadMesh(lod, nullptr, mesh::Normalize::kNo);
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
                                              DrawTarget target) {
    std::unique_ptr<FixedPath> p(new FixedPath());
    std::optional<core::Atlas> atlas;  // for the variation count and the default puff
    if (!scene.atlas.empty()) {
      auto loaded = core::loadAtlas(scene.atlas);
      if (!loaded) return Error::at(scene.file, "/atlas: " + loaded.error().message);
      atlas = std::move(*loaded);
      p->variations_ = std::max(1, atlas->desc.variations);
    }
    PUFF_TRY_ASSIGN(auto puff, fixedPuffMesh(scene, atlas ? &*atlas : nullptr));
    // A mesh without vertex colours is drawn in the colour the atlas was baked with (puffbake
    // --color, a display value like Eq. 2's C), as the nailboards draw it.
    if (atlas && !atlas->desc.sources.empty() && !puff.hasColors()) {
      p->puffColor_ = atlas->desc.sources[0].defaultColor;
    }
    // The puff texture is drawn through the frame's own pixels (2 x 2 cells): a small frame gets
    // smaller cells.
    int cellSize = scene.fixed.cellSize;
    while (cellSize > 8 && 2 * cellSize > std::min(scene.width, scene.height)) cellSize /= 2;
    if (2 * cellSize > std::min(scene.width, scene.height)) {
      return Error::at(scene.file, "/output: the fixed-function path needs a frame of at least 16 x 16 pixels");
    }
    PUFF_TRY_ASSIGN(auto fixed, fixedfunc::FixedRenderer::create(puff, cellSize));
    p->fixed_ = std::move(fixed);
    if (!scene.ramp.empty()) {
      auto ramp = cel::Ramp::read(scene.ramp);
      if (!ramp) return Error::at(scene.file, "/ramp: " + ramp.error().message);
      if (auto ok = p->fixed_->setRamp(*ramp); !ok) {
        return Error::at(scene.file, "/ramp: " + Error::at(scene.ramp, ok.error().message).message);
      }
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
    if (!scene.plate.empty()) {
      PUFF_TRY_ASSIGN(auto plate, loadPlate(scene));
      p->plate_ = std::move(plate);
    }
    // One sample: the fixed path copies the framebuffer into its puff texture (no multisampled copy).
    const bool haveFbo = glCreateFramebuffers && glNamedRenderbufferStorageMultisample && glBlitNamedFramebuffer;
    GLint alphaBits = 0;
    glGetIntegerv(GL_ALPHA_BITS, &alphaBits);  // of the context's own framebuffer (OpenGL 1.0)
    core::drainGlErrors();
    if ((target == DrawTarget::kContextFramebuffer || !haveFbo) && alphaBits > 0) {
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
           a.plate != b.plate || scene::hasParticles(a) != scene::hasParticles(b);
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
    // Transparent: nothing (renderFrame takes the alpha from two backgrounds).
    f.background = s.transparent ? glm::vec4(0.0f) : glm::vec4(s.background, 1.0f);
    if (objectsMove_) {
      for (std::size_t i = 0; i < s.objects.size(); ++i)
        objects_[i].transform = scene::objectTransform(s.objects[i], frame.inputs.time);
      auto moved = fixed_->setObjects(objects_);
      PUFF_CHECK(moved.ok());  // the scene's checks keep transforms finite and invertible
    }
    std::vector<fixedfunc::Billboard> billboards;
    billboards.reserve(frame.inputs.particles.size());
    // The fixed path takes display values (fixedfunc/renderer.h); a cel particle's tint is scene-linear.
    for (const cel::Particle& p : frame.inputs.particles)
      billboards.push_back(
          {p.position, p.size, p.variation, p.tint == glm::vec3(1.0f) ? p.tint : core::linearToSrgb(p.tint)});
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
    if (!plate_.empty()) {
      // The plate is this path's host frame: drawn first, then the fixed path draws over it
      // without a clear (FixedFrame::clear), as it would into a game's frame.
      drawPlate(viewport);
      f.clear = false;
    }
    return fillRateFloor_ ? fixed_->drawFloorFrame(f, billboards) : fixed_->drawFrame(f, billboards, style);
  }

  // The benchmarks' floor of this path: its billboards as GL 1.x bare quads (FixedRenderer::drawFloorFrame).
  void setFillRateFloor(bool on) override { fillRateFloor_ = on; }

 private:
  FixedPath() = default;
  std::unique_ptr<fixedfunc::FixedRenderer> fixed_;
  std::vector<fixedfunc::FixedObject> objects_;
  bool objectsMove_ = false;
  bool contextFramebuffer_ = false;
  bool fillRateFloor_ = false;
  int variations_ = 0;                     // 0: no atlas, no particles
  glm::vec3 puffColor_{1.0f};              // C (display value): the atlas's bake colour for a mesh without colours
  core::Image plate_;                      // output.plate, scene-linear RGBA; empty: none
  std::vector<unsigned char> plateBytes_;  // plate_ stretched to the last viewport, display values, bottom row first
  int plateWidth_ = 0, plateHeight_ = 0;

  // The plate's display values written over the viewport (glDrawPixels: this path writes display
  // values), depth cleared to 1. OpenGL 1.0 calls only; all state it sets is pushed and popped.
  void drawPlate(const cel::Viewport& vp) {
    if (vp.width != plateWidth_ || vp.height != plateHeight_) {
      const core::Image sized = resizePlate(plate_, vp.width, vp.height);
      plateBytes_.assign(static_cast<std::size_t>(vp.width) * vp.height * 4, 255);
      for (int y = 0; y < vp.height; ++y) {
        for (int x = 0; x < vp.width; ++x) {
          const std::size_t o = (static_cast<std::size_t>(vp.height - 1 - y) * vp.width + x) * 4;
          for (int c = 0; c < 3; ++c) {
            const double d = core::linearToSrgb(std::clamp(double{sized.at(x, y, c)}, 0.0, 1.0));
            plateBytes_[o + c] = static_cast<unsigned char>(std::lround(d * 255.0));
          }
        }
      }
      plateWidth_ = vp.width;
      plateHeight_ = vp.height;
    }
    glPushAttrib(GL_ALL_ATTRIB_BITS);
    glPushClientAttrib(GL_CLIENT_ALL_ATTRIB_BITS);
    glMatrixMode(GL_PROJECTION);
    glPushMatrix();
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
    glPushMatrix();
    glLoadIdentity();
    glViewport(vp.x, vp.y, vp.width, vp.height);
    glScissor(vp.x, vp.y, vp.width, vp.height);
    glEnable(GL_SCISSOR_TEST);
    glDepthMask(GL_TRUE);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    for (GLenum cap : {GL_DEPTH_TEST, GL_STENCIL_TEST, GL_BLEND, GL_ALPHA_TEST, GL_LIGHTING, GL_FOG, GL_TEXTURE_1D,
                       GL_TEXTURE_2D, GL_COLOR_LOGIC_OP, GL_DITHER})
      glDisable(cap);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    glPixelZoom(1.0f, 1.0f);
    glRasterPos2f(-1.0f, -1.0f);  // the viewport's lower-left corner
    glDrawPixels(vp.width, vp.height, GL_RGBA, GL_UNSIGNED_BYTE, plateBytes_.data());
    glMatrixMode(GL_MODELVIEW);
    glPopMatrix();
    glMatrixMode(GL_PROJECTION);
    glPopMatrix();
    glPopClientAttrib();
    glPopAttrib();
  }
};

}  // namespace

Result<std::unique_ptr<Path>> createFixedPath(const scene::Scene& scene, const scene::SceneGeometry& geometry,
                                              DrawTarget target) {
  return FixedPath::create(scene, geometry, target);
}

}  // namespace puff::render::detail
