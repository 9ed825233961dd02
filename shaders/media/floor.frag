#version 450 core
// The media path's fill-rate floor (for the benchmarks, media::Renderer::setFillRateFloor): the
// same quads as billboard.frag, the same blending, and nothing computed: a constant faint grey.
// What any billboard method pays to touch those pixels.
layout(location = 0) out vec4 outMedia;
layout(location = 1) out vec4 outShimmer;

void main() {
  outMedia = vec4(0.002, 0.002, 0.002, 0.01);
  outShimmer = vec4(0.0);
}
