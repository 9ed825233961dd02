// What both media billboard programs (billboard_body.glsl, billboard_textured_body.glsl) shade
// alike once a pixel's optical path is known: the particle's material, the detail video, the
// scattered light and the emission. Included after each program's inputs and samplers.

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

// The particle's material (data.x) at its life (data.y, float bits): blended into the material it
// becomes (its next) over its transition.
MaterialGpu particleMaterial(uvec4 data) {
  const uint mi = min(data.x, 31u);
  const float life = uintBitsToFloat(data.y);
  MaterialGpu mat = uMaterials[mi];
  const int next = int(mat.windowSpeedShimmerNext.w);
  if (next >= 0) {
    const vec2 tr = mat.transition.xy;
    const float f = tr.y > tr.x ? clamp((life - tr.x) / (tr.y - tr.x), 0.0, 1.0) : step(tr.x, life);
    mat = blend(mat, uMaterials[min(next, PUFF_MAX_MATERIALS - 1)], f);
  }
  return mat;
}

// The point of the detail video (x, y, time) at `uv` in the particle's window: a random place and
// time offset from its seed, `uv` scaled by the material's window.
vec3 detailCoord(vec2 uv, uint seed, float window) {
  return vec3(vec2(unitHash(seed), unitHash(seed ^ 0x68bc21ebu)) + uv * window, unitHash(seed ^ 0x02e5be93u));
}

// The opacity detail's factor on tau: the opacity video at tex3, played at the material's speed,
// moves it by up to the material's detail amount either way, never below 0.
float opacityDetail(MaterialGpu mat, vec3 tex3, float speed) {
  const vec3 size = vec3(textureSize(uOpacityDetail, 0));
  const float D = texture(uOpacityDetail, vec3(tex3.xy, tex3.z + uTime.x * speed / size.z)).r;
  return max(0.0, 1.0 + mat.tempRangeBurnDetail.w * (2.0 * D - 1.0));
}

// The light the material scatters toward the eye along `dir` (the ambient and the light through the
// phase function, times its colour and albedo), added to `radiance`.
void addScattering(MaterialGpu mat, vec3 dir, inout vec3 radiance, out vec3 scatter) {
  const float cosTheta = dot(uLightDir.xyz, dir);  // light's travel vs the scattered direction
  const float g = mat.densityGEmissiveEmission.y;
  const vec2 pc = vec2(sqrt(clamp((1.0 - cosTheta) * 0.5, 0.0, 1.0)), (g + 0.95) / 1.9);
  const vec2 ps = vec2(textureSize(uPhase, 0));
  const float p4pi = texture(uPhase, (pc * (ps - 1.0) + 0.5) / ps).r;
  const vec3 C = uAmbient.rgb + uLightColor.rgb * p4pi;
  scatter = mat.colorAlbedo.a * mat.colorAlbedo.rgb * C;
  radiance += scatter;
}

// The black body's radiance at the particle's temperature (T0 plus the material's range times the
// temperature video at tex3, played at the material's speed), times the emissive weight, the emission
// scale and the exposure, added to `radiance`. temperatureDetail and shimmerY: the video's two
// samples (the shimmer's x and y); kelvin: the temperature.
void addEmission(MaterialGpu mat, vec3 tex3, float speed, float emissive, inout vec3 radiance,
                 out float temperatureDetail, out float shimmerY, out float kelvin) {
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
