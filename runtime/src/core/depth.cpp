// Depth conventions (core/depth.h): linear depth to what an attachment stores, and back.
#include <algorithm>
#include <cmath>

#include <puff/core/depth.h>

namespace puff::core {

float storedDepth(const DepthSpace& space, float linear) {
  if (space.convention == DepthConvention::kLinear) return linear;
  // The same arithmetic as frame.glsl's storeDepth, in float, so the two agree to rounding.
  const float dist = space.nearPlane + std::max(linear, 0.0f) * (space.farPlane - space.nearPlane);
  const glm::mat4& p = space.projection;
  const float z = p[3][2] - p[2][2] * dist, w = p[3][3] - p[2][3] * dist;
  const float ndc = z / w;
  return std::clamp(space.clipDepth == ClipDepth::kZeroToOne ? ndc : 0.5f * ndc + 0.5f, 0.0f, 1.0f);
}

float linearFromStored(const DepthSpace& space, float stored) {
  if (space.convention == DepthConvention::kLinear) return std::clamp(stored, 0.0f, 1.0f);
  // The same arithmetic as media/host_depth.glsl's linearFromStored. ndc = (A z + B) / (C z + D)
  // for the projection's z row (A, B) and w row (C, D) at camera z; solved for z = -distance.
  // The far plane's stored value (what the buffer clears to) is "no surface" exactly: through the
  // projection in float it reads ~1 - 1e-6 for standard depth, and a light would take the sky
  // for a surface just in front of the far plane.
  if (space.convention == DepthConvention::kStandard ? stored >= 1.0f : stored <= 0.0f) return 1.0f;
  const glm::mat4& p = space.projection;
  const float ndc = space.clipDepth == ClipDepth::kZeroToOne ? stored : 2.0f * stored - 1.0f;
  const float a = p[2][2], b = p[3][2], c = p[2][3], d = p[3][3];
  const float den = ndc * c - a;
  const float num = b - ndc * d;  // z = num / den; distance = -z
  // den == 0: the infinite far plane (reversed-z stores 0 there).
  if (den == 0.0f || !std::isfinite(num / den)) return 1.0f;
  const float dist = -num / den;
  const float lin = (dist - space.nearPlane) / (space.farPlane - space.nearPlane);
  return std::isnan(lin) ? 1.0f : std::clamp(lin, 0.0f, 1.0f);
}

}  // namespace puff::core
