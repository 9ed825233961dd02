#version 450 core
// The view transform (docs/colour.md), as puff::core::viewTransform: a scene-linear frame to
// display values, once, at the end. uView 0: standard (clip, then sRGB); 1: filmic (the largest
// channel rolled off above the knee, all three scaled alike so hue and saturation are kept).
#include "common/colour.glsl"
#include "common/contract.glsl"

layout(binding = 0) uniform sampler2D uLinear;  // scene-linear RGBA, the viewport's size
layout(location = PUFF_LOC_VIEW_TRANSFORM) uniform int uView;
layout(location = PUFF_LOC_VIEW_ORIGIN) uniform vec2 uOrigin;  // the output viewport's origin, pixels
layout(location = PUFF_LOC_VIEW_KNEE) uniform float uKnee;       // core::kFilmicKnee

layout(location = 0) out vec4 oColor;

float shoulder(float m) {
  return m <= uKnee ? m : uKnee + (1.0 - uKnee) * (1.0 - exp(-(m - uKnee) / (1.0 - uKnee)));
}

void main() {
  vec4 c = texelFetch(uLinear, ivec2(gl_FragCoord.xy - uOrigin), 0);
  vec3 rgb = max(c.rgb, vec3(0.0));
  if (uView == 1) {
    float m = max(rgb.r, max(rgb.g, rgb.b));
    if (m > uKnee) rgb *= shoulder(m) / m;
  }
  oColor = vec4(linearToSrgb(clamp(rgb, 0.0, 1.0)), clamp(c.a, 0.0, 1.0));
}
