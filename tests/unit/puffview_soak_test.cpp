// puffview stays up: one viewer process reloads an edited scene from disk over and over, every
// other version broken (a half-written save), takes panel edits (saved) between them, and draws frames all
// the while; its resident memory stays flat after the first 100 frames (within 5%) and it holds no
// more GL objects of any kind it makes at the end than after the first 30 reloads (the same scene
// shown).
//
// The suite runs a sample (200 reloads, 1,000 frames); PUFF_SOAK_RELOADS and PUFF_SOAK_FRAMES set
// the counts, and tests/soak/puffview_soak.sh runs it whole (2,000 reloads, 10,000 frames). Opens a
// window: ctest runs it under Xvfb (PuffviewUnderXvfb); without a display it skips.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include <puff/gl_api.h>
#include <puffview/viewer.h>

#include "puffview_test_helpers.h"
#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;

// The count an environment variable names, else `fallback`.
int countFrom(const char* name, int fallback) {
  const char* v = std::getenv(name);
  if (v == nullptr || *v == '\0') return fallback;
  return std::max(1, std::atoi(v));
}

// Resident memory, bytes (/proc/self/statm's second field, in pages).
std::size_t residentBytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

// The kinds of GL object the renderers and the panels make.
constexpr const char* kKinds[] = {"textures",      "buffers",  "framebuffers", "renderbuffers",
                                  "vertex arrays", "programs", "shaders"};
constexpr std::size_t kKindCount = std::size(kKinds);

// How many objects of each kind live in the context now: each name that names one (glIs*), from 1 to
// well past the next name the GL hands out. (The next name alone is no count: Mesa need not hand a
// deleted vertex array's name out again, and Dear ImGui makes and deletes one every frame.)
std::array<int, kKindCount> liveObjects() {
  GLuint next = 0, name = 0;
  glGenTextures(1, &name), glDeleteTextures(1, &name), next = std::max(next, name);
  glGenBuffers(1, &name), glDeleteBuffers(1, &name), next = std::max(next, name);
  glGenFramebuffers(1, &name), glDeleteFramebuffers(1, &name), next = std::max(next, name);
  glGenRenderbuffers(1, &name), glDeleteRenderbuffers(1, &name), next = std::max(next, name);
  glGenVertexArrays(1, &name), glDeleteVertexArrays(1, &name), next = std::max(next, name);
  name = glCreateProgram(), glDeleteProgram(name), next = std::max(next, name);
  std::array<int, kKindCount> live{};
  for (GLuint n = 1; n < next + 4096; ++n) {
    live[0] += glIsTexture(n) == GL_TRUE;
    live[1] += glIsBuffer(n) == GL_TRUE;
    live[2] += glIsFramebuffer(n) == GL_TRUE;
    live[3] += glIsRenderbuffer(n) == GL_TRUE;
    live[4] += glIsVertexArray(n) == GL_TRUE;
    live[5] += glIsProgram(n) == GL_TRUE;
    live[6] += glIsShader(n) == GL_TRUE;
  }
  return live;
}

class PuffviewSoak : public ::testing::Test {
 protected:
  // A cloud of puffs; `variant` moves the background, the count and the seed (a new scene to load),
  // and every so often the samples and the shadows (new targets and passes for the renderer).
  static std::string scene(int variant) {
    static const char* kBackgrounds[] = {"#ff0000", "#00ff00", "#0000ff", "#808080"};
    static const char* kShadows[] = {"false", "true, \"shadowMethod\": \"map\"", "true, \"shadowMethod\": \"volumes\""};
    return std::string(R"({"output": {"width": 96, "height": 72, "samples": )") + (variant % 5 == 0 ? "4" : "1") +
           R"(, "background": ")" + kBackgrounds[variant % 4] +
           R"("}, "atlas": "${PUFF_ART}/default/puff.json", "animation": {"frames": 48},
               "style": {"shadows": )" +
           kShadows[variant % 3] + R"(}, "emitters": [{"count": )" + std::to_string(20 + variant % 7) +
           R"(, "seed": )" + std::to_string(variant % 5) + R"(, "radius": 0.7, "sizeMin": 0.6, "sizeMax": 0.9}]})";
  }
  // Writes `text` and moves the file's time on by a second from the last, so every change is seen.
  void rewrite(const fs::path& file, const std::string& text) {
    std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
    stamp_ += std::chrono::seconds(1);
    fs::last_write_time(file, stamp_);
  }

  puff::test::ScopedTempDir dir_{"puffview-soak"};
  fs::file_time_type stamp_ = fs::file_time_type::clock::now();
};

TEST_F(PuffviewSoak, ReloadsAndFramesKeepMemoryAndGlObjectsFlat) {
  PUFFVIEW_NEEDS_DISPLAY();
  const int reloads = countFrom("PUFF_SOAK_RELOADS", 200), frames = countFrom("PUFF_SOAK_FRAMES", 1000);
  constexpr int kSettle = 100;  // frames before the memory's baseline: caches and pools fill
  // Reloads before the objects' baseline: every good version's samples and shadows shown once (the
  // renderers keep what a setting made, such as a shadow map, for when it comes back).
  constexpr int kWarmReloads = 30;
  ASSERT_GT(frames, kSettle);
  ASSERT_GE(reloads, 2 * kWarmReloads) << "the objects are counted after the first " << kWarmReloads << " reloads";
  const fs::path file = dir_ / "soak.json";
  rewrite(file, scene(0));
  puff::view::ViewerOptions o;
  o.scene = file;
  o.artDir = PUFF_ART_DIR;
  o.width = 96;
  o.height = 72;
  o.ui = true;  // the panels and the error box are drawn too
  o.quiet = true;
  auto opened = puff::view::Viewer::open(o);
  ASSERT_OK(opened);
  puff::view::Viewer& v = **opened;

  std::size_t baseline = 0, most = 0;
  std::array<int, kKindCount> baseLive{}, lastLive{};
  std::size_t half = 0;
  int reloaded = 0, broken = 0, edits = 0, lastGood = 0, baseScene = -1, baseFrame = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    // Reloads spread over the frames: every other one a half-written save (the last good scene kept).
    const int due = static_cast<int>(static_cast<long long>(f + 1) * reloads / frames);
    while (reloaded < due) {
      const bool bad = reloaded % 2 == 1;
      rewrite(file, bad ? std::string("{\"output\": {\"background\": ") : scene(reloaded / 2));
      v.checkFiles();
      EXPECT_EQ(v.fileError().empty(), !bad) << "reload " << reloaded << ": " << v.fileError();
      broken += bad ? 1 : 0;
      if (!bad) lastGood = reloaded / 2;
      if (!bad && reloaded % 8 == 0) {  // an edit in the panel, saved, as an artist would between saves
        v.beginEdit();
        v.scene().style.outlineWidth = 1.0f + static_cast<float>(edits % 3);
        v.endEdit();
        EXPECT_OK(v.applyEdit());
        EXPECT_OK(v.save());
        EXPECT_FALSE(v.unsaved());
        ++edits;
      }
      ++reloaded;
    }
    v.processEvents();
    v.setFrame(f % 48);
    v.drawFrame();
    v.present();
    if (f + 1 == kSettle) {
      glFinish();
      baseline = residentBytes();
    }
    if (baseScene < 0 && reloaded >= kWarmReloads) {
      glFinish();
      baseLive = liveObjects();
      baseScene = lastGood;
      baseFrame = f + 1;
    }
    if (f + 1 > kSettle && (f + 1) % 50 == 0) most = std::max(most, residentBytes());
    if (f + 1 == frames / 2) half = residentBytes();
  }
  glFinish();
  most = std::max(most, residentBytes());
  // The objects counted with the scene the baseline showed: its samples and shadows.
  rewrite(file, scene(baseScene));
  v.checkFiles();
  EXPECT_EQ(v.fileError(), "");
  v.processEvents();
  v.drawFrame();
  v.present();
  glFinish();
  lastLive = liveObjects();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "soak: %d reloads (%d broken), %d edits, %d frames in %.1f s; resident %.1f MB after %d frames, "
      "%.1f MB half way, at most %.1f MB after\n",
      reloaded, broken, edits, frames, seconds, static_cast<double>(baseline) / 1048576.0, kSettle,
      static_cast<double>(half) / 1048576.0, static_cast<double>(most) / 1048576.0);
  EXPECT_EQ(reloaded, reloads);
  EXPECT_LE(static_cast<double>(most), 1.05 * static_cast<double>(baseline))
      << "resident memory grew from " << baseline << " to " << most << " bytes";
  for (std::size_t k = 0; k < kKindCount; ++k) {
    std::printf("soak: %s live after %d frames %d, at the end %d\n", kKinds[k], baseFrame, baseLive[k], lastLive[k]);
    EXPECT_LE(lastLive[k], baseLive[k]) << kKinds[k] << " live grew from " << baseLive[k] << " to " << lastLive[k];
  }
}

}  // namespace
