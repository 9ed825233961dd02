// Opacity and colour of one particle sphere at this pixel (Umenhoffer Eq. 1, 2), written as
// Ilmonen's premultiplied colour + burn-scaled alpha for glBlendFunc(ONE, ONE_MINUS_SRC_ALPHA).
#include "common/media.glsl"

flat in vec4 vCentreRadius;
flat in uvec4 vData;
flat in vec4 vTintTemperature;

layout(binding = 0) uniform sampler2D uDepthTex;        // opaque linear depth at this target's size
layout(binding = 1) uniform sampler1D uBlackbody;       // linear sRGB radiance over uKelvin.xy
layout(binding = 2) uniform sampler2D uPhase;  // 4 pi P(cos, g): s = sqrt((1 - cos) / 2), t = (g + 0.95) / 1.9
layout(binding = 3) uniform sampler3D uTemperatureDetail;  // (x, y, time), repeating
layout(binding = 4) uniform sampler3D uOpacityDetail;

layout(location = 0) out vec4 outMedia;    // premultiplied radiance, alpha * (1 - burn)
layout(location = 1) out vec4 outShimmer;  // rg: offset noise weighted by opacity
#ifdef PUFF_CARTOON
layout(location = 2) out vec4 outCartoonFire;  // the cartoon style (common/media.glsl, cartoonOutputs)
layout(location = 3) out vec4 outCartoonDepth;
#endif

// Lorach's contrast curve (RTR3 §10.6): 0 and 1 at the ends, flat there, so the fade has no kink.
float sCurve(float x) {
  return x < 0.5 ? 0.5 * pow(2.0 * x, 2.0) : 1.0 - 0.5 * pow(2.0 * (1.0 - x), 2.0);
}

uint hash(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}
float unitHash(uint x) { return float(hash(x) >> 8) / 16777216.0; }

MaterialGpu blend(MaterialGpu a, MaterialGpu b, float f) {
  MaterialGpu m;
  m.colorAlbedo = mix(a.colorAlbedo, b.colorAlbedo, f);
  m.densityGEmissiveEmission = mix(a.densityGEmissiveEmission, b.densityGEmissiveEmission, f);
  m.tempRangeBurnDetail = mix(a.tempRangeBurnDetail, b.tempRangeBurnDetail, f);
  m.windowSpeedShimmerNext = mix(a.windowSpeedShimmerNext, b.windowSpeedShimmerNext, f);
  m.transition = a.transition;
  return m;
}

void main() {
  const vec3 c = vCentreRadius.xyz;
  const float r = vCentreRadius.w;
  const bool ortho = uDepth.w > 0.5;

  // The pixel's ray in camera space (exact, through the texel centre).
  const vec2 pixel = gl_FragCoord.xy - uOrigin.xy;
  const vec2 ndc = pixel * uTarget.zw * 2.0 - 1.0;
  const vec4 pn = uInvProj * vec4(ndc, -1.0, 1.0);
  const vec4 pf = uInvProj * vec4(ndc, 1.0, 1.0);
  vec3 o, dir;
  if (ortho) {
    o = vec3(pn.xy / pn.w, 0.0);
    dir = vec3(0.0, 0.0, -1.0);
  } else {
    o = vec3(0.0);
    dir = normalize(pf.xyz / pf.w);
  }
  // Sphere: closest approach d, entry tF and exit tB along the ray.
  const vec3 m = o - c;
  const float b = dot(m, dir);
  const vec3 across = cross(m, dir);  // |m x dir| = distance to the ray, without |m|^2 - b^2 cancelling
  const float d2 = dot(across, across);
  if (d2 >= r * r) discard;
  const float d = sqrt(d2), w = sqrt(r * r - d2);
  const float tF = -b - w, tB = -b + w;
  // Depths along the view axis become ray parameters through the ray's slope.
  const float cosA = -dir.z, oz = -o.z;
  const float lin = texelFetch(uDepthTex, ivec2(pixel), 0).r;
  const float zs = lin >= 1.0 ? 3.0e38 : uDepth.x + lin * uDepth.z;  // cleared depth: no surface
  const float tScene = (zs - oz) / cosA, tNear = (uDepth.x - oz) / cosA;

  float ds = 2.0 * w;  // planar methods: the full chord
  float fade = 1.0;
  const float dzc = -c.z;
  if (uMode.x == kSpherical) {
    ds = max(0.0, min(tB, tScene) - max(tF, tNear));  // clipped by surfaces and the near plane, never < 0
  } else if (uMode.x == kPlanar) {
    if (dzc > zs) discard;  // the billboard plane behind the surface: the depth test
  } else {
    const float x = clamp((zs - dzc) / (2.0 * r), 0.0, 1.0);  // Ilmonen: (zb - z) / size
    fade = uMode.x == kSoftLinear ? x : sCurve(x);
  }

  // The material, turning into another over the particle's life.
  const uint mi = min(vData.x, 31u);
  const float life = uintBitsToFloat(vData.y);
  const float density = uintBitsToFloat(vData.z);
  const uint seed = vData.w;
  MaterialGpu mat = uMaterials[mi];
  const int next = int(mat.windowSpeedShimmerNext.w);
  if (next >= 0) {
    const vec2 tr = mat.transition.xy;
    const float f = tr.y > tr.x ? clamp((life - tr.x) / (tr.y - tr.x), 0.0, 1.0) : step(tr.x, life);
    mat = blend(mat, uMaterials[min(next, PUFF_MAX_MATERIALS - 1)], f);
  }

  // The particle's window of the detail video: a random place and time offset from its seed.
  const vec3 closest = o + dir * (-b) - c;
  const vec2 uv = closest.xy / (2.0 * r) + 0.5;
  const float window = mat.windowSpeedShimmerNext.x;
  const vec3 detailAt = vec3(vec2(unitHash(seed), unitHash(seed ^ 0x68bc21ebu)) + uv * window,
                             unitHash(seed ^ 0x02e5be93u));
  const float emissive = mat.densityGEmissiveEmission.z;
  const float speed = mat.windowSpeedShimmerNext.y;
  const vec3 tex3 = vec3(detailAt.xy, detailAt.z);

  float tau = mat.densityGEmissiveEmission.x * density;
  vec3 radiance = vec3(0.0), scatter = vec3(0.0);
  float kelvin = 0.0;
  float temperatureDetail = 0.5, shimmerY = 0.5;
  // Opacity detail and scattering: both amounts are uploaded as 0 for emitters, so a material
  // turning from fire into smoke takes them up continuously (linearly) across its transition.
  if (mat.tempRangeBurnDetail.w > 0.0) {
    const vec3 size = vec3(textureSize(uOpacityDetail, 0));
    const float D = texture(uOpacityDetail, vec3(tex3.xy, tex3.z + uTime.x * speed / size.z)).r;
    tau *= max(0.0, 1.0 + mat.tempRangeBurnDetail.w * (2.0 * D - 1.0));
  }
  if (mat.colorAlbedo.a > 0.0) {
    const float cosTheta = dot(uLightDir.xyz, dir);  // light's travel vs the scattered direction
    const float g = mat.densityGEmissiveEmission.y;
    const vec2 pc = vec2(sqrt(clamp((1.0 - cosTheta) * 0.5, 0.0, 1.0)), (g + 0.95) / 1.9);
    const vec2 ps = vec2(textureSize(uPhase, 0));
    const float p4pi = texture(uPhase, (pc * (ps - 1.0) + 0.5) / ps).r;
    const vec3 C = uAmbient.rgb + uLightColor.rgb * p4pi;
    scatter = mat.colorAlbedo.a * mat.colorAlbedo.rgb * C;
    radiance += scatter;
  }
  if (emissive > 0.0) {
    const vec3 size = vec3(textureSize(uTemperatureDetail, 0));
    const vec3 at = vec3(tex3.xy, tex3.z + uTime.x * speed / size.z);
    temperatureDetail = texture(uTemperatureDetail, at).r;
    shimmerY = texture(uTemperatureDetail, at + vec3(0.37, 0.61, 0.0)).r;
    // T0: the particle's own temperature over its life when it has one, else the material's.
    const float t0 = vTintTemperature.a > 0.0 ? vTintTemperature.a : mat.tempRangeBurnDetail.x;
    const float T = t0 + mat.tempRangeBurnDetail.y * temperatureDetail;
    kelvin = T;
    const float s = clamp((T - uKelvin.x) * uKelvin.z, 0.0, 1.0);
    const float n = float(textureSize(uBlackbody, 0));
    const vec3 le = max(texture(uBlackbody, (s * (n - 1.0) + 0.5) / n).rgb, vec3(0.0));  // gamut: clip at 0
    radiance += emissive * mat.densityGEmissiveEmission.w * uKelvin.w * le;
  }

  const float alpha = (1.0 - exp(-tau * (1.0 - d / r) * ds)) * fade;
  if (!(alpha > 0.0)) discard;
  const float burn = clamp(mat.tempRangeBurnDetail.z, 0.0, 1.0);
  const vec3 tint = max(vTintTemperature.rgb, vec3(0.0));
  radiance *= tint;  // the particle's tint: what it scatters and emits
  outMedia = vec4(alpha * radiance, alpha * (1.0 - burn));
#ifdef PUFF_CARTOON
  {
    // The medium's depth where the ray enters it (or the near plane), as the layer's linear depth.
    const float zIn = oz + max(tF, tNear) * cosA;
    const float lin = clamp((zIn - uDepth.x) / uDepth.z, 0.0, 1.0);
    const float emission = mat.densityGEmissiveEmission.w * dot(tint, vec3(0.2126, 0.7152, 0.0722));
    // The opacity without the opaque surfaces' clipping (the near plane still clips) or soft fade.
    const float dsFree = uMode.x == kSpherical ? max(0.0, tB - max(tF, tNear)) : 2.0 * w;
    const float free = 1.0 - exp(-tau * (1.0 - d / r) * dsFree);
    cartoonOutputs(alpha, scatter * tint, emissive, kelvin, emission, lin, free, outMedia, outCartoonFire,
                   outCartoonDepth);
  }
#endif
  // Heat shimmer: a signed offset from the detail video, where fire is.
  const float sh = mat.windowSpeedShimmerNext.z * alpha;
  outShimmer = vec4(sh * (temperatureDetail - 0.5), sh * (shimmerY - 0.5), 0.0, 0.0);
}
