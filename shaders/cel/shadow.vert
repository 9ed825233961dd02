#version 450 core
// Billboard shadow volumes (McGuire & Fein §4.3): per particle, one front-facing and one
// back-facing face that cover exactly the same pixels; the billboard is the third polygon.
//
// The proxy is the puff's silhouette seen from the light (its distance map) swept along the
// direction D the light travels: a prism with cross-section perpendicular to D. The paper's proxy,
// a square containing the view direction, collapses to a sliver when the light is near the view
// axis (a back-lit cloud) and can never contain the eye; this one stays a full shadow from any
// side, and the camera can stand inside it. docs/cel-rendering.md has the comparison.
//
// The faces are drawn over a conservative footprint (the screen rectangle around the prism, or
// the whole screen when the prism reaches the eye); the fragment shader finds where the eye ray
// enters and leaves the volume and writes that depth, so both faces always cover the same pixels
// and the depth-fail count is exact with the camera inside a volume or a volume through the near
// plane. 12 vertices per particle: the front face counter-clockwise, then the back face clockwise.
#include "common/frame.glsl"
#include "cel/particle.glsl"

uniform float uShadowBias;    // volume starts this many diameters past the puff's far side
uniform float uShadowLength;  // world units
uniform vec4 uShadowFloor;    // world plane (n, w): volumes end a diameter past it; n = 0: none

flat out vec3 vCenter;
flat out mat3 vLightFrame;  // columns e1, e2, D: world axes of the volume (orthonormal)
flat out vec4 vExtent;      // size, lambda end (world), 0, 0
flat out int vCell;

const int kQuad[6] = int[](0, 1, 2, 0, 2, 3);

void main() {
  uint index = uint(gl_VertexID) / 12u;
  int local = gl_VertexID % 12;
  bool backFace = local >= 6;
  Particle p = unpackParticle(index);
  float s = p.size;
  if (s <= 0.0) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  vec3 D = -uLightDirWorld.xyz;
  vec3 ref = abs(D.y) > 0.99 ? vec3(0.0, 0.0, 1.0) : vec3(0.0, 1.0, 0.0);
  vec3 e1 = normalize(cross(ref, D));
  vec3 e2 = cross(D, e1);
  float lambda1 = uShadowLength;
  float dn = dot(uShadowFloor.xyz, D);
  if (dot(uShadowFloor.xyz, uShadowFloor.xyz) > 0.0 && dn < -1e-4) {
    float toFloor = (dot(uShadowFloor.xyz, p.position) + uShadowFloor.w) / -dn;
    lambda1 = clamp(toFloor + s, 0.0, lambda1);
  }
  vCenter = p.position;
  vLightFrame = mat3(e1, e2, D);
  vExtent = vec4(s, lambda1, 0.0, 0.0);
  // The cell whose view is nearest the light's: the silhouette the light sees.
  mat3 bb = billboardFrame(p.position);
  ivec4 cell;
  vec4 weight;
  selectViews(p, transpose(puffFrame(p, bb)) * uLightDirWorld.xyz, cell, weight);
  int best = 0;
  for (int k = 1; k < 4; ++k) {
    if (weight[k] > weight[best]) best = k;
  }
  vCell = cell[best];

  // Conservative footprint: the screen rectangle around the prism's eight corners.
  vec2 lo = vec2(1e30), hi = vec2(-1e30);
  bool reachesEye = false;
  for (int i = 0; i < 8; ++i) {
    vec3 corner = p.position + 0.5 * s * ((i & 1) != 0 ? e1 : -e1) + 0.5 * s * ((i & 2) != 0 ? e2 : -e2) +
                  ((i & 4) != 0 ? lambda1 : -0.5 * s) * D;
    vec4 clip = uViewProj * vec4(corner, 1.0);
    if (!isOrthographic() && clip.w < uDepthRange.x * 1.01) reachesEye = true;
    vec2 ndc = clip.xy / max(clip.w, 1e-6);
    lo = min(lo, ndc);
    hi = max(hi, ndc);
  }
  if (reachesEye) {
    lo = vec2(-1.0);
    hi = vec2(1.0);
  }
  lo = clamp(lo, vec2(-1.0), vec2(1.0));
  hi = clamp(hi, vec2(-1.0), vec2(1.0));
  vec2 corners[4] = vec2[](lo, vec2(hi.x, lo.y), hi, vec2(lo.x, hi.y));  // counter-clockwise
  int k = kQuad[local % 6];
  if (backFace) k = (4 - k) % 4;  // the same quad, clockwise
  gl_Position = vec4(corners[k], 0.0, 1.0);
}
