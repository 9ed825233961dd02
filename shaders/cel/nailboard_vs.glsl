// Nailboards (McGuire & Fein §4.1-4.2): each particle becomes a quad here, by vertex pulling from
// the 16-byte records (no per-vertex data leaves the CPU). 6 vertices per particle. Compiled with
// PUFF_VIEWS = 1 (one baked view per variation: nailboard.vert) or 4 (a multi-view atlas, the
// four nearest views blended: nailboard_views.vert), so every array index is a constant.
#include "common/frame.glsl"
#include "cel/particle.glsl"

#define PUFF_VERTEX_STAGE
#include "cel/nailboard_io.glsl"
#include "cel/nailboard_setup.glsl"

// The shadow map's caster pass (NailboardRenderer::drawShadowCasters, the light's frame bound):
// 1, with the eye's camera right and up (world), so an unoriented puff faces the light in
// lightFacingFrame. 0 in every other pass.
uniform int uCaster;
uniform vec3 uEyeRight;
uniform vec3 uEyeUp;
#if PUFF_VIEWS == 4
// Which particles this draw takes (cel::detail::TumbleShare): 0 all; 1 those that take the hull
// (vHull), 2 the others.
uniform int uTumbleShare;
#endif


const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
  uint index = uint(gl_VertexID) / 6u;
  vec2 corner = kCorners[gl_VertexID % 6];
  Particle p = unpackParticle(index);
  mat3 bb = uCaster == 1 ? lightFacingFrame(uInvView[2].xyz, uEyeRight, uEyeUp) : billboardFrame(p);
  float pxPerDiameter = setUpParticle(index, p, bb);
  // The quad covers the whole cell (margin included) so the outline can reach past the silhouette;
  // a puff so small that its band and antialiased edge (outline width + 1.5 pixels) reach past the
  // cell gets a quad that holds them: the silhouette lies within half a diameter of the centre.
#ifdef PUFF_HULL_OCCLUDER
  // The hull's occluder pass: the disc of the puff's core (a ball inside its hull) through the core's
  // centre, facing along the march's rays, where the march hits the hull before the disc
  // (nailboard_fs.glsl, hullOccluded); a pixel and a half inside its rim, where the ray's chord
  // through the core is long beside the march's least step (a quarter pixel) and the filtered
  // field's rounding near the rim.
  vec4 core = cells[vCell.x].core;
  float towardEye = vNormalXf[0][2].z;  // view z of the billboard's normal: diameters along it -> view depth
  float radius = core.w - 1.5 / pxPerDiameter;
  vec2 centre = vec2(dot(core.xyz, vBillboardPuff[0]), dot(core.xyz, vBillboardPuff[1]));
  vDisc = vec4(centre, radius, dot(core.xyz, vBillboardPuff[2]) * towardEye * p.size);
  vPuff = centre + corner * radius;
  bool occludes = vHull == 1 && radius > 0.0 && towardEye > 0.0;
#else
  float halfCell = 0.5 * uAtlasGeom.z / uAtlasScale.x;  // cell half-width in puff diameters
  float band = (uOutlines == 1 ? max(0.0, uOutlineWidth) : 0.0) + 1.5;
  vPuff = corner * max(halfCell, 0.5 + band / pxPerDiameter);
  const bool occludes = true;
#endif
  vec3 world = p.position + p.size * (vPuff.x * bb[0] + vPuff.y * bb[1]);
  vec4 viewPos = uView * vec4(world, 1.0);
  vDist = -viewPos.z;
  vWorld = world;
  bool drawn = p.size > 0.0 && occludes;
#if PUFF_VIEWS == 4
  drawn = drawn && (uTumbleShare == 0 || (vHull == 1) == (uTumbleShare == 1));
#endif
  gl_Position = drawn ? uProj * viewPos : vec4(2.0, 2.0, 2.0, 1.0);  // (outside the clip volume: nothing drawn)
}
