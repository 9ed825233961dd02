#version 450 core
// The fill-rate floor the nailboards are measured against: the same particles and quads, the
// colour map alpha-tested and nothing else (no shading, no depth offset, no outlines). Its depth is
// the nailboards' convention (common/frame.glsl): the quad plane's LINEAR depth, written per pixel
// by sprite.frag as nailboard.frag writes it (less the per-pixel offset), so the floor passes and
// fails the depth test where the nailboards do and pays the same per-pixel depth write.
#include "common/frame.glsl"
#include "cel/particle.glsl"

out vec2 vUv;
out float vDist;  // camera-space distance along the view axis of the billboard plane here

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
  uint index = uint(gl_VertexID) / 6u;
  vec2 corner = kCorners[gl_VertexID % 6];
  Particle p = unpackParticle(index);
  mat3 bb = billboardFrame(p);
  float halfCell = 0.5 * uAtlasGeom.z / uAtlasScale.x;
  vec2 puff = corner * halfCell;
  vUv = cellUv(p.variation * max(1, uAtlasLayout.y), puff);
  vec3 world = p.position + p.size * (puff.x * bb[0] + puff.y * bb[1]);
  vec4 viewPos = uView * vec4(world, 1.0);
  vDist = -viewPos.z;
  gl_Position = p.size > 0.0 ? uProj * viewPos : vec4(2.0, 2.0, 2.0, 1.0);
}
