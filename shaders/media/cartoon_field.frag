#version 450 core
// The cartoon style, pass 1 (layers.h, "Cartoon media"): the media layer and its cartoon attributes
// upsampled to the output's size as compose.frag upsamples the layer, and each pixel's flat fill,
// accumulated opacity and medium depth.
#include "media/compose.glsl"
#include "media/cartoon.glsl"

layout(binding = 5) uniform sampler2D uCartoonFire;   // (sum a e s, sum a e, sum a e w, A)
layout(binding = 6) uniform sampler2D uCartoonDepth;  // (sum a lin, sum free T, 0, A)

layout(location = 0) out vec4 outFill;   // cartoonFill
// x: accumulated opacity A, y: the medium's linear depth, z: its opacity without the opaque
// surfaces' clipping (>= A; common/media.glsl)
layout(location = 1) out vec4 outField;

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy);  // drawn into Layers' own full-size target
  vec2 shimmer;
  const Taps k = mediaTaps(p, shimmer);
  const vec4 fire = upsample(uCartoonFire, k);
  const float A = clamp(fire.a, 0.0, 1.0);
  const vec4 depth = upsample(uCartoonDepth, k);
  outField = vec4(A, A > 0.0 ? depth.r / fire.a : 1.0, clamp(depth.g, 0.0, 1.0), 0.0);
  outFill = cartoonFill(upsample(uMedia, k).rgb, fire, fire.a);
}
