#version 450 core
#define PUFF_VIEWS 4
#define PUFF_HULL 1
#define PUFF_CASTER 1
#include "cel/nailboard_fs.glsl"
