// Nailboard shading (McGuire & Fein Eq. 2) with a per-pixel depth offset (§4.2) and outlines drawn
// from the baked signed distance to the silhouette, so their width is a run-time choice and both
// edges are antialiased (alpha-to-coverage when the target is multisampled).
// Compiled with PUFF_CASTER for the shadow map's caster pass (drawn from the light: depth and id only).
#include "common/frame.glsl"
#include "cel/particle.glsl"
#include "cel/shadow_map.glsl"

in vec2 vPuff;
in float vDist;
in vec3 vWorld;
flat in uint vId;
flat in float vSize;
flat in float vTexelsPerPixel;
flat in ivec4 vCell;
flat in vec4 vWeight;
flat in vec4 vMap[PUFF_VIEWS];
flat in mat3 vNormalXf[PUFF_VIEWS];

// Two reads per pixel, as in the paper: normal x, y (z rebuilt), depth offset and distance to the
// silhouette packed by NailboardRenderer::setAtlas; and the colour.
layout(binding = 2) uniform sampler2D uPacked;
layout(binding = 3) uniform sampler2D uColor;  // scene-linear (an sRGB texture decodes the atlas's display values)

uniform int uPass;          // 0 lit, 1 shadowed (ambient only), 2 depth only
uniform int uShading;       // 1: q(N.L); 0: flat
uniform int uOutlines;      // 1: draw the outline band
uniform float uOutlineWidth;   // pixels
uniform vec3 uOutlineColor;   // display value
uniform int uMultisample;   // 1: alpha-to-coverage resolves the edge; 0: hard edge at half coverage

#ifdef PUFF_CASTER
uniform float uShadowBias;  // diameters past the puff's far side where its shadow starts
layout(location = 0) out uint oId;
#else
out vec4 fragColor;
#endif

void main() {
  // First what every pass needs: depth offset and distance to the silhouette (one read per view).
  // The mip level comes from the particle's projected size, like the texel-to-pixel scale below:
  // no derivatives, so the colour can be read after the discards.
  float lod = max(0.0, log2(max(1e-4, vTexelsPerPixel)));
  // From the particle's projected size, not from derivatives: those break down along the quad's
  // diagonal on some rasterizers, and the size is known anyway.
  float tpp = max(1e-4, vTexelsPerPixel);
  // The distance map holds the distance to the silhouette (texels) up to its range, and a coarse
  // mip blurs it over 2^lod texels: it is trusted below `trusted`. A puff so small that its band
  // and antialiased edge reach past that (puffs a few dozen pixels wide and less) takes its
  // silhouette and band from the radius table instead (particle.glsl, silhouetteRadius), which
  // reaches any distance: outlines never thin away, and silhouettes are not eroded.
  float range = uAtlasScale.z;
  float trusted = range - 1.0 - 0.5 * tpp;
  float wantTexels = uOutlines == 1 ? max(0.0, uOutlineWidth) * tpp : 0.0;
  bool fromTable = wantTexels > trusted;  // the same for the whole puff
  vec2 uv[PUFF_VIEWS];
  vec2 nxy[PUFF_VIEWS];
  bool inside[PUFF_VIEWS];
  float depth = 0.0, dist = 0.0, tableDist = 0.0;
  for (int k = 0; k < PUFF_VIEWS; ++k) {  // a constant bound: unrolled
    vec2 local = mat2(vMap[k].xy, vMap[k].zw) * vPuff;  // the cell's view, puff diameters
    uv[k] = cellUv(vCell[k], local);
    // Lookups stay inside their cell: a rolled or foreshortened quad reaches past the cell's
    // corners, into other variations and views. Outside is empty.
    inside[k] = insideCell(local, lod);
    vec4 pk = inside[k] ? textureLod(uPacked, uv[k], lod) : vec4(0.5, 0.5, 0.5, 1.0);
    nxy[k] = pk.xy * 2.0 - 1.0;
    float w = vWeight[k];
    depth += w * (pk.z - 0.5) * uAtlasScale.y * vNormalXf[k][2].z;
    dist += w * ((pk.w - 0.5) * 2.0 * range);
    if (fromTable) tableDist += w * (length(local) - silhouetteRadius(vCell[k], local)) * uAtlasScale.x;
  }
  // The outline band: 0 < dist <= width (texels). From the map, the band and its antialiased edge
  // (half a pixel) must end inside its range; beyond is empty.
  float widthTexels;
  if (fromTable) {
    dist = dist < trusted ? dist : max(tableDist, trusted);
    widthTexels = wantTexels;
  } else {
    if (dist >= range - 0.5) discard;
    widthTexels = max(0.0, min(wantTexels, range - 1.0 - 0.5 * tpp));
  }
  float coverage = clamp(0.5 - (dist - widthTexels) / tpp, 0.0, 1.0);
  float body = clamp(0.5 - dist / tpp, 0.0, 1.0);
  if (uMultisample == 1 ? coverage <= 0.0 : coverage < 0.5) discard;

  // Outline and flange texels hold d = 0: they sit on the billboard plane, behind the bodies of
  // nearer particles, which is what hides outlines inside a cloud (Fig. 5).
  float d = dist > 0.0 ? 0.0 : depth;
#ifdef PUFF_CASTER
  // Drawn from the light, the map keeps where this puff's shadow starts: behind its far side, taken
  // as its near side's depth-map offset mirrored through the billboard plane (as the shadow volumes
  // take it), plus the bias. Its own near side lies before that, so it does not shadow itself even
  // where the map saw only it.
  gl_FragDepth = storeDepth(linearDepth(vDist + (max(d, 0.0) + uShadowBias) * vSize));
  oId = vId;
#else
  gl_FragDepth = storeDepth(linearDepth(vDist - d * vSize));
  if (uPass == 2) {
    fragColor = vec4(0.0);
    return;
  }
  vec3 ka = ambientAt(gl_FragCoord.xy);
  vec3 rgb = ka;
  if (uPass == 0) {  // the lit pass alone needs the normal and the colour (the second read)
    vec3 n = vec3(0.0), color = vec3(0.0);
    for (int k = 0; k < PUFF_VIEWS; ++k) {
      float w = vWeight[k];
      n += w * (vNormalXf[k] * vec3(nxy[k], sqrt(max(0.0, 1.0 - dot(nxy[k], nxy[k])))));
      if (inside[k]) color += w * textureLod(uColor, uv[k], lod).rgb;  // views blended in linear light
    }
    color = linearToSrgb(color);  // Eq. 2 combines display values
    vec3 q = uShading == 1 ? quantize(dot(normalize(n), uLightDirView.xyz)) : vec3(1.0);
    rgb = ka + color * uLightColor.rgb * q;
    // A shadow-map receiver in another caster's shadow keeps the ambient term only, as the volumes'
    // shadowed pass draws it. The point is on this pixel's eye ray at the offset depth.
    if (shadowMapEnabled()) {
      vec3 p;
      if (isOrthographic()) {
        p = vWorld + normalize(uInvView[2].xyz) * (d * vSize);
      } else {
        p = uCameraWorld.xyz + (vWorld - uCameraWorld.xyz) * ((vDist - d * vSize) / vDist);
      }
      if (inShadowMap(p, vId)) rgb = ka;
    }
  }
  // Eq. 2's result is a display value, limited to the display's range as the paper's 8-bit frame
  // buffer limited it (K_a + C K_L q may exceed 1), then to scene-linear; the outline's antialiased
  // edge blends in linear light.
  rgb = srgbToLinear(clamp(rgb, 0.0, 1.0));
  if (uOutlines == 1) rgb = mix(srgbToLinear(clamp(uOutlineColor, 0.0, 1.0)), rgb, body);
  fragColor = vec4(rgb, uMultisample == 1 ? coverage : 1.0);
#endif
}
