#include <puff/cel/shadow_map.h>
#include <puff/gl_api.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <puff/core/bind_points.h>

namespace puff::cel {

void Bounds::add(const glm::vec3& p) {
  lo = glm::min(lo, p);
  hi = glm::max(hi, p);
}

void Bounds::add(const Bounds& b) {
  if (b.empty()) return;
  add(b.lo);
  add(b.hi);
}

Bounds particleBounds(std::span<const Particle> particles) {
  Bounds b;
  for (const Particle& p : particles) {
    if (!(p.size > 0.0f) || !std::isfinite(p.size)) continue;
    const glm::vec3 r(0.5f * p.size);
    b.add(p.position - r);
    b.add(p.position + r);
  }
  return b;
}

namespace {

// The casters' box in the light's frame: x, y across the light, dist along it.
struct LightBox {
  glm::vec2 xyLo, xyHi;
  float dLo, dHi;
};

// The light's unit direction, or +y when the frame's has no finite length.
glm::vec3 unitLightDirection(const glm::vec3& direction) {
  const float len = glm::length(direction);
  return len > 0.0f && std::isfinite(len) ? direction / len : glm::vec3(0.0f, 1.0f, 0.0f);
}

// The light's view matrix, its eye beyond the casters' bounding sphere (centre, radius) along l.
glm::mat4 lightView(const glm::vec3& l, const glm::vec3& centre, float radius) {
  const glm::vec3 up = std::abs(l.y) < 0.99f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
  // The light's eye on the line through the world's origin along the light: x and y in its frame
  // are then fixed to the world (only its distance moves with the casters), so the texel lattice
  // (chooseShadowMap) does not slide when the casters do.
  const float along = glm::dot(centre, l) + radius + 1.0f;
  return glm::lookAt(along * l, (along - 1.0f) * l, up);
}

// The box [lo, hi] seen from the light (`view`), its depth range widened to reach `reach`.
LightBox lightBox(const glm::mat4& view, const glm::vec3& lo, const glm::vec3& hi, const Bounds& reach) {
  LightBox b{glm::vec2(std::numeric_limits<float>::max()), glm::vec2(std::numeric_limits<float>::lowest()),
             std::numeric_limits<float>::max(), std::numeric_limits<float>::lowest()};
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 corner((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    const glm::vec3 v = glm::vec3(view * glm::vec4(corner, 1.0f));
    b.xyLo = glm::min(b.xyLo, glm::vec2(v));
    b.xyHi = glm::max(b.xyHi, glm::vec2(v));
    b.dLo = std::min(b.dLo, -v.z);
    b.dHi = std::max(b.dHi, -v.z);
  }
  // The depth range reaches every caster, planes included (a plane above the puffs is in front of
  // them all, and must still be drawn: it is not clipped away).
  if (!reach.empty()) {
    for (int i = 0; i < 8; ++i) {
      const glm::vec3 corner((i & 1) ? reach.hi.x : reach.lo.x, (i & 2) ? reach.hi.y : reach.lo.y,
                             (i & 4) ? reach.hi.z : reach.lo.z);
      const float d = -(view * glm::vec4(corner, 1.0f)).z;
      b.dLo = std::min(b.dLo, d);
      b.dHi = std::max(b.dHi, d);
    }
  }
  return b;
}

// The map's texels per world unit: the eye's at `centre`, scaled, quantized, and fitting `box` in maxSize.
float mapTexelsPerUnit(const Frame& eye, const glm::vec3& centre, const Style& style, const LightBox& box,
                       int maxSize) {
  // Texels per world unit: the eye's pixels per world unit at the casters' centre, times the scale.
  const bool ortho = eye.projection[3][3] == 1.0f;
  const float pixelsHigh = static_cast<float>(std::max(1, eye.viewport.height));
  float pxPerUnit = 0.5f * pixelsHigh * std::abs(eye.projection[1][1]);
  if (!ortho) {
    const float dist = -(eye.view * glm::vec4(centre, 1.0f)).z;
    pxPerUnit /= std::max(eye.nearPlane, dist);
  }
  const float scale = std::clamp(style.shadowMapScale, 0.125f, 4.0f);
  // Quantized to quarter octaves, so a camera moving smoothly changes the map's resolution in steps
  // of 19%, not every frame (a changing resolution makes shadow edges swim).
  float t = std::exp2(std::round(std::log2(std::max(1e-6f, scale * pxPerUnit)) * 4.0f) / 4.0f);
  const glm::vec2 extent = glm::max(box.xyHi - box.xyLo, glm::vec2(1e-4f));
  const float largest = std::max(extent.x, extent.y);
  // (One texel spare for the snapping below.)
  if ((largest * t) + 1.0f > static_cast<float>(maxSize)) t = static_cast<float>(maxSize - 1) / largest;
  return t;
}

}  // namespace

ShadowMapPlan chooseShadowMap(const Frame& eye, const Bounds& casters, const Style& style, int maxSize,
                              const Bounds& reach) {
  maxSize = std::max(16, maxSize);
  ShadowMapPlan plan;
  const glm::vec3 l = unitLightDirection(eye.light.direction);
  const bool none = casters.empty();
  const glm::vec3 lo = none ? glm::vec3(-0.5f) : casters.lo, hi = none ? glm::vec3(0.5f) : casters.hi;
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = std::max(1e-3f, 0.5f * glm::length(hi - lo));
  const glm::mat4 view = lightView(l, centre, radius);
  const LightBox box = lightBox(view, lo, hi, reach);
  const float t = mapTexelsPerUnit(eye, centre, style, box, maxSize);
  // The region starts on the world-fixed lattice of texels (whole texels from the light frame's
  // origin), so moving casters move the region by whole texels and the texels under a still
  // shadow stay where they were. Texels are square.
  const glm::vec2 regionLo = glm::floor(box.xyLo * t) / t;
  const int w = std::clamp(static_cast<int>(std::ceil((box.xyHi.x - regionLo.x) * t)), 16, maxSize);
  const int h = std::clamp(static_cast<int>(std::ceil((box.xyHi.y - regionLo.y) * t)), 16, maxSize);
  const glm::vec2 regionHi = regionLo + glm::vec2(w, h) / t;
  // Depth: from just before the nearest caster to well past the farthest one, whose shadow may
  // start up to a diameter and a half behind its centre (depth offset plus bias); receivers farther
  // still compare unclamped in the shader.
  const float nearDist = box.dLo - 0.01f * radius - 1e-3f, farDist = box.dHi + 2.0f * radius + 1e-3f;
  const glm::mat4 proj = glm::ortho(regionLo.x, regionHi.x, regionLo.y, regionHi.y, nearDist, farDist);

  plan.light.view = view;
  plan.light.projection = proj;
  plan.light.nearPlane = nearDist;
  plan.light.farPlane = farDist;
  plan.light.depth = DepthConvention::kLinear;  // the map is Puff's own: linear (ortho: the window depth too)
  plan.light.viewport = {0, 0, w, h};
  plan.light.light = eye.light;
  plan.width = w;
  plan.height = h;
  plan.texelsPerUnit = t;
  plan.lookup.enabled = !none;
  plan.lookup.worldToMap = proj * view;
  const float depthRange = farDist - nearDist;
  plan.lookup.tolerance = (1.0f / t) / depthRange;  // a texel's width, along the light
  plan.lookup.length = std::max(0.0f, style.shadowLength) / depthRange;
  return plan;
}

ShadowMap::ShadowMap(const Bindings& bindings)
    : bindings_(bindings), lightBlock_(bindings), fbo_(core::makeFramebuffer("shadow map")) {}

void ShadowMap::prepare(const Frame& eye, const Bounds& casters, const Style& style, const Bounds& reach) {
  GLint maxTexture = 4096;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
  plan_ = chooseShadowMap(eye, casters, style, std::min(4096, static_cast<int>(maxTexture)), reach);
  if (plan_.width == allocatedW_ && plan_.height == allocatedH_) return;
  allocatedW_ = plan_.width;
  allocatedH_ = plan_.height;
  // Nearest sampling, no comparison: the receivers compare depths and ids themselves.
  depth_ = core::makeTexture(GL_TEXTURE_2D, "shadow map: depth");
  glTextureStorage2D(depth_.get(), 1, GL_DEPTH_COMPONENT32F, allocatedW_, allocatedH_);
  ids_ = core::makeTexture(GL_TEXTURE_2D, "shadow map: caster ids");
  glTextureStorage2D(ids_.get(), 1, GL_R32UI, allocatedW_, allocatedH_);
  for (GLuint t : {depth_.get(), ids_.get()}) {
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  glTextureParameteri(depth_.get(), GL_TEXTURE_COMPARE_MODE, GL_NONE);
  glNamedFramebufferTexture(fbo_.get(), GL_COLOR_ATTACHMENT0, ids_.get(), 0);
  glNamedFramebufferTexture(fbo_.get(), GL_DEPTH_ATTACHMENT, depth_.get(), 0);
  glNamedFramebufferDrawBuffer(fbo_.get(), GL_COLOR_ATTACHMENT0);
}

void ShadowMap::beginCasters() {
  // The map must not be read while it is drawn into: take it off the receivers' units.
  glBindTextureUnit(bindings_.shadowMapDepth, 0);
  glBindTextureUnit(bindings_.shadowMapIds, 0);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_.get());
  glViewport(0, 0, plan_.width, plan_.height);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_RASTERIZER_DISCARD);  // it would discard the clears too
  glDepthMask(GL_TRUE);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  const float far = 1.0f;
  const GLuint none[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(fbo_.get(), GL_DEPTH, 0, &far);
  glClearNamedFramebufferuiv(fbo_.get(), GL_COLOR, 0, none);
  PUFF_CHECK(lightBlock_.upload(plan_.light).ok());  // the light frame's planes are made valid above
}

void ShadowMap::bind() const {
  core::bindTextureAndNoSampler(bindings_.shadowMapDepth, depth_.get());
  core::bindTextureAndNoSampler(bindings_.shadowMapIds, ids_.get());
}

}  // namespace puff::cel
