// Phase functions (Umenhoffer §3.1) and the names of the media enums.
#include <cmath>
#include <numbers>

#include <puff/media/media.h>

namespace puff::media {

std::string_view toString(Method m) {
  switch (m) {
    case Method::kPlanar:
      return "planar";
    case Method::kSoftLinear:
      return "soft-linear";
    case Method::kSoftSCurve:
      return "soft-scurve";
    case Method::kSpherical:
      return "spherical";
    case Method::kPlanarTextured:
      return "planar-textured";
  }
  return "?";
}

std::optional<Method> parseMethod(std::string_view name) {
  for (Method m :
       {Method::kPlanar, Method::kSoftLinear, Method::kSoftSCurve, Method::kSpherical, Method::kPlanarTextured})
    if (name == toString(m)) return m;
  return std::nullopt;
}

std::string_view toString(PhaseModel m) {
  return m == PhaseModel::kCornetteShanks ? "cornette-shanks" : "henyey-greenstein";
}

std::optional<PhaseModel> parsePhaseModel(std::string_view name) {
  if (name == "cornette-shanks") return PhaseModel::kCornetteShanks;
  if (name == "henyey-greenstein") return PhaseModel::kHenyeyGreenstein;
  return std::nullopt;
}

std::string_view toString(SortKey k) { return k == SortKey::kPowerDistance ? "power-distance" : "view-depth"; }

std::optional<SortKey> parseSortKey(std::string_view name) {
  if (name == "view-depth") return SortKey::kViewDepth;
  if (name == "power-distance") return SortKey::kPowerDistance;
  return std::nullopt;
}

double phase(PhaseModel model, double c, double g) {
  const double g2 = g * g;
  const double denom = std::pow(1.0 + g2 - 2.0 * g * c, 1.5);
  constexpr double kInv4Pi = 1.0 / (4.0 * std::numbers::pi);
  if (model == PhaseModel::kHenyeyGreenstein) return kInv4Pi * (1.0 - g2) / denom;
  // Cornette & Shanks 1992, as Umenhoffer et al. print it: 3/2 (1-g^2)/(2+g^2) (1+c^2)/(1+g^2-2gc)^1.5
  // over 4 pi. At g = 0 it is the Rayleigh shape 3/(16 pi) (1 + c^2), not isotropic.
  return kInv4Pi * 3.0 * (1.0 - g2) * (1.0 + c * c) / (2.0 * (2.0 + g2) * denom);
}

}  // namespace puff::media
