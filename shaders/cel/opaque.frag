#version 450 core
// Opaque scene objects, lit like the puffs (McGuire & Fein Eq. 2) and writing the frame's LINEAR
// depth, stored in the frame's convention (storeDepth). One program serves every ShadePass, so the
// depth a kShadowed pass compares with GL_EQUAL is computed by exactly the same code as the depth the
// kLit or kDepthOnly pass wrote.
//   lit, cel:    albedo * (K_a + K_L * q(max(0, N.L)))
//   lit, smooth: albedo * (K_a + K_L * max(0, N.L))
//   shadowed:    albedo * K_a       (the kShadowed pass, or a lit pass whose shadow map says so)
#include "common/frame.glsl"
#include "cel/shadow_map.glsl"

in vec3 vNormalView;
in float vDist;
in vec3 vWorld;

layout(location = PUFF_LOC_OPAQUE_ALBEDO) uniform vec3 uAlbedo;
layout(location = PUFF_LOC_OPAQUE_CEL) uniform int uCel;   // 1: through the ramp q, 0: smooth Lambert
layout(location = PUFF_LOC_OPAQUE_PASS) uniform int uPass;  // PUFF_PASS_LIT, _SHADOWED or _DEPTH_ONLY
layout(location = PUFF_LOC_OPAQUE_ID) uniform uint uId;   // the object's caster id in the shadow map

layout(location = 0) out vec4 oColor;

void main() {
  gl_FragDepth = storeDepth(linearDepth(vDist));
  if (uPass == PUFF_PASS_DEPTH_ONLY) {
    oColor = vec4(0.0);  // colour writes are masked off; keep the ramp lookups out of the depth pass
    return;
  }
  // Culling is off so a plane shows both sides: turn the normal toward the viewer on back faces.
  // (The renderer flips glFrontFace for mirroring transforms, so "front" stays "outside".)
  vec3 n = normalize(vNormalView);
  if (!gl_FrontFacing) n = -n;
  if (uOutput.x != PUFF_OUTPUT_COLOUR) {
    oColor = vec4(mapValue(n, vDist, 0.0, vec2(0.0)), 1.0);  // objects' own motion is not written
    return;
  }
  vec3 ambient = ambientAt(gl_FragCoord.xy);
  if (uPass == PUFF_PASS_SHADOWED || (shadowMapEnabled() && inShadowMap(vWorld, uId))) {
    oColor = vec4(srgbToLinear(clamp(uAlbedo * ambient, 0.0, 1.0)), 1.0);
    return;
  }
  float nDotL = dot(n, uLightDirView.xyz);
  vec3 diffuse = uCel != 0 ? quantize(nDotL) : vec3(max(0.0, nDotL));
  // Eq. 2 in display values, limited to the display's range (as an 8-bit frame buffer limits it), out linear.
  oColor = vec4(srgbToLinear(clamp(uAlbedo * (ambient + uLightColor.rgb * diffuse), 0.0, 1.0)), 1.0);
}
