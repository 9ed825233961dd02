#version 450 core
#define PUFF_VIEWS 1
#include "cel/nailboard_vs.glsl"
