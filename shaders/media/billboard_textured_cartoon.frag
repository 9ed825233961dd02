#version 450 core
// The cartoon style (media::Style::kCartoon): the same program, also writing the cartoon
// attributes to draw buffers 2 and 3.
#define PUFF_CARTOON 1
#include "media/billboard_textured_body.glsl"
