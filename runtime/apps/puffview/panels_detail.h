// Private to puffview_lib: what the panel files share: the edit tracker, the error colour, the
// direction widget, and the topics' panels that drawPanels (panels.cpp) lays out: panels_look.cpp
// (style, atlas, ramp, light, ambient gradient), panels_sim.cpp (forces, emitters, placed particles,
// rigid bodies) and panels_media.cpp (the media).
#pragma once

#include <imgui.h>

#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>
#include <glm/vec3.hpp>

#include <puff/scene/scene.h>
#include <puff/sim/simulator.h>
#include <puffview/panels.h>

namespace puff::view::detail {

inline const ImVec4 kRed(1.0f, 0.35f, 0.3f, 1.0f);

// Each widget returns whether it changed something; `edited` collects that for one applyEdit.
struct Edits {
  bool any = false;
  bool operator()(bool changed) {
    any = any || changed;
    return changed;
  }
};

inline bool direction(const char* label, glm::vec3& v) {
  if (!ImGui::DragFloat3(label, glm::value_ptr(v), 0.01f, -1.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp))
    return false;
  if (v == glm::vec3(0.0f)) v = glm::vec3(0.0f, 1.0f, 0.0f);  // keep it a direction
  return true;
}

// Which curves over life an emitter's particles take (the scene refuses the others).
enum class CurveSet {
  kCel,        ///< placed cel puffs: size, colour
  kCelSim,     ///< simulated cel puffs: size, density, colour
  kMedia,      ///< media that do not emit: size, density, colour
  kMediaFire,  ///< media that emit (or turn into a material that does): and temperature
};

// Style, atlas, ramp, light and ambient (panels_look.cpp).
void stylePanel(scene::Scene& s, Edits& edit);
void lightPanel(scene::Scene& s, Edits& edit);
void atlasPanel(Viewer& v, PanelState& state, Edits& edit);
void rampPanel(Viewer& v, PanelState& state);
void gradientPanel(Viewer& v, PanelState& state);

// The simulation (panels_sim.cpp).
void forcesPanel(sim::Forces& f, Edits& edit);
void simEmittersPanel(std::vector<sim::Emitter>& emitters, Edits& edit, CurveSet curves = CurveSet::kCelSim);
void sceneEmittersPanel(std::vector<scene::EmitterSpec>& emitters, Edits& edit);
void bodiesPanel(scene::Scene& s, Edits& edit, std::string& error);

// The media (panels_media.cpp).
void mediaPanel(Viewer& v, Edits& edit);

}  // namespace puff::view::detail
