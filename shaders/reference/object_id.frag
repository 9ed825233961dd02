#version 450 core
// The cel reference: each opaque object's caster id into the frame's id buffer (attachment 1), over
// the pixels it showed in its lit pass (depth LEQUAL against what that pass wrote, nudged toward the
// eye by a millionth so rounding in another program cannot lose a pixel), so the shadow pass knows
// which object a pixel shows (an object never shadows itself, as in the shadow map method).
#include "common/frame.glsl"

in float vDist;

layout(location = PUFF_LOC_OPAQUE_ID) uniform uint uId;

layout(location = 0) out vec4 oColor;  // not written: attachment 0 is masked off
layout(location = 1) out uint oId;

void main() {
  gl_FragDepth = linearDepth(vDist) - 1e-6;
  oColor = vec4(0.0);
  oId = uId;
}
