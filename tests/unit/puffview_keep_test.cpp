// puffview keeps the artist's work: quitting with unsaved edits asks (and keys go to the prompt, not
// the shortcuts), a killed viewer leaves an autosave the next one offers back, and a save is whole
// or nothing, its failure said in the window.
//
// These tests open a window: ctest runs them under Xvfb (PuffviewUnderXvfb, with
// PUFF_TEST_REQUIRE_GLFW=1); without a display they skip.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <puff/core/files.h>
#include <puff/scene/read.h>
#include <puffview/ramp_edit.h>
#include <puffview/viewer.h>

#include "puffview_test_helpers.h"
#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using puff::view::Viewer;

class PuffviewKeep : public ::testing::Test {
 protected:
  void SetUp() override {
    file_ = dir_ / "cloud.json";
    std::ofstream(file_) << R"({"output": {"width": 160, "height": 120, "background": "#ffffff"},
      "atlas": "${PUFF_ART}/default/puff.json", "emitters": [{"count": 30, "seed": 3, "radius": 0.7}]})";
  }
  std::unique_ptr<Viewer> open(double autosaveSeconds = 0.0) {
    puff::view::ViewerOptions o;
    o.scene = file_;
    o.artDir = PUFF_ART_DIR;
    o.width = 160;
    o.height = 120;
    o.quiet = true;
    o.autosaveSeconds = autosaveSeconds;
    auto v = Viewer::open(o);
    EXPECT_OK(v);
    return v ? std::move(*v) : nullptr;
  }
  // One displayed frame: events (and the autosave when due), then the frame with its prompts.
  static bool frame(Viewer& v) {
    const bool closing = v.processEvents();
    v.drawFrame();
    v.present();
    return closing;
  }
  static void edit(Viewer& v, glm::vec3 background) {
    v.beginEdit();
    v.scene().background = background;
    v.endEdit();
    ASSERT_OK(v.applyEdit());
  }
  // An edited ramp (one red band): written to the viewer's scratch directory, named by the scene.
  static void editRamp(Viewer& v) {
    puff::view::RampBands red;
    red.starts = {0.0f};
    red.colors = {{1.0f, 0.0f, 0.0f}};
    v.beginEdit();
    ASSERT_OK(v.setRamp(puff::view::rampImage(red)));
    v.endEdit();
  }
  std::string onDisk() const { return *puff::core::readFileBytes(file_); }

  puff::test::ScopedTempDir dir_{"puffview-keep"};
  fs::path file_;
};

TEST_F(PuffviewKeep, QuittingWithUnsavedEditsAsksFirst) {
  PUFFVIEW_NEEDS_DISPLAY();
  const std::string original = onDisk();
  auto v = open();
  ASSERT_TRUE(v);
  EXPECT_FALSE(v->unsaved());
  EXPECT_EQ(v->title(), "cloud.json - puffview");
  v->typeKey(GLFW_KEY_ESCAPE);
  EXPECT_TRUE(frame(*v)) << "nothing to lose: Esc quits at once";

  v.reset();  // one viewer at a time: ImGui's GLFW backend reads the current context

  v = open();
  ASSERT_TRUE(v);
  edit(*v, {0.5f, 0.25f, 0.0f});
  EXPECT_TRUE(v->unsaved());
  EXPECT_EQ(v->title(), "* cloud.json - puffview");
  for (const auto& [key, mods] : {std::pair{GLFW_KEY_ESCAPE, 0}, {GLFW_KEY_Q, GLFW_MOD_CONTROL}}) {
    SCOPED_TRACE("key " + std::to_string(key));
    v->typeKey(key, mods);
    EXPECT_FALSE(frame(*v));
    EXPECT_TRUE(v->quitPromptOpen());
    // Keys go to the prompt: none of them plays, steps or restarts behind it.
    const bool playing = v->playing();
    const int at = v->frame();
    for (int k : {GLFW_KEY_SPACE, GLFW_KEY_PERIOD, GLFW_KEY_R}) v->typeKey(k);
    EXPECT_FALSE(frame(*v));
    EXPECT_EQ(v->playing(), playing);
    EXPECT_EQ(v->frame(), at);
    EXPECT_TRUE(v->quitPromptOpen());
    v->answerQuit(Viewer::QuitAnswer::kCancel);
    EXPECT_FALSE(frame(*v)) << "Cancel: back to work";
    EXPECT_FALSE(v->quitPromptOpen());
    frame(*v);  // the frame the prompt closed in still had the keyboard
  }
  // Esc in the prompt cancels it (the Esc that opened it does not).
  v->typeKey(GLFW_KEY_ESCAPE);
  frame(*v);
  frame(*v);  // the key up again
  ASSERT_TRUE(v->quitPromptOpen());
  v->typeKey(GLFW_KEY_ESCAPE);
  EXPECT_FALSE(frame(*v));
  EXPECT_FALSE(v->quitPromptOpen());
  frame(*v);
  EXPECT_EQ(onDisk(), original);
  // Discard: the file as it was, no autosave left, and the scratch directory (an edited ramp) goes
  // with the viewer.
  editRamp(*v);
  const fs::path scratch = v->scratchDir();
  v->requestQuit();  // what the window's close button does
  EXPECT_TRUE(v->quitPromptOpen());
  v->answerQuit(Viewer::QuitAnswer::kDiscard);
  EXPECT_TRUE(frame(*v));
  EXPECT_EQ(onDisk(), original);
  EXPECT_FALSE(fs::exists(v->autosavePath()));
  v.reset();
  EXPECT_FALSE(fs::exists(scratch));

  // Save: the file has the edit, then the viewer closes.
  v = open();
  ASSERT_TRUE(v);
  edit(*v, {0.0f, 0.5f, 1.0f});
  v->requestQuit();
  v->answerQuit(Viewer::QuitAnswer::kSave);
  EXPECT_TRUE(frame(*v));
  auto saved = puff::scene::loadScene(file_, PUFF_ART_DIR);
  ASSERT_OK(saved);
  EXPECT_EQ(saved->background, glm::vec3(0.0f, 0.5f, 1.0f));
  EXPECT_FALSE(fs::exists(v->autosavePath()));

  // Undone back to the file, nothing is unsaved: Esc quits at once again.
  v.reset();  // one viewer at a time: ImGui's GLFW backend reads the current context
  v = open();
  ASSERT_TRUE(v);
  edit(*v, {1.0f, 0.0f, 0.0f});
  ASSERT_TRUE(v->undo());
  EXPECT_FALSE(v->unsaved());
  EXPECT_EQ(v->title(), "cloud.json - puffview");
  v->typeKey(GLFW_KEY_ESCAPE);
  EXPECT_TRUE(frame(*v));
}

TEST_F(PuffviewKeep, AKilledViewerLeavesAnAutosaveTheNextOneOffersBack) {
  PUFFVIEW_NEEDS_DISPLAY();
  const std::string original = onDisk();
  auto v = open(3600.0);
  ASSERT_TRUE(v);
  edit(*v, {0.5f, 0.25f, 0.0f});
  frame(*v);
  EXPECT_FALSE(fs::exists(v->autosavePath())) << "not before its time";
  v.reset();  // one viewer at a time: ImGui's GLFW backend reads the current context
  v = open();
  ASSERT_TRUE(v);
  EXPECT_FALSE(v->autosaveOffered());
  edit(*v, {0.5f, 0.25f, 0.0f});
  editRamp(*v);
  frame(*v);
  const fs::path kept = v->autosavePath();
  EXPECT_EQ(kept, dir_ / ".cloud.json.puffview-autosave");
  ASSERT_TRUE(fs::exists(kept)) << "written while the edits are unsaved";
  EXPECT_EQ(onDisk(), original) << "the scene file is not touched";
  const fs::path ramp = v->scene().ramp;
  v.reset();  // as a kill leaves it: nothing answered
  ASSERT_TRUE(fs::exists(kept));
  ASSERT_TRUE(fs::exists(ramp)) << "the edited ramp the autosave names stays";

  v.reset();  // one viewer at a time: ImGui's GLFW backend reads the current context

  v = open();
  ASSERT_TRUE(v);
  EXPECT_TRUE(v->autosaveOffered());
  EXPECT_FALSE(v->unsaved()) << "the file is shown until the artist answers";
  EXPECT_NE(v->status().find("restore them or discard them"), std::string::npos) << v->status();
  const bool playing = v->playing();
  v->typeKey(GLFW_KEY_SPACE);
  frame(*v);
  EXPECT_EQ(v->playing(), playing) << "keys go to the offer";
  v->answerAutosave(true);
  EXPECT_FALSE(v->autosaveOffered());
  EXPECT_TRUE(v->unsaved());
  EXPECT_EQ(v->scene().background, glm::vec3(0.5f, 0.25f, 0.0f));
  EXPECT_EQ(v->scene().ramp, ramp);
  ASSERT_TRUE(v->undo()) << "restoring is a step undo takes back";
  EXPECT_FALSE(v->unsaved());
  ASSERT_TRUE(v->redo());
  ASSERT_OK(v->save());
  EXPECT_FALSE(fs::exists(kept)) << "saved: nothing left to keep";
  EXPECT_TRUE(fs::exists(dir_ / "cloud_ramp.png"));

  // Discarded, the autosave is gone and the file is what opens.
  edit(*v, {0.0f, 1.0f, 0.0f});
  frame(*v);
  ASSERT_TRUE(fs::exists(kept));
  v.reset();  // one viewer at a time: ImGui's GLFW backend reads the current context
  v = open();
  ASSERT_TRUE(v);
  ASSERT_TRUE(v->autosaveOffered());
  v->answerAutosave(false);
  EXPECT_FALSE(fs::exists(kept));
  EXPECT_EQ(v->scene().background, glm::vec3(0.5f, 0.25f, 0.0f));
  v.reset();  // one viewer at a time: ImGui's GLFW backend reads the current context
  v = open();
  EXPECT_FALSE(v->autosaveOffered());
}

TEST_F(PuffviewKeep, AFailedSaveChangesNoFileAndSaysWhy) {
  PUFFVIEW_NEEDS_DISPLAY();
  const std::string original = onDisk();
  auto v = open();
  ASSERT_TRUE(v);
  editRamp(*v);
  const fs::path scratchRamp = v->scene().ramp;

  // A scene the reader would refuse: nothing is written, the ramp beside it included.
  v->beginEdit();
  v->scene().atlas = dir_ / "no-such-atlas.json";
  v->endEdit();
  EXPECT_FALSE(v->applyEdit());
  auto refused = v->save();
  ASSERT_FALSE(refused);
  EXPECT_EQ(v->status(), refused.error().message) << "said in the window";
  EXPECT_NE(v->status().find("not saved"), std::string::npos) << v->status();
  EXPECT_FALSE(fs::exists(dir_ / "cloud_ramp.png"));
  EXPECT_EQ(onDisk(), original);
  ASSERT_TRUE(v->undo());
  // A scene changed without applyEdit (a host calling the viewer's API) that the reader refuses:
  // Save's own check finds it, and writes nothing, the ramp included.
  v->scene().style.outlineWidth = -1.0f;
  refused = v->save();
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("/style/outlineWidth"), std::string::npos) << refused.error().message;
  EXPECT_FALSE(fs::exists(dir_ / "cloud_ramp.png"));
  EXPECT_EQ(onDisk(), original);
  v->scene().style.outlineWidth = 2.0f;

  // A file that cannot be written (the ramp's place is a directory): neither file changes, and the
  // viewer's scene still names its own ramp.
  fs::create_directories(dir_ / "cloud_ramp.png");
  refused = v->save();
  ASSERT_FALSE(refused);
  EXPECT_NE(v->status().find("cloud_ramp.png"), std::string::npos) << v->status();
  EXPECT_EQ(onDisk(), original);
  EXPECT_TRUE(fs::is_directory(dir_ / "cloud_ramp.png"));
  EXPECT_EQ(v->scene().ramp, scratchRamp);
  EXPECT_TRUE(v->unsaved());

  // Once it can be, both are written together.
  fs::remove(dir_ / "cloud_ramp.png");
  ASSERT_OK(v->save());
  EXPECT_EQ(v->scene().ramp, dir_ / "cloud_ramp.png");
  EXPECT_TRUE(fs::is_regular_file(dir_ / "cloud_ramp.png"));
  EXPECT_NE(onDisk().find("cloud_ramp.png"), std::string::npos);
  EXPECT_FALSE(v->unsaved());
  EXPECT_EQ(v->status(), "saved " + file_.string());
}

// A kept autosave the reader refuses is not restored, says why, and stays for the artist to look at.
TEST_F(PuffviewKeep, AKeptAutosaveThatDoesNotLoadSaysWhy) {
  PUFFVIEW_NEEDS_DISPLAY();
  const fs::path kept = dir_ / ".cloud.json.puffview-autosave";
  std::ofstream(kept) << R"({"style": {"outlineWidth": -7}})";
  auto v = open();
  ASSERT_TRUE(v);
  ASSERT_TRUE(v->autosaveOffered());
  v->answerAutosave(true);
  EXPECT_NE(v->status().find("cannot restore the kept edits"), std::string::npos) << v->status();
  EXPECT_NE(v->status().find("/style/outlineWidth"), std::string::npos) << v->status();
  EXPECT_FALSE(v->unsaved());
  EXPECT_TRUE(fs::exists(kept));
  v.reset();  // one viewer at a time: ImGui's GLFW backend reads the current context
  fs::remove(kept);
  fs::create_directories(kept);
  v = open();
  ASSERT_TRUE(v);
  EXPECT_FALSE(v->autosaveOffered());
  EXPECT_NE(v->status().find("it is not a file"), std::string::npos) << v->status();
}

// The scene file changed on disk while edits are unsaved: asked, not reloaded over them.
TEST_F(PuffviewKeep, AChangeOnDiskDoesNotReloadOverUnsavedEdits) {
  PUFFVIEW_NEEDS_DISPLAY();
  auto v = open();
  ASSERT_TRUE(v);
  edit(*v, {0.5f, 0.25f, 0.0f});
  frame(*v);
  ASSERT_TRUE(fs::exists(v->autosavePath()));
  auto rewrite = [&](const std::string& background) {
    const auto before = fs::last_write_time(file_);
    std::string text = onDisk();
    text.replace(text.find("#ffffff"), 7, background);
    std::ofstream(file_, std::ios::trunc) << text;
    fs::last_write_time(file_, before + std::chrono::seconds(1));
  };
  rewrite("#00ff00");
  v->checkFiles();
  EXPECT_TRUE(v->diskChangePrompt());
  EXPECT_EQ(v->scene().background, glm::vec3(0.5f, 0.25f, 0.0f)) << "the edits stay";
  EXPECT_TRUE(fs::exists(v->autosavePath())) << "and are still kept";
  v->answerDiskChange(false);
  EXPECT_FALSE(v->diskChangePrompt());
  EXPECT_TRUE(v->unsaved());
  // Reload it instead: the file's scene, the edits one undo away.
  edit(*v, {0.25f, 0.25f, 0.25f});
  const std::string green = onDisk();
  std::ofstream(file_, std::ios::trunc) << green;
  fs::last_write_time(file_, fs::last_write_time(file_) + std::chrono::seconds(2));
  v->checkFiles();
  ASSERT_TRUE(v->diskChangePrompt());
  v->answerDiskChange(true);
  EXPECT_EQ(v->scene().background, glm::vec3(0.0f, 1.0f, 0.0f));
  EXPECT_FALSE(v->unsaved());
  ASSERT_TRUE(v->undo());
  EXPECT_EQ(v->scene().background, glm::vec3(0.25f, 0.25f, 0.25f));

  // Save as: the edits kept under the old name are saved, and their autosave goes.
  frame(*v);
  const fs::path kept = v->autosavePath();
  ASSERT_TRUE(fs::exists(kept));
  ASSERT_OK(v->save(dir_ / "copy.json"));
  EXPECT_FALSE(fs::exists(kept));
  EXPECT_FALSE(fs::exists(v->autosavePath()));
}

// The panel never holds what the file would refuse: such an edit is not applied, the scene goes
// back, and the window says why.
TEST_F(PuffviewKeep, AnEditTheFileWouldRefuseChangesNothing) {
  PUFFVIEW_NEEDS_DISPLAY();
  std::ofstream(file_) << R"({"output": {"width": 96, "height": 72, "background": "#ffffff"},
    "media": {"style": "cartoon", "particles": [{"position": [0, 0, 0], "radius": 1, "material": "fire"}]}})";
  auto v = open(3600.0);
  ASSERT_TRUE(v);
  edit(*v, {0.5f, 0.25f, 0.0f});
  const puff::scene::Scene before = v->scene();
  struct Case {
    const char* what;
    std::function<void(puff::scene::Scene&)> change;
    std::string error;
  };
  for (const Case& c : std::vector<Case>{
           {"motion blur on cartoon media", [](auto& s) { s.media->motionBlurFrames = 2; },
            "/media/motionBlur: motion blur blends whole frames"},
           {"a negative outline", [](auto& s) { s.style.outlineWidth = -2.0f; }, "/style/outlineWidth: expected"},
           {"a loop with an orbit", [](auto& s) { s.animation.period = 24, s.animation.orbitDegreesPerSecond = 5.0f; },
            "/animation/orbit: a camera that orbits"},
       }) {
    SCOPED_TRACE(c.what);
    v->beginEdit();
    c.change(v->scene());
    auto refused = v->applyEdit();
    v->endEdit();
    ASSERT_FALSE(refused);
    EXPECT_NE(v->editError().find(c.error), std::string::npos) << v->editError();
    EXPECT_TRUE(v->scene() == before) << "the scene is as it was before the edit";
    frame(*v);
    // The next edit the file takes clears the error.
    edit(*v, {0.5f, 0.25f, 0.0f});
    EXPECT_EQ(v->editError(), "");
  }
  EXPECT_TRUE(v->save());
  EXPECT_EQ(puff::scene::loadScene(file_, PUFF_ART_DIR)->media->motionBlurFrames, 0);
}

// A save keeps the artist's file: the value the edit changed is rewritten where it stands, and the
// rest stays byte for byte (order, spacing, "#ffffff", defaults left out), save after save and on
// a Save as; an edited ramp is named at the end of the file.
TEST_F(PuffviewKeep, ASaveChangesTheFileOnlyWhereTheSceneChanged) {
  PUFFVIEW_NEEDS_DISPLAY();
  const std::string original = onDisk();
  const std::string head = original.substr(0, original.find("\"#ffffff\"")),
                    tail = original.substr(head.size() + std::string("\"#ffffff\"").size());
  auto v = open(3600.0);
  ASSERT_TRUE(v);
  // The saved text is the file's own but for the background's value, which reads back as edited.
  auto expectOnlyTheBackground = [&](const fs::path& file, const nlohmann::json& value) {
    const std::string saved = *puff::core::readFileBytes(file);
    ASSERT_EQ(saved.substr(0, head.size()), head) << saved;
    ASSERT_GE(saved.size(), head.size() + tail.size()) << saved;
    ASSERT_EQ(saved.substr(saved.size() - tail.size()), tail) << saved;
    EXPECT_EQ(nlohmann::json::parse(saved.substr(head.size(), saved.size() - head.size() - tail.size())), value);
  };
  edit(*v, {0.5f, 0.25f, 0.0f});
  ASSERT_OK(v->save());
  expectOnlyTheBackground(file_, {0.5, 0.25, 0});
  edit(*v, {0.25f, 0.25f, 0.25f});
  ASSERT_OK(v->save());
  expectOnlyTheBackground(file_, {0.25, 0.25, 0.25});
  fs::create_directories(dir_ / "elsewhere");
  edit(*v, {1.0f, 0.5f, 0.0f});
  ASSERT_OK(v->save(dir_ / "elsewhere" / "cloud.json"));
  expectOnlyTheBackground(dir_ / "elsewhere" / "cloud.json", {1, 0.5, 0});
  // A field the file left out comes at the end of its object, on a line of its own as the others are.
  editRamp(*v);
  ASSERT_OK(v->save());
  const std::string saved = *puff::core::readFileBytes(dir_ / "elsewhere" / "cloud.json");
  EXPECT_NE(saved.find("\"radius\": 0.7}],\n      \"ramp\": {\"image\": \"cloud_ramp.png\""), std::string::npos)
      << saved;
  EXPECT_EQ(puff::scene::loadScene(dir_ / "elsewhere" / "cloud.json", PUFF_ART_DIR)->ramp,
            dir_ / "elsewhere" / "cloud_ramp.png");
}

// A field the file leaves out reads back as its default, which may follow a field the edit changed:
// a style whose preset changed and whose shading was set back to the old preset's is saved with
// the shading written out, so that it reads back as edited.
TEST_F(PuffviewKeep, AFieldLeftOutIsWrittenWhereItWouldReadBackOtherwise) {
  PUFFVIEW_NEEDS_DISPLAY();
  std::ofstream(file_) << R"({"output": {"width": 96, "height": 72}, "atlas": "${PUFF_ART}/default/puff.json",
  "style": {"preset": "cel"}, "particles": [{"position": [0, 0, 0], "size": 1}]})";
  auto v = open(3600.0);
  ASSERT_TRUE(v);
  ASSERT_TRUE(v->scene().style.shading);
  v->beginEdit();
  v->scene().stylePreset = "outlines";
  v->scene().style = *puff::scene::stylePreset("outlines");
  v->scene().style.shading = true;
  v->endEdit();
  ASSERT_OK(v->applyEdit());
  ASSERT_OK(v->save());
  const std::string saved = onDisk();
  EXPECT_NE(saved.find("\"style\": {\"preset\": \"outlines\", \"shading\": "), std::string::npos) << saved;
  auto back = puff::scene::loadScene(file_, PUFF_ART_DIR);
  ASSERT_OK(back);
  EXPECT_TRUE(back->style.shading);
  EXPECT_EQ(back->stylePreset, "outlines");
}

}  // namespace
