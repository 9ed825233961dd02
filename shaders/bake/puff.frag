#version 450 core
// Writes the unencoded bake samples; the CPU resolve averages, dilates and encodes them (Eq. 1).
in vec3 vNormal;
in vec3 vColor;
in float vDepth;

layout(location = 0) out vec4 oNormalDepth;  // camera-space unit normal, camera-space z
layout(location = 1) out vec4 oColor;        // diffuse colour, coverage 1

void main() {
  oNormalDepth = vec4(normalize(vNormal), vDepth);
  oColor = vec4(vColor, 1.0);
}
