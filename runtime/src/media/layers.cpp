// Layer composition: the opaque target, the low-resolution media layer and the compose pass.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <glm/matrix.hpp>

#include <puff/core/bind_points.h>
#include <puff/core/blackbody.h>
#include <puff/core/limits.h>
#include <puff/core/shader.h>
#include <puff/gl_api.h>
#include <puff/media/layers.h>
#include <puff/shader_blocks.h>

namespace puff::media {

namespace {

using shader::CartoonBlockData;
using shader::ComposeBlockData;
using shader::LightGpu;

// The state Layers' full-screen passes rely on (and leave): no depth or stencil test, blending,
// culling, scissor, rasterizer discard, alpha to coverage or sample mask; filled polygons; colour
// writes on. GL_FRAMEBUFFER_SRGB
// stays the host's: Puff's own targets are float, and a host's sRGB target with the flag on
// encodes the scene-linear colour compose writes (docs/colour.md).
void fullscreenState() {
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_RASTERIZER_DISCARD);
  // A multisampled target: every sample written (composeOver's colour output has alpha 0, which
  // alpha to coverage would turn into no sample at all).
  glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
  glDisable(GL_SAMPLE_MASK);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

// A call the caller may not make (the header says so): one line naming it, then abort, as a
// broken promise of the caller's, not Puff's ("internal check failed" would blame Puff).
// The pixels of `outer` outside `inner` (which lies inside it), as at most four boxes.
std::vector<PixelBox> around(const PixelBox& outer, const PixelBox& inner) {
  if (inner.empty()) return {outer};
  std::vector<PixelBox> strips;
  for (const PixelBox& b :
       {PixelBox{outer.x0, outer.y0, outer.x1, inner.y0}, PixelBox{outer.x0, inner.y1, outer.x1, outer.y1},
        PixelBox{outer.x0, inner.y0, inner.x0, inner.y1}, PixelBox{inner.x1, inner.y0, outer.x1, inner.y1}})
    if (!b.empty()) strips.push_back(b);
  return strips;
}

// Scissors the passes that follow to `box`, offset by the target viewport's origin; nullopt: off.
void scissorTo(const std::optional<PixelBox>& box, int x = 0, int y = 0) {
  if (!box) {
    glDisable(GL_SCISSOR_TEST);
    return;
  }
  glEnable(GL_SCISSOR_TEST);
  glScissor(x + box->x0, y + box->y0, box->x1 - box->x0, box->y1 - box->y0);
}

[[noreturn]] void misuse(const char* message) {
  std::fprintf(stderr, "puff: %s\n", message);
  std::abort();
}

core::Texture makeTexture2D(GLenum format, int w, int h, GLenum filter) {
  core::Texture t = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(t.get(), 1, format, w, h);
  glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, static_cast<GLint>(filter));
  glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, static_cast<GLint>(filter));
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

}  // namespace

struct LayersBase::Impl {
  Bindings bindings;
  int width = 0, height = 0, samples = 1, factor = 1, mediaWidth = 0, mediaHeight = 0;
  float scale = 1.0f;
  Upsampling upsampling = Upsampling::kBilateral;
  core::Framebuffer opaqueFbo, resolveFbo, linearFbo, depthFbo, mediaFbo;
  core::Texture msColor, msDepth;                          // multisample textures (1 sample when MSAA is off)
  core::Texture color, depth, mediaDepth, media, shimmer;  // depth: R32F linear, the samples' nearest
  core::Program resolveDepth, downsample, compose, blur;   // Layers' programs (downsample: both kinds')
  core::Program resolveHost, resolveHostMs, composeOver;   // HostLayers' programs
  std::vector<core::Texture> history;
  std::vector<core::Framebuffer> historyFbo;
  core::VertexArray vao;
  core::Buffer block;
  // The cartoon style (made on first use): the layer's attributes (attachments 2, 3 of mediaFbo),
  // the full-size fill and field, the seeds ping-ponged by the flood passes, and the programs.
  bool cartoonMade = false, cartoonBegun = false;
  core::Texture cartoonFire, cartoonDepth, fill, field, seeds[2];
  core::Framebuffer fieldFbo, seedFbo[2];
  core::Program cartoonField, cartoonSeed, cartoonFlood, cartoonCompose;
  core::Buffer cartoonBlock;
  core::Program copy;  // the opaque colour alone, where the media change nothing (setCoverage)
  // setCoverage: what the media cover (nullopt: the whole frame), the style and ink it was set for.
  std::optional<PixelBox> covered;
  Style coveredStyle = Style::kPhotoreal;
  float coveredInk = 0.0f;
  PixelBox fieldBox;  // what the last cartoon compose's field pass wrote

  // The boxes each pass runs over for the coverage set (full-size pixels; `layer` in layer texels).
  struct Boxes {
    PixelBox compose;  // where the media layer (and the cartoon fill) can differ from none
    PixelBox inked;    // the cartoon compose: where a seed can reach (the ink, the fill's rim)
    PixelBox flood;    // the seeds and the flooding, exact over `inked`
    PixelBox field;    // the cartoon field the seeds read
    PixelBox cleared;  // seeds cleared to none, around `flood`, before the seed pass
    PixelBox layer;    // the layer's depth: every texel a pass above reads, and 3 around
    PixelBox resolve;  // the full-size linear depth: the layer texels' pixels
  };
  Boxes boxes() const;
  bool wholeFrame(const PixelBox& b) const { return b == PixelBox{0, 0, width, height}; }
  // A pass's box for the coverage set: nullopt (the whole frame) without one.
  std::optional<PixelBox> limit(const PixelBox& b) const { return covered ? std::optional(b) : std::nullopt; }

  // What both kinds make: the sizes checked, the downsample program, the compose block, the
  // full-size linear depth, the layer's depth and the media layer.
  static Result<std::unique_ptr<Impl>> make(int width, int height, int samples, float scale, const Bindings& bindings);
  // Layers' programs and its multisampled opaque target with its resolve target.
  Result<void> makeOwn();
  // HostLayers' programs: the host depth resolves and the dual-source compose.
  Result<void> makeHost();
  // An error when a framebuffer made is not complete on this GL.
  Result<void> checkComplete() const;
  // Fills the compose passes' uniform block (compose.glsl's ComposeBlock).
  void uploadComposeBlock(const core::Viewport& viewport, const Frame& frame, std::span<const ExplosionLight> lights,
                          const ComposeSettings& settings);
  // Binds the compose passes' block and layer textures and draws `program` over the viewport
  // (compose binds the opaque colour too; composeOver has none).
  void drawCompose(GLuint program);
  // drawCompose over `box` (the coverage's, in the output viewport), the opaque colour copied
  // around it; over the whole viewport without a coverage.
  void composeWithin(GLuint program, const PixelBox& box, const core::Viewport& viewport);
  // The opaque colour copied to the output viewport's pixels outside `box` (four strips: every
  // pixel written once, which a multisampled target pays per sample).
  void copyAround(const PixelBox& box, const core::Viewport& viewport);
  // The full-size linear depth's layer-resolution nearest (downsample.frag), into depthFbo.
  void downsampleDepth();
  // Makes the cartoon style's textures and framebuffers (its programs are built with the layers).
  void makeCartoon();
  // compose()'s cartoon passes (layers.h, "Cartoon media"), the block already uploaded.
  void composeCartoon(GLuint target, const core::Viewport& viewport, const CartoonCompose& cartoon);
};

namespace {

// The layer's factor (1, 2, 4 or 8) for a `scale` of 1, 1/2, 1/4 or 1/8; 0 for any other.
int layerFactor(float scale) {
  int factor = 0;
  for (int f : {1, 2, 4, 8})
    if (std::abs(scale - 1.0f / static_cast<float>(f)) < 1e-6f) factor = f;
  return factor;
}

Result<core::Program> fullscreenProgram(const char* fragment) {
  return core::buildProgram({"media/fullscreen.vert", fragment});
}

}  // namespace

Result<std::unique_ptr<LayersBase::Impl>> LayersBase::Impl::make(int width, int height, int samples, float scale,
                                                                 const Bindings& bindings) {
  PUFF_TRY(validate(bindings));
  if (width < 1 || height < 1 || width > core::kMaxImageSize || height > core::kMaxImageSize)
    return Error{"media layers: size " + std::to_string(width) + "x" + std::to_string(height) + " outside 1.." +
                 std::to_string(core::kMaxImageSize)};
  const int factor = layerFactor(scale);
  if (factor == 0) return Error{"media resolution: expected 1, 0.5, 0.25 or 0.125, got " + std::to_string(scale)};
  GLint maxSamples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  if (samples < 1 || samples > maxSamples)
    return Error{std::to_string(samples) + " samples per pixel asked, but this GL gives 1 to " +
                 std::to_string(maxSamples)};
  auto m = std::make_unique<Impl>();
  PUFF_TRY_ASSIGN(m->downsample, fullscreenProgram("media/downsample.frag"));
  m->width = width, m->height = height, m->samples = samples, m->factor = factor, m->scale = scale;
  m->mediaWidth = std::max(1, (width + factor - 1) / factor);
  m->mediaHeight = std::max(1, (height + factor - 1) / factor);
  m->bindings = bindings;
  core::assignBindPoints(m->downsample.get(),
                         {{core::BindPoint::Kind::kSampler, "uDepthFull", bindings.resolveSource}});
  m->vao = core::makeVertexArray();
  m->block = core::makeBuffer();
  glNamedBufferStorage(m->block.get(), sizeof(ComposeBlockData), nullptr, GL_DYNAMIC_STORAGE_BIT);

  m->depth = makeTexture2D(GL_R32F, width, height, GL_NEAREST);
  m->linearFbo = core::makeFramebuffer();
  glNamedFramebufferTexture(m->linearFbo.get(), GL_COLOR_ATTACHMENT0, m->depth.get(), 0);
  m->mediaDepth = makeTexture2D(GL_R32F, m->mediaWidth, m->mediaHeight, GL_NEAREST);
  m->depthFbo = core::makeFramebuffer();
  glNamedFramebufferTexture(m->depthFbo.get(), GL_COLOR_ATTACHMENT0, m->mediaDepth.get(), 0);
  // 32-bit floats: Mesa llvmpipe blends half floats rounding toward zero, which over the ~100 layers of
  // a camera inside smoke darkened the image by 0.004 (4x the 8-bit rounding; puffbench measures it).
  m->media = makeTexture2D(GL_RGBA32F, m->mediaWidth, m->mediaHeight, GL_NEAREST);
  m->shimmer = makeTexture2D(GL_RG16F, m->mediaWidth, m->mediaHeight, GL_NEAREST);
  m->mediaFbo = core::makeFramebuffer();
  glNamedFramebufferTexture(m->mediaFbo.get(), GL_COLOR_ATTACHMENT0, m->media.get(), 0);
  glNamedFramebufferTexture(m->mediaFbo.get(), GL_COLOR_ATTACHMENT1, m->shimmer.get(), 0);
  const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(m->mediaFbo.get(), 2, both);
  return m;
}

Result<void> LayersBase::Impl::makeOwn() {
  PUFF_TRY_ASSIGN(resolveDepth, fullscreenProgram("media/resolve_depth.frag"));
  PUFF_TRY_ASSIGN(compose, fullscreenProgram("media/compose.frag"));
  PUFF_TRY_ASSIGN(blur, fullscreenProgram("media/blur.frag"));
  PUFF_TRY_ASSIGN(cartoonField, fullscreenProgram("media/cartoon_field.frag"));
  PUFF_TRY_ASSIGN(cartoonSeed, fullscreenProgram("media/cartoon_seed.frag"));
  PUFF_TRY_ASSIGN(cartoonFlood, fullscreenProgram("media/cartoon_flood.frag"));
  PUFF_TRY_ASSIGN(cartoonCompose, fullscreenProgram("media/cartoon_compose.frag"));
  PUFF_TRY_ASSIGN(copy, fullscreenProgram("media/copy.frag"));
  using K = core::BindPoint::Kind;
  const Bindings& b = bindings;
  const unsigned c = b.cartoonFirst;
  core::assignBindPoints(resolveDepth.get(), {{K::kSampler, "uDepthMS", b.resolveSource}});
  core::assignBindPoints(blur.get(), {{K::kSampler, "uHistory[0]", b.historyFirst, shader::kMaxBlurFrames}});
  core::assignBindPoints(compose.get(), {{K::kUniformBlock, "ComposeBlock", b.composeBlock},
                                         {K::kSampler, "uOpaqueColor", b.opaqueColor},
                                         {K::kSampler, "uOpaqueDepth", b.opaqueDepth},
                                         {K::kSampler, "uMedia", b.mediaLayer},
                                         {K::kSampler, "uMediaDepth", b.mediaDepth},
                                         {K::kSampler, "uShimmerTex", b.shimmer}});
  core::assignBindPoints(
      copy.get(), {{K::kUniformBlock, "ComposeBlock", b.composeBlock}, {K::kSampler, "uOpaqueColor", b.opaqueColor}});
  core::assignBindPoints(cartoonField.get(), {{K::kUniformBlock, "ComposeBlock", b.composeBlock},
                                              {K::kUniformBlock, "CartoonBlock", b.cartoonBlock},
                                              {K::kSampler, "uOpaqueDepth", b.opaqueDepth},
                                              {K::kSampler, "uMedia", b.mediaLayer},
                                              {K::kSampler, "uMediaDepth", b.mediaDepth},
                                              {K::kSampler, "uShimmerTex", b.shimmer},
                                              {K::kSampler, "uCartoonFire", c},
                                              {K::kSampler, "uCartoonDepth", c + 1}});
  core::assignBindPoints(cartoonSeed.get(),
                         {{K::kUniformBlock, "CartoonBlock", b.cartoonBlock}, {K::kSampler, "uField", c + 1}});
  core::assignBindPoints(cartoonFlood.get(),
                         {{K::kUniformBlock, "CartoonBlock", b.cartoonBlock}, {K::kSampler, "uSeeds", c + 2}});
  core::assignBindPoints(cartoonCompose.get(), {{K::kUniformBlock, "ComposeBlock", b.composeBlock},
                                                {K::kUniformBlock, "CartoonBlock", b.cartoonBlock},
                                                {K::kSampler, "uOpaqueColor", b.opaqueColor},
                                                {K::kSampler, "uOpaqueDepth", b.opaqueDepth},
                                                {K::kSampler, "uMedia", b.mediaLayer},
                                                {K::kSampler, "uMediaDepth", b.mediaDepth},
                                                {K::kSampler, "uShimmerTex", b.shimmer},
                                                {K::kSampler, "uFill", c},
                                                {K::kSampler, "uField", c + 1},
                                                {K::kSampler, "uSeeds", c + 2}});

  // Opaque pass: multisample textures (the depth is read per sample), resolved into textures.
  opaqueFbo = core::makeFramebuffer();
  msColor = core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE);
  msDepth = core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE);
  // Scene-linear colour (docs/colour.md): half floats, as the output target.
  glTextureStorage2DMultisample(msColor.get(), samples, GL_RGBA16F, width, height, GL_TRUE);
  glTextureStorage2DMultisample(msDepth.get(), samples, GL_DEPTH24_STENCIL8, width, height, GL_TRUE);
  glTextureParameteri(msDepth.get(), GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
  glNamedFramebufferTexture(opaqueFbo.get(), GL_COLOR_ATTACHMENT0, msColor.get(), 0);
  glNamedFramebufferTexture(opaqueFbo.get(), GL_DEPTH_STENCIL_ATTACHMENT, msDepth.get(), 0);
  color = makeTexture2D(GL_RGBA16F, width, height, GL_NEAREST);
  resolveFbo = core::makeFramebuffer();
  glNamedFramebufferTexture(resolveFbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  return {};
}

Result<void> LayersBase::Impl::makeHost() {
  PUFF_TRY_ASSIGN(resolveHost, fullscreenProgram("media/resolve_host_depth.frag"));
  PUFF_TRY_ASSIGN(resolveHostMs, fullscreenProgram("media/resolve_host_depth_ms.frag"));
  PUFF_TRY_ASSIGN(composeOver, fullscreenProgram("media/compose_over.frag"));
  using K = core::BindPoint::Kind;
  const Bindings& b = bindings;
  core::assignBindPoints(resolveHost.get(), {{K::kSampler, "uHostDepth", b.resolveSource}});
  core::assignBindPoints(resolveHostMs.get(), {{K::kSampler, "uHostDepth", b.resolveSource}});
  core::assignBindPoints(composeOver.get(), {{K::kUniformBlock, "ComposeBlock", b.composeBlock},
                                             {K::kSampler, "uOpaqueDepth", b.opaqueDepth},
                                             {K::kSampler, "uMedia", b.mediaLayer},
                                             {K::kSampler, "uMediaDepth", b.mediaDepth},
                                             {K::kSampler, "uShimmerTex", b.shimmer}});
  return {};
}

Result<void> LayersBase::Impl::checkComplete() const {
  for (GLuint fbo : {opaqueFbo.get(), resolveFbo.get(), linearFbo.get(), depthFbo.get(), mediaFbo.get()}) {
    if (fbo != 0 && glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      return Error{"media layers of " + std::to_string(width) + "x" + std::to_string(height) + " with " +
                   std::to_string(samples) + " samples are not supported by this GL"};
  }
  return {};
}

void LayersBase::Impl::uploadComposeBlock(const core::Viewport& viewport, const Frame& frame,
                                          std::span<const ExplosionLight> lights, const ComposeSettings& settings) {
  ComposeBlockData d{};
  d.invProj = glm::inverse(frame.projection);
  d.viewport = glm::vec4(viewport.x, viewport.y, viewport.width, viewport.height);
  d.depth = glm::vec4(frame.nearPlane, frame.farPlane, frame.farPlane - frame.nearPlane, frame.orthographic ? 1 : 0);
  d.layer = glm::vec4(mediaWidth, mediaHeight, factor, settings.depthTolerance);
  d.shimmer = glm::vec4(settings.shimmerPixels, 0.0f, 0.0f, 0.0f);
  int n = 0;
  for (const ExplosionLight& l : lights) {
    if (n == shader::kMaxLights) break;
    if (!(l.intensity > 0.0f) || !(l.radius > 0.0f)) continue;
    d.lights[n].centreRadius = glm::vec4(glm::vec3(frame.view * glm::vec4(l.center, 1.0f)), l.radius);
    d.lights[n].colorIntensity = glm::vec4(l.color, l.intensity);
    d.lights[n].flags = glm::ivec4(l.modulate ? 1 : 0, l.fullAtBack ? 1 : 0, 0, 0);
    ++n;
  }
  // compose.frag's rules: 0 plain bilinear, 1 bilateral in depth, 2 all-or-nearest.
  const int rule = !settings.depthAware ? 0 : upsampling == Upsampling::kBilateral ? 1 : 2;
  d.counts = glm::ivec4(n, rule, 0, 0);
  glNamedBufferSubData(block.get(), 0, sizeof(d), &d);
}

void LayersBase::Impl::drawCompose(GLuint program) {
  glUseProgram(program);
  const GLuint b = block.get();
  glBindBuffersBase(GL_UNIFORM_BUFFER, bindings.composeBlock, 1, &b);  // multi-bind: the generic binding stays
  core::bindTextureAndNoSampler(bindings.opaqueDepth, depth.get());
  core::bindTextureAndNoSampler(bindings.mediaLayer, media.get());
  core::bindTextureAndNoSampler(bindings.mediaDepth, mediaDepth.get());
  core::bindTextureAndNoSampler(bindings.shimmer, shimmer.get());
  glBindVertexArray(vao.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
}

void LayersBase::Impl::composeWithin(GLuint program, const PixelBox& box, const core::Viewport& viewport) {
  if (!covered || wholeFrame(box)) {
    drawCompose(program);
    return;
  }
  copyAround(box, viewport);
  if (box.empty()) return;
  scissorTo(box, viewport.x, viewport.y);
  drawCompose(program);
  glDisable(GL_SCISSOR_TEST);
}

void LayersBase::Impl::copyAround(const PixelBox& box, const core::Viewport& viewport) {
  for (const PixelBox& strip : around(PixelBox{0, 0, width, height}, box)) {
    scissorTo(strip, viewport.x, viewport.y);
    drawCompose(copy.get());
  }
  glDisable(GL_SCISSOR_TEST);
}

void LayersBase::Impl::downsampleDepth() {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, depthFbo.get());
  glViewport(0, 0, mediaWidth, mediaHeight);
  glUseProgram(downsample.get());
  glUniform1i(shader::loc::kDownsampleFactor, factor);
  core::bindTextureAndNoSampler(bindings.resolveSource, depth.get());
  scissorTo(limit(boxes().layer));
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDisable(GL_SCISSOR_TEST);
}

LayersBase::LayersBase(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
LayersBase::~LayersBase() = default;
Layers::~Layers() = default;
HostLayers::~HostLayers() = default;
int LayersBase::width() const { return impl_->width; }
int LayersBase::height() const { return impl_->height; }
int LayersBase::mediaWidth() const { return impl_->mediaWidth; }
int LayersBase::mediaHeight() const { return impl_->mediaHeight; }
float LayersBase::scale() const { return impl_->scale; }
GLuint LayersBase::mediaDepth() const { return impl_->mediaDepth.get(); }
GLuint LayersBase::mediaColor() const { return impl_->media.get(); }
void LayersBase::setUpsampling(Upsampling rule) { impl_->upsampling = rule; }
LayersBase::Upsampling LayersBase::upsampling() const { return impl_->upsampling; }
GLuint Layers::opaqueFramebuffer() const { return impl_->opaqueFbo.get(); }
GLuint Layers::opaqueColor() const { return impl_->color.get(); }
GLuint LayersBase::opaqueDepth() const { return impl_->depth.get(); }
GLuint Layers::cartoonField() const { return impl_->field.get(); }
PixelBox Layers::cartoonFieldBox() const { return impl_->fieldBox; }

Result<std::unique_ptr<Layers>> Layers::create(int width, int height, int samples, float scale,
                                               const Bindings& bindings) {
  PUFF_TRY_ASSIGN(auto m, Impl::make(width, height, samples, scale, bindings));
  PUFF_TRY(m->makeOwn());
  PUFF_TRY(m->checkComplete());
  return std::unique_ptr<Layers>(new Layers(std::move(m)));
}

Result<std::unique_ptr<HostLayers>> HostLayers::create(int width, int height, float scale, const Bindings& bindings) {
  PUFF_TRY_ASSIGN(auto m, Impl::make(width, height, 1, scale, bindings));
  PUFF_TRY(m->makeHost());
  PUFF_TRY(m->checkComplete());
  return std::unique_ptr<HostLayers>(new HostLayers(std::move(m)));
}

void Layers::setHistorySlots(int slots) {
  Impl& m = *impl_;
  PUFF_CHECK(slots >= 1 && slots <= shader::kMaxBlurFrames);
  if (static_cast<int>(m.history.size()) == slots) return;
  m.history.clear();
  m.historyFbo.clear();
  for (int i = 0; i < slots; ++i) {
    m.history.push_back(makeTexture2D(GL_RGBA16F, m.width, m.height, GL_NEAREST));
    m.historyFbo.push_back(core::makeFramebuffer());
    glNamedFramebufferTexture(m.historyFbo.back().get(), GL_COLOR_ATTACHMENT0, m.history.back().get(), 0);
  }
}

GLuint Layers::historyFramebuffer(int slot) const {
  PUFF_CHECK(slot >= 0 && slot < static_cast<int>(impl_->historyFbo.size()));
  return impl_->historyFbo[static_cast<std::size_t>(slot)].get();
}

void Layers::blendHistory(GLuint target, const core::Viewport& viewport, std::span<const int> slots,
                          std::span<const float> weights) {
  Impl& m = *impl_;
  PUFF_CHECK(slots.size() == weights.size() && !slots.empty() &&
             slots.size() <= static_cast<std::size_t>(shader::kMaxBlurFrames));
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  fullscreenState();
  glUseProgram(m.blur.get());
  glUniform1i(shader::loc::kBlurCount, static_cast<GLint>(slots.size()));
  glUniform1fv(shader::loc::kBlurWeights, static_cast<GLsizei>(weights.size()), weights.data());
  glUniform4f(shader::loc::kBlurViewport, static_cast<float>(viewport.x), static_cast<float>(viewport.y), 0.0f, 0.0f);
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const int slot = slots[i];
    PUFF_CHECK(slot >= 0 && slot < static_cast<int>(m.history.size()));
    core::bindTextureAndNoSampler(m.bindings.historyFirst + static_cast<GLuint>(i),
                                  m.history[static_cast<std::size_t>(slot)].get());
  }
  glBindVertexArray(m.vao.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
}

Frame LayersBase::layerFrame(const Frame& full) const {
  const Impl& m = *impl_;
  // Clip x' = sx x + (sx - 1) w maps the full image's [-1, 1] onto the first width() of the layer's
  // mediaWidth * factor pixels.
  const float sx = static_cast<float>(m.width) / static_cast<float>(m.mediaWidth * m.factor);
  const float sy = static_cast<float>(m.height) / static_cast<float>(m.mediaHeight * m.factor);
  glm::mat4 s(1.0f);
  s[0][0] = sx, s[3][0] = sx - 1.0f;
  s[1][1] = sy, s[3][1] = sy - 1.0f;
  Frame f = full;
  f.projection = s * full.projection;
  f.x = f.y = 0;
  f.width = m.mediaWidth;
  f.height = m.mediaHeight;
  return f;
}

void Layers::resolveOpaque() {
  Impl& m = *impl_;
  // Its own framebuffers must not stay bound to catch the host's next draws: the draw framebuffer
  // and viewport it found are put back (two queries, answered client-side on desktop drivers).
  GLint hostDraw = 0, hostViewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &hostDraw);
  glGetIntegerv(GL_VIEWPORT, hostViewport);
  fullscreenState();  // (the blit honours the scissor test; both colour buffers are float: no sRGB conversion)
  glBlitNamedFramebuffer(m.opaqueFbo.get(), m.resolveFbo.get(), 0, 0, m.width, m.height, 0, 0, m.width, m.height,
                         GL_COLOR_BUFFER_BIT, GL_NEAREST);
  const Impl::Boxes boxes = m.boxes();
  if (!m.covered || !boxes.resolve.empty()) {  // no media: no depth read
    glBindVertexArray(m.vao.get());
    // Depth cannot be averaged: each pixel keeps the nearest of its samples.
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.linearFbo.get());
    glViewport(0, 0, m.width, m.height);
    glUseProgram(m.resolveDepth.get());
    glUniform1i(shader::loc::kResolveSamples, m.samples);
    core::bindTextureAndNoSampler(m.bindings.resolveSource, m.msDepth.get());
    scissorTo(m.limit(boxes.resolve));
    glDrawArrays(GL_TRIANGLES, 0, 3);
    m.downsampleDepth();
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(hostDraw));
  glViewport(hostViewport[0], hostViewport[1], hostViewport[2], hostViewport[3]);
}

namespace {

bool isDepthFormat(GLint format) {
  switch (format) {
    case GL_DEPTH_COMPONENT16:
    case GL_DEPTH_COMPONENT24:
    case GL_DEPTH_COMPONENT32:
    case GL_DEPTH_COMPONENT32F:
    case GL_DEPTH24_STENCIL8:
    case GL_DEPTH32F_STENCIL8:
      return true;
    default:
      return false;
  }
}

}  // namespace

Result<void> HostLayers::resolveHostDepth(const HostDepth& host) {
  Impl& m = *impl_;
  // Built only on an error: this runs every frame.
  const auto what = [&] { return "resolveHostDepth: HostDepth.texture " + std::to_string(host.texture); };
  if (host.texture == 0 || glIsTexture(host.texture) != GL_TRUE) return Error{what() + " is not a texture"};
  // The texture says what it is: target, format, size and samples (a few object queries, no sync).
  GLint target = 0, format = 0, w = 0, h = 0, samples = 0, mode = GL_DEPTH_COMPONENT, compare = GL_NONE;
  glGetTextureParameteriv(host.texture, GL_TEXTURE_TARGET, &target);
  if (target != GL_TEXTURE_2D && target != GL_TEXTURE_2D_MULTISAMPLE)
    return Error{what() + " is not a 2D or 2D multisample texture"};
  glGetTextureLevelParameteriv(host.texture, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
  glGetTextureLevelParameteriv(host.texture, 0, GL_TEXTURE_WIDTH, &w);
  glGetTextureLevelParameteriv(host.texture, 0, GL_TEXTURE_HEIGHT, &h);
  glGetTextureLevelParameteriv(host.texture, 0, GL_TEXTURE_SAMPLES, &samples);
  glGetTextureParameteriv(host.texture, GL_DEPTH_STENCIL_TEXTURE_MODE, &mode);
  glGetTextureParameteriv(host.texture, GL_TEXTURE_COMPARE_MODE, &compare);
  if (!isDepthFormat(format)) return Error{what() + " does not hold depth (not a depth or depth-stencil format)"};
  if (mode != GL_DEPTH_COMPONENT)
    return Error{what() + " reads its stencil (GL_DEPTH_STENCIL_TEXTURE_MODE); set it to GL_DEPTH_COMPONENT"};
  if (compare != GL_NONE) return Error{what() + " has GL_TEXTURE_COMPARE_MODE on; it must be GL_NONE"};
  if (host.x < 0 || host.y < 0 || host.x + m.width > w || host.y + m.height > h)
    return Error{what() + " is " + std::to_string(w) + "x" + std::to_string(h) + ": the layers' " +
                 std::to_string(m.width) + "x" + std::to_string(m.height) + " at (" + std::to_string(host.x) + ", " +
                 std::to_string(host.y) + ") does not fit in it"};
  const core::DepthSpace& space = host.space;
  if (!(space.nearPlane > 0.0f) || !(space.farPlane > space.nearPlane) || !std::isfinite(space.farPlane))
    return Error{"resolveHostDepth: HostDepth.space planes " + std::to_string(space.nearPlane) + ", " +
                 std::to_string(space.farPlane) + ": need 0 < near < far, far finite (linear depth's 1)"};
  GLint hostDraw = 0, hostViewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &hostDraw);
  glGetIntegerv(GL_VIEWPORT, hostViewport);
  fullscreenState();
  glBindVertexArray(m.vao.get());
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.linearFbo.get());
  glViewport(0, 0, m.width, m.height);
  const bool multi = target == GL_TEXTURE_2D_MULTISAMPLE;
  glUseProgram(multi ? m.resolveHostMs.get() : m.resolveHost.get());
  const core::DepthSpace& sp = host.space;
  const glm::mat4& p = sp.projection;
  if (multi) glUniform1i(shader::loc::kResolveSamples, samples);
  glUniform4f(shader::loc::kHostProjZW, p[2][2], p[3][2], p[2][3], p[3][3]);
  // host_depth.glsl's uPlanes.z: 0 linear, 1 standard, 2 reversed-z.
  const float convention = sp.convention == core::DepthConvention::kLinear     ? 0.0f
                           : sp.convention == core::DepthConvention::kStandard ? 1.0f
                                                                               : 2.0f;
  glUniform4f(shader::loc::kHostPlanes, sp.nearPlane, sp.farPlane - sp.nearPlane, convention,
              sp.clipDepth == core::ClipDepth::kZeroToOne ? 1.0f : 0.0f);
  glUniform2i(shader::loc::kHostOrigin, host.x, host.y);
  core::bindTextureAndNoSampler(m.bindings.resolveSource, host.texture);  // on its own target (2D or 2D MS)
  const Impl::Boxes boxes = m.boxes();
  if (!m.covered || !boxes.resolve.empty()) {  // no media: no depth read
    scissorTo(m.limit(boxes.resolve));
    glDrawArrays(GL_TRIANGLES, 0, 3);
    m.downsampleDepth();
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(hostDraw));
  glViewport(hostViewport[0], hostViewport[1], hostViewport[2], hostViewport[3]);
  return {};
}

Result<void> HostLayers::composeOver(GLuint target, const core::Viewport& viewport, const Frame& frame,
                                     std::span<const ExplosionLight> lights, const ComposeSettings& settings) {
  Impl& m = *impl_;
  if (m.cartoonBegun)
    return Error{
        "composeOver: the layer holds the cartoon style (beginMedia(Style::kCartoon)), which is not drawn over a "
        "host's frame yet; draw it with Style::kPhotoreal"};
  if (settings.shimmerPixels != 0.0f)
    return Error{"composeOver: heat shimmer (shimmerPixels " + std::to_string(settings.shimmerPixels) +
                 ") displaces the host's scene, which composeOver blends onto and cannot read; set it to 0"};
  if (const auto lit = std::count_if(lights.begin(), lights.end(),
                                     [](const ExplosionLight& l) { return l.intensity > 0.0f && l.radius > 0.0f; });
      lit > shader::kMaxLights)
    return Error{"composeOver: " + std::to_string(lit) + " explosion lights, at most " +
                 std::to_string(shader::kMaxLights)};
  if (viewport.width != m.width || viewport.height != m.height)
    return Error{"composeOver: viewport " + std::to_string(viewport.width) + "x" + std::to_string(viewport.height) +
                 " is not the layers' " + std::to_string(m.width) + "x" + std::to_string(m.height)};
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  // Dual-source blending writes GL_MAX_DUAL_SOURCE_DRAW_BUFFERS draw buffers at most (1 on
  // common GPUs): a target with more enabled would make the draw an error.
  GLint maxDual = 1, maxDraw = 1;
  glGetIntegerv(GL_MAX_DUAL_SOURCE_DRAW_BUFFERS, &maxDual);
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &maxDraw);
  for (GLint i = std::max(maxDual, 1); i < maxDraw; ++i) {
    GLint buffer = GL_NONE;
    glGetIntegerv(GL_DRAW_BUFFER0 + i, &buffer);
    if (buffer != GL_NONE)
      return Error{"composeOver: framebuffer " + std::to_string(target) + " draws to " + std::to_string(i + 1) +
                   " or more colour buffers, and dual-source blending allows " + std::to_string(maxDual) +
                   "; give it one draw buffer (glNamedFramebufferDrawBuffer) for this call"};
  }
  m.uploadComposeBlock(viewport, frame, lights, settings);
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  fullscreenState();  // GL_FRAMEBUFFER_SRGB the host's: on an sRGB target with it on, the blend is in linear
  // dst * src1 + src0 on RGB (compose_over.frag); the host's alpha kept.
  glEnablei(GL_BLEND, 0);
  glBlendEquationSeparatei(0, GL_FUNC_ADD, GL_FUNC_ADD);
  glBlendFuncSeparatei(0, GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
  // Outside the coverage the blend would leave the host's colour as it is: nothing is drawn there.
  const Impl::Boxes boxes = m.boxes();
  if (!m.covered || !boxes.compose.empty()) {
    scissorTo(m.limit(boxes.compose), viewport.x, viewport.y);
    m.drawCompose(m.composeOver.get());
    glDisable(GL_SCISSOR_TEST);
  }
  glDisablei(GL_BLEND, 0);
  return {};
}

void LayersBase::Impl::makeCartoon() {
  if (cartoonMade) return;
  cartoonFire = makeTexture2D(GL_RGBA32F, mediaWidth, mediaHeight, GL_NEAREST);
  cartoonDepth = makeTexture2D(GL_RGBA32F, mediaWidth, mediaHeight, GL_NEAREST);
  glNamedFramebufferTexture(mediaFbo.get(), GL_COLOR_ATTACHMENT2, cartoonFire.get(), 0);
  glNamedFramebufferTexture(mediaFbo.get(), GL_COLOR_ATTACHMENT3, cartoonDepth.get(), 0);
  fill = makeTexture2D(GL_RGBA16F, width, height, GL_NEAREST);
  field = makeTexture2D(GL_RGBA32F, width, height, GL_NEAREST);
  fieldFbo = core::makeFramebuffer();
  glNamedFramebufferTexture(fieldFbo.get(), GL_COLOR_ATTACHMENT0, fill.get(), 0);
  glNamedFramebufferTexture(fieldFbo.get(), GL_COLOR_ATTACHMENT1, field.get(), 0);
  const GLenum two[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(fieldFbo.get(), 2, two);
  for (int i = 0; i < 2; ++i) {
    seeds[i] = makeTexture2D(GL_RGBA32UI, width, height, GL_NEAREST);
    seedFbo[i] = core::makeFramebuffer();
    glNamedFramebufferTexture(seedFbo[i].get(), GL_COLOR_ATTACHMENT0, seeds[i].get(), 0);
  }
  cartoonBlock = core::makeBuffer();
  glNamedBufferStorage(cartoonBlock.get(), sizeof(CartoonBlockData), nullptr, GL_DYNAMIC_STORAGE_BIT);
  cartoonMade = true;
}

static std::vector<int> floodSteps(float inkWidth) {
  // A jump-flooding pass of step k carries a seed k pixels; steps 2^j .. 1 reach 2^(j+1) - 1. The
  // field must reach the ink's outer edge and the fill's antialiasing pixel: width + 2.
  int step = 1;
  while (2 * step - 1 < static_cast<int>(std::ceil(inkWidth)) + 2) step *= 2;
  std::vector<int> steps;
  for (; step >= 1; step /= 2) steps.push_back(step);
  steps.push_back(1);  // "JFA+1": one more step of 1 mends most of jump flooding's misses
  return steps;
}

LayersBase::Impl::Boxes LayersBase::Impl::boxes() const {
  Boxes b;
  if (!covered || covered->empty()) return b;  // no media: every box empty
  // A pixel's taps are the layer texels up to 2 away from the one holding it (compose.glsl,
  // mediaTaps); a texel holds media where a billboard covers its centre, inside `covered`.
  b.compose = grow(*covered, 4 * factor + 1, width, height);
  PixelBox reads = b.compose;
  if (coveredStyle == Style::kCartoon) {
    // Seeds lie within a pixel of where A can be above 0, and flooding carries them at most the
    // sum of its steps: past that no pixel holds a seed, and the whole frame's passes draw the
    // opaque colour there. The flooding is exact over `inked` when it runs that far beyond it.
    int reach = 1;
    for (int step : floodSteps(coveredInk)) reach += step;
    b.inked = grow(b.compose, reach + 1, width, height);
    b.flood = grow(b.inked, reach, width, height);
    b.field = grow(b.flood, 2, width, height);  // the seed pass reads the field's gradient
    b.cleared = grow(b.flood, floodSteps(coveredInk).front(), width, height);
    reads = b.field;
  }
  b.layer = grow(PixelBox{reads.x0 / factor, reads.y0 / factor, (reads.x1 + factor - 1) / factor,
                          (reads.y1 + factor - 1) / factor},
                 3, mediaWidth, mediaHeight);
  b.resolve = PixelBox{b.layer.x0 * factor, b.layer.y0 * factor, std::min(width, b.layer.x1 * factor),
                       std::min(height, b.layer.y1 * factor)};
  return b;
}

void LayersBase::Impl::composeCartoon(GLuint target, const core::Viewport& viewport, const CartoonCompose& cartoon) {
  const CartoonStyle& st = cartoon.style;
  CartoonBlockData d{};
  const float inkWidth = st.outlines ? st.outlineWidth : 0.0f;
  d.style = glm::vec4(st.threshold, static_cast<float>(st.opacityBands), static_cast<float>(st.fireBands), inkWidth);
  d.ink = glm::vec4(st.outlineColor, 1.0f);
  for (std::size_t k = 0; k < cartoon.fireColors.size() && k < shader::kMaxFireBands; ++k)
    d.fireColors[k] = glm::vec4(cartoon.fireColors[k], 1.0f);
  glNamedBufferSubData(cartoonBlock.get(), 0, sizeof(d), &d);
  const GLuint blocks[2] = {block.get(), cartoonBlock.get()};
  glBindBuffersBase(GL_UNIFORM_BUFFER, bindings.composeBlock, 1, &blocks[0]);  // multi-bind: the generic binding stays
  glBindBuffersBase(GL_UNIFORM_BUFFER, bindings.cartoonBlock, 1, &blocks[1]);
  fullscreenState();
  glBindVertexArray(vao.get());
  const unsigned c = bindings.cartoonFirst;
  core::bindTextureAndNoSampler(bindings.opaqueColor, color.get());
  core::bindTextureAndNoSampler(bindings.opaqueDepth, depth.get());
  core::bindTextureAndNoSampler(bindings.mediaLayer, media.get());
  core::bindTextureAndNoSampler(bindings.mediaDepth, mediaDepth.get());
  core::bindTextureAndNoSampler(bindings.shimmer, shimmer.get());

  const Boxes b = boxes();
  if (covered && b.inked.empty()) {  // no media: the opaque colour alone
    fieldBox = PixelBox{};
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
    glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
    copyAround(PixelBox{}, viewport);
    return;
  }
  // 1. The fill and the field at the output's size.
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fieldFbo.get());
  glViewport(0, 0, width, height);
  glUseProgram(cartoonField.get());
  core::bindTextureAndNoSampler(c, cartoonFire.get());
  core::bindTextureAndNoSampler(c + 1, cartoonDepth.get());
  scissorTo(limit(b.field));
  glDrawArrays(GL_TRIANGLES, 0, 3);
  fieldBox = covered ? b.field : PixelBox{0, 0, width, height};
  // 2. The seeds. With a coverage, the flooding reads up to a step around its box: no seed there.
  if (covered) {
    const GLuint none[4] = {0u, 0u, 0u, 0xffffffffu};  // cartoon.glsl's kNoSeed in w
    for (const PixelBox& r : around(b.cleared, b.flood))
      for (const core::Texture& t : seeds)
        glClearTexSubImage(t.get(), 0, r.x0, r.y0, 0, r.x1 - r.x0, r.y1 - r.y0, 1, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                           none);
  }
  core::bindTextureAndNoSampler(c + 1, field.get());
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, seedFbo[0].get());
  glUseProgram(cartoonSeed.get());
  scissorTo(limit(b.flood));
  glDrawArrays(GL_TRIANGLES, 0, 3);
  // 3. Jump flooding, ping-ponging the seeds.
  int from = 0;
  glUseProgram(cartoonFlood.get());
  for (int step : floodSteps(inkWidth)) {
    core::bindTextureAndNoSampler(c + 2, seeds[from].get());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, seedFbo[1 - from].get());
    glUniform1i(shader::loc::kFloodStep, step);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    from = 1 - from;
  }
  // 4. The fill and the ink over the opaque scene (copied around the ink's box).
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  glDisable(GL_SCISSOR_TEST);
  if (covered && !wholeFrame(b.inked)) {
    copyAround(b.inked, viewport);
    glBindVertexArray(vao.get());
  }
  scissorTo(limit(b.inked), viewport.x, viewport.y);
  glUseProgram(cartoonCompose.get());
  core::bindTextureAndNoSampler(c, fill.get());
  core::bindTextureAndNoSampler(c + 2, seeds[from].get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDisable(GL_SCISSOR_TEST);
  glBindVertexArray(0);
  glUseProgram(0);
}

void LayersBase::beginMedia(Style style) {
  Impl& m = *impl_;
  const bool cartoon = style == Style::kCartoon;
  if (cartoon) m.makeCartoon();
  m.cartoonBegun = cartoon;
  const GLenum buffers[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
  glNamedFramebufferDrawBuffers(m.mediaFbo.get(), cartoon ? 4 : 2, buffers);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.mediaFbo.get());
  glViewport(0, 0, m.mediaWidth, m.mediaHeight);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_RASTERIZER_DISCARD);  // it would discard the clears too
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  const float none[4] = {0.0f, 0.0f, 0.0f, 1.0f}, zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearNamedFramebufferfv(m.mediaFbo.get(), GL_COLOR, 0, none);
  glClearNamedFramebufferfv(m.mediaFbo.get(), GL_COLOR, 1, zero);
  if (cartoon) {
    glClearNamedFramebufferfv(m.mediaFbo.get(), GL_COLOR, 2, zero);
    glClearNamedFramebufferfv(m.mediaFbo.get(), GL_COLOR, 3, zero);
  }
}

void Layers::compose(GLuint target, const core::Viewport& viewport, const Frame& frame,
                     std::span<const ExplosionLight> lights, const ComposeSettings& settings,
                     const CartoonCompose* cartoon) {
  Impl& m = *impl_;
  if ((cartoon != nullptr) != m.cartoonBegun)
    misuse(cartoon ? "Layers::compose with a CartoonCompose on a layer not begun with beginMedia(Style::kCartoon)"
                   : "Layers::compose without a CartoonCompose on a layer begun with beginMedia(Style::kCartoon)");
  PUFF_CHECK(viewport.width == m.width && viewport.height == m.height);
  if (m.covered && (m.coveredStyle == Style::kCartoon) != (cartoon != nullptr))
    misuse("Layers::compose of another style than setCoverage was given");
  if (m.covered && cartoon && cartoon->style.outlines && cartoon->style.outlineWidth > m.coveredInk)
    misuse("Layers::compose with a wider ink than setCoverage was given");
  m.uploadComposeBlock(viewport, frame, lights, settings);
  if (cartoon) {
    m.composeCartoon(target, viewport, *cartoon);  // its own passes, the target's last
    return;
  }
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  fullscreenState();
  core::bindTextureAndNoSampler(m.bindings.opaqueColor, m.color.get());
  m.composeWithin(m.compose.get(), m.boxes().compose, viewport);
}

void LayersBase::setCoverage(std::optional<PixelBox> covered, Style style, float inkPixels) {
  impl_->covered = covered;
  impl_->coveredStyle = style;
  impl_->coveredInk = std::max(0.0f, inkPixels);
}

}  // namespace puff::media
