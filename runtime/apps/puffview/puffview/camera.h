// The viewer's own camera: orbit (yaw/pitch about a target, distance, pan) or fly (position plus
// yaw/pitch, moved with WASD/QE). Lens settings (field of view, orthographic height, near and far
// planes) always come from the scene's camera, so the view matches what puffrender draws.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <puff/cel/frame.h>

namespace puff::view {

class CameraController {
 public:
  enum class Mode { kOrbit, kFly };

  /// Starts from `camera` (the scene's camera at the current frame).
  void reset(const cel::Camera& camera);

  /// Orbit: turns about the target by `delta` pixels of mouse motion (x: yaw, y: pitch).
  /// Fly: looks around by the same amount.
  void rotate(glm::vec2 delta);
  /// Moves the target (orbit) or the eye (fly) in the view plane by `delta` pixels of a window
  /// `viewportHeight` pixels high, so the point under the cursor follows it at the target's depth.
  void pan(glm::vec2 delta, int viewportHeight);
  /// Orbit: scales the distance to the target by 0.9^steps. Fly: moves forward by steps.
  void zoom(float steps);
  /// Fly: moves by `local` (x right, y up, z forward) * speed * seconds. Ignored in orbit mode.
  void fly(glm::vec3 local, float seconds);

  void setMode(Mode mode);
  Mode mode() const { return mode_; }

  /// The camera to draw with: position/target/up from the controller, lens from the scene.
  cel::Camera camera(const cel::Camera& lens) const;
  glm::vec3 position() const;
  glm::vec3 target() const { return target_; }
  float distance() const { return distance_; }

 private:
  glm::vec3 forward() const;  ///< unit view direction from yaw/pitch
  glm::vec3 up_{0.0f, 1.0f, 0.0f};
  glm::vec3 target_{0.0f};
  float yaw_ = 0.0f, pitch_ = 0.0f;  ///< radians; yaw about up, pitch above the horizon
  float distance_ = 5.0f;
  glm::vec3 eye_{0.0f, 0.0f, 5.0f};  ///< fly mode
  Mode mode_ = Mode::kOrbit;
};

}  // namespace puff::view
