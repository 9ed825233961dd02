// Per-frame values shared by every cel program (nailboards, shadow volumes, opaque objects),
// uploaded once per frame by puff::cel::FrameBlock into uniform buffer binding 0. The layout
// mirrors puff::cel::FrameBlockData (std140) field for field.
//
// Depth convention (McGuire & Fein §4.2): the depth buffer holds LINEAR depth, the camera-space
// distance along the view axis mapped so that the near plane is 0 and the far plane 1:
//   depth = (-z_view - near) / (far - near)
// Every cel program writes gl_FragDepth this way, so a nailboard's per-pixel offset is an addition.
//
// Colour (docs/colour.md): Eq. 2 combines DISPLAY values (sRGB-encoded, as the paper and the
// artist's palette do): uLightColor and uAmbientColor are display values, and ambientAt and quantize
// return display values (their textures hold scene-linear values, so filtering happens in linear
// light, and are encoded after the lookup). A program decodes Eq. 2's result with srgbToLinear
// before it leaves the shader: the target holds scene-linear colour.
#include "common/colour.glsl"
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
};

layout(binding = 0) uniform sampler1D uRamp;      // q: the artist's ramp, clamp-to-edge; scene-linear texels
layout(binding = 1) uniform sampler2D uGradient;  // K_a(x, y): image-space gradient, top row at the top; scene-linear

// Linear depth of a camera-space point at view-axis distance `dist` (= -z_view).
float linearDepth(float dist) { return (dist - uDepthRange.x) * uDepthRange.z; }

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
