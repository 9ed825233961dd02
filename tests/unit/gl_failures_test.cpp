// GL failures stay messages. No context, a context too old for GL 4.5, and a shader that
// does not compile each give puffbake and puffrender one line on stderr (puffview's no-display and
// broken-shader cases are in puffview_test.cpp), never a crash or a compiler log spread over
// several lines. puffrender's documented fallback to the fixed path for a context older than GL 4.5
// (without --path) still draws, and says why in one line.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <puff/cel/nailboards.h>
#include <puff/core/atlas.h>
#include <puff/core/files.h>
#include <puff/core/gl.h>
#include <puff/gl_api.h>
#include <puff/support/text.h>

#include "support/gl_fixture.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;

#if defined(__has_feature)  // Clang
#if __has_feature(address_sanitizer)
#define PUFF_TEST_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(PUFF_TEST_ASAN)  // PUFF_SANITIZE=ON
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif

struct ToolRun {
  int exitCode = -1;
  std::string err;
};

class GlFailures : public ::testing::Test {
 protected:
  // Runs `env exe args` with stdout discarded.
  ToolRun run(const std::string& env, const std::string& exe, const std::string& args) {
    const fs::path err = dir_ / "stderr.txt";
    const std::string cmd = "env " + env + " " + exe + " " + args + " >/dev/null 2>" + err.string();
    const int status = std::system(cmd.c_str());
    ToolRun r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.err = *puff::core::readFileBytes(err);
    return r;
  }
  static std::size_t lines(const std::string& s) {
    return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
  }
  // A copy of the shaders in which every fragment shader of `dir` ends in a line that is not GLSL.
  fs::path brokenShaders(const std::string& dir) {
    const fs::path shaders = dir_ / "shaders";
    fs::copy(fs::path(PUFF_SOURCE_DIR) / "shaders", shaders, fs::copy_options::recursive);
    for (const auto& e : fs::directory_iterator(shaders / dir)) {
      if (e.path().extension() == ".frag") std::ofstream(e.path(), std::ios::app) << "\nthis is not glsl;\n";
    }
    return shaders;
  }
  std::string bake() const { return "bake -g sphere -n 1 -s 32 --no-contact-sheet -o " + (dir_ / "baked").string(); }
  std::string render() const {
    // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on a chain of operator+.
    std::string args = PUFF_SOURCE_DIR;
    args += "/art/scenes/cloud-fig8a.json --art-dir ";
    args += PUFF_ART_DIR;
    args += " --width 64 --height 48 -o ";
    args += (dir_ / "out.png").string();
    return args;
  }
  puff::test::ScopedTempDir dir_{"puff_gl_failures"};
};

TEST_F(GlFailures, NoContextIsOneLineAndExitOne) {
  for (const std::string env : {"PUFF_GL=no-such-backend", "-u DISPLAY -u WAYLAND_DISPLAY PUFF_GL=glfw"}) {
    SCOPED_TRACE(env);
    const ToolRun b = run(env, PUFFBAKE_EXE, bake());
    EXPECT_EQ(b.exitCode, 1);
    EXPECT_EQ(b.err.rfind("puffbake: error: ", 0), 0u) << b.err;
    EXPECT_EQ(lines(b.err), 1u) << b.err;
    const ToolRun r = run(env, PUFFRENDER_EXE, render());
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.err.rfind("puffrender: error: ", 0), 0u) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out.png"));
  }
  // The same reason for both paths is said once.
  const ToolRun r = run("PUFF_GL=no-such-backend", PUFFRENDER_EXE, render());
  EXPECT_EQ(r.err,
            "puffrender: error: PUFF_GL: unknown GL backend \"no-such-backend\" (accepted: osmesa, egl, glfw)\n");
}

TEST_F(GlFailures, AContextTooOldIsOneLine) {
  // Mesa told to offer OpenGL 3.3 at most: puffbake needs 4.5 and stops; puffrender draws with the
  // fixed path and says why, each reason on one line.
  const ToolRun b = run("PUFF_GL=osmesa MESA_GL_VERSION_OVERRIDE=3.3", PUFFBAKE_EXE, bake());
  EXPECT_EQ(b.exitCode, 1);
  EXPECT_EQ(b.err.rfind("puffbake: error: osmesa: cannot create a 4.5 core context", 0), 0u) << b.err;
  EXPECT_EQ(lines(b.err), 1u) << b.err;
  const ToolRun r = run("PUFF_GL=osmesa MESA_GL_VERSION_OVERRIDE=3.3", PUFFRENDER_EXE, render());
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.err.rfind("puffrender: the programmable (cel) path cannot run here: osmesa: cannot create", 0), 0u)
      << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;  // why, and "; drawing with the fixed-function path"
}

TEST_F(GlFailures, AShaderThatDoesNotCompileIsOneLine) {
  // The compiler's log (two lines per error here) becomes one line naming the file.
  const fs::path shaders = brokenShaders("bake");
  const ToolRun b = run("PUFF_GL=osmesa", PUFFBAKE_EXE, bake() + " --shader-dir " + shaders.string());
  EXPECT_EQ(b.exitCode, 1);
  // Named where it is: under --shader-dir, a path the user can open.
  EXPECT_EQ(b.err.rfind("puffbake: error: " + (shaders / "bake").string() + "/", 0), 0u) << b.err;
  EXPECT_NE(b.err.find(".frag:"), std::string::npos) << b.err;
  EXPECT_EQ(lines(b.err), 1u) << b.err;
  EXPECT_FALSE(fs::exists(dir_ / "baked" / "puff.json"));
}

// An atlas larger than the GL's largest texture (one baked at 16384 texels drawn on a GPU that takes
// 8192) is one error that says what to do, not a blank texture. The atlas here claims twice
// llvmpipe's largest size over 1 x 1 maps: the check comes before anything is allocated.
// GL_OUT_OF_MEMORY from the same upload is reported the same way (OutOfMemoryInTheAtlasUploadIsOneError).
class GlLimits : public puff::test::GlTest {};

TEST_F(GlLimits, AnAtlasLargerThanTheLargestTextureIsOneError) {
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  ASSERT_GT(maxSize, 0);
  puff::core::Atlas atlas;
  puff::core::AtlasDesc& d = atlas.desc;
  d.width = d.height = d.cellSize = 2 * maxSize;
  d.columns = d.rows = 1;
  d.variations = d.views = 1;
  puff::core::AtlasCell cell;
  cell.rect = {0, 0, d.cellSize, d.cellSize};
  d.cells.push_back(cell);
  for (const char* map : {"normalDepth", "color"}) atlas.maps[map].push_back(puff::core::Image(1, 1, 4, 0.5f));
  atlas.maps["distance"].push_back(puff::core::Image(1, 1, 1, 0.5f));
  auto renderer = puff::cel::NailboardRenderer::create();
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  auto r = (*renderer)->setAtlas(atlas);
  ASSERT_FALSE(r.ok());
  const std::string size = std::to_string(2 * maxSize);
  EXPECT_EQ(r.error().message, "the atlas is " + size + "x" + size + " texels, more than this GL's largest texture (" +
                                   std::to_string(maxSize) + "): bake it with a smaller --size or fewer --views");
  EXPECT_EQ(puff::core::drainGlErrors(), "");
}

// A real GL_OUT_OF_MEMORY: llvmpipe allocates a texture's storage in the process's own memory, so an
// address-space limit (RLIMIT_AS) set just before setAtlas makes glTextureStorage2D fail. The atlas
// is 4096 x 4096 with one level: setAtlas first packs normalDepth and distance into a float copy
// (4 floats a texel, 256 MiB), then allocates the RGBA8 texture (64 MiB). The limit leaves room for
// the copy and half the texture. The colour map is never reached: 1 x 1 is enough. (The storage is
// checked on its own: unchecked, the failure goes unseen until converting the level throws
// std::bad_alloc.)
// The upload runs in a fresh process (EXPECT_EXIT, "threadsafe": this binary run again for this test
// alone, with its own GL context), so the limit and whatever fails under it stay there. The child
// writes setAtlas's message to stderr and exits 0 if setAtlas failed, 1 if it succeeded; an abort
// (std::bad_alloc, a crash in the driver) fails the test too.
TEST_F(GlLimits, OutOfMemoryInTheAtlasUploadIsOneError) {
  if (kAddressSanitizer) GTEST_SKIP() << "AddressSanitizer's shadow memory alone exceeds any address-space limit";
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  if (!renderer || std::string(renderer).find("llvmpipe") == std::string::npos) {
    GTEST_SKIP() << "texture memory is the process's own only on llvmpipe, not on " << (renderer ? renderer : "?");
  }
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  constexpr int kSize = 4096;
  const auto uploadUnderALimit = [] {
    puff::core::Atlas atlas;
    puff::core::AtlasDesc& d = atlas.desc;
    d.width = d.height = d.cellSize = d.contentSize = kSize;
    d.columns = d.rows = 1;
    d.variations = d.views = 1;
    puff::core::AtlasCell cell;
    cell.rect = {0, 0, kSize, kSize};
    d.cells.push_back(cell);
    atlas.maps["normalDepth"].push_back(puff::core::Image(kSize, kSize, 4, 0.5f));
    atlas.maps["distance"].push_back(puff::core::Image(kSize, kSize, 1, 0.5f));
    atlas.maps["color"].push_back(puff::core::Image(1, 1, 4, 0.5f));
    auto r = puff::cel::NailboardRenderer::create();
    if (!r.ok()) {
      std::fprintf(stderr, "NailboardRenderer::create: %s\n", r.error().message.c_str());
      std::_Exit(2);
    }
    glFinish();
    // What this process maps now (pages), plus the packed copy and half the texture.
    long pages = 0;
    if (std::FILE* f = std::fopen("/proc/self/statm", "r")) {
      if (std::fscanf(f, "%ld", &pages) != 1) pages = 0;
      std::fclose(f);
    }
    constexpr rlim_t kTexels = rlim_t{kSize} * kSize;
    rlimit limit{};
    getrlimit(RLIMIT_AS, &limit);
    limit.rlim_cur = static_cast<rlim_t>(pages) * static_cast<rlim_t>(sysconf(_SC_PAGESIZE)) +
                     kTexels * 4 * sizeof(float) + kTexels * 4 / 2;
    if (pages <= 0 || setrlimit(RLIMIT_AS, &limit) != 0) {
      std::fprintf(stderr, "cannot limit the address space\n");
      std::_Exit(2);
    }
    const auto result = (*r)->setAtlas(atlas);
    std::fprintf(stderr, "%s\n", result.ok() ? "setAtlas succeeded" : result.error().message.c_str());
    std::fflush(stderr);
    std::_Exit(result.ok() ? 1 : 0);
  };
  // One line that names the map, its size and the GL error, nothing else on stderr.
  EXPECT_EXIT(uploadUnderALimit(), ::testing::ExitedWithCode(0),
              "^cannot make the atlas normalDepth texture \\(4096x4096, 1 level\\): GL_OUT_OF_MEMORY\n$");
}

TEST(OneLine, JoinsLinesAndCountsWhatItLeavesOut) {
  using puff::core::oneLine;
  EXPECT_EQ(oneLine("a"), "a");
  EXPECT_EQ(oneLine("a\nb\r\n\n  \nc \n"), "a; b; c");
  EXPECT_EQ(oneLine("1\n2\n3\n4\n5\n6"), "1; 2; 3; 4 (and 2 more)");
  EXPECT_EQ(oneLine("1\n2\n3", 1), "1 (and 2 more)");
  EXPECT_EQ(oneLine(""), "");
}

}  // namespace
