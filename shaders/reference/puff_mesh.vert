#version 450 core
// The cel reference (puff::render RenderPath::kReference): each particle drawn as its actual
// puff mesh, instanced, placed by an affine model matrix (position, puff frame, size / 2: the mesh lies
// in the unit sphere and the particle's size is the puff's diameter). uMode 0: the camera's view
// (Eq. 2 shading in puff_mesh.frag); 1 and 2: the light's view (the shadow map's two passes).
#include "common/frame.glsl"

layout(location = 0) in vec3 aPosition;  // puff space, |p| <= 1
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec3 aColor;     // C as baked (sRGB-encoded values, used as is like the atlas's)

struct Instance {
  vec4 row0, row1, row2;  // model matrix rows: puff -> world
  uvec4 id;               // x: the particle's id (its index + 1; 0 means "no puff"); yzw: its tint (float bits)
};
layout(std430, binding = 0) readonly buffer Instances { Instance instances[]; };

uniform int uFirst;          // instance index of this draw's first particle
uniform int uMode;           // 0 camera, 1 / 2 light
uniform mat4 uLightView;     // world -> light space (light looks along -z)
uniform mat4 uLightProj;     // light space -> clip (orthographic)

out vec3 vWorld;
out vec3 vNormalView;
out vec3 vColor;
out float vDist;  // camera: -z_view; light: -z_light
flat out uint vId;

void main() {
  Instance inst = instances[uFirst + gl_InstanceID];
  mat4 model = transpose(mat4(inst.row0, inst.row1, inst.row2, vec4(0.0, 0.0, 0.0, 1.0)));
  vec4 world = model * vec4(aPosition, 1.0);
  vWorld = world.xyz;
  vId = inst.id.x;
  vColor = aColor * uintBitsToFloat(inst.id.yzw);  // the particle's tint multiplies C (display values)
  // The model is a rotation times a uniform scale: its 3x3 turns normals as it turns vectors.
  vec3 nWorld = mat3(model) * aNormal;
  vNormalView = transpose(mat3(uInvView)) * nWorld;
  if (uMode == 0) {
    vec4 view = uView * world;
    vDist = -view.z;
    gl_Position = uProj * view;
  } else {
    vec4 lv = uLightView * world;
    vDist = -lv.z;
    gl_Position = uLightProj * lv;
  }
}
