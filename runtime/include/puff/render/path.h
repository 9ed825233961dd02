// A render path: one way of drawing a scene's frames. SceneRenderer (render.h) owns the target, the
// read-back, motion blur and the scene's evaluation, and hands each frame's inputs to its path:
// the cel path (nailboards, shadows, and the media pass for fire, smoke and dust) and the
// GL 1.x fixed path live in puff::render; puff::eval adds the cel reference through this interface.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <puff/cel/nailboards.h>
#include <puff/cel/types.h>
#include <puff/core/error.h>
#include <puff/media/types.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/scene.h>

namespace puff::media {
class Layers;
}

namespace puff::render {

/// The render paths a scene can be drawn with (what each is and can do: renderPathTable()).
enum class RenderPath {
  kCel,    ///< programmable GL 4.5: nailboards, outlines from the flange, shadow map or volumes (puff::cel)
  kFixed,  ///< GL 1.x fixed function (puff::fixedfunc, §4.4): per-frame puff texture, backing
           ///< billboards for outlines; one light, uniform ambient, no shadows, flat billboards
  /// The image the nailboards approximate: every particle as its actual puff mesh (puff::eval,
  /// eval/cel_reference.h). Measurement, not a path a game draws with.
  kReference,
};

/// Where a SceneRenderer's frames go.
enum class DrawTarget {
  kOffscreen,  ///< framebuffer objects of the scene's size (every path that has them)
  /// The context's own framebuffer, which must be at least the scene's size and have alpha: every
  /// call the fixed path makes is then OpenGL 1.x. kFixed only; kCel ignores it.
  kContextFramebuffer,
};

class SceneRenderer;

/// A render path and what it can do: one row of renderPathTable(), which every list, parser, menu
/// and warning of the libraries and tools reads.
struct RenderPathInfo {
  RenderPath path;
  std::string name;         ///< as a scene, --path and puffview's menu spell it
  std::string description;  ///< one line, for a tool's --help or a menu's tooltip
  /// Makes the path's renderer in the current context (SceneRenderer::create); null for the cel
  /// reference, which puff::eval makes (eval::createRenderer), being measurement a game never draws.
  Result<std::unique_ptr<SceneRenderer>> (*create)(const scene::Scene& scene, DrawTarget target);
  /// Whether the media's motion blur applies (the references model none: docs/media.md).
  bool motionBlur;
  /// One line for each part of `scene` this path leaves out or draws otherwise (empty: it draws
  /// all of it), for a tool to print and a viewer to show.
  std::vector<std::string> (*omissions)(const scene::Scene& scene);
};
/// Every render path, the default first.
const std::vector<RenderPathInfo>& renderPathTable();
/// The paths SceneRenderer::create draws with (the rows with a `create`), the default first.
std::vector<RenderPathInfo> renderPaths();
const RenderPathInfo& renderPathInfo(RenderPath path);
std::string_view toString(RenderPath path);  ///< its row's name
/// The path whose name is `name`, of every path in the table; nullopt for any other name.
std::optional<RenderPath> parseRenderPath(std::string_view name);
/// The table's names, joined by `separator` ("cel, fixed, reference").
std::string renderPathNames(std::string_view separator = ", ");

struct FrameStats {
  std::size_t particles = 0;  ///< drawn (listed + placed + simulated)
  std::size_t simulated = 0;  ///< of which from the simulator
  std::size_t bytesUploaded = 0;
  double simulateMs = 0.0;         ///< CPU time spent stepping the simulators for this frame
  std::size_t mediaParticles = 0;  ///< fire, smoke and dust particles drawn
  /// Pixels of the frame the media can change (media::coverage; the whole frame with
  /// SceneRenderer::setMediaOverWholeFrame): the media passes run over these, grown by what they read.
  std::size_t mediaCoveredPixels = 0;
};

/// What the media pass drew in its most recent frame, read back (for tools and tests: puff::eval
/// hands it to puff::reference to compute the exact image over the same opaque layer).
struct MediaFrameInputs {
  media::Frame frame;                      ///< the FULL-SIZE frame (camera, planes, light, ambient, time, size)
  std::vector<media::Particle> particles;  ///< listed + simulated, as handed to media::Renderer::draw
  /// The resolved opaque layer the media were composed over, width x height, row 0 at the BOTTOM:
  /// the colour as its RGBA16F texture holds it (scene-linear) and the linear depth (R32F, >= 1: none).
  std::vector<glm::vec3> opaqueColor;
  std::vector<float> opaqueDepth;
  /// The cartoon style only (else empty): the layer's accumulated opacity A at the output's size,
  /// as the cartoon passes read it (media::Layers::cartoonField), row 0 at the BOTTOM. Its iso-line
  /// A = threshold is where the fill ends and the ink begins.
  std::vector<float> cartoonOpacity;
};

/// How a map frame scales what it encodes (SceneRenderer::setOutput; cel::OutputScale).
struct MapRanges {
  float depth = 1.0f;   ///< kDepth: scene units either side of the camera target's distance, > 0
  float motion = 1.0f;  ///< kMotion: pixels either side of no motion, > 0
};

/// One frame for a path to draw into the current draw framebuffer.
struct PathFrame {
  const scene::Scene& scene;         ///< as it is now (style, light and other looks are read here)
  const scene::FrameInputs& inputs;  ///< camera, time and particles of this frame
  cel::Viewport viewport;            ///< where in the draw framebuffer
  FrameStats& stats;                 ///< the path adds what it drew (bytesUploaded, mediaParticles)
  /// A motion map's frame: each of inputs.particles where it is at the next frame (world xyz, size
  /// w); empty otherwise.
  std::span<const glm::vec4> next = {};
};

/// The offscreen target a path draws into.
struct TargetNeeds {
  int samples = 1;  ///< MSAA samples per pixel
  /// Draw into the context's own framebuffer instead (GL 1.x contexts), which must then be at least
  /// the scene's size and have alpha.
  bool contextFramebuffer = false;
  /// What the path made depends on the frame's size (the fixed path's puff texture): drawn into a
  /// viewport of another size, it is made again for that size first.
  bool sizedToFrame = false;
  /// The path writes DISPLAY values (the fixed path: GL 1.x has no float targets and blends what it
  /// is given): the target is 8-bit and its read-back is decoded to scene-linear. Otherwise the path
  /// writes scene-linear values into a half-float target (docs/colour.md).
  bool displayValues = false;
};

class Path {
 public:
  virtual ~Path() = default;
  virtual RenderPath kind() const = 0;
  virtual TargetNeeds targetNeeds() const = 0;
  /// The atlas's variation count (cel particles pick among them), or 0 when the path draws no cel
  /// particles (the scene names no atlas).
  virtual int variations() const = 0;
  /// Whether the evaluator should simulate the fire, smoke and dust (only paths that draw them).
  virtual bool drawsMedia() const { return false; }
  /// The path's reload rule: whether an edit from `current` to `next` changes what it loaded when
  /// it was made (files, meshes, programs' tables). Anything else it reads from the scene each frame.
  virtual bool needsRebuild(const scene::Scene& current, const scene::Scene& next) const = 0;
  /// Draws the frame. Errors: what the draw found wrong (a context without what the path needs).
  virtual Result<void> draw(const PathFrame& frame) = 0;

  /// Benchmarks: draw each particle as the fill-rate floor instead (see SceneRenderer).
  virtual void setFillRateFloor(bool) {}
  /// Tests and benchmarks: the media passes over the whole frame (see SceneRenderer).
  virtual void setMediaOverWholeFrame(bool) {}
  /// Tests and benchmarks: how the nailboards' lit pass shades (see SceneRenderer).
  virtual void setLitShading(cel::LitShading) {}
  /// Tests and benchmarks: the tumbling hull's occluders (see SceneRenderer).
  virtual void setHullOcclusion(cel::HullOcclusion) {}
  /// What the frames hold (see SceneRenderer::setOutput). A path that writes no maps accepts only
  /// kColour.
  virtual Result<void> setOutput(cel::FrameOutput output, const MapRanges& ranges) {
    (void)ranges;
    if (output == cel::FrameOutput::kColour) return {};
    return Error{"the " + std::string(toString(kind())) + " path writes no maps (" +
                 std::string(cel::toString(output)) + "): only the cel path does"};
  }
  /// The media layers drawn into for a viewport of this size (made on first use), or null when the
  /// path draws no media. Motion blur keeps its history there. Errors: the layers could not be made.
  virtual Result<media::Layers*> mediaLayers(const scene::Scene&, const cel::Viewport&) { return nullptr; }
  /// See SceneRenderer::lastMediaFrame.
  virtual Result<MediaFrameInputs> lastMediaFrame() const {
    return Error{"the scene has no media, or this path does not draw them"};
  }
};

}  // namespace puff::render
