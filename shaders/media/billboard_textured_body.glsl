// The classic textured billboard (media::Method::kPlanarTextured): the opacity is one lookup of
// the baked falloff texture (the lone sphere's optical path per radius, 2 (1 - rho) sqrt(1 - rho^2),
// made once by media::Renderer) and one exp; no ray is intersected with the sphere and no path
// is clipped. The quad is depth-tested against the opaque linear depth as the hardware test would
// (GL_LESS on the quad's linear depth, all or nothing per pixel): the media layer has no depth
// attachment, its opaque depth is a texture, so the test is the shader's first statement.
// The material terms (colour, albedo, phase, emission / black body, detail video, burn, shimmer)
// are billboard.frag's, so the two methods' images differ only in the opacity's shape and clipping.
#include "common/media.glsl"

flat in vec4 vCentreRadius;
flat in uvec4 vData;
flat in vec4 vTintTemperature;
in vec2 vUv;
in vec3 vView;

layout(binding = 0) uniform sampler2D uDepthTex;        // opaque linear depth at this target's size
layout(binding = 1) uniform sampler1D uBlackbody;       // linear sRGB radiance over uKelvin.xy
layout(binding = 2) uniform sampler2D uPhase;  // 4 pi P(cos, g): s = sqrt((1 - cos) / 2), t = (g + 0.95) / 1.9
layout(binding = 3) uniform sampler3D uTemperatureDetail;  // (x, y, time), repeating
layout(binding = 4) uniform sampler3D uOpacityDetail;
layout(binding = 5) uniform sampler2D uFalloff;  // path through the sphere / r over the quad's [0, 1]^2

layout(location = 0) out vec4 outMedia;    // premultiplied radiance, alpha * (1 - burn)
layout(location = 1) out vec4 outShimmer;  // rg: offset noise weighted by opacity
#ifdef PUFF_CARTOON
layout(location = 2) out vec4 outCartoonFire;  // the cartoon style (common/media.glsl, cartoonOutputs)
layout(location = 3) out vec4 outCartoonDepth;
#endif

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
  // The depth test: the quad's linear depth (constant: it faces the camera) against the opaque one.
  const float lin = texelFetch(uDepthTex, ivec2(gl_FragCoord.xy - uOrigin.xy), 0).r;
  if (!((-vCentreRadius.z - uDepth.x) / uDepth.z < lin)) discard;
  const float weight = texture(uFalloff, vUv).r;
  if (!(weight > 0.0)) discard;
  const float r = vCentreRadius.w;
  const vec3 dir = uDepth.w > 0.5 ? vec3(0.0, 0.0, -1.0) : normalize(vView);

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
  const float window = mat.windowSpeedShimmerNext.x;
  const vec3 tex3 = vec3(vec2(unitHash(seed), unitHash(seed ^ 0x68bc21ebu)) + vUv * window,
                         unitHash(seed ^ 0x02e5be93u));
  const float emissive = mat.densityGEmissiveEmission.z;
  const float speed = mat.windowSpeedShimmerNext.y;

  float tau = mat.densityGEmissiveEmission.x * density;
  vec3 radiance = vec3(0.0), scatter = vec3(0.0);
  float kelvin = 0.0;
  float temperatureDetail = 0.5, shimmerY = 0.5;
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

  const float alpha = 1.0 - exp(-tau * r * weight);
  if (!(alpha > 0.0)) discard;
  const float burn = clamp(mat.tempRangeBurnDetail.z, 0.0, 1.0);
  const vec3 tint = max(vTintTemperature.rgb, vec3(0.0));
  radiance *= tint;  // the particle's tint: what it scatters and emits
  outMedia = vec4(alpha * radiance, alpha * (1.0 - burn));
#ifdef PUFF_CARTOON
  {
    const float w = mat.densityGEmissiveEmission.w * dot(tint, vec3(0.2126, 0.7152, 0.0722));
    const float quadLin = clamp((-vCentreRadius.z - uDepth.x) / uDepth.z, 0.0, 1.0);  // the quad's depth
    // All or nothing against the opaque depth: nothing else clips it.
    cartoonOutputs(alpha, scatter * tint, emissive, kelvin, w, quadLin, alpha, outMedia, outCartoonFire,
                   outCartoonDepth);
  }
#endif
  const float sh = mat.windowSpeedShimmerNext.z * alpha;
  outShimmer = vec4(sh * (temperatureDetail - 0.5), sh * (shimmerY - 0.5), 0.0, 0.0);
}
