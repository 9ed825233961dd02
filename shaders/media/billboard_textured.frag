#version 450 core
// The photoreal style (media.h); billboard_textured_body.glsl is the program.
#include "media/billboard_textured_body.glsl"
