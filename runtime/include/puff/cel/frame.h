// What every cel pass shares in one frame: the camera, the light, the ambient term K_a and the ramp
// q of McGuire & Fein Eq. 2, and the depth convention. A host fills a Frame, uploads it once with
// FrameBlock::upload, then calls the passes it wants (opaque objects, nailboards, shadows) in its
// own GL frame.
//
// Units and conventions:
//  - World space is right-handed, y up, in the scene's units (metres by convention).
//  - Depth: Puff computes every depth in LINEAR space (§4.2), (-z_view - near)/(far - near): 0 at
//    Frame::nearPlane, 1 at Frame::farPlane. A nailboard's per-pixel offset, the shadow bias and a
//    shadow volume's entry and exit are additions there. What the depth attachment STORES is the
//    host's choice, Frame::depth (docs/cel-rendering.md, "Depth conventions"):
//      kLinear    the linear depth itself, the paper's; test LESS, clear to 1. Geometry the host
//                 draws itself must write it too (include shaders/common/frame.glsl, write
//                 gl_FragDepth = linearDepth(dist)).
//      kStandard  the window depth the host's projection gives (hyperbolic in perspective), as its
//                 own shaders write it through gl_Position; test LESS, clear to 1.
//      kReversedZ the same, with a projection that maps near -> 1 and far -> 0 (far may be
//                 infinite); test GREATER, clear to 0. Usually with glClipControl(GL_LOWER_LEFT,
//                 GL_ZERO_TO_ONE) and a GL_DEPTH32F_STENCIL8 attachment.
//    For kStandard and kReversedZ the window depth of a view distance d comes from Frame::projection
//    itself: clip = P * (0, 0, -d, 1), ndc = clip.z / clip.w, window = ndc (ClipDepth::kZeroToOne)
//    or 0.5 * ndc + 0.5 (kNegativeOneToOne), with glDepthRange(0, 1) (resetPassState sets it). Any
//    perspective or orthographic projection works, an infinite far plane included, as long as its
//    z row depends on z and w only (no oblique near plane). Each cel program converts its linear
//    depth per pixel at the very end (storeDepth in frame.glsl), so host shaders do not change;
//    the conversion is monotonic, so depth-fail counting and the shadowed pass's EQUAL test work
//    in every convention. The passes test with nearerDepthFunc(): LESS, or GREATER for kReversedZ.
//  - Frame::farPlane must be finite even when the projection's far plane is infinite: it is the
//    end of Puff's linear scale. Shadow volumes end there (their depth is clamped to it), and
//    volumeClip treats receivers beyond it as unseen; puffs beyond it still draw and test right
//    (linear depth > 1 converts through the projection). Choose it past everything that casts or
//    receives a shadow.
//  - Colours a host passes (the light's K_L, the ambient K_a, a particle's tint, the ink, an opaque
//    object's albedo) are scene-linear, as every colour passed to Puff is (core/frame.h). Eq. 2
//    combines display values, as the paper does: FrameBlock::upload and the passes encode them
//    (core::linearToSrgb) inside. The ramp and gradient images are display values.
//
// Why the standalone renderer (puff::render, puffrender) keeps kLinear: it draws into a 24-bit
// depth buffer, where linear depth resolves (far - near) / 2^24 world units at every distance,
// and standard depth d^2 (far - near) / (far * near * 2^24) ~ d^2 / (near * 2^24) at distance d
// (2^-24 over the slope of the window depth f (d - n) / ((f - n) d)). For the default near 0.1, far 100:
//      distance d      0.5       1         3.16      10        50        100
//      linear        5.95e-6   5.95e-6   5.95e-6   5.95e-6   5.95e-6   5.95e-6
//      standard      1.49e-7   5.95e-7   5.95e-6   5.95e-5   1.49e-3   5.95e-3
// Standard is finer only nearer than sqrt(near * far) = 3.16 units, where both are far below
// anything a puff's depth offset or bias resolves; beyond it standard is 10x coarser at 10 units
// and 1000x at the far plane. The opaque shadow volumes' bias (1e-5 of the linear range, 1e-3
// world units by default) is below one standard 24-bit step beyond about 41 units. (Reversed-z
// in a 32-bit float buffer resolves at most d * 2^-23: 1.2e-5 at 100 units, finer than linear
// nearer than 50 units, but it needs a float depth buffer and glClipControl.)
#pragma once

#include <cstdint>
#include <string_view>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <puff/cel/bindings.h>
#include <puff/cel/types.h>
#include <puff/core/depth.h>
#include <puff/core/error.h>
#include <puff/core/frame.h>
#include <puff/core/gl.h>
#include <puff/core/image.h>

namespace puff::cel {

/// How receivers look up a shadow map (ShadowMap::lookup fills it; off by default). A receiver at
/// world point P with caster id `own` is in shadow when the map's texel at worldToMap * P holds a
/// caster other than `own` whose shadow starts at least `tolerance` before P along the light and
/// no more than `length` before it.
struct ShadowLookup {
  bool enabled = false;
  glm::mat4 worldToMap{1.0f};  ///< world -> the map's clip space (orthographic): xy over the map, z its depth
  float tolerance = 0.0f;      ///< map depth units (the map's z in [0, 1])
  float length = 0.0f;         ///< map depth units: Style::shadowLength
};

/// What the lit passes of the nailboards and the opaque objects write (Frame::output): the frame's
/// colour, or a map of the same pixels for an engine that lights them itself (puffrender --flipbook
/// --maps, docs/flipbooks.md). A map is data in [0, 1] per channel (no transfer function): a
/// frame asking for one draws no shadows; the shadowed pass must not be drawn (it writes colour).
enum class FrameOutput {
  kColour,  ///< Eq. 2, scene-linear
  kNormal,  ///< the camera-space normal n as 0.5 n + 0.5: x right, y up, z toward the camera
  kDepth,   ///< 0.5 + (origin - d) / (2 range) for view-axis distance d (OutputDepth): nearer is brighter
  kInk,     ///< the ink's share of the covered pixel (0 without outlines), in every channel
  /// The screen motion m to the next frame (pixels, x right, y up) as 0.5 + m / (2 motionRange) in
  /// x and y (z 0): each billboard point carried as its particle moves and grows
  /// (NailboardRenderer::uploadNext), seen by this frame's camera; objects write 0.
  kMotion,
};
std::string_view toString(FrameOutput output);

/// How the maps encode what they hold (Frame::outputScale).
struct OutputScale {
  float depthOrigin = 0.0f;  ///< kDepth: the view-axis distance written as 0.5
  float depthRange = 1.0f;   ///< kDepth: scene units either side of it spanning [0, 1], > 0
  float motionRange = 1.0f;  ///< kMotion: pixels either side of no motion spanning [0, 1], > 0
};

/// What the depth attachment stores and the projection's clip z range (core/depth.h; the header
/// comment above has the formulas).
using DepthConvention = core::DepthConvention;
using ClipDepth = core::ClipDepth;

/// Everything a pass needs to know about the frame: what every Puff frame has (core/frame.h: the
/// camera, the light and K_a in scene-linear, the depth convention, the viewport) and the cel
/// path's own. No GL objects: textures are set separately.
struct Frame : core::SharedFrame {
  Frame() = default;
  /// The shared part from `shared`, the cel path's own fields at their defaults.
  explicit Frame(const core::SharedFrame& shared) : core::SharedFrame(shared) {}

  bool ambientGradient = false;  ///< K_a from the gradient texture (Gradient::bind) instead of `ambient`
  /// Shadows from a ShadowMap (Style::shadowMethod kMap): the lit passes of nailboards and opaque
  /// objects draw a shadowed receiver with the ambient term only. Its textures go on units `shadowMapDepth` and
  /// `shadowMapIds` (ShadowMap::bind).
  ShadowLookup shadow;
  FrameOutput output = FrameOutput::kColour;  ///< what the lit passes write
  OutputScale outputScale;                    ///< how kDepth and kMotion encode theirs

  /// A frame looking through `camera` at a viewport of width x height pixels.
  static Frame fromCamera(const Camera& camera, int width, int height);
};

/// Linear depth of a world-space point in `frame`, as the cel programs write it (may lie outside
/// [0, 1] for points outside the near/far range; the depth buffer clamps).
float linearDepth(const Frame& frame, const glm::vec3& worldPoint);

/// What the depth attachment stores for linear depth `linear` in `frame`'s convention, as the cel
/// programs write it (shaders/common/frame.glsl, storeDepth): `linear` itself for kLinear; for
/// kStandard and kReversedZ the projection's window depth at distance near + max(linear, 0) *
/// (far - near), clamped to [0, 1].
float storedDepth(const Frame& frame, float linear);

/// The depth function that lets the nearer fragment through in `convention`: GL_LESS for kLinear
/// and kStandard, GL_GREATER for kReversedZ. The depth buffer clears to clearDepth(convention).
core::GlEnum nearerDepthFunc(DepthConvention convention);
float clearDepth(DepthConvention convention);

/// The convention of the FrameBlock last uploaded or bound on this thread (kStandard before any):
/// the cel passes take their depth test from it (nearerDepthFunc(boundDepthConvention())).
DepthConvention boundDepthConvention();
/// The viewport of the FrameBlock last uploaded or bound on this thread (empty before any): the
/// nailboards' visibility pre-pass sizes its target from it (NailboardRenderer::drawNailboards).
core::Viewport boundViewport();
/// A number that changes whenever a FrameBlock is uploaded or bound on this thread: the nailboards'
/// shadowed pass reads the lit pass's pre-pass only while it is the same.
std::uint64_t boundFrameSerial();
/// The projection x view of the FrameBlock last uploaded or bound on this thread (identity before
/// any), and its projection's y scale (projection[1][1]): the nailboards' lit pass estimates how
/// deep its quads stack on the screen from them.
glm::mat4 boundViewProjection();
float boundProjectionScaleY();

/// The frame's uniform buffer (shaders/common/frame.glsl) on uniform binding `bindings.frameBlock`
/// (cel/bindings.h). Owns one GL buffer.
class FrameBlock {
 public:
  /// Needs a current GL 4.5 context. `bindings`: the renderers' (only frameBlock is used).
  explicit FrameBlock(const Bindings& bindings = {});
  /// Fills the buffer from `frame` (glNamedBufferSubData: no binding used) and binds it (bind()).
  /// The frame's depth convention becomes the one the cel passes test with (boundDepthConvention),
  /// its viewport the one they draw in (boundViewport).
  /// Errors (nothing uploaded, nothing bound): planes not finite with nearPlane < farPlane.
  /// Leaves: uniform buffer binding `frameBlock` = this block (whole buffer). Nothing else; the
  /// generic GL_UNIFORM_BUFFER binding is untouched (glBindBuffersBase).
  Result<void> upload(const Frame& frame);
  /// Binds it to uniform binding `frameBlock` again (after the host used it for something else),
  /// its depth convention and viewport with it.
  /// Leaves what upload leaves.
  void bind() const;
  core::GlId buffer() const { return buffer_.get(); }

 private:
  core::Buffer buffer_;
  DepthConvention depth_ = DepthConvention::kStandard;
  core::Viewport viewport_;
  glm::mat4 viewProjection_{1.0f};
  float projectionScaleY_ = 1.0f;
  core::GlId binding_ = 0;
};

/// What a ramp file may be, checked from its header before decoding: at most 16384 pixels wide
/// and 256 rows, 1 to 4 channels, a file of at most 64 MiB (create's own rule: at least 2 wide).
inline constexpr core::ImageLimits kRampLimits{"a ramp", 16384, 256, 4, 1ll << 28, std::uintmax_t{64} << 20};
/// What a gradient file may be: at most 4096 x 4096 pixels, 1 to 4 channels, a file of at most
/// 256 MiB.
inline constexpr core::ImageLimits kGradientLimits{"a gradient", 4096, 4096, 4, 1ll << 24, std::uintmax_t{256} << 20};

/// The quantization ramp q (§4.1): a 1D texture, clamp-to-edge, which enforces max(0, N.L).
/// How a Ramp's texture is filtered between its texels.
enum class RampFilter { kNearest, kLinear };

class Ramp {
 public:
  /// Reads a ramp file within kRampLimits and checks it as create does, without GL: the image
  /// create takes. Errors name the file.
  static Result<core::Image> read(const std::filesystem::path& path);
  /// create's checks alone: a width in [2, 16384] and finite values in the middle row.
  static Result<void> check(const core::Image& image, const std::string& what);
  /// Uses the middle row of `image` (RGB; a 1- or 2-channel image is grey). Width in [2, 16384].
  /// `filter`: kNearest (the default) keeps the bands hard as in the paper; kLinear blends them.
  /// Errors name `what` (usually the file).
  static Result<Ramp> create(const core::Image& image, const std::string& what,
                             RampFilter filter = RampFilter::kNearest);
  /// Loads a ramp image: a cooked image, or PNG and the like through the installed codec (core/image.h).
  static Result<Ramp> load(const std::filesystem::path& path, RampFilter filter = RampFilter::kNearest);
  /// A two-tone ramp: black below 0.5, white from 0.5 (the paper's typical map).
  static Ramp twoTone();
  /// Binds to texture unit `bindings.ramp` with no sampler object there. Leaves:
  /// that unit's 1D texture = the ramp and its sampler binding = 0. The active texture unit and
  /// the unit's other targets are untouched (glBindTextureUnit).
  void bind(const Bindings& bindings = {}) const;
  int width() const { return width_; }

 private:
  core::Texture texture_;
  int width_ = 0;
};

/// An image-space ambient gradient K_a(x, y) (§4.1, Fig. 8b): stretched over the viewport, top row
/// at the top of the image, linear filtering.
class Gradient {
 public:
  /// Reads a gradient file within kGradientLimits and checks it as create does, without GL.
  static Result<core::Image> read(const std::filesystem::path& path);
  /// create's checks alone: 1 to 4096 pixels on each side, finite values.
  static Result<void> check(const core::Image& image, const std::string& what);
  static Result<Gradient> create(const core::Image& image, const std::string& what);
  static Result<Gradient> load(const std::filesystem::path& path);
  /// Binds to texture unit `bindings.gradient` with no sampler object there.
  /// Leaves: that unit's 2D texture = the gradient and its sampler binding = 0.
  void bind(const Bindings& bindings = {}) const;

 private:
  core::Texture texture_;
};

}  // namespace puff::cel
