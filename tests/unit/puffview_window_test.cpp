// The viewer (puffview_lib) one displayed frame at a time: it reloads a scene or shader changed on
// disk and keeps the last good state when the file is broken, applies panel edits at once and saves
// them back, undoes and redoes them whole, docks the panel beside the image, shows an edited ramp and
// gradient, and switches render paths.
//
// These tests open a window: ctest runs them under Xvfb (PuffviewUnderXvfb, with
// PUFF_TEST_REQUIRE_GLFW=1); in the plain puff_tests run without DISPLAY they skip.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <glm/geometric.hpp>

#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/core/shader.h>
#include <puff/scene/read.h>
#include <puffview/ramp_edit.h>
#include <puffview/viewer.h>

#include "puffview_test_helpers.h"
#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using puff::core::Image;
using puff::view::test::rgb;
using puff::view::test::shareWithin;

void expectColor(const Image& image, int x, int y, glm::vec3 expected, const char* what) {
  const glm::vec3 got = rgb(image, x, y);
  EXPECT_NEAR(got.r, expected.r, 1.5 / 255) << what << " at " << x << "," << y;
  EXPECT_NEAR(got.g, expected.g, 1.5 / 255) << what << " at " << x << "," << y;
  EXPECT_NEAR(got.b, expected.b, 1.5 / 255) << what << " at " << x << "," << y;
}

// Pixels of `image` within `tolerance` (RGB distance) of `color`.
int pixelsNear(const Image& image, glm::vec3 color, float tolerance = 0.05f) {
  int n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) n += glm::length(rgb(image, x, y) - color) < tolerance ? 1 : 0;
  return n;
}

// Share of the puffs' inner pixels (the pixel and its 4 neighbours far from `background` in `a`,
// so antialiased edges, which mix in the background, do not count) that are the same in `b`.
double samePuffs(const Image& a, const Image& b, glm::vec3 background, int maxX = 1 << 30, int maxY = 1 << 30) {
  auto far = [&](int x, int y) { return glm::length(rgb(a, x, y) - background) > 0.3f; };
  std::size_t inner = 0, same = 0;
  for (int y = 1; y + 1 < a.height; ++y) {
    for (int x = 1; x + 1 < a.width; ++x) {
      if (x < maxX && y >= maxY) continue;  // the error box's corner
      if (!(far(x, y) && far(x - 1, y) && far(x + 1, y) && far(x, y - 1) && far(x, y + 1))) continue;
      ++inner;
      same += glm::length(rgb(a, x, y) - rgb(b, x, y)) < 2.0f / 255 ? 1 : 0;
    }
  }
  EXPECT_GT(inner, 200u) << "the puffs cover part of the image";
  return inner ? static_cast<double>(same) / static_cast<double>(inner) : 0.0;
}

class PuffviewWindow : public ::testing::Test {
 protected:
  void TearDown() override { puff::core::setShaderDir({}); }

  // A red-backed cloud of 30 puffs in front of the default camera.
  static std::string scene(const std::string& background) {
    return R"({"output": {"width": 160, "height": 120, "background": ")" + background +
           R"("}, "atlas": "${PUFF_ART}/default/puff.json",
               "emitters": [{"count": 30, "seed": 3, "radius": 0.7, "sizeMin": 0.6, "sizeMax": 0.9}]})";
  }
  // Writes `text` and moves the file's time on by a second, so the change is seen even where the
  // file system's clock is coarse.
  void rewrite(const fs::path& file, const std::string& text) {
    const auto before = fs::exists(file) ? fs::last_write_time(file) : fs::file_time_type::clock::now();
    std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
    fs::last_write_time(file, before + std::chrono::seconds(1));
  }
  // A small quiet window without panels.
  static puff::view::ViewerOptions options(const fs::path& file, const fs::path& shaderDir = {},
                                           const std::string& path = "cel") {
    puff::view::ViewerOptions o;
    o.scene = file;
    o.artDir = PUFF_ART_DIR;
    o.shaderDir = shaderDir;
    o.path = path;
    o.width = 160;
    o.height = 120;
    o.ui = false;
    o.quiet = true;
    return o;
  }
  std::unique_ptr<puff::view::Viewer> open(const fs::path& file, const fs::path& shaderDir = {},
                                           const std::string& path = "cel") {
    auto v = puff::view::Viewer::open(options(file, shaderDir, path));
    EXPECT_OK(v);
    return v ? std::move(*v) : nullptr;
  }
  Image draw(puff::view::Viewer& v) {
    v.processEvents();
    v.drawFrame();
    auto image = v.readWindow();
    EXPECT_OK(image);
    v.present();
    return image ? *image : Image{};
  }

  puff::test::ScopedTempDir dir_{"puffview"};
};

TEST_F(PuffviewWindow, SceneFileChangeReloadsAndABrokenFileKeepsTheLastGoodState) {
  PUFFVIEW_NEEDS_DISPLAY();
  const fs::path file = dir_ / "cloud.json";
  rewrite(file, scene("#ff0000"));
  auto v = open(file);
  ASSERT_TRUE(v);
  Image first = draw(*v);
  ASSERT_EQ(first.width, 160);
  ASSERT_EQ(first.height, 120);
  expectColor(first, 2, 2, {1, 0, 0}, "background");

  v->checkFiles();  // nothing changed yet
  EXPECT_EQ(v->fileError(), "");

  rewrite(file, scene("#0000ff"));
  v->checkFiles();
  EXPECT_EQ(v->fileError(), "");
  Image blue = draw(*v);
  expectColor(blue, 2, 2, {0, 0, 1}, "background after the file changed");
  EXPECT_GE(samePuffs(first, blue, {1, 0, 0}), 0.99) << "the same puffs";

  // An editor's half-written save: the error is shown, the last good state still drawn.
  rewrite(file, "{\"output\": {\"background\": ");
  v->checkFiles();
  EXPECT_NE(v->fileError().find(file.string()), std::string::npos) << v->fileError();
  draw(*v);  // Dear ImGui sizes a new auto-sized window on its first frame and shows it on the second
  Image kept = draw(*v);
  expectColor(kept, 157, 2, {0, 0, 1}, "last good background (top right, away from the error box)");
  // The error box covers at most the bottom-left 60% x 50%, inside an 8-pixel margin.
  EXPECT_GE(samePuffs(first, kept, {1, 0, 0}, 100, 48), 0.99) << "the last good puffs";
  EXPECT_NE(rgb(kept, 10, 110), glm::vec3(0, 0, 1)) << "the error box is drawn bottom-left";

  // The file vanishes for a moment (delete + create): an error, then the new version loads.
  fs::remove(file);
  v->checkFiles();
  EXPECT_NE(v->fileError(), "");
  rewrite(file, scene("#00ff00"));
  v->checkFiles();
  EXPECT_EQ(v->fileError(), "");
  expectColor(draw(*v), 2, 2, {0, 1, 0}, "background once the file is good again");
}

TEST_F(PuffviewWindow, PanelEditsShowAtOnceAndSaveRoundTrips) {
  PUFFVIEW_NEEDS_DISPLAY();
  const fs::path file = dir_ / "cloud.json";
  rewrite(file, scene("#ffffff"));
  auto v = open(file);
  ASSERT_TRUE(v);
  const Image before = draw(*v);
  EXPECT_GT(pixelsNear(before, {0, 0, 0}), 20) << "black outlines are drawn";
  EXPECT_EQ(pixelsNear(before, {0, 1, 0}), 0);

  // What a slider does: edit the scene, apply, and the next frame shows it (no reload, no file).
  v->scene().style.outlineColor = glm::vec3(0.0f, 1.0f, 0.0f);
  v->scene().background = glm::vec3(0.5f, 0.25f, 0.0f);
  ASSERT_TRUE(v->applyEdit());
  const Image edited = draw(*v);
  EXPECT_GT(pixelsNear(edited, {0, 1, 0}), 20) << "green outlines";
  EXPECT_LT(pixelsNear(edited, {0, 0, 0}), pixelsNear(before, {0, 0, 0}) / 4) << "no black ones left";
  expectColor(edited, 2, 2, {0.5f, 0.25f, 0.0f}, "edited background");

  auto saved = v->save();
  ASSERT_OK(saved);
  EXPECT_EQ(*saved, file);
  auto reloaded = puff::scene::loadScene(file, PUFF_ART_DIR);
  ASSERT_OK(reloaded);
  EXPECT_EQ(reloaded->style.outlineColor, glm::vec3(0.0f, 1.0f, 0.0f));
  EXPECT_EQ(reloaded->background, glm::vec3(0.5f, 0.25f, 0.0f));
  const std::string text = *puff::core::readFileBytes(file);
  EXPECT_NE(text.find("\"${PUFF_ART}/default/puff.json\""), std::string::npos) << "art paths stay portable:\n" << text;
  v->checkFiles();
  EXPECT_EQ(v->status(), "saved " + file.string()) << "our own save is not reloaded as an outside change";

  // Save as: the new file becomes the scene file.
  const fs::path copy = dir_ / "sub" / "copy.json";
  fs::create_directories(copy.parent_path());
  ASSERT_TRUE(v->save(copy));
  EXPECT_EQ(v->sceneFile(), copy);
  auto copied = puff::scene::loadScene(copy, PUFF_ART_DIR);
  ASSERT_OK(copied);
  EXPECT_EQ(copied->style.outlineColor, glm::vec3(0.0f, 1.0f, 0.0f));

  // An edit the renderer refuses keeps the last good state and says why.
  v->scene().atlas = dir_ / "no-such-atlas.json";
  EXPECT_FALSE(v->applyEdit());
  EXPECT_NE(v->editError().find("no-such-atlas.json"), std::string::npos) << v->editError();
  expectColor(draw(*v), 157, 2, {0.5f, 0.25f, 0.0f}, "last good state");
  // ... and Save refuses to write it (the file would not load), leaving the file as it was.
  const std::string beforeRefusal = *puff::core::readFileBytes(copy);
  auto refused = v->save();
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("not saved"), std::string::npos) << refused.error().message;
  EXPECT_EQ(*puff::core::readFileBytes(copy), beforeRefusal);
}

// Undo and redo: every edit is one step however many changes make it (a drag), a change
// on disk is a step too, a new edit drops the steps undone, and the scene file stays where Save as
// put it.
TEST_F(PuffviewWindow, UndoAndRedoTakeEditsBackAndForthWhole) {
  PUFFVIEW_NEEDS_DISPLAY();
  const fs::path file = dir_ / "cloud.json";
  rewrite(file, scene("#ffffff"));
  auto v = open(file);
  ASSERT_TRUE(v);
  EXPECT_FALSE(v->canUndo());
  EXPECT_FALSE(v->undo());
  expectColor(draw(*v), 2, 2, {1, 1, 1}, "white to start");

  // Edit 1: the background, dragged through three values.
  v->beginEdit();
  for (float r : {0.2f, 0.4f, 0.6f}) {
    v->scene().background = glm::vec3(r, 0.0f, 0.0f);
    ASSERT_TRUE(v->applyEdit());
    v->beginEdit();  // called on every change of the drag: still one step
  }
  v->endEdit();
  // Edit 2: the outline width.
  v->beginEdit();
  v->scene().style.outlineWidth = 7.0f;
  ASSERT_TRUE(v->applyEdit());
  v->endEdit();
  expectColor(draw(*v), 2, 2, {0.6f, 0, 0}, "after the drag");

  ASSERT_TRUE(v->undo());
  EXPECT_NE(v->scene().style.outlineWidth, 7.0f);
  EXPECT_EQ(v->scene().background, glm::vec3(0.6f, 0.0f, 0.0f)) << "only the last edit is taken back";
  ASSERT_TRUE(v->undo());
  EXPECT_EQ(v->scene().background, glm::vec3(1.0f)) << "the whole drag at once";
  expectColor(draw(*v), 2, 2, {1, 1, 1}, "drawn as undone");
  EXPECT_FALSE(v->canUndo());
  ASSERT_TRUE(v->redo());
  EXPECT_EQ(v->scene().background, glm::vec3(0.6f, 0.0f, 0.0f));
  expectColor(draw(*v), 2, 2, {0.6f, 0, 0}, "drawn as redone");
  ASSERT_TRUE(v->redo());
  EXPECT_EQ(v->scene().style.outlineWidth, 7.0f);
  EXPECT_FALSE(v->redo());

  // A new edit after an undo drops what was undone.
  ASSERT_TRUE(v->undo());
  EXPECT_TRUE(v->canRedo());
  v->beginEdit();
  v->scene().style.outlineColor = glm::vec3(0.0f, 0.0f, 1.0f);
  ASSERT_TRUE(v->applyEdit());
  v->endEdit();
  EXPECT_FALSE(v->canRedo());

  // A change on disk is undone like an edit; the file saved elsewhere stays the scene file.
  rewrite(file, scene("#00ff00"));
  v->checkFiles();
  ASSERT_TRUE(v->diskChangePrompt()) << "the edits are unsaved: asked before reloading";
  v->answerDiskChange(true);
  ASSERT_EQ(v->fileError(), "");
  EXPECT_EQ(v->scene().background, glm::vec3(0.0f, 1.0f, 0.0f));
  const fs::path copy = dir_ / "copy.json";
  ASSERT_TRUE(v->save(copy));
  ASSERT_TRUE(v->undo());
  EXPECT_EQ(v->scene().style.outlineColor, glm::vec3(0.0f, 0.0f, 1.0f)) << "the panel edit before the reload";
  EXPECT_EQ(v->scene().background, glm::vec3(0.6f, 0.0f, 0.0f));
  EXPECT_EQ(v->sceneFile(), copy);
  expectColor(draw(*v), 2, 2, {0.6f, 0, 0}, "the reload taken back");
}

// The panel docks beside the image: the window is the image plus the panel's width, at
// least the panel's height, and the image is drawn whole beside the panel, the same pixels as
// without the panels; hiding the panels gives the image the window.
TEST_F(PuffviewWindow, ThePanelDocksBesideTheImageNotOverIt) {
  PUFFVIEW_NEEDS_DISPLAY();
  const fs::path file = dir_ / "cloud.json";
  rewrite(file, scene("#ff0000"));
  auto bare = open(file);
  ASSERT_TRUE(bare);
  const Image alone = draw(*bare);
  const std::string path = bare->pathName();
  bare.reset();

  puff::view::ViewerOptions o = options(file);
  o.ui = true;
  auto opened = puff::view::Viewer::open(o);
  ASSERT_OK(opened);
  puff::view::Viewer& v = **opened;
  // A window that could not be opened for GL 4.5 at that moment falls back to the fixed path (seen
  // once under Xvfb: "Failed to open display" right after the other window closed); the comparison
  // is between the same path's images.
  if (v.pathName() != path) {
    ASSERT_OK(v.setPath(path));
  }
  draw(v);
  const Image docked = draw(v);
  ASSERT_EQ(docked.width, 160 + puff::view::kPanelWidth);
  ASSERT_EQ(docked.height, puff::view::kPanelMinHeight);
  const puff::cel::Viewport area = v.imageViewport();
  EXPECT_EQ(area.x, 0);
  EXPECT_EQ(area.width, 160);
  EXPECT_EQ(area.height, 120);
  EXPECT_EQ(area.y, (puff::view::kPanelMinHeight - 120) / 2) << "centred beside the panel";
  const int top = docked.height - area.y - area.height;  // readWindow's rows run top to bottom
  int differ = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x)
      differ += glm::length(rgb(docked, x, top + y) - rgb(alone, x, y)) > 2.0f / 255.0f ? 1 : 0;
  EXPECT_EQ(differ, 0) << "the image beside the panel is the image without it";
  // Above the image, a plain bar; right of it, the panel (not the red background).
  expectColor(docked, 80, top / 2, {0.11f, 0.11f, 0.12f}, "the bar above the image");
  int red = 0;
  for (int y = 0; y < docked.height; ++y)
    for (int x = 160; x < docked.width; ++x) red += glm::length(rgb(docked, x, y) - glm::vec3(1, 0, 0)) < 0.1f ? 1 : 0;
  EXPECT_EQ(red, 0) << "nothing of the image under the panel";

  // Panels hidden: the image fills the window at its own aspect.
  v.uiVisible = false;
  const puff::cel::Viewport full = v.imageViewport();
  EXPECT_EQ(full.width, 560);
  EXPECT_EQ(full.height, 420);
  EXPECT_EQ(full.y, 30);

  // A tall image: beside the panel it keeps its size (the area is as wide as it), centred up and
  // down; with the panels hidden it grows to the window's height, centred across with bars on
  // both sides.
  o.width = 60;
  o.height = 120;
  opened = puff::view::Viewer::open(o);
  ASSERT_OK(opened);
  EXPECT_EQ((*opened)->framebufferSize(), glm::ivec2(60 + puff::view::kPanelWidth, puff::view::kPanelMinHeight));
  const puff::cel::Viewport tall = (*opened)->imageViewport();
  EXPECT_EQ(tall.x, 0);
  EXPECT_EQ(tall.width, 60);
  EXPECT_EQ(tall.height, 120);
  EXPECT_EQ(tall.y, (puff::view::kPanelMinHeight - 120) / 2);
  (*opened)->uiVisible = false;
  const puff::cel::Viewport pillar = (*opened)->imageViewport();
  EXPECT_EQ(pillar.height, puff::view::kPanelMinHeight);
  EXPECT_EQ(pillar.width, 240) << "60x120 fitted into 460x480";
  EXPECT_EQ(pillar.x, (60 + puff::view::kPanelWidth - 240) / 2) << "centred across";
  EXPECT_EQ(pillar.y, 0);
}

// The ramp and gradient editors: an edited ramp shows in the next frame, undo takes it
// back, and Save writes it beside the scene file and names it there.
TEST_F(PuffviewWindow, AnEditedRampShowsAtOnceAndIsSavedBesideTheScene) {
  PUFFVIEW_NEEDS_DISPLAY();
  const fs::path file = dir_ / "cloud.json";
  rewrite(file, scene("#ffffff"));
  auto v = open(file);
  ASSERT_TRUE(v);
  const auto share = [](const Image& image, glm::vec3 color) { return pixelsNear(image, color, 0.08f); };
  const Image before = draw(*v);
  // One flat band of pure red: q = (1, 0, 0) at every N.L, so a lit puff pixel is K_a + C K_L q with
  // white C and K_L: the ambient plus pure red, a colour the two-tone ramp never gives.
  puff::view::RampBands red;
  red.starts = {0.0f};
  red.colors = {{1.0f, 0.0f, 0.0f}};
  v->beginEdit();
  ASSERT_OK(v->setRamp(puff::view::rampImage(red)));
  v->endEdit();
  EXPECT_EQ(v->scene().ramp.parent_path(), v->scratchDir());
  const Image edited = draw(*v);
  const glm::vec3 ka = v->scene().ambientColor;
  const glm::vec3 lit = glm::min(ka + glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(1.0f));
  EXPECT_GT(share(edited, lit), 200) << "puffs lit through the red ramp";
  EXPECT_EQ(share(before, lit), 0);

  // The gradient (green at the top, blue at the bottom) replaces the uniform K_a under the puffs.
  v->beginEdit();
  ASSERT_OK(v->setAmbientGradient(puff::view::gradientImage({{0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}})));
  v->endEdit();
  const Image graded = draw(*v);
  EXPECT_NE(samePuffs(edited, graded, {1, 1, 1}), 1.0) << "the gradient changes the puffs";

  // Save: both beside the scene, named there, the same pixels.
  ASSERT_OK(v->save());
  EXPECT_EQ(v->scene().ramp, dir_ / "cloud_ramp.png");
  EXPECT_EQ(v->scene().ambientGradient, dir_ / "cloud_gradient.png");
  auto saved = puff::scene::loadScene(file, PUFF_ART_DIR);
  ASSERT_OK(saved);
  EXPECT_EQ(saved->ramp, dir_ / "cloud_ramp.png");
  auto rampFile = puff::core::readImage(dir_ / "cloud_ramp.png");
  ASSERT_OK(rampFile);
  EXPECT_EQ(rgb(*rampFile, 100, 0), glm::vec3(1.0f, 0.0f, 0.0f));
  const std::string text = *puff::core::readFileBytes(file);
  EXPECT_NE(text.find("cloud_ramp.png"), std::string::npos) << text;
  EXPECT_EQ(text.find(v->scratchDir().string()), std::string::npos) << "no scratch path in the saved scene";
  EXPECT_GE(samePuffs(graded, draw(*v), {1, 1, 1}), 0.99) << "the same frame from the saved files";

  // Undo twice: the built-in ramp and no gradient again.
  ASSERT_TRUE(v->undo());
  ASSERT_TRUE(v->undo());
  EXPECT_TRUE(v->scene().ramp.empty());
  EXPECT_TRUE(v->scene().ambientGradient.empty());
  EXPECT_GE(samePuffs(before, draw(*v), {1, 1, 1}), 0.99) << "drawn as before the edits";
  const fs::path scratch = v->scratchDir();
  v.reset();
  EXPECT_FALSE(fs::exists(scratch)) << "the scratch directory goes with the viewer";
}

TEST_F(PuffviewWindow, BrokenShaderShowsItsErrorAndKeepsTheLastGoodRenderer) {
  PUFFVIEW_NEEDS_DISPLAY();
  const fs::path shaders = dir_ / "shaders";
  fs::copy(fs::path(PUFF_SOURCE_DIR) / "shaders", shaders, fs::copy_options::recursive);
  const fs::path file = dir_ / "cloud.json";
  rewrite(file, scene("#ff0000"));
  auto v = open(file, shaders);
  ASSERT_TRUE(v);
  const Image good = draw(*v);

  const fs::path frag = shaders / "cel" / "nailboard.frag";
  const std::string source = *puff::core::readFileBytes(frag);
  rewrite(frag, source + "\nthis is not glsl;\n");
  v->checkFiles();
  EXPECT_NE(v->fileError().find("cel/nailboard.frag"), std::string::npos) << v->fileError();
  draw(*v);  // the error box appears on the second frame
  const Image kept = draw(*v);
  EXPECT_GE(samePuffs(good, kept, {1, 0, 0}, 100, 48), 0.99) << "still drawing with the old programs";

  rewrite(frag, source);
  v->checkFiles();
  EXPECT_EQ(v->fileError(), "");
  EXPECT_GE(shareWithin(draw(*v), good, 0), 0.999);
}

TEST_F(PuffviewWindow, SwitchingPathsRedrawsAndSwitchingBackRestoresCel) {
  PUFFVIEW_NEEDS_DISPLAY();
  const fs::path file = dir_ / "cloud.json";
  rewrite(file, scene("#ff0000"));
  auto v = open(file);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->pathName(), "cel");
  const Image cel = draw(*v);

  ASSERT_TRUE(v->setPath("fixed"));
  EXPECT_EQ(v->pathName(), "fixed");
  const Image fixed = draw(*v);
  expectColor(fixed, 157, 2, {1, 0, 0}, "the fixed path's background");
  EXPECT_LT(shareWithin(fixed, cel, 2), 0.99) << "the fixed path draws other pixels";
  int puffPixels = 0;
  for (int y = 0; y < fixed.height; ++y)
    for (int x = 0; x < fixed.width; ++x) puffPixels += glm::length(rgb(fixed, x, y) - glm::vec3(1, 0, 0)) > 0.3f;
  EXPECT_GT(puffPixels, 500) << "the fixed path draws the puffs";

  // Edits reach whichever path draws.
  v->scene().background = glm::vec3(0.0f, 0.0f, 1.0f);
  ASSERT_TRUE(v->applyEdit());
  expectColor(draw(*v), 157, 2, {0, 0, 1}, "edited background on the fixed path");
  v->scene().background = glm::vec3(1.0f, 0.0f, 0.0f);
  ASSERT_TRUE(v->applyEdit());
  EXPECT_GE(shareWithin(draw(*v), fixed, 0), 0.999) << "the edit undone";

  // A path that does not exist keeps the one drawing and says why.
  auto bad = v->setPath("media");
  ASSERT_FALSE(bad);
  EXPECT_EQ(v->pathName(), "fixed");
  EXPECT_NE(v->status().find("media"), std::string::npos) << v->status();
  EXPECT_GE(shareWithin(draw(*v), fixed, 0), 0.999);

  ASSERT_TRUE(v->setPath("cel"));
  EXPECT_EQ(v->pathName(), "cel");
  EXPECT_GE(shareWithin(draw(*v), cel, 0), 0.999) << "back to the cel path's pixels";
}

TEST_F(PuffviewWindow, BrokenCelShaderAtStartIsAnErrorNamingTheShader) {
  PUFFVIEW_NEEDS_DISPLAY();
  const fs::path file = dir_ / "cloud.json";
  rewrite(file, scene("#ff0000"));
  const fs::path shaders = dir_ / "shaders";
  fs::copy(fs::path(PUFF_SOURCE_DIR) / "shaders", shaders, fs::copy_options::recursive);
  const fs::path frag = shaders / "cel" / "nailboard.frag";
  rewrite(frag, *puff::core::readFileBytes(frag) + "\nthis is not glsl;\n");
  auto v = puff::view::Viewer::open(options(file, shaders));
  ASSERT_FALSE(v.ok());
  EXPECT_NE(v.error().message.find("cel/nailboard.frag"), std::string::npos) << v.error().message;
  // (One line is the tool's business: PuffviewCli.BrokenCelShaderIsOneLineAndExitOne.)
}

}  // namespace
