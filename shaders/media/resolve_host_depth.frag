#version 450 core
// A host's single-sample depth texture, in its convention, to linear depth at full resolution.
#include "media/host_depth.glsl"
layout(binding = 0) uniform sampler2D uHostDepth;
layout(location = 0) out float outDepth;

void main() { outDepth = linearFromStored(texelFetch(uHostDepth, ivec2(gl_FragCoord.xy) + uOrigin, 0).r); }
