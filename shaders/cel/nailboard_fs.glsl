// Nailboard shading (McGuire & Fein Eq. 2) with a per-pixel depth offset (§4.2) and outlines drawn
// from the baked signed distance to the silhouette, so their width is a run-time choice and both
// edges are antialiased (alpha-to-coverage when the target is multisampled).
// Compiled with PUFF_CASTER for the shadow map's caster pass (drawn from the light: depth and id only),
// and with PUFF_HULL (four views, nailboard_hull*.frag) to draw oriented puffs by marching the hull of
// their views (style.tumble "hull"); without it, oriented puffs blend four views and the program
// carries none of the hull's code (its registers would slow every puff drawn with it).
// Every other variant is compiled once per shade pass, PUFF_SHADE_PASS (PUFF_PASS_LIT, _SHADOWED or
// _DEPTH_ONLY, common/contract.glsl): a pass carries none of the code it does not run, since a
// uniform's branch still costs what it skips on a rasterizer that runs both sides under a mask.
// The lit and shadowed passes shade each pixel once (cel::LitShading, nailboards.h): PUFF_VISIBILITY
// compiles the pre-pass (the quads' depth and particle id into Puff's own target), PUFF_DEFERRED the
// screen pass that shades each pixel's particles from it (PUFF_DEFERRED_MS: multisampled), the
// quads' varyings computed per pixel (nailboard_setup.glsl).
#include "common/frame.glsl"
#include "cel/particle.glsl"
#include "cel/shadow_map.glsl"

#include "cel/nailboard_io.glsl"
#ifdef PUFF_DEFERRED
#include "cel/nailboard_setup.glsl"
#endif

// Two reads per pixel, as in the paper: normal x, y (z rebuilt), depth offset and distance to the
// silhouette packed by NailboardRenderer::setAtlas; and the colour.
layout(binding = 2) uniform sampler2D uPacked;
layout(binding = 3) uniform sampler2D uColor;  // scene-linear (an sRGB texture decodes the atlas's display values)

uniform int uShading;       // 1: q(N.L); 0: flat
uniform vec3 uOutlineColor;   // display value
uniform int uMultisample;   // 1: alpha-to-coverage resolves the edge; 0: hard edge at half coverage

#if defined(PUFF_DEFERRED) && defined(PUFF_HULL)
#error "the tumbling hull is drawn forward: no deferred variant"
#endif
#if !defined(PUFF_CASTER) && !defined(PUFF_SHADE_PASS)
#error "a nailboard program that is not a caster names its PUFF_SHADE_PASS"
#endif
#ifdef PUFF_CASTER
uniform float uShadowBias;  // diameters past the puff's far side where its shadow starts
layout(location = 0) out uint oId;
#elif defined(PUFF_VISIBILITY)
// The visibility pre-pass (a depth-only pass into Puff's own target): the nearest particle's id and
// the depth it stores, per pixel, for the deferred shading pass.
layout(location = 0) out uvec2 oVisible;
#else
out vec4 fragColor;
#endif

// Samples per pixel of the target (multisampled: the visibility pre-pass's sample mask, the
// deferred pass's loop).
uniform int uSamples;

#ifdef PUFF_DEFERRED
// The pixel's clip-space x, y (cel/screen_rect.vert): from it, not from gl_FragCoord, whose y runs
// down the clip space's under glClipControl(GL_UPPER_LEFT, ...).
in vec2 vScreenNdc;
// The visibility pre-pass's target: x the particle id (0: none), y the bits of the depth stored.
#ifdef PUFF_DEFERRED_MS
layout(binding = 8) uniform usampler2DMS uVisible;
#else
layout(binding = 8) uniform usampler2D uVisible;
#endif

// The varyings the vertex stage would have given the nailboard of particle `id` at this pixel: its
// per-particle values (setUpParticle), and where the pixel's eye ray meets its billboard plane.
void loadVarying(uint id) {
  Particle p = unpackParticle(id - 1u);
  mat3 bb = billboardFrame(p);
  setUpParticle(id - 1u, p, bb);
  vec4 onRay = uInvViewProj * vec4(vScreenNdc, 0.5, 1.0);
  vec3 origin = onRay.xyz / onRay.w;
  vec3 dir = isOrthographic() ? -uInvView[2].xyz : origin - uCameraWorld.xyz;
  vec3 world = origin + dir * (dot(p.position - origin, bb[2]) / dot(dir, bb[2]));
  vPuff = vec2(dot(world - p.position, bb[0]), dot(world - p.position, bb[1])) / p.size;
  vWorld = world;
  vDist = -(uView * vec4(world, 1.0)).z;
}
#endif

#ifdef PUFF_HULL
#include "cel/hull_march.glsl"
#endif

// The blend of the views' packed maps at this fragment: each view's lookup (uv, inside its cell)
// and normal, and the weighted depth offset and silhouette distance (texels; tableDist the radius
// table's, read only when fromTable). All zero where the blend does not shade (`shades` false).
struct ViewBlend {
  vec2 uv[PUFF_VIEWS];
  vec2 nxy[PUFF_VIEWS];
  bool inside[PUFF_VIEWS];
  float depth, dist, tableDist;
};

ViewBlend blendViews(float lod, float range, bool fromTable, bool shades) {
  ViewBlend v;
  v.depth = 0.0;
  v.dist = 0.0;
  v.tableDist = 0.0;
  for (int k = 0; k < PUFF_VIEWS; ++k) {  // a constant bound: unrolled
    v.uv[k] = vec2(0.0);
    v.nxy[k] = vec2(0.0);
    v.inside[k] = false;
    if (!shades) continue;
    vec2 local = mat2(vMap[k].xy, vMap[k].zw) * vPuff;  // the cell's view, puff diameters
    v.uv[k] = cellUv(vCell[k], local);
    // Lookups stay inside their cell: a rolled or foreshortened quad reaches past the cell's
    // corners, into other variations and views. Outside is empty.
    v.inside[k] = insideCell(local, lod);
    vec4 pk = v.inside[k] ? textureLod(uPacked, v.uv[k], lod) : vec4(0.5, 0.5, 0.5, 1.0);
    v.nxy[k] = pk.xy * 2.0 - 1.0;
    float w = vWeight[k];
    v.depth += w * (pk.z - 0.5) * uAtlasScale.y * vNormalXf[k][2].z;
    v.dist += w * ((pk.w - 0.5) * 2.0 * range);
    if (fromTable) v.tableDist += w * (length(local) - silhouetteRadius(vCell[k], local)) * uAtlasScale.x;
  }
  return v;
}

#ifndef PUFF_CASTER
// The blend's normal (camera space, unnormalized) and colour (scene-linear: views blended in linear
// light; the colour map is the second read, the lit pass's alone).
void blendedSurface(ViewBlend v, float lod, out vec3 n, out vec3 color) {
  n = vec3(0.0);
  color = vec3(0.0);
  for (int k = 0; k < PUFF_VIEWS; ++k) {
    float w = vWeight[k];
    n += w * (vNormalXf[k] * vec3(v.nxy[k], sqrt(max(0.0, 1.0 - dot(v.nxy[k], v.nxy[k])))));
    if (v.inside[k]) color += w * textureLod(uColor, v.uv[k], lod).rgb;
  }
}

// The world point this fragment shades: on its eye ray at the offset depth `d` (diameters toward
// the eye).
vec3 pointAtOffset(float d) {
  if (isOrthographic()) return vWorld + normalize(uInvView[2].xyz) * (d * vSize);
  return uCameraWorld.xyz + (vWorld - uCameraWorld.xyz) * ((vDist - d * vSize) / vDist);
}
#endif

// The outline band: 0 < dist <= width (texels), the width returned. From the map, the band and its
// antialiased edge (half a pixel) must end inside its range; beyond is empty (dist made so far that
// nothing covers the pixel). With
// `fromTable`, a blended distance past what the map holds is the radius table's (`tableDist`).
float outlineBand(bool fromTable, bool blended, float tableDist, float trusted, float range, float wantTexels,
                  float tpp, inout float dist) {
  if (fromTable) {
    if (blended) dist = dist < trusted ? dist : max(tableDist, trusted);
    return wantTexels;
  }
  if (dist >= range - 0.5) dist = 1e30;  // nothing drawn: no coverage
  return max(0.0, min(wantTexels, range - 1.0 - 0.5 * tpp));
}

#if defined(PUFF_HULL) && !defined(PUFF_CASTER)
// The hull's occluders (NailboardRenderer, drawn into Puff's own target before the hull: uOccluded
// 1): per pixel the view depth of the nearest core's disc (hull_occluder.frag), behind which that
// puff's hull is drawn. A marched puff whose every depth at the pixel lies behind it is hidden there:
// its fragment is dropped before it marches. Its depths lie within its unit sphere (the march's
// chord, hullMarch) or on its billboard plane (the ink). Compared as the depth buffer stores them,
// uOccluderSteps of its steps apart at least: two depths the buffer would store alike (clamped at the
// near or far plane, or within its precision) tie there, and a tie is left to the depth test.
layout(binding = 8) uniform sampler2D uOccluders;
uniform int uOccluded;
uniform float uOccluderSteps;  // the margin: that many of the host depth buffer's steps
bool hullOccluded() {
  if (uOccluded != 1 || vHull != 1) return false;
  ivec2 px = ivec2(gl_FragCoord.xy);
  if (any(greaterThanEqual(px, textureSize(uOccluders, 0)))) return false;  // past the frame's viewport
  float chord = sqrt(max(0.25 - dot(vPuff, vPuff), 0.0));  // half the chord, diameters
  float nearest = storeDepth(linearDepth(vDist - chord * abs(vNormalXf[0][2].z) * vSize));
  float disc = storeDepth(linearDepth(texelFetch(uOccluders, px, 0).r));
  return uDepthMode.x == 2 ? nearest < disc - uOccluderSteps : nearest > disc + uOccluderSteps;
}
#endif

#ifdef PUFF_HULL
// An oriented puff: the hull marched (hullMarch) in place of the blend, whose depth offset and
// silhouette distance (texels: outside, the least distance to the hull; inside, how deep the ray
// reaches into it) replace the blend's.
HullHit marchHull(float lod, float tpp, float wantTexels, inout float depth, inout float dist) {
  float reach = (wantTexels + tpp) / uAtlasScale.x;
#ifdef PUFF_CASTER
  HullHit hull = hullMarch(lod, tpp, reach, false, false);
#else
  const bool wantEdge = PUFF_SHADE_PASS != PUFF_PASS_DEPTH_ONLY, wantShade = PUFF_SHADE_PASS == PUFF_PASS_LIT;
  HullHit hull = hullMarch(lod, tpp, reach, wantEdge, wantShade);
#endif
  depth = hull.t * vNormalXf[0][2].z;
  dist = hull.hit ? min(hull.deepest * uAtlasScale.x, -1e-3) : max(hull.nearest * uAtlasScale.x, 1e-3);
  return hull;
}
#endif

#ifndef PUFF_CASTER
// A motion map's frame (PUFF_OUTPUT_MOTION): each particle where it is at the next frame (world xyz,
// its size in w), in the upload's order (NailboardRenderer::uploadNext). Read by no other frame.
layout(std430, binding = 2) readonly buffer ParticleNext { vec4 particleNext[]; };

// This fragment's billboard point carried to the next frame as its particle moves and grows
// (screenMotion, pixels). A tumbling puff's turn is not in it.
vec2 billboardMotion() {
  Particle p = unpackParticle(vId - 1u);
  vec4 next = particleNext[vId - 1u];
  return screenMotion(vWorld, next.xyz + (vWorld - p.position) * (next.w / max(p.size, 1e-6)));
}

// Eq. 2, K_a + C K_L q(N . L), in display values: the surface's colour (scene-linear) is encoded and
// the particle's tint multiplies it. A shadow-map receiver in another caster's shadow keeps the
// ambient term only, as the volumes' shadowed pass draws it.
vec3 litColor(vec3 ka, vec3 n, vec3 color, float d) {
  color = linearToSrgb(color) * vTint;
  vec3 q = uShading == 1 ? quantize(dot(normalize(n), uLightDirView.xyz)) : vec3(1.0);
  vec3 rgb = ka + color * uLightColor.rgb * q;
  if (shadowMapEnabled() && inShadowMap(pointAtOffset(d), vId)) rgb = ka;
  return rgb;
}
#endif

// A nailboard fragment as every pass sees it (evaluateFragment).
struct NailboardFragment {
  float coverage;  // of the pixel, the ink's outer edge antialiased (0: nothing drawn)
  float body;      // the body's share of it (the rest is ink)
  float d;         // depth offset, diameters toward the eye (0 on the ink and flange)
  float lod;
  ViewBlend views;
#ifdef PUFF_HULL
  bool marched;
  float blendDist;  // the blend's distance to its silhouette (when it shades)
  HullHit hull;
#endif
};

// First what every pass needs: depth offset and distance to the silhouette (one read per view).
// The mip level comes from the particle's projected size, like the texel-to-pixel scale below:
// no derivatives, so the colour can be read after the discards.
NailboardFragment evaluateFragment() {
  NailboardFragment f;
  float lod = max(0.0, log2(max(1e-4, vTexelsPerPixel)));
  f.lod = lod;
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
#ifdef PUFF_HULL
  bool marched = vHull == 1;  // an oriented puff: hullMarch below, not the blend of four views
  bool blendShades = !marched || vHullBehind == 1;  // from behind, the blend shades the hull (below)
  f.marched = marched;
#else
  const bool marched = false, blendShades = true;
#endif
  f.views = blendViews(lod, range, fromTable, blendShades);
  float depth = f.views.depth, dist = f.views.dist;
#ifdef PUFF_HULL
  f.blendDist = dist;
  if (marched) f.hull = marchHull(lod, tpp, wantTexels, depth, dist);
#endif
  float widthTexels = outlineBand(fromTable, !marched, f.views.tableDist, trusted, range, wantTexels, tpp, dist);
  f.coverage = clamp(0.5 - (dist - widthTexels) / tpp, 0.0, 1.0);
  f.body = clamp(0.5 - dist / tpp, 0.0, 1.0);
  // Outline and flange texels hold d = 0: they sit on the billboard plane, behind the bodies of
  // nearer particles, which is what hides outlines inside a cloud (Fig. 5).
  f.d = dist > 0.0 ? 0.0 : depth;
  return f;
}

#if !defined(PUFF_CASTER) && !defined(PUFF_VISIBILITY)
// The colour of a lit (or shadowed) fragment, scene-linear.
vec3 shadeFragment(NailboardFragment f) {
  vec3 ka = ambientAt(gl_FragCoord.xy);
  vec3 rgb = ka;
  if (PUFF_SHADE_PASS == PUFF_PASS_LIT) {  // the lit pass alone needs the normal and the colour (the second read)
    vec3 n, color;
    blendedSurface(f.views, f.lod, n, color);
#ifdef PUFF_HULL
    if (f.marched && f.hull.hit) {
      // Seen from behind, the hull's surface is an assumption that differs from view to view: the
      // blend's turned normals shade it (coherent, as the blend draws backs) where the blend covers
      // the pixel; the colour is the hull's.
      if (!f.hull.behind || f.blendDist > 0.0) n = f.hull.normal;
      color = f.hull.color;
    }
#endif
    if (uOutput.x != PUFF_OUTPUT_COLOUR)
      return mapValue(n, vDist - f.d * vSize, uOutlines == 1 ? 1.0 - f.body : 0.0, billboardMotion());
    rgb = litColor(ka, n, color, f.d);
  }
  // Eq. 2's result is a display value, limited to the display's range as the paper's 8-bit frame
  // buffer limited it (K_a + C K_L q may exceed 1), then to scene-linear; the outline's antialiased
  // edge blends in linear light.
  rgb = srgbToLinear(clamp(rgb, 0.0, 1.0));
  if (uOutlines == 1) rgb = mix(srgbToLinear(clamp(uOutlineColor, 0.0, 1.0)), rgb, f.body);
  return rgb;
}
#endif

#ifdef PUFF_DEFERRED
// Each pixel's particles, as the pre-pass left them (one per sample), shaded once each at the
// pixel's centre, as the nailboards' quads would have shaded them there. The pre-pass kept them: none
// is discarded. Single-sampled, exactly what the quads draw. Multisampled, the samples' colours
// averaged over the samples the particles cover (what the resolve makes of them) and written to
// those samples at the depth of the particle that covers most of them: a sample of another particle
// at the pixel (only along silhouettes) takes that depth.
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);  // (the target spans the viewport's origin)
#ifdef PUFF_DEFERRED_MS
  uvec2 samples[PUFF_MAX_DEFERRED_SAMPLES];
  int count = clamp(uSamples, 1, PUFF_MAX_DEFERRED_SAMPLES);
  int mask = 0;
  for (int i = 0; i < count; ++i) {
    samples[i] = texelFetch(uVisible, px, i).xy;
    if (samples[i].x != 0u) mask |= 1 << i;
  }
  if (mask == 0) discard;
  vec3 sum = vec3(0.0);
  int covered = 0, most = 0;
  float depth = 0.0;
  for (int i = 0; i < count; ++i) {
    uint id = samples[i].x;
    bool first = id != 0u;
    int n = 0;
    for (int j = 0; j < count; ++j) {
      first = first && !(j < i && samples[j].x == id);
      n += samples[j].x == id ? 1 : 0;
    }
    if (!first) continue;
    loadVarying(id);
    sum += float(n) * shadeFragment(evaluateFragment());
    covered += n;
    if (n > most) {
      most = n;
      depth = uintBitsToFloat(samples[i].y);
    }
  }
  gl_SampleMask[0] = mask;
  gl_FragDepth = depth;
  fragColor = vec4(sum / float(covered), 1.0);
#else
  uvec2 visible = texelFetch(uVisible, px, 0).xy;
  if (visible.x == 0u) discard;
  loadVarying(visible.x);
  gl_FragDepth = uintBitsToFloat(visible.y);
  fragColor = vec4(shadeFragment(evaluateFragment()), 1.0);
#endif
}
#else
void main() {
#if defined(PUFF_HULL) && !defined(PUFF_CASTER)
  if (hullOccluded()) discard;
#endif
  NailboardFragment f = evaluateFragment();
  if (uMultisample == 1 ? f.coverage <= 0.0 : f.coverage < 0.5) discard;
#ifdef PUFF_CASTER
  // Drawn from the light, the map keeps where this puff's shadow starts: behind its far side, taken
  // as its near side's depth-map offset mirrored through the billboard plane (as the shadow volumes
  // take it), plus the bias. Its own near side lies before that, so it does not shadow itself even
  // where the map saw only it.
  gl_FragDepth = storeDepth(linearDepth(vDist + (max(f.d, 0.0) + uShadowBias) * vSize));
  oId = vId;
#elif defined(PUFF_VISIBILITY)
  gl_FragDepth = storeDepth(linearDepth(vDist - f.d * vSize));
  // Multisampled, the coverage goes to the sample mask (an integer target has no alpha for
  // alpha-to-coverage): sample s where coverage > s / samples, the rule Mesa's rasterizers spend
  // alpha-to-coverage's alpha by, so the quads drawn forward there cover the same samples. (A GPU
  // may dither its own; the count of samples is the same on average.)
  if (uMultisample == 1) {
    int mask = 0;
    for (int s = 0; s < uSamples; ++s) mask |= f.coverage > float(s) / float(uSamples) ? 1 << s : 0;
    gl_SampleMask[0] = mask;
  }
  oVisible = uvec2(vId, floatBitsToUint(clamp(gl_FragDepth, 0.0, 1.0)));
#else
  gl_FragDepth = storeDepth(linearDepth(vDist - f.d * vSize));
  if (PUFF_SHADE_PASS == PUFF_PASS_DEPTH_ONLY) {
    fragColor = vec4(0.0);
    return;
  }
  fragColor = vec4(shadeFragment(f), uMultisample == 1 ? f.coverage : 1.0);
#endif
}
#endif
