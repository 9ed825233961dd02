// The cartoon style's values (types.h) and its compose inputs (layers.h).
#include <cmath>
#include <cstdio>
#include <string>

#include <puff/core/blackbody.h>
#include <puff/core/colour.h>
#include <puff/core/number_text.h>
#include <puff/media/layers.h>
#include <puff/media/types.h>
#include <puff/shader_contract.h>

namespace puff::media {

std::string_view toString(Style s) { return s == Style::kCartoon ? "cartoon" : "photoreal"; }

std::optional<Style> parseStyle(std::string_view name) {
  if (name == "photoreal") return Style::kPhotoreal;
  if (name == "cartoon") return Style::kCartoon;
  return std::nullopt;
}

std::vector<glm::vec3> defaultFireColors() { return {{1.0f, 0.9f, 0.45f}, {1.0f, 0.6f, 0.15f}, {0.93f, 0.3f, 0.1f}}; }

int fireBandCount(const CartoonStyle& s) {
  return s.fireColors.empty() ? s.fireBands : static_cast<int>(s.fireColors.size());
}

Result<void> validate(const CartoonStyle& s) {
  if (!(s.threshold > 0.0f && s.threshold < 1.0f))
    return Error{"threshold: expected an opacity in (0, 1), got " + core::numberText(s.threshold)};
  if (s.opacityBands < 1 || s.opacityBands > 8)
    return Error{"opacityBands: expected 1 to 8, got " + std::to_string(s.opacityBands)};
  if (s.fireBands < 1 || s.fireBands > shader::kMaxFireBands)
    return Error{"fireBands: expected 1 to " + std::to_string(shader::kMaxFireBands) + ", got " +
                 std::to_string(s.fireBands)};
  if (s.fireColors.size() > static_cast<std::size_t>(shader::kMaxFireBands))
    return Error{"fireColors: expected at most " + std::to_string(shader::kMaxFireBands) + " colours, got " +
                 std::to_string(s.fireColors.size())};
  for (std::size_t k = 0; k < s.fireColors.size(); ++k) {
    for (int i = 0; i < 3; ++i) {
      if (!(s.fireColors[k][i] >= 0.0f && s.fireColors[k][i] <= 1.0f))
        return Error{"fireColors/" + std::to_string(k) + "/" + std::to_string(i) + ": expected [0, 1], got " +
                     core::numberText(s.fireColors[k][i])};
    }
  }
  if (!(s.coolKelvin > 0.0f && s.coolKelvin < 1e5f))
    return Error{"coolKelvin: expected kelvin in (0, 100000), got " + core::numberText(s.coolKelvin)};
  if (!(s.hotKelvin > s.coolKelvin && s.hotKelvin <= 1e5f))
    return Error{"hotKelvin: expected kelvin in (coolKelvin " + core::numberText(s.coolKelvin) + ", 100000], got " +
                 core::numberText(s.hotKelvin)};
  if (!(s.outlineWidth >= 0.0f && s.outlineWidth <= 64.0f))
    return Error{"outlineWidth: expected pixels in [0, 64], got " + core::numberText(s.outlineWidth)};
  for (int i = 0; i < 3; ++i) {
    if (!(s.outlineColor[i] >= 0.0f && s.outlineColor[i] <= 1.0f))
      return Error{"outlineColor/" + std::to_string(i) + ": expected [0, 1], got " +
                   core::numberText(s.outlineColor[i])};
  }
  return {};
}

Result<CartoonCompose> cartoonCompose(const Settings& settings) {
  if (auto ok = validate(settings.cartoon); !ok) return Error{"cartoon/" + ok.error().message};
  const CartoonStyle& st = settings.cartoon;
  // The renderer's normalization (luminance 1 at normalizeKelvin), over the bands' own range.
  PUFF_TRY_ASSIGN(auto ramp, core::makeBlackbodyRamp(st.coolKelvin, st.hotKelvin, 2, settings.normalizeKelvin));
  const glm::dvec3 white = core::blackbodyXYZ(settings.normalizeKelvin);
  CartoonCompose c;
  c.style = st;
  if (!st.fireColors.empty()) {
    // The palette lists the core first; the bands run from the coolest.
    for (auto it = st.fireColors.rbegin(); it != st.fireColors.rend(); ++it)
      c.fireColors.push_back(core::srgbToLinear(*it) * settings.exposure);
    return c;
  }
  const double width = (static_cast<double>(st.hotKelvin) - st.coolKelvin) / st.fireBands;
  for (int k = 0; k < st.fireBands; ++k) {
    const double kelvin = st.coolKelvin + (k + 0.5) * width;
    const glm::dvec3 rgb = core::xyzToLinearSrgb(core::blackbodyXYZ(kelvin) / white.y);
    c.fireColors.push_back(glm::max(glm::vec3(rgb), glm::vec3(0.0f)) * settings.exposure);
  }
  return c;
}

}  // namespace puff::media
