// Private to puffview_lib: the viewer's window, GL target and input state (Viewer::Impl), which the
// viewer's source files share: viewer.cpp (open, close, undo, timeline, camera, the loops),
// viewer_input.cpp (keys and mouse), viewer_draw.cpp (the frame and the panels into the window),
// viewer_reload.cpp (hot reload) and viewer_files.cpp (scratch images, save, screenshots).
#pragma once

#include <puff/gl_api.h>  // before GLFW, which would otherwise include the system <GL/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <imgui.h>

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

#include <puff/core/error.h>
#include <puff/core/gl.h>
#include <puff/platform/gl_context.h>
#include <puff/render/view.h>
#include <puffview/panels.h>
#include <puffview/viewer.h>

namespace puff::view {

struct Viewer::Impl {
  std::unique_ptr<core::GlContext> context;
  GLFWwindow* window = nullptr;
  ImGuiContext* imgui = nullptr;
  bool imguiBackends = false;
  bool uiDrawnLastFrame = false;
  // The last frame's UI had the keyboard: a text field, an item held, or a popup open (a colour
  // picker, a prompt), so keys go to it and not to the viewer's shortcuts.
  bool uiHoldsKeys = false;
  PanelState panels;

  // The scene is drawn into this target and resolved into the window: the cel path with the scene's
  // samples (like puffrender), so edges look the same as in puffrender's images; the fixed path
  // with one sample (it copies part of the framebuffer into a texture). Colour: scene-linear RGBA16F,
  // or RGBA8 display values for the fixed path.
  core::Framebuffer fbo;
  core::Renderbuffer color, depthStencil;
  int fboWidth = 0, fboHeight = 0, fboSamples = 0;
  bool fboDisplayValues = false;  // the fixed path writes display values into an 8-bit target
  // The scene-linear frame resolved to one sample, which the view transform reads (programmable paths).
  core::Framebuffer resolveFbo;
  core::Texture resolved;
  std::optional<render::ViewPass> viewPass;

  std::vector<std::pair<int, int>> keys;  // key presses (and repeats) since the last processEvents, with modifiers
  // Keys Viewer::typeKey pressed: since the last processEvents, and down through the frame it began
  // (released at the next one).
  std::vector<std::pair<int, int>> typed, typedSeen;
  double scroll = 0.0;
  double cursorX = 0.0, cursorY = 0.0;
  bool haveCursor = false;
  double lastInput = 0.0, lastPresent = 0.0, lastPoll = 0.0;
  bool screenshotRequested = false;
  std::string sceneError, resourceError;  // what fileError() joins

  /// Seconds on GLFW's clock: what frame times, input steps and file polls are measured with.
  static double now() { return glfwGetTime(); }

  // Keys and mouse (viewer_input.cpp).
  static Viewer* of(GLFWwindow* w);
  static void onKey(GLFWwindow* w, int key, int scancode, int action, int mods);
  static void onScroll(GLFWwindow* w, double x, double y);
  static void onClose(GLFWwindow* w);  // the window's close button: Viewer::requestQuit (viewer_keep.cpp)
  static void touchCamera(Viewer& v);
  static void pressKey(Viewer& v, int key, int mods);
  static void fly(Viewer& v, float dt);
  static void drag(Viewer& v, bool uiMouse);

  // Dear ImGui on the window (viewer.cpp).
  Result<void> initImgui();

  // The target the scene is drawn into, made anew for `size`, `samples` and the colour format
  // (viewer_draw.cpp).
  void makeTarget(glm::ivec2 size, int samples, bool displayValues);
};

}  // namespace puff::view
