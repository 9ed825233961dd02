#include <puffview/camera.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace puff::view {

namespace {
constexpr float kRadiansPerPixel = 0.005f;
constexpr float kMaxPitch = 1.55f;  // just short of straight up or down, where yaw degenerates
}  // namespace

void CameraController::reset(const cel::Camera& camera) {
  up_ = glm::length(camera.up) > 0.0f ? glm::normalize(camera.up) : glm::vec3(0.0f, 1.0f, 0.0f);
  target_ = camera.target;
  glm::vec3 toTarget = camera.target - camera.position;
  distance_ = std::max(glm::length(toTarget), 1e-3f);
  const glm::vec3 d = toTarget / distance_;
  // Yaw and pitch in a frame where up_ is "y": pick any x perpendicular to up.
  const glm::vec3 ref = std::abs(up_.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
  const glm::vec3 x = glm::normalize(glm::cross(up_, glm::cross(ref, up_)));
  const glm::vec3 z = glm::cross(x, up_);
  pitch_ = std::asin(std::clamp(glm::dot(d, up_), -1.0f, 1.0f));
  yaw_ = std::atan2(glm::dot(d, x), glm::dot(d, z));
  pitch_ = std::clamp(pitch_, -kMaxPitch, kMaxPitch);
  eye_ = camera.position;
}

glm::vec3 CameraController::forward() const {
  const glm::vec3 ref = std::abs(up_.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
  const glm::vec3 x = glm::normalize(glm::cross(up_, glm::cross(ref, up_)));
  const glm::vec3 z = glm::cross(x, up_);
  const float c = std::cos(pitch_);
  return glm::normalize(c * std::sin(yaw_) * x + c * std::cos(yaw_) * z + std::sin(pitch_) * up_);
}

glm::vec3 CameraController::position() const { return mode_ == Mode::kOrbit ? target_ - forward() * distance_ : eye_; }

void CameraController::rotate(glm::vec2 delta) {
  if (mode_ == Mode::kOrbit) {
    // Dragging right moves the camera right around the target, so the scene turns left.
    yaw_ += delta.x * kRadiansPerPixel;
    pitch_ = std::clamp(pitch_ + delta.y * kRadiansPerPixel, -kMaxPitch, kMaxPitch);
  } else {
    yaw_ -= delta.x * kRadiansPerPixel;
    pitch_ = std::clamp(pitch_ - delta.y * kRadiansPerPixel, -kMaxPitch, kMaxPitch);
  }
}

void CameraController::pan(glm::vec2 delta, int viewportHeight) {
  const glm::vec3 f = forward();
  const glm::vec3 right = glm::normalize(glm::cross(f, up_));
  const glm::vec3 up = glm::cross(right, f);
  // World units per pixel at the target's depth for a 45-degree lens; close enough for panning.
  const float perPixel =
      2.0f * distance_ * std::tan(glm::radians(22.5f)) / static_cast<float>(std::max(1, viewportHeight));
  const glm::vec3 move = (-delta.x * right + delta.y * up) * perPixel;
  target_ += move;
  eye_ += move;
}

void CameraController::zoom(float steps) {
  if (mode_ == Mode::kOrbit) {
    distance_ = std::clamp(distance_ * std::pow(0.9f, steps), 1e-3f, 1e6f);
  } else {
    eye_ += forward() * steps * 0.1f * distance_;
  }
}

void CameraController::fly(glm::vec3 local, float seconds) {
  if (mode_ != Mode::kFly) return;
  const glm::vec3 f = forward();
  const glm::vec3 right = glm::normalize(glm::cross(f, up_));
  // Speed scales with how far the scene was when flying started: a cloud 10 units away is
  // crossed in a few seconds, a 1000-unit explosion too.
  const float speed = std::max(distance_, 0.1f) * 0.5f;
  eye_ += (local.x * right + local.y * up_ + local.z * f) * speed * seconds;
}

void CameraController::setMode(Mode mode) {
  if (mode == mode_) return;
  if (mode == Mode::kFly) {
    eye_ = target_ - forward() * distance_;
  } else {
    target_ = eye_ + forward() * distance_;
  }
  mode_ = mode;
}

cel::Camera CameraController::camera(const cel::Camera& lens) const {
  cel::Camera c = lens;
  c.position = position();
  c.target = c.position + forward() * distance_;
  c.up = up_;
  return c;
}

}  // namespace puff::view
