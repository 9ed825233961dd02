#version 450 core
// Opaque scene objects of the cel frame (puff::cel::OpaqueRenderer): a triangle mesh placed by its
// model transform, passing the camera-space normal and view-axis distance on to opaque.frag.
#include "common/frame.glsl"

layout(location = 0) in vec3 aPosition;  // object space
layout(location = 1) in vec3 aNormal;    // object space

layout(location = PUFF_LOC_OPAQUE_MODEL) uniform mat4 uModel;         // object -> world
layout(location = PUFF_LOC_OPAQUE_NORMAL_MATRIX) uniform mat3 uNormalMatrix;  // inverse transpose of mat3(uModel)

out vec3 vNormalView;  // camera space, not normalized
out float vDist;       // -z_view: view-axis distance, affine in camera space so interpolation is exact
out vec3 vWorld;       // world space (shadow-map receivers)

void main() {
  vec4 world = uModel * vec4(aPosition, 1.0);
  vec4 view = uView * world;
  // Normals go through the inverse transpose of the view's 3x3 too, which is transpose(mat3(uInvView)):
  // exact for any invertible view matrix, not only rigid ones.
  vNormalView = transpose(mat3(uInvView)) * (uNormalMatrix * aNormal);
  vDist = -view.z;
  vWorld = world.xyz;
  gl_Position = uProj * view;
}
