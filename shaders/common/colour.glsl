// The sRGB transfer function (IEC 61966-2-1), as puff::core::srgbToLinear / linearToSrgb
// (runtime/include/puff/core/colour.h; docs/colour.md). DISPLAY values are sRGB-encoded; SCENE-LINEAR
// values are light (Rec. 709 primaries). Negative values keep their sign.
vec3 srgbToLinear(vec3 display) {
  vec3 a = abs(display);
  vec3 l = mix(a / 12.92, pow((a + 0.055) / 1.055, vec3(2.4)), greaterThan(a, vec3(0.04045)));
  return sign(display) * l;
}

vec3 linearToSrgb(vec3 linear) {
  vec3 a = abs(linear);
  vec3 d = mix(a * 12.92, 1.055 * pow(a, vec3(1.0 / 2.4)) - 0.055, greaterThan(a, vec3(0.0031308)));
  return sign(linear) * d;
}
