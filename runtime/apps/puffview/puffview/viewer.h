// puffview's core: a GLFW window showing a scene through one render path, the artist's camera,
// play/pause/step, the panels that edit the scene live, saving it back, screenshots, and hot
// reload of every file the scene draws on. The app (puff::view::run, options.cpp) is a loop around
// this class; tests drive it one displayed frame at a time (processEvents, checkFiles, drawFrame,
// readWindow).
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <nlohmann/json_fwd.hpp>

#include <puff/core/error.h>
#include <puff/core/image.h>
#include <puff/render/render.h>
#include <puff/scene/scene.h>
#include <puffview/camera.h>
#include <puffview/watcher.h>

namespace puff::view {

struct ViewerOptions {
  std::filesystem::path scene;   ///< the scene file
  std::filesystem::path artDir;  ///< what "${PUFF_ART}" in the scene's paths stands for
  /// Shaders are read from here (core::setShaderDir) and every file under it is watched. Empty:
  /// $PUFF_SHADER_DIR when set (watched too), else the embedded copies (nothing to watch).
  std::filesystem::path shaderDir;
  std::string path = "cel";  ///< render path, one of render::renderPaths()
  /// The image's size; 0: the scene's output size, clamped to [64, 1920] x [64, 1200]. The window is
  /// that, and with the panels shown as wide again as the panel (kPanelWidth) and at least
  /// kPanelMinHeight tall: the panel docks beside the image, never over it.
  int width = 0, height = 0;
  bool visible = true;                  ///< show the window (tests under Xvfb may keep it hidden)
  bool ui = true;                       ///< draw the panels (H toggles them at run time)
  std::filesystem::path screenshotDir;  ///< screenshots go here; empty: beside the scene file
  bool quiet = false;                   ///< print nothing but errors
  /// Seconds after an edit before the autosave is written (Viewer::autosavePath); 0: at the next
  /// displayed frame.
  double autosaveSeconds = 2.0;
};

/// A renderer drawing `scene` with the path named `pathName` (one of render::renderPaths()) in the
/// current GL context. Errors: an unknown name (listing the available ones), or whatever loading the
/// scene's resources or building the programs reported.
Result<std::unique_ptr<render::SceneRenderer>> createRenderer(const std::string& pathName, const scene::Scene& scene);

/// The docked panel's width and the least window height that shows it (window pixels).
inline constexpr int kPanelWidth = 400, kPanelMinHeight = 480;

class Viewer {
 public:
  /// Loads the scene, opens the window (GL 4.5 compatibility profile, so both render paths run in
  /// it; depth 24, stencil 8) and builds the render path. With the cel path it falls back to the
  /// fixed path when the context cannot run it (older than GL 4.5:
  /// SceneRenderer::checkProgrammable), printing one line "puffview: the programmable (cel) path
  /// cannot run here: WHY; drawing with the fixed-function path" to stderr and showing it as
  /// status(). Errors: the scene's ("FILE: /pointer: ..."), no display ("glfw: cannot open a
  /// window: ..."), no GL 4.5 context (the renderer needs GL 4.5 framebuffer objects on either
  /// path), or the path's (a missing atlas, a mesh that does not load, a shader that does not
  /// build: the compiler's errors on one line).
  static Result<std::unique_ptr<Viewer>> open(const ViewerOptions& options);
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  // ---- the loops ---------------------------------------------------------------------------
  /// Runs until the window is closed (or Esc, asking first when edits are unsaved); the frame
  /// advances with the wall clock at the scene's fps while playing. SIGTERM, SIGHUP or SIGINT stop
  /// it too, after writing the autosave of unsaved edits at once. Returns the exit code (128 + the
  /// signal's number after a signal).
  int runInteractive();
  /// Shows frames first .. last, one per displayed frame (no wall clock: the same every run). After
  /// drawing frame f it saves the window as drawn to screenshotFor(f) when that is not empty, and
  /// tells `progress` (frames shown, of all) when given.
  Result<void> runBatch(int first, int last, const std::function<std::filesystem::path(int)>& screenshotFor,
                        const std::function<void(int done, int total)>& progress = {});

  // ---- one displayed frame, step by step ------------------------------------------------------
  /// Processes window events and the keyboard/mouse (camera, keys); true once closing was asked.
  bool processEvents();
  /// Hot reload: polls the watched files now and reloads what changed. A broken file sets
  /// fileError() and keeps the last good state; a later good version clears it.
  void checkFiles();
  /// Draws the current frame (and the panels when shown) into the window's back buffer.
  void drawFrame();
  /// The back buffer as last drawn: RGBA in [0, 1], top row first, framebufferSize() pixels.
  Result<core::Image> readWindow();
  /// Shows the back buffer (swap) and measures the frame time.
  void present();
  /// While playing, moves the frame on by `seconds` of wall time at the scene's fps (wrapping
  /// after the last frame when `loop`). The interactive loop calls it; batch runs never do.
  void advance(double seconds);

  // ---- the scene ---------------------------------------------------------------------------
  /// The scene being edited. Change it, then call applyEdit().
  scene::Scene& scene() { return scene_; }
  /// Applies scene() to the render path at once. First it is checked as the scene reader checks a
  /// file: an edit the file would refuse (a value out of range, motion blur on cartoon media...) is
  /// not applied, scene() goes back to the scene as last applied, and editError() says why. An edit
  /// the reader takes but the render path cannot draw (an atlas path that names no atlas) stays in
  /// scene(), the view keeps the last good state and editError() says why. The next successful edit
  /// clears it.
  Result<void> applyEdit();
  /// Writes scene() as JSON (every field) to `file` (default: the scene file), with a ramp or
  /// gradient edited in the panel beside it (STEM_ramp.png, STEM_gradient.png): the scene is checked
  /// first, then every file is staged and all are renamed into place together, so a failure changes
  /// no file and no part of the viewer's scene. A failure is the status line ("FILE: not saved: ...")
  /// and stderr. Saving elsewhere makes that file the scene file from then on (watched, saved to).
  Result<std::filesystem::path> save(const std::filesystem::path& file = {});
  const std::filesystem::path& sceneFile() const { return scene_.file; }

  // ---- keeping the artist's work -------------------------------------------------------------
  /// True while scene() differs from the scene file as last loaded or saved; the window's title
  /// (title()) starts with "* " then.
  bool unsaved() const { return unsaved_; }
  const std::string& title() const { return title_; }
  /// Quitting (Esc, Ctrl+Q, the window's close button): at once when nothing is unsaved, else the
  /// quit prompt opens (Save / Discard / Cancel), and processEvents() returns true only once it is
  /// answered Save (and the save succeeded) or Discard.
  void requestQuit();
  bool quitPromptOpen() const { return quitPrompt_; }
  enum class QuitAnswer { kSave, kDiscard, kCancel };
  void answerQuit(QuitAnswer answer);
  /// While edits are unsaved, the edited scene is written to autosavePath() (beside the scene file,
  /// hidden: ".NAME.puffview-autosave") ViewerOptions::autosaveSeconds after an edit; it is removed
  /// once the scene is saved, the edits are discarded, or undone back to the file. A crash or a kill
  /// leaves it, and a viewer opened on that scene offers to restore it (autosaveOffered(),
  /// answerAutosave): restored, it is an edit undo takes back.
  std::filesystem::path autosavePath() const;
  bool autosaveOffered() const { return autosaveOffer_; }
  void answerAutosave(bool restore);
  /// The scene file changed on disk while edits are unsaved: it is not reloaded over them; a prompt
  /// asks (diskChangePrompt(); answerDiskChange: reload it, the edits one undo away, or keep them).
  bool diskChangePrompt() const { return diskPrompt_; }
  void answerDiskChange(bool reload);
  /// A key as if pressed (GLFW key and modifiers), through the window's key callbacks (Dear ImGui's
  /// and the viewer's), and released once a whole frame has seen it down (a key typed again needs a
  /// frame between, as Dear ImGui reads keys once a frame): what
  /// the shortcuts and the panels do with it. For tests and scripted sessions.
  void typeKey(int key, int mods = 0);

  // ---- ramp and gradient editing ---------------------------------------------------------------
  /// The ramp (q, RGB display values, Ramp's limits) or ambient gradient edited in the panel: written,
  /// named by its content, into the viewer's scratch directory and the scene pointed at it, so the
  /// next frame shows it and undo can go back to any earlier one. Call within an edit
  /// (beginEdit). save() writes it beside the scene file as STEM_ramp.png / STEM_gradient.png and
  /// points the saved scene (and the viewer's) there.
  Result<void> setRamp(const core::Image& ramp);
  Result<void> setAmbientGradient(const core::Image& gradient);
  /// Where setRamp and setAmbientGradient write (removed with the viewer).
  const std::filesystem::path& scratchDir();

  // ---- undo and redo -------------------------------------------------------------------------
  /// An edit begins: the scene as it was when the last edit ended becomes an undo step (once per
  /// edit, however many small changes it makes: a slider dragged is undone whole) and the redo
  /// steps are dropped. The panels call it on an edit's first change, endEdit() when no widget is
  /// held any more.
  void beginEdit();
  void endEdit();
  /// Back to the scene before the last edit (or reload from disk), applied at once; false when
  /// there is nothing to undo. The scene file (Save as) stays where it is.
  bool undo();
  /// Forward again to the edit undo() took back; false when there is nothing to redo.
  bool redo();
  bool canUndo() const { return !undo_.empty(); }
  bool canRedo() const { return !redo_.empty(); }
  const std::string& fileError() const { return fileError_; }
  const std::string& editError() const { return editError_; }

  // ---- timeline ----------------------------------------------------------------------------
  int frame() const { return frame_; }
  void setFrame(int frame);
  bool playing() const { return playing_; }
  void setPlaying(bool playing);
  void step();       ///< pauses and shows the next frame
  void restart();    ///< back to frame 0 (the simulation restarts)
  bool loop = true;  ///< wrap to frame 0 after the scene's last frame while playing

  // ---- camera, path, stats, screenshots -----------------------------------------------------
  CameraController& cameraController() { return camera_; }
  /// True once the user moved the camera: the viewer's camera replaces the scene's (and its
  /// animated orbit) until resetCamera().
  bool cameraOverridden() const { return cameraOverride_; }
  void setCameraOverridden(bool on) { cameraOverride_ = on; }
  void resetCamera();
  /// Copies the viewer's camera into scene().camera (so Save keeps the view).
  void cameraToScene();

  const std::string& pathName() const { return pathName_; }
  /// Switches the render path (one of render::renderPaths()), building it anew for scene(); on error the
  /// old one stays and status() says why.
  Result<void> setPath(const std::string& name);

  const render::FrameStats& stats() const { return stats_; }
  double frameMs() const { return frameMs_; }  ///< wall time between displayed frames, smoothed
  glm::ivec2 framebufferSize() const;
  /// Where the image is drawn in the window (framebuffer pixels, origin bottom-left): the window
  /// left of the panel when it is shown, else the whole window, the image's aspect fitted and
  /// centred in it (the image size from the options, else the scene's output size).
  cel::Viewport imageViewport() const;

  /// Saves the window (as drawn last, panels included when shown) as a PNG: to `file`, or when
  /// empty to a new "<scene>_fNNNN[_K].png" in the screenshot directory. Returns the path.
  Result<std::filesystem::path> saveScreenshot(const std::filesystem::path& file = {});

  bool uiVisible = true;
  /// The last status line (saved to ..., screenshot ...), shown in the panel.
  const std::string& status() const { return status_; }
  const std::filesystem::path& artDir() const { return options_.artDir; }

 private:
  Viewer();
  struct Impl;
  std::unique_ptr<Impl> impl_;

  void watchScene();
  void reloadScene();
  void rebuildPath(const std::string& why);
  void handleInput();
  void drawUi();
  void setStatus(std::string text);
  /// The scene's warnings (scene::sceneWarnings) on stderr and in the status line after `lead`
  /// ("reloaded FILE"); with none, the status is `lead` (left as it is when that is empty).
  void showSceneWarnings(const std::string& lead);

  glm::ivec2 imageSize() const;

  ViewerOptions options_;
  scene::Scene scene_;
  std::unique_ptr<render::SceneRenderer> renderer_;
  std::string drawError_;  // the last draw's error, shown once
  std::string pathName_;
  FileWatcher watcher_;
  std::string fileError_, editError_, status_;
  int frame_ = 0;
  bool playing_ = true;
  double playClock_ = 0.0;  // seconds played since frame_ began
  render::FrameStats stats_;
  double frameMs_ = 0.0;
  CameraController camera_;
  bool cameraOverride_ = false;
  // Undo: the scene before each edit (oldest first, at most kUndoSteps), the steps undone, and the
  // scene as the last edit left it (what beginEdit() records).
  static constexpr std::size_t kUndoSteps = 200;
  std::vector<scene::Scene> undo_, redo_;
  scene::Scene committed_;
  scene::Scene applied_;  // the scene as last applied: what an edit the reader refuses goes back to
  bool editing_ = false;
  void restore(scene::Scene scene, const char* what);
  std::filesystem::path scratch_;
  Result<std::filesystem::path> writeScratch(const char* kind, const core::Image& image);
  /// The scene as the window shows it: a transparent frame over a grey checkerboard (a plate in the
  /// scratch directory at the frame's size), so dark ink and smoke stay visible; any other scene
  /// as it is. What is edited and saved is always the scene itself.
  scene::Scene shown(const scene::Scene& s);
  glm::ivec2 checkerSize_{0};
  std::filesystem::path checkerPlate_;  ///< the checkerboard written for checkerSize_
  /// save(): where a ramp or gradient still in the scratch directory goes beside `target` (else
  /// `image` as it is); the scene's JSON text as written to `target`, checked as the reader reads it.
  std::filesystem::path besideScene(const std::filesystem::path& target, const std::filesystem::path& image,
                                    const char* suffix) const;
  /// `wrote`, when given: whether the text is the whole scene rather than the file's own text edited.
  Result<std::string> sceneText(const scene::Scene& s, const std::filesystem::path& target,
                                bool* wrote = nullptr) const;
  /// toJson of `s` as saved to `target`: paths relative to it, the art directory's as ${PUFF_ART}.
  nlohmann::json writtenJson(const scene::Scene& s, const std::filesystem::path& target) const;
  Result<void> readerCheck(const scene::Scene& s) const;  // s as its file would be read: refused or not
  Result<std::filesystem::path> writeScene(const std::filesystem::path& target);
  // Keeping the artist's work (viewer_keep.cpp): the scene as last loaded or saved, whether scene()
  // differs from it, the title, the prompts and the autosave.
  scene::Scene saved_;
  // The file's text as last read or saved: a save changes it only where the scene changed since
  // (scene::editSceneText).
  std::string diskText_;
  bool unsaved_ = false, quitPrompt_ = false, autosaveOffer_ = false, diskPrompt_ = false, batch_ = false;
  std::string title_;
  double autosaveDue_ = -1.0;  // when the autosave is to be written (GLFW seconds); < 0: none due
  void markSaved();            // scene() is the file now
  void noteChange();           // after scene() changed: unsaved, the title, the autosave's time
  void keepWork();             // each displayed frame: writes the autosave when due
  void keepNow();              // a stop asked by a signal: the autosave now, whatever its time
  void releaseTyped();         // typeKey's keys up again, once a whole frame has seen them down
  void removeAutosave();
  void offerAutosave();  // at open: an autosave beside the scene is offered
  void adoptScratch(std::filesystem::path& image, const char* kind);  // another viewer's scratch image into ours
  void drawPrompts();
};

}  // namespace puff::view
