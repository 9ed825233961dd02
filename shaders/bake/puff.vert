#version 450 core
// Bakes one view of a puff mesh (McGuire & Fein Fig. 3): the mesh, already in the unit sphere, is
// rotated into the view's camera space and projected orthographically so the unit square
// [-1,1]^2 fills the viewport. Camera-space z is the signed offset toward the viewer from the
// billboard plane through the puff's center.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec3 aColor;

uniform mat3 uViewRotation;  // rows: camera right, up, toward the viewer

out vec3 vNormal;
out vec3 vColor;
out float vDepth;

void main() {
  vec3 p = uViewRotation * aPosition;
  vNormal = uViewRotation * aNormal;
  vColor = aColor;
  vDepth = p.z;
  // Nearer (larger z) must win the depth test: window depth grows away from the viewer.
  gl_Position = vec4(p.xy, -p.z * 0.5, 1.0);
}
