#include <puffview/panels.h>

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include <puff/cel/frame.h>
#include <puff/core/files.h>
#include <puff/render/path.h>
#include <puff/scene/bodies.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>
#include <puffview/viewer.h>

namespace puff::view {

namespace fs = std::filesystem;

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

// What every curve editor shares: "Add curve" when there is none (`none` says what that means;
// both keys of a new curve are `start`), the curve drawn by `plot`, linear or smooth, each key's age
// (kept between its neighbours') and its value (`editValue`, returning whether it changed),
// removing and adding keys, and back to the default. Returns whether the curve changed.
template <typename Curve, typename Value, typename Plot, typename EditValue>
bool curveEditor(const char* label, Curve& c, const char* none, Value start, Plot plot, EditValue editValue,
                 const char* keyLabel) {
  bool changed = false;
  ImGui::PushID(label);
  if (c.empty()) {
    ImGui::TextDisabled("%s: %s", label, none);
    ImGui::SameLine();
    if (ImGui::SmallButton("Add curve")) {
      c.ages = {0.0f, 1.0f};
      c.values = {start, start};
      changed = true;
    }
    ImGui::PopID();
    return changed;
  }
  plot();
  int interp = c.interp == sim::LifeCurve::Interp::kSmooth ? 1 : 0;
  const char* interps[] = {"linear", "smooth"};
  if (ImGui::Combo("Between keys", &interp, interps, 2)) {
    c.interp = interp == 1 ? sim::LifeCurve::Interp::kSmooth : sim::LifeCurve::Interp::kLinear;
    changed = true;
  }
  int remove = -1;
  for (std::size_t k = 0; k < c.ages.size(); ++k) {
    ImGui::PushID(static_cast<int>(k));
    // Age and value edited apart: an age moves in steps of 0.005 whatever the value's range.
    float age = c.ages[k];
    ImGui::SetNextItemWidth(0.3f * ImGui::CalcItemWidth());
    if (ImGui::DragFloat("##age", &age, 0.005f, 0.0f, 1.0f, "%.3f", ImGuiSliderFlags_AlwaysClamp)) {
      // Ages stay between their neighbours' (strictly increasing), in [0, 1].
      const float lo = k > 0 ? c.ages[k - 1] + 1e-3f : 0.0f, hi = k + 1 < c.ages.size() ? c.ages[k + 1] - 1e-3f : 1.0f;
      c.ages[k] = std::clamp(age, lo, std::max(lo, hi));
      changed = true;
    }
    ImGui::SameLine();
    changed |= editValue(c.values[k]);
    ImGui::SameLine();
    if (ImGui::Button("x")) remove = static_cast<int>(k);
    ImGui::SameLine();
    ImGui::TextDisabled(k == 0 ? keyLabel : "");
    ImGui::PopID();
  }
  if (remove >= 0) {
    c.ages.erase(c.ages.begin() + remove);
    c.values.erase(c.values.begin() + remove);
    changed = true;
  }
  if (ImGui::SmallButton("Add key") && c.ages.size() < 64) {
    // Halfway along the widest gap (or at the end).
    std::size_t at = c.ages.size();
    float gap = c.ages.empty() ? 1.0f : 1.0f - c.ages.back(), age = c.ages.empty() ? 0.0f : 1.0f;
    for (std::size_t k = 0; k + 1 < c.ages.size(); ++k) {
      if (c.ages[k + 1] - c.ages[k] > gap) gap = c.ages[k + 1] - c.ages[k], at = k + 1, age = c.ages[k] + 0.5f * gap;
    }
    if (at == c.ages.size() && !(gap > 1e-3f)) age = -1.0f;  // no room
    if (age >= 0.0f) {
      const Value value = c.at(age);
      c.ages.insert(c.ages.begin() + static_cast<long>(at), age);
      c.values.insert(c.values.begin() + static_cast<long>(at), value);
      changed = true;
    }
  }
  ImGui::SameLine();
  if (ImGui::SmallButton("Default")) {
    c = {};
    changed = true;
  }
  ImGui::PopID();
  return changed;
}

// A number over life, plotted. `minValue`..`maxValue`: the values the scene takes; `start`: both
// keys of a new curve.
bool lifeCurveEditor(const char* label, sim::LifeCurve& c, float maxValue, float minValue = 0.0f, float start = 1.0f) {
  const auto plot = [&] {
    float samples[64];
    for (int i = 0; i < 64; ++i) samples[i] = c.at(static_cast<float>(i) / 63.0f);
    ImGui::PlotLines(label, samples, 64, 0, nullptr, 0.0f, std::max(1.0f, *std::max_element(samples, samples + 64)),
                     ImVec2(0, 48));
  };
  const auto editValue = [&](float& value) {
    const float speed = std::max(0.005f, maxValue / 20000.0f);  // kelvin move faster than multipliers
    ImGui::SetNextItemWidth(0.7f * ImGui::CalcItemWidth() - ImGui::GetFrameHeight() - 16.0f);
    if (!ImGui::DragFloat("##value", &value, speed, minValue, maxValue, "%.3f", ImGuiSliderFlags_AlwaysClamp))
      return false;
    value = std::clamp(value, minValue, maxValue);
    return true;
  };
  return curveEditor(label, c, "the default", start, plot, editValue, "age, value");
}

// A colour over life: a strip of its colours, each key a colour picker's display value.
bool colourCurveEditor(const char* label, sim::ColourCurve& c) {
  const auto plot = [&] {
    // 32 swatches (display values, as the keys are).
    const ImVec2 at = ImGui::GetCursorScreenPos();
    const float width = ImGui::CalcItemWidth(), height = 16.0f;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    for (int i = 0; i < 32; ++i) {
      const glm::vec3 v = glm::clamp(c.at((static_cast<float>(i) + 0.5f) / 32.0f), glm::vec3(0.0f), glm::vec3(1.0f));
      const float x0 = at.x + width * static_cast<float>(i) / 32.0f,
                  x1 = at.x + width * static_cast<float>(i + 1) / 32.0f;
      draw->AddRectFilled(ImVec2(x0, at.y), ImVec2(x1, at.y + height),
                          ImGui::ColorConvertFloat4ToU32(ImVec4(v.r, v.g, v.b, 1.0f)));
    }
    ImGui::Dummy(ImVec2(width, height));
    ImGui::SameLine();
    ImGui::TextUnformatted(label);
  };
  const auto editValue = [](glm::vec3& colour) {
    return ImGui::ColorEdit3("##colour", glm::value_ptr(colour), ImGuiColorEditFlags_NoInputs);
  };
  return curveEditor(label, c, "white (no tint)", glm::vec3(1.0f), plot, editValue, "age, colour");
}

// Which curves over life an emitter's particles take (the scene refuses the others).
enum class CurveSet {
  kCel,        ///< placed cel puffs: size, colour
  kCelSim,     ///< simulated cel puffs: size, density, colour
  kMedia,      ///< media that do not emit: size, density, colour
  kMediaFire,  ///< media that emit (or turn into a material that does): and temperature
};

bool lifeCurvesEditor(sim::LifeCurves& curves, CurveSet set) {
  bool changed = false;
  if (ImGui::TreeNode("Over life")) {
    changed |= lifeCurveEditor("Size", curves.size, 100.0f);
    if (set != CurveSet::kCel) changed |= lifeCurveEditor("Density", curves.density, 1000.0f);
    changed |= colourCurveEditor("Colour", curves.color);
    if (set == CurveSet::kMediaFire)
      changed |= lifeCurveEditor("Temperature (K)", curves.temperature, 1e5f, 1.0f, 2500.0f);
    ImGui::TreePop();
  }
  if (set != CurveSet::kMediaFire && !curves.temperature.empty()) {
    curves.temperature = {};  // a material that does not emit has no temperature to shape (the scene refuses it)
    changed = true;
  }
  return changed;
}

void simEmittersPanel(std::vector<sim::Emitter>& emitters, Edits& edit, CurveSet curves = CurveSet::kCelSim) {
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
      edit(lifeCurvesEditor(e.overLife, curves));
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
      if (e.lifetime > 0.0f) {
        edit(lifeCurvesEditor(e.overLife, CurveSet::kCel));
      } else if (!e.overLife.empty()) {
        e.overLife = {};  // particles that live forever have no life to shape (the scene refuses it)
        edit(true);
      }
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
}

// The atlas: any sidecar under the art directory (a JSON file with cells and maps), and the level
// of its mips the nailboards start from.
std::vector<fs::path> findAtlases(const fs::path& artDir) {
  std::vector<fs::path> found;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(artDir, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec)) {
    if (it.depth() > 2) it.disable_recursion_pending();
    if (!it->is_regular_file(ec) || it->path().extension() != ".json" || it->file_size(ec) > (1u << 22)) continue;
    auto text = core::readFileBytes(it->path());
    if (text && text->find("\"cells\"") != std::string::npos && text->find("\"maps\"") != std::string::npos) {
      found.push_back(it->path());
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

void atlasPanel(Viewer& v, PanelState& state, Edits& edit) {
  scene::Scene& s = v.scene();
  const std::string current = s.atlas.empty() ? "(none)" : s.atlas.string();
  if (ImGui::BeginCombo("Atlas", current.c_str())) {
    if (ImGui::IsWindowAppearing()) state.atlases = findAtlases(v.artDir());
    for (const fs::path& a : state.atlases) {
      const std::string label = fs::relative(a, v.artDir()).string();
      if (ImGui::Selectable(label.c_str(), a == s.atlas) && a != s.atlas) {
        s.atlas = a;
        s.atlasLevel = 0;
        edit(true);
      }
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", a.c_str());
    }
    if (state.atlases.empty()) ImGui::TextDisabled("no atlas under %s", v.artDir().c_str());
    ImGui::EndCombo();
  }
  edit(ImGui::SliderInt("Atlas level", &s.atlasLevel, 0, 6, "%d", ImGuiSliderFlags_AlwaysClamp));
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("draw from this mip level on: cells 2^level times smaller");
  edit(ImGui::SliderFloat("Particle share", &s.particleFraction, 0.01f, 1.0f, "%.3f", ImGuiSliderFlags_AlwaysClamp));
}

// A strip showing `colors` over [0, 1] (the ramp's bands, the gradient's ends), `height` pixels.
void colorStrip(const std::vector<float>& starts, const std::vector<glm::vec3>& colors, float height) {
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 at = ImGui::GetCursorScreenPos();
  const float width = ImGui::CalcItemWidth();
  for (std::size_t i = 0; i < colors.size(); ++i) {
    const float x0 = at.x + width * starts[i], x1 = at.x + width * (i + 1 < starts.size() ? starts[i + 1] : 1.0f);
    const glm::vec3 c = colors[i];
    draw->AddRectFilled(ImVec2(x0, at.y), ImVec2(x1, at.y + height),
                        ImGui::ColorConvertFloat4ToU32(ImVec4(c.r, c.g, c.b, 1.0f)));
  }
  draw->AddRect(at, ImVec2(at.x + width, at.y + height), IM_COL32(90, 90, 90, 255));
  ImGui::Dummy(ImVec2(width, height));
}

// The ramp editor: flat bands over N.L (Eq. 2's q), shown at once and kept beside the scene on Save.
void rampPanel(Viewer& v, PanelState& state) {
  scene::Scene& s = v.scene();
  if (state.rampFrom != s.ramp) {  // the scene names another ramp (opened, undone, reloaded): read it
    state.rampFrom = s.ramp;
    state.rampError.clear();
    if (s.ramp.empty()) {
      state.ramp = RampBands{};  // the built-in two-tone ramp
    } else if (auto image = cel::Ramp::read(s.ramp)) {
      state.ramp = bandsFromImage(*image);
    } else {
      state.rampError = image.error().message;
    }
  }
  if (!state.rampError.empty()) ImGui::TextColored(kRed, "%s", state.rampError.c_str());
  RampBands& r = state.ramp;
  const RampBands shown = normalized(r);
  colorStrip(shown.starts, shown.colors, 18.0f);
  bool changed = false;
  int remove = -1;
  for (std::size_t i = 0; i < r.starts.size(); ++i) {
    ImGui::PushID(static_cast<int>(i));
    changed |= ImGui::ColorEdit3("##colour", glm::value_ptr(r.colors[i]), ImGuiColorEditFlags_NoInputs);
    ImGui::SameLine();
    ImGui::BeginDisabled(i == 0);
    ImGui::SetNextItemWidth(ImGui::CalcItemWidth() - ImGui::GetFrameHeight() - 8.0f);
    changed |= ImGui::SliderFloat("##start", &r.starts[i], 0.0f, 1.0f, i == 0 ? "from 0" : "from %.3f",
                                  ImGuiSliderFlags_AlwaysClamp);
    ImGui::SameLine();
    if (ImGui::Button("x") && r.starts.size() > 1) remove = static_cast<int>(i);
    ImGui::EndDisabled();
    ImGui::PopID();
  }
  if (remove >= 0) {
    r.starts.erase(r.starts.begin() + remove);
    r.colors.erase(r.colors.begin() + remove);
    changed = true;
  }
  ImGui::BeginDisabled(r.starts.size() >= static_cast<std::size_t>(kMaxRampBands));
  if (ImGui::Button("Add band")) {
    // Halfway through the widest band, its colour a step lighter.
    const RampBands n = normalized(r);
    std::size_t widest = 0;
    float width = 0.0f;
    for (std::size_t i = 0; i < n.starts.size(); ++i) {
      const float w = (i + 1 < n.starts.size() ? n.starts[i + 1] : 1.0f) - n.starts[i];
      if (w > width) width = w, widest = i;
    }
    r = n;
    r.starts.insert(r.starts.begin() + static_cast<long>(widest) + 1, n.starts[widest] + 0.5f * width);
    r.colors.insert(r.colors.begin() + static_cast<long>(widest) + 1,
                    glm::min(n.colors[widest] + glm::vec3(0.25f), glm::vec3(1.0f)));
    changed = true;
  }
  ImGui::EndDisabled();
  ImGui::SameLine();
  bool smooth = s.rampSmooth;
  if (ImGui::Checkbox("Smooth", &smooth)) {
    v.beginEdit();
    s.rampSmooth = smooth;
    (void)v.applyEdit();
  }
  if (changed) {
    v.beginEdit();
    if (auto ok = v.setRamp(rampImage(r)); !ok) state.rampError = ok.error().message;
    state.rampFrom = s.ramp;  // what the editor holds is what the scene names now
  }
  ImGui::TextDisabled(s.ramp.empty() ? "built-in two-tone ramp" : "%s", s.ramp.filename().c_str());
}

// The dynamic objects (rigid bodies) and the rigid-body world. Their trajectories are
// simulated again at once, and what rides on them follows (scene::updateBodies), so the frame shows
// what puffrender makes of the saved scene.
void bodiesPanel(scene::Scene& s, Edits& edit, std::string& error) {
  bool changed = false;
  changed |= ImGui::DragFloat3("Gravity", glm::value_ptr(s.rigidBodies.gravity), 0.05f, -1e4f, 1e4f, "%.2f",
                               ImGuiSliderFlags_AlwaysClamp);
  changed |= ImGui::SliderInt("Steps per second", &s.rigidBodies.stepsPerSecond, 24, 2400, "%d",
                              ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    scene::ObjectSpec& o = s.objects[i];
    if (!o.dynamic) continue;
    ImGui::PushID(7000 + static_cast<int>(i));
    if (ImGui::TreeNode("body", "%s", o.name.c_str())) {
      scene::DynamicBody& d = *o.dynamic;
      changed |= ImGui::DragFloat3("Start", glm::value_ptr(o.translate), 0.01f, -1000.0f, 1000.0f, "%.2f",
                                   ImGuiSliderFlags_AlwaysClamp);
      changed |= ImGui::SliderFloat("Mass (kg)", &d.mass, 0.001f, 1e6f, "%.3f",
                                    ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
      changed |= ImGui::DragFloat3("Velocity", glm::value_ptr(d.velocity), 0.02f, -1e4f, 1e4f, "%.2f",
                                   ImGuiSliderFlags_AlwaysClamp);
      changed |= ImGui::DragFloat3("Spin (rad/s)", glm::value_ptr(d.angularVelocity), 0.05f, -1e4f, 1e4f, "%.2f",
                                   ImGuiSliderFlags_AlwaysClamp);
      changed |= ImGui::SliderFloat("Friction", &d.friction, 0.0f, 10.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp);
      changed |= ImGui::SliderFloat("Restitution", &d.restitution, 0.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp);
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  if (changed) {
    // A setting the simulation refuses (too many keys, a body that diverges) keeps the last good
    // trajectories and says why.
    scene::Scene next = s;
    if (auto ok = scene::updateBodies(next); ok) {
      s = std::move(next);
      error.clear();
    } else {
      error = ok.error().message;
    }
    edit(true);
  }
  if (!error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", error.c_str());
}

// The ambient gradient editor: K_a from the top of the frame to its bottom, or a uniform colour.
void gradientPanel(Viewer& v, PanelState& state) {
  scene::Scene& s = v.scene();
  if (state.gradientFrom != s.ambientGradient) {
    state.gradientFrom = s.ambientGradient;
    if (!s.ambientGradient.empty()) {
      if (auto image = cel::Gradient::read(s.ambientGradient)) state.gradient = gradientFromImage(*image);
    } else {
      state.gradient.top = state.gradient.bottom = s.ambientColor;
    }
  }
  bool use = !s.ambientGradient.empty();
  bool changed = false;
  if (ImGui::Checkbox("Gradient (else the uniform ambient colour)", &use)) {
    if (use) {
      changed = true;
    } else {
      v.beginEdit();
      s.ambientGradient.clear();
      state.gradientFrom = s.ambientGradient;
      (void)v.applyEdit();
    }
  }
  if (!use && !changed) return;
  VerticalGradient& g = state.gradient;
  colorStrip({0.0f, 0.5f}, {g.top, g.bottom}, 12.0f);
  changed |= ImGui::ColorEdit3("Top", glm::value_ptr(g.top));
  changed |= ImGui::ColorEdit3("Bottom", glm::value_ptr(g.bottom));
  if (changed) {
    v.beginEdit();
    if (auto ok = v.setAmbientGradient(gradientImage(g)); !ok) state.rampError = ok.error().message;
    state.gradientFrom = s.ambientGradient;
  }
}

// The media: how they are drawn, their materials, emitters and lights.
void mediaPanel(Viewer& v, Edits& edit) {
  scene::Scene& s = v.scene();
  if (!s.media) {
    ImGui::TextDisabled("this scene has no \"media\"");
    return;
  }
  scene::MediaSpec& m = *s.media;
  const char* methods[] = {"planar", "soft-linear", "soft-scurve", "spherical", "planar-textured"};
  int method = static_cast<int>(m.method);
  if (edit(ImGui::Combo("Method", &method, methods, 5))) m.method = static_cast<media::Method>(method);
  const float resolutions[] = {1.0f, 0.5f, 0.25f, 0.125f};
  const char* resolutionNames[] = {"1 (full)", "1/2", "1/4", "1/8"};
  int r = 0;
  for (int i = 0; i < 4; ++i) r = m.resolution == resolutions[i] ? i : r;
  if (edit(ImGui::Combo("Resolution", &r, resolutionNames, 4))) m.resolution = resolutions[r];
  const char* views[] = {"automatic", "standard", "filmic"};
  int view = !s.view ? 0 : *s.view == core::ViewTransform::kStandard ? 1 : 2;
  if (edit(ImGui::Combo("View transform", &view, views, 3))) {
    s.view = view == 0   ? std::nullopt
             : view == 1 ? std::optional(core::ViewTransform::kStandard)
                         : std::optional(core::ViewTransform::kFilmic);
  }
  edit(ImGui::SliderFloat("Exposure", &m.settings.exposure, 0.01f, 100.0f, "%.3f",
                          ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp));
  edit(ImGui::SliderInt("Motion blur frames", &m.motionBlurFrames, 0, 16, "%d", ImGuiSliderFlags_AlwaysClamp));
  if (m.motionBlurFrames > 0) {
    edit(
        ImGui::SliderFloat("Persistence", &m.motionBlurPersistence, 0.0f, 0.99f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
  }
  edit(ImGui::SliderFloat("Heat shimmer", &m.compose.shimmerPixels, 0.0f, 20.0f, "%.1f px",
                          ImGuiSliderFlags_AlwaysClamp));
  std::vector<const char*> names;
  for (const media::Material& mat : m.materials) names.push_back(mat.name.c_str());
  for (std::size_t i = 0; i < m.materials.size(); ++i) {
    media::Material& mat = m.materials[i];
    ImGui::PushID(4000 + static_cast<int>(i));
    if (ImGui::TreeNode("material", "Material %s", mat.name.c_str())) {
      edit(ImGui::Checkbox("Emissive (black body)", &mat.emissive));
      if (mat.emissive) {
        edit(ImGui::DragFloat("Temperature", &mat.temperature, 10.0f, 0.0f, 1e5f, "%.0f K",
                              ImGuiSliderFlags_AlwaysClamp));
        edit(ImGui::DragFloat("Temperature range", &mat.temperatureRange, 10.0f, -1e5f, 1e5f, "%.0f K",
                              ImGuiSliderFlags_AlwaysClamp));
        edit(ImGui::SliderFloat("Emission", &mat.emission, 0.0f, 100.0f, "%.2f",
                                ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp));
      } else {
        edit(ImGui::SliderFloat("Albedo", &mat.albedo, 0.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
        edit(ImGui::ColorEdit3("Tint", glm::value_ptr(mat.color)));
        edit(ImGui::SliderFloat("Phase g", &mat.g, -0.95f, 0.95f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
        edit(ImGui::SliderFloat("Detail", &mat.detail, 0.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      }
      edit(ImGui::SliderFloat("Density", &mat.density, 0.0f, 100.0f, "%.3f /unit",
                              ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Burn", &mat.burn, 0.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::SliderFloat("Shimmer", &mat.shimmer, 0.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      std::vector<const char*> becomes{"(stays)"};
      becomes.insert(becomes.end(), names.begin(), names.end());
      int b = mat.becomes + 1;
      if (edit(ImGui::Combo("Becomes", &b, becomes.data(), static_cast<int>(becomes.size())))) mat.becomes = b - 1;
      if (mat.becomes >= 0) {
        edit(ImGui::DragFloatRange2("Transition", &mat.transitionStart, &mat.transitionEnd, 0.01f, 0.0f, 1.0f,
                                    "from %.2f", "to %.2f", ImGuiSliderFlags_AlwaysClamp));
      }
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  for (std::size_t i = 0; i < m.emitters.size(); ++i) {
    scene::MediaEmitterSpec& e = m.emitters[i];
    ImGui::PushID(5000 + static_cast<int>(i));
    if (ImGui::TreeNode("emitter", "Media emitter %zu (%s)", i, e.material.c_str())) {
      int mat = e.materialIndex;
      if (edit(ImGui::Combo("Material", &mat, names.data(), static_cast<int>(names.size())))) {
        e.materialIndex = mat;
        e.material = m.materials[static_cast<std::size_t>(mat)].name;
      }
      edit(ImGui::SliderFloat("Growth", &e.growth, 0.0f, 100.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      const media::Material& mt = m.materials[static_cast<std::size_t>(e.materialIndex)];
      const bool emits = mt.emissive || (mt.becomes >= 0 && m.materials[static_cast<std::size_t>(mt.becomes)].emissive);
      std::vector<sim::Emitter> one{e.emitter};
      Edits inner;
      simEmittersPanel(one, inner, emits ? CurveSet::kMediaFire : CurveSet::kMedia);
      if (edit(inner.any)) e.emitter = one[0];
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  for (std::size_t i = 0; i < m.lights.size(); ++i) {
    scene::MediaLightSpec& l = m.lights[i];
    ImGui::PushID(6000 + static_cast<int>(i));
    if (ImGui::TreeNode("light", "Explosion light %zu", i)) {
      edit(ImGui::DragFloat3("Centre", glm::value_ptr(l.center), 0.01f, -1000.0f, 1000.0f, "%.2f",
                             ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::DragFloat("Radius", &l.radius, 0.01f, 0.01f, 1000.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
      edit(ImGui::ColorEdit3("Colour", glm::value_ptr(l.color)));
      edit(ImGui::Checkbox("Modulate", &l.modulate));
      ImGui::SameLine();
      edit(ImGui::Checkbox("Full at back", &l.fullAtBack));
      for (std::size_t k = 0; k < l.times.size() && k < l.intensities.size(); ++k) {
        ImGui::PushID(static_cast<int>(k));
        float key[2] = {l.times[k], l.intensities[k]};
        if (edit(ImGui::DragFloat2("Key (s, intensity)", key, 0.01f, 0.0f, 1e4f, "%.2f",
                                   ImGuiSliderFlags_AlwaysClamp))) {
          // Times stay in order between their neighbours.
          const float lo = k > 0 ? l.times[k - 1] : 0.0f, hi = k + 1 < l.times.size() ? l.times[k + 1] : 1e4f;
          l.times[k] = std::clamp(key[0], lo, hi);
          l.intensities[k] = key[1];
        }
        ImGui::PopID();
      }
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  if (ImGui::TreeNode("Media forces")) {
    forcesPanel(m.forces, edit);
    ImGui::TreePop();
  }
  // A temperature curve on an emitter whose material no longer emits (its material switched, made
  // to scatter, or set to become another) would make the scene one it refuses: the same edit drops it.
  if (edit.any) view::dropRefusedCurves(s);
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
