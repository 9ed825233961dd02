#version 450 core
// The cel reference: the supersampled image box-filtered to the output (uFactor^2 samples a pixel).
layout(binding = 0) uniform sampler2D uImage;
uniform int uFactor;
uniform ivec2 uOrigin;  // the output viewport's origin, pixels

layout(location = 0) out vec4 oColor;

void main() {
  ivec2 base = (ivec2(gl_FragCoord.xy) - uOrigin) * uFactor;
  vec4 sum = vec4(0.0);
  for (int y = 0; y < uFactor; ++y)
    for (int x = 0; x < uFactor; ++x) sum += texelFetch(uImage, base + ivec2(x, y), 0);
  oColor = sum / float(uFactor * uFactor);
}
