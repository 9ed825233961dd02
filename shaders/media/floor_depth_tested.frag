#version 450 core
// The fill-rate floor of the depth-tested methods (planar, planar-textured; media::Renderer::
// setFillRateFloor): their quads, their depth test against the opaque linear depth (as in
// billboard.frag's planar branch and billboard_textured.frag: the quad's constant linear depth
// must be nearer than the surface's), their blending, and nothing else computed: floor.frag's
// constant faint grey where the test passes.
#include "common/media.glsl"

flat in vec4 vCentreRadius;  // camera-space centre, radius

layout(binding = 0) uniform sampler2D uDepthTex;  // opaque linear depth at this target's size

layout(location = 0) out vec4 outMedia;
layout(location = 1) out vec4 outShimmer;

void main() {
  const float lin = texelFetch(uDepthTex, ivec2(gl_FragCoord.xy - uOrigin.xy), 0).r;
  if (!((-vCentreRadius.z - uDepth.x) / uDepth.z < lin)) discard;
  outMedia = vec4(0.002, 0.002, 0.002, 0.01);
  outShimmer = vec4(0.0);
}
