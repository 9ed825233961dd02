#version 450 core
// Opaque objects' shadow volumes (puff::cel::OpaqueRenderer::drawShadowVolumes): the mesh's vertices
// in world space, for opaque_volume.geom to extrude along the light.
layout(location = 0) in vec3 aPosition;  // object space

#include "common/contract.glsl"
layout(location = PUFF_LOC_OPAQUE_MODEL) uniform mat4 uModel;  // object -> world

out vec3 vWorldPos;  // world space

void main() { vWorldPos = (uModel * vec4(aPosition, 1.0)).xyz; }
