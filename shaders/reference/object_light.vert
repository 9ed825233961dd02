#version 450 core
// The cel reference's shadow map passes for opaque objects (puff::cel::OpaqueRenderer::drawGeometry):
// the object's triangles seen from the light, as puff_mesh.vert places the puffs there.
layout(location = 0) in vec3 aPosition;  // object space

#include "common/contract.glsl"
layout(location = PUFF_LOC_OPAQUE_MODEL) uniform mat4 uModel;  // object -> world
uniform mat4 uLightView;                   // world -> light space (light looks along -z)
uniform mat4 uLightProj;                   // light space -> clip (orthographic)

out float vDist;  // -z_light

void main() {
  vec4 lv = uLightView * (uModel * vec4(aPosition, 1.0));
  vDist = -lv.z;
  gl_Position = uLightProj * lv;
}
