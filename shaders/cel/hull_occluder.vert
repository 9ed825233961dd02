#version 450 core
#define PUFF_VIEWS 4
#define PUFF_HULL_OCCLUDER 1
#include "cel/nailboard_vs.glsl"
