// The C++ side of shaders/common/contract.glsl: the limits, shade passes and uniform locations
// Puff's C++ and GLSL share, read from that one file (its directory is on the private include path
// of every Puff library: puff_gl_api, cmake/glad.cmake).
#pragma once

#include <common/contract.glsl>

namespace puff::shader {

inline constexpr int kMaxLights = PUFF_MAX_LIGHTS;
inline constexpr int kMaxMaterials = PUFF_MAX_MATERIALS;
inline constexpr int kMaxFireBands = PUFF_MAX_FIRE_BANDS;
inline constexpr int kMaxBlurFrames = PUFF_MAX_BLUR_FRAMES;
inline constexpr int kMaxDeferredSamples = PUFF_MAX_DEFERRED_SAMPLES;

inline constexpr int kPassLit = PUFF_PASS_LIT;
inline constexpr int kPassShadowed = PUFF_PASS_SHADOWED;
inline constexpr int kPassDepthOnly = PUFF_PASS_DEPTH_ONLY;

inline constexpr int kOutputColour = PUFF_OUTPUT_COLOUR;
inline constexpr int kOutputNormal = PUFF_OUTPUT_NORMAL;
inline constexpr int kOutputDepth = PUFF_OUTPUT_DEPTH;
inline constexpr int kOutputInk = PUFF_OUTPUT_INK;
inline constexpr int kOutputMotion = PUFF_OUTPUT_MOTION;

/// Uniform locations (contract.glsl names the program of each).
namespace loc {
inline constexpr int kBlurCount = PUFF_LOC_BLUR_COUNT, kBlurWeights = PUFF_LOC_BLUR_WEIGHTS,
                     kBlurViewport = PUFF_LOC_BLUR_VIEWPORT;
inline constexpr int kDownsampleFactor = PUFF_LOC_DOWNSAMPLE_FACTOR;
inline constexpr int kResolveSamples = PUFF_LOC_RESOLVE_SAMPLES;
inline constexpr int kHostProjZW = PUFF_LOC_HOST_PROJ_ZW, kHostPlanes = PUFF_LOC_HOST_PLANES,
                     kHostOrigin = PUFF_LOC_HOST_ORIGIN;
inline constexpr int kFloodStep = PUFF_LOC_FLOOD_STEP;
inline constexpr int kViewTransform = PUFF_LOC_VIEW_TRANSFORM, kViewOrigin = PUFF_LOC_VIEW_ORIGIN,
                     kViewKnee = PUFF_LOC_VIEW_KNEE;
inline constexpr int kPlateOrigin = PUFF_LOC_PLATE_ORIGIN;
inline constexpr int kOpaqueModel = PUFF_LOC_OPAQUE_MODEL, kOpaqueNormalMatrix = PUFF_LOC_OPAQUE_NORMAL_MATRIX,
                     kOpaqueAlbedo = PUFF_LOC_OPAQUE_ALBEDO, kOpaqueCel = PUFF_LOC_OPAQUE_CEL,
                     kOpaquePass = PUFF_LOC_OPAQUE_PASS, kOpaqueId = PUFF_LOC_OPAQUE_ID;
inline constexpr int kVolumeLength = PUFF_LOC_VOLUME_LENGTH, kVolumeFloor = PUFF_LOC_VOLUME_FLOOR,
                     kVolumeBias = PUFF_LOC_VOLUME_BIAS;
}  // namespace loc

}  // namespace puff::shader
