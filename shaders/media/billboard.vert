#version 450 core
// One quad per particle from the sorted particle buffer (6 vertices each, by gl_VertexID).
// Spherical: perpendicular to the camera's z at the sphere's FAR point (Umenhoffer §2), sized to
// cover the sphere's whole projection; a sphere that reaches the camera's plane gets a quad over
// the whole target. Planar methods: the classic billboard through the centre, which the near
// plane clips whole (that is the popping the spherical method removes).
#include "common/media.glsl"

flat out vec4 vCentreRadius;  // camera space centre, radius
flat out uvec4 vData;
flat out vec4 vTintTemperature;  // rgb: scene-linear tint; a: T0 (kelvin) when > 0

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
  const MediaParticle p = particles[gl_VertexID / 6];
  const vec2 corner = kCorners[gl_VertexID % 6];
  const vec3 c = (uView * vec4(p.positionRadius.xyz, 1.0)).xyz;
  const float r = p.positionRadius.w;
  vCentreRadius = vec4(c, r);
  vData = p.data;
  vTintTemperature = p.tintTemperature;
  const float dz = -c.z;  // distance along the view axis
  const bool ortho = uDepth.w > 0.5;
  // Nothing to draw: no size, wholly behind the camera's near plane or beyond the far plane.
  if (!(r > 0.0) || dz + r < uDepth.x || dz - r > uDepth.y) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  if (uMode.x != kSpherical) {
    // The billboard through the centre, large enough for the sphere's perspective silhouette (the
    // bound below at the centre's depth), at most 4 r.
    const float h = ortho ? r : min(4.0 * r, dz * r / max(dz - r, 1e-6) * (1.0 + length(c.xy) / dz));
    gl_Position = uProj * vec4(c.xy + h * corner, c.z, 1.0);
    return;
  }
  const float zq = dz + r;  // the far point
  if (ortho) {
    gl_Position = uProj * vec4(c.xy + r * corner, -zq, 1.0);
    return;
  }
  if (dz - r < 0.05 * dz) {  // the sphere reaches the camera's plane: cover the target
    gl_Position = vec4(corner, 0.0, 1.0);
    return;
  }
  // Every point X of the sphere projects onto the plane at zq within
  // zq * r / (dz - r) * (1 + |c.xy| / dz) of the projected centre c.xy * zq / dz.
  const float h = zq * r / (dz - r) * (1.0 + length(c.xy) / dz);
  gl_Position = uProj * vec4(c.xy * (zq / dz) + h * corner, -zq, 1.0);
}
