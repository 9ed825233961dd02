#include <puff/core/blackbody.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/core/number_text.h>

namespace puff::core {

namespace fs = std::filesystem;

namespace {

// CODATA 2018 (exact in the SI since 2019).
constexpr double kPlanck = 6.62607015e-34;   // J s
constexpr double kLight = 299792458.0;       // m / s
constexpr double kBoltzmann = 1.380649e-23;  // J / K

constexpr double kCmfFirstNm = 360.0, kCmfStepNm = 5.0;
constexpr double kCmf[][3] = {
#include "cie1931_2deg.inc"
};
constexpr int kCmfRows = static_cast<int>(sizeof kCmf / sizeof kCmf[0]);
static_assert(kCmfRows == 95, "360..830 nm at 5 nm");

std::string number(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

Result<void> checkRange(double minKelvin, double maxKelvin, int size, double normalizeKelvin) {
  const std::string top = core::numberText(kMaxKelvin);
  if (!(minKelvin > 0.0 && minKelvin < kMaxKelvin))
    return Error{"minKelvin must be in (0, " + top + "), got " + core::numberText(minKelvin)};
  if (!(maxKelvin > minKelvin && maxKelvin <= kMaxKelvin))
    return Error{"maxKelvin must be in (minKelvin = " + core::numberText(minKelvin) + ", " + top + "], got " +
                 core::numberText(maxKelvin)};
  if (size < 2 || size > kMaxBlackbodyTexels)
    return Error{"size must be in [2, " + std::to_string(kMaxBlackbodyTexels) + "] texels, got " +
                 std::to_string(size)};
  if (!(normalizeKelvin > 0.0 && normalizeKelvin <= kMaxKelvin))
    return Error{"normalizeKelvin must be in (0, " + top + "], got " + core::numberText(normalizeKelvin)};
  return {};
}

}  // namespace

double planckRadiance(double lambdaMetres, double kelvin) {
  PUFF_CHECK(lambdaMetres > 0.0 && kelvin > 0.0);
  const double x = kPlanck * kLight / (lambdaMetres * kBoltzmann * kelvin);
  // expm1 keeps precision in the Rayleigh-Jeans limit (x small); a huge x overflows to inf -> 0.
  return 2.0 * kPlanck * kLight * kLight / std::pow(lambdaMetres, 5.0) / std::expm1(x);
}

glm::dvec3 blackbodyXYZ(double kelvin) {
  PUFF_CHECK(kelvin > 0.0);
  glm::dvec3 sum(0.0);
  for (int i = 0; i < kCmfRows; ++i) {
    const double lambda = (kCmfFirstNm + kCmfStepNm * i) * 1e-9;
    const double weight = (i == 0 || i == kCmfRows - 1) ? 0.5 : 1.0;  // trapezoid rule
    const double l = planckRadiance(lambda, kelvin) * weight;
    sum += l * glm::dvec3(kCmf[i][0], kCmf[i][1], kCmf[i][2]);
  }
  return sum * (kCmfStepNm * 1e-9);
}

// IEC 61966-2-1:1999, §5.2 (XYZ -> RGB) and §5.3 (RGB -> XYZ), rows as printed.
glm::dvec3 xyzToLinearSrgb(glm::dvec3 c) {
  return {3.2406 * c.x - 1.5372 * c.y - 0.4986 * c.z, -0.9689 * c.x + 1.8758 * c.y + 0.0415 * c.z,
          0.0557 * c.x - 0.2040 * c.y + 1.0570 * c.z};
}

glm::dvec3 linearSrgbToXyz(glm::dvec3 c) {
  return {0.4124 * c.x + 0.3576 * c.y + 0.1805 * c.z, 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z,
          0.0193 * c.x + 0.1192 * c.y + 0.9505 * c.z};
}

glm::vec3 BlackbodyRamp::at(double kelvin) const {
  PUFF_CHECK(rgb.size() >= 2 && maxKelvin > minKelvin);
  const double last = static_cast<double>(rgb.size() - 1);
  const double u = std::clamp((kelvin - minKelvin) / (maxKelvin - minKelvin) * last, 0.0, last);
  const std::size_t i = std::min(static_cast<std::size_t>(u), rgb.size() - 2);
  const float f = static_cast<float>(u - static_cast<double>(i));
  return rgb[i] * (1.0f - f) + rgb[i + 1] * f;
}

Result<BlackbodyRamp> makeBlackbodyRamp(double minKelvin, double maxKelvin, int size, double normalizeKelvin) {
  if (auto r = checkRange(minKelvin, maxKelvin, size, normalizeKelvin); !r)
    return Error{"black-body ramp: " + r.error().message};
  const double y = blackbodyXYZ(normalizeKelvin).y;
  if (!(y > 0.0) || !std::isfinite(1.0 / y)) {
    return Error{"black-body ramp: normalizeKelvin " + core::numberText(normalizeKelvin) +
                 " K gives no visible light to normalize by"};
  }
  BlackbodyRamp ramp;
  ramp.minKelvin = minKelvin;
  ramp.maxKelvin = maxKelvin;
  ramp.normalizeKelvin = normalizeKelvin;
  ramp.rgb.resize(static_cast<std::size_t>(size));
  for (int i = 0; i < size; ++i) {
    const double t = i == size - 1 ? maxKelvin : minKelvin + (maxKelvin - minKelvin) * i / (size - 1);
    const glm::vec3 c(xyzToLinearSrgb(blackbodyXYZ(t) / y));
    if (!std::isfinite(c.r) || !std::isfinite(c.g) || !std::isfinite(c.b)) {
      return Error{"black-body ramp: the colour at " + core::numberText(t) + " K is " +
                   core::numberText(blackbodyXYZ(t).y / y) + " times as bright as at normalizeKelvin " +
                   core::numberText(normalizeKelvin) +
                   " K: too much for 32-bit floats (raise normalizeKelvin or lower maxKelvin)"};
    }
    ramp.rgb[static_cast<std::size_t>(i)] = c;
  }
  return ramp;
}

Result<void> writeBlackbodyRamp(const fs::path& path, const BlackbodyRamp& ramp) {
  PUFF_CHECK(ramp.rgb.size() >= 2);
  Image img(static_cast<int>(ramp.rgb.size()), 1, 3);
  for (std::size_t i = 0; i < ramp.rgb.size(); ++i) {
    for (int c = 0; c < 3; ++c) img.pixels[i * 3 + static_cast<std::size_t>(c)] = ramp.rgb[i][c];
  }
  const ImageAttributes attributes = {{"puff:minKelvin", number(ramp.minKelvin)},
                                      {"puff:maxKelvin", number(ramp.maxKelvin)},
                                      {"puff:normalizeKelvin", number(ramp.normalizeKelvin)}};
  OutputTransaction tx;
  PUFF_TRY(tx.prepareDirectory(path.parent_path()));
  PUFF_TRY(writeImage(tx.stage(path), img, PixelType::kFloat, attributes, path));
  return tx.commit();
}

Result<BlackbodyRamp> readBlackbodyRamp(const fs::path& path) {
  ImageFileInfo info;  // one read: the pixels and the puff: attributes together
  PUFF_TRY_ASSIGN(auto img, readImage(path, &info, kBlackbodyRampLimits));
  if (img.height != 1 || img.channels != 3 || img.width < 2) {
    return Error::at(path, "not a black-body ramp: expected N x 1 RGB (N >= 2), got " + std::to_string(img.width) +
                               "x" + std::to_string(img.height) + " with " + std::to_string(img.channels) +
                               " channel(s)");
  }
  BlackbodyRamp ramp;
  const std::pair<const char*, double*> fields[] = {{"puff:minKelvin", &ramp.minKelvin},
                                                    {"puff:maxKelvin", &ramp.maxKelvin},
                                                    {"puff:normalizeKelvin", &ramp.normalizeKelvin}};
  for (const auto& field : fields) {
    const char* name = field.first;  // a plain variable: clang 14 cannot capture a structured binding
    double* out = field.second;
    const auto found = std::find_if(info.attributes.begin(), info.attributes.end(),
                                    [&](const auto& attribute) { return attribute.first == name; });
    const std::string* text = found == info.attributes.end() ? nullptr : &found->second;
    if (!text || text->empty()) {
      return Error::at(path, std::string("missing attribute ") + name + " (not a black-body ramp?)");
    }
    char* end = nullptr;
    *out = std::strtod(text->c_str(), &end);
    if (end != text->c_str() + text->size() || !std::isfinite(*out)) {
      return Error::at(path, std::string("attribute ") + name + " is not a number: \"" + *text + "\"");
    }
  }
  if (auto r = checkRange(ramp.minKelvin, ramp.maxKelvin, img.width, ramp.normalizeKelvin); !r) {
    return Error::at(path, r.error().message);
  }
  ramp.rgb.resize(static_cast<std::size_t>(img.width));
  for (std::size_t i = 0; i < ramp.rgb.size(); ++i) {
    ramp.rgb[i] = glm::vec3(img.pixels[i * 3], img.pixels[i * 3 + 1], img.pixels[i * 3 + 2]);
    if (!std::isfinite(ramp.rgb[i].r) || !std::isfinite(ramp.rgb[i].g) || !std::isfinite(ramp.rgb[i].b)) {
      return Error::at(path, "texel " + std::to_string(i) + " is not finite");
    }
  }
  return ramp;
}

}  // namespace puff::core
