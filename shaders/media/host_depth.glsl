// A host's stored depth to Puff's linear depth (core/depth.h linearFromStored; media/layers.h,
// Layers::resolveHostDepth). For kStandard and kReversedZ, ndc = (A z + B) / (C z + D) from the
// host projection's z row (A, B) and w row (C, D) at camera z; solved for z = -distance.
#include "common/contract.glsl"
layout(location = PUFF_LOC_HOST_PROJ_ZW) uniform vec4 uProjZW;  // A = P[2][2], B = P[3][2], C = P[2][3], D = P[3][3]
layout(location = PUFF_LOC_HOST_PLANES) uniform vec4 uPlanes;  // near, far - near, convention (0 linear, 1 standard, 2 reversed-z), 1 if clip z is [0, 1]
layout(location = PUFF_LOC_HOST_ORIGIN) uniform ivec2 uOrigin;  // the layers' region in the host's texture

float linearFromStored(float stored) {
  if (uPlanes.z < 0.5) return clamp(stored, 0.0, 1.0);
  // The far plane's stored value (the clear) is "no surface" exactly (core/depth.cpp says why).
  if (uPlanes.z < 1.5 ? stored >= 1.0 : stored <= 0.0) return 1.0;
  const float ndc = uPlanes.w > 0.5 ? stored : 2.0 * stored - 1.0;
  const float den = ndc * uProjZW.z - uProjZW.x;
  const float num = uProjZW.y - ndc * uProjZW.w;
  if (den == 0.0) return 1.0;  // reversed-z's infinite far plane
  const float lin = (-num / den - uPlanes.x) / uPlanes.y;
  return isnan(lin) || isinf(lin) ? 1.0 : clamp(lin, 0.0, 1.0);
}
