// Composition (Umenhoffer §4) shared by compose.frag (over Puff's own opaque pass) and
// compose_over.frag (blended over a host's frame): the media layer upsampled depth-aware, and the
// explosions' light on the opaque surfaces (volumetric-explosion-effects).
#include "common/contract.glsl"
layout(binding = 1) uniform sampler2D uOpaqueDepth;  // linear depth, full resolution
layout(binding = 2) uniform sampler2D uMedia;        // premultiplied radiance, transmittance
layout(binding = 3) uniform sampler2D uMediaDepth;   // nearest linear depth per layer texel
layout(binding = 4) uniform sampler2D uShimmerTex;   // rg offsets

struct LightGpu {
  vec4 centreRadius;    // camera space, radius
  vec4 colorIntensity;  // rgb, intensity
  ivec4 flags;          // x: modulate, y: full at the back
};
layout(std140, binding = 5) uniform ComposeBlock {
  mat4 uInvProj;
  vec4 uViewport;  // x, y, width, height of the output viewport
  vec4 uDepth;     // near, far, far - near, 1 if orthographic
  vec4 uLayer;     // layer width, height, factor (full pixels per layer texel), depth tolerance
  vec4 uShimmer;   // x: pixels per unit offset
  ivec4 uCounts;   // x: lights, y: upsampling rule (0 bilinear, 1 bilateral in depth, 2 all-or-nearest)
  LightGpu uLights[PUFF_MAX_LIGHTS];
};

float viewDistance(float lin) { return uDepth.x + lin * uDepth.z; }

// The explosions' light on the surface at pixel p: surface * mul + add (the lights applied in
// order compose into one affine map per channel). Background pixels (no surface) get none.
void lightTerms(ivec2 p, out vec3 mul, out vec3 add) {
  mul = vec3(1.0);
  add = vec3(0.0);
  const float lin = texelFetch(uOpaqueDepth, p, 0).r;
  if (uCounts.x == 0 || lin >= 1.0) return;  // background: no surface to light
  const vec2 ndc = (vec2(p) + 0.5) / uViewport.zw * 2.0 - 1.0;
  const vec4 pn = uInvProj * vec4(ndc, -1.0, 1.0), pf = uInvProj * vec4(ndc, 1.0, 1.0);
  const bool ortho = uDepth.w > 0.5;
  const vec3 o = ortho ? vec3(pn.xy / pn.w, 0.0) : vec3(0.0);
  const vec3 dir = ortho ? vec3(0.0, 0.0, -1.0) : normalize(pf.xyz / pf.w);
  const float zs = viewDistance(lin);
  for (int i = 0; i < uCounts.x; ++i) {
    const vec3 centre = uLights[i].centreRadius.xyz;
    const float r = uLights[i].centreRadius.w;
    // Screen-space projected texture: a radial falloff over the explosion's projected disc (the
    // cone from the eye tangent to its sphere; a cylinder for an orthographic camera).
    float rho;
    if (ortho) {
      rho = length(o.xy - centre.xy) / r;
    } else {
      const float dist = length(centre);
      const float halfAngle = dist > r ? asin(r / dist) : 3.14159265;
      rho = acos(clamp(dot(dir, centre / max(dist, 1e-20)), -1.0, 1.0)) / halfAngle;
    }
    const float wxy = pow(clamp(1.0 - rho * rho, 0.0, 1.0), 2.0);
    // Depth: nothing in front of the sphere, full from its centre (or back) on.
    const float dz = -centre.z;
    const float zFront = dz - r, zFull = uLights[i].flags.y != 0 ? dz + r : dz;
    const float wz = clamp((zs - zFront) / max(zFull - zFront, 1e-6), 0.0, 1.0);
    const float k = uLights[i].colorIntensity.a * wxy * wz;
    if (uLights[i].flags.x != 0) {
      const vec3 m = mix(vec3(1.0), uLights[i].colorIntensity.rgb, clamp(k, 0.0, 1.0));
      mul *= m;
      add *= m;
    } else {
      add += uLights[i].colorIntensity.rgb * k;
    }
  }
}

// How much a layer texel drawn against depth zi counts for a pixel at depth z (view distances):
// 1 within the tolerance (the same surface), falling linearly to 0 at kDepthFalloff tolerances
// (another surface). Relative to z, so it means the same near and far.
const float kDepthFalloff = 5.0;
float depthWeight(float diff, float tolerance) {
  const float x = diff / max(tolerance, 1e-20);
  return clamp((kDepthFalloff - x) / (kDepthFalloff - 1.0), 0.0, 1.0);
}

// The layer texels pixel p reads and their weights, by uCounts.y's rule: the value there is
// sum(w[i] * texel(t[i])) / sum (upsample()). `shimmer` is the heat-shimmer offset at p.
struct Taps {
  ivec2 t[4];
  float w[4];
  float sum;
};

Taps mediaTaps(ivec2 p, out vec2 shimmer) {
  const float factor = uLayer.z;
  const ivec2 layerSize = ivec2(uLayer.xy);

  // The four layer texels around this pixel and the bilinear weights.
  const vec2 q = (vec2(p) + 0.5) / factor - 0.5;
  const ivec2 b = ivec2(floor(q));
  const vec2 f = q - vec2(b);
  const ivec2 t[4] = ivec2[](b, b + ivec2(1, 0), b + ivec2(0, 1), b + ivec2(1, 1));
  const float w[4] = float[]((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);

  const float z = viewDistance(texelFetch(uOpaqueDepth, p, 0).r);
  const float tolerance = uLayer.w * z;
  Taps plain, bilateral;
  plain.sum = 1.0;
  bilateral.sum = 0.0;
  shimmer = vec2(0.0);
  float worst = 0.0, best = 3.0e38;
  int nearest = 0;
  for (int i = 0; i < 4; ++i) {
    const ivec2 ti = clamp(t[i], ivec2(0), layerSize - 1);
    const float zi = viewDistance(texelFetch(uMediaDepth, ti, 0).r);
    const float diff = abs(zi - z);
    worst = max(worst, diff);
    if (diff < best) {
      best = diff;
      nearest = i;
    }
    plain.t[i] = ti;
    plain.w[i] = w[i];
    bilateral.t[i] = ti;
    bilateral.w[i] = w[i] * depthWeight(diff, tolerance);
    bilateral.sum += bilateral.w[i];
    shimmer += w[i] * texelFetch(uShimmerTex, ti, 0).rg;
  }
  // uCounts.y: 0 plain bilinear; 1 bilateral in depth; 2 the all-or-nearest switch (kept
  // to measure against).
  const int rule = uCounts.y;
  if (rule == 1 && bilateral.sum > 0.0) return bilateral;
  if ((rule == 1) || (rule == 2 && worst > tolerance)) {
    // Not one surface: take the layer texel drawn against the depth nearest this pixel's, looking
    // one texel further out too (a surface thinner than a texel owns the texels around it).
    ivec2 pick = t[nearest];
    for (int y = -1; y <= 2; ++y) {
      for (int x = -1; x <= 2; ++x) {
        if (x >= 0 && x <= 1 && y >= 0 && y <= 1) continue;
        const ivec2 ti = clamp(b + ivec2(x, y), ivec2(0), layerSize - 1);
        const float diff = abs(viewDistance(texelFetch(uMediaDepth, ti, 0).r) - z);
        if (diff < best) {
          best = diff;
          pick = ti;
        }
      }
    }
    Taps one;
    one.t[0] = clamp(pick, ivec2(0), layerSize - 1);
    one.w[0] = 1.0;
    for (int i = 1; i < 4; ++i) {
      one.t[i] = one.t[0];
      one.w[i] = 0.0;
    }
    one.sum = 1.0;
    return one;
  }
  return plain;
}

// A layer texture at the taps.
vec4 upsample(sampler2D layer, Taps k) {
  vec4 v = vec4(0.0);
  for (int i = 0; i < 4; ++i) v += k.w[i] * texelFetch(layer, k.t[i], 0);
  return v / k.sum;
}

// The media layer at pixel p (premultiplied radiance, transmittance), upsampled by uCounts.y's rule,
// and the heat-shimmer offset there.
vec4 upsampledMedia(ivec2 p, out vec2 shimmer) { return upsample(uMedia, mediaTaps(p, shimmer)); }
