// Cel-shaded nailboards with outlines and shadows (McGuire & Fein §4.1-4.3), drawn with
// programmable GL (4.5) into whatever framebuffer is current. Shadows come from a shadow map (the
// default; the puffs drawn as its casters: cel/shadow_map.h) or from billboard shadow volumes.
//
// A frame, as a host draws it (render::detail::CelPath draws the whole sequence; shadow_map.h the map's):
//   1. clear colour, depth (to clearDepth(frame.depth): 1, or 0 for reversed-z) and stencil (to 0);
//      upload a FrameBlock; bind Ramp and Gradient;
//   2. draw opaque geometry lit, writing depth in the frame's convention (OpaqueRenderer, or the
//      host's own shaders: linear depth for kLinear, plain gl_Position depth for the others);
//   3. NailboardRenderer::drawNailboards(..., ShadePass::kLit) (each pixel shaded once: a pre-pass
//      into Puff's own target, then a pass over the screen rectangle the puffs reach;
//      drawNailboards says what it leaves);
//   with shadow volumes (Style::shadowMethod kVolumes; the shadow map's frame is in shadow_map.h):
//   4. NailboardRenderer::drawShadowVolumes(...) counts into the stencil buffer (depth-fail);
//   5. every receiver is drawn again with ShadePass::kShadowed: depth test EQUAL, only where the
//      stencil is non-zero, colour = the ambient term only (Eq. 2 without its diffuse term).
//
// Host state (docs/cel-rendering.md, "Host state"). Each draw call sets every piece of GL state it
// relies on, never trusting what the host or an earlier pass left, and queries no host state (a
// glGet may stall a threaded driver) but the draw framebuffer's binding, samples and depth format (the
// lit pass's pre-pass: drawNailboards) and which draw buffers
// it has. Every draw writes the framebuffer's draw buffer 0 alone: one with more colour
// attachments enabled (a G-buffer) draws to its first alone during the call and gets its own draw
// buffers back (core::DrawBufferZero), its other attachments untouched. What each call LEAVES changed is
// listed with it below, exactly; everything else is as the host had it. A host that wants its state back wraps its Puff
// calls in one core::HostStateGuard (core/host_state.h): one capture and one restore per frame
// instead of a restore in every pass, since consecutive passes set the same state. The binding
// points are the host's (Bindings, bindings.h: offsets from one base per kind). Lists below use:
//  - "the pass state" (pass_state.h, resetPassState): blending off on draw buffer 0, culling,
//    scissor test, depth clamp, polygon offset fill, alpha to coverage, rasterizer discard,
//    primitive restart and fixed-index primitive restart all off; polygon mode GL_FILL; depth range
//    [0, 1]; depth test on (GL_FRAMEBUFFER_SRGB is the host's: Puff writes scene-linear colour,
//    which an sRGB target with the flag on encodes);
//  - "write masks on" (restoreWriteMasks): depth write mask on, draw buffer 0's colour write mask
//    on, stencil write mask 0xFF front and back;
//  - "no program, no vertex array": glUseProgram(0), glBindVertexArray(0) (a host binding an
//    element buffer next would otherwise change Puff's vertex array);
//  - "its atlas": units `atlasPacked`, `atlasColor` (2D: the atlas's maps) and `atlasHull` (3D: the
//    tumbling hull's field; the renderer's own 1 x 1 x 1 texture when the atlas has one view) and
//    `shadowProfile` (2D: the silhouettes' radius table), each with sampler binding 0; storage buffer bindings
//    `particles` and `cells` (whole buffers; the generic GL_SHADER_STORAGE_BUFFER binding is
//    untouched: multi-bind).
// Never changed by any cel call: the framebuffers (but ShadowMap::beginCasters) and their draw
// buffers, the viewport (the same), the blending and colour write masks of draw buffers 1 and up,
// the active texture unit, the generic buffer bindings, the blend functions, equations and
// colour, the stencil test's state but where listed, the cull face mode, the polygon offset factor
// and units, and texture units, uniform and storage bindings other than those listed.
//
// Particles reach the GPU as 16 bytes each (PackedParticle) and become quads in the vertex shader
// (vertex pulling from a shader storage buffer): 6 vertices per nailboard, 12 per shadow-volume
// face (a fan of four triangles over the volume's convex hull on screen), drawn twice: the entry
// and the exit face are the same triangles, told apart by the draw rather than their winding.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/volume_clip.h>
#include <puff/core/atlas.h>

namespace puff::cel {

/// The 16 bytes one particle costs per frame on the bus.
///   x: position x | y << 16   (16-bit grid indices, PackBounds)
///   y: position z | half(size) << 16
///   z: orientation, "smallest three" quaternion: 2-bit index of the dropped component, 3 x 10 bits
///   w: variation (8 bits) | oriented flag (bit 8) | tint r, g, b (7 bits each, bits 9, 16 and 23:
///      round(127 x linearToSrgb(channel)), the display multiplier of C); bits 30-31 are 0
struct PackedParticle {
  std::uint32_t x = 0, y = 0, z = 0, w = 0;
};
static_assert(sizeof(PackedParticle) == 16);

/// The grid positions are quantized on, per axis: point q (0..65535) is min + q * step (world units).
/// The grid is fixed in the world, not fitted to the batch's box, so that a still particle keeps its
/// exact position while the rest of a large batch moves (no shimmer):
///   step: the smallest power of two, at least 2^-24, with the batch's extent (max - min of its
///         drawn positions) <= 65534 steps. It changes only when the extent crosses 65534 * 2^k.
///   min:  the origin, a multiple of step (the batch's least coordinate rounded down to the grid).
///   max:  min + 65535 * step, the grid's far corner (rounded to a float; not used to unpack).
/// Worst-case position error: step / 2 < max(extent / 65534, 2^-24) per axis, i.e. under 1.53e-5
/// of the batch's extent (the box-fitted grid this replaced: 0.77e-5), at any distance from the
/// world's origin. Far out, a position is exactly its float when the step is finer than the float.
struct PackBounds {
  glm::vec3 min{0.0f}, max{65535.0f * 0x1.0p-24f}, step{0x1.0p-24f};
};

/// Packs `particles` into `out` (resized) and returns the grid used. Sizes above 65504 (half
/// float) are clamped; orientations are normalized. Positions round to the nearest grid point. A
/// position that is not finite or has a coordinate beyond 2^125 draws nothing (size 0) and does
/// not widen the grid.
PackBounds packParticles(std::span<const Particle> particles, std::vector<PackedParticle>& out);
/// The particle the GPU sees after packing (for tests and the CPU reference): bit for bit what
/// shaders/cel/particle.glsl's unpackParticle computes, but the tint, which the shader keeps as the
/// display value (code / 127) and this gives decoded to scene-linear, as a Particle holds it.
Particle unpackParticle(const PackedParticle& packed, const PackBounds& bounds);

/// Counts for the benchmark and tests.
struct DrawStats {
  std::size_t particles = 0;
  std::size_t bytesUploaded = 0;  ///< bytes of particle data sent this call
  std::size_t drawCalls = 0;
};

/// How the lit pass shades (NailboardRenderer::drawNailboards, ShadePass::kLit).
enum class LitShading {
  /// kOncePerPixel where the quads stack: where their summed screen area is at least
  /// kOnceMinOverdraw times the screen rectangle they reach (estimated each frame from at most 4096
  /// of them), else kEveryLayer. The default.
  kAuto,
  /// Each pixel once: a visibility pre-pass draws the nailboards' depth and particle id into Puff's
  /// own target, then a pass over the screen rectangle the puffs reach shades each pixel's particles
  /// there, at that depth. For the tumbling hull, on a framebuffer of more samples than
  /// PUFF_MAX_DEFERRED_SAMPLES (8) or GL_MAX_INTEGER_SAMPLES, and where Puff's target cannot be made
  /// (an incomplete framebuffer), kEveryLayer.
  kOncePerPixel,
  /// Every layer as it is drawn (the nailboards' quads, depth-tested): the yardstick kOncePerPixel
  /// is checked and timed against.
  kEveryLayer,
};
/// kAuto's threshold: shading once pays where the quads stack deeper than this over the rectangle
/// (the screen pass costs its whole rectangle where a rasterizer runs a discarded pixel's code, as
/// llvmpipe does). Measured with puff_bench_cel --overdraw (docs/cel-rendering.md, "Shading each
/// pixel once"): 1,000 puffs stacked 1 deep cost about the same either way, 2 deep once is 1.1x
/// cheaper, half a screen deep 1.5x dearer.
inline constexpr float kOnceMinOverdraw = 1.5f;

/// Whether the tumbling hull's passes drop the fragments hidden behind another hull-drawn puff's core
/// before they march (NailboardRenderer::setHullOcclusion). The pixels are the same every way.
enum class HullOcclusion {
  /// kCores where the quads stack at least kOccludersMinOverdraw deep (kAuto's estimate, LitShading),
  /// else kNone. The default.
  kAuto,
  /// Before each pass of the hull, an occluder pass draws each hull-drawn puff's core (a ball inside
  /// its hull, found when the field is built) as a disc into Puff's own target (sized from the bound
  /// frame's viewport; the host's framebuffer gets no attachment); the hull's fragments behind a disc
  /// are dropped.
  kCores,
  /// Every fragment marches: the yardstick kCores is checked and timed against.
  kNone,
};
/// kAuto's threshold: where the quads do not stack, no core hides another puff and the occluder pass
/// is a cost alone. Measured at two points only, not where it turns (docs/cel-rendering.md,
/// "Tumbling puffs: the hull"): a grid of puffs apart (stacked about 1 deep) costs less without the
/// pass, dust-roll (2.6 deep) much less with it; the value is kOnceMinOverdraw's.
inline constexpr float kOccludersMinOverdraw = 1.5f;

class NailboardRenderer {
 public:
  /// Builds the programs and points them at `bindings` (validated: cel::validate). Needs a current
  /// GL 4.5 context; fails with the shader log otherwise. Leaves no bound state changed.
  static Result<std::unique_ptr<NailboardRenderer>> create(const Bindings& bindings = {});
  ~NailboardRenderer();

  /// Uploads the atlas's maps (every mip level) and, for an atlas of several views, builds the
  /// tumbling hull's field from them (on the CPU, every core: the hull of all the views' silhouettes and far sides,
  /// sampled on core::hullFieldLayout's grid). Fails if a map is missing or sizes disagree. Leaves GL_UNPACK_ALIGNMENT
  /// = 4 (and no bound object changed: direct state access).
  Result<void> setAtlas(const core::Atlas& atlas);
  const core::AtlasDesc& atlas() const;
  /// Bytes the atlas's textures hold on the GL (the packed normal/depth/distance map and the colour
  /// map, every level, and a multi-view atlas's hull field), measured from the textures: each level's width x
  /// height (and depth) (queried) times the bytes per texel of its queried internal format. 0 before setAtlas. Equals
  /// core::atlasTextureBytes(atlas()). Not counted: the per-cell shadow profile (32 floats a cell).
  std::size_t textureBytes() const;

  /// Uploads this frame's particles (16 bytes each). Call once per frame before drawing; the
  /// passes below all draw the particles of the last upload. Leaves no state changed (direct state
  /// access: no buffer is bound).
  DrawStats upload(std::span<const Particle> particles);
  /// For a frame that writes motion (FrameOutput::kMotion): each particle of the last upload where it
  /// is at the next frame (world xyz; w its size there), in the upload's order. The passes then bind
  /// them on storage binding `particleNext`. An empty span forgets them (the next upload does too).
  void uploadNext(std::span<const glm::vec4> next);

  /// Draws the nailboards of the last upload into the current framebuffer with `frame`'s block
  /// already bound (FrameBlock::upload), the ramp and the gradient on their units (Ramp::bind,
  /// Gradient::bind). Binds the atlas on units `atlasPacked` (packed normal, depth, distance),
  /// `atlasColor` and `atlasHull` (the hull's field, or a 1 x 1 x 1 texture) and the silhouette's radius table on
  /// `shadowProfile` (small puffs' silhouettes and ink bands: shaders/cel/particle.glsl, silhouetteRadius). kLit shades
  /// each pixel once (LitShading::kOncePerPixel; one view or four blended, up to PUFF_MAX_DEFERRED_SAMPLES samples; the
  /// tumbling hull is drawn as kEveryLayer, and with Style::hullFromPixels after the blend has drawn the puffs smaller
  /// than that): a pre-pass draws the nailboards' depth and particle ids into Puff's own target (sized from the bound
  /// frame's viewport, its depth buffer of the framebuffer's depth format; the host's framebuffer gets no attachment),
  /// then two triangles over the screen rectangle the quads reach (the drawn centres' box grown by the largest quad,
  /// projected, padded by the ink) shade each pixel's particles there and writes their depth, depth-tested as the quads
  /// were. Multisampled, a pixel's samples take the average of its particles' colours, and the depth of the one
  /// covering most of them (only along silhouettes does a sample's depth differ from the quads', and the colour written
  /// there is the pixel's particles' average, hidden ones included). kShadowed after a kLit that shaded once, of the
  /// same upload, frame block (boundFrameSerial), draw framebuffer, samples and hullFromPixels split, shades what that
  /// pre-pass found, once per pixel too (its depth test EQUAL meets the depth kLit wrote); otherwise
  /// every layer. Queries the draw framebuffer's binding (put back after the pre-pass), samples and
  /// depth format.
  /// Leaves: the pass state; its atlas; no program, no vertex array; write masks on; and per pass
  ///   kLit, kDepthOnly: depth function GL_LESS, stencil test off;
  ///   kShadowed: depth function GL_EQUAL, stencil test ON, stencil function GL_NOTEQUAL, reference
  ///              0, value mask 0xFF and operations GL_KEEP x 3, front and back;
  ///   kLit and kShadowed when they shade once per pixel: unit `visibility` = the pre-pass's target
  ///              (2D, or 2D multisample on a multisampled framebuffer), sampler 0 there;
  ///   every pass that draws the tumbling hull with its occluders (setHullOcclusion): unit
  ///              `visibility` = the occluder target (2D), sampler 0 there (in a hullFromPixels split
  ///              too: the hull is drawn after the blend's share).
  /// On a multisampled framebuffer also GL_MULTISAMPLE on. Nothing at all with no particles or no
  /// atlas (it returns before any GL call).
  DrawStats drawNailboards(const Style& style, ShadePass pass);
  /// How the lit pass shades (kAuto by default).
  void setLitShading(LitShading shading);
  /// Whether the tumbling hull's passes drop the fragments hidden behind other puffs' cores (kAuto by
  /// default).
  void setHullOcclusion(HullOcclusion occlusion);

  /// The benchmark's fill-rate floor: the same quads with the colour map alpha-tested, nothing
  /// else (no shading, depth offset or outlines); the nearer depth test (nearerDepthFunc) with the quad's own depth.
  /// Leaves what drawNailboards(kLit) leaves (never GL_MULTISAMPLE).
  DrawStats drawBaseline(const Style& style);

  /// Counts the particles' shadow volumes into the stencil buffer (depth-fail, depth clamp; the
  /// target needs a stencil attachment). Leaves colour and depth untouched. Stencil is not cleared.
  /// `floorPlane` (world plane n.x + w = 0, n pointing up; n = 0 for none): volumes stop one puff
  /// diameter past it, which saves fill rate when everything below it is out of sight. `clip`
  /// (volumeClip of the receivers' box: puffs and opaque objects) limits the pass to the receivers'
  /// screen rectangle and depth range; the default clips nothing.
  /// Leaves: the pass state; its atlas; no program, no vertex array; write masks on; depth function
  /// GL_LESS; stencil test off with function GL_ALWAYS, reference 0, value mask 0xFF and operations
  /// (GL_KEEP, GL_INCR_WRAP, GL_KEEP), front and back; with a clip that is not `everything`, the
  /// scissor box = clip.scissor (and, where GL_EXT_depth_bounds_test is there, the depth bounds =
  /// its range, the bounds test off). Nothing with no particles, no atlas or clip.nothing.
  DrawStats drawShadowVolumes(const Style& style, const glm::vec4& floorPlane = glm::vec4(0.0f),
                              const VolumeClip& clip = VolumeClip{});

  /// Draws the particles of the last upload into a shadow map (after ShadowMap::beginCasters, whose
  /// light frame is bound): nailboards facing the light (an unoriented puff shows the light its front
  /// view, its right the eye's right carried across the light, so a long puff's shadow lies along it
  /// as the eye sees it; an oriented one the view toward the light), each texel keeping where the
  /// puff's shadow starts (its far side plus style.shadowBias diameters) and the particle's id. No
  /// outlines. `eye`: the frame the puffs are seen in.
  /// Leaves what drawNailboards(kLit) leaves (never GL_MULTISAMPLE).
  DrawStats drawShadowCasters(const Style& style, const Frame& eye);

 private:
  NailboardRenderer();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace puff::cel
