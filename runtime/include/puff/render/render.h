// Renders scene frames into images or a window. A SceneRenderer owns an offscreen target (colour,
// linear depth + stencil, MSAA when asked) and its read-back, the scene's evaluation (particles,
// simulators, camera), motion blur's history, and one render path (path.h) that draws each frame.
// puffrender and puffview are thin shells around this.
#pragma once

#include <functional>
#include <memory>

#include <puff/cel/types.h>
#include <puff/core/error.h>
#include <puff/core/image.h>
#include <puff/render/path.h>
#include <puff/scene/geometry.h>
#include <puff/scene/scene.h>

namespace puff::render {

class SceneRenderer {
 public:
  /// Makes a path for a scene in the current context; called again when an edit needs it rebuilt.
  using PathFactory = std::function<Result<std::unique_ptr<Path>>(const scene::Scene&, const scene::SceneGeometry&)>;

  /// Loads the scene's resources and builds the GL objects in the CURRENT context: GL 4.5 for kCel;
  /// a compatibility profile of any version >= 1.3 for kFixed, which draws the scene within its
  /// limits (no shadows, the uniform ambient colour instead of a gradient, view-plane billboards,
  /// no MSAA) with the puff mesh of `scene.fixed` (default: the atlas's first source mesh).
  /// Where frames go: `target` (DrawTarget); kFixed in a context without GL 4.5's framebuffer
  /// objects always draws into the context's own framebuffer. kReference is made by puff::eval
  /// (eval::createRenderer), not here: renderPathTable() says which path is made where.
  /// Errors name the file that failed (atlas, ramp, gradient, mesh) and why.
  static Result<std::unique_ptr<SceneRenderer>> create(const scene::Scene& scene, RenderPath path = RenderPath::kCel,
                                                       DrawTarget target = DrawTarget::kOffscreen);
  /// A renderer around a path made by `factory` (another library's path, such as the cel reference).
  static Result<std::unique_ptr<SceneRenderer>> create(const scene::Scene& scene, PathFactory factory);

  /// Whether the current context can run the programmable path: GL >= 4.5. The error says why not
  /// (for an automatic fallback to kFixed). A program that does not build is not a reason to fall
  /// back: creating the kCel path fails with the compiler's error.
  static Result<void> checkProgrammable();

  RenderPath path() const;
  /// The target the path draws into: a window's framebuffer should match (the fixed path cannot
  /// draw into a multisampled one).
  TargetNeeds targetNeeds() const;
  ~SceneRenderer();

  /// Renders frame `frame` (>= 0) and reads it back: RGBA floats, top row first, `scene.width` x
  /// `scene.height`, RGB SCENE-LINEAR (not limited to [0, 1]; core::viewTransform with
  /// scene::viewTransformFor makes display values of it), alpha 1 for an opaque frame. The same
  /// frame always gives the same pixels. A transparent scene (scene.transparent) gives PREMULTIPLIED
  /// colour and alpha = the frame's coverage (puffs, outlines, objects, the media's opacity 1 - T,
  /// edges antialiased): it is drawn twice, over black and over white (every pass is affine in the
  /// background), and a = 1 - mean(white - black), colour = the black frame (core::unpremultiply and
  /// core::viewTransform(image, view, alpha) turn it into a file's values). It costs two frames.
  /// A scene with a plate (scene.plate) has it under the frame and alpha 1.
  Result<core::Image> renderFrame(int frame, FrameStats* stats = nullptr);

  /// Renders frame `frame` into the current draw framebuffer instead (for a window), which must have
  /// depth + stencil for the cel path. The path writes SCENE-LINEAR colour (a float framebuffer keeps
  /// it; view.h's ViewPass then shows it) unless targetNeeds().displayValues (the fixed path). A scene with media draws
  /// its opaque pass into the renderer's own layers and composes colour only into the framebuffer (its depth and
  /// stencil are left as they were); the draw and read framebuffer bindings are as they were on return. `camera`
  /// (optional) replaces the scene's camera for this frame (a viewer's orbit camera). A transparent
  /// scene's frame is drawn over nothing: colour and alpha 0 where nothing is (black on a screen). A path whose
  /// resources depend on the frame's size (TargetNeeds::sizedToFrame) is made again for a viewport of another size.
  /// Errors: what the path found wrong while drawing.
  Result<void> drawFrame(int frame, const cel::Viewport& viewport, FrameStats* stats = nullptr,
                         const cel::Camera* camera = nullptr);

  /// Applies an edited scene (a viewer's panel). Style, camera, light, ambient colour, background,
  /// animation and the simulation's forces take effect at once (new forces: the next frame drawn is
  /// simulated from the start under them, so it equals that frame of the saved scene). An edit of
  /// what the path loaded (atlas, ramp, gradient, objects, media materials, size, samples, ...)
  /// rebuilds the path; an edit of what places or simulates particles restarts the simulation. On
  /// error nothing changes and the error names the file or field.
  Result<void> update(const scene::Scene& scene);

  const scene::Scene& scene() const;

  /// Benchmarks: on the programmable cel path, draw every cel particle as the fill-rate floor (a bare
  /// alpha-tested quad of the nailboard's size) and every media particle as its quad with a fragment
  /// program that computes nothing; on the fixed path, every billboard as a GL 1.x bare alpha-tested
  /// quad (fixedfunc::FixedRenderer::drawFloorFrame); the rest of the frame as usual. Ignored by the
  /// references. Off by default. docs/bench/README.md says what it measures.
  void setFillRateFloor(bool on);
  /// Tests and benchmarks: run the media passes (the depth resolve, the layer's depth, the compose)
  /// over the whole frame, as if the media covered it, instead of over what they cover
  /// (media::LayersBase::setCoverage): the yardstick the coverage is checked and timed against.
  /// Off by default.
  void setMediaOverWholeFrame(bool on);
  /// Tests and benchmarks: on the programmable cel path, how the nailboards' lit pass shades
  /// (cel::LitShading: kAuto by default; kEveryLayer is the yardstick shading each pixel once is
  /// checked and timed against).
  void setLitShading(cel::LitShading shading);
  /// Tests and benchmarks: on the programmable cel path, whether the tumbling hull drops the
  /// fragments behind other puffs' cores before they march (cel::HullOcclusion: kAuto by default;
  /// kNone is the yardstick they are checked and timed against).
  void setHullOcclusion(cel::HullOcclusion occlusion);

  /// What renderFrame and drawFrame produce: the frame's colour (cel::FrameOutput::kColour, the
  /// default), or on the cel path a map of the same pixels for an engine that lights them itself
  /// (cel::FrameOutput: normals, depth about the camera's target with `ranges.depth` scene units
  /// either side, the ink's share, the motion to the next frame with `ranges.motion` pixels either
  /// side: each particle matched with itself in the next frame by its key, scene::FrameInputs::keys;
  /// one that is gone by then does not move). A map frame draws the puffs and objects as the colour
  /// frame does (the same coverage, depth test and edges) but no shadows, media, plate or motion
  /// blur; renderFrame reads it from a 32-bit float target, its values as the map encodes them (no
  /// view transform applies), over the background (transparent scenes: premultiplied, alpha the
  /// coverage). Errors: another path, or a range that is not positive and finite; nothing changes.
  Result<void> setOutput(cel::FrameOutput output, const MapRanges& ranges = {});
  cel::FrameOutput output() const;

  using MediaFrameInputs = render::MediaFrameInputs;
  /// What the media pass drew in the most recent frame, read back. With motion blur, the last frame
  /// drawn is the frame itself. Needs this renderer's context current. Errors: the scene has no
  /// media, the path does not draw them, or no frame with media has been drawn yet.
  Result<MediaFrameInputs> lastMediaFrame() const;

 private:
  SceneRenderer();
  void fitPathTo(const cel::Viewport& viewport);
  Result<core::Image> renderOpaque(int frame, FrameStats* stats);  // one frame, the target read back
  Result<void> drawSingle(int frame, const cel::Viewport& viewport, FrameStats* stats, const cel::Camera* camera);
  Result<void> drawBlurred(int frame, const cel::Viewport& viewport, FrameStats* stats, const cel::Camera* camera);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace puff::render
