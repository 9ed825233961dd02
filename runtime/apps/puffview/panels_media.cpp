// The media panel: how fire, smoke and dust are drawn, their materials, emitters and explosion lights.
#include <imgui.h>

#include <algorithm>
#include <optional>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include <puff/scene/scene.h>
#include <puffview/ramp_edit.h>
#include <puffview/viewer.h>

#include "panels_detail.h"

namespace puff::view::detail {

namespace {

// How the media are drawn: the method, resolution and view transform, exposure, motion blur and
// heat shimmer.
void mediaDrawingPanel(scene::Scene& s, scene::MediaSpec& m, Edits& edit) {
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
}

// Each material, `names` naming them all (what one may become).
void materialsPanel(std::vector<media::Material>& materials, const std::vector<const char*>& names, Edits& edit) {
  for (std::size_t i = 0; i < materials.size(); ++i) {
    media::Material& mat = materials[i];
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
}

// Each media emitter: its material (one of `names`), growth, and the emitter's own settings.
void mediaEmittersPanel(scene::MediaSpec& m, const std::vector<const char*>& names, Edits& edit) {
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
}

// Each explosion light: where, how large, its colour, and its intensity keys over time.
void explosionLightsPanel(std::vector<scene::MediaLightSpec>& lights, Edits& edit) {
  for (std::size_t i = 0; i < lights.size(); ++i) {
    scene::MediaLightSpec& l = lights[i];
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
}

}  // namespace

// The media: how they are drawn, their materials, emitters and lights.
void mediaPanel(Viewer& v, Edits& edit) {
  scene::Scene& s = v.scene();
  if (!s.media) {
    ImGui::TextDisabled("this scene has no \"media\"");
    return;
  }
  scene::MediaSpec& m = *s.media;
  mediaDrawingPanel(s, m, edit);
  std::vector<const char*> names;
  for (const media::Material& mat : m.materials) names.push_back(mat.name.c_str());
  materialsPanel(m.materials, names, edit);
  mediaEmittersPanel(m, names, edit);
  explosionLightsPanel(m.lights, edit);
  if (ImGui::TreeNode("Media forces")) {
    forcesPanel(m.forces, edit);
    ImGui::TreePop();
  }
  // A temperature curve on an emitter whose material no longer emits (its material switched, made
  // to scatter, or set to become another) would make the scene one it refuses: the same edit drops it.
  if (edit.any) view::dropRefusedCurves(s);
}

}  // namespace puff::view::detail
