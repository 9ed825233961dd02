#version 450 core
// One quad per particle from the sorted particle buffer (6 vertices each, by gl_VertexID).
// Spherical: perpendicular to the camera's z at the sphere's FAR point (Umenhoffer §2), over the
// box the sphere's silhouette projects into (exact, an eighth of a pixel's margin), so no more fragments run
// than the silhouette's box holds; a sphere that reaches the camera's plane gets a quad over the
// whole target. Planar methods: the classic billboard through the centre, which the near
// plane clips whole (that is the popping the spherical method removes).
#include "common/media.glsl"

flat out vec4 vCentreRadius;  // camera space centre, radius
flat out uvec4 vData;
flat out vec4 vTintTemperature;  // rgb: scene-linear tint; a: T0 (kelvin) when > 0

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

// The extremes of x / dz over a sphere (centre (cx, dz) in the plane of one screen axis and the view
// axis, radius r, the eye outside it): the slopes of the two lines from the eye tangent to its
// circle, tan(phi -+ theta) with tan(phi) = cx / dz, sin(theta) = r / |(cx, dz)|. False when a
// tangent line does not run forward (the silhouette is unbounded on that side).
bool tangentSlopes(float cx, float dz, float r, out vec2 slopes) {
  const float t = sqrt(max(cx * cx + dz * dz - r * r, 0.0));
  const float lo = dz * t + r * cx, hi = dz * t - r * cx;
  if (!(lo > 0.0) || !(hi > 0.0)) return false;
  slopes = vec2((cx * t - r * dz) / lo, (cx * t + r * dz) / hi);
  return true;
}

// The normalized-device box (xmin, ymin, xmax, ymax) the sphere (camera-space centre c, radius r)
// projects into, exact, for a perspective projection of the usual form (clip x and y from x, y and
// z alone, w = -z): ndc = (P00 x + P20 z) / -z. False for any other form, or an unbounded silhouette.
bool projectedSphereBox(vec3 c, float r, out vec4 box) {
  const bool usual = uProj[1][0] == 0.0 && uProj[3][0] == 0.0 && uProj[0][1] == 0.0 && uProj[3][1] == 0.0 &&
                     uProj[0][3] == 0.0 && uProj[1][3] == 0.0 && uProj[2][3] == -1.0 && uProj[3][3] == 0.0 &&
                     uProj[0][0] > 0.0 && uProj[1][1] > 0.0;
  vec2 sx, sy;
  if (!usual || !tangentSlopes(c.x, -c.z, r, sx) || !tangentSlopes(c.y, -c.z, r, sy)) return false;
  box = vec4(uProj[0][0] * sx.x - uProj[2][0], uProj[1][1] * sy.x - uProj[2][1], uProj[0][0] * sx.y - uProj[2][0],
             uProj[1][1] * sy.y - uProj[2][1]);
  return true;
}

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
  vec4 box;
  if (projectedSphereBox(c, r, box)) {
    // The quad over the silhouette's own box, an eighth of a pixel wider on each side (for
    // rounding: the fragments keep their own exact test), at the far point's depth: clip =
    // (ndc * w, z, w) with w = zq.
    const vec2 margin = 0.25 * uTarget.zw;
    const vec2 ndc = mix(box.xy - margin, box.zw + margin, corner * 0.5 + 0.5);
    const vec4 far = uProj * vec4(0.0, 0.0, -zq, 1.0);
    gl_Position = vec4(ndc * far.w, far.z, far.w);
    return;
  }
  // A projection of another form: every point X of the sphere projects onto the plane at zq within
  // zq * r / (dz - r) * (1 + |c.xy| / dz) of the projected centre c.xy * zq / dz.
  const float h = zq * r / (dz - r) * (1.0 + length(c.xy) / dz);
  gl_Position = uProj * vec4(c.xy * (zq / dz) + h * corner, -zq, 1.0);
}
