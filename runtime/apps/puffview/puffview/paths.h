// The render paths the viewer can switch between. Only the paths that exist are listed: today the
// cel path and the GL 1.x fixed-function path (both puff::render::SceneRenderer). The media path
// adds an entry here (and a class implementing ScenePath) when it is written; the viewer's --path
// option and its combo box list whatever this table holds.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <puff/render/render.h>

namespace puff::view {

struct RenderPathInfo {
  std::string name;         ///< "cel", "fixed"
  std::string description;  ///< one line for --help and the combo's tooltip
};

/// Every path built into this binary, the default first.
const std::vector<RenderPathInfo>& renderPaths();

/// One render path drawing a scene into the current framebuffer.
class ScenePath {
 public:
  virtual ~ScenePath() = default;
  /// Draws frame `frame` into the current draw framebuffer (depth + stencil), `camera` replacing
  /// the scene's camera when given.
  virtual void draw(int frame, const cel::Viewport& viewport, render::FrameStats* stats, const cel::Camera* camera) = 0;
  /// Applies an edited scene; on error nothing changes.
  virtual Result<void> update(const render::Scene& scene) = 0;
  /// Whether the path can draw into a multisampled framebuffer. The fixed path cannot (it copies
  /// part of the framebuffer into a texture): the viewer gives it a single-sample one.
  virtual bool multisample() const { return true; }
};

/// Builds path `name` for `scene` in the current GL context (GL 4.5 for "cel", a compatibility
/// profile for "fixed"). Errors: unknown name (listing the
/// available ones), or whatever loading the scene's resources or building the programs reported.
Result<std::unique_ptr<ScenePath>> createPath(const std::string& name, const render::Scene& scene);

}  // namespace puff::view
