#version 450 core
#define PUFF_VIEWS 4
#define PUFF_HULL 1
#define PUFF_SHADE_PASS PUFF_PASS_DEPTH_ONLY
#include "cel/nailboard_fs.glsl"
