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

#include "media/billboard_shading.glsl"

// The pixel's eye ray in camera space, exact through the texel centre: origin `o` (the eye, or under an
// orthographic projection the pixel's point in the camera's plane) and unit direction `dir`.
void pixelRay(vec2 pixel, bool ortho, out vec3 o, out vec3 dir) {
  const vec2 ndc = pixel * uTarget.zw * 2.0 - 1.0;
  const vec4 pn = uInvProj * vec4(ndc, -1.0, 1.0);
  const vec4 pf = uInvProj * vec4(ndc, 1.0, 1.0);
  if (ortho) {
    o = vec3(pn.xy / pn.w, 0.0);
    dir = vec3(0.0, 0.0, -1.0);
  } else {
    o = vec3(0.0);
    dir = normalize(pf.xyz / pf.w);
  }
}

// The opaque surface's distance along the view axis at this pixel, from the opaque linear depth;
// where the depth is cleared there is no surface, and the distance is beyond everything.
float opaqueDistance(vec2 pixel) {
  const float lin = texelFetch(uDepthTex, ivec2(pixel), 0).r;
  return lin >= 1.0 ? 3.0e38 : uDepth.x + lin * uDepth.z;
}

// The ray's path through the sphere that the opacity integrates (ds) and the soft methods' fade,
// by the method (uMode.x): the spherical chord clipped by the opaque surface and the near plane,
// the planar methods' full chord. The planar method discards the fragment where its billboard
// through the centre lies behind the opaque surface at distance zs (the depth test).
void pathAndFade(vec3 c, float r, float w, float tF, float tB, float tScene, float tNear, float zs, out float ds,
                 out float fade) {
  ds = 2.0 * w;  // planar methods: the full chord
  fade = 1.0;
  const float dzc = -c.z;
  if (uMode.x == kSpherical) {
    ds = max(0.0, min(tB, tScene) - max(tF, tNear));  // clipped by surfaces and the near plane, never < 0
  } else if (uMode.x == kPlanar) {
    if (dzc > zs) discard;  // the billboard plane behind the surface: the depth test
  } else {
    const float x = clamp((zs - dzc) / (2.0 * r), 0.0, 1.0);  // Ilmonen: (zb - z) / size
    fade = uMode.x == kSoftLinear ? x : sCurve(x);
  }
}

// Where the ray passes closest to the centre c (ray parameter -b), over the billboard's [0, 1]^2
// (the sphere's diameter across).
vec2 closestUv(vec3 o, vec3 dir, float b, vec3 c, float r) {
  const vec3 closest = o + dir * (-b) - c;
  return closest.xy / (2.0 * r) + 0.5;
}

#ifdef PUFF_CARTOON
// The medium's depth where the ray enters it (or the near plane), as the layer's linear depth.
float entryDepth(float oz, float tF, float tNear, float cosA) {
  const float zIn = oz + max(tF, tNear) * cosA;
  return clamp((zIn - uDepth.x) / uDepth.z, 0.0, 1.0);
}

// The opacity without the opaque surfaces' clipping (the near plane still clips) or soft fade.
float unclippedOpacity(float tau, float d, float r, float w, float tF, float tB, float tNear) {
  const float dsFree = uMode.x == kSpherical ? max(0.0, tB - max(tF, tNear)) : 2.0 * w;
  return 1.0 - exp(-tau * (1.0 - d / r) * dsFree);
}
#endif

void main() {
  const vec3 c = vCentreRadius.xyz;
  const float r = vCentreRadius.w;
  const bool ortho = uDepth.w > 0.5;

  // The pixel's ray in camera space (exact, through the texel centre).
  const vec2 pixel = gl_FragCoord.xy - uOrigin.xy;
  vec3 o, dir;
  pixelRay(pixel, ortho, o, dir);
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
  const float zs = opaqueDistance(pixel);
  const float tScene = (zs - oz) / cosA, tNear = (uDepth.x - oz) / cosA;
  float ds, fade;
  pathAndFade(c, r, w, tF, tB, tScene, tNear, zs, ds, fade);  // discards a planar billboard behind the surface

  // The material, turning into another over the particle's life.
  const float density = uintBitsToFloat(vData.z);
  const uint seed = vData.w;
  MaterialGpu mat = particleMaterial(vData);

  // The particle's window of the detail video: a random place and time offset from its seed.
  const vec3 tex3 = detailCoord(closestUv(o, dir, b, c, r), seed, mat.windowSpeedShimmerNext.x);
  const float emissive = mat.densityGEmissiveEmission.z;
  const float speed = mat.windowSpeedShimmerNext.y;

  float tau = mat.densityGEmissiveEmission.x * density;
  vec3 radiance = vec3(0.0), scatter = vec3(0.0);
  float kelvin = 0.0;
  float temperatureDetail = 0.5, shimmerY = 0.5;
  // Opacity detail and scattering: both amounts are uploaded as 0 for emitters, so a material
  // turning from fire into smoke takes them up continuously (linearly) across its transition.
  if (mat.tempRangeBurnDetail.w > 0.0) tau *= opacityDetail(mat, tex3, speed);
  if (mat.colorAlbedo.a > 0.0) addScattering(mat, dir, radiance, scatter);
  if (emissive > 0.0) addEmission(mat, tex3, speed, emissive, radiance, temperatureDetail, shimmerY, kelvin);

  const float alpha = (1.0 - exp(-tau * (1.0 - d / r) * ds)) * fade;
  if (!(alpha > 0.0)) discard;
  const float burn = clamp(mat.tempRangeBurnDetail.z, 0.0, 1.0);
  const vec3 tint = max(vTintTemperature.rgb, vec3(0.0));
  radiance *= tint;  // the particle's tint: what it scatters and emits
  outMedia = vec4(alpha * radiance, alpha * (1.0 - burn));
#ifdef PUFF_CARTOON
  const float emission = mat.densityGEmissiveEmission.w * dot(tint, vec3(0.2126, 0.7152, 0.0722));
  cartoonOutputs(alpha, scatter * tint, emissive, kelvin, emission, entryDepth(oz, tF, tNear, cosA),
                 unclippedOpacity(tau, d, r, w, tF, tB, tNear), outMedia, outCartoonFire, outCartoonDepth);
#endif
  // Heat shimmer: a signed offset from the detail video, where fire is.
  const float sh = mat.windowSpeedShimmerNext.z * alpha;
  outShimmer = vec4(sh * (temperatureDetail - 0.5), sh * (shimmerY - 0.5), 0.0, 0.0);
}
