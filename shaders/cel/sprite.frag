#version 450 core
in vec2 vUv;
layout(binding = 3) uniform sampler2D uColor;
out vec4 fragColor;

void main() {
  vec4 c = texture(uColor, vUv);
  if (c.a < 0.5) discard;
  fragColor = c;
}
