#version 450 core
// The tumbling hull's occluder pass (NailboardRenderer, drawn into Puff's own target before the
// hull): each hull-drawn puff's core as a disc (hull_occluder.vert), the nearest disc's view depth
// kept per pixel (the depth test, in the frame's convention). The hull's fragments behind it are
// dropped before they march (nailboard_fs.glsl, hullOccluded).
#define PUFF_VIEWS 4
#define PUFF_HULL_OCCLUDER 1
#include "common/frame.glsl"
#include "cel/nailboard_io.glsl"

layout(location = 0) out float oDepth;  // view depth, world units

void main() {
  vec2 off = vPuff - vDisc.xy;
  if (dot(off, off) > vDisc.z * vDisc.z) discard;
  float dist = vDist - vDisc.w;
  gl_FragDepth = storeDepth(linearDepth(dist));
  oDepth = dist;
}
