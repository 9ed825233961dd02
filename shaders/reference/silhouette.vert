#version 450 core
// The cel reference's outlines (silhouette.geom): the puff meshes' vertices in camera space.
#include "common/frame.glsl"

layout(location = 0) in vec3 aPosition;

struct Instance {
  vec4 row0, row1, row2;
  uvec4 id;
};
layout(std430, binding = 0) readonly buffer Instances { Instance instances[]; };
uniform int uFirst;

out vec3 vView;  // camera space
flat out uint vId;

void main() {
  Instance inst = instances[uFirst + gl_InstanceID];
  mat4 model = transpose(mat4(inst.row0, inst.row1, inst.row2, vec4(0.0, 0.0, 0.0, 1.0)));
  vView = (uView * model * vec4(aPosition, 1.0)).xyz;
  vId = inst.id.x;
  gl_Position = uProj * vec4(vView, 1.0);
}
