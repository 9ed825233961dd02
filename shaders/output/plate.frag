#version 450 core
// The plate (output.plate) under a frame: one texel per pixel of the viewport, scene-linear (the
// plate was decoded and stretched to the viewport's size on the CPU, render::resizePlate).
#include "common/contract.glsl"
layout(binding = 0) uniform sampler2D uPlate;  // scene-linear RGBA, the viewport's size, bottom row first
layout(location = PUFF_LOC_PLATE_ORIGIN) uniform vec2 uOrigin; // the viewport's origin, pixels

layout(location = 0) out vec4 oColor;

void main() { oColor = vec4(texelFetch(uPlate, ivec2(gl_FragCoord.xy - uOrigin), 0).rgb, 1.0); }
