// The classic textured billboard (media::Method::kPlanarTextured): the opacity is one lookup of
// the baked falloff texture (the lone sphere's optical path per radius, 2 (1 - rho) sqrt(1 - rho^2),
// made once by media::Renderer) and one exp; no ray is intersected with the sphere and no path
// is clipped. The quad is depth-tested against the opaque linear depth as the hardware test would
// (GL_LESS on the quad's linear depth, all or nothing per pixel): the media layer has no depth
// attachment, its opaque depth is a texture, so the test is the shader's first statement.
// The material terms (colour, albedo, phase, emission / black body, detail video, burn, shimmer)
// are billboard.frag's (billboard_shading.glsl), so the two methods' images differ only in the
// opacity's shape and clipping.
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

#include "media/billboard_shading.glsl"

void main() {
  // The depth test: the quad's linear depth (constant: it faces the camera) against the opaque one.
  const float lin = texelFetch(uDepthTex, ivec2(gl_FragCoord.xy - uOrigin.xy), 0).r;
  if (!((-vCentreRadius.z - uDepth.x) / uDepth.z < lin)) discard;
  const float weight = texture(uFalloff, vUv).r;
  if (!(weight > 0.0)) discard;
  const float r = vCentreRadius.w;
  const vec3 dir = uDepth.w > 0.5 ? vec3(0.0, 0.0, -1.0) : normalize(vView);

  // The material, turning into another over the particle's life.
  const float density = uintBitsToFloat(vData.z);
  const uint seed = vData.w;
  MaterialGpu mat = particleMaterial(vData);

  // The particle's window of the detail video: a random place and time offset from its seed.
  const vec3 tex3 = detailCoord(vUv, seed, mat.windowSpeedShimmerNext.x);
  const float emissive = mat.densityGEmissiveEmission.z;
  const float speed = mat.windowSpeedShimmerNext.y;

  float tau = mat.densityGEmissiveEmission.x * density;
  vec3 radiance = vec3(0.0), scatter = vec3(0.0);
  float kelvin = 0.0;
  float temperatureDetail = 0.5, shimmerY = 0.5;
  if (mat.tempRangeBurnDetail.w > 0.0) tau *= opacityDetail(mat, tex3, speed);
  if (mat.colorAlbedo.a > 0.0) addScattering(mat, dir, radiance, scatter);
  if (emissive > 0.0) addEmission(mat, tex3, speed, emissive, radiance, temperatureDetail, shimmerY, kelvin);

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
