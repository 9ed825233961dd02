#version 450 core
// Where this pixel's eye ray enters (front face) or leaves (back face) the particle's shadow
// volume, written as the face's depth. In the light frame (x along e1, y along e2, in puff
// diameters; lambda along D, world units) the volume is
//   (x, y) inside the puff's silhouette,   s * (d(x, y) + bias) <= lambda <= lambda1
// where d is the puff's depth-map offset: the volume starts behind the puff's own far side, and
// its edge follows the silhouette, so shadow edges on the ground and on other puffs are wavy.
// The silhouette test marches the ray's shadow across the baked signed distance map (2D sphere
// tracing). Depths are clamped to the near plane, never negative.
#include "common/frame.glsl"
#include "cel/particle.glsl"

uniform float uShadowBias;

flat in vec3 vCenter;
flat in mat3 vLightFrame;
flat in vec4 vExtent;
flat in int vCell;

layout(binding = 2) uniform sampler2D uNormalDepth;
layout(binding = 4) uniform sampler2D uDistance;

// Intersects [t0, t1] with the ray parameters where lo <= c0 + t * c1 <= hi.
void clipSlab(float c0, float c1, float lo, float hi, inout float t0, inout float t1) {
  if (abs(c1) < 1e-12) {
    if (c0 < lo || c0 > hi) t1 = -1.0;
    return;
  }
  float ta = (lo - c0) / c1, tb = (hi - c0) / c1;
  t0 = max(t0, min(ta, tb));
  t1 = min(t1, max(ta, tb));
}

// Signed distance to the silhouette, in puff diameters, outside positive.
float silhouetteDistance(vec2 puff) {
  return (textureLod(uDistance, cellUv(vCell, puff), 0.0).r - 0.5) * 2.0 * uAtlasScale.z / uAtlasScale.x;
}

void main() {
  vec2 ndc = (gl_FragCoord.xy - uViewport.xy) / uViewport.zw * 2.0 - 1.0;
  mat4 invViewProj = inverse(uViewProj);
  vec4 pn = invViewProj * vec4(ndc, -1.0, 1.0), pf = invViewProj * vec4(ndc, 1.0, 1.0);
  vec3 origin = pn.xyz / pn.w;
  vec3 dir = pf.xyz / pf.w - origin;  // t in [0, 1]: near plane to far plane
  float s = vExtent.x;
  mat3 toLight = transpose(vLightFrame);
  vec3 c0 = toLight * (origin - vCenter), c1 = toLight * dir;
  c0.xy /= s;
  c1.xy /= s;
  float t0 = 0.0, t1 = 1.0;
  clipSlab(c0.x, c1.x, -0.5, 0.5, t0, t1);
  clipSlab(c0.y, c1.y, -0.5, 0.5, t0, t1);
  clipSlab(c0.z, c1.z, 0.0, vExtent.y, t0, t1);
  if (t1 <= t0) discard;

  const float kEps = 1e-3;
  float speed = length(c1.xy);
  float tIn = t0, tOut = t1;
  if (speed < 1e-7) {
    if (silhouetteDistance(c0.xy + t0 * c1.xy) > kEps) discard;
  } else {
    for (int i = 0; i < 24; ++i) {
      float d = silhouetteDistance(c0.xy + tIn * c1.xy);
      if (d <= kEps) break;
      tIn += d / speed;
      if (tIn > t1) discard;
    }
    for (int i = 0; i < 24; ++i) {
      float d = silhouetteDistance(c0.xy + tOut * c1.xy);
      if (d <= kEps) break;
      tOut -= d / speed;
    }
    if (tOut <= tIn) discard;
  }
  // The start cap follows the depth map: just past the puff's far side (its front mirrored).
  vec2 mid = c0.xy + 0.5 * (tIn + tOut) * c1.xy;
  float offset = max(0.0, (textureLod(uNormalDepth, cellUv(vCell, mid), 0.0).a - 0.5) * uAtlasScale.y);
  clipSlab(c0.z, c1.z, s * (offset + uShadowBias), vExtent.y, tIn, tOut);
  if (tOut <= tIn) discard;
  float t = gl_FrontFacing ? tIn : tOut;
  vec3 hit = origin + t * dir;
  gl_FragDepth = clamp(linearDepth(-(uView * vec4(hit, 1.0)).z), 0.0, 1.0);
}
