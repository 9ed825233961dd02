#version 450 core
// The cel reference's shadow map passes for opaque objects, as puff_mesh.frag's modes 1 and 2 for the
// puffs: pass 1 the nearest surface's distance and its caster id; pass 2 the nearest surface of any
// caster other than the one pass 1 kept there.
in float vDist;

#include "common/contract.glsl"
layout(location = PUFF_LOC_OPAQUE_ID) uniform uint uId;  // kObjectIdBase + the object's index
uniform int uMode;                       // 1 or 2
layout(binding = 5) uniform usampler2D uShadowId;  // pass 1's ids (pass 2 only)

layout(location = 0) out vec4 oColor;  // distance in .r (R32F target)
layout(location = 1) out uint oId;

void main() {
  if (uMode == 2 && texelFetch(uShadowId, ivec2(gl_FragCoord.xy), 0).r == uId) discard;
  gl_FragDepth = gl_FragCoord.z;
  oColor = vec4(vDist);
  oId = uId;
}
