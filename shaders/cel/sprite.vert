#version 450 core
// The fill-rate floor the nailboards are measured against: the same particles and quads, the
// colour map alpha-tested and nothing else (no shading, no depth offset, no outlines).
#include "common/frame.glsl"
#include "cel/particle.glsl"

out vec2 vUv;

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
  uint index = uint(gl_VertexID) / 6u;
  vec2 corner = kCorners[gl_VertexID % 6];
  Particle p = unpackParticle(index);
  mat3 bb = billboardFrame(p.position);
  float halfCell = 0.5 * uAtlasGeom.z / uAtlasScale.x;
  vec2 puff = corner * halfCell;
  vUv = cellUv(p.variation * max(1, uAtlasLayout.y), puff);
  vec3 world = p.position + p.size * (puff.x * bb[0] + puff.y * bb[1]);
  gl_Position = p.size > 0.0 ? uViewProj * vec4(world, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
}
