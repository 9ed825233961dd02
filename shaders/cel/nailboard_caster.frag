#version 450 core
#define PUFF_VIEWS 1
#define PUFF_CASTER 1
#include "cel/nailboard_fs.glsl"
