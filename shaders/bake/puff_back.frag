#version 450 core
// The back map's samples (PuffRasterizer::render with `back`): drawn with no depth test and GL_MIN
// blending, so each sample keeps the least camera-space z of every fragment: the farthest point
// where its ray crosses the mesh.
in vec3 vNormal;
in vec3 vColor;
in float vDepth;

layout(location = 0) out float oFarthest;

void main() { oFarthest = vDepth; }
