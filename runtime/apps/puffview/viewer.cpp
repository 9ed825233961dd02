#include <puff/gl_api.h>  // before GLFW, which would otherwise include the system <GL/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include <puff/cel/frame.h>
#include <puff/core/atlas.h>
#include <puff/core/files.h>
#include <puff/core/gl.h>
#include <puff/core/shader.h>
#include <puff/platform/gl_context.h>
#include <puff/render/view.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>
#include <puff/support/text.h>
#include <puffview/panels.h>
#include <puffview/viewer.h>

#include <unistd.h>

namespace puff::view {

Result<std::unique_ptr<render::SceneRenderer>> createRenderer(const std::string& pathName, const scene::Scene& scene) {
  for (const render::RenderPathInfo& p : render::renderPaths()) {
    if (p.name == pathName) return render::SceneRenderer::create(scene, p.path);
  }
  std::string list;
  for (const render::RenderPathInfo& p : render::renderPaths()) list += (list.empty() ? "" : ", ") + p.name;
  return Error{"unknown render path \"" + pathName + "\" (available: " + list + ")"};
}

namespace fs = std::filesystem;

struct Viewer::Impl {
  std::unique_ptr<core::GlContext> context;
  GLFWwindow* window = nullptr;
  ImGuiContext* imgui = nullptr;
  bool imguiBackends = false;
  bool uiDrawnLastFrame = false;
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
  double scroll = 0.0;
  double cursorX = 0.0, cursorY = 0.0;
  bool haveCursor = false;
  double lastInput = 0.0, lastPresent = 0.0, lastPoll = 0.0;
  bool screenshotRequested = false;
  std::string sceneError, resourceError;  // what fileError() joins

  static Viewer* of(GLFWwindow* w) { return static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }
  static void onKey(GLFWwindow* w, int key, int /*scancode*/, int action, int mods) {
    if (action == GLFW_PRESS || action == GLFW_REPEAT) {
      if (Viewer* v = of(w)) v->impl_->keys.emplace_back(key, mods);
    }
  }
  static void onScroll(GLFWwindow* w, double /*x*/, double y) {
    if (Viewer* v = of(w)) v->impl_->scroll += y;
  }

  // The camera is the user's from the first touch on: it leaves the scene's.
  static void touchCamera(Viewer& v) {
    if (!v.cameraOverride_) {
      v.camera_.reset(scene::cameraAt(v.scene_, v.frame_));
      v.cameraOverride_ = true;
    }
  }

  static void pressKey(Viewer& v, int key, int mods) {
    if (mods & GLFW_MOD_CONTROL) {  // Ctrl+Z undo; Ctrl+Y or Ctrl+Shift+Z redo
      if (key == GLFW_KEY_Z && !(mods & GLFW_MOD_SHIFT)) {
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
        glfwSetWindowShouldClose(v.impl_->window, GLFW_TRUE);
        break;
      default:
        break;
    }
  }

  // Fly mode: W/S, A/D and Q/E move the camera (Shift: faster).
  static void fly(Viewer& v, float dt) {
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
  static void drag(Viewer& v, bool uiMouse) {
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

  // ImGui on the window, its GLFW and OpenGL 3 backends.
  Result<void> initImgui() {
    IMGUI_CHECKVERSION();
    imgui = ImGui::CreateContext();
    ImGui::SetCurrentContext(imgui);
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the artist's working directory
    ImGui::StyleColorsDark();
    if (!ImGui_ImplGlfw_InitForOpenGL(window, true)) return Error{"imgui: cannot attach to the GLFW window"};
    if (!ImGui_ImplOpenGL3_Init("#version 450 core")) {
      ImGui_ImplGlfw_Shutdown();
      return Error{"imgui: cannot initialize its OpenGL 3 renderer"};
    }
    imguiBackends = true;
    return {};
  }
};

namespace {

using core::oneLine;

// The window's context; where `mayFallBack` and GL 4.5 compatibility is not to be had, the oldest
// compatibility context, with the reason in `whyNotCel`.
Result<std::unique_ptr<core::GlContext>> createContext(const core::GlContextOptions& gl, bool mayFallBack,
                                                       std::string& whyNotCel) {
  auto context = core::createGlContext(gl);
  if (!context && mayFallBack) {
    core::GlContextOptions old = gl;  // the oldest compatibility context (Mesa may give more)
    old.major = 2, old.minor = 1;
    auto older = core::createGlContext(old);
    if (!older) return context.error();
    if (!PUFF_GLAD_GL_VERSION_4_5) {
      // puff::render::SceneRenderer builds its targets with GL 4.5 calls on either path: an older
      // context would crash it, so this is an error, not a fallback (yet).
      return Error{context.error().message +
                   "; the fixed-function path cannot run in the older context either (the renderer needs GL 4.5 "
                   "framebuffer objects)"};
    }
    whyNotCel = context.error().message;
    context = std::move(older);
  }
  return context;
}

fs::path normalAbsolute(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec);
  return (ec ? p : a).lexically_normal();
}

// Paths inside the art directory are written as "${PUFF_ART}/..." again, so a saved scene keeps
// working with another build's art directory (toJson writes them relative to the scene).
void restoreArtPaths(nlohmann::json& j, const fs::path& sceneDir, const fs::path& artDir) {
  if (artDir.empty()) return;
  const fs::path art = normalAbsolute(artDir);
  if (j.is_structured()) {
    for (auto& item : j) restoreArtPaths(item, sceneDir, artDir);
    return;
  }
  if (!j.is_string()) return;
  const std::string s = j.get<std::string>();
  if (s.empty() || s.starts_with("${")) return;
  const fs::path full = normalAbsolute(fs::path(s).is_absolute() ? fs::path(s) : sceneDir / s);
  const fs::path rel = full.lexically_relative(art);
  std::error_code ec;
  if (rel.empty() || *rel.begin() == ".." || !fs::is_regular_file(full, ec)) return;
  j = "${PUFF_ART}/" + rel.generic_string();
}

double now() { return glfwGetTime(); }

}  // namespace

Viewer::Viewer() : impl_(std::make_unique<Impl>()) {}

Viewer::~Viewer() {
  if (!scratch_.empty()) {
    std::error_code ec;
    fs::remove_all(scratch_, ec);
  }
  if (!impl_ || !impl_->context) return;
  impl_->context->makeCurrent();
  renderer_.reset();
  impl_->fbo = {};
  impl_->color = {};
  impl_->depthStencil = {};
  if (impl_->imgui) {
    ImGui::SetCurrentContext(impl_->imgui);
    if (impl_->imguiBackends) {
      ImGui_ImplOpenGL3_Shutdown();
      ImGui_ImplGlfw_Shutdown();
    }
    ImGui::DestroyContext(impl_->imgui);
  }
  glfwSetWindowUserPointer(impl_->window, nullptr);
  impl_->context.reset();
}

Result<std::unique_ptr<Viewer>> Viewer::open(const ViewerOptions& options) {
  auto loaded = scene::loadScene(options.scene, options.artDir);
  if (!loaded) return loaded.error();
  if (!options.shaderDir.empty()) core::setShaderDir(options.shaderDir);

  std::unique_ptr<Viewer> v(new Viewer());
  v->options_ = options;
  v->scene_ = std::move(*loaded);
  v->uiVisible = options.ui;
  Impl& m = *v->impl_;

  core::GlContextOptions gl;
  gl.backend = "glfw";
  gl.profile = core::GlProfile::kCompatibility;  // GL 4.5 for the cel path, GL 1.x calls for the fixed one
  gl.visible = options.visible;
  const glm::ivec2 image = v->imageSize();
  gl.width = image.x + (options.ui ? kPanelWidth : 0);
  gl.height = options.ui ? std::max(image.y, kPanelMinHeight) : image.y;
  gl.title = "puffview: " + options.scene.string();
  // The automatic fallback: the cel path (the default) needs GL 4.5 and programs that build; where
  // the platform or the shaders cannot give that, the fixed path draws instead, saying so.
  const bool mayFallBack = options.path == "cel";
  std::string whyNotCel;
  auto context = createContext(gl, mayFallBack, whyNotCel);
  if (!context) return context.error();
  m.context = std::move(*context);
  m.window = static_cast<GLFWwindow*>(m.context->nativeWindow());
  glfwSetWindowUserPointer(m.window, v.get());
  // Ours first: ImGui's backend chains to the callbacks installed before it.
  glfwSetKeyCallback(m.window, Impl::onKey);
  glfwSetScrollCallback(m.window, Impl::onScroll);

  PUFF_TRY(m.initImgui());

  if (mayFallBack && whyNotCel.empty()) {
    if (auto ok = render::SceneRenderer::checkProgrammable(); !ok) whyNotCel = ok.error().message;
  }
  std::string pathName = options.path;
  if (!whyNotCel.empty()) {
    const std::string message =
        "the programmable (cel) path cannot run here: " + oneLine(whyNotCel) + "; drawing with the fixed-function path";
    std::fprintf(stderr, "puffview: %s\n", message.c_str());
    v->setStatus(message);
    pathName = "fixed";
  }
  PUFF_TRY_ASSIGN(v->renderer_, createRenderer(pathName, v->shown(v->scene_)));
  v->pathName_ = pathName;
  v->camera_.reset(scene::cameraAt(v->scene_, 0));
  v->committed_ = v->scene_;
  v->watchScene();
  m.lastInput = m.lastPresent = m.lastPoll = now();
  return v;
}

// ---- hot reload -----------------------------------------------------------------------------

void Viewer::watchScene() {
  std::vector<fs::path> files{scene_.file};
  if (!scene_.atlas.empty()) {
    files.push_back(scene_.atlas);
    if (auto desc = core::loadAtlasDesc(scene_.atlas)) {
      for (const auto& [name, map] : desc->maps) {
        for (const std::string& level : map.levels) files.push_back(scene_.atlas.parent_path() / level);
      }
    }
  }
  if (!scene_.ramp.empty()) files.push_back(scene_.ramp);
  if (!scene_.ambientGradient.empty()) files.push_back(scene_.ambientGradient);
  for (const scene::ObjectSpec& o : scene_.objects) {
    if (o.type == scene::ObjectSpec::Type::kMesh && !o.mesh.empty()) files.push_back(o.mesh);
  }
  std::vector<fs::path> dirs;
  if (const fs::path shaders = core::shaderDir(); !shaders.empty()) dirs.push_back(shaders);
  watcher_.watch(std::move(files), std::move(dirs));
}

void Viewer::checkFiles() {
  impl_->lastPoll = now();
  const std::vector<fs::path> changed = watcher_.poll();
  if (changed.empty()) return;
  const bool sceneChanged = std::find(changed.begin(), changed.end(), scene_.file) != changed.end();
  const bool resourcesChanged = changed.size() > (sceneChanged ? 1u : 0u);
  if (!options_.quiet) {
    for (const fs::path& p : changed) std::printf("puffview: changed: %s\n", p.c_str());
    std::fflush(stdout);
  }
  if (sceneChanged) {
    reloadScene();
    if (resourcesChanged && impl_->sceneError.empty()) rebuildPath("changed files");
  } else {
    rebuildPath("changed files");
  }
}

void Viewer::reloadScene() {
  Impl& m = *impl_;
  auto loaded = scene::loadScene(scene_.file, options_.artDir);
  auto fail = [&](const std::string& message) {
    m.sceneError = message;
    fileError_ = m.sceneError + (m.resourceError.empty() ? "" : "\n" + m.resourceError);
    if (!options_.quiet) std::fprintf(stderr, "puffview: error: %s\n", message.c_str());
  };
  if (!loaded) return fail(loaded.error().message);
  loaded->file = scene_.file;
  if (auto r = renderer_->update(shown(*loaded)); !r) return fail(r.error().message);
  // A change on disk is a step undo can take back, like an edit in the panels.
  endEdit();
  beginEdit();
  scene_ = std::move(*loaded);
  endEdit();
  m.sceneError.clear();
  m.resourceError.clear();  // update() reloaded what the scene names, or nothing changed there
  fileError_.clear();
  editError_.clear();
  if (!cameraOverride_) camera_.reset(scene::cameraAt(scene_, frame_));
  const fs::path file = scene_.file;
  watchScene();  // the scene may name other files now
  setStatus("reloaded " + file.string());
}

void Viewer::rebuildPath(const std::string& why) {
  Impl& m = *impl_;
  auto path = createRenderer(pathName_, shown(scene_));
  if (!path) {
    m.resourceError = path.error().message;
    if (!options_.quiet) std::fprintf(stderr, "puffview: error: %s\n", m.resourceError.c_str());
  } else {
    renderer_ = std::move(*path);
    m.resourceError.clear();
    setStatus("rebuilt the " + pathName_ + " path (" + why + ")");
  }
  fileError_ = m.sceneError + (!m.sceneError.empty() && !m.resourceError.empty() ? "\n" : "") + m.resourceError;
  watchScene();  // an atlas sidecar may name other images now
}

// ---- editing ---------------------------------------------------------------------------------

const fs::path& Viewer::scratchDir() {
  if (scratch_.empty()) {
    std::error_code ec;
    const fs::path base = fs::temp_directory_path(ec);
    scratch_ = (ec ? fs::path("/tmp") : base) / ("puffview-" + std::to_string(::getpid()));
    fs::create_directories(scratch_, ec);
  }
  return scratch_;
}

Result<fs::path> Viewer::writeScratch(const char* kind, const core::Image& image) {
  std::string bytes(reinterpret_cast<const char*>(image.pixels.data()), image.pixels.size() * sizeof(float));
  bytes += std::to_string(image.width) + "x" + std::to_string(image.height) + "x" + std::to_string(image.channels);
  const fs::path file = scratchDir() / (std::string(kind) + "." + core::fnv1a64Hex(bytes).substr(0, 12) + ".png");
  std::error_code ec;
  if (fs::exists(file, ec)) return file;  // named by its content: already written
  core::OutputTransaction tx;
  PUFF_TRY(core::writeImage(tx.stage(file), image, core::PixelType::kUInt8, {}, file));
  PUFF_TRY(tx.commit());
  return file;
}

scene::Scene Viewer::shown(const scene::Scene& s) {
  if (!s.transparent) return s;
  // 8-pixel squares of two light greys (display values), one plate pixel per pixel of the image the
  // window shows at its own size (the plate is stretched to the frame drawn).
  // Made once per size: shown() runs on every edit, and the plate is the same file each time.
  const glm::ivec2 size = imageSize();
  if (size == checkerSize_ && !checkerPlate_.empty()) {
    scene::Scene copy = s;
    copy.transparent = false;
    copy.alpha.reset();
    copy.plate = checkerPlate_;
    return copy;
  }
  core::Image checker(size.x, size.y, 3);
  for (int y = 0; y < checker.height; ++y) {
    for (int x = 0; x < checker.width; ++x) {
      const float v = ((x / 8) + (y / 8)) % 2 == 0 ? 0.62f : 0.78f;
      for (int c = 0; c < 3; ++c) checker.at(x, y, c) = v;
    }
  }
  auto plate = writeScratch("checker", checker);
  if (!plate) {
    setStatus("cannot draw the checkerboard under the transparent frame: " + plate.error().message);
    return s;
  }
  checkerSize_ = size;
  checkerPlate_ = *plate;
  return shown(s);
}

Result<void> Viewer::setRamp(const core::Image& ramp) {
  PUFF_TRY(cel::Ramp::check(ramp, "the edited ramp"));
  auto file = writeScratch("ramp", ramp);
  if (!file) return file.error();
  scene_.ramp = *file;
  return applyEdit();
}

Result<void> Viewer::setAmbientGradient(const core::Image& gradient) {
  PUFF_TRY(cel::Gradient::check(gradient, "the edited gradient"));
  auto file = writeScratch("gradient", gradient);
  if (!file) return file.error();
  scene_.ambientGradient = *file;
  return applyEdit();
}

Result<void> Viewer::keepBeside(const fs::path& target, fs::path& image, const char* suffix) {
  if (image.empty() || scratch_.empty() || image.parent_path() != scratch_) return {};
  const fs::path beside = target.parent_path() / (target.stem().string() + suffix);
  core::OutputTransaction tx;
  std::error_code ec;
  fs::copy_file(image, tx.stage(beside), fs::copy_options::overwrite_existing, ec);
  if (ec) return Error::at(beside, "cannot write: " + ec.message());
  PUFF_TRY(tx.commit());
  image = beside;
  return {};
}

void Viewer::beginEdit() {
  if (editing_) return;
  editing_ = true;
  undo_.push_back(committed_);
  if (undo_.size() > kUndoSteps) undo_.erase(undo_.begin());
  redo_.clear();
}

void Viewer::endEdit() {
  if (!editing_) return;
  editing_ = false;
  committed_ = scene_;
}

void Viewer::restore(scene::Scene scene, const char* what) {
  scene.file = scene_.file;  // Save as moved the file on: undo does not move it back
  scene_ = std::move(scene);
  committed_ = scene_;
  if (!cameraOverride_) camera_.reset(scene::cameraAt(scene_, frame_));
  (void)applyEdit();
  setStatus(what);
}

bool Viewer::undo() {
  endEdit();
  if (undo_.empty()) return false;
  redo_.push_back(scene_);
  scene::Scene previous = std::move(undo_.back());
  undo_.pop_back();
  restore(std::move(previous), "undo");
  return true;
}

bool Viewer::redo() {
  endEdit();
  if (redo_.empty()) return false;
  undo_.push_back(scene_);
  scene::Scene next = std::move(redo_.back());
  redo_.pop_back();
  restore(std::move(next), "redo");
  return true;
}

Result<void> Viewer::applyEdit() {
  auto r = renderer_->update(shown(scene_));
  editError_ = r ? "" : r.error().message;
  return r;
}

Result<fs::path> Viewer::save(const fs::path& file) {
  const fs::path target = file.empty() ? scene_.file : file;
  // Never write what would not load, and never overwrite newer text edits that failed to load.
  if (!editError_.empty()) {
    return Error::at(target, "not saved: the panel holds a value the scene rejects (" + editError_ + ")");
  }
  if (!fileError_.empty() && target == scene_.file) {
    return Error::at(target,
                     "not saved: the file on disk has edits that do not load (fix them there, or Save as another "
                     "file); saving would overwrite them");
  }
  // A ramp or gradient edited in the panel goes beside the scene file, and the scene names it there.
  scene::Scene beside = scene_;
  PUFF_TRY(keepBeside(target, beside.ramp, "_ramp.png"));
  PUFF_TRY(keepBeside(target, beside.ambientGradient, "_gradient.png"));
  if (beside.ramp != scene_.ramp || beside.ambientGradient != scene_.ambientGradient) {
    scene_.ramp = beside.ramp;
    scene_.ambientGradient = beside.ambientGradient;
    committed_.ramp = scene_.ramp;
    committed_.ambientGradient = scene_.ambientGradient;
    (void)applyEdit();
  }
  scene::Scene copy = scene_;
  copy.file = target;  // toJson writes paths relative to where the file will be
  nlohmann::json j = scene::toJson(copy);
  if (auto check = scene::parseScene(j, target, options_.artDir); !check) {
    return Error::at(target, "not saved: " + check.error().message);
  }
  restoreArtPaths(j, target.parent_path(), options_.artDir);
  if (auto r = core::writeFileAtomic(target, scene::jsonText(j) + "\n"); !r) return r.error();
  if (target == scene_.file) {
    watcher_.markSeen(target);  // our own write is not an outside change to reload
  } else {
    scene_.file = target;
    watchScene();
  }
  setStatus("saved " + target.string());
  if (!options_.quiet) std::printf("puffview: saved %s\n", target.c_str());
  return target;
}

void Viewer::setStatus(std::string text) { status_ = std::move(text); }

// ---- timeline --------------------------------------------------------------------------------

void Viewer::setFrame(int frame) {
  frame_ = std::max(0, frame);
  playClock_ = 0.0;
}
void Viewer::setPlaying(bool playing) {
  playing_ = playing;
  playClock_ = 0.0;
}
void Viewer::step() {
  playing_ = false;
  setFrame(frame_ + 1);
}
void Viewer::restart() { setFrame(0); }

void Viewer::advance(double seconds) {
  if (!playing_) return;
  playClock_ += seconds;
  const double frameSeconds = 1.0 / std::max(1e-3f, scene_.animation.fps);
  // A slow frame (a 50,000-particle scene on llvmpipe) skips frames to keep time, as a player
  // does; the simulation steps through them anyway.
  const int ahead = static_cast<int>(playClock_ / frameSeconds);
  if (ahead <= 0) return;
  playClock_ -= ahead * frameSeconds;
  int next = frame_ + ahead;
  const int frames = std::max(1, scene_.animation.frames);
  if (next >= frames) {
    if (loop) {
      next %= frames;
    } else {
      next = frames - 1;
      playing_ = false;
    }
  }
  frame_ = next;
}

// ---- camera and path -------------------------------------------------------------------------

void Viewer::resetCamera() {
  cameraOverride_ = false;
  camera_.reset(scene::cameraAt(scene_, frame_));
}

void Viewer::cameraToScene() {
  const cel::Camera c = camera_.camera(scene_.camera);
  endEdit();
  beginEdit();
  scene_.camera = c;
  scene_.animation.orbitDegreesPerSecond = 0.0f;  // the saved view is the view seen
  cameraOverride_ = false;
  endEdit();
  (void)applyEdit();
}

Result<void> Viewer::setPath(const std::string& name) {
  impl_->context->makeCurrent();
  auto path = createRenderer(name, shown(scene_));
  if (!path) {
    setStatus("cannot switch to the " + name + " path: " + path.error().message);
    return path.error();
  }
  renderer_ = std::move(*path);
  pathName_ = name;
  setStatus("drawing with the " + name + " path");
  return {};
}

glm::ivec2 Viewer::imageSize() const {
  return {options_.width > 0 ? options_.width : std::clamp(scene_.width, 64, 1920),
          options_.height > 0 ? options_.height : std::clamp(scene_.height, 64, 1200)};
}

cel::Viewport Viewer::imageViewport() const {
  const glm::ivec2 fb = framebufferSize();
  int windowWidth = 0, windowHeight = 0;
  glfwGetWindowSize(impl_->window, &windowWidth, &windowHeight);
  const double pixelsPerPoint = windowWidth > 0 ? static_cast<double>(fb.x) / windowWidth : 1.0;
  const int panel = uiVisible ? static_cast<int>(std::lround(kPanelWidth * pixelsPerPoint)) : 0;
  const int areaW = std::max(1, fb.x - panel), areaH = std::max(1, fb.y);
  const glm::ivec2 image = imageSize();
  const double scale = std::min(static_cast<double>(areaW) / image.x, static_cast<double>(areaH) / image.y);
  const int w = std::clamp(static_cast<int>(std::lround(image.x * scale)), 1, areaW);
  const int h = std::clamp(static_cast<int>(std::lround(image.y * scale)), 1, areaH);
  return cel::Viewport{(areaW - w) / 2, (areaH - h) / 2, w, h};
}

glm::ivec2 Viewer::framebufferSize() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(impl_->window, &w, &h);
  return {w, h};
}

// ---- input -----------------------------------------------------------------------------------

bool Viewer::processEvents() {
  impl_->context->pollEvents();
  handleInput();
  return glfwWindowShouldClose(impl_->window) == GLFW_TRUE;
}

void Viewer::handleInput() {
  Impl& m = *impl_;
  ImGui::SetCurrentContext(m.imgui);
  const ImGuiIO& io = ImGui::GetIO();
  const bool uiMouse = m.uiDrawnLastFrame && io.WantCaptureMouse;
  const bool uiKeys = m.uiDrawnLastFrame && io.WantCaptureKeyboard;
  const double t = now();
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

// ---- drawing ---------------------------------------------------------------------------------

void Viewer::drawFrame() {
  Impl& m = *impl_;
  m.context->makeCurrent();
  const glm::ivec2 window = framebufferSize();
  if (window.x <= 0 || window.y <= 0) return;  // minimized
  const cel::Viewport area = imageViewport();
  const glm::ivec2 size(area.width, area.height);

  GLint maxSamples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  const int samples = std::clamp(renderer_->targetNeeds().samples, 1, std::max(1, maxSamples));
  const bool displayValues = renderer_->targetNeeds().displayValues;
  if (!m.fbo || m.fboWidth != size.x || m.fboHeight != size.y || m.fboSamples != samples ||
      m.fboDisplayValues != displayValues) {
    m.fbo = core::makeFramebuffer();
    m.color = core::makeRenderbuffer();
    m.depthStencil = core::makeRenderbuffer();
    const int s = samples > 1 ? samples : 0;
    // Scene-linear half floats (docs/colour.md), or the fixed path's 8-bit display values.
    const GLenum format = displayValues ? GL_RGBA8 : GL_RGBA16F;
    glNamedRenderbufferStorageMultisample(m.color.get(), s, format, size.x, size.y);
    glNamedRenderbufferStorageMultisample(m.depthStencil.get(), s, GL_DEPTH24_STENCIL8, size.x, size.y);
    glNamedFramebufferRenderbuffer(m.fbo.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m.color.get());
    glNamedFramebufferRenderbuffer(m.fbo.get(), GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, m.depthStencil.get());
    m.fboWidth = size.x, m.fboHeight = size.y, m.fboSamples = samples, m.fboDisplayValues = displayValues;
    m.resolveFbo = core::makeFramebuffer();
    m.resolved = core::makeTexture(GL_TEXTURE_2D);
    glTextureStorage2D(m.resolved.get(), 1, GL_RGBA16F, size.x, size.y);
    glNamedFramebufferTexture(m.resolveFbo.get(), GL_COLOR_ATTACHMENT0, m.resolved.get(), 0);
  }

  glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.get());
  cel::Camera camera;
  if (cameraOverride_) camera = camera_.camera(scene::cameraAt(scene_, frame_));
  render::FrameStats stats;
  auto drawn =
      renderer_->drawFrame(frame_, cel::Viewport{0, 0, size.x, size.y}, &stats, cameraOverride_ ? &camera : nullptr);
  const std::string drawError = drawn ? "" : drawn.error().message;
  if (drawError != drawError_ && !drawError.empty()) setStatus("cannot draw: " + drawError);
  drawError_ = drawError;
  stats_ = stats;

  // Into the window's back buffer: display values as they are, a scene-linear frame resolved and
  // through the scene's view transform.
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  if (!m.viewPass && !displayValues) {
    auto pass = render::ViewPass::create();
    if (!pass) {
      setStatus("cannot show the frame: " + pass.error().message);
      return;
    }
    m.viewPass = std::move(*pass);
  }
  // What the image does not cover (beside the panel, or bars where the window's shape is not the
  // image's) is a plain dark grey.
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDrawBuffer(GL_BACK);
  glViewport(0, 0, window.x, window.y);
  glClearColor(0.11f, 0.11f, 0.12f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  if (displayValues) {
    glBlitNamedFramebuffer(m.fbo.get(), 0, 0, 0, size.x, size.y, area.x, area.y, area.x + size.x, area.y + size.y,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
  } else {
    glBlitNamedFramebuffer(m.fbo.get(), m.resolveFbo.get(), 0, 0, size.x, size.y, 0, 0, size.x, size.y,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDrawBuffer(GL_BACK);
    m.viewPass->draw(m.resolved.get(), area, scene::viewTransformFor(scene_));
  }
  drawUi();
}

void Viewer::drawUi() {
  Impl& m = *impl_;
  m.uiDrawnLastFrame = uiVisible || !fileError_.empty() || !editError_.empty();
  if (!m.uiDrawnLastFrame) return;
  ImGui::SetCurrentContext(m.imgui);
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  if (uiVisible) drawPanels(*this, m.panels);
  drawErrorOverlay(*this);
  ImGui::Render();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

Result<core::Image> Viewer::readWindow() {
  const glm::ivec2 size = framebufferSize();
  if (size.x <= 0 || size.y <= 0) return Error{"the window has no pixels (minimized?)"};
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size.x) * size.y * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, size.x, size.y, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
  if (const std::string errors = core::drainGlErrors(); !errors.empty())
    return Error{"GL error while reading the window: " + errors};
  core::Image image(size.x, size.y, 4);
  for (int y = 0; y < size.y; ++y) {
    const unsigned char* row = &bytes[static_cast<std::size_t>(size.y - 1 - y) * size.x * 4];
    for (int x = 0; x < size.x; ++x) {
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = row[x * 4 + c] / 255.0f;
      image.at(x, y, 3) = 1.0f;  // a window is opaque, whatever alpha the visual keeps
    }
  }
  return image;
}

void Viewer::present() {
  Impl& m = *impl_;
  m.context->swapBuffers();
  const double t = now();
  const double ms = (t - m.lastPresent) * 1000.0;
  m.lastPresent = t;
  frameMs_ = frameMs_ == 0.0 ? ms : 0.9 * frameMs_ + 0.1 * ms;
}

Result<fs::path> Viewer::saveScreenshot(const fs::path& file) {
  fs::path target = file;
  if (target.empty()) {
    const fs::path dir = options_.screenshotDir.empty() ? scene_.file.parent_path() : options_.screenshotDir;
    char number[32];
    std::snprintf(number, sizeof number, "_f%04d", frame_);
    const std::string base = scene_.file.stem().string() + number;
    target = dir / (base + ".png");
    std::error_code ec;
    for (int k = 2; fs::exists(target, ec); ++k) target = dir / (base + "_" + std::to_string(k) + ".png");
  }
  auto image = readWindow();
  if (!image) return image.error();
  core::OutputTransaction tx;
  if (!target.parent_path().empty()) {
    if (auto r = tx.prepareDirectory(target.parent_path()); !r) return r.error();
  }
  const fs::path temp = tx.stage(target);
  if (auto r = core::writeImage(temp, *image, core::PixelType::kUInt8, {}, "screenshot.png"); !r)
    return Error::at(target, r.error().message);
  if (auto r = tx.commit(); !r) return r.error();
  setStatus("screenshot " + target.string());
  return target;
}

// ---- loops -----------------------------------------------------------------------------------

int Viewer::runInteractive() {
  Impl& m = *impl_;
  glfwSwapInterval(1);
  double last = now();
  while (!processEvents()) {
    if (now() - m.lastPoll >= 0.25) checkFiles();
    drawFrame();
    if (m.screenshotRequested) {
      m.screenshotRequested = false;
      auto shot = saveScreenshot();
      if (!shot) {
        editError_ = "screenshot: " + shot.error().message;
      } else if (!options_.quiet) {
        std::printf("puffview: wrote %s\n", shot->c_str());
        std::fflush(stdout);
      }
    }
    present();
    const double t = now();
    advance(t - last);
    last = t;
  }
  return 0;
}

Result<void> Viewer::runBatch(int first, int last, const std::function<fs::path(int)>& screenshotFor,
                              const std::function<void(int done, int total)>& progress) {
  glfwSwapInterval(0);
  playing_ = false;
  const int total = last - first + 1;
  for (int f = first; f <= last; ++f) {
    if (progress) progress(f - first, total);
    setFrame(f);
    if (processEvents()) return Error{"the window was closed before frame " + std::to_string(f)};
    frame_ = f;  // keys (space, arrows) must not move a batch run off its frames
    drawFrame();
    if (const fs::path shot = screenshotFor ? screenshotFor(f) : fs::path(); !shot.empty()) {
      if (auto saved = saveScreenshot(shot); !saved) return saved.error();
    }
    present();
  }
  if (progress) progress(total, total);
  return {};
}

}  // namespace puff::view
