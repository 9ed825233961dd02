// puffview stays up: one viewer process reloads an edited scene from disk over and over, every
// other version broken (a half-written save), takes panel edits (saved) between them, and draws frames all
// the while; its resident memory stays flat after the first 100 frames (within 5%) and it holds no
// more GL objects of any kind at the end than after those frames.
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

// How many objects of each kind the renderers make live in the context now: each name below the next
// one the GL hands out (and a margin past it) that names an object (glIs*). (The next name alone is
// no count: Mesa need not hand a deleted vertex array's name out again, and Dear ImGui makes and
// deletes one every frame.)
std::array<int, 5> liveObjects() {
  std::array<int, 5> live{};
  GLuint next[5] = {};
  glGenTextures(1, &next[0]);
  glDeleteTextures(1, &next[0]);
  glGenBuffers(1, &next[1]);
  glDeleteBuffers(1, &next[1]);
  glGenFramebuffers(1, &next[2]);
  glDeleteFramebuffers(1, &next[2]);
  glGenVertexArrays(1, &next[3]);
  glDeleteVertexArrays(1, &next[3]);
  next[4] = glCreateProgram();
  glDeleteProgram(next[4]);
  for (int k = 0; k < 5; ++k) {
    for (GLuint name = 1; name < next[k] + 256; ++name) {
      const GLboolean is = k == 0   ? glIsTexture(name)
                           : k == 1 ? glIsBuffer(name)
                           : k == 2 ? glIsFramebuffer(name)
                           : k == 3 ? glIsVertexArray(name)
                                    : glIsProgram(name);
      live[static_cast<std::size_t>(k)] += is == GL_TRUE ? 1 : 0;
    }
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
  constexpr int kSettle = 100;  // frames before the baseline: caches and pools fill
  ASSERT_GT(frames, kSettle);
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
  std::array<int, 5> baseLive{}, lastLive{};
  int reloaded = 0, broken = 0, edits = 0;
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
      baseLive = liveObjects();
    }
    if (f + 1 > kSettle && (f + 1) % 50 == 0) most = std::max(most, residentBytes());
  }
  glFinish();
  most = std::max(most, residentBytes());
  lastLive = liveObjects();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "soak: %d reloads (%d broken), %d edits, %d frames in %.1f s; resident %.1f MB after %d frames, "
      "at most %.1f MB after\n",
      reloaded, broken, edits, frames, seconds, static_cast<double>(baseline) / 1048576.0, kSettle,
      static_cast<double>(most) / 1048576.0);
  EXPECT_EQ(reloaded, reloads);
  EXPECT_LE(static_cast<double>(most), 1.05 * static_cast<double>(baseline))
      << "resident memory grew from " << baseline << " to " << most << " bytes";
  const char* kinds[] = {"textures", "buffers", "framebuffers", "vertex arrays", "programs"};
  for (std::size_t k = 0; k < lastLive.size(); ++k) {
    std::printf("soak: %s live after %d frames %d, at the end %d\n", kinds[k], kSettle, baseLive[k], lastLive[k]);
    EXPECT_LE(lastLive[k], baseLive[k]) << kinds[k] << " live grew from " << baseLive[k] << " to " << lastLive[k];
  }
}

}  // namespace
