#version 450 core
// The cel reference's outlines: the TRUE silhouette of each puff mesh, its edges between a triangle
// facing the eye and one facing away. The ink is every pixel within uWidth pixels of a silhouette
// edge (the segment, round at its ends: the exact offset of the silhouette polygon, as a distance to
// the silhouette defines it), at the edge's own depth. Each edge is drawn as the rectangle around
// its capsule; silhouette.frag keeps the pixels whose centres lie within uWidth of the segment.
// Drawn after everything else with the depth test and no depth write: a nearer surface hides the
// ink, a farther one or the background shows it, as the nailboards' flange (§4.2, Fig. 5). Only the
// puff's OUTER silhouette is inked, as the nailboards' distance map outlines it: silhouette.frag drops
// ink over the puff's own pixels (a fold inside its outline shows the puff itself behind it).
#include "common/frame.glsl"

layout(triangles_adjacency) in;
layout(triangle_strip, max_vertices = 12) out;

in vec3 vView[];
flat in uint vId[];
flat out uint gId;
flat out vec4 gSegment;  // the edge's ends, pixels of the target viewport
flat out vec2 gEndDist;  // their view-axis distances (the ink's depth is the edge's at the nearest point)

uniform float uWidth;  // pixels of the (supersampled) target

bool facesEye(vec3 a, vec3 b, vec3 c) {
  vec3 n = cross(b - a, c - a);
  return uDepthRange.w > 0.5 ? n.z > 0.0 : dot(n, -a) > 0.0;
}

vec2 toPixels(vec4 clip) { return (clip.xy / clip.w * 0.5 + 0.5) * uViewport.zw; }

void emit(vec4 clip, vec2 offsetPixels, vec4 segment, vec2 endDist) {
  gl_Position = vec4(clip.xy + offsetPixels / uViewport.zw * 2.0 * clip.w, clip.zw);
  gId = vId[0];
  gSegment = segment;
  gEndDist = endDist;
  EmitVertex();
}

void main() {
  // Triangle 0, 2, 4; vertex 1, 3, 5 lies opposite edge 0-2, 2-4, 4-0 across the neighbour.
  if (!facesEye(vView[0], vView[2], vView[4])) return;
  for (int e = 0; e < 3; ++e) {
    int i0 = 2 * e, i1 = (2 * e + 2) % 6, across = 2 * e + 1, inner = (2 * e + 4) % 6;
    if (vView[across] == vView[inner]) continue;  // no neighbour (an open mesh's border): not inked
    if (facesEye(vView[i1], vView[i0], vView[across])) continue;  // both faces front: not a silhouette
    vec4 c0 = gl_in[i0].gl_Position, c1 = gl_in[i1].gl_Position;
    if (c0.w <= 0.0 || c1.w <= 0.0) continue;  // through the eye plane: left out
    vec2 p0 = toPixels(c0), p1 = toPixels(c1);
    vec2 along = p1 - p0;
    float len = length(along);
    // A edge seen end-on is a point: its ink is the disc around it.
    along = len < 1e-6 ? vec2(1.0, 0.0) : along / len;
    vec2 side = vec2(-along.y, along.x);
    // Half a pixel more all round: every pixel centre within uWidth is inside the rectangle.
    float reach = uWidth + 0.5;
    vec2 a = -along * reach, b = along * reach, o = side * reach;
    vec4 segment = vec4(p0, p1);
    vec2 endDist = vec2(-vView[i0].z, -vView[i1].z);
    emit(c0, a - o, segment, endDist);
    emit(c0, a + o, segment, endDist);
    emit(c1, b - o, segment, endDist);
    emit(c1, b + o, segment, endDist);
    EndPrimitive();
  }
}
