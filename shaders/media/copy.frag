#version 450 core
// Where the media change nothing (Layers::setCoverage): the opaque colour, as compose.frag draws it
// under no medium and no explosion light.
layout(binding = 0) uniform sampler2D uOpaqueColor;
#include "media/compose.glsl"

layout(location = 0) out vec4 outColor;

void main() { outColor = vec4(texelFetch(uOpaqueColor, ivec2(gl_FragCoord.xy - uViewport.xy), 0).rgb, 1.0); }
