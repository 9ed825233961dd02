#version 450 core
// Opaque objects drawn from the light into the shadow map (puff::cel::OpaqueRenderer::drawCasters):
// their near surface's depth in the light's frame and their caster id, so they shadow puffs and
// each other (an object never shadows itself: cel/shadow_map.glsl).
#include "common/frame.glsl"

in float vDist;

layout(location = PUFF_LOC_OPAQUE_ID) uniform uint uId;

layout(location = 0) out uint oId;

void main() {
  gl_FragDepth = storeDepth(linearDepth(vDist));
  oId = uId;
}
