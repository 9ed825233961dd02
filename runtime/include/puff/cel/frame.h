// What every cel pass shares in one frame: the camera, the light, the ambient term K_a and the ramp
// q of McGuire & Fein Eq. 2, and the linear depth convention. A host fills a Frame, uploads it once
// with FrameBlock::upload, then calls the passes it wants (opaque objects, nailboards, shadows)
// in its own GL frame.
//
// Units and conventions:
//  - World space is right-handed, y up, in the scene's units (metres by convention).
//  - Depth is LINEAR (§4.2): the depth attachment of the target holds (-z_view - near)/(far - near),
//    0 at the near plane and 1 at the far plane. Every cel program writes gl_FragDepth that way, so
//    geometry the host draws itself must too (include shaders/common/frame.glsl, use linearDepth).
//  - Colours are display values in [0, 1] (no sRGB conversion), as in the paper.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <puff/cel/bindings.h>
#include <puff/cel/types.h>
#include <puff/core/error.h>
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

/// Everything a pass needs to know about the frame. No GL objects: textures are set separately.
struct Frame {
  glm::mat4 view{1.0f};                       ///< world -> camera
  glm::mat4 projection{1.0f};                 ///< camera -> clip (perspective or orthographic)
  float nearPlane = 0.1f, farPlane = 100.0f;  ///< the planes `projection` uses; define linear depth
  Viewport viewport;
  Light light;
  glm::vec3 ambientColor{0.25f};  ///< uniform K_a, used when no gradient texture is bound
  bool ambientGradient = false;   ///< K_a from the gradient texture (Gradient::bind) instead
  /// Shadows from a ShadowMap (Style::shadowMethod kMap): the lit passes of nailboards and opaque
  /// objects draw a shadowed receiver with the ambient term only. Its textures go on units 6 and 7
  /// (ShadowMap::bind).
  ShadowLookup shadow;

  /// A frame looking through `camera` at a viewport of width x height pixels.
  static Frame fromCamera(const Camera& camera, int width, int height);
};

/// Linear depth of a world-space point in `frame`, as the cel programs write it (may lie outside
/// [0, 1] for points outside the near/far range; the depth buffer clamps).
float linearDepth(const Frame& frame, const glm::vec3& worldPoint);

/// The frame's uniform buffer (shaders/common/frame.glsl) on uniform binding `bindings.frameBlock`
/// (0 by default). Owns one GL buffer.
class FrameBlock {
 public:
  /// Needs a current GL 4.5 context. `bindings`: the renderers' (only frameBlock is used).
  explicit FrameBlock(const Bindings& bindings = {});
  /// Fills the buffer from `frame` (glNamedBufferSubData: no binding used) and binds it (bind()).
  /// Leaves: uniform buffer binding `frameBlock` = this block (whole buffer). Nothing else; the
  /// generic GL_UNIFORM_BUFFER binding is untouched (glBindBuffersBase).
  void upload(const Frame& frame);
  /// Binds it to uniform binding `frameBlock` again (after the host used it for something else).
  /// Leaves what upload leaves.
  void bind() const;
  GLuint buffer() const { return buffer_.get(); }

 private:
  core::Buffer buffer_;
  GLuint binding_ = 0;
};

/// The quantization ramp q (§4.1): a 1D texture, clamp-to-edge, which enforces max(0, N.L).
class Ramp {
 public:
  /// Uses the middle row of `image` (RGB; a 1- or 2-channel image is grey). Width in [2, 16384].
  /// `smooth` selects linear filtering; the default, nearest, keeps the bands hard as in the paper.
  /// Errors name `what` (usually the file).
  static Result<Ramp> create(const core::Image& image, const std::string& what, bool smooth = false);
  /// Loads a ramp image (PNG or anything OpenImageIO reads).
  static Result<Ramp> load(const std::filesystem::path& path, bool smooth = false);
  /// A two-tone ramp: black below 0.5, white from 0.5 (the paper's typical map).
  static Ramp twoTone();
  /// Binds to texture unit `bindings.ramp` (0 by default) with no sampler object there. Leaves:
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
  static Result<Gradient> create(const core::Image& image, const std::string& what);
  static Result<Gradient> load(const std::filesystem::path& path);
  /// Binds to texture unit `bindings.gradient` (1 by default) with no sampler object there.
  /// Leaves: that unit's 2D texture = the gradient and its sampler binding = 0.
  void bind(const Bindings& bindings = {}) const;

 private:
  core::Texture texture_;
};

}  // namespace puff::cel
