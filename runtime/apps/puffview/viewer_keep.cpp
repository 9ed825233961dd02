// What keeps the artist's work: the unsaved marker, the quit prompt, and the autosave a crash or
// a kill leaves beside the scene, offered back on the next start.
#include <cstdio>
#include <string>

#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/scene/read.h>
#include <puffview/viewer.h>

#include "viewer_impl.h"

#include <backends/imgui_impl_glfw.h>

namespace puff::view {

namespace fs = std::filesystem;

fs::path Viewer::autosavePath() const {
  // Appended, not "." + name: GCC 12 warns (-Wrestrict) on that concatenation, wrongly.
  std::string name = ".";
  name += scene_.file.filename().string();
  name += ".puffview-autosave";
  return scene_.file.parent_path() / name;
}

void Viewer::markSaved() {
  saved_ = scene_;
  noteChange();
}

void Viewer::noteChange() {
  const bool was = unsaved_;
  unsaved_ = !(scene_ == saved_);
  const std::string title = (unsaved_ ? "* " : "") + scene_.file.filename().string() + " - puffview";
  if (title != title_) {
    title_ = title;
    if (impl_->window) glfwSetWindowTitle(impl_->window, title_.c_str());
  }
  if (unsaved_) {
    autosaveDue_ = Impl::now() + options_.autosaveSeconds;
  } else if (was || autosaveDue_ >= 0.0) {
    autosaveDue_ = -1.0;
    removeAutosave();  // saved, or undone back to the file: nothing left to keep
  }
}

void Viewer::keepWork() {
  if (autosaveDue_ < 0.0 || Impl::now() < autosaveDue_) return;
  autosaveDue_ = -1.0;
  // The scene as save() would write it (paths relative to the scene file, beside which it lies);
  // an edit the reader refuses is not kept (the last good autosave stays).
  auto text = sceneText(scene_, scene_.file);
  if (!text) return;
  if (auto r = core::writeFileAtomic(autosavePath(), *text); !r) {
    // Said where the artist looks: these edits are kept nowhere but in this window.
    setStatus("your edits are not being kept (Save them): cannot write the autosave: " + r.error().message);
    if (!options_.quiet)
      std::fprintf(stderr, "puffview: warning: cannot write the autosave: %s\n", r.error().message.c_str());
  }
}

void Viewer::removeAutosave() {
  std::error_code ec;
  fs::remove(autosavePath(), ec);
}

void Viewer::offerAutosave() {
  std::error_code ec;
  const fs::file_status kept = fs::symlink_status(autosavePath(), ec);
  if (!fs::exists(kept)) return;
  if (!fs::is_regular_file(fs::status(autosavePath(), ec))) {
    setStatus(autosavePath().string() +
              " is where puffview keeps unsaved edits, and it is not a file: nothing to restore");
    if (!options_.quiet) std::fprintf(stderr, "puffview: warning: %s\n", status().c_str());
    return;
  }
  autosaveOffer_ = true;
  setStatus("unsaved edits to " + scene_.file.filename().string() + " were kept in " + autosavePath().string() +
            ": restore them or discard them");
}

void Viewer::answerAutosave(bool restore) {
  if (!autosaveOffer_) return;
  autosaveOffer_ = false;
  if (!restore) {
    removeAutosave();
    setStatus("discarded the kept edits");
    return;
  }
  auto kept = scene::loadScene(autosavePath(), options_.artDir);
  if (!kept) {
    setStatus("cannot restore the kept edits (left in " + autosavePath().string() + "): " + kept.error().message);
    if (!options_.quiet) std::fprintf(stderr, "puffview: error: %s\n", status().c_str());
    return;
  }
  kept->file = scene_.file;
  // An edited ramp or gradient the autosave names lies in the stopped viewer's scratch directory:
  // taken into this one's, so that Save puts it beside the scene.
  adoptScratch(kept->ramp, "ramp");
  adoptScratch(kept->ambientGradient, "gradient");
  endEdit();
  beginEdit();  // restored edits are one step undo takes back
  scene_ = std::move(*kept);
  endEdit();
  (void)applyEdit();
  setStatus("restored the kept edits (unsaved)");
}

void Viewer::adoptScratch(fs::path& image, const char* kind) {
  if (image.empty() || !image.parent_path().filename().string().starts_with("puffview-") ||
      image.parent_path() == scratchDir())
    return;
  auto pixels = core::readImage(image);
  auto adopted = pixels ? writeScratch(kind, *pixels) : Result<fs::path>(pixels.error());
  if (!adopted) {
    setStatus("the kept " + std::string(kind) + " cannot be read: " + adopted.error().message);
    return;
  }
  // The stopped viewer's copy is ours now: removed, and its directory with the last of them.
  std::error_code ec;
  fs::remove(image, ec);
  if (fs::is_empty(image.parent_path(), ec) && !ec) fs::remove(image.parent_path(), ec);
  image = *adopted;
}

void Viewer::answerDiskChange(bool reload) {
  if (!diskPrompt_) return;
  diskPrompt_ = false;
  if (reload) {
    reloadScene();
  } else {
    setStatus("kept your edits; Save overwrites " + scene_.file.string());
  }
}

void Viewer::requestQuit() {
  if (!unsaved_) {
    glfwSetWindowShouldClose(impl_->window, GLFW_TRUE);
    return;
  }
  glfwSetWindowShouldClose(impl_->window, GLFW_FALSE);
  quitPrompt_ = true;
}

void Viewer::answerQuit(QuitAnswer answer) {
  if (!quitPrompt_) return;
  quitPrompt_ = false;
  switch (answer) {
    case QuitAnswer::kSave:
      if (!save()) return;  // the error is in the status line; the viewer stays open
      break;
    case QuitAnswer::kDiscard:
      autosaveDue_ = -1.0;
      removeAutosave();
      unsaved_ = false;  // nothing is kept any more: the scratch directory goes with the viewer
      break;
    case QuitAnswer::kCancel:
      return;
  }
  glfwSetWindowShouldClose(impl_->window, GLFW_TRUE);
}

void Viewer::keepNow() {
  if (!unsaved_) return;
  autosaveDue_ = 0.0;  // due at once
  keepWork();
}

void Viewer::typeKey(int key, int mods) {
  // Through the window's key callback, as GLFW delivers a key: Dear ImGui's, which hands it on to
  // the viewer's (Impl::onKey).
  ImGui::SetCurrentContext(impl_->imgui);
  if (!impl_->imguiBackends) {
    impl_->keys.emplace_back(key, mods);
    return;
  }
  ImGui_ImplGlfw_KeyCallback(impl_->window, key, 0, GLFW_PRESS, mods);
  impl_->typed.emplace_back(key, mods);  // released after a frame has seen it down (releaseTyped)
}

void Viewer::releaseTyped() {
  Impl& m = *impl_;
  if (m.imguiBackends && !m.typedSeen.empty()) {
    ImGui::SetCurrentContext(m.imgui);
    for (const auto& [key, mods] : m.typedSeen) ImGui_ImplGlfw_KeyCallback(m.window, key, 0, GLFW_RELEASE, mods);
  }
  m.typedSeen = std::move(m.typed);  // down through the frame this call begins
  m.typed.clear();
}

void Viewer::Impl::onClose(GLFWwindow* w) {
  if (Viewer* v = of(w)) v->requestQuit();
}

// The prompts, modal over the window: quitting with unsaved edits, and kept edits found at start.
void Viewer::drawPrompts() {
  const char* quit = "Unsaved changes";
  const char* kept = "Kept edits";
  if (quitPrompt_ && !ImGui::IsPopupOpen(quit)) ImGui::OpenPopup(quit);
  if (ImGui::BeginPopupModal(quit, nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("%s has unsaved changes.", scene_.file.filename().c_str());
    if (ImGui::Button("Save")) answerQuit(QuitAnswer::kSave);
    ImGui::SameLine();
    if (ImGui::Button("Discard")) answerQuit(QuitAnswer::kDiscard);
    ImGui::SameLine();
    // Esc cancels, but not the Esc that asked to quit (the prompt's first frame sees it too).
    const bool escape = !ImGui::IsWindowAppearing() && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false);
    if (ImGui::Button("Cancel") || escape) answerQuit(QuitAnswer::kCancel);
    if (!quitPrompt_) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
  const char* disk = "Changed on disk";
  if (diskPrompt_ && !quitPrompt_ && !ImGui::IsPopupOpen(disk)) ImGui::OpenPopup(disk);
  if (ImGui::BeginPopupModal(disk, nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("%s changed on disk, and your edits to it are unsaved.", scene_.file.filename().c_str());
    if (ImGui::Button("Reload it (undo brings your edits back)")) answerDiskChange(true);
    if (ImGui::Button("Keep my edits (Save overwrites the file)")) answerDiskChange(false);
    if (!diskPrompt_) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
  const bool offer = autosaveOffer_ && !batch_;
  if (offer && !quitPrompt_ && !ImGui::IsPopupOpen(kept)) ImGui::OpenPopup(kept);
  if (ImGui::BeginPopupModal(kept, nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("Edits to %s were not saved when puffview last stopped.", scene_.file.filename().c_str());
    if (ImGui::Button("Restore")) answerAutosave(true);
    ImGui::SameLine();
    if (ImGui::Button("Discard")) answerAutosave(false);
    if (!autosaveOffer_) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
}

}  // namespace puff::view
