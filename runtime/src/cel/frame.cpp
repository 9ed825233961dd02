#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <puff/cel/frame.h>
#include <puff/core/bind_points.h>
#include <puff/core/colour.h>
#include <puff/core/number_text.h>
#include <puff/gl_api.h>
#include <puff/shader_blocks.h>
#include <puff/shader_contract.h>

namespace puff::cel {

glm::mat4 Camera::view() const { return glm::lookAt(position, target, up); }

glm::mat4 Camera::projection(float aspect) const {
  if (fovYDegrees <= 0.0f) {
    const float h = orthoHeight * 0.5f, w = h * aspect;
    return glm::ortho(-w, w, -h, h, nearPlane, farPlane);
  }
  return glm::perspective(glm::radians(fovYDegrees), aspect, nearPlane, farPlane);
}

Frame Frame::fromCamera(const Camera& camera, int width, int height) {
  Frame f;
  f.view = camera.view();
  f.projection = camera.projection(static_cast<float>(width) / static_cast<float>(std::max(1, height)));
  f.nearPlane = camera.nearPlane;
  f.farPlane = camera.farPlane;
  f.viewport = {0, 0, width, height};
  return f;
}

float linearDepth(const Frame& frame, const glm::vec3& worldPoint) {
  const float dist = -(frame.view * glm::vec4(worldPoint, 1.0f)).z;
  return (dist - frame.nearPlane) / (frame.farPlane - frame.nearPlane);
}

float storedDepth(const Frame& frame, float linear) {
  return core::storedDepth({frame.depth, frame.clipDepth, frame.projection, frame.nearPlane, frame.farPlane}, linear);
}

core::GlEnum nearerDepthFunc(DepthConvention convention) {
  return convention == DepthConvention::kReversedZ ? GL_GREATER : GL_LESS;
}

float clearDepth(DepthConvention convention) { return convention == DepthConvention::kReversedZ ? 0.0f : 1.0f; }

namespace {

// The convention the cel passes test with: the last FrameBlock uploaded or bound on this thread (a
// GL context is current on one thread).
thread_local DepthConvention boundConvention = DepthConvention::kStandard;
thread_local core::Viewport boundFrameViewport;
thread_local std::uint64_t frameSerial = 0;
thread_local glm::mat4 frameViewProjection{1.0f};
thread_local float frameProjectionScaleY = 1.0f;

}  // namespace

DepthConvention boundDepthConvention() { return boundConvention; }

std::string_view toString(FrameOutput output) {
  switch (output) {
    case FrameOutput::kColour:
      return "colour";
    case FrameOutput::kNormal:
      return "normal";
    case FrameOutput::kDepth:
      return "depth";
    case FrameOutput::kInk:
      return "ink";
    case FrameOutput::kMotion:
      return "motion";
  }
  return "?";
}
core::Viewport boundViewport() { return boundFrameViewport; }
std::uint64_t boundFrameSerial() { return frameSerial; }
glm::mat4 boundViewProjection() { return frameViewProjection; }
float boundProjectionScaleY() { return frameProjectionScaleY; }

namespace {

using shader::FrameBlockData;

int outputCode(FrameOutput output) {
  switch (output) {
    case FrameOutput::kColour:
      return shader::kOutputColour;
    case FrameOutput::kNormal:
      return shader::kOutputNormal;
    case FrameOutput::kDepth:
      return shader::kOutputDepth;
    case FrameOutput::kInk:
      return shader::kOutputInk;
    case FrameOutput::kMotion:
      return shader::kOutputMotion;
  }
  return shader::kOutputColour;
}

}  // namespace

FrameBlock::FrameBlock(const Bindings& bindings)
    : buffer_(core::makeBuffer("cel frame block")), binding_(bindings.frameBlock) {
  glNamedBufferStorage(buffer_.get(), sizeof(FrameBlockData), nullptr, GL_DYNAMIC_STORAGE_BIT);
}

Result<void> FrameBlock::upload(const Frame& frame) {
  // Linear depth divides by far - near: both finite, far beyond near (an infinite far plane lives in
  // the projection only).
  if (!(std::isfinite(frame.nearPlane) && std::isfinite(frame.farPlane) && frame.nearPlane < frame.farPlane))
    return Error{"FrameBlock::upload: the frame's planes " + core::numberText(frame.nearPlane) + ", " +
                 core::numberText(frame.farPlane) + ": need near < far, both finite (linear depth's 0 and 1)"};
  const OutputScale& scale = frame.outputScale;
  if (!(std::isfinite(scale.depthOrigin) && std::isfinite(scale.depthRange) && scale.depthRange > 0.0f &&
        std::isfinite(scale.motionRange) && scale.motionRange > 0.0f))
    return Error{"FrameBlock::upload: the maps' depth origin " + core::numberText(scale.depthOrigin) + ", range " +
                 core::numberText(scale.depthRange) + " and motion range " + core::numberText(scale.motionRange) +
                 ": need all finite, the ranges > 0"};
  FrameBlockData d{};
  d.view = frame.view;
  d.proj = frame.projection;
  d.viewProj = frame.projection * frame.view;
  d.invView = glm::inverse(frame.view);
  d.invViewProj = glm::inverse(d.viewProj);
  d.viewport = glm::vec4(frame.viewport.x, frame.viewport.y, frame.viewport.width, frame.viewport.height);
  const bool ortho = frame.projection[3][3] == 1.0f;
  d.depthRange = glm::vec4(frame.nearPlane, frame.farPlane, 1.0f / (frame.farPlane - frame.nearPlane), ortho ? 1 : 0);
  glm::vec3 l = frame.light.direction;
  l = glm::length(l) > 0.0f ? glm::normalize(l) : glm::vec3(0, 1, 0);
  d.lightDirWorld = glm::vec4(l, 0.0f);
  d.lightDirView = glm::vec4(glm::normalize(glm::vec3(frame.view * glm::vec4(l, 0.0f))), 0.0f);
  // Eq. 2 combines display values: the frame's scene-linear colours encoded.
  d.lightColor = glm::vec4(core::linearToSrgb(frame.light.color), 1.0f);
  d.ambientColor = glm::vec4(core::linearToSrgb(frame.ambient), 1.0f);
  d.cameraWorld = d.invView[3];
  d.ambientMode = glm::ivec4(frame.ambientGradient ? 1 : 0, 0, 0, 0);
  d.shadowMatrix = frame.shadow.worldToMap;
  d.shadowParams = glm::vec4(frame.shadow.enabled ? 1.0f : 0.0f, frame.shadow.tolerance, frame.shadow.length, 0.0f);
  // The projection's z and w rows at a view point (0, 0, -dist, 1): clip z = y - x dist, w = w - z dist.
  d.depthProjection =
      glm::vec4(frame.projection[2][2], frame.projection[3][2], frame.projection[2][3], frame.projection[3][3]);
  d.depthMode = glm::ivec4(static_cast<int>(frame.depth), frame.clipDepth == ClipDepth::kZeroToOne ? 1 : 0, 0, 0);
  d.output = glm::ivec4(outputCode(frame.output), 0, 0, 0);
  d.outputScale = glm::vec4(scale.depthOrigin, 0.5f / scale.depthRange, 0.5f / scale.motionRange, 0.0f);
  glNamedBufferSubData(buffer_.get(), 0, sizeof d, &d);
  depth_ = frame.depth;
  viewport_ = frame.viewport;
  viewProjection_ = d.viewProj;
  projectionScaleY_ = frame.projection[1][1];
  bind();
  return {};
}

void FrameBlock::bind() const {
  // The multi-bind call leaves the generic GL_UNIFORM_BUFFER binding alone (glBindBufferBase would not).
  const GLuint b = buffer_.get();
  glBindBuffersBase(GL_UNIFORM_BUFFER, binding_, 1, &b);
  boundConvention = depth_;
  boundFrameViewport = viewport_;
  frameViewProjection = viewProjection_;
  frameProjectionScaleY = projectionScaleY_;
  ++frameSerial;
}

namespace {

// Values of one row as RGB floats (grey for 1-2 channel images).
std::vector<float> rowRgb(const core::Image& image, int y) {
  std::vector<float> out(static_cast<std::size_t>(image.width) * 3);
  for (int x = 0; x < image.width; ++x) {
    for (int c = 0; c < 3; ++c) {
      const int src = image.channels >= 3 ? c : 0;
      out[static_cast<std::size_t>(x) * 3 + c] = image.at(x, y, src);
    }
  }
  return out;
}

// The image at `path` within `limits`, then through `check` (a use's own rules), errors naming the file.
Result<core::Image> readChecked(const std::filesystem::path& path, const core::ImageLimits& limits,
                                Result<void> (*check)(const core::Image&, const std::string&)) {
  PUFF_TRY_ASSIGN(auto image, core::readImage(path, nullptr, limits));
  PUFF_TRY(check(image, path.string()));
  return image;
}

}  // namespace

Result<void> Ramp::check(const core::Image& image, const std::string& what) {
  if (image.width < 2 || image.width > kRampLimits.maxWidth || image.height < 1 || image.channels < 1) {
    return Error::at(what, "a ramp must be 2 to " + std::to_string(kRampLimits.maxWidth) + " pixels wide (got " +
                               std::to_string(image.width) + "x" + std::to_string(image.height) + ")");
  }
  for (float v : rowRgb(image, image.height / 2)) {
    if (!std::isfinite(v)) return Error::at(what, "ramp holds a non-finite value");
  }
  return {};
}

Result<core::Image> Ramp::read(const std::filesystem::path& path) { return readChecked(path, kRampLimits, check); }

Result<Ramp> Ramp::create(const core::Image& image, const std::string& what, RampFilter filter) {
  PUFF_TRY(check(image, what));
  const std::vector<float> row = rowRgb(image, image.height / 2);
  Ramp r;
  r.width_ = image.width;
  r.texture_ = core::makeTexture(GL_TEXTURE_1D, "ramp");
  const GLuint t = r.texture_.get();
  glTextureStorage1D(t, 1, GL_RGBA16F, image.width);
  std::vector<float> rgba(static_cast<std::size_t>(image.width) * 4, 1.0f);
  for (int x = 0; x < image.width; ++x) {
    // The image holds display values; the texture holds them decoded, so a smooth ramp
    // interpolates light (frame.glsl's quantize encodes after the lookup).
    for (int c = 0; c < 3; ++c) {
      rgba[static_cast<std::size_t>(x) * 4 + c] =
          static_cast<float>(core::srgbToLinear(double{row[static_cast<std::size_t>(x) * 3 + c]}));
    }
  }
  glTextureSubImage1D(t, 0, 0, image.width, GL_RGBA, GL_FLOAT, rgba.data());
  // Clamp-to-edge is what makes q(N.L) equal q(max(0, N.L)) (§4.1).
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  const GLint glFilter = filter == RampFilter::kLinear ? GL_LINEAR : GL_NEAREST;
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, glFilter);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, glFilter);
  return r;
}

Result<Ramp> Ramp::load(const std::filesystem::path& path, RampFilter filter) {
  PUFF_TRY_ASSIGN(auto image, read(path));
  return create(image, path.string(), filter);
}

Ramp Ramp::twoTone() {
  core::Image image(2, 1, 1);
  image.at(0, 0) = 0.0f;
  image.at(1, 0) = 1.0f;
  auto r = create(image, "built-in two-tone ramp");
  PUFF_CHECK(r.ok());
  return std::move(*r);
}

void Ramp::bind(const Bindings& bindings) const { core::bindTextureAndNoSampler(bindings.ramp, texture_.get()); }

Result<void> Gradient::check(const core::Image& image, const std::string& what) {
  if (image.width < 1 || image.height < 1 || image.width > kGradientLimits.maxWidth ||
      image.height > kGradientLimits.maxHeight || image.channels < 1) {
    return Error::at(what, "a gradient must be 1 to " + std::to_string(kGradientLimits.maxWidth) +
                               " pixels on each side (got " + std::to_string(image.width) + "x" +
                               std::to_string(image.height) + ")");
  }
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(image.at(x, y, image.channels >= 3 ? c : 0)))
          return Error::at(what, "gradient holds a non-finite value");
      }
    }
  }
  return {};
}

Result<core::Image> Gradient::read(const std::filesystem::path& path) {
  return readChecked(path, kGradientLimits, check);
}

Result<Gradient> Gradient::create(const core::Image& image, const std::string& what) {
  PUFF_TRY(check(image, what));
  std::vector<float> rgba(static_cast<std::size_t>(image.width) * image.height * 4, 1.0f);
  // GL rows go bottom-up: store image row 0 (the top) last, so texture t = 1 is the top.
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float v = image.at(x, y, image.channels >= 3 ? c : 0);
        // Display value in, scene-linear texel: bilinear filtering mixes light (ambientAt encodes).
        rgba[(static_cast<std::size_t>(image.height - 1 - y) * image.width + x) * 4 + c] =
            static_cast<float>(core::srgbToLinear(double{v}));
      }
    }
  }
  Gradient g;
  g.texture_ = core::makeTexture(GL_TEXTURE_2D, "ambient gradient");
  const GLuint t = g.texture_.get();
  glTextureStorage2D(t, 1, GL_RGBA16F, image.width, image.height);
  glTextureSubImage2D(t, 0, 0, 0, image.width, image.height, GL_RGBA, GL_FLOAT, rgba.data());
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  return g;
}

Result<Gradient> Gradient::load(const std::filesystem::path& path) {
  PUFF_TRY_ASSIGN(auto image, read(path));
  return create(image, path.string());
}

void Gradient::bind(const Bindings& bindings) const {
  core::bindTextureAndNoSampler(bindings.gradient, texture_.get());
}

}  // namespace puff::cel
