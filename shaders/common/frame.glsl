// Per-frame values shared by every cel program (nailboards, shadow volumes, opaque objects),
// uploaded once per frame by puff::cel::FrameBlock into uniform buffer binding `frameBlock`
// (cel::Bindings; this file's layout(binding) values are never used). The layout
// is mirrored by puff::shader::FrameBlockData (std140, runtime/private/puff/shader_blocks.h).
//
// Depth (McGuire & Fein §4.2): every cel program computes LINEAR depth, the camera-space distance
// along the view axis mapped so that the near plane is 0 and the far plane 1:
//   linear = (-z_view - near) / (far - near)
// so a nailboard's per-pixel offset, the shadow bias and a shadow volume's entry and exit are
// additions. What the depth attachment stores is the host's convention (puff::cel::DepthConvention,
// uDepthMode.x), and each program converts at the very end: gl_FragDepth = storeDepth(linear).
//   linear (0):     the linear depth itself (the paper's; puffrender's);
//   standard (1):   the window depth the host's projection gives at that distance, as the host's
//                   own shaders write it through gl_Position (glDepthRange(0, 1));
//   reversed-z (2): the same with a reversed projection (near -> 1, far -> 0, infinite far too).
// The conversion is monotonic, so comparisons keep their order in every convention.
//
// Colour (docs/colour.md): Eq. 2 combines DISPLAY values (sRGB-encoded, as the paper and the
// artist's palette do): uLightColor and uAmbientColor are display values, and ambientAt and quantize
// return display values (their textures hold scene-linear values, so filtering happens in linear
// light, and are encoded after the lookup). A program decodes Eq. 2's result with srgbToLinear
// before it leaves the shader: the target holds scene-linear colour.
#include "common/colour.glsl"
#include "common/contract.glsl"
layout(std140, binding = 0) uniform FrameBlock {
  mat4 uView;            // world -> camera
  mat4 uProj;            // camera -> clip
  mat4 uViewProj;        // world -> clip
  mat4 uInvView;         // camera -> world
  mat4 uInvViewProj;     // clip -> world
  vec4 uViewport;        // x, y, width, height of the target viewport, pixels
  vec4 uDepthRange;      // near, far, 1 / (far - near), 1 if the projection is orthographic else 0
  vec4 uLightDirView;    // xyz: unit camera-space direction toward the light
  vec4 uLightDirWorld;   // xyz: unit world-space direction toward the light
  vec4 uLightColor;      // rgb: K_L
  vec4 uAmbientColor;    // rgb: uniform K_a (used when uAmbientMode.x == 0)
  vec4 uCameraWorld;     // xyz: camera position in world space
  ivec4 uAmbientMode;    // x: 1 = K_a from the gradient texture, 0 = uniform colour
  mat4 uShadowMatrix;    // world -> the shadow map's clip space (cel/shadow_map.glsl)
  vec4 uShadowParams;    // x: 1 = receivers look up the shadow map; y: tolerance, z: length (map depth units)
  vec4 uDepthProj;       // uProj[2][2], uProj[3][2], uProj[2][3], uProj[3][3]: the clip z and w rows at (0, 0, -d, 1)
  ivec4 uDepthMode;      // x: 0 linear, 1 standard, 2 reversed-z; y: 1 = clip z in [0, 1], 0 = [-1, 1]
  ivec4 uOutput;         // x: what the lit passes write, PUFF_OUTPUT_* (common/contract.glsl)
  vec4 uOutputScale;     // x: PUFF_OUTPUT_DEPTH's distance written as 0.5, y: 1 / (2 range); z: PUFF_OUTPUT_MOTION's 1 / (2 range)
};

layout(binding = 0) uniform sampler1D uRamp;      // q: the artist's ramp, clamp-to-edge; scene-linear texels
layout(binding = 1) uniform sampler2D uGradient;  // K_a(x, y): image-space gradient, top row at the top; scene-linear

// Linear depth of a camera-space point at view-axis distance `dist` (= -z_view).
float linearDepth(float dist) { return (dist - uDepthRange.x) * uDepthRange.z; }

// What the depth attachment stores for linear depth `linear` (the value every cel program writes to
// gl_FragDepth). Linear: as it is (the depth buffer clamps). Standard and reversed-z: the distance
// d = near + linear (far - near), never nearer than the near plane (the linear buffer would clamp
// there too, and w must stay positive), through the projection: clip = uProj * (0, 0, -d, 1),
// ndc = clip.z / clip.w, window = ndc ([0, 1] clip z) or 0.5 ndc + 0.5 ([-1, 1]), in [0, 1]. Linear
// depth above 1 (past uDepthRange's far, with an infinite-far projection) converts as well.
// puff::cel::storedDepth is the same arithmetic on the CPU.
float storeDepth(float linear) {
  if (uDepthMode.x == 0) return linear;
  float dist = uDepthRange.x + max(linear, 0.0) * (uDepthRange.y - uDepthRange.x);
  float z = uDepthProj.y - uDepthProj.x * dist, w = uDepthProj.w - uDepthProj.z * dist;
  float ndc = z / w;
  return clamp(uDepthMode.y != 0 ? ndc : 0.5 * ndc + 0.5, 0.0, 1.0);
}

// What a lit pass writes in place of its colour when the frame asks for a map (uOutput.x != 0):
// camera-space normal `n` (any length; none: facing the camera), the view-axis distance `dist`, the
// ink's share `ink` of the covered pixel, or the screen motion `motion` (pixels) to the next frame,
// as PUFF_OUTPUT_* encodes each. Data, not colour: no transfer function, no ink mixed in.
vec3 mapValue(vec3 n, float dist, float ink, vec2 motion) {
  if (uOutput.x == PUFF_OUTPUT_NORMAL) return 0.5 * (dot(n, n) > 1e-12 ? normalize(n) : vec3(0.0, 0.0, 1.0)) + 0.5;
  if (uOutput.x == PUFF_OUTPUT_DEPTH) return vec3(0.5 + (uOutputScale.x - dist) * uOutputScale.y);
  if (uOutput.x == PUFF_OUTPUT_MOTION) return vec3(0.5 + motion * uOutputScale.z, 0.0);
  return vec3(ink);
}

// Where world point `p` moves on the screen (pixels, x right, y up) when it goes to `next`.
vec2 screenMotion(vec3 p, vec3 next) {
  vec4 a = uViewProj * vec4(p, 1.0), b = uViewProj * vec4(next, 1.0);
  return (b.xy / b.w - a.xy / a.w) * 0.5 * uViewport.zw;
}

// K_a at the current fragment (Eq. 2), a display value: the gradient image stretched over the viewport.
vec3 ambientAt(vec2 fragCoord) {
  if (uAmbientMode.x == 0) return uAmbientColor.rgb;
  vec2 uv = (fragCoord - uViewport.xy) / uViewport.zw;
  return linearToSrgb(texture(uGradient, uv).rgb);  // stored bottom-up: t = 1 is the image's top row
}

// q(max(0, N.L)), a display value: the ramp's clamp-to-edge addressing enforces the max (§4.1), so
// the raw dot product goes in.
vec3 quantize(float nDotL) {
  return linearToSrgb(texture(uRamp, nDotL).rgb);
}
