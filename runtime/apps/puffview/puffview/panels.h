// The viewer's Dear ImGui panels: timeline and stats, camera, render path, style, light, ambient,
// background, simulation forces and emitters, save / save as, and the red error overlay. Every
// widget edits Viewer::scene() and applies it at once (Viewer::applyEdit).
#pragma once

#include <string>

namespace puff::view {

class Viewer;

struct PanelState {
  char saveAs[1024] = {};  ///< the "Save as" path field
  bool saveAsInitialized = false;
};

/// Draws the panels inside the current ImGui frame.
void drawPanels(Viewer& viewer, PanelState& state);
/// Draws the file/edit errors (red) at the bottom-left of the window, if there are any.
void drawErrorOverlay(const Viewer& viewer);

}  // namespace puff::view
