#version 450 core
// The nailboards' deferred screen pass (nailboard_fs.glsl, PUFF_DEFERRED): two triangles over the
// screen rectangle the batch's quads can cover, not the whole viewport, so the pass costs what the
// puffs cover. The box's eight corners projected, padded for the ink and its antialiased edge; the
// whole viewport where a corner lies at or behind the eye (its projection is not bounded there).
#include "common/frame.glsl"

uniform vec3 uBoxMin;  // world box holding every quad of the batch (NailboardRenderer::upload)
uniform vec3 uBoxMax;
uniform float uPadPixels;  // screen pixels the quads reach past it (the ink band and its edge)

// The fragment's clip-space x, y (w = 1): its eye ray, whatever the clip origin (glClipControl).
out vec2 vScreenNdc;

const vec2 kCorners[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

void main() {
  vec2 lo = vec2(1e30), hi = vec2(-1e30);
  bool whole = false;
  for (int i = 0; i < 8; ++i) {
    vec3 corner = mix(uBoxMin, uBoxMax, vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
    vec4 clip = uViewProj * vec4(corner, 1.0);
    whole = whole || clip.w <= 1e-6;
    vec2 ndc = clip.xy / max(clip.w, 1e-6);
    lo = min(lo, ndc);
    hi = max(hi, ndc);
  }
  vec2 pad = 2.0 * uPadPixels / uViewport.zw;
  lo = whole ? vec2(-1.0) : max(lo - pad, vec2(-1.0));
  hi = whole ? vec2(1.0) : min(hi + pad, vec2(1.0));
  vScreenNdc = mix(lo, hi, kCorners[gl_VertexID]);
  gl_Position = vec4(vScreenNdc, 0.0, 1.0);
}
