#version 450 core
// The cel reference's puff meshes (see puff_mesh.vert). uMode 0: Eq. 2 per pixel,
//   lit:      K_a(x, y) + C * K_L * q(N.L)      (shading off: K_a + C * K_L)
//   shadowed: K_a(x, y)                          (as the nailboards' shadowed pass)
// writing the frame's linear depth and the puff's id (for the outline and shadow passes).
// uMode 1: the light's nearest surface (distance, id). uMode 2: the nearest surface of any puff other
// than pass 1's there.
#include "common/frame.glsl"
#include "reference/shadow_test.glsl"

in vec3 vWorld;
in vec3 vNormalView;
in vec3 vColor;
in float vDist;
flat in uint vId;

uniform int uMode;
uniform int uShading;  // 1: q(N.L); 0: flat
uniform int uShadows;  // 1: test the shadow maps

layout(location = 0) out vec4 oColor;  // mode 0: colour; 1, 2: distance in .r (R32F target)
layout(location = 1) out uint oId;

void main() {
  if (uMode == 1) {
    gl_FragDepth = gl_FragCoord.z;  // written on every path: the light passes' depth test needs it
    oColor = vec4(vDist);
    oId = vId;
    return;
  }
  if (uMode == 2) {
    if (texelFetch(uShadowId, ivec2(gl_FragCoord.xy), 0).r == vId) discard;
    gl_FragDepth = gl_FragCoord.z;
    oColor = vec4(vDist);
    oId = vId;
    return;
  }
  gl_FragDepth = linearDepth(vDist);
  vec3 ka = ambientAt(gl_FragCoord.xy);
  vec3 rgb;
  if (uShadows == 1 && inShadow(vWorld, vId)) {
    rgb = ka;
  } else {
    // A closed puff shows only its outside; should a back face show (a mesh with holes), turn it.
    vec3 n = normalize(vNormalView);
    if (!gl_FrontFacing) n = -n;
    vec3 q = uShading == 1 ? quantize(dot(n, uLightDirView.xyz)) : vec3(1.0);
    rgb = ka + vColor * uLightColor.rgb * q;
  }
  oColor = vec4(srgbToLinear(clamp(rgb, 0.0, 1.0)), 1.0);  // Eq. 2 in display values (limited to 1), out linear
  oId = vId;
}
