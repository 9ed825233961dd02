// The viewer's keys and mouse: the shortcuts, the fly keys, and dragging and wheeling the camera.
#include <puff/gl_api.h>  // before GLFW, which would otherwise include the system <GL/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <imgui.h>

#include <algorithm>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <puff/scene/evaluate.h>
#include <puffview/camera.h>
#include <puffview/viewer.h>

#include "viewer_impl.h"

namespace puff::view {

Viewer* Viewer::Impl::of(GLFWwindow* w) { return static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

void Viewer::Impl::onKey(GLFWwindow* w, int key, int /*scancode*/, int action, int mods) {
  if (action == GLFW_PRESS || action == GLFW_REPEAT) {
    if (Viewer* v = of(w)) v->impl_->keys.emplace_back(key, mods);
  }
}

void Viewer::Impl::onScroll(GLFWwindow* w, double /*x*/, double y) {
  if (Viewer* v = of(w)) v->impl_->scroll += y;
}

// The camera is the user's from the first touch on: it leaves the scene's.
void Viewer::Impl::touchCamera(Viewer& v) {
  if (!v.cameraOverride_) {
    v.camera_.reset(scene::cameraAt(v.scene_, v.frame_));
    v.cameraOverride_ = true;
  }
}

void Viewer::Impl::pressKey(Viewer& v, int key, int mods) {
  if (mods & GLFW_MOD_CONTROL) {  // Ctrl+Z undo; Ctrl+Y or Ctrl+Shift+Z redo; Ctrl+S save; Ctrl+Q quit
    if (key == GLFW_KEY_S) {
      (void)v.save();  // a failure is the status line
    } else if (key == GLFW_KEY_Q) {
      v.requestQuit();
    } else if (key == GLFW_KEY_Z && !(mods & GLFW_MOD_SHIFT)) {
      if (!v.undo()) v.setStatus("nothing to undo");
    } else if (key == GLFW_KEY_Y || key == GLFW_KEY_Z) {
      if (!v.redo()) v.setStatus("nothing to redo");
    }
    return;
  }
  switch (key) {
    case GLFW_KEY_SPACE:
      v.setPlaying(!v.playing_);
      break;
    case GLFW_KEY_PERIOD:
    case GLFW_KEY_RIGHT:
      v.step();
      break;
    case GLFW_KEY_COMMA:
    case GLFW_KEY_LEFT:
      v.playing_ = false;
      v.setFrame(v.frame_ - 1);
      break;
    case GLFW_KEY_R:
    case GLFW_KEY_HOME:
      v.restart();
      break;
    case GLFW_KEY_F12:
    case GLFW_KEY_P:
      v.impl_->screenshotRequested = true;
      break;
    case GLFW_KEY_F:
      touchCamera(v);
      v.camera_.setMode(v.camera_.mode() == CameraController::Mode::kOrbit ? CameraController::Mode::kFly
                                                                           : CameraController::Mode::kOrbit);
      break;
    case GLFW_KEY_C:
      v.resetCamera();
      break;
    case GLFW_KEY_H:
      v.uiVisible = !v.uiVisible;
      break;
    case GLFW_KEY_ESCAPE:
      v.requestQuit();
      break;
    default:
      break;
  }
}

// Fly mode: W/S, A/D and Q/E move the camera (Shift: faster).
void Viewer::Impl::fly(Viewer& v, float dt) {
  GLFWwindow* window = v.impl_->window;
  glm::vec3 move(0.0f);
  auto down = [&](int k) { return glfwGetKey(window, k) == GLFW_PRESS ? 1.0f : 0.0f; };
  move.z = down(GLFW_KEY_W) - down(GLFW_KEY_S);
  move.x = down(GLFW_KEY_D) - down(GLFW_KEY_A);
  move.y = down(GLFW_KEY_E) - down(GLFW_KEY_Q);
  if (move != glm::vec3(0.0f)) {
    touchCamera(v);
    const float fast = down(GLFW_KEY_LEFT_SHIFT) > 0.0f ? 4.0f : 1.0f;
    v.camera_.fly(move * fast, dt);
  }
}

// The mouse: the cursor's move rotates or pans the camera, the wheel zooms (unless the UI has it).
void Viewer::Impl::drag(Viewer& v, bool uiMouse) {
  Impl& m = *v.impl_;
  CameraController& camera = v.camera_;
  double x = 0.0, y = 0.0;
  glfwGetCursorPos(m.window, &x, &y);
  const glm::vec2 delta = m.haveCursor ? glm::vec2(x - m.cursorX, y - m.cursorY) : glm::vec2(0.0f);
  m.cursorX = x, m.cursorY = y, m.haveCursor = true;
  const double scroll = m.scroll;
  m.scroll = 0.0;
  if (uiMouse) return;
  const bool left = glfwGetMouseButton(m.window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  const bool right = glfwGetMouseButton(m.window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  const bool middle = glfwGetMouseButton(m.window, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
  const bool moved = delta != glm::vec2(0.0f);
  if (camera.mode() == CameraController::Mode::kOrbit) {
    if (left && moved) touchCamera(v), camera.rotate(delta);
    if ((right || middle) && moved) touchCamera(v), camera.pan(delta, v.imageViewport().height);
  } else {
    if ((right || left) && moved) touchCamera(v), camera.rotate(delta);
    if (middle && moved) touchCamera(v), camera.pan(delta, v.imageViewport().height);
  }
  if (scroll != 0.0) touchCamera(v), camera.zoom(static_cast<float>(scroll));
}

bool Viewer::processEvents() {
  releaseTyped();
  impl_->context->pollEvents();
  handleInput();
  keepWork();
  return glfwWindowShouldClose(impl_->window) == GLFW_TRUE;
}

void Viewer::handleInput() {
  Impl& m = *impl_;
  ImGui::SetCurrentContext(m.imgui);
  const ImGuiIO& io = ImGui::GetIO();
  const bool uiMouse = m.uiDrawnLastFrame && io.WantCaptureMouse;
  const bool uiKeys = (m.uiDrawnLastFrame && (io.WantCaptureKeyboard || m.uiHoldsKeys)) || quitPrompt_ || diskPrompt_ ||
                      (autosaveOffer_ && !batch_);
  const double t = Impl::now();
  const float dt = static_cast<float>(std::min(0.1, t - m.lastInput));
  m.lastInput = t;

  std::vector<std::pair<int, int>> keys;
  keys.swap(m.keys);
  if (!uiKeys) {
    for (const auto& [key, mods] : keys) Impl::pressKey(*this, key, mods);
    if (camera_.mode() == CameraController::Mode::kFly) Impl::fly(*this, dt);
  }
  Impl::drag(*this, uiMouse);
}

}  // namespace puff::view
