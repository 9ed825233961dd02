// What the media reference tests share: a camera down -z, a plain material, a sphere, and rendering the reference.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/core/image.h>
#include <puff/media/media.h>
#include <puff/reference/media_reference.h>

#include "support/assert_ok.h"

namespace puff::reference_test {

using reference::MediaReferenceInput;

// A camera at the origin looking down -z.
inline media::Frame axisFrame(int w, int h, float nearPlane = 0.5f, float farPlane = 50.0f) {
  media::Frame f;
  f.projection =
      glm::perspective(glm::radians(40.0f), static_cast<float>(w) / static_cast<float>(h), nearPlane, farPlane);
  f.nearPlane = nearPlane;
  f.farPlane = farPlane;
  f.viewport.width = w;
  f.viewport.height = h;
  f.light.direction = glm::vec3(0.0f, 0.6f, 0.8f);
  f.light.color = glm::vec3(0.9f, 0.8f, 0.7f);
  f.ambient = glm::vec3(0.2f, 0.25f, 0.3f);
  return f;
}

inline double linearDepth(const media::Frame& f, double distance) {
  return (distance - f.nearPlane) / (f.farPlane - f.nearPlane);
}

inline media::Material plain(float tau, float albedo = 0.6f) {
  media::Material m;
  m.name = "plain";
  m.albedo = albedo;
  m.density = tau;
  m.color = glm::vec3(1.0f, 0.5f, 0.25f);
  m.g = 0.3f;
  m.detail = 0.0f;
  return m;
}

inline media::Particle sphereAt(glm::vec3 c, float r, std::uint32_t material = 0) {
  media::Particle p;
  p.position = c;
  p.radius = r;
  p.material = material;
  return p;
}

inline core::Image render(const MediaReferenceInput& in, core::Image* layer = nullptr) {
  auto image = reference::renderMediaReference(in, layer);
  EXPECT_OK(image);
  return image.ok() ? std::move(*image) : core::Image();
}

}  // namespace puff::reference_test
