// Renders scene frames into images: loads what a scene names (atlas, ramp, gradient, meshes),
// owns an offscreen target (colour, linear depth + stencil, MSAA when asked) and runs the cel
// frame: opaque objects, nailboards, shadow volumes, shadowed receivers. puffrender is a thin
// shell around this.
#pragma once

#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include <puff/core/image.h>
#include <puff/render/scene.h>

namespace puff::render {

/// The render paths a scene can be drawn with.
enum class RenderPath {
  kCel,    ///< programmable GL 4.5: nailboards, outlines from the flange, shadow volumes (puff::cel)
  kFixed,  ///< GL 1.x fixed function (puff::fixedfunc, §4.4): per-frame puff texture, backing
           ///< billboards for outlines; one light, uniform ambient, no shadows, flat billboards
  /// The cel REFERENCE (issue 7): the image nailboards approximate. Every particle is its actual puff
  /// mesh (the atlas's source mesh of its variation, full detail), placed and turned as its billboard
  /// (the puff frame of Style::alignment, or its orientation), shaded by Eq. 2 per pixel with the
  /// same K_a, C, K_L and q; ink around each puff's true silhouette in the image (a pixel within
  /// Style::outlineWidth of a NEARER puff's visible pixels); exact shadows from a shadow map of the
  /// puff meshes at high resolution that knows which puff each texel saw, so a puff is shadowed by
  /// every other puff (and opaque objects by all puffs) but never by itself, as the billboard shadow
  /// volumes intend; shadows are not cut at Style::shadowLength. Supersampled (no MSAA), slow, GL 4.5.
  /// Media (fire, smoke, dust) are left out: puff::reference::renderMediaReference is theirs.
  kReference,
};
std::string_view toString(RenderPath path);
std::optional<RenderPath> parseRenderPath(std::string_view name);  ///< "cel", "fixed" or "reference"

/// How finely the cel reference (RenderPath::kReference) samples.
struct CelReferenceOptions {
  int supersample = 3;       ///< samples per pixel side, box-filtered down; [1, 8]
  int shadowMapSize = 4096;  ///< texels per side of the shadow map over the puffs' bounding sphere; [256, 8192]
};

struct FrameStats {
  std::size_t particles = 0;  ///< drawn (listed + placed + simulated)
  std::size_t simulated = 0;  ///< of which from the simulator
  std::size_t bytesUploaded = 0;
  double simulateMs = 0.0;         ///< CPU time spent stepping the simulators for this frame
  std::size_t mediaParticles = 0;  ///< fire, smoke and dust particles drawn
};

class SceneRenderer {
 public:
  /// Loads the scene's resources and builds the GL objects in the CURRENT context: GL 4.5 for kCel;
  /// a compatibility profile of any version >= 1.3 for kFixed, which draws the scene within its
  /// limits (no shadows, the uniform ambient colour instead of a gradient, view-plane billboards,
  /// no MSAA) with the puff mesh of `scene.fixed` (default: the atlas's first source mesh).
  /// Where frames go: an offscreen target (framebuffer objects) by default; with
  /// `contextFramebuffer` (kFixed only) the context's own framebuffer, which must then be at least
  /// the scene's size and have alpha: every call the fixed pipeline makes is then OpenGL 1.x.
  /// kFixed in a context without GL 4.5's framebuffer objects always draws there.
  /// Errors name the file that failed (atlas, ramp, gradient, mesh) and why.
  static Result<std::unique_ptr<SceneRenderer>> create(const Scene& scene, RenderPath path = RenderPath::kCel,
                                                       bool contextFramebuffer = false);
  /// RenderPath::kReference with chosen sampling. Needs GL 4.5; the atlas's sources must still be
  /// where the sidecar says, unchanged (their hash is checked), or be its generators' puffs. Errors
  /// name the file (scene, atlas, mesh) and why, or the option out of range.
  static Result<std::unique_ptr<SceneRenderer>> createReference(const Scene& scene,
                                                                const CelReferenceOptions& options = {});

  /// Whether the current context can run the programmable path: GL >= 4.5 and every cel program
  /// compiles and links. The error says why not (for an automatic fallback to kFixed).
  static Result<void> checkProgrammable();

  RenderPath path() const;
  ~SceneRenderer();

  /// Renders frame `frame` (>= 0) and reads it back: RGBA floats in [0,1], top row first,
  /// `scene.width` x `scene.height`. The same frame always gives the same pixels.
  Result<core::Image> renderFrame(int frame, FrameStats* stats = nullptr);

  /// Renders frame `frame` into the current draw framebuffer instead (for a window), which must have
  /// depth + stencil for the cel path. A scene with media draws its opaque pass into the renderer's
  /// own layers and composes colour only into the framebuffer (its depth and stencil are left as
  /// they were); the draw and read framebuffer bindings are as they were on return.
  /// `camera` (optional) replaces the scene's camera for this frame (a viewer's orbit camera).
  void drawFrame(int frame, const cel::Viewport& viewport, FrameStats* stats = nullptr,
                 const cel::Camera* camera = nullptr);

  /// Applies an edited scene (a viewer's panel). Style, camera, light, ambient colour, background,
  /// animation and the simulation's forces take effect at once (new forces: the next frame drawn is
  /// simulated from the start under them, so it equals that frame of the saved scene);
  /// anything else (atlas, ramp, gradient, objects, emitters, particles, size, samples, simulation
  /// settings other than forces) reloads what the scene names and restarts the simulation. On
  /// error nothing changes and the error names the file or field.
  Result<void> update(const Scene& scene);

  const Scene& scene() const;

  /// Benchmarks (issue 7): on the programmable cel path, draw every cel particle as the fill-rate
  /// floor instead, a bare alpha-tested quad of the nailboard's size (NailboardRenderer::drawBaseline:
  /// no shading, depth offset, outlines or shadows), and every media particle as its quad with a
  /// fragment program that computes nothing (media::Renderer::setFillRateFloor); the rest of the frame
  /// as usual: what any billboard method pays to touch those pixels. Ignored by the other paths. Off by
  /// default.
  void setFillRateFloor(bool on);

  /// What the media path drew in the most recent frame, read back (for tools and tests:
  /// render::measureMediaBudget, budget.h, hands it to puff::reference to compute the exact image
  /// over the same opaque layer). With motion blur, the last frame drawn is the frame itself.
  struct MediaFrameInputs {
    media::Frame frame;                      ///< the FULL-SIZE frame (camera, planes, light, ambient, time, size)
    std::vector<media::Particle> particles;  ///< listed + simulated, as handed to media::Renderer::draw
    /// The resolved opaque layer the media were composed over, width x height, row 0 at the BOTTOM:
    /// the colour as its RGBA8 texture holds it (k / 255) and the linear depth (R32F, >= 1: none).
    std::vector<glm::vec3> opaqueColor;
    std::vector<float> opaqueDepth;
  };
  /// Needs this renderer's context current. Errors: the scene has no media, the path is kFixed,
  /// or no frame with media has been drawn yet.
  Result<MediaFrameInputs> lastMediaFrame() const;

 private:
  SceneRenderer();
  static Result<std::unique_ptr<SceneRenderer>> createFixed(const Scene& scene, bool contextFramebuffer);
  static Result<std::unique_ptr<SceneRenderer>> createProgrammable(const Scene& scene,
                                                                   const CelReferenceOptions* reference);
  Result<void> createMedia();
  void drawSingle(int frame, const cel::Viewport& viewport, FrameStats* stats, const cel::Camera* camera);
  bool ensureLayers(const cel::Viewport& viewport);
  void drawMedia(int frame, const cel::Camera& camera, const cel::Viewport& viewport, GLuint target, FrameStats* stats);
  struct Impl;
  std::unique_ptr<Impl> impl_;
  struct History;  // motion blur's kept frames
  std::unique_ptr<History> history_;
};

}  // namespace puff::render
