// Layer composition (Umenhoffer §4): the opaque scene is drawn into colour + linear depth, the
// media into a float layer at 1, 1/2, 1/4 or 1/8 of the screen, and a last pass composes them:
//     out = opaque(x + shimmer offset) * T + M
// where M (premultiplied radiance) and T (transmittance) come from the media layer, upsampled
// depth-aware so a low-resolution layer does not halo around opaque edges: each of the four layer
// texels around a pixel gets its bilinear weight times a depth weight, 1 when the depth it was
// drawn against is within depthTolerance * z of the pixel's view distance z, falling linearly to 0
// at 5 * depthTolerance * z (a joint bilateral upsampling in depth); the weights are normalized.
// When all four vanish (a surface no texel around the pixel was drawn against) the pixel takes the
// texel of the 4 x 4 around it whose depth is nearest its own. The layer's depth is the NEAREST
// opaque depth in its footprint, so thin near objects keep their own texels. On a slanted surface
// the texels' depths drift from the pixel's gradually, so their weights do too (the other rule,
// Upsampling::kAllOrNearest, kept for comparison: bilinear only when all four are within the
// tolerance and otherwise the nearest texel, switches there in blocks).
//
// Heat shimmer moves the opaque scene by the layer's offset times ComposeSettings::shimmerPixels,
// in fractions of a pixel: the opaque colour (lit) is fetched bilinearly at the displaced position.
//
// The explosion's light on the scene (*Volumetric Explosion Effects*, docs/media.md) is applied in
// the same pass from the depth texture, per pixel: surfaces seen through the explosion's projected circle
// get its projected texture, 0 in front of the explosion sphere, rising linearly to full at its
// centre (or its back), full behind; added (additive) or multiplied in (modulating). No z-bias,
// no polygon clipping. Background pixels (no surface) are left alone, as in the paper.
//
// In a host's frame (HostLayers; docs/embedding.md, "Media in the game's frame") there is no
// opaque pass of Puff's: the host draws its scene into its own framebuffer with its own depth
// convention. resolveHostDepth turns the host's depth texture into the linear depth above (full
// size and the layer's), and composeOver blends the layer onto the host's colour target:
//     out = dst * (mul * T) + (add * T + M)
// with dual-source blending, where dst * mul + add is the surface with the explosions' light
// (mul = the modulating lights' product, add = the additive lights' sum). The same image as
// compose() gives over the same opaque colour, without reading or copying the host's colour;
// heat shimmer, which must read the scene displaced, is the one thing it cannot do.
//
// CARTOON MEDIA (media::Style::kCartoon, beyond the papers; docs/media.md, "Cartoon media"). The
// renderer then writes, besides the scattered light, each particle's emissive weight, temperature,
// emission and depth into two more layer attachments, all over-composited (beginMedia(Style::kCartoon)).
// compose() with a CartoonCompose draws, instead of out = opaque T + M, in four passes at the
// output's size:
//   1. the layer and its attributes upsampled as above; per pixel the accumulated opacity A, the
//      medium's depth and the flat fill (types.h, CartoonStyle: an opacity tier, and the fire band's
//      black-body colour where emitting medium is most of what is seen, else the scattered light);
//   2. the seeds of a distance field: where the iso-line A = threshold crosses the segments between
//      neighbouring pixel centres, A linear along them (sub-pixel, so the ink moves smoothly);
//   3. jump flooding (Rong & Tan 2006): every pixel finds its nearest seed, up to the ink's width
//      away (steps 2^k .. 1, then 1 again);
//   4. out = opaque (1 - a - ink) + fill a + inkColour ink, with s the signed distance to the
//      iso-line (negative inside), a = clamp(0.5 - s) x tier and ink = clamp(width + 0.5 - s) -
//      clamp(0.5 - s): the fill ends at the iso-line and the ink is a band `width` pixels wide
//      outside it, one outline around the whole layer however many particles overlap (Fig. 5's
//      merging). The ink lies at the medium's depth: nearer opaque surfaces hide it. Where an
//      opaque surface cuts the medium (outside the iso-line the medium unclipped is above the
//      threshold), the iso-line is the surface's edge, not the medium's: no ink, no rim.
// The cartoon style ignores burn: cartoon fire occludes what is behind it. HostLayers::composeOver
// draws it over a host's frame too (given the CartoonCompose), without the heat shimmer.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <puff/core/depth.h>
#include <puff/core/error.h>
#include <puff/core/gl.h>
#include <puff/core/viewport.h>
#include <puff/media/coverage.h>
#include <puff/media/media.h>
#include <puff/media/types.h>

namespace puff::media {

/// The host's depth buffer, read by HostLayers::resolveHostDepth.
struct HostDepth {
  /// A depth or depth-stencil texture, GL_TEXTURE_2D or GL_TEXTURE_2D_MULTISAMPLE (each pixel
  /// keeps its nearest sample), holding the host's opaque scene. Its target, format, size and
  /// sample count are read from the texture itself. A depth-stencil texture must keep its default
  /// GL_DEPTH_STENCIL_TEXTURE_MODE (GL_DEPTH_COMPONENT), and GL_TEXTURE_COMPARE_MODE must be
  /// GL_NONE (the default). Read with texelFetch: filters and mipmaps do not matter.
  core::GlId texture = 0;
  int x = 0, y = 0;  ///< where the layers' width() x height() region starts in the texture
};

/// What Layers::compose needs to draw the cartoon style.
struct CartoonCompose {
  CartoonStyle style;
  /// Band k's colour (k < fireBandCount(style), the coolest first): the palette's colour decoded to
  /// linear, or without one the black-body colour at the band's centre temperature, linear sRGB
  /// clipped at 0, normalized as the renderer's (luminance 1 at normalizeKelvin); either times the
  /// exposure. A pixel's fire colour is this times its particles' mean emission.
  std::vector<glm::vec3> fireColors;
  bool operator==(const CartoonCompose&) const = default;
};
/// The cartoon compose for `settings` (its cartoon style, black-body normalization and exposure).
/// Errors: the style's or the black body's values (validate, makeBlackbodyRamp).
Result<CartoonCompose> cartoonCompose(const Settings& settings);

/// What Layers and HostLayers share: the media layer (radiance, transmittance, shimmer and, for
/// the cartoon style, its attributes) at `scale` of the output, the opaque depth at the layer's
/// resolution, and how the layer is upsampled. Made only through Layers::create or
/// HostLayers::create.
class LayersBase {
 public:
  int width() const;
  int height() const;
  int mediaWidth() const;
  int mediaHeight() const;
  float scale() const;
  /// The opaque scene's full-size linear depth (R32F: the nearest of each pixel's samples), as
  /// Layers::resolveOpaque or HostLayers::resolveHostDepth left it (for tests and tools).
  core::GlId opaqueDepth() const;
  /// The opaque depth at the layer's resolution (for Renderer::draw).
  core::GlId mediaDepth() const;
  /// The media layer (RGBA32F: premultiplied radiance, transmittance), as the last draw left it.
  core::GlId mediaColor() const;
  /// The frame to draw the media layer with, from the full-size frame: the layer's size, and a
  /// projection whose viewport is the layer's (mediaWidth * factor may exceed width(): layer texel
  /// i covers full pixels [i * factor, (i + 1) * factor), the last ones partly outside the image).
  Frame layerFrame(const Frame& full) const;
  /// Binds the media layer framebuffer (attachment 0: RGBA32F radiance + transmittance; 1: RG16F
  /// shimmer), sets the viewport and clears it to no medium (0, 0, 0, 1). Style::kCartoon: for a
  /// renderer with that style, attachments 2 and 3 (RGBA32F, made on first use) too, cleared to 0.
  /// Leaves (a begin call: Renderer::draw draws into it next): the draw framebuffer = the media
  /// layer's; the viewport = (0, 0, mediaWidth(), mediaHeight()); scissor test and rasterizer
  /// discard off; colour write masks on for draw buffers 0 and 1 (0 to 3 for kCartoon). (GL_STENCIL_REF then reads back
  /// 0: the query clamps the stored reference to the bound framebuffer's stencil bits, none here; the stored value is
  /// untouched. The same for compose and blendHistory with a `target` without stencil.)
  void beginMedia(Style style = Style::kPhotoreal);
  /// How compose() upsamples when ComposeSettings::depthAware is on: bilateral weights in depth
  /// (the default), or the all-or-nearest rule (all four texels within the tolerance: bilinear, else the
  /// nearest-depth texel), kept so tests and benchmarks can measure one against the other.
  enum class Upsampling { kBilateral, kAllOrNearest };
  /// Limits the passes of the frames that follow to what the media can change (coverage.h): the
  /// full-size depth resolve, the layer's depth and the compose (the cartoon style's field, seeds,
  /// flooding and ink too) run over `covered` (coverage() of the frame's particles and lights),
  /// grown by what each pass reads around a pixel: the upsampling's taps, and for Style::kCartoon
  /// the jump flooding's reach for an ink `inkPixels` wide. Outside it compose copies the opaque
  /// colour (composeOver leaves the host's). The image is the whole frame's passes' image, bit for
  /// bit where the grown box reaches (tests/unit/media_coverage_test.cpp). An empty `covered` runs
  /// no media pass but the copy. std::nullopt (the default): every pass over the whole frame.
  /// `style` and `inkPixels` must be the frame's: compose stops the program with a message when
  /// its cartoon style differs or its ink is wider. With a coverage set, resolveOpaque,
  /// resolveHostDepth, compose and composeOver also leave the scissor box changed (their last
  /// pass's box; the scissor test off, as listed).
  void setCoverage(std::optional<PixelBox> covered, Style style = Style::kPhotoreal, float inkPixels = 0.0f);
  void setUpsampling(Upsampling rule);
  Upsampling upsampling() const;

 protected:
  struct Impl;
  explicit LayersBase(std::unique_ptr<Impl> impl);
  ~LayersBase();
  LayersBase(const LayersBase&) = delete;
  LayersBase& operator=(const LayersBase&) = delete;
  std::unique_ptr<Impl> impl_;
};

/// Layers with an opaque pass of Puff's own: Puff draws the opaque scene into opaqueFramebuffer(),
/// resolves it, and composes the media over it into a target.
class Layers final : public LayersBase {
 public:
  /// Full size width x height (the output; 1 to 16384 each, core::kMaxImageSize), `samples` MSAA
  /// samples for the opaque pass (1, 2, 4, 8), media layer at `scale` of it (1, 0.5, 0.25 or 0.125;
  /// at least 1 x 1). Needs GL 4.5. The programs read the units and buffer `bindings` names
  /// (validated: media::validate). Leaves no bound state changed.
  static Result<std::unique_ptr<Layers>> create(int width, int height, int samples, float scale,
                                                const Bindings& bindings = {});
  ~Layers();
  /// The framebuffer the opaque pass draws into: colour (RGBA16F, scene-linear) + depth/stencil (the
  /// cel programs' linear depth: draw with cel::Frame::depth = kLinear), multisampled as asked. The caller binds it,
  /// sets the viewport and clears.
  core::GlId opaqueFramebuffer() const;
  /// Resolves the opaque pass into single-sample colour + depth textures and builds the media
  /// layer's depth (nearest depth per layer texel, R32F linear). Sets its own state.
  /// Restores the draw framebuffer and viewport it found (two queries: a framebuffer of its own
  /// left bound would take the host's next draws unseen). Leaves: "the full-screen state" (depth
  /// test, stencil test, blending on draw buffer 0, culling, scissor test, rasterizer discard,
  /// alpha to coverage and the sample mask off (GL_FRAMEBUFFER_SRGB is the host's, untouched by
  /// every Layers call); polygon mode GL_FILL; draw buffer 0's colour write mask on; the blending
  /// and write masks of the other draw buffers as they were, but where a call lists them); no program, no vertex array;
  /// unit `resolveSource` with its 2D multisample texture = the opaque depth, its 2D texture = the resolved depth and
  /// sampler binding 0.
  void resolveOpaque();
  /// Composes into framebuffer `target` (0 = the default framebuffer; bound as the DRAW framebuffer,
  /// the read binding is left alone) over `viewport` (its width x height must be width() x height()).
  /// `frame`: the full-size frame (camera, planes) for the explosion lights. Colour only: the
  /// target's depth and stencil are not written.
  /// Leaves: the draw framebuffer = `target`; the viewport = `viewport`; the full-screen state
  /// (resolveOpaque); no program, no vertex array; uniform buffer binding `composeBlock` = its
  /// block (whole buffer; the generic binding untouched); units `opaqueColor`, `opaqueDepth`,
  /// `mediaLayer`, `mediaDepth` and `shimmer` with their 2D textures = its and sampler binding 0.
  /// With `cartoon` (the layer begun with beginMedia(Style::kCartoon); otherwise the program stops
  /// with a message): the cartoon style (header comment). It also leaves uniform buffer binding
  /// `cartoonBlock` and units cartoonFirst .. cartoonFirst + 2 with their 2D textures bound to its
  /// own, the generic uniform buffer binding untouched, and the full-screen state.
  void compose(core::GlId target, const core::Viewport& viewport, const Frame& frame,
               std::span<const ExplosionLight> lights, const ComposeSettings& settings,
               const CartoonCompose* cartoon = nullptr);
  /// Motion blur: `slots` full-size RGBA16F frames kept between calls (1..8; reallocated when the
  /// count changes). A frame is composed into historyFramebuffer(slot), then blendHistory sums
  /// the chosen slots with their weights into `target` (colour only, over `viewport`).
  /// blendHistory leaves: the draw framebuffer = `target`; the viewport = `viewport`; the
  /// full-screen state; no program, no vertex array; units historyFirst + i (i < slots.size())
  /// with their 2D textures = the slots' and sampler binding 0; the uniforms of its own program.
  void setHistorySlots(int slots);
  core::GlId historyFramebuffer(int slot) const;
  void blendHistory(core::GlId target, const core::Viewport& viewport, std::span<const int> slots,
                    std::span<const float> weights);
  /// The resolved opaque colour (RGBA16F, scene-linear; for tests and tools).
  core::GlId opaqueColor() const;
  /// The cartoon style's field at the output's size (RGBA32F: accumulated opacity A, the medium's
  /// linear depth, A without the opaque surfaces' clipping), as the last cartoon compose made it;
  /// 0 before the first cartoon beginMedia.
  core::GlId cartoonField() const;
  /// The pixels of cartoonField() the last cartoon compose wrote: the whole frame without a
  /// coverage (setCoverage). Beyond them the whole frame's passes find no medium (A = 0); the
  /// texture holds what an earlier frame left there.
  PixelBox cartoonFieldBox() const;

 private:
  using LayersBase::LayersBase;
};

/// Layers for a host that draws its own opaque scene (docs/embedding.md): the media layer and its
/// depth, no opaque framebuffer of their own. resolveHostDepth reads the host's depth and
/// composeOver blends the layer onto the host's colour target.
class HostLayers final : public LayersBase {
 public:
  /// Full size width x height (the host's viewport; 1 to 16384 each, core::kMaxImageSize), media
  /// layer at `scale` of it (1, 0.5, 0.25 or 0.125; at least 1 x 1). Needs GL 4.5. The programs
  /// read the units and buffer `bindings` names (validated: media::validate). Leaves no bound
  /// state changed.
  static Result<std::unique_ptr<HostLayers>> create(int width, int height, float scale, const Bindings& bindings = {});
  ~HostLayers();
  /// Layers::resolveOpaque for a host's scene: reads `depth` (in `frame`'s depth convention, with its
  /// projection and planes, the frame the media are drawn in; converted per sample to linear depth
  /// and clamped to [0, 1]; the far plane and an infinite one read 1, "no surface")
  /// into the full-size linear depth and the layer's nearest depth. Restores the draw framebuffer
  /// and viewport it found. Leaves: the full-screen state (Layers::resolveOpaque); no program, no
  /// vertex array; unit `resolveSource` with sampler binding 0, its 2D texture = Puff's linear depth
  /// and, after a multisample `depth`, its 2D multisample texture = `depth.texture`. Reading a
  /// texture attached to the bound read framebuffer is fine; it must not be attached to a draw
  /// buffer Puff renders into (it is not: Puff draws into its own).
  /// Errors (nothing drawn, no state changed): `depth.texture` not a 2D or 2D multisample texture
  /// of a depth format, reading its stencil or comparing; the layers' region not inside it; the
  /// frame's planes not 0 < near < far < infinity. Checking takes eight queries of the texture object's parameters.
  Result<void> resolveHostDepth(const HostDepth& depth, const core::SharedFrame& frame);
  /// Layers::compose for a host's frame (after resolveHostDepth): blends the media layer and the
  /// explosion lights over what framebuffer `target` already holds (header comment), over
  /// `viewport` (its size must be width() x height()). Colour only (RGB; the target's alpha, depth
  /// and stencil are kept). The blend happens in the target's space: give it scene-linear colour,
  /// a float target or an sRGB one with GL_FRAMEBUFFER_SRGB on (left as the host set it).
  /// `cartoon`: for a layer begun with beginMedia(Style::kCartoon), its CartoonCompose: the fill and
  /// the ink blended over the host's colour (cartoon_compose_over.frag: Layers::compose's cartoon
  /// image without shimmer), drawn where the media are (nothing elsewhere).
  /// Errors (nothing drawn): `cartoon` missing for a cartoon layer, or given for a photoreal one; a
  /// coverage set for the other style or a narrower ink (setCoverage); settings.shimmerPixels != 0;
  /// more than 8 lights that shine (intensity and radius > 0: compose() uses the first 8); a
  /// viewport of another size.
  /// A target drawing to more colour buffers (a G-buffer) draws to its first alone during the call
  /// (dual-source blending allows GL_MAX_DUAL_SOURCE_DRAW_BUFFERS, 1 on common GPUs) and gets its
  /// own draw buffers back; its other attachments are untouched.
  /// Leaves: the draw framebuffer = `target`; the viewport = `viewport`; depth test, stencil test,
  /// culling, scissor test, rasterizer discard, alpha to coverage and the sample mask off; polygon mode GL_FILL; draw
  /// buffer 0's colour write mask on; blending off on draw buffer 0, with its functions (GL_ONE,
  /// GL_SRC1_COLOR, GL_ZERO, GL_ONE) and equation GL_FUNC_ADD; no program, no vertex array; uniform buffer binding
  /// `composeBlock` = its block; units `opaqueDepth`, `mediaLayer`, `mediaDepth` and `shimmer` with their 2D textures =
  /// its and sampler binding 0; with `cartoon` also what Layers::compose's cartoon passes leave (uniform buffer binding
  /// `cartoonBlock`, units `cartoonFirst` to `cartoonFirst + 2`) but `opaqueColor`, which is not bound.
  Result<void> composeOver(core::GlId target, const core::Viewport& viewport, const Frame& frame,
                           std::span<const ExplosionLight> lights, const ComposeSettings& settings,
                           const CartoonCompose* cartoon = nullptr);

 private:
  using LayersBase::LayersBase;
};

}  // namespace puff::media
