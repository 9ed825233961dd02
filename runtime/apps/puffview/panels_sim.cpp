// The simulation's panels: forces, emitters and their curves over life, placed particles and rigid bodies.
#include <imgui.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <puff/scene/bodies.h>
#include <puff/scene/scene.h>

#include "panels_detail.h"

namespace puff::view::detail {

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

namespace {

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

}  // namespace

void simEmittersPanel(std::vector<sim::Emitter>& emitters, Edits& edit, CurveSet curves) {
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

}  // namespace puff::view::detail
