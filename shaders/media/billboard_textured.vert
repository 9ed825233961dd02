#version 450 core
// The classic textured billboard (media::Method::kPlanarTextured; the "planar" billboards of
// Umenhoffer et al.'s Table 1): one camera-facing quad per particle through the sphere's centre,
// half side r, carrying the baked falloff texture over [0, 1]^2. The near plane clips it whole (it
// pops), nothing clips its depth but the opaque depth test (billboard_textured.frag).
#include "common/media.glsl"

flat out vec4 vCentreRadius;  // camera-space centre, radius
flat out uvec4 vData;
flat out vec4 vTintTemperature;  // rgb: scene-linear tint; a: T0 (kelvin) when > 0
out vec2 vUv;    // [0, 1]^2 over the quad: the falloff texture's and the detail window's coordinates
out vec3 vView;  // camera-space point on the quad: the eye ray's direction there (perspective)

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
  const MediaParticle p = particles[gl_VertexID / 6];
  const vec2 corner = kCorners[gl_VertexID % 6];
  const vec3 c = (uView * vec4(p.positionRadius.xyz, 1.0)).xyz;
  const float r = p.positionRadius.w;
  vCentreRadius = vec4(c, r);
  vData = p.data;
  vTintTemperature = p.tintTemperature;
  vUv = corner * 0.5 + 0.5;
  const float dz = -c.z;
  // Nothing to draw: no size, wholly behind the camera's near plane or beyond the far plane.
  if (!(r > 0.0) || dz + r < uDepth.x || dz - r > uDepth.y) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  vView = vec3(c.xy + r * corner, c.z);
  gl_Position = uProj * vec4(vView, 1.0);
}
