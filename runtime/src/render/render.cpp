// SceneRenderer: the scene's evaluation, the target and its read-back, motion blur, and the path.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include <puff/cel/nailboards.h>
#include <puff/cel/opaque.h>
#include <puff/core/colour.h>
#include <puff/core/gl.h>
#include <puff/core/number_text.h>
#include <puff/gl_api.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>
#include <puff/render/render.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/geometry.h>

#include "paths.h"
#include "target.h"

namespace puff::render {

namespace {

Result<std::unique_ptr<SceneRenderer>> createCel(const scene::Scene& scene, DrawTarget) {
  return SceneRenderer::create(
      scene, [](const scene::Scene& s, const scene::SceneGeometry& g) { return detail::createCelPath(s, g); });
}

Result<std::unique_ptr<SceneRenderer>> createFixed(const scene::Scene& scene, DrawTarget target) {
  return SceneRenderer::create(scene, [target](const scene::Scene& s, const scene::SceneGeometry& g) {
    return detail::createFixedPath(s, g, target);
  });
}

std::vector<std::string> celOmissions(const scene::Scene&) { return {}; }

std::vector<std::string> fixedOmissions(const scene::Scene& scene) {
  std::vector<std::string> lines;
  if (scene.media) lines.push_back("the fixed-function path draws no fire, smoke or dust: /media is left out");
  if (scene.style.shadows) {
    lines.push_back(
        "the fixed-function path draws no shadows (neither the puffs' nor the objects'): /style/shadows is left out");
  }
  if (!scene::orientedPuffs(scene).empty()) {
    lines.push_back(
        "the fixed-function path draws every puff as a view-plane billboard: oriented puffs do not turn there");
  }
  return lines;
}

std::vector<std::string> referenceOmissions(const scene::Scene& scene) {
  if (!scene.media) return {};
  return {
      "the media are drawn by the physical reference (the particles' density fields integrated along every ray "
      "on the CPU, step halved until the image changes by < 1e-4 RMSE): seconds per frame; no explosion lights, "
      "heat shimmer or motion blur"};
}

}  // namespace

const std::vector<RenderPathInfo>& renderPathTable() {
  static const std::vector<RenderPathInfo> table = {
      {RenderPath::kCel, "cel",
       "programmable GL 4.5 (McGuire & Fein 2006): nailboards with cel shading, outlines from the flange, shadows "
       "from a light-space map or billboard shadow volumes; the media pass for fire, smoke and dust",
       createCel, true, celOmissions},
      {RenderPath::kFixed, "fixed",
       "GL 1.x fixed function (McGuire & Fein 2006, 4.4): flat billboards of a per-frame puff texture, backing "
       "billboards for outlines; one light, uniform ambient, no shadows",
       createFixed, false, fixedOmissions},
      {RenderPath::kReference, "reference",
       "the image the nailboards approximate: every particle's actual puff mesh, Eq. 2 per pixel, outlines around "
       "the true silhouettes, exact shadows; supersampled 3x3 and slow; media by the physical reference (the "
       "particles' summed density fields integrated along every ray on the CPU, seconds per frame)",
       nullptr, false, referenceOmissions},
  };
  return table;
}

std::vector<RenderPathInfo> renderPaths() {
  std::vector<RenderPathInfo> paths;
  for (const RenderPathInfo& p : renderPathTable()) {
    if (p.create) paths.push_back(p);
  }
  return paths;
}

const RenderPathInfo& renderPathInfo(RenderPath path) {
  for (const RenderPathInfo& p : renderPathTable()) {
    if (p.path == path) return p;
  }
  PUFF_CHECK(false && "every RenderPath has a row in renderPathTable()");
  return renderPathTable().front();
}

std::string_view toString(RenderPath path) { return renderPathInfo(path).name; }

std::optional<RenderPath> parseRenderPath(std::string_view name) {
  for (const RenderPathInfo& p : renderPathTable()) {
    if (name == p.name) return p.path;
  }
  return std::nullopt;
}

std::string renderPathNames(std::string_view separator) {
  std::string names;
  for (const RenderPathInfo& p : renderPathTable()) {
    if (!names.empty()) names += separator;
    names += p.name;
  }
  return names;
}

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

// Each particle of `now` where it is in `later` (position, size), matched by key; where it is gone,
// or its key is not one particle's alone in either frame (simulated ids that collide, a loop's
// particles born again under an id still alive), where it is now.
std::vector<glm::vec4> nextPositions(const scene::FrameInputs& now, const scene::FrameInputs& later) {
  constexpr std::size_t kShared = static_cast<std::size_t>(-1);
  std::unordered_map<std::uint64_t, std::size_t> at, here;
  at.reserve(later.keys.size());
  for (std::size_t i = 0; i < later.keys.size(); ++i) {
    const auto [it, fresh] = at.emplace(later.keys[i], i);
    if (!fresh) it->second = kShared;
  }
  here.reserve(now.keys.size());
  for (std::size_t i = 0; i < now.keys.size(); ++i) {
    const auto [it, fresh] = here.emplace(now.keys[i], i);
    if (!fresh) it->second = kShared;
  }
  std::vector<glm::vec4> next;
  next.reserve(now.particles.size());
  for (std::size_t i = 0; i < now.particles.size(); ++i) {
    const auto found = i < now.keys.size() ? at.find(now.keys[i]) : at.end();
    const bool alone = found != at.end() && found->second != kShared && here.at(now.keys[i]) != kShared;
    const cel::Particle& p = alone ? later.particles[found->second] : now.particles[i];
    next.emplace_back(p.position, p.size);
  }
  return next;
}

}  // namespace

struct SceneRenderer::Impl {
  scene::Scene scene;
  PathFactory factory;
  scene::SceneGeometry geometry;
  std::unique_ptr<Path> path;
  std::unique_ptr<scene::FrameEvaluator> evaluator;
  detail::Target target;
  std::vector<HistoryTag> history;    // motion blur's kept frames, one per slot
  int pathWidth = 0, pathHeight = 0;  // the frame size the path was made for
  // The benchmarks' and tests' switches (setFillRateFloor, setMediaOverWholeFrame,
  // setLitShading, setHullOcclusion), kept across the paths a renderer makes again.
  struct Switches {
    bool fillRateFloor = false, mediaOverWholeFrame = false;
    cel::LitShading litShading = cel::LitShading::kAuto;
    cel::HullOcclusion hullOcclusion = cel::HullOcclusion::kAuto;
    cel::FrameOutput output = cel::FrameOutput::kColour;  // setOutput
    MapRanges ranges;
  } switches;
  detail::Target mapTarget;  // made on the first map frame (RGBA32F, the target's size and samples)
  // The frame drawn last with the scene's camera, and for a motion map its particles' next positions.
  std::optional<scene::FrameInputs> last;
  std::vector<glm::vec4> lastNext;
  void configure(Path& p) const {
    p.setFillRateFloor(switches.fillRateFloor);
    p.setMediaOverWholeFrame(switches.mediaOverWholeFrame);
    p.setLitShading(switches.litShading);
    p.setHullOcclusion(switches.hullOcclusion);
    // A path made again is of the kind that took the output before.
    (void)p.setOutput(switches.output, switches.ranges);
  }
};

SceneRenderer::SceneRenderer() : impl_(std::make_unique<Impl>()) {}
SceneRenderer::~SceneRenderer() = default;
const scene::Scene& SceneRenderer::scene() const { return impl_->scene; }
RenderPath SceneRenderer::path() const { return impl_->path->kind(); }
TargetNeeds SceneRenderer::targetNeeds() const { return impl_->path->targetNeeds(); }

void SceneRenderer::setFillRateFloor(bool on) {
  impl_->switches.fillRateFloor = on;
  impl_->configure(*impl_->path);
}

void SceneRenderer::setLitShading(cel::LitShading shading) {
  impl_->switches.litShading = shading;
  impl_->configure(*impl_->path);
}

void SceneRenderer::setHullOcclusion(cel::HullOcclusion occlusion) {
  impl_->switches.hullOcclusion = occlusion;
  impl_->configure(*impl_->path);
}

Result<void> SceneRenderer::setOutput(cel::FrameOutput output, const MapRanges& ranges) {
  for (const auto& [value, what] : {std::pair{ranges.depth, "depth"}, {ranges.motion, "motion"}}) {
    if (!(std::isfinite(value) && value > 0.0f))
      return Error{std::string("the ") + what + " map's range " + core::numberText(value) + ": need a positive number"};
  }
  PUFF_TRY(impl_->path->setOutput(output, ranges));
  impl_->switches.output = output;
  impl_->switches.ranges = ranges;
  impl_->history.clear();  // motion blur's kept frames hold the other output
  return {};
}

cel::FrameOutput SceneRenderer::output() const { return impl_->switches.output; }

void SceneRenderer::setMediaOverWholeFrame(bool on) {
  impl_->switches.mediaOverWholeFrame = on;
  impl_->configure(*impl_->path);
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
  return {};
}

Result<std::unique_ptr<SceneRenderer>> SceneRenderer::create(const scene::Scene& scene, RenderPath path,
                                                             DrawTarget target) {
  const RenderPathInfo& info = renderPathInfo(path);
  if (!info.create) {
    return Error{"the " + info.name + " path is measurement: puff::eval makes it (eval::createRenderer)"};
  }
  return info.create(scene, target);
}

Result<std::unique_ptr<SceneRenderer>> SceneRenderer::create(const scene::Scene& scene, PathFactory factory) {
  std::unique_ptr<SceneRenderer> r(new SceneRenderer());
  Impl& m = *r->impl_;
  m.scene = scene;
  m.factory = std::move(factory);
  PUFF_TRY_ASSIGN(auto geometry, scene::loadGeometry(scene));
  m.geometry = std::move(geometry);
  PUFF_TRY_ASSIGN(auto path, m.factory(scene, m.geometry));
  m.path = std::move(path);
  m.pathWidth = scene.width;
  m.pathHeight = scene.height;
  const TargetNeeds needs = m.path->targetNeeds();
  if (needs.contextFramebuffer) {
    m.target = detail::Target::contextOwn(scene.width, scene.height);
  } else {
    PUFF_TRY_ASSIGN(m.target, detail::Target::create(scene.width, scene.height, needs.samples, needs.displayValues));
  }
  PUFF_TRY_ASSIGN(m.evaluator, scene::FrameEvaluator::create(scene, m.geometry, m.path->variations(),
                                                             m.path->drawsMedia() ? scene::MediaEvaluation::kEvaluate
                                                                                  : scene::MediaEvaluation::kSkip));
  return r;
}

Result<void> SceneRenderer::update(const scene::Scene& next) {
  Impl& m = *impl_;
  m.history.clear();  // kept frames were drawn from the old scene
  m.last.reset();
  const scene::Scene& now = m.scene;
  const bool targetChanged = now.width != next.width || now.height != next.height || now.samples != next.samples;
  if (targetChanged || now.objects != next.objects || m.path->needsRebuild(now, next)) {
    PUFF_TRY_ASSIGN(auto fresh, create(next, m.factory));
    const Impl::Switches switches = m.switches;
    impl_ = std::move((fresh)->impl_);  // `m` and `now` are gone from here on
    impl_->switches = switches;
    impl_->configure(*impl_->path);
    return {};
  }
  if (m.evaluator->needsRebuild(next)) {
    PUFF_TRY_ASSIGN(auto evaluator,
                    scene::FrameEvaluator::create(
                        next, m.geometry, m.path->variations(),
                        m.path->drawsMedia() ? scene::MediaEvaluation::kEvaluate : scene::MediaEvaluation::kSkip));
    m.evaluator = std::move(evaluator);
  } else if (auto ok = m.evaluator->update(next); !ok) {
    return ok.error();
  }
  m.scene = next;
  return {};
}

Result<void> SceneRenderer::drawFrame(int frame, const cel::Viewport& viewport, FrameStats* stats,
                                      const cel::Camera* camera) {
  fitPathTo(viewport);
  const scene::Scene& s = impl_->scene;
  // The references model no motion blur (docs/media.md): only a path with media layers blurs.
  if (s.media && s.media->motionBlurFrames > 0 && impl_->path->drawsMedia() &&
      impl_->switches.output == cel::FrameOutput::kColour && renderPathInfo(impl_->path->kind()).motionBlur) {
    return drawBlurred(frame, viewport, stats, camera);
  }
  return drawSingle(frame, viewport, stats, camera);
}

void SceneRenderer::fitPathTo(const cel::Viewport& viewport) {
  Impl& m = *impl_;
  if (!m.path->targetNeeds().sizedToFrame) return;
  if (viewport.width == m.pathWidth && viewport.height == m.pathHeight) return;
  m.pathWidth = viewport.width;
  m.pathHeight = viewport.height;
  scene::Scene sized = m.scene;
  sized.width = viewport.width;
  sized.height = viewport.height;
  // A frame too small for the path keeps the path it has (which then says so when it draws).
  if (auto path = m.factory(sized, m.geometry)) {
    m.path = std::move(*path);
    m.configure(*m.path);
  }
}

Result<void> SceneRenderer::drawSingle(int frame, const cel::Viewport& viewport, FrameStats* stats,
                                       const cel::Camera* camera) {
  Impl& m = *impl_;
  // A map frame with the scene's camera keeps what it evaluated: the same frame drawn again (another
  // map, a transparent frame's second background) is not evaluated again, so a simulation that
  // stepped on to the next frame for a motion map is not run again from the start.
  const bool keep = m.switches.output != cel::FrameOutput::kColour && !camera;
  std::optional<scene::FrameInputs> own;
  double simulateMs = 0.0;
  if (!keep) {
    own = m.evaluator->evaluate(frame, camera);
    simulateMs = own->simulateMs;
    m.last.reset();
  } else if (!m.last || m.last->frame != frame) {
    m.last = m.evaluator->evaluate(frame);
    simulateMs = m.last->simulateMs;
    m.lastNext.clear();
  }
  const scene::FrameInputs& inputs = keep ? *m.last : *own;
  FrameStats unused;
  FrameStats& st = stats ? *stats : unused;
  st.particles = inputs.particles.size();
  st.simulated = inputs.simulated;
  st.simulateMs = simulateMs;
  st.bytesUploaded = 0;
  const bool motion = m.switches.output == cel::FrameOutput::kMotion;
  if (motion && (!keep || m.lastNext.empty()))
    m.lastNext = nextPositions(inputs, m.evaluator->evaluate(frame + 1, camera));
  const std::span<const glm::vec4> next =
      motion ? std::span<const glm::vec4>(m.lastNext) : std::span<const glm::vec4>();
  return m.path->draw(PathFrame{m.scene, inputs, viewport, st, next});
}

// Motion blur: frame k is sum_i w_i F(k - i), i = 0..n, w_i = p^i normalized over the frames that
// exist (k - i >= 0). Each F is a pure function of its frame (and camera), kept in a ring of n + 1
// slots of the media layers, so a sequence draws one new frame per call and a frame alone draws the
// n before it first: the same sums, the same pixels.
Result<void> SceneRenderer::drawBlurred(int frame, const cel::Viewport& viewport, FrameStats* stats,
                                        const cel::Camera* camera) {
  Impl& m = *impl_;
  const scene::Scene& s = m.scene;
  GLint callerFbo = 0, callerRead = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &callerFbo);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &callerRead);
  const int n = s.media->motionBlurFrames;
  PUFF_TRY_ASSIGN(auto layers, m.path->mediaLayers(s, viewport));
  media::Layers& history = *layers;
  history.setHistorySlots(n + 1);
  m.history.resize(static_cast<std::size_t>(n + 1));
  const cel::Viewport local{0, 0, viewport.width, viewport.height};
  std::vector<int> slots;
  std::vector<float> weights;
  float total = 0.0f;
  // A loop's frames before 0 are its last ones (frame f - period draws what frame f does).
  const int period = s.animation.period;
  auto wrap = [](int k, int count) { return ((k % count) + count) % count; };
  for (int k = period > 0 ? frame - n : std::max(0, frame - n); k <= frame; ++k) {
    const int drawn = period > 0 && k < 0 ? wrap(k, period) : k;
    const cel::Camera cam = camera ? *camera : scene::cameraAt(s, drawn);
    const int slot = wrap(k, n + 1);
    const HistoryTag tag = historyTag(k, cam, viewport);
    if (k == frame || !(m.history[static_cast<std::size_t>(slot)] == tag)) {
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, history.historyFramebuffer(slot));
      if (auto ok = drawSingle(drawn, local, k == frame ? stats : nullptr, &cam); !ok) return ok;
      m.history[static_cast<std::size_t>(slot)] = tag;
    }
    const float w = std::pow(s.media->motionBlurPersistence, static_cast<float>(frame - k));
    slots.push_back(slot);
    weights.push_back(w);
    total += w;
  }
  for (float& w : weights) w /= total;
  const core::Viewport& vp = viewport;
  history.blendHistory(static_cast<GLuint>(callerFbo), vp, slots, weights);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(callerRead));
  return {};
}

Result<SceneRenderer::MediaFrameInputs> SceneRenderer::lastMediaFrame() const { return impl_->path->lastMediaFrame(); }

Result<core::Image> SceneRenderer::renderFrame(int frame, FrameStats* stats) {
  if (!impl_->scene.transparent) return renderOpaque(frame, stats);
  // A transparent frame: drawn over black and over white. Every pass is affine in the background
  // (a sample is covered, kept, or attenuated by media transmittance T with light added; MSAA
  // resolve, motion blur and shimmer mix linearly), so per pixel F(B) = P + (1 - a) B: the black
  // frame is the premultiplied colour P and 1 - a is the white frame minus the black one.
  Impl& m = *impl_;
  const scene::Scene kept = m.scene;
  auto over = [&](float background, FrameStats* st) {
    m.scene.transparent = false;
    m.scene.background = glm::vec3(background);  // display 0 and 1 are linear 0 and 1
    m.history.clear();                           // motion blur's kept frames had the other background
    auto image = renderOpaque(frame, st);
    m.scene = kept;
    m.history.clear();
    return image;
  };
  PUFF_TRY_ASSIGN(auto black, over(0.0f, stats));
  PUFF_TRY_ASSIGN(auto white, over(1.0f, nullptr));
  core::Image& out = black;
  const std::size_t n = static_cast<std::size_t>(out.width) * out.height;
  for (std::size_t i = 0; i < n; ++i) {
    float* p = &out.pixels[i * 4];
    const float* w = &white.pixels[i * 4];
    const float behind = ((w[0] - p[0]) + (w[1] - p[1]) + (w[2] - p[2])) / 3.0f;  // 1 - a
    p[3] = std::clamp(1.0f - behind, 0.0f, 1.0f);
  }
  return black;
}

Result<core::Image> SceneRenderer::renderOpaque(int frame, FrameStats* stats) {
  Impl& m = *impl_;
  if (m.switches.output != cel::FrameOutput::kColour &&
      (m.mapTarget.width != m.target.width || m.mapTarget.height != m.target.height ||
       m.mapTarget.samples != m.target.samples)) {
    PUFF_TRY_ASSIGN(m.mapTarget, detail::Target::createData(m.target.width, m.target.height, m.target.samples));
  }
  detail::Target& t = m.switches.output == cel::FrameOutput::kColour ? m.target : m.mapTarget;
  const std::size_t values = static_cast<std::size_t>(t.width) * t.height * 4;
  std::vector<unsigned char> bytes;
  std::vector<float> floats;
  // Display values come back as the 8 bits they are; scene-linear ones as floats (half floats
  // widen exactly).
  auto readBack = [&] {
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (t.displayValues) {
      bytes.resize(values);
      glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
    } else {
      floats.resize(values);
      glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_FLOAT, floats.data());
    }
  };
  Result<void> drawn;
  if (t.contextFramebuffer) {
    // GL 1.x-era context: draw and read the context's own framebuffer (only 1.x calls here).
    drawn = drawFrame(frame, cel::Viewport{0, 0, t.width, t.height}, stats);
    readBack();
  } else {
    glBindFramebuffer(GL_FRAMEBUFFER, t.fbo.get());
    drawn = drawFrame(frame, cel::Viewport{0, 0, t.width, t.height}, stats);
    GLuint readFbo = t.fbo.get();
    if (t.samples > 1) {
      glBlitNamedFramebuffer(t.fbo.get(), t.resolveFbo.get(), 0, 0, t.width, t.height, 0, 0, t.width, t.height,
                             GL_COLOR_BUFFER_BIT, GL_NEAREST);
      readFbo = t.resolveFbo.get();
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    readBack();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  if (!drawn) return Error::at(m.scene.file, "frame " + std::to_string(frame) + ": " + drawn.error().message);
  const std::string glErrors = core::drainGlErrors();
  if (!glErrors.empty())
    return Error::at(m.scene.file, "GL error while rendering frame " + std::to_string(frame) + ": " + glErrors);
  core::Image image(t.width, t.height, 4);
  const std::size_t row = static_cast<std::size_t>(t.width) * 4;
  for (int y = 0; y < t.height; ++y) {
    const std::size_t src = static_cast<std::size_t>(t.height - 1 - y) * row;
    float* dst = &image.pixels[static_cast<std::size_t>(y) * row];
    for (std::size_t i = 0; i < row; ++i) {
      dst[i] = t.displayValues ? static_cast<float>(bytes[src + i]) / 255.0f : floats[src + i];
    }
  }
  // Display values (the fixed path's 8 bits) to scene-linear, alpha as it is.
  return t.displayValues ? core::decodeSrgb(image) : image;
}

}  // namespace puff::render
