// The panels for how the scene looks: style, atlas, the ramp editor, light, ambient gradient, background.
#include <imgui.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <puff/cel/frame.h>
#include <puff/core/files.h>
#include <puff/scene/scene.h>
#include <puffview/ramp_edit.h>
#include <puffview/viewer.h>

#include "panels_detail.h"

namespace puff::view::detail {

namespace fs = std::filesystem;

namespace {

// The atlas sidecars under the art directory: JSON files with cells and maps.
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

}  // namespace

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
  if (st.tumble == cel::TumbleMethod::kHull) {
    edit(ImGui::SliderFloat("Hull from (px)", &st.hullFromPixels, 0.0f, cel::kMaxHullFromPixels, "%.0f",
                            ImGuiSliderFlags_AlwaysClamp | ImGuiSliderFlags_Logarithmic));
  }
}

void lightPanel(scene::Scene& s, Edits& edit) {
  edit(direction("Light direction", s.light.direction));
  edit(ImGui::ColorEdit3("Light colour", glm::value_ptr(s.light.color), ImGuiColorEditFlags_Float));
  edit(ImGui::ColorEdit3("Ambient colour", glm::value_ptr(s.ambientColor), ImGuiColorEditFlags_Float));
  if (!s.ambientGradient.empty()) ImGui::TextDisabled("ambient gradient: %s", s.ambientGradient.filename().c_str());
  edit(ImGui::ColorEdit3("Background", glm::value_ptr(s.background), ImGuiColorEditFlags_Float));
}

// The atlas: any sidecar under the art directory (a JSON file with cells and maps), and the level
// of its mips the nailboards start from.
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

}  // namespace puff::view::detail
