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

struct Layers::Impl {
  Bindings bindings;
  int width = 0, height = 0, samples = 1, factor = 1, mediaWidth = 0, mediaHeight = 0;
  float scale = 1.0f;
  Upsampling upsampling = Upsampling::kBilateral;
  core::Framebuffer opaqueFbo, resolveFbo, linearFbo, depthFbo, mediaFbo;
  core::Texture msColor, msDepth;                          // multisample textures (1 sample when MSAA is off)
  core::Texture color, depth, mediaDepth, media, shimmer;  // depth: R32F linear, the samples' nearest
  core::Program resolveDepth, downsample, compose, blur;
  bool host = false;                                      // createForHost: no opaque pass of its own
  core::Program resolveHost, resolveHostMs, composeOver;  // host programs (createForHost only)
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

  // Fills the compose passes' uniform block (compose.glsl's ComposeBlock).
  void uploadComposeBlock(const int viewport[4], const Frame& frame, std::span<const ExplosionLight> lights,
                          const ComposeSettings& settings);
  // Binds the compose passes' block and layer textures and draws `program` over the viewport
  // (compose binds the opaque colour too; composeOver has none).
  void drawCompose(GLuint program);
  // The full-size linear depth's layer-resolution nearest (downsample.frag), into depthFbo.
  void downsampleDepth();
  // Makes the cartoon style's textures and framebuffers (its programs are built with the layers).
  void makeCartoon();
  // compose()'s cartoon passes (layers.h, "Cartoon media"), the block already uploaded.
  void composeCartoon(GLuint target, const int viewport[4], const CartoonCompose& cartoon);
};

void Layers::Impl::uploadComposeBlock(const int viewport[4], const Frame& frame, std::span<const ExplosionLight> lights,
                                      const ComposeSettings& settings) {
  ComposeBlockData d{};
  d.invProj = glm::inverse(frame.projection);
  d.viewport = glm::vec4(viewport[0], viewport[1], viewport[2], viewport[3]);
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

void Layers::Impl::drawCompose(GLuint program) {
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

void Layers::Impl::downsampleDepth() {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, depthFbo.get());
  glViewport(0, 0, mediaWidth, mediaHeight);
  glUseProgram(downsample.get());
  glUniform1i(shader::loc::kDownsampleFactor, factor);
  core::bindTextureAndNoSampler(bindings.resolveSource, depth.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
}

Layers::Layers() : impl_(std::make_unique<Impl>()) {}
Layers::~Layers() = default;
int Layers::width() const { return impl_->width; }
int Layers::height() const { return impl_->height; }
int Layers::mediaWidth() const { return impl_->mediaWidth; }
int Layers::mediaHeight() const { return impl_->mediaHeight; }
float Layers::scale() const { return impl_->scale; }
GLuint Layers::opaqueFramebuffer() const { return impl_->opaqueFbo.get(); }
GLuint Layers::mediaDepth() const { return impl_->mediaDepth.get(); }
GLuint Layers::opaqueColor() const { return impl_->color.get(); }
GLuint Layers::opaqueDepth() const { return impl_->depth.get(); }
GLuint Layers::mediaColor() const { return impl_->media.get(); }
GLuint Layers::cartoonField() const { return impl_->field.get(); }
void Layers::setUpsampling(Upsampling rule) { impl_->upsampling = rule; }
Layers::Upsampling Layers::upsampling() const { return impl_->upsampling; }
bool Layers::forHost() const { return impl_->host; }

Result<std::unique_ptr<Layers>> Layers::create(int width, int height, int samples, float scale,
                                               const Bindings& bindings) {
  return make(width, height, samples, scale, bindings, false);
}

Result<std::unique_ptr<Layers>> Layers::createForHost(int width, int height, float scale, const Bindings& bindings) {
  return make(width, height, 1, scale, bindings, true);
}

Result<std::unique_ptr<Layers>> Layers::make(int width, int height, int samples, float scale, const Bindings& bindings,
                                             bool host) {
  if (auto ok = validate(bindings); !ok) return ok.error();
  if (width < 1 || height < 1 || width > core::kMaxImageSize || height > core::kMaxImageSize)
    return Error{"media layers: size " + std::to_string(width) + "x" + std::to_string(height) + " outside 1.." +
                 std::to_string(core::kMaxImageSize)};
  int factor = 0;
  for (int f : {1, 2, 4, 8})
    if (std::abs(scale - 1.0f / static_cast<float>(f)) < 1e-6f) factor = f;
  if (factor == 0) return Error{"media resolution: expected 1, 0.5, 0.25 or 0.125, got " + std::to_string(scale)};
  GLint maxSamples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  if (samples < 1 || samples > maxSamples)
    return Error{std::to_string(samples) + " samples per pixel asked, but this GL gives 1 to " +
                 std::to_string(maxSamples)};
  auto resolveDepth = core::buildProgram({"media/fullscreen.vert", "media/resolve_depth.frag"});
  if (!resolveDepth) return resolveDepth.error();
  auto downsample = core::buildProgram({"media/fullscreen.vert", "media/downsample.frag"});
  if (!downsample) return downsample.error();
  auto compose = core::buildProgram({"media/fullscreen.vert", "media/compose.frag"});
  if (!compose) return compose.error();
  auto blur = core::buildProgram({"media/fullscreen.vert", "media/blur.frag"});
  if (!blur) return blur.error();
  const char* cartoonStages[] = {"media/cartoon_field.frag", "media/cartoon_seed.frag", "media/cartoon_flood.frag",
                                 "media/cartoon_compose.frag"};
  core::Program cartoon[4];
  for (int i = 0; i < (host ? 0 : 4); ++i) {
    PUFF_TRY_ASSIGN(cartoon[i], core::buildProgram({"media/fullscreen.vert", cartoonStages[i]}));
  }
  core::Program resolveHost, resolveHostMs, composeOver;
  if (host) {
    auto single = core::buildProgram({"media/fullscreen.vert", "media/resolve_host_depth.frag"});
    if (!single) return single.error();
    auto multi = core::buildProgram({"media/fullscreen.vert", "media/resolve_host_depth_ms.frag"});
    if (!multi) return multi.error();
    auto over = core::buildProgram({"media/fullscreen.vert", "media/compose_over.frag"});
    if (!over) return over.error();
    resolveHost = std::move(*single), resolveHostMs = std::move(*multi), composeOver = std::move(*over);
  }

  std::unique_ptr<Layers> l(new Layers());
  Impl& m = *l->impl_;
  m.width = width, m.height = height, m.samples = samples, m.factor = factor, m.scale = scale;
  m.mediaWidth = std::max(1, (width + factor - 1) / factor);
  m.mediaHeight = std::max(1, (height + factor - 1) / factor);
  m.resolveDepth = std::move(*resolveDepth);
  m.downsample = std::move(*downsample);
  m.compose = std::move(*compose);
  m.blur = std::move(*blur);
  m.host = host;
  m.resolveHost = std::move(resolveHost), m.resolveHostMs = std::move(resolveHostMs);
  m.composeOver = std::move(composeOver);
  m.cartoonField = std::move(cartoon[0]), m.cartoonSeed = std::move(cartoon[1]);
  m.cartoonFlood = std::move(cartoon[2]), m.cartoonCompose = std::move(cartoon[3]);
  m.bindings = bindings;
  {
    using K = core::BindPoint::Kind;
    core::assignBindPoints(m.resolveDepth.get(), {{K::kSampler, "uDepthMS", bindings.resolveSource}});
    core::assignBindPoints(m.downsample.get(), {{K::kSampler, "uDepthFull", bindings.resolveSource}});
    core::assignBindPoints(m.blur.get(), {{K::kSampler, "uHistory[0]", bindings.historyFirst, shader::kMaxBlurFrames}});
    core::assignBindPoints(m.compose.get(), {{K::kUniformBlock, "ComposeBlock", bindings.composeBlock},
                                             {K::kSampler, "uOpaqueColor", bindings.opaqueColor},
                                             {K::kSampler, "uOpaqueDepth", bindings.opaqueDepth},
                                             {K::kSampler, "uMedia", bindings.mediaLayer},
                                             {K::kSampler, "uMediaDepth", bindings.mediaDepth},
                                             {K::kSampler, "uShimmerTex", bindings.shimmer}});
    if (!host) {
      const unsigned c = bindings.cartoonFirst;
      core::assignBindPoints(m.cartoonField.get(), {{K::kUniformBlock, "ComposeBlock", bindings.composeBlock},
                                                    {K::kUniformBlock, "CartoonBlock", bindings.cartoonBlock},
                                                    {K::kSampler, "uOpaqueDepth", bindings.opaqueDepth},
                                                    {K::kSampler, "uMedia", bindings.mediaLayer},
                                                    {K::kSampler, "uMediaDepth", bindings.mediaDepth},
                                                    {K::kSampler, "uShimmerTex", bindings.shimmer},
                                                    {K::kSampler, "uCartoonFire", c},
                                                    {K::kSampler, "uCartoonDepth", c + 1}});
      core::assignBindPoints(m.cartoonSeed.get(), {{K::kUniformBlock, "CartoonBlock", bindings.cartoonBlock},
                                                   {K::kSampler, "uField", c + 1}});
      core::assignBindPoints(m.cartoonFlood.get(), {{K::kUniformBlock, "CartoonBlock", bindings.cartoonBlock},
                                                    {K::kSampler, "uSeeds", c + 2}});
      core::assignBindPoints(m.cartoonCompose.get(), {{K::kUniformBlock, "ComposeBlock", bindings.composeBlock},
                                                      {K::kUniformBlock, "CartoonBlock", bindings.cartoonBlock},
                                                      {K::kSampler, "uOpaqueColor", bindings.opaqueColor},
                                                      {K::kSampler, "uOpaqueDepth", bindings.opaqueDepth},
                                                      {K::kSampler, "uMedia", bindings.mediaLayer},
                                                      {K::kSampler, "uMediaDepth", bindings.mediaDepth},
                                                      {K::kSampler, "uShimmerTex", bindings.shimmer},
                                                      {K::kSampler, "uFill", c},
                                                      {K::kSampler, "uField", c + 1},
                                                      {K::kSampler, "uSeeds", c + 2}});
    }
    if (host) {
      core::assignBindPoints(m.resolveHost.get(), {{K::kSampler, "uHostDepth", bindings.resolveSource}});
      core::assignBindPoints(m.resolveHostMs.get(), {{K::kSampler, "uHostDepth", bindings.resolveSource}});
      core::assignBindPoints(m.composeOver.get(), {{K::kUniformBlock, "ComposeBlock", bindings.composeBlock},
                                                   {K::kSampler, "uOpaqueDepth", bindings.opaqueDepth},
                                                   {K::kSampler, "uMedia", bindings.mediaLayer},
                                                   {K::kSampler, "uMediaDepth", bindings.mediaDepth},
                                                   {K::kSampler, "uShimmerTex", bindings.shimmer}});
    }
  }
  m.vao = core::makeVertexArray();
  m.block = core::makeBuffer();
  glNamedBufferStorage(m.block.get(), sizeof(ComposeBlockData), nullptr, GL_DYNAMIC_STORAGE_BIT);

  // Opaque pass: multisample textures (the depth is read per sample), resolved into textures. A
  // host's Layers keep only the linear depth (below): the host owns its scene's colour and depth.
  if (!host) {
    m.opaqueFbo = core::makeFramebuffer();
    m.msColor = core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE);
    m.msDepth = core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE);
    // Scene-linear colour (docs/colour.md): half floats, as the output target.
    glTextureStorage2DMultisample(m.msColor.get(), samples, GL_RGBA16F, width, height, GL_TRUE);
    glTextureStorage2DMultisample(m.msDepth.get(), samples, GL_DEPTH24_STENCIL8, width, height, GL_TRUE);
    glTextureParameteri(m.msDepth.get(), GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
    glNamedFramebufferTexture(m.opaqueFbo.get(), GL_COLOR_ATTACHMENT0, m.msColor.get(), 0);
    glNamedFramebufferTexture(m.opaqueFbo.get(), GL_DEPTH_STENCIL_ATTACHMENT, m.msDepth.get(), 0);

    m.color = makeTexture2D(GL_RGBA16F, width, height, GL_NEAREST);
    m.resolveFbo = core::makeFramebuffer();
    glNamedFramebufferTexture(m.resolveFbo.get(), GL_COLOR_ATTACHMENT0, m.color.get(), 0);
  }
  m.depth = makeTexture2D(GL_R32F, width, height, GL_NEAREST);
  m.linearFbo = core::makeFramebuffer();
  glNamedFramebufferTexture(m.linearFbo.get(), GL_COLOR_ATTACHMENT0, m.depth.get(), 0);

  m.mediaDepth = makeTexture2D(GL_R32F, m.mediaWidth, m.mediaHeight, GL_NEAREST);
  m.depthFbo = core::makeFramebuffer();
  glNamedFramebufferTexture(m.depthFbo.get(), GL_COLOR_ATTACHMENT0, m.mediaDepth.get(), 0);

  // 32-bit floats: Mesa llvmpipe blends half floats rounding toward zero, which over the ~100 layers of
  // a camera inside smoke darkened the image by 0.004 (4x the 8-bit rounding; puffbench measures it).
  m.media = makeTexture2D(GL_RGBA32F, m.mediaWidth, m.mediaHeight, GL_NEAREST);
  m.shimmer = makeTexture2D(GL_RG16F, m.mediaWidth, m.mediaHeight, GL_NEAREST);
  m.mediaFbo = core::makeFramebuffer();
  glNamedFramebufferTexture(m.mediaFbo.get(), GL_COLOR_ATTACHMENT0, m.media.get(), 0);
  glNamedFramebufferTexture(m.mediaFbo.get(), GL_COLOR_ATTACHMENT1, m.shimmer.get(), 0);
  const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(m.mediaFbo.get(), 2, both);

  for (GLuint fbo : {m.opaqueFbo.get(), m.resolveFbo.get(), m.linearFbo.get(), m.depthFbo.get(), m.mediaFbo.get()}) {
    if (fbo != 0 && glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      return Error{"media layers of " + std::to_string(width) + "x" + std::to_string(height) + " with " +
                   std::to_string(samples) + " samples are not supported by this GL"};
  }
  return l;
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

void Layers::blendHistory(GLuint target, const int viewport[4], std::span<const int> slots,
                          std::span<const float> weights) {
  Impl& m = *impl_;
  PUFF_CHECK(slots.size() == weights.size() && !slots.empty() &&
             slots.size() <= static_cast<std::size_t>(shader::kMaxBlurFrames));
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  fullscreenState();
  glUseProgram(m.blur.get());
  glUniform1i(shader::loc::kBlurCount, static_cast<GLint>(slots.size()));
  glUniform1fv(shader::loc::kBlurWeights, static_cast<GLsizei>(weights.size()), weights.data());
  glUniform4f(shader::loc::kBlurViewport, static_cast<float>(viewport[0]), static_cast<float>(viewport[1]), 0.0f, 0.0f);
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

Frame Layers::layerFrame(const Frame& full) const {
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
  if (m.host)
    misuse("Layers::resolveOpaque on layers made by createForHost, which have no opaque pass: call resolveHostDepth");
  // Its own framebuffers must not stay bound to catch the host's next draws: the draw framebuffer
  // and viewport it found are put back (two queries, answered client-side on desktop drivers).
  GLint hostDraw = 0, hostViewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &hostDraw);
  glGetIntegerv(GL_VIEWPORT, hostViewport);
  fullscreenState();  // (the blit honours the scissor test; both colour buffers are float: no sRGB conversion)
  glBlitNamedFramebuffer(m.opaqueFbo.get(), m.resolveFbo.get(), 0, 0, m.width, m.height, 0, 0, m.width, m.height,
                         GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindVertexArray(m.vao.get());
  // Depth cannot be averaged: each pixel keeps the nearest of its samples.
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.linearFbo.get());
  glViewport(0, 0, m.width, m.height);
  glUseProgram(m.resolveDepth.get());
  glUniform1i(shader::loc::kResolveSamples, m.samples);
  core::bindTextureAndNoSampler(m.bindings.resolveSource, m.msDepth.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);

  m.downsampleDepth();
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

Result<void> Layers::resolveHostDepth(const HostDepth& host) {
  Impl& m = *impl_;
  // Built only on an error: this runs every frame.
  const auto what = [&] { return "resolveHostDepth: HostDepth.texture " + std::to_string(host.texture); };
  if (!m.host)
    return Error{
        "resolveHostDepth: these media layers have their own opaque pass (Layers::create): use "
        "resolveOpaque"};
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
  glDrawArrays(GL_TRIANGLES, 0, 3);
  m.downsampleDepth();
  glBindVertexArray(0);
  glUseProgram(0);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(hostDraw));
  glViewport(hostViewport[0], hostViewport[1], hostViewport[2], hostViewport[3]);
  return {};
}

Result<void> Layers::composeOver(GLuint target, const int viewport[4], const Frame& frame,
                                 std::span<const ExplosionLight> lights, const ComposeSettings& settings) {
  Impl& m = *impl_;
  if (!m.host) return Error{"composeOver: these media layers have their own opaque pass (Layers::create): use compose"};
  if (m.cartoonBegun)
    return Error{
        "composeOver: the layer holds the cartoon style (beginMedia(true)), which is not drawn over a "
        "host's frame yet; draw it with Style::kPhotoreal"};
  if (settings.shimmerPixels != 0.0f)
    return Error{"composeOver: heat shimmer (shimmerPixels " + std::to_string(settings.shimmerPixels) +
                 ") displaces the host's scene, which composeOver blends onto and cannot read; set it to 0"};
  if (const auto lit = std::count_if(lights.begin(), lights.end(),
                                     [](const ExplosionLight& l) { return l.intensity > 0.0f && l.radius > 0.0f; });
      lit > shader::kMaxLights)
    return Error{"composeOver: " + std::to_string(lit) + " explosion lights, at most " +
                 std::to_string(shader::kMaxLights)};
  if (viewport[2] != m.width || viewport[3] != m.height)
    return Error{"composeOver: viewport " + std::to_string(viewport[2]) + "x" + std::to_string(viewport[3]) +
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
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  fullscreenState();  // GL_FRAMEBUFFER_SRGB the host's: on an sRGB target with it on, the blend is in linear
  // dst * src1 + src0 on RGB (compose_over.frag); the host's alpha kept.
  glEnablei(GL_BLEND, 0);
  glBlendEquationSeparatei(0, GL_FUNC_ADD, GL_FUNC_ADD);
  glBlendFuncSeparatei(0, GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
  m.drawCompose(m.composeOver.get());
  glDisablei(GL_BLEND, 0);
  return {};
}

void Layers::Impl::makeCartoon() {
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

void Layers::Impl::composeCartoon(GLuint target, const int viewport[4], const CartoonCompose& cartoon) {
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

  // 1. The fill and the field at the output's size.
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fieldFbo.get());
  glViewport(0, 0, width, height);
  glUseProgram(cartoonField.get());
  core::bindTextureAndNoSampler(c, cartoonFire.get());
  core::bindTextureAndNoSampler(c + 1, cartoonDepth.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  // 2. The seeds.
  core::bindTextureAndNoSampler(c + 1, field.get());
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, seedFbo[0].get());
  glUseProgram(cartoonSeed.get());
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
  // 4. The fill and the ink over the opaque scene.
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  glUseProgram(cartoonCompose.get());
  core::bindTextureAndNoSampler(c, fill.get());
  core::bindTextureAndNoSampler(c + 2, seeds[from].get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
}

void Layers::beginMedia(bool cartoon) {
  Impl& m = *impl_;
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

void Layers::compose(GLuint target, const int viewport[4], const Frame& frame, std::span<const ExplosionLight> lights,
                     const ComposeSettings& settings, const CartoonCompose* cartoon) {
  Impl& m = *impl_;
  if (m.host) misuse("Layers::compose on layers made by createForHost, which have no opaque colour: call composeOver");
  if ((cartoon != nullptr) != m.cartoonBegun)
    misuse(cartoon ? "Layers::compose with a CartoonCompose on a layer not begun with beginMedia(true)"
                   : "Layers::compose without a CartoonCompose on a layer begun with beginMedia(true)");
  PUFF_CHECK(viewport[2] == m.width && viewport[3] == m.height);
  m.uploadComposeBlock(viewport, frame, lights, settings);
  if (cartoon) {
    m.composeCartoon(target, viewport, *cartoon);  // its own passes, the target's last
    return;
  }
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  fullscreenState();
  core::bindTextureAndNoSampler(m.bindings.opaqueColor, m.color.get());
  m.drawCompose(m.compose.get());
}

}  // namespace puff::media
