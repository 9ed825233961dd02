// puffrender's commands, one file each, as run() hands them a checked scene: render.cpp draws the
// frames into their outputs, compare.cpp draws them by two paths side by side (--compare), and
// choose.cpp picks the cheapest model within an error (--max-error) before the frames are drawn.
#pragma once

#include <memory>
#include <string>

#include <puff/core/image.h>
#include <puff/render/flipbook.h>
#include <puff/render/render.h>
#include <puff/scene/scene.h>

#include "options.h"

namespace puff::app {

/// Everything the commands need once the scene is known: which frames go where, in which format.
struct Plan {
  OutputPattern pattern;
  int first = 0, last = 0;
  bool exr = false;
  int flipColumns = 0, flipRows = 0;  ///< --flipbook: the sheet's grid; 0: frames go to their own files
  int flipLast = 0;         ///< --flipbook: the last frame it may draw (past `last` when --skip-empty skips frames)
  bool writeFrames = true;  ///< false: no -o, only --contact-sheet and/or --preview
};

/// Draws the plan's frames of `scene` (with --compare, by both paths; with --max-error, after
/// choosing the model) into their outputs. Returns the exit code, after saying why on failure.
int renderFrames(const Options& o, scene::Scene scene, const Plan& plan);

/// --flipbook: the plan's frames, each drawn with a transparent background, into the cells of one
/// sprite sheet (plan.pattern's single file), and beside it a JSON of its layout, frame rate and
/// alpha mode (docs/flipbooks.md). Returns the exit code.
int writeFlipbook(const Options& o, const scene::Scene& scene, const Plan& plan, render::SceneRenderer& renderer);
/// Whether a sheet of `layout`'s size may be written (core::imageLimitProblem); `what` starts the error.
Result<void> checkSheetSize(const render::SheetLayout& layout, const std::string& what);
/// Before anything is drawn: the layout JSON beside the sheet may be written (it is not the scene,
/// and any file already there is this sheet's own layout).
Result<void> checkFlipbookLayoutTarget(const Options& o, const Plan& plan);

/// --contact-sheet and --preview: the frames of a run as a grid with their numbers, and as an
/// animated GIF or MP4 (sequence.cpp). open() before the first frame, add() each frame as rendered
/// (scene-linear), finish() after the last: it writes them and returns what to say on stdout.
class SequenceExtras {
 public:
  SequenceExtras(const Options& o, const scene::Scene& scene, const Plan& plan);
  ~SequenceExtras();
  bool wanted() const;
  Result<void> open();
  Result<void> add(int frame, const core::Image& linear);
  Result<std::string> finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Which animated previews this machine can write, for --help and messages.
std::string previewSupport();
/// --preview's name: .gif (when OpenImageIO has a GIF writer) or .mp4 (when ffmpeg is on PATH).
Result<void> checkPreviewTarget(const std::string& preview);

/// --compare A,B: every frame by both paths, and without particles for the masks; OUT gets the side
/// by side image, stdout a line per frame and a summary. Needs a compatibility context current.
int compareFrames(const Options& o, const scene::Scene& scene, const Plan& plan);

/// Whether `scene` has particles the cel path draws as nailboards (an atlas, and particles or
/// emitters placed or simulated).
bool hasCelParticles(const scene::Scene& scene);

/// --max-error: measures the cel particles' model (particle share, then atlas level) and the media
/// layer's resolution against their references and sets the cheapest within the error on `scene`
/// (render/budget.h). Needs the programmable path's context current. Returns 0, or the exit code of
/// a failure (after saying why).
int chooseModel(const Options& o, scene::Scene& scene, const Plan& plan);

}  // namespace puff::app
