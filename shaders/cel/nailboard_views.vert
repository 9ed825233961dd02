#version 450 core
#define PUFF_VIEWS 4
#include "cel/nailboard_vs.glsl"
