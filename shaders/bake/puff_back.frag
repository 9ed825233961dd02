#version 450 core
// The back map's samples (PuffRasterizer::render with `back`): drawn with no depth test and blending
// that adds red (each fragment one crossing of the sample's ray with the mesh) and keeps the least
// alpha (the farthest crossing's camera-space z).
in vec3 vNormal;
in vec3 vColor;
in float vDepth;

layout(location = 0) out vec4 oCrossing;

void main() { oCrossing = vec4(1.0, 0.0, 0.0, vDepth); }
