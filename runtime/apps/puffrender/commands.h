// puffrender's commands, one file each, as run() hands them a checked scene: render.cpp draws the
// frames into their outputs, compare.cpp draws them by two paths side by side (--compare), and
// choose.cpp picks the cheapest model within an error (--max-error) before the frames are drawn.
#pragma once

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
};

/// Draws the plan's frames of `scene` (with --compare, by both paths; with --max-error, after
/// choosing the model) into their outputs. Returns the exit code, after saying why on failure.
int renderFrames(const Options& o, scene::Scene scene, const Plan& plan);

/// --flipbook: the plan's frames, each drawn with a transparent background, into the cells of one
/// sprite sheet (plan.pattern's single file), and beside it a JSON of its layout, frame rate and
/// alpha mode (docs/flipbooks.md). Returns the exit code.
int writeFlipbook(const Options& o, const scene::Scene& scene, const Plan& plan, render::SceneRenderer& renderer);

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
