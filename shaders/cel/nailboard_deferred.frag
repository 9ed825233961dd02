#version 450 core
#define PUFF_VIEWS 1
#define PUFF_SHADE_PASS PUFF_PASS_LIT
#define PUFF_DEFERRED 1
#include "cel/nailboard_fs.glsl"
