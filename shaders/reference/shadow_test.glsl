// The cel reference's shadow test: two maps of the puff meshes seen from the light. Pass 1
// keeps the nearest surface's distance and its puff's id; pass 2 the nearest surface of ANY OTHER
// puff than the one pass 1 kept there. A point of puff `id` is in shadow when the nearest surface of
// another puff lies between it and the light: d1 if pass 1 saw another puff there, else d2. A point
// of opaque object `id` (kObjectIdBase + its index; the objects are drawn into both maps too) likewise;
// id 0 is shadowed by every caster (d1). A shadow reaches uShadowLength past its caster, as the
// methods' do (Style::shadowLength). Exact up to the map's texel.
layout(binding = 4) uniform sampler2D uShadowNear;    // R32F: pass 1 distance (1e30: nothing)
layout(binding = 5) uniform usampler2D uShadowId;     // R32UI: pass 1 puff id (0: nothing)
layout(binding = 6) uniform sampler2D uShadowOther;   // R32F: pass 2 distance
uniform mat4 uShadowView;   // world -> light space
uniform mat4 uShadowProj;   // light space -> clip
uniform float uShadowBias;  // light-space distance, world units
uniform float uShadowLength;  // world units

bool inShadow(vec3 world, uint id) {
  vec4 lv = uShadowView * vec4(world, 1.0);
  vec4 clip = uShadowProj * lv;
  vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return false;
  ivec2 size = textureSize(uShadowNear, 0);
  ivec2 t = min(ivec2(uv * vec2(size)), size - 1);
  uint nearId = texelFetch(uShadowId, t, 0).r;
  float occluder = (nearId != id) ? texelFetch(uShadowNear, t, 0).r : texelFetch(uShadowOther, t, 0).r;
  float behind = -lv.z - occluder;
  return behind > uShadowBias && behind <= uShadowLength;
}
