// The viewer's Dear ImGui panels: undo/redo, timeline and stats, camera, render path, style, the atlas,
// the ramp and gradient editors, light, ambient, background, simulation forces and emitters, the
// media (method, resolution, view transform, materials, emitters, lights), save / save as, and the
// red error overlay. Every widget edits Viewer::scene() and applies it at once (Viewer::applyEdit),
// one undo step per edit.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <puffview/ramp_edit.h>

namespace puff::view {

class Viewer;

struct PanelState {
  char saveAs[1024] = {};  ///< the "Save as" path field
  bool saveAsInitialized = false;
  // The ramp and gradient editors: what they edit, and the file they read it from (read again when
  // the scene names another, after an undo or a reload).
  RampBands ramp;
  std::filesystem::path rampFrom = "?";
  VerticalGradient gradient;
  std::filesystem::path gradientFrom = "?";
  std::string rampError;
  // The atlases found under the art directory, listed when the combo opens.
  std::vector<std::filesystem::path> atlases;
  std::string bodiesError;  ///< why the last rigid-body edit could not be simulated
};

/// Draws the panels inside the current ImGui frame.
void drawPanels(Viewer& viewer, PanelState& state);
/// Draws the file/edit errors (red) at the bottom-left of the window, if there are any.
void drawErrorOverlay(const Viewer& viewer);

}  // namespace puff::view
