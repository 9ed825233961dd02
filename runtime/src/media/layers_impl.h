// What layers.cpp and layers_coverage.cpp share: the layers' state (LayersBase::Impl) and the
// full-screen passes' helpers.
#pragma once

#include <optional>
#include <vector>

#include <puff/core/gl.h>
#include <puff/gl_api.h>
#include <puff/media/layers.h>
#include <puff/shader_blocks.h>

namespace puff::media {

using shader::CartoonBlockData;
using shader::ComposeBlockData;
using shader::LightGpu;

// The state Layers' full-screen passes rely on (and leave): no depth or stencil test, blending,
// culling, scissor, rasterizer discard, alpha to coverage or sample mask; filled polygons; colour
// writes on. GL_FRAMEBUFFER_SRGB
// stays the host's: Puff's own targets are float, and a host's sRGB target with the flag on
// encodes the scene-linear colour compose writes (docs/colour.md).
// `drawBuffers`: how many draw buffers the pass's framebuffer draws to (1 but for the cartoon
// field's 2): blending and the colour write masks are set for those alone, so a host's masks and
// blending of its other draw buffers stay as it set them.
inline void fullscreenState(int drawBuffers) {
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_STENCIL_TEST);
  for (int i = 0; i < drawBuffers; ++i) glDisablei(GL_BLEND, static_cast<GLuint>(i));
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_RASTERIZER_DISCARD);
  // A multisampled target: every sample written (composeOver's colour output has alpha 0, which
  // alpha to coverage would turn into no sample at all).
  glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
  glDisable(GL_SAMPLE_MASK);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  for (int i = 0; i < drawBuffers; ++i) glColorMaski(static_cast<GLuint>(i), GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

// A call the caller may not make (the header says so): one line naming it, then abort, as a
// broken promise of the caller's, not Puff's ("internal check failed" would blame Puff).
// The pixels of `outer` outside `inner` (which lies inside it), as at most four boxes.
inline std::vector<PixelBox> around(const PixelBox& outer, const PixelBox& inner) {
  if (inner.empty()) return {outer};
  std::vector<PixelBox> strips;
  for (const PixelBox& b :
       {PixelBox{outer.x0, outer.y0, outer.x1, inner.y0}, PixelBox{outer.x0, inner.y1, outer.x1, outer.y1},
        PixelBox{outer.x0, inner.y0, inner.x0, inner.y1}, PixelBox{inner.x1, inner.y0, outer.x1, inner.y1}})
    if (!b.empty()) strips.push_back(b);
  return strips;
}

// Scissors the passes that follow to `box`, offset by the target viewport's origin; nullopt: off.
inline void scissorTo(const std::optional<PixelBox>& box, int x = 0, int y = 0) {
  if (!box) {
    glDisable(GL_SCISSOR_TEST);
    return;
  }
  glEnable(GL_SCISSOR_TEST);
  glScissor(x + box->x0, y + box->y0, box->x1 - box->x0, box->y1 - box->y0);
}

[[noreturn]] inline void misuse(const char* message) {
  std::fprintf(stderr, "puff: %s\n", message);
  std::abort();
}

inline core::Texture makeTexture2D(GLenum format, int w, int h, GLenum filter, std::string_view what) {
  core::Texture t = core::makeTexture(GL_TEXTURE_2D, what);
  glTextureStorage2D(t.get(), 1, format, w, h);
  glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, static_cast<GLint>(filter));
  glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, static_cast<GLint>(filter));
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

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
  core::Program cartoonComposeOver;  // HostLayers': the fill and ink blended over a host's colour
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
  // The cartoon passes, the last into `target`: over Puff's own opaque colour (a whole frame), or
  // with `overHost` blended over what the host's target holds (nothing drawn where the media are not).
  void composeCartoon(GLuint target, const core::Viewport& viewport, const CartoonCompose& cartoon,
                      bool overHost = false);
  // The cartoon passes' programs, pointed at the bindings (both kinds of layers).
  Result<void> makeCartoonPrograms();
};

}  // namespace puff::media
