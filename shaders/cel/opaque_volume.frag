#version 450 core
// Opaque objects' shadow volumes: the face's LINEAR depth (common/frame.glsl; stored in the frame's
// convention by storeDepth, which keeps the order), pushed back by
// uDepthBias so that a surface lying on a volume's boundary (an object's own light-facing faces,
// which are its volume's cap; faces parallel to the light, which lie in its sides) counts as outside
// it: the depth-fail count sees a face at the receiver's own depth as behind it, never in front.
#include "common/frame.glsl"

in float vDist;  // view-axis distance, affine in camera space so interpolation is exact

layout(location = PUFF_LOC_VOLUME_BIAS) uniform float uDepthBias;  // linear depth units

void main() { gl_FragDepth = storeDepth(clamp(linearDepth(vDist) + uDepthBias, 0.0, 1.0)); }
