#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/cel/opaque.h>
#include <puff/core/detail_video.h>
#include <puff/core/gl.h>
#include <puff/fixedfunc/renderer.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>
#include <puff/mesh/mesh.h>
#include <puff/render/render.h>

#include "cel_reference.h"

namespace puff::render {

namespace fs = std::filesystem;

namespace {

// An offscreen target: colour + depth/stencil, multisampled when asked, with a single-sample
// resolve target to read back from.
struct Target {
  int width = 0, height = 0, samples = 1;
  /// No framebuffer objects in this context (GL before 4.5's direct state access: the fixed path
  /// in an old context): frames go to the context's own framebuffer, which must be at least this
  /// size (puffrender creates it so).
  bool contextFramebuffer = false;
  core::Framebuffer fbo, resolveFbo;
  core::Renderbuffer color, depthStencil, resolveColor;

  static Result<Target> create(int w, int h, int samples) {
    Target t;
    t.width = w;
    t.height = h;
    GLint maxSamples = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    if (samples > maxSamples) {
      return Error{std::to_string(samples) + " samples per pixel asked, but this GL gives at most " +
                   std::to_string(maxSamples) + " (set /output/samples or --samples lower)"};
    }
    t.samples = std::max(1, samples);
    t.fbo = core::makeFramebuffer();
    t.color = core::makeRenderbuffer();
    t.depthStencil = core::makeRenderbuffer();
    const int s = t.samples > 1 ? t.samples : 0;
    glNamedRenderbufferStorageMultisample(t.color.get(), s, GL_RGBA8, w, h);
    glNamedRenderbufferStorageMultisample(t.depthStencil.get(), s, GL_DEPTH24_STENCIL8, w, h);
    glNamedFramebufferRenderbuffer(t.fbo.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t.color.get());
    glNamedFramebufferRenderbuffer(t.fbo.get(), GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, t.depthStencil.get());
    if (glCheckNamedFramebufferStatus(t.fbo.get(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      return Error{"render target of " + std::to_string(w) + "x" + std::to_string(h) + " with " +
                   std::to_string(t.samples) + " samples is not supported by this GL"};
    }
    if (t.samples > 1) {
      t.resolveFbo = core::makeFramebuffer();
      t.resolveColor = core::makeRenderbuffer();
      glNamedRenderbufferStorage(t.resolveColor.get(), GL_RGBA8, w, h);
      glNamedFramebufferRenderbuffer(t.resolveFbo.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t.resolveColor.get());
    }
    return t;
  }
};

std::shared_ptr<const cel::TriangleMesh> toTriangleMesh(const mesh::TriMesh& m) {
  auto out = std::make_shared<cel::TriangleMesh>();
  out->positions = m.positions;
  out->normals = m.normals;
  out->indices.reserve(m.triangles.size() * 3);
  for (const glm::uvec3& t : m.triangles) {
    out->indices.insert(out->indices.end(), {t.x, t.y, t.z});
  }
  return out;
}

}  // namespace

std::string_view toString(RenderPath path) {
  switch (path) {
    case RenderPath::kCel:
      return "cel";
    case RenderPath::kFixed:
      return "fixed";
    case RenderPath::kReference:
      return "reference";
  }
  return "cel";
}

std::optional<RenderPath> parseRenderPath(std::string_view name) {
  for (RenderPath p : {RenderPath::kCel, RenderPath::kFixed, RenderPath::kReference}) {
    if (name == toString(p)) return p;
  }
  return std::nullopt;
}

struct SceneRenderer::Impl {
  Scene scene;
  RenderPath path = RenderPath::kCel;
  std::unique_ptr<fixedfunc::FixedRenderer> fixed;
  std::vector<fixedfunc::FixedObject> fixedObjects;
  bool fixedObjectsMove = false;
  std::string lastError;  // a draw that failed (the fixed path checks the context state)
  std::unique_ptr<cel::NailboardRenderer> nailboards;
  std::unique_ptr<cel::OpaqueRenderer> opaque;
  std::unique_ptr<cel::FrameBlock> block;
  std::optional<cel::Ramp> ramp;
  std::optional<cel::Gradient> gradient;
  Target target;
  int variations = 1;
  bool hasAtlas = false;
  glm::vec4 floorPlane{0.0f};
  std::unique_ptr<sim::Simulator> sim;
  // Media (fire, smoke, dust): the renderer, the layers (made for the viewport's size on first
  // use) and the simulator of the media emitters.
  std::unique_ptr<media::Renderer> media;
  std::unique_ptr<media::Layers> layers;
  std::unique_ptr<sim::Simulator> mediaSim;
  std::vector<media::Particle> mediaParticles;
  std::optional<media::Frame> lastMediaFrame;       // the full-size frame of the last media draw
  std::unique_ptr<detail::CelReference> reference;  // RenderPath::kReference
  CelReferenceOptions referenceOptions;
  bool fillRateFloor = false;  // setFillRateFloor
};

namespace {

// What a motion-blur history slot holds: a frame seen by a camera at a size.
struct HistoryTag {
  int frame = -1;
  glm::vec3 position{0.0f}, target{0.0f}, up{0.0f};
  float fov = 0.0f, ortho = 0.0f;
  int width = 0, height = 0;
  bool operator==(const HistoryTag&) const = default;
};

HistoryTag historyTag(int frame, const cel::Camera& c, const cel::Viewport& v) {
  return HistoryTag{frame, c.position, c.target, c.up, c.fovYDegrees, c.orthoHeight, v.width, v.height};
}

}  // namespace

struct SceneRenderer::History {
  std::vector<HistoryTag> tags;
};

SceneRenderer::SceneRenderer() : impl_(std::make_unique<Impl>()) {}
SceneRenderer::~SceneRenderer() = default;
const Scene& SceneRenderer::scene() const { return impl_->scene; }
RenderPath SceneRenderer::path() const { return impl_->path; }
void SceneRenderer::setFillRateFloor(bool on) {
  impl_->fillRateFloor = on;
  if (impl_->media) impl_->media->setFillRateFloor(on);
}

Result<void> SceneRenderer::checkProgrammable() {
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  core::drainGlErrors();  // GL_MAJOR_VERSION is unknown to a GL 2.x context
  if (major * 10 + minor < 45) {
    const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return Error{std::string("the context is OpenGL ") + (version ? version : "(unknown)") + ", not 4.5"};
  }
  if (auto nb = cel::NailboardRenderer::create(); !nb) return nb.error();
  if (auto op = cel::OpaqueRenderer::create(); !op) return op.error();
  if (auto md = media::Renderer::create(); !md) return md.error();
  if (auto ly = media::Layers::create(16, 16, 1, 0.5f); !ly) return ly.error();
  return {};
}

namespace {

// The fixed path's puff: the scene's, or the mesh the atlas's first variation was baked from.
Result<mesh::TriMesh> fixedPuffMesh(const Scene& scene) {
  fs::path file = scene.fixed.puff;
  if (file.empty()) {
    const bool particles = !scene.particles.empty() || !scene.emitters.empty() ||
                           (scene.simulation && !scene.simulation->emitters.empty());
    // A scene of objects (and media, which this path does not draw) needs no puff: any will do.
    if (scene.atlas.empty() && !particles) return mesh::generateSphere(mesh::SphereParams{});
    if (scene.atlas.empty()) return Error::at(scene.file, "/fixed/puff: no puff mesh and no atlas to take one from");
    auto atlas = core::loadAtlas(scene.atlas);
    if (!atlas) return atlas.error();
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

}  // namespace

// The simulator of a simulated scene (any path).
template <class Impl>
Result<void> createSimulator(Impl& m, const Scene& scene) {
  auto settings = simulationSettings(scene);
  if (!settings) return settings.error();
  if (*settings) {
    // Particles carry an 8-bit variation (cel::Particle): emitters pick among the first 256.
    auto sim = sim::Simulator::create(std::move(**settings), std::min(m.variations, 256));
    if (!sim) return Error::at(scene.file, "/simulation" + sim.error().message);
    m.sim = std::move(*sim);
  }
  return {};
}

Result<std::unique_ptr<SceneRenderer>> SceneRenderer::create(const Scene& scene, RenderPath path,
                                                             bool contextFramebuffer) {
  if (path == RenderPath::kFixed) return createFixed(scene, contextFramebuffer);
  if (path == RenderPath::kReference) return createReference(scene);
  return createProgrammable(scene, nullptr);
}

Result<std::unique_ptr<SceneRenderer>> SceneRenderer::createReference(const Scene& scene,
                                                                      const CelReferenceOptions& options) {
  return createProgrammable(scene, &options);
}

Result<std::unique_ptr<SceneRenderer>> SceneRenderer::createProgrammable(const Scene& scene,
                                                                         const CelReferenceOptions* reference) {
  std::unique_ptr<SceneRenderer> r(new SceneRenderer());
  Impl& m = *r->impl_;
  m.scene = scene;
  if (reference) {
    if (auto ok = detail::validate(*reference); !ok) return ok.error();
    m.path = RenderPath::kReference;
    m.referenceOptions = *reference;
  }
  auto nb = cel::NailboardRenderer::create();
  if (!nb) return nb.error();
  m.nailboards = std::move(*nb);
  auto op = cel::OpaqueRenderer::create();
  if (!op) return op.error();
  m.opaque = std::move(*op);
  m.block = std::make_unique<cel::FrameBlock>();

  const bool needsAtlas =
      !scene.particles.empty() || !scene.emitters.empty() || (scene.simulation && !scene.simulation->emitters.empty());
  if (!scene.atlas.empty()) {
    auto atlas = core::loadAtlas(scene.atlas);
    if (!atlas) return atlas.error();
    if (scene.atlasLevel > 0) {
      auto level = core::atlasFromLevel(*atlas, scene.atlasLevel);
      if (!level) return Error::at(scene.file, "/atlasLevel: " + level.error().message);
      atlas = std::move(*level);
    }
    auto set = m.nailboards->setAtlas(*atlas);
    if (!set) return Error::at(scene.atlas, set.error().message);
    m.variations = std::max(1, atlas->desc.variations);
    m.hasAtlas = true;
    if (reference) {
      auto meshes = detail::atlasSourceMeshes(atlas->desc, scene.atlas);
      if (!meshes) return meshes.error();
      auto ref = detail::CelReference::create(std::move(*meshes), *reference);
      if (!ref) return ref.error();
      m.reference = std::move(*ref);
    }
  } else if (needsAtlas) {
    return Error::at(scene.file, "/atlas: the scene has particles but names no atlas");
  }

  if (!scene.ramp.empty()) {
    auto ramp = cel::Ramp::load(scene.ramp, scene.rampSmooth);
    if (!ramp) return ramp.error();
    m.ramp = std::move(*ramp);
  } else {
    m.ramp = cel::Ramp::twoTone();
  }
  if (!scene.ambientGradient.empty()) {
    auto g = cel::Gradient::load(scene.ambientGradient);
    if (!g) return g.error();
    m.gradient = std::move(*g);
  }

  std::vector<cel::OpaqueObject> objects;
  std::shared_ptr<const cel::TriangleMesh> plane, box, sphere;
  float floorHeight = 0.0f;
  bool haveFloor = false;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const ObjectSpec& o = scene.objects[i];
    cel::OpaqueObject obj;
    obj.name = o.name.empty() ? "objects/" + std::to_string(i) : o.name;
    obj.transform = objectTransform(o);
    obj.albedo = o.albedo;
    obj.cel = o.cel;
    switch (o.type) {
      case ObjectSpec::Type::kPlane:
        if (!plane) plane = std::make_shared<const cel::TriangleMesh>(cel::makePlane());
        obj.mesh = plane;
        // Shadow volumes may stop at the lowest horizontal plane: nothing below it is seen.
        if (o.rotateDegrees == glm::vec3(0.0f) && o.path.empty() && (!haveFloor || o.translate.y < floorHeight)) {
          floorHeight = o.translate.y;
          haveFloor = true;
        }
        break;
      case ObjectSpec::Type::kBox:
        if (!box) box = std::make_shared<const cel::TriangleMesh>(cel::makeBox());
        obj.mesh = box;
        break;
      case ObjectSpec::Type::kSphere:
        if (!sphere) sphere = std::make_shared<const cel::TriangleMesh>(cel::makeSphere());
        obj.mesh = sphere;
        break;
      case ObjectSpec::Type::kMesh: {
        auto loaded = mesh::loadMesh(o.mesh);
        if (!loaded) return loaded.error();
        obj.mesh = toTriangleMesh(*loaded);
        break;
      }
    }
    objects.push_back(std::move(obj));
  }
  if (haveFloor) m.floorPlane = glm::vec4(0.0f, 1.0f, 0.0f, -floorHeight);
  auto set = m.opaque->setObjects(std::move(objects));
  if (!set) return Error::at(scene.file, set.error().message);

  if (reference && !m.reference) {
    // Nothing to draw but objects: the reference still supersamples them like the puffs.
    auto ref = detail::CelReference::create({mesh::generateSphere(mesh::SphereParams{})}, *reference);
    if (!ref) return ref.error();
    m.reference = std::move(*ref);
  }
  // The reference supersamples instead of multisampling.
  auto target = Target::create(scene.width, scene.height, reference ? 1 : scene.samples);
  if (!target) return target.error();
  m.target = std::move(*target);

  if (auto ok = createSimulator(m, scene); !ok) return ok.error();
  if (scene.media && !reference) {
    if (auto ok = r->createMedia(); !ok) return ok.error();
  }
  return r;
}

Result<void> SceneRenderer::createMedia() {
  Impl& m = *impl_;
  const MediaSpec& spec = *m.scene.media;
  auto renderer = media::Renderer::create(spec.settings);
  if (!renderer) return Error::at(m.scene.file, "/media: " + renderer.error().message);
  if (auto ok = (*renderer)->setMaterials(spec.materials); !ok)
    return Error::at(m.scene.file, "/media/materials: " + ok.error().message);
  std::optional<core::DetailVideo> temperature, opacity;
  if (!spec.temperatureDetail.empty()) {
    auto v = core::loadDetailVideo(spec.temperatureDetail);
    if (!v) return v.error();
    temperature = std::move(*v);
  }
  if (!spec.opacityDetail.empty()) {
    auto v = core::loadDetailVideo(spec.opacityDetail);
    if (!v) return v.error();
    opacity = std::move(*v);
  }
  (*renderer)->setDetail(temperature ? &*temperature : nullptr, opacity ? &*opacity : nullptr);
  m.media = std::move(*renderer);
  auto settings = mediaSimulationSettings(m.scene);
  if (!settings) return settings.error();
  if (*settings) {
    auto sim = sim::Simulator::create(std::move(**settings), 1);
    if (!sim) return Error::at(m.scene.file, "/media" + sim.error().message);
    m.mediaSim = std::move(*sim);
  }
  return {};
}

Result<std::unique_ptr<SceneRenderer>> SceneRenderer::createFixed(const Scene& scene, bool contextFramebuffer) {
  std::unique_ptr<SceneRenderer> r(new SceneRenderer());
  Impl& m = *r->impl_;
  m.scene = scene;
  m.path = RenderPath::kFixed;
  auto puff = fixedPuffMesh(scene);
  if (!puff) return puff.error();
  // The puff texture is drawn through the frame's own pixels (2 x 2 cells): a small frame gets
  // smaller cells.
  int cellSize = scene.fixed.cellSize;
  while (cellSize > 8 && 2 * cellSize > std::min(scene.width, scene.height)) cellSize /= 2;
  if (2 * cellSize > std::min(scene.width, scene.height)) {
    return Error::at(scene.file, "/output: the fixed-function path needs a frame of at least 16 x 16 pixels");
  }
  auto fixed = fixedfunc::FixedRenderer::create(*puff, cellSize);
  if (!fixed) return fixed.error();
  m.fixed = std::move(*fixed);
  if (!scene.ramp.empty()) {
    auto ramp = core::readImage(scene.ramp);
    if (!ramp) return ramp.error();
    if (auto ok = m.fixed->setRamp(*ramp); !ok) return Error::at(scene.ramp, ok.error().message);
  }
  if (!scene.atlas.empty()) {
    auto atlas = core::loadAtlas(scene.atlas);
    if (!atlas) return atlas.error();
    m.variations = std::max(1, atlas->desc.variations);
    m.hasAtlas = true;
  }
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const ObjectSpec& o = scene.objects[i];
    fixedfunc::FixedObject obj;
    switch (o.type) {
      case ObjectSpec::Type::kPlane:
        obj.mesh = fixedfunc::makePlaneMesh();
        break;
      case ObjectSpec::Type::kBox:
        obj.mesh = fixedfunc::makeBoxMesh();
        break;
      case ObjectSpec::Type::kSphere:
        obj.mesh = fixedfunc::makeSphereMesh();
        break;
      case ObjectSpec::Type::kMesh: {
        auto loaded = mesh::loadMesh(o.mesh);
        if (!loaded) return loaded.error();
        obj.mesh = std::move(*loaded);
        break;
      }
    }
    obj.transform = objectTransform(o);
    obj.albedo = o.albedo;
    obj.shading = o.cel ? fixedfunc::ObjectShading::kCel : fixedfunc::ObjectShading::kSmooth;
    m.fixedObjects.push_back(std::move(obj));
    m.fixedObjectsMove |= !o.path.empty();
  }
  if (auto ok = m.fixed->setObjects(m.fixedObjects); !ok) return Error::at(scene.file, ok.error().message);
  // One sample: the fixed path copies the framebuffer into its puff texture (no multisampled copy).
  const bool haveFbo = glCreateFramebuffers && glNamedRenderbufferStorageMultisample && glBlitNamedFramebuffer;
  GLint alphaBits = 0;
  glGetIntegerv(GL_ALPHA_BITS, &alphaBits);  // of the context's own framebuffer (OpenGL 1.0)
  core::drainGlErrors();
  if ((contextFramebuffer || !haveFbo) && alphaBits > 0) {
    m.target.width = scene.width, m.target.height = scene.height;
    m.target.contextFramebuffer = true;
  } else if (haveFbo) {  // e.g. a surfaceless EGL context: nothing of its own to draw into
    auto target = Target::create(scene.width, scene.height, 1);
    if (!target) return target.error();
    m.target = std::move(*target);
  } else {
    return Error{
        "the fixed-function path needs a framebuffer with alpha, and this context has neither one of its "
        "own nor framebuffer objects"};
  }
  if (auto ok = createSimulator(m, scene); !ok) return ok.error();
  return r;
}

namespace {

// What an edit may change without reloading anything: the look, the camera, the clock, and the
// simulation's forces. toJson writes every field, so comparing the rest catches every other edit.
nlohmann::json reloadKey(const Scene& s) {
  nlohmann::json j = toJson(s);
  for (const char* key : {"camera", "light", "style"}) j.erase(key);
  j["ambient"].erase("color");
  j["output"].erase("background");
  j["animation"].erase("orbit");
  j["animation"].erase("frames");
  if (j.contains("simulation")) j["simulation"].erase("forces");
  if (j.contains("media")) j["media"].erase("forces");
  return j;
}

}  // namespace

Result<void> SceneRenderer::update(const Scene& next) {
  Impl& m = *impl_;
  history_.reset();  // kept frames were drawn from the old scene
  if (reloadKey(m.scene) != reloadKey(next)) {
    auto fresh = m.path == RenderPath::kReference ? createReference(next, m.referenceOptions)
                                                  : create(next, m.path, m.target.contextFramebuffer);
    if (!fresh) return fresh.error();
    impl_ = std::move((*fresh)->impl_);
    return {};
  }
  if (m.mediaSim && next.media) {
    auto ok = m.mediaSim->setForces(next.media->forces);
    if (!ok) return Error::at(next.file, "/media" + ok.error().message);
    m.mediaSim->reset();
  }
  if (m.sim && next.simulation) {
    auto ok = m.sim->setForces(next.simulation->forces);
    if (!ok) return Error::at(next.file, "/simulation" + ok.error().message);
    // A frame stays a pure function of the scene: the next draw simulates from the start under the
    // new forces, so what a viewer shows is what puffrender makes of the saved file.
    m.sim->reset();
  }
  m.scene = next;
  return {};
}

void SceneRenderer::drawFrame(int frame, const cel::Viewport& viewport, FrameStats* stats, const cel::Camera* camera) {
  Impl& m = *impl_;
  const Scene& s = m.scene;
  if (m.path != RenderPath::kCel || !s.media || s.media->motionBlurFrames == 0) {
    drawSingle(frame, viewport, stats, camera);
    return;
  }
  // Motion blur: frame k is sum_i w_i F(k - i), i = 0..n, w_i = p^i normalized over the frames
  // that exist (k - i >= 0). Each F is a pure function of its frame (and camera), kept in a ring
  // of n + 1 slots, so a sequence draws one new frame per call and a frame alone draws the n before
  // it first: the same sums, the same pixels.
  GLint callerFbo = 0, callerRead = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &callerFbo);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &callerRead);
  const int n = s.media->motionBlurFrames;
  if (!ensureLayers(viewport)) return;
  m.layers->setHistorySlots(n + 1);
  if (!history_) history_ = std::make_unique<History>();
  history_->tags.resize(static_cast<std::size_t>(n + 1));
  const cel::Viewport local{0, 0, viewport.width, viewport.height};
  std::vector<int> slots;
  std::vector<float> weights;
  float total = 0.0f;
  for (int k = std::max(0, frame - n); k <= frame; ++k) {
    const cel::Camera cam = camera ? *camera : cameraAt(s, k);
    const int slot = k % (n + 1);
    const HistoryTag tag = historyTag(k, cam, viewport);
    if (k == frame || !(history_->tags[static_cast<std::size_t>(slot)] == tag)) {
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.layers->historyFramebuffer(slot));
      drawSingle(k, local, k == frame ? stats : nullptr, &cam);
      history_->tags[static_cast<std::size_t>(slot)] = tag;
    }
    const float w = std::pow(s.media->motionBlurPersistence, static_cast<float>(frame - k));
    slots.push_back(slot);
    weights.push_back(w);
    total += w;
  }
  for (float& w : weights) w /= total;
  const int vp[4] = {viewport.x, viewport.y, viewport.width, viewport.height};
  m.layers->blendHistory(static_cast<GLuint>(callerFbo), vp, slots, weights);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(callerRead));
}

bool SceneRenderer::ensureLayers(const cel::Viewport& viewport) {
  Impl& m = *impl_;
  if (m.layers && m.layers->width() == viewport.width && m.layers->height() == viewport.height) return true;
  auto layers = media::Layers::create(viewport.width, viewport.height, m.scene.samples, m.scene.media->resolution);
  if (!layers) {
    m.lastError = layers.error().message;
    return false;
  }
  m.layers = std::move(*layers);
  if (history_) history_->tags.clear();
  return true;
}

namespace {

// The cel frame of `frame` through `cam` for an output of viewport's size drawn at `drawViewport`
// (the reference supersamples): light and ambient, the ramp and gradient bound, objects on paths
// moved to where they are at this frame. Shared by the cel path and its reference.
template <class Impl>
cel::Frame prepareCelFrame(Impl& m, int frame, const cel::Camera& cam, const cel::Viewport& viewport,
                           const cel::Viewport& drawViewport) {
  const Scene& s = m.scene;
  cel::Frame f = cel::Frame::fromCamera(cam, viewport.width, viewport.height);
  f.viewport = drawViewport;
  f.light = s.light;
  f.ambientColor = s.ambientColor;
  f.ambientGradient = m.gradient.has_value();
  m.ramp->bind();
  if (m.gradient) m.gradient->bind();
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    if (s.objects[i].path.empty()) continue;
    auto moved = m.opaque->setTransform(i, objectTransform(s.objects[i], frameTime(s, frame)));
    PUFF_CHECK(moved.ok());  // the scene's checks keep transforms finite and invertible
  }
  return f;
}

}  // namespace

void SceneRenderer::drawSingle(int frame, const cel::Viewport& viewport, FrameStats* stats, const cel::Camera* camera) {
  Impl& m = *impl_;
  const Scene& s = m.scene;
  const cel::Camera cam = camera ? *camera : cameraAt(s, frame);

  // The particles: listed, placed and simulated (the same for every path).
  std::vector<cel::Particle> particles;
  std::size_t simulated = 0;
  double simulateMs = 0.0;
  if (m.hasAtlas) {
    particles = particlesAt(s, frame, m.variations);
    if (m.sim) {
      const auto t0 = std::chrono::steady_clock::now();
      m.sim->advanceToFrame(frame);
      simulateMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      particles.reserve(particles.size() + m.sim->size());
      for (std::size_t i = 0; i < m.sim->size(); ++i) {
        const sim::ParticleState p = m.sim->particle(i);
        if (!(p.size > 0.0f)) continue;
        particles.push_back(cel::Particle{p.position, p.size, p.variation, p.oriented, p.orientation});
        ++simulated;
      }
    }
  }
  if (stats) {
    stats->particles = particles.size();
    stats->simulated = simulated;
    stats->simulateMs = simulateMs;
    stats->bytesUploaded = 0;
  }

  if (m.path == RenderPath::kFixed) {
    fixedfunc::FixedFrame f;
    f.view = cam.view();
    f.projection = cam.projection(static_cast<float>(viewport.width) / static_cast<float>(viewport.height));
    f.viewport = {viewport.x, viewport.y, viewport.width, viewport.height};
    f.lightDirection = s.light.direction;
    f.lightColor = s.light.color;
    f.ambientColor = s.ambientColor;  // the fixed path has no ambient gradient
    f.background = glm::vec4(s.background, 1.0f);
    if (m.fixedObjectsMove) {
      for (std::size_t i = 0; i < s.objects.size(); ++i)
        m.fixedObjects[i].transform = objectTransform(s.objects[i], frameTime(s, frame));
      auto moved = m.fixed->setObjects(m.fixedObjects);
      PUFF_CHECK(moved.ok());  // the scene's checks keep transforms finite and invertible
    }
    std::vector<fixedfunc::Billboard> billboards;
    billboards.reserve(particles.size());
    for (const cel::Particle& p : particles) billboards.push_back({p.position, p.size, p.variation});
    fixedfunc::FixedStyle style;
    style.outlines = s.style.outlines;
    style.shading = s.style.shading;
    style.outlineScale = s.fixed.outlineScale;
    style.outlineOffset = s.fixed.outlineOffset;
    // A cel renderer in the same context (puffrender --compare) may have left its program and
    // vertex array bound; the fixed path draws only with neither. Never in a context-framebuffer
    // frame, which makes OpenGL 1.x calls only.
    if (!m.target.contextFramebuffer) {
      if (glUseProgram) glUseProgram(0);
      if (glBindVertexArray) glBindVertexArray(0);
    }
    auto drawn = m.fixed->drawFrame(f, billboards, style);
    if (!drawn) m.lastError = drawn.error().message;
    return;
  }

  if (m.path == RenderPath::kReference) {
    GLint callerFbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &callerFbo);
    const cel::Frame f =
        prepareCelFrame(m, frame, cam, viewport, m.reference->supersampledViewport(viewport.width, viewport.height));
    m.reference->draw(f, *m.block, *m.opaque, particles, s.style, s.background, static_cast<GLuint>(callerFbo),
                      viewport);
    return;
  }

  // With media the opaque scene goes into the layers' target first, and the composition writes
  // the caller's framebuffer.
  GLint callerFbo = 0, callerRead = 0;
  cel::Viewport celViewport = viewport;
  if (m.media) {
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &callerFbo);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &callerRead);
    if (!ensureLayers(viewport)) return;
    glBindFramebuffer(GL_FRAMEBUFFER, m.layers->opaqueFramebuffer());
    celViewport = cel::Viewport{0, 0, viewport.width, viewport.height};
  }
  glViewport(celViewport.x, celViewport.y, celViewport.width, celViewport.height);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glStencilMask(0xFF);
  glClearColor(s.background.r, s.background.g, s.background.b, 1.0f);
  glClearDepth(1.0);
  glClearStencil(0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);

  const cel::Frame f = prepareCelFrame(m, frame, cam, viewport, celViewport);
  m.block->upload(f);
  m.opaque->draw(cel::ShadePass::kLit);
  if (m.hasAtlas) {
    const cel::DrawStats up = m.nailboards->upload(particles);
    if (stats) stats->bytesUploaded = up.bytesUploaded;
    if (m.fillRateFloor) {
      m.nailboards->drawBaseline(s.style);
    } else {
      m.nailboards->drawNailboards(s.style, cel::ShadePass::kLit);
    }
    if (s.style.shadows && !m.fillRateFloor) {
      m.nailboards->drawShadowVolumes(s.style, m.floorPlane);
      m.opaque->draw(cel::ShadePass::kShadowed);
      m.nailboards->drawNailboards(s.style, cel::ShadePass::kShadowed);
    }
  }
  if (m.media) {
    drawMedia(frame, cam, viewport, static_cast<GLuint>(callerFbo), stats);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(callerRead));
  }
}

void SceneRenderer::drawMedia(int frame, const cel::Camera& cam, const cel::Viewport& viewport, GLuint target,
                              FrameStats* stats) {
  Impl& m = *impl_;
  const Scene& s = m.scene;
  const MediaSpec& spec = *s.media;
  // The particles: listed, then simulated (radius growing, density fading over their lives).
  std::vector<media::Particle>& ps = m.mediaParticles;
  ps.clear();
  for (const MediaParticleSpec& p : spec.particles) {
    ps.push_back(
        media::Particle{p.position, p.radius, static_cast<std::uint32_t>(p.materialIndex), p.life, p.density, p.seed});
  }
  double simulateMs = 0.0;
  if (m.mediaSim) {
    const auto t0 = std::chrono::steady_clock::now();
    m.mediaSim->advanceToFrame(frame);
    simulateMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    for (std::size_t i = 0; i < m.mediaSim->size(); ++i) {
      const sim::ParticleState p = m.mediaSim->particle(i);
      const MediaEmitterSpec& e = spec.emitters[static_cast<std::size_t>(p.emitter)];
      const float life = std::clamp(p.age / p.lifetime, 0.0f, 1.0f);
      // The emitter's density multiplies the material's tau and falls linearly to 0 with age.
      ps.push_back(media::Particle{p.position, 0.5f * p.birthSize * (1.0f + e.growth * life),
                                   static_cast<std::uint32_t>(e.materialIndex), life, p.density, p.id});
    }
  }
  m.layers->resolveOpaque();
  m.layers->beginMedia();
  media::Frame mf;
  mf.view = cam.view();
  mf.projection = cam.projection(static_cast<float>(viewport.width) / static_cast<float>(viewport.height));
  mf.nearPlane = cam.nearPlane;
  mf.farPlane = cam.farPlane;
  mf.orthographic = cam.fovYDegrees == 0.0f;
  mf.lightDirection = s.light.direction;
  mf.lightColor = s.light.color;
  mf.ambient = s.ambientColor;
  mf.time = frameTime(s, frame);
  mf.width = viewport.width;
  mf.height = viewport.height;
  media::DrawStats ds;
  m.media->draw(m.layers->layerFrame(mf), ps, spec.method, m.layers->mediaDepth(), spec.compose.shimmerPixels > 0.0f,
                &ds);
  std::vector<media::ExplosionLight> lights;
  for (const MediaLightSpec& l : spec.lights) {
    lights.push_back(
        media::ExplosionLight{l.center, l.radius, l.color, l.intensityAt(mf.time), l.modulate, l.fullAtBack});
  }
  const int vp[4] = {viewport.x, viewport.y, viewport.width, viewport.height};
  m.layers->compose(target, vp, mf, lights, spec.compose);
  m.lastMediaFrame = mf;
  if (stats) {
    stats->mediaParticles = ds.particles;
    stats->simulateMs += simulateMs;
  }
}

Result<SceneRenderer::MediaFrameInputs> SceneRenderer::lastMediaFrame() const {
  const Impl& m = *impl_;
  if (!m.media) return Error{"the scene has no media, or this path does not draw them"};
  if (!m.layers || !m.lastMediaFrame) return Error{"no frame with media has been drawn yet"};
  MediaFrameInputs in;
  in.frame = *m.lastMediaFrame;
  in.particles = m.mediaParticles;
  const std::size_t n = static_cast<std::size_t>(m.layers->width()) * static_cast<std::size_t>(m.layers->height());
  in.opaqueColor.resize(n);
  in.opaqueDepth.resize(n);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(m.layers->opaqueColor(), 0, GL_RGB, GL_FLOAT, static_cast<GLsizei>(n * sizeof(glm::vec3)),
                    in.opaqueColor.data());
  glGetTextureImage(m.layers->opaqueDepth(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(n * sizeof(float)),
                    in.opaqueDepth.data());
  if (const std::string e = core::drainGlErrors(); !e.empty()) return Error{"reading the opaque layer back: " + e};
  return in;
}

Result<core::Image> SceneRenderer::renderFrame(int frame, FrameStats* stats) {
  Impl& m = *impl_;
  Target& t = m.target;
  std::vector<unsigned char> bytes(static_cast<std::size_t>(t.width) * t.height * 4);
  if (t.contextFramebuffer) {
    // GL 1.x-era context: draw and read the context's own framebuffer (only 1.x calls here).
    drawFrame(frame, cel::Viewport{0, 0, t.width, t.height}, stats);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
  } else {
    glBindFramebuffer(GL_FRAMEBUFFER, t.fbo.get());
    drawFrame(frame, cel::Viewport{0, 0, t.width, t.height}, stats);
    GLuint readFbo = t.fbo.get();
    if (t.samples > 1) {
      glBlitNamedFramebuffer(t.fbo.get(), t.resolveFbo.get(), 0, 0, t.width, t.height, 0, 0, t.width, t.height,
                             GL_COLOR_BUFFER_BIT, GL_NEAREST);
      readFbo = t.resolveFbo.get();
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  if (!m.lastError.empty()) {
    std::string e = std::move(m.lastError);
    m.lastError.clear();
    return Error::at(m.scene.file, "frame " + std::to_string(frame) + ": " + e);
  }
  const std::string glErrors = core::drainGlErrors();
  if (!glErrors.empty())
    return Error::at(m.scene.file, "GL error while rendering frame " + std::to_string(frame) + ": " + glErrors);
  core::Image image(t.width, t.height, 4);
  for (int y = 0; y < t.height; ++y) {
    const unsigned char* row = &bytes[static_cast<std::size_t>(t.height - 1 - y) * t.width * 4];
    for (int i = 0; i < t.width * 4; ++i) image.pixels[static_cast<std::size_t>(y) * t.width * 4 + i] = row[i] / 255.0f;
  }
  return image;
}

}  // namespace puff::render
