// The std140 mirrors of the uniform blocks in Puff's GLSL, field for field: what the libraries
// upload into each block's buffer. ShaderContract (tests/unit/shader_test.cpp) compares each size with
// GL_UNIFORM_BLOCK_DATA_SIZE in every program that declares the block.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include <puff/shader_contract.h>

namespace puff::shader {

/// shaders/common/frame.glsl's FrameBlock (puff::cel::FrameBlock uploads it).
struct FrameBlockData {
  glm::mat4 view, proj, viewProj, invView, invViewProj;
  glm::vec4 viewport, depthRange, lightDirView, lightDirWorld, lightColor, ambientColor, cameraWorld;
  glm::ivec4 ambientMode;
  glm::mat4 shadowMatrix;
  glm::vec4 shadowParams;
  glm::vec4 depthProjection;
  glm::ivec4 depthMode;
  glm::ivec4 output;
  glm::vec4 outputScale;
};
static_assert(sizeof(FrameBlockData) == 6 * 64 + 13 * 16);

/// shaders/common/media.glsl's MediaBlock (puff::media::Renderer).
struct MediaBlockData {
  glm::mat4 view, proj, invProj;
  glm::vec4 target, origin, depth, lightDir, lightColor, ambient, kelvin;
  glm::ivec4 mode;
  glm::vec4 time;
  glm::vec4 cartoon;
};

/// One entry of shaders/common/media.glsl's MaterialBlock, which holds kMaxMaterials of them.
struct MaterialGpu {
  glm::vec4 colorAlbedo, densityGEmissiveEmission, tempRangeBurnDetail, windowSpeedShimmerNext, transition;
};
static_assert(sizeof(MaterialGpu) == 80);

/// shaders/media/compose.glsl's ComposeBlock (puff::media::Layers) and its lights.
struct LightGpu {
  glm::vec4 centreRadius, colorIntensity;
  glm::ivec4 flags;
};
struct ComposeBlockData {
  glm::mat4 invProj;
  glm::vec4 viewport, depth, layer, shimmer;
  glm::ivec4 counts;
  LightGpu lights[kMaxLights];
};

/// shaders/media/cartoon.glsl's CartoonBlock (puff::media::Layers).
struct CartoonBlockData {
  glm::vec4 style, ink;
  glm::vec4 fireColors[kMaxFireBands];
};

}  // namespace puff::shader
