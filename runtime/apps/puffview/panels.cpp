// The panel's layout (undo, timeline, camera, render path, the topics' sections, save) and the error overlay.
#include <puffview/panels.h>

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <puff/render/path.h>
#include <puff/scene/evaluate.h>
#include <puffview/viewer.h>

#include "panels_detail.h"

namespace puff::view {

using namespace detail;  // the shared widgets and the topics' panels (panels_detail.h)

namespace {

void timelinePanel(Viewer& v) {
  const render::FrameStats& s = v.stats();
  ImGui::Text("%.1f ms/frame (%.0f fps)   sim %.2f ms", v.frameMs(), v.frameMs() > 0 ? 1000.0 / v.frameMs() : 0.0,
              s.simulateMs);
  ImGui::Text("particles %zu (simulated %zu)", s.particles, s.simulated);
  if (ImGui::Button(v.playing() ? "Pause" : "Play")) v.setPlaying(!v.playing());
  ImGui::SameLine();
  if (ImGui::Button("Step")) v.step();
  ImGui::SameLine();
  if (ImGui::Button("Restart")) v.restart();
  ImGui::SameLine();
  ImGui::Checkbox("Loop", &v.loop);
  int frame = v.frame();
  const int last = std::max(0, v.scene().animation.frames - 1);
  if (ImGui::SliderInt("Frame", &frame, 0, std::max(last, frame))) v.setFrame(frame);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Space play/pause, . or Right step, R or Home restart");
}

void cameraPanel(Viewer& v, Edits& edit) {
  CameraController& c = v.cameraController();
  int mode = c.mode() == CameraController::Mode::kOrbit ? 0 : 1;
  if (ImGui::RadioButton("Orbit", &mode, 0)) c.setMode(CameraController::Mode::kOrbit);
  ImGui::SameLine();
  if (ImGui::RadioButton("Fly (F)", &mode, 1)) {
    if (!v.cameraOverridden()) {
      c.reset(scene::cameraAt(v.scene(), v.frame()));
      v.setCameraOverridden(true);
    }
    c.setMode(CameraController::Mode::kFly);
  }
  ImGui::SameLine();
  if (ImGui::Button("Reset (C)")) v.resetCamera();
  ImGui::SameLine();
  if (ImGui::Button("Use as scene camera")) v.cameraToScene();
  ImGui::TextDisabled(v.cameraOverridden() ? "viewer camera" : "scene camera");
  cel::Camera& cam = v.scene().camera;
  edit(ImGui::SliderFloat("Field of view", &cam.fovYDegrees, 0.0f, 120.0f, "%.1f deg", ImGuiSliderFlags_AlwaysClamp));
  if (cam.fovYDegrees == 0.0f)
    edit(ImGui::DragFloat("Ortho height", &cam.orthoHeight, 0.05f, 0.01f, 1e4f, "%.3f", ImGuiSliderFlags_AlwaysClamp));
  edit(ImGui::DragFloat("Orbit deg/s", &v.scene().animation.orbitDegreesPerSecond, 0.5f, -360.0f, 360.0f, "%.3f",
                        ImGuiSliderFlags_AlwaysClamp));
}

void pathPanel(Viewer& v) {
  const std::vector<render::RenderPathInfo> paths = render::renderPaths();
  if (ImGui::BeginCombo("Render path", v.pathName().c_str())) {
    for (const render::RenderPathInfo& p : paths) {
      if (ImGui::Selectable(p.name.c_str(), p.name == v.pathName()) && p.name != v.pathName()) {
        if (auto r = v.setPath(p.name); !r) std::fprintf(stderr, "puffview: error: %s\n", r.error().message.c_str());
      }
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", p.description.c_str());
    }
    ImGui::EndCombo();
  }
  // What this path leaves out of the scene, as puffrender says it on stderr.
  if (const std::optional<render::RenderPath> path = render::parseRenderPath(v.pathName())) {
    for (const std::string& line : render::renderPathInfo(*path).omissions(v.scene())) {
      ImGui::TextWrapped("%s", line.c_str());
    }
  }
}

void savePanel(Viewer& v, PanelState& state) {
  if (!state.saveAsInitialized) {
    std::snprintf(state.saveAs, sizeof state.saveAs, "%s", v.sceneFile().c_str());
    state.saveAsInitialized = true;
  }
  if (ImGui::Button("Save")) (void)v.save();  // a failure is the status line (and stderr)
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Write the scene to %s", v.sceneFile().c_str());
  ImGui::SameLine();
  if (ImGui::Button("Save as") && state.saveAs[0] != '\0') (void)v.save(state.saveAs);
  ImGui::SameLine();
  ImGui::InputText("##saveas", state.saveAs, sizeof state.saveAs);
}

}  // namespace

void drawPanels(Viewer& v, PanelState& state) {
  // Docked on the window's right, beside the image (Viewer::imageViewport), never over it.
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(display.x - static_cast<float>(kPanelWidth), 0.0f), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(static_cast<float>(kPanelWidth), display.y), ImGuiCond_Always);
  if (!ImGui::Begin("puffview", nullptr,
                    ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                        ImGuiWindowFlags_NoTitleBar)) {
    ImGui::End();
    return;
  }
  ImGui::PushItemWidth(ImGui::GetWindowWidth() * 0.55f);  // room for the labels on the right
  ImGui::TextUnformatted(v.unsaved() ? (v.sceneFile().string() + " (unsaved)").c_str() : v.sceneFile().c_str());
  // The status line (saved, not saved and why, kept edits...) where it is always in view, wrapped in
  // a box of fixed height, so a message never moves the controls under it (a longer one scrolls).
  ImGui::BeginChild("status", ImVec2(0.0f, 2.0f * ImGui::GetTextLineHeightWithSpacing()), false);
  ImGui::TextWrapped("%s", v.status().c_str());
  ImGui::EndChild();
  ImGui::BeginDisabled(!v.canUndo());
  if (ImGui::Button("Undo")) v.undo();
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("Ctrl+Z");
  ImGui::SameLine();
  ImGui::BeginDisabled(!v.canRedo());
  if (ImGui::Button("Redo")) v.redo();
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("Ctrl+Y or Ctrl+Shift+Z");
  timelinePanel(v);
  Edits edit;
  scene::Scene& s = v.scene();
  if (ImGui::CollapsingHeader("Camera")) cameraPanel(v, edit);
  pathPanel(v);
  if (ImGui::CollapsingHeader("Style", ImGuiTreeNodeFlags_DefaultOpen)) stylePanel(s, edit);
  if (ImGui::CollapsingHeader("Atlas")) atlasPanel(v, state, edit);
  if (ImGui::CollapsingHeader("Ramp (q)")) rampPanel(v, state);
  if (ImGui::CollapsingHeader("Light, ambient, background")) {
    lightPanel(s, edit);
    gradientPanel(v, state);
  }
  if (ImGui::CollapsingHeader("Fire, smoke and dust (media)")) mediaPanel(v, edit);
  if (ImGui::CollapsingHeader("Simulation")) {
    if (s.simulation) {
      forcesPanel(s.simulation->forces, edit);
      simEmittersPanel(s.simulation->emitters, edit);
    } else {
      ImGui::TextDisabled("this scene has no \"simulation\"");
    }
  }
  if (!s.emitters.empty() && ImGui::CollapsingHeader("Placed particles")) sceneEmittersPanel(s.emitters, edit);
  const bool bodies =
      std::any_of(s.objects.begin(), s.objects.end(), [](const auto& o) { return o.dynamic.has_value(); });
  if (bodies && ImGui::CollapsingHeader("Rigid bodies")) bodiesPanel(s, edit, state.bodiesError);
  // One undo step per edit: it begins with its first change and ends when no widget is held.
  if (edit.any) {
    v.beginEdit();
    (void)v.applyEdit();
  }
  if (!ImGui::IsAnyItemActive()) v.endEdit();
  if (!v.editError().empty()) ImGui::TextColored(kRed, "%s", v.editError().c_str());
  ImGui::Separator();
  savePanel(v, state);
  ImGui::TextDisabled("H panels  P/F12 screenshot  F orbit/fly  C reset camera  Ctrl+Z/Y undo/redo");
  ImGui::PopItemWidth();
  ImGui::End();
}

void drawErrorOverlay(const Viewer& v) {
  if (v.fileError().empty() && v.editError().empty()) return;
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(8, display.y - 8), ImGuiCond_Always, ImVec2(0.0f, 1.0f));
  ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(display.x * 0.6f, display.y * 0.5f));
  ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(0.25f, 0.0f, 0.0f, 0.9f));
  ImGui::Begin("error", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing |
                   ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs);
  ImGui::PushTextWrapPos(display.x * 0.6f - 16.0f);
  if (!v.fileError().empty()) ImGui::TextColored(kRed, "%s", v.fileError().c_str());
  if (!v.editError().empty()) ImGui::TextColored(kRed, "%s", v.editError().c_str());
  ImGui::TextDisabled("showing the last good state");
  ImGui::PopTextWrapPos();
  ImGui::End();
  ImGui::PopStyleColor();
}

}  // namespace puff::view
