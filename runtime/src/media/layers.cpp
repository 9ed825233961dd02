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

#include "layers_impl.h"

namespace puff::media {

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
  m->vao = core::makeVertexArray("media layers: vertex array");
  m->block = core::makeBuffer("media layers: compose block");
  glNamedBufferStorage(m->block.get(), sizeof(ComposeBlockData), nullptr, GL_DYNAMIC_STORAGE_BIT);

  m->depth = makeTexture2D(GL_R32F, width, height, GL_NEAREST, "media layers: linear depth");
  m->linearFbo = core::makeFramebuffer("media layers: linear depth");
  glNamedFramebufferTexture(m->linearFbo.get(), GL_COLOR_ATTACHMENT0, m->depth.get(), 0);
  m->mediaDepth = makeTexture2D(GL_R32F, m->mediaWidth, m->mediaHeight, GL_NEAREST, "media layers: layer depth");
  m->depthFbo = core::makeFramebuffer("media layers: layer depth");
  glNamedFramebufferTexture(m->depthFbo.get(), GL_COLOR_ATTACHMENT0, m->mediaDepth.get(), 0);
  // 32-bit floats: Mesa llvmpipe blends half floats rounding toward zero, which over the ~100 layers of
  // a camera inside smoke darkened the image by 0.004 (4x the 8-bit rounding; puffbench measures it).
  m->media = makeTexture2D(GL_RGBA32F, m->mediaWidth, m->mediaHeight, GL_NEAREST, "media layers: media");
  m->shimmer = makeTexture2D(GL_RG16F, m->mediaWidth, m->mediaHeight, GL_NEAREST, "media layers: shimmer");
  m->mediaFbo = core::makeFramebuffer("media layers: media");
  glNamedFramebufferTexture(m->mediaFbo.get(), GL_COLOR_ATTACHMENT0, m->media.get(), 0);
  glNamedFramebufferTexture(m->mediaFbo.get(), GL_COLOR_ATTACHMENT1, m->shimmer.get(), 0);
  const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(m->mediaFbo.get(), 2, both);
  return m;
}

Result<void> LayersBase::Impl::makeCartoonPrograms() {
  PUFF_TRY_ASSIGN(cartoonField, fullscreenProgram("media/cartoon_field.frag"));
  PUFF_TRY_ASSIGN(cartoonSeed, fullscreenProgram("media/cartoon_seed.frag"));
  PUFF_TRY_ASSIGN(cartoonFlood, fullscreenProgram("media/cartoon_flood.frag"));
  using K = core::BindPoint::Kind;
  const Bindings& b = bindings;
  const unsigned c = b.cartoonFirst;
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
  return {};
}

Result<void> LayersBase::Impl::makeOwn() {
  PUFF_TRY_ASSIGN(resolveDepth, fullscreenProgram("media/resolve_depth.frag"));
  PUFF_TRY_ASSIGN(compose, fullscreenProgram("media/compose.frag"));
  PUFF_TRY_ASSIGN(blur, fullscreenProgram("media/blur.frag"));
  PUFF_TRY_ASSIGN(cartoonCompose, fullscreenProgram("media/cartoon_compose.frag"));
  PUFF_TRY_ASSIGN(copy, fullscreenProgram("media/copy.frag"));
  PUFF_TRY(makeCartoonPrograms());
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
  opaqueFbo = core::makeFramebuffer("media layers: opaque");
  msColor = core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE, "media layers: opaque colour");
  msDepth = core::makeTexture(GL_TEXTURE_2D_MULTISAMPLE, "media layers: opaque depth");
  // Scene-linear colour (docs/colour.md): half floats, as the output target.
  glTextureStorage2DMultisample(msColor.get(), samples, GL_RGBA16F, width, height, GL_TRUE);
  glTextureStorage2DMultisample(msDepth.get(), samples, GL_DEPTH24_STENCIL8, width, height, GL_TRUE);
  glTextureParameteri(msDepth.get(), GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
  glNamedFramebufferTexture(opaqueFbo.get(), GL_COLOR_ATTACHMENT0, msColor.get(), 0);
  glNamedFramebufferTexture(opaqueFbo.get(), GL_DEPTH_STENCIL_ATTACHMENT, msDepth.get(), 0);
  color = makeTexture2D(GL_RGBA16F, width, height, GL_NEAREST, "media layers: resolved opaque colour");
  resolveFbo = core::makeFramebuffer("media layers: resolved opaque colour");
  glNamedFramebufferTexture(resolveFbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  return {};
}

Result<void> LayersBase::Impl::makeHost() {
  PUFF_TRY_ASSIGN(resolveHost, fullscreenProgram("media/resolve_host_depth.frag"));
  PUFF_TRY_ASSIGN(resolveHostMs, fullscreenProgram("media/resolve_host_depth_ms.frag"));
  PUFF_TRY_ASSIGN(composeOver, fullscreenProgram("media/compose_over.frag"));
  PUFF_TRY_ASSIGN(cartoonComposeOver, fullscreenProgram("media/cartoon_compose_over.frag"));
  PUFF_TRY(makeCartoonPrograms());
  using K = core::BindPoint::Kind;
  const Bindings& b = bindings;
  core::assignBindPoints(resolveHost.get(), {{K::kSampler, "uHostDepth", b.resolveSource}});
  core::assignBindPoints(resolveHostMs.get(), {{K::kSampler, "uHostDepth", b.resolveSource}});
  core::assignBindPoints(composeOver.get(), {{K::kUniformBlock, "ComposeBlock", b.composeBlock},
                                             {K::kSampler, "uOpaqueDepth", b.opaqueDepth},
                                             {K::kSampler, "uMedia", b.mediaLayer},
                                             {K::kSampler, "uMediaDepth", b.mediaDepth},
                                             {K::kSampler, "uShimmerTex", b.shimmer}});
  core::assignBindPoints(cartoonComposeOver.get(), {{K::kUniformBlock, "ComposeBlock", b.composeBlock},
                                                    {K::kUniformBlock, "CartoonBlock", b.cartoonBlock},
                                                    {K::kSampler, "uOpaqueDepth", b.opaqueDepth},
                                                    {K::kSampler, "uMedia", b.mediaLayer},
                                                    {K::kSampler, "uMediaDepth", b.mediaDepth},
                                                    {K::kSampler, "uShimmerTex", b.shimmer},
                                                    {K::kSampler, "uFill", b.cartoonFirst},
                                                    {K::kSampler, "uField", b.cartoonFirst + 1},
                                                    {K::kSampler, "uSeeds", b.cartoonFirst + 2}});
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
  d.depth = glm::vec4(frame.nearPlane, frame.farPlane, frame.farPlane - frame.nearPlane, frame.orthographic() ? 1 : 0);
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
    m.history.push_back(makeTexture2D(GL_RGBA16F, m.width, m.height, GL_NEAREST, "media layers: motion blur history"));
    m.historyFbo.push_back(core::makeFramebuffer("media layers: motion blur history"));
    glNamedFramebufferTexture(m.historyFbo.back().get(), GL_COLOR_ATTACHMENT0, m.history.back().get(), 0);
  }
}

GLuint Layers::historyFramebuffer(int slot) const {
  PUFF_CHECK(slot >= 0 && slot < static_cast<int>(impl_->historyFbo.size()));
  return impl_->historyFbo[static_cast<std::size_t>(slot)].get();
}

void Layers::blendHistory(GLuint target, const core::Viewport& viewport, std::span<const int> slots,
                          std::span<const float> weights) {
  const core::DebugGroup group("media motion blur");
  Impl& m = *impl_;
  PUFF_CHECK(slots.size() == weights.size() && !slots.empty() &&
             slots.size() <= static_cast<std::size_t>(shader::kMaxBlurFrames));
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  const core::DrawBufferZero drawBuffers;  // the target's other attachments stay as they are
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  fullscreenState(1);
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
  f.viewport.x = f.viewport.y = 0;
  f.viewport.width = m.mediaWidth;
  f.viewport.height = m.mediaHeight;
  return f;
}

void Layers::resolveOpaque() {
  const core::DebugGroup group("media: resolve the opaque frame");
  Impl& m = *impl_;
  // Its own framebuffers must not stay bound to catch the host's next draws: the draw framebuffer
  // and viewport it found are put back (two queries, answered client-side on desktop drivers).
  GLint hostDraw = 0, hostViewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &hostDraw);
  glGetIntegerv(GL_VIEWPORT, hostViewport);
  fullscreenState(1);  // (the blit honours the scissor test; both colour buffers are float: no sRGB conversion)
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

Result<void> HostLayers::resolveHostDepth(const HostDepth& host, const core::SharedFrame& frame) {
  const core::DebugGroup group("media: resolve the host's depth");
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
  const core::DepthSpace space = frame.depthSpace();
  if (!(space.nearPlane > 0.0f) || !(space.farPlane > space.nearPlane) || !std::isfinite(space.farPlane))
    return Error{"resolveHostDepth: the frame's planes " + std::to_string(space.nearPlane) + ", " +
                 std::to_string(space.farPlane) + ": need 0 < near < far, far finite (linear depth's 1)"};
  GLint hostDraw = 0, hostViewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &hostDraw);
  glGetIntegerv(GL_VIEWPORT, hostViewport);
  fullscreenState(1);
  glBindVertexArray(m.vao.get());
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.linearFbo.get());
  glViewport(0, 0, m.width, m.height);
  const bool multi = target == GL_TEXTURE_2D_MULTISAMPLE;
  glUseProgram(multi ? m.resolveHostMs.get() : m.resolveHost.get());
  const core::DepthSpace& sp = space;
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
                                     std::span<const ExplosionLight> lights, const ComposeSettings& settings,
                                     const CartoonCompose* cartoon) {
  const core::DebugGroup group("media compose over the host's frame");
  Impl& m = *impl_;
  if (m.cartoonBegun && cartoon == nullptr)
    return Error{
        "composeOver: the layer holds the cartoon style (beginMedia(Style::kCartoon)); pass its CartoonCompose "
        "(media::cartoonCompose(settings))"};
  if (!m.cartoonBegun && cartoon != nullptr)
    return Error{"composeOver: a CartoonCompose for a layer not begun with beginMedia(Style::kCartoon)"};
  if (m.covered && (m.coveredStyle == Style::kCartoon) != (cartoon != nullptr))
    return Error{"composeOver: the layer's coverage was set for the other style (setCoverage)"};
  if (m.covered && cartoon && cartoon->style.outlines && cartoon->style.outlineWidth > m.coveredInk)
    return Error{"composeOver: the ink is wider than the coverage was set for (setCoverage's inkPixels)"};
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
  // Draw buffer 0 alone: the host's other attachments stay as they are, and dual-source blending
  // (at most GL_MAX_DUAL_SOURCE_DRAW_BUFFERS draw buffers, 1 on common GPUs) is allowed.
  m.uploadComposeBlock(viewport, frame, lights, settings);
  if (cartoon) {
    // The blend of the last pass, set first: what the header says composeOver leaves, drawn or not.
    glBlendEquationSeparatei(0, GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparatei(0, GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
    m.composeCartoon(target, viewport, *cartoon, true);  // its own passes, the target's last
    return {};
  }
  const core::DrawBufferZero drawBuffers;
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  fullscreenState(1);  // GL_FRAMEBUFFER_SRGB the host's: on an sRGB target with it on, the blend is in linear
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
  for (GLuint i = 0; i < (cartoon ? 4u : 2u); ++i) glColorMaski(i, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
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
  const core::DebugGroup group("media compose");
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
  const core::DrawBufferZero drawBuffers;  // the target's other attachments stay as they are
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
  fullscreenState(1);
  core::bindTextureAndNoSampler(m.bindings.opaqueColor, m.color.get());
  m.composeWithin(m.compose.get(), m.boxes().compose, viewport);
}

}  // namespace puff::media
