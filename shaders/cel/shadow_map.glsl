// Shadow-map receivers (Style::shadowMethod "map"; puff::cel::ShadowMap draws the map). The map holds,
// per texel, where the nearest caster's shadow starts along the light (its far side plus the bias,
// in the map's depth, [0, 1]) and that caster's id; uShadowMatrix and uShadowParams come with the
// frame block (common/frame.glsl). Texels are read nearest, without filtering: shadow edges stay
// as hard as the cel bands (a texel of the map is about a pixel of the screen at the casters).
layout(binding = 6) uniform sampler2D uShadowMapDepth;  // DEPTH_COMPONENT32F, compare mode off
layout(binding = 7) uniform usampler2D uShadowMapId;    // R32UI: caster id, 0 where nothing was drawn

bool shadowMapEnabled() { return uShadowParams.x > 0.5; }

// True when world point `p`, on the caster with id `own` (a puff never shadows itself, nor an object
// itself), lies in another caster's shadow: at least the tolerance behind where it starts, and no
// more than the shadow's length.
bool inShadowMap(vec3 p, uint own) {
  vec4 c = uShadowMatrix * vec4(p, 1.0);
  vec2 uv = c.xy * 0.5 + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return false;
  ivec2 size = textureSize(uShadowMapId, 0);
  ivec2 t = min(ivec2(uv * vec2(size)), size - 1);
  uint id = texelFetch(uShadowMapId, t, 0).r;
  if (id == 0u || id == own) return false;
  float behind = (c.z * 0.5 + 0.5) - texelFetch(uShadowMapDepth, t, 0).r;
  return behind > uShadowParams.y && behind <= uShadowParams.z;
}
