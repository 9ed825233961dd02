// The cartoon style's passes (media::Layers::compose with a CartoonCompose; layers.h, "Cartoon
// media"): its block, and what a pixel's fill is.
#include "common/contract.glsl"
layout(std140, binding = 3) uniform CartoonBlock {
  vec4 uStyle;          // x: threshold, y: opacity bands, z: fire bands, w: ink width in pixels (0: no ink)
  vec4 uInk;            // rgb: the ink, scene-linear
  vec4 uFireColors[PUFF_MAX_FIRE_BANDS];  // band k's colour: Le at its centre temperature times the exposure, linear
};

// A seed texel with no iso-line point.
const uint kNoSeed = 0xffffffffu;

// How much the iso-line at a seed is an opaque surface's edge rather than the medium's: from the
// medium's opacity without the surfaces' clipping just outside it (A < threshold there). At the
// threshold (the medium thins out by itself: a silhouette) 0; from halfway between the threshold
// and 1 (a surface cuts through thick medium) 1; smooth between, so an iso-line that surfaces cut
// in some places and not in others fades its ink instead of breaking it into dashes.
float cartoonCut(float unclipped) {
  const float theta = uStyle.x;
  return smoothstep(theta, theta + 0.5 * (1.0 - theta), unclipped);
}

// The flat fill of a pixel from the upsampled layer: scatterSum the scattered light (premultiplied,
// over-composited), fire = (sum a e s, sum a e, sum a e w, A) (common/media.glsl, cartoonOutputs).
// rgb: the colour (linear, unpremultiplied); a: the opacity tier, theta + (1 - theta) (k + 1) / n for
// A in tier k, the first tier below the threshold (a pixel the fill only partly covers shows it).
vec4 cartoonFill(vec3 scatterSum, vec4 fire, float A) {
  if (!(A > 0.0)) return vec4(0.0);
  const float theta = uStyle.x, tiers = uStyle.y;
  const float x = clamp((A - theta) / (1.0 - theta), 0.0, 1.0);
  const float tier = theta + (1.0 - theta) * (min(floor(x * tiers), tiers - 1.0) + 1.0) / tiers;
  const float e = fire.g;
  vec3 colour;
  if (e >= 0.5 * A) {
    // Emitting medium is most of what is seen: the black-body colour of the band its mean
    // temperature falls in, times its mean emission.
    const float bands = uStyle.z;
    const float s = clamp(fire.r / e, 0.0, 1.0);
    colour = uFireColors[int(min(floor(s * bands), bands - 1.0))].rgb * (fire.b / e);
  } else {
    colour = scatterSum / (A - e);  // the scattered light, flat where one medium is seen
  }
  return vec4(max(colour, vec3(0.0)), tier);
}
