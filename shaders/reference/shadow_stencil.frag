#version 450 core
// The cel reference: marks (stencil, by not discarding) the pixels of opaque objects that another
// caster (a puff or another object) shadows, so OpaqueRenderer's own shadowed pass draws them (as in
// the nailboard frame).
#include "common/frame.glsl"
#include "reference/shadow_test.glsl"

layout(binding = 2) uniform sampler2D uDepth;  // a copy of the frame's depth (linear)
layout(binding = 3) uniform usampler2D uId;    // the frame's caster ids (puffs, objects; 0: neither)

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float depth = texelFetch(uDepth, p, 0).r;
  uint id = texelFetch(uId, p, 0).r;
  // Background, or a puff (the puffs shade their own shadows): nothing to mark.
  if (depth >= 1.0 || (id != 0u && id < 0x80000000u)) discard;
  // The point on the pixel's ray at that linear depth: the view-axis distance is affine along a ray,
  // so it lies that fraction of the way from the ray's near-plane point to its far-plane point.
  vec2 ndc = (gl_FragCoord.xy - uViewport.xy) / uViewport.zw * 2.0 - 1.0;
  vec4 a = uInvViewProj * vec4(ndc, -1.0, 1.0);
  vec4 b = uInvViewProj * vec4(ndc, 1.0, 1.0);
  vec3 world = mix(a.xyz / a.w, b.xyz / b.w, depth);
  if (!inShadow(world, id)) discard;
}
