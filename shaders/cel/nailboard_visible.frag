#version 450 core
#define PUFF_VIEWS 1
#define PUFF_SHADE_PASS PUFF_PASS_DEPTH_ONLY
#define PUFF_VISIBILITY 1
#include "cel/nailboard_fs.glsl"
