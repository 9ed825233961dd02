// The colour of fire: a black-body radiator seen by the CIE 1931 2-degree standard observer
// (Umenhoffer et al. 2006, §3.2). Planck's law gives the spectral radiance at temperature T; the
// colour-matching functions (CIE 015:2004, 5 nm, 360..830 nm) turn it into CIE XYZ; the IEC
// 61966-2-1 matrix turns that into linear sRGB. A BlackbodyRamp tabulates those colours over a
// temperature range, so a shader can look up T = T0 + T1 * detail in a 1D texture.
#pragma once

#include <filesystem>
#include <vector>

#include <glm/vec3.hpp>

#include <puff/core/error.h>
#include <puff/core/image.h>

namespace puff::core {

inline constexpr double kMaxKelvin = 1e5;          ///< highest temperature a ramp may cover
inline constexpr int kMaxBlackbodyTexels = 65536;  ///< most texels in a ramp
/// What a black-body ramp file may be, checked from its header before decoding: at most 65536
/// wide and 16 rows, 1 to 4 channels, a file of at most 16 MiB (readBlackbodyRamp then wants N x 1 RGB).
inline constexpr ImageLimits kBlackbodyRampLimits{"a black-body ramp",        kMaxBlackbodyTexels,     16, 4,
                                                  16ll * kMaxBlackbodyTexels, std::uintmax_t{16} << 20};

/// Planck's law: spectral radiance 2hc^2 / lambda^5 / (exp(hc / (lambda k T)) - 1) in W sr^-1 m^-3,
/// for a wavelength in metres and a temperature in kelvin (CODATA 2018 h, c, k). Both must be > 0
/// (PUFF_CHECK); an exponent that overflows gives 0 (no light at that wavelength).
double planckRadiance(double lambdaMetres, double kelvin);

/// CIE XYZ of a black body's spectral radiance at `kelvin` (> 0): the integral of
/// planckRadiance(lambda, T) times x-bar, y-bar, z-bar over 360..830 nm, by the trapezoid rule on
/// the table's 5 nm grid. Unnormalized (W sr^-1 m^-2; multiply Y by 683 lm/W for luminance).
glm::dvec3 blackbodyXYZ(double kelvin);

/// CIE XYZ to linear sRGB (D65) and back, with the matrices IEC 61966-2-1 prints (4 decimals;
/// they are each other's inverse to about 1e-4). Out-of-gamut colours give negative components.
glm::dvec3 xyzToLinearSrgb(glm::dvec3 xyz);
glm::dvec3 linearSrgbToXyz(glm::dvec3 rgb);

/// Black-body colours over a temperature range, in linear sRGB, scaled so that luminance Y is 1 at
/// normalizeKelvin (a fire's brightness is relative to a chosen temperature; hotter is brighter).
/// Components are NOT clamped: at low temperatures blue (and at high ones red) may be negative,
/// because those colours lie outside the sRGB gamut. Shaders clamp at use; the table keeps the
/// truth so its chromaticity is exact.
struct BlackbodyRamp {
  double minKelvin = 0, maxKelvin = 0, normalizeKelvin = 0;
  /// Linear sRGB, `size` texels: texel i is the colour at T = min + i * (max - min) / (size - 1).
  std::vector<glm::vec3> rgb;

  /// The colour at `kelvin`, linearly interpolated between texels; clamped to the end texels
  /// outside [minKelvin, maxKelvin]. The ramp must hold at least 2 texels (PUFF_CHECK).
  glm::vec3 at(double kelvin) const;
};

/// Tabulates a ramp. Errors name the value and its range: 0 < minKelvin < maxKelvin <= 1e5,
/// size in [2, 65536], normalizeKelvin in (0, 1e5]; also a normalizeKelvin so cold that it gives
/// no visible light, or values that overflow 32-bit floats (a cold normalizeKelvin with a hot
/// maxKelvin).
Result<BlackbodyRamp> makeBlackbodyRamp(double minKelvin, double maxKelvin, int size, double normalizeKelvin);

/// Writes a ramp as a size x 1 RGB 32-bit float EXR with the attributes puff:minKelvin,
/// puff:maxKelvin and puff:normalizeKelvin (decimal text, exact). Atomic: a temporary file beside
/// `path` is renamed over it when complete, so a failure leaves any existing file untouched.
/// Errors name the file (cannot create its directory, cannot write).
Result<void> writeBlackbodyRamp(const std::filesystem::path& path, const BlackbodyRamp& ramp);

/// Reads a ramp written by writeBlackbodyRamp. Errors name the file: unreadable, not size x 1 RGB,
/// an attribute missing or not a number, or values out of the ranges makeBlackbodyRamp accepts.
Result<BlackbodyRamp> readBlackbodyRamp(const std::filesystem::path& path);

}  // namespace puff::core
