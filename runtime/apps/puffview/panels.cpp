#include <puffview/panels.h>

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include <puff/render/path.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>
#include <puffview/viewer.h>

namespace puff::view {

namespace {

const ImVec4 kRed(1.0f, 0.35f, 0.3f, 1.0f);

// Each widget returns whether it changed something; `edited` collects that for one applyEdit.
struct Edits {
  bool any = false;
  bool operator()(bool changed) {
    any = any || changed;
    return changed;
  }
};

bool direction(const char* label, glm::vec3& v) {
  if (!ImGui::DragFloat3(label, glm::value_ptr(v), 0.01f, -1.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp))
    return false;
  if (v == glm::vec3(0.0f)) v = glm::vec3(0.0f, 1.0f, 0.0f);  // keep it a direction
  return true;
}

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
  const std::vector<render::RenderPathInfo>& paths = render::renderPaths();
  if (ImGui::BeginCombo("Render path", v.pathName().c_str())) {
    for (const render::RenderPathInfo& p : paths) {
      if (ImGui::Selectable(p.name.c_str(), p.name == v.pathName()) && p.name != v.pathName()) {
        if (auto r = v.setPath(p.name); !r) std::fprintf(stderr, "puffview: error: %s\n", r.error().message.c_str());
      }
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", p.description.c_str());
    }
    ImGui::EndCombo();
  }
}

void stylePanel(scene::Scene& s, Edits& edit) {
  const std::vector<std::string> presets = scene::stylePresetNames();
  const std::string current = s.stylePreset.empty() ? "(none)" : s.stylePreset;
  if (ImGui::BeginCombo("Preset", current.c_str())) {
    for (const std::string& name : presets) {
      if (ImGui::Selectable(name.c_str(), name == s.stylePreset)) {
        if (auto style = scene::stylePreset(name)) {
          s.style = *style;
          s.stylePreset = name;
          edit(true);
        }
      }
    }
    ImGui::EndCombo();
  }
  cel::Style& st = s.style;
  edit(ImGui::Checkbox("Outlines", &st.outlines));
  ImGui::SameLine();
  edit(ImGui::Checkbox("Shading", &st.shading));
  ImGui::SameLine();
  edit(ImGui::Checkbox("Shadows", &st.shadows));
  edit(ImGui::SliderFloat("Outline width", &st.outlineWidth, 0.0f, 10.0f, "%.2f px", ImGuiSliderFlags_AlwaysClamp));
  edit(ImGui::ColorEdit3("Outline colour", glm::value_ptr(st.outlineColor)));
  const char* alignments[] = {"view-plane", "viewpoint", "axial"};
  int a = static_cast<int>(st.alignment);
  if (edit(ImGui::Combo("Alignment", &a, alignments, 3))) st.alignment = static_cast<cel::Alignment>(a);
  edit(ImGui::SliderFloat("Shadow bias", &st.shadowBias, 0.0f, 1.0f, "%.3f", ImGuiSliderFlags_AlwaysClamp));
  edit(ImGui::DragFloat("Shadow length", &st.shadowLength, 0.1f, 0.01f, 1000.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
  st.shadowLength = std::max(st.shadowLength, 0.01f);
  const char* methods[] = {"volumes", "map"};
  int m = static_cast<int>(st.shadowMethod);
  if (edit(ImGui::Combo("Shadow method", &m, methods, 2))) st.shadowMethod = static_cast<cel::ShadowMethod>(m);
  if (st.shadowMethod == cel::ShadowMethod::kMap) {
    edit(ImGui::SliderFloat("Shadow map scale", &st.shadowMapScale, 0.125f, 4.0f, "%.3f",
                            ImGuiSliderFlags_AlwaysClamp | ImGuiSliderFlags_Logarithmic));
  }
  const char* tumbles[] = {"hull", "blend"};
  int t = static_cast<int>(st.tumble);
  if (edit(ImGui::Combo("Tumbling puffs", &t, tumbles, 2))) st.tumble = static_cast<cel::TumbleMethod>(t);
}

void lightPanel(scene::Scene& s, Edits& edit) {
  edit(direction("Light direction", s.light.direction));
  edit(ImGui::ColorEdit3("Light colour", glm::value_ptr(s.light.color), ImGuiColorEditFlags_Float));
  edit(ImGui::ColorEdit3("Ambient colour", glm::value_ptr(s.ambientColor), ImGuiColorEditFlags_Float));
  if (!s.ambientGradient.empty()) ImGui::TextDisabled("ambient gradient: %s", s.ambientGradient.filename().c_str());
  edit(ImGui::ColorEdit3("Background", glm::value_ptr(s.background), ImGuiColorEditFlags_Float));
}

void forcesPanel(sim::Forces& f, Edits& edit) {
  edit(ImGui::DragFloat3("Gravity", glm::value_ptr(f.gravity), 0.01f, -100.0f, 100.0f, "%.2f",
                         ImGuiSliderFlags_AlwaysClamp));
  edit(ImGui::SliderFloat("Buoyancy", &f.buoyancy, -10.0f, 20.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
  edit(ImGui::SliderFloat("Drag", &f.drag, 0.0f, 20.0f, "%.2f /s", ImGuiSliderFlags_AlwaysClamp));
  edit(ImGui::DragFloat3("Wind", glm::value_ptr(f.wind), 0.01f, -50.0f, 50.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
  if (ImGui::TreeNode("Turbulence")) {
    edit(ImGui::SliderFloat("Strength", &f.turbulence.strength, 0.0f, 10.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
    edit(ImGui::SliderFloat("Scale", &f.turbulence.scale, 0.05f, 20.0f, "%.2f",
                            ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp));
    edit(ImGui::SliderFloat("Speed", &f.turbulence.speed, 0.0f, 5.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
    ImGui::TreePop();
  }
  for (std::size_t i = 0; i < f.vortices.size(); ++i) {
    sim::Vortex& vx = f.vortices[i];
    ImGui::PushID(static_cast<int>(i));
    if (ImGui::TreeNode("vortex", "Vortex %zu", i)) {
      edit(ImGui::SliderFloat("Strength", &vx.strength, -20.0f, 20.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Radius", &vx.radius, 0.01f, 10.0f, "%.2f",
                              ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Falloff", &vx.falloff, 0.0f, 20.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::DragFloat3("Position", glm::value_ptr(vx.position), 0.01f, -1000.0f, 1000.0f, "%.2f",
                             ImGuiSliderFlags_AlwaysClamp));
      edit(direction("Axis", vx.axis));
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  for (std::size_t i = 0; i < f.windVolumes.size(); ++i) {
    sim::WindVolume& w = f.windVolumes[i];
    ImGui::PushID(1000 + static_cast<int>(i));
    if (ImGui::TreeNode("wind", "Wind volume %zu", i)) {
      edit(ImGui::DragFloat3("Velocity", glm::value_ptr(w.velocity), 0.01f, -50.0f, 50.0f, "%.2f",
                             ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::DragFloat3("Center", glm::value_ptr(w.center), 0.01f, -1000.0f, 1000.0f, "%.2f",
                             ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::DragFloat3("Half extent", glm::value_ptr(w.halfExtent), 0.01f, 0.0f, 1000.0f, "%.2f",
                             ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Feather", &w.feather, 0.0f, 10.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
}

void simEmittersPanel(std::vector<sim::Emitter>& emitters, Edits& edit) {
  for (std::size_t i = 0; i < emitters.size(); ++i) {
    sim::Emitter& e = emitters[i];
    ImGui::PushID(2000 + static_cast<int>(i));
    if (ImGui::TreeNode("emitter", "Emitter %zu", i)) {
      edit(ImGui::SliderFloat("Rate", &e.rate, 0.0f, 1000.0f, "%.1f /s",
                              ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::DragFloat3("Velocity", glm::value_ptr(e.velocity), 0.01f, -100.0f, 100.0f, "%.2f",
                             ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Spread", &e.spreadDegrees, 0.0f, 180.0f, "%.1f deg", ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Speed spread", &e.speedSpread, 0.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Lifetime", &e.lifetime, 0.05f, 30.0f, "%.2f s",
                              ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Lifetime spread", &e.lifetimeSpread, 0.0f, 0.99f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::DragFloatRange2("Size", &e.sizeMin, &e.sizeMax, 0.01f, 0.0f, 100.0f, "min %.2f", "max %.2f",
                                  ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Density", &e.density, 0.01f, 10.0f, "%.2f",
                              ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Radius", &e.radius, 0.0f, 10.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::DragFloat3("Position", glm::value_ptr(e.position), 0.01f, -1000.0f, 1000.0f, "%.2f",
                             ImGuiSliderFlags_AlwaysClamp));
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
}

// The force-free emitters (placed particles) a scene may list besides the simulator's.
void sceneEmittersPanel(std::vector<scene::EmitterSpec>& emitters, Edits& edit) {
  for (std::size_t i = 0; i < emitters.size(); ++i) {
    scene::EmitterSpec& e = emitters[i];
    ImGui::PushID(3000 + static_cast<int>(i));
    if (ImGui::TreeNode("placed", "Placed particles %zu", i)) {
      edit(ImGui::SliderInt("Count", &e.count, 0, 50000, "%d",
                            ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp));
      int seed = static_cast<int>(e.seed);
      if (edit(ImGui::DragInt("Seed", &seed, 1.0f, 0, 1 << 30))) e.seed = static_cast<unsigned>(seed);
      edit(ImGui::DragFloat3("Center", glm::value_ptr(e.center), 0.01f, -1000.0f, 1000.0f, "%.2f",
                             ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Radius", &e.radius, 0.0f, 20.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::DragFloatRange2("Size", &e.sizeMin, &e.sizeMax, 0.01f, 0.0f, 100.0f, "min %.2f", "max %.2f",
                                  ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Size falloff", &e.sizeFalloff, 0.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::DragFloat3("Velocity", glm::value_ptr(e.velocity), 0.01f, -100.0f, 100.0f, "%.2f",
                             ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Lifetime", &e.lifetime, 0.0f, 30.0f, "%.2f s", ImGuiSliderFlags_AlwaysClamp));
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
}

void savePanel(Viewer& v, PanelState& state) {
  if (!state.saveAsInitialized) {
    std::snprintf(state.saveAs, sizeof state.saveAs, "%s", v.sceneFile().c_str());
    state.saveAsInitialized = true;
  }
  if (ImGui::Button("Save")) {
    if (auto r = v.save(); !r) std::fprintf(stderr, "puffview: error: %s\n", r.error().message.c_str());
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Write the scene to %s", v.sceneFile().c_str());
  ImGui::SameLine();
  if (ImGui::Button("Save as") && state.saveAs[0] != '\0') {
    if (auto r = v.save(state.saveAs); !r) std::fprintf(stderr, "puffview: error: %s\n", r.error().message.c_str());
  }
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
  ImGui::TextUnformatted(v.sceneFile().c_str());
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
  if (ImGui::CollapsingHeader("Light, ambient, background")) lightPanel(s, edit);
  if (ImGui::CollapsingHeader("Simulation")) {
    if (s.simulation) {
      forcesPanel(s.simulation->forces, edit);
      simEmittersPanel(s.simulation->emitters, edit);
    } else {
      ImGui::TextDisabled("this scene has no \"simulation\"");
    }
  }
  if (!s.emitters.empty() && ImGui::CollapsingHeader("Placed particles")) sceneEmittersPanel(s.emitters, edit);
  // One undo step per edit: it begins with its first change and ends when no widget is held.
  if (edit.any) {
    v.beginEdit();
    (void)v.applyEdit();
  }
  if (!ImGui::IsAnyItemActive()) v.endEdit();
  if (!v.editError().empty()) ImGui::TextColored(kRed, "%s", v.editError().c_str());
  ImGui::Separator();
  savePanel(v, state);
  if (!v.status().empty()) ImGui::TextDisabled("%s", v.status().c_str());
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
