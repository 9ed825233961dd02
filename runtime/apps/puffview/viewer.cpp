// The viewer's life (open, close), undo and redo, timeline, camera, render path, image placement, loops.
#include <puff/gl_api.h>  // before GLFW, which would otherwise include the system <GL/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>

#include <puff/core/shader.h>
#include <puff/platform/gl_context.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>
#include <puff/support/text.h>
#include <puffview/viewer.h>

#include "viewer_impl.h"

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

}  // namespace

// ImGui on the window, its GLFW and OpenGL 3 backends.
Result<void> Viewer::Impl::initImgui() {
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

Viewer::Viewer() : impl_(std::make_unique<Impl>()) {}

Viewer::~Viewer() {
  // Unsaved edits keep their autosave, and the edited ramp or gradient it names.
  const bool named =
      unsaved_ && (scene_.ramp.parent_path() == scratch_ || scene_.ambientGradient.parent_path() == scratch_);
  if (!scratch_.empty() && !named) {
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
  std::string text;
  PUFF_TRY_ASSIGN(auto loaded, scene::loadScene(options.scene, options.artDir, &text));
  if (!options.shaderDir.empty()) core::setShaderDir(options.shaderDir);

  std::unique_ptr<Viewer> v(new Viewer());
  v->options_ = options;
  v->scene_ = std::move(loaded);
  v->diskText_ = std::move(text);
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
  PUFF_TRY_ASSIGN(auto context, createContext(gl, mayFallBack, whyNotCel));
  m.context = std::move(context);
  m.window = static_cast<GLFWwindow*>(m.context->nativeWindow());
  glfwSetWindowUserPointer(m.window, v.get());
  // Ours first: ImGui's backend chains to the callbacks installed before it.
  glfwSetKeyCallback(m.window, Impl::onKey);
  glfwSetScrollCallback(m.window, Impl::onScroll);
  glfwSetWindowCloseCallback(m.window, Impl::onClose);

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
  v->committed_ = v->applied_ = v->scene_;
  v->markSaved();
  v->showSceneWarnings("");
  v->offerAutosave();
  v->watchScene();
  m.lastInput = m.lastPresent = m.lastPoll = Impl::now();
  return v;
}

// ---- undo and redo ---------------------------------------------------------------------------

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
  if (auto ok = readerCheck(scene_); !ok) {
    editError_ = "not applied: " + ok.error().message;
    scene_ = applied_;
    noteChange();
    return Error{editError_};
  }
  applied_ = scene_;
  auto r = renderer_->update(shown(scene_));
  editError_ = r ? "" : r.error().message;
  noteChange();
  return r;
}

void Viewer::setStatus(std::string text) { status_ = std::move(text); }

void Viewer::showSceneWarnings(const std::string& lead) {
  const std::vector<std::string> warnings = scene::sceneWarnings(scene_);
  for (const std::string& w : warnings) {
    if (!options_.quiet) std::fprintf(stderr, "puffview: warning: %s: %s\n", scene_.file.c_str(), w.c_str());
  }
  if (warnings.empty()) {
    if (!lead.empty()) setStatus(lead);
    return;
  }
  const std::string more = warnings.size() > 1 ? " (and " + std::to_string(warnings.size() - 1) + " more)" : "";
  setStatus(lead + (lead.empty() ? "" : "; ") + "warning: " + warnings.front() + more);
}

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

// ---- loops -----------------------------------------------------------------------------------

namespace {

// A stop asked from outside (kill, logout, Ctrl+C in the terminal): the signal's number.
volatile std::sig_atomic_t stopSignal = 0;
extern "C" void onStopSignal(int signal) { stopSignal = signal; }

}  // namespace

int Viewer::runInteractive() {
  Impl& m = *impl_;
  glfwSwapInterval(1);
  double last = Impl::now();
  for (int s : {SIGTERM, SIGHUP, SIGINT}) std::signal(s, onStopSignal);
  while (!processEvents()) {
    if (stopSignal != 0) {  // unsaved edits are kept at once, whatever the autosave's time
      keepNow();
      return 128 + stopSignal;
    }
    if (Impl::now() - m.lastPoll >= 0.25) checkFiles();
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
    const double t = Impl::now();
    advance(t - last);
    last = t;
  }
  return 0;
}

Result<void> Viewer::runBatch(int first, int last, const std::function<fs::path(int)>& screenshotFor,
                              const std::function<void(int done, int total)>& progress) {
  glfwSwapInterval(0);
  playing_ = false;
  batch_ = true;  // no prompts in the frames
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
