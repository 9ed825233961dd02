// The viewer's hot reload: the files it watches, and what it reloads or rebuilds when they change.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <puff/core/atlas.h>
#include <puff/core/shader.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>
#include <puffview/viewer.h>

#include "viewer_impl.h"

namespace puff::view {

namespace fs = std::filesystem;

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
  impl_->lastPoll = Impl::now();
  const std::vector<fs::path> changed = watcher_.poll();
  if (changed.empty()) return;
  const bool sceneChanged = std::find(changed.begin(), changed.end(), scene_.file) != changed.end();
  const bool resourcesChanged = changed.size() > (sceneChanged ? 1u : 0u);
  if (!options_.quiet) {
    for (const fs::path& p : changed) std::printf("puffview: changed: %s\n", p.c_str());
    std::fflush(stdout);
  }
  if (sceneChanged && unsaved_) {
    // Not over the artist's edits: asked first (Viewer::drawPrompts).
    diskPrompt_ = true;
    setStatus(scene_.file.string() + " changed on disk while your edits are unsaved");
    if (resourcesChanged) rebuildPath("changed files");
  } else if (sceneChanged) {
    reloadScene();
    if (resourcesChanged && impl_->sceneError.empty()) rebuildPath("changed files");
  } else {
    rebuildPath("changed files");
  }
}

void Viewer::reloadScene() {
  Impl& m = *impl_;
  std::string text;
  auto loaded = scene::loadScene(scene_.file, options_.artDir, &text);
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
  applied_ = scene_;
  endEdit();
  markSaved();  // what is shown is the file
  diskText_ = std::move(text);
  m.sceneError.clear();
  m.resourceError.clear();  // update() reloaded what the scene names, or nothing changed there
  fileError_.clear();
  editError_.clear();
  if (!cameraOverride_) camera_.reset(scene::cameraAt(scene_, frame_));
  const fs::path file = scene_.file;
  watchScene();  // the scene may name other files now
  showSceneWarnings("reloaded " + file.string());
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

}  // namespace puff::view
