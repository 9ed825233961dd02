// The media pass's per-frame values (puff::media::Renderer, uniform binding `mediaBlock`) and its
// particle and material layouts (storage binding `particles`, uniform binding `materialBlock`:
// media::Bindings; this file's layout(binding) values are never used). The blocks are mirrored by
// runtime/private/puff/shader_blocks.h, the particle by puff::media::Particle.
#include "common/contract.glsl"
layout(std140, binding = 3) uniform MediaBlock {
  mat4 uView;         // world -> camera
  mat4 uProj;         // camera -> clip
  mat4 uInvProj;      // clip -> camera
  vec4 uTarget;       // width, height, 1 / width, 1 / height of the media viewport, pixels
  vec4 uOrigin;       // xy: the viewport's origin, pixels
  vec4 uDepth;        // near, far, far - near, 1 if orthographic
  vec4 uLightDir;     // xyz: unit camera-space direction toward the light
  vec4 uLightColor;   // rgb: radiance an isotropic medium scatters toward the eye
  vec4 uAmbient;      // rgb: isotropic in-scattered radiance
  vec4 uKelvin;       // black-body texture range: min, max, 1 / (max - min), exposure
  ivec4 uMode;        // x: method (0 planar, 1 soft linear, 2 soft S-curve, 3 spherical), y: shimmer target
  vec4 uTime;         // x: seconds
  vec4 uCartoon;      // x: the fire bands' cool kelvin, y: 1 / (hot - cool)
};

struct MaterialGpu {
  vec4 colorAlbedo;              // rgb tint, albedo a
  vec4 densityGEmissiveEmission; // tau, g, emissive weight (0/1), emission scale
  vec4 tempRangeBurnDetail;      // T0, T1, burn, opacity detail amount
  vec4 windowSpeedShimmerNext;   // detail window, detail fps, shimmer, becomes (-1 = none)
  vec4 transition;               // start, end (life fractions)
};
layout(std140, binding = 4) uniform MaterialBlock {
  MaterialGpu uMaterials[PUFF_MAX_MATERIALS];
};

struct MediaParticle {
  vec4 positionRadius;      // world position, radius
  uvec4 data;               // material, life (float bits), density (float bits), seed
  vec4 tintTemperature;     // rgb: scene-linear tint of its light; a: T0 in kelvin when > 0 (else the material's)
};
layout(std430, binding = 0) readonly buffer MediaParticles {
  MediaParticle particles[];
};

const int kPlanar = 0;
const int kSoftLinear = 1;
const int kSoftSCurve = 2;
const int kSpherical = 3;

// The cartoon style (media::Style::kCartoon; runtime/include/puff/media/layers.h says how Layers read
// them): what one particle adds at this pixel, for over-compositing (ONE, ONE_MINUS_SRC_ALPHA on
// every channel, burn ignored: cartoon fire occludes). alpha: its opacity; scatter: the light it
// scatters, tinted; e: its emissive weight; kelvin: its temperature; w: its emission scale (the
// material's emission times the tint's luminance); lin: the medium's linear depth here; free: its
// opacity were no opaque surface to clip it (where a surface cuts the medium, A < threshold
// while the medium itself is not thin: that iso-line is the surface's edge, not the medium's).
//   media:  (alpha * scatter, alpha)                     rgb: scattered light only; a: transmittance x (1 - alpha)
//   fire:   (alpha e s, alpha e, alpha e w, alpha)        s: kelvin over the fire bands' range, clamped to [0, 1]
//   depth:  (alpha lin, free, 0, alpha)     g: sum free x the transmittance in front, >= A
void cartoonOutputs(float alpha, vec3 scatter, float e, float kelvin, float w, float lin, float free, out vec4 media,
                    out vec4 fire, out vec4 depth) {
  const float s = clamp((kelvin - uCartoon.x) * uCartoon.y, 0.0, 1.0);
  media = vec4(alpha * scatter, alpha);
  fire = vec4(alpha * e * s, alpha * e, alpha * e * w, alpha);
  depth = vec4(alpha * lin, max(free, alpha), 0.0, alpha);
}
