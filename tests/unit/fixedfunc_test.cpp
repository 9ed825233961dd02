// puff::fixedfunc: the GL 1.x path in a host's context. GL 1.5 entry points only (against glad's
// GL 1.5 header), every GL call through the logging wrapper, host state restored, drawing into the
// host's frame, what it refuses, and a run in the oldest context OSMesa gives. What it draws, against
// analytic values: fixedfunc_draw_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <puff/gl_api.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <puff/core/image.h>
#include <puff/fixedfunc/renderer.h>
#include <puff/mesh/mesh.h>
#include <puff/platform/gl_context.h>

#include "fixedfunc_fixture.h"
#include "support/assert_ok.h"
#include "support/skip.h"

namespace puff::fixedfunc::test {
namespace {

/// Writes the current framebuffer to $PUFF_FIXEDFUNC_DUMP_DIR/NAME.png when that is set, for a look.
void dumpIfAsked(const std::string& name) {
  const char* dir = std::getenv("PUFF_FIXEDFUNC_DUMP_DIR");
  if (dir == nullptr) return;
  const std::vector<glm::vec4> px = readFramebuffer();
  core::Image image(kSize, kSize, 3);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      for (int c = 0; c < 3; ++c) image.at(x, kSize - 1 - y, c) = px[static_cast<std::size_t>(y) * kSize + x][c];
    }
  }
  EXPECT_TRUE(core::writeImage(std::filesystem::path(dir) / (name + ".png"), image, core::PixelType::kUInt8).ok());
}

// ---- 1. OpenGL 1.5 entry points only ------------------------------------------------------------

std::set<std::string> gl15EntryPoints() {
  std::ifstream in(PUFF_GL15_HEADER);
  std::set<std::string> names;
  const std::regex define(R"(^#define (gl[A-Z][A-Za-z0-9_]*) glad_gl[A-Za-z0-9_]*\s*$)");
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_match(line, m, define)) names.insert(m[1]);
  }
  return names;
}

/// A host frame: everything the path can draw (objects of both shadings, outlines, shading on).
void drawEverything(FixedRenderer& r) {
  FixedObject plane{
      mesh::makePlane(), glm::translate(glm::mat4(1.0f), {0, -1.5f, -6}), {0.5f, 0.7f, 0.4f}, ObjectShading::kCel};
  FixedObject ball{
      mesh::makeSphere(24), glm::translate(glm::mat4(1.0f), {1.5f, 0, -7}), {0.8f, 0.3f, 0.3f}, ObjectShading::kSmooth};
  FixedObject box{
      mesh::makeBox(), glm::translate(glm::mat4(1.0f), {-1.5f, 0, -7}), {0.3f, 0.3f, 0.8f}, ObjectShading::kCel};
  ASSERT_TRUE(r.setObjects({plane, ball, box}).ok());
  std::vector<Billboard> billboards;
  for (int i = 0; i < 8; ++i) billboards.push_back({{0.3f * i - 1.0f, 0.1f * i, -5.0f - 0.2f * i}, 0.8f, i});
  auto drawn = r.drawFrame(makeFrame(), billboards, FixedStyle{});
  ASSERT_OK(drawn);
  dumpIfAsked("fixedfunc-everything");
}

TEST_F(FixedFuncTest, CallsOnlyOpenGl15EntryPoints) {
  const std::set<std::string> allowed = gl15EntryPoints();
  ASSERT_GT(allowed.size(), 400u) << "could not read " << PUFF_GL15_HEADER;
  ASSERT_EQ(allowed.count("glBegin"), 1u);
  ASSERT_EQ(allowed.count("glCreateShader"), 0u);  // 2.0
  ASSERT_EQ(allowed.count("glBindFramebuffer"), 0u);

  std::vector<std::string> log;
  setCallLog(&log);
  {
    // A host buffer bound to GL_ARRAY_BUFFER makes the path unbind and rebind it (glBindBuffer, 1.5).
    GLuint buffer = 0;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    auto r = FixedRenderer::create(unitSphere(), 64);
    ASSERT_OK(r);
    ASSERT_TRUE((*r)->setRamp(twoToneRamp(0.3f, 0.9f)).ok());
    drawEverything(**r);
    r->reset();
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(1, &buffer);
  }
  setCallLog(nullptr);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

  ASSERT_FALSE(log.empty());
  std::set<std::string> used(log.begin(), log.end());
  for (const std::string& name : used)
    EXPECT_EQ(allowed.count(name), 1u) << name << " is not an OpenGL <= 1.5 function";
  // The heart of §4.4 went through the log.
  for (const char* name :
       {"glTexGeni", "glLoadMatrixf", "glCopyTexSubImage2D", "glTexImage1D", "glTexEnvi", "glAlphaFunc",
        "glDrawElements", "glDrawArrays", "glPushAttrib", "glPopClientAttrib", "glBindBuffer"}) {
    EXPECT_EQ(used.count(name), 1u) << name << " missing from the call log";
  }
}

/// Drops comments and string/char literals, keeping line breaks.
std::string stripCommentsAndStrings(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.compare(i, 2, "//") == 0) {
      while (i < s.size() && s[i] != '\n') ++i;
      if (i < s.size()) out += '\n';
    } else if (s.compare(i, 2, "/*") == 0) {
      i += 2;
      while (i + 1 < s.size() && s.compare(i, 2, "*/") != 0) {
        if (s[i] == '\n') out += '\n';
        ++i;
      }
      ++i;
    } else if (s[i] == '"' || s[i] == '\'') {
      const char quote = s[i++];
      while (i < s.size() && s[i] != quote) i += s[i] == '\\' ? 2 : 1;
      out += "\"\"";
    } else {
      out += s[i];
    }
  }
  return out;
}

TEST(FixedFuncSources, EveryGlCallGoesThroughTheLoggingWrapper) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(PUFF_SOURCE_DIR) / "fixedfunc";
  // A direct call: gl*( or glad_*( ; through the wrapper the name is an argument: FF_GL(glEnable, ...).
  const std::regex direct(R"(\b(gl[A-Z][A-Za-z0-9_]*|glad_[A-Za-z0-9_]+)\s*\()");
  const std::regex wrapped(R"(\bFF_GL\(\s*(gl[A-Z][A-Za-z0-9_]*)\s*[,)])");
  int files = 0, wrappedCalls = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const fs::path& p = entry.path();
    if (!entry.is_regular_file() || (p.extension() != ".cpp" && p.extension() != ".h")) continue;
    if (p.filename() == "gl_calls.h" || p.filename() == "gl_calls.cpp") continue;  // the door itself
    ++files;
    std::ifstream in(p);
    std::stringstream buffer;
    buffer << in.rdbuf();
    const std::string code = stripCommentsAndStrings(buffer.str());
    std::istringstream lines(code);
    std::string line;
    for (int n = 1; std::getline(lines, line); ++n) {
      for (std::sregex_iterator it(line.begin(), line.end(), direct), end; it != end; ++it) {
        ADD_FAILURE() << p.lexically_relative(PUFF_SOURCE_DIR).string() << ":" << n << ": " << (*it)[1]
                      << "( bypasses FF_GL";
      }
      wrappedCalls += static_cast<int>(
          std::distance(std::sregex_iterator(line.begin(), line.end(), wrapped), std::sregex_iterator()));
    }
  }
  EXPECT_GE(files, 2);
  EXPECT_GT(wrappedCalls, 50);  // the scan does see the path's calls
}

// ---- 2. host state restored ---------------------------------------------------------------------

/// Every piece of state a host may care about, by name. Reads with glGet only and puts back the
/// active texture unit it walks through.
std::map<std::string, std::vector<double>> captureState() {
  std::map<std::string, std::vector<double>> s;
  auto ints = [&](const char* name, GLenum e, int n) {
    std::array<GLint, 16> v{};
    glGetIntegerv(e, v.data());
    s[name] = std::vector<double>(v.begin(), v.begin() + n);
  };
  auto floats = [&](const char* name, GLenum e, int n) {
    std::array<GLfloat, 16> v{};
    glGetFloatv(e, v.data());
    s[name] = std::vector<double>(v.begin(), v.begin() + n);
  };
  auto enabled = [&](const char* name, GLenum e) { s[name] = {static_cast<double>(glIsEnabled(e))}; };
  ints("viewport", GL_VIEWPORT, 4);
  ints("scissor box", GL_SCISSOR_BOX, 4);
  floats("clear colour", GL_COLOR_CLEAR_VALUE, 4);
  floats("clear depth", GL_DEPTH_CLEAR_VALUE, 1);
  ints("blend src", GL_BLEND_SRC, 1);
  ints("blend dst", GL_BLEND_DST, 1);
  ints("depth func", GL_DEPTH_FUNC, 1);
  ints("depth mask", GL_DEPTH_WRITEMASK, 1);
  ints("colour mask", GL_COLOR_WRITEMASK, 4);
  ints("alpha func", GL_ALPHA_TEST_FUNC, 1);
  floats("alpha ref", GL_ALPHA_TEST_REF, 1);
  ints("cull face mode", GL_CULL_FACE_MODE, 1);
  ints("polygon mode", GL_POLYGON_MODE, 2);
  ints("shade model", GL_SHADE_MODEL, 1);
  ints("matrix mode", GL_MATRIX_MODE, 1);
  ints("active texture", GL_ACTIVE_TEXTURE, 1);
  ints("client active texture", GL_CLIENT_ACTIVE_TEXTURE, 1);
  ints("array buffer", GL_ARRAY_BUFFER_BINDING, 1);
  ints("unpack alignment", GL_UNPACK_ALIGNMENT, 1);
  ints("pack alignment", GL_PACK_ALIGNMENT, 1);
  floats("red scale", GL_RED_SCALE, 1);
  floats("current colour", GL_CURRENT_COLOR, 4);
  floats("light model ambient", GL_LIGHT_MODEL_AMBIENT, 4);
  floats("projection", GL_PROJECTION_MATRIX, 16);
  floats("modelview", GL_MODELVIEW_MATRIX, 16);
  ints("vertex array size", GL_VERTEX_ARRAY_SIZE, 1);
  ints("vertex array stride", GL_VERTEX_ARRAY_STRIDE, 1);
  for (auto [name, cap] : std::initializer_list<std::pair<const char*, GLenum>>{{"blend", GL_BLEND},
                                                                                {"depth test", GL_DEPTH_TEST},
                                                                                {"scissor test", GL_SCISSOR_TEST},
                                                                                {"alpha test", GL_ALPHA_TEST},
                                                                                {"cull face", GL_CULL_FACE},
                                                                                {"lighting", GL_LIGHTING},
                                                                                {"light0", GL_LIGHT0},
                                                                                {"light3", GL_LIGHT3},
                                                                                {"fog", GL_FOG},
                                                                                {"normalize", GL_NORMALIZE},
                                                                                {"stencil test", GL_STENCIL_TEST},
                                                                                {"vertex array", GL_VERTEX_ARRAY},
                                                                                {"normal array", GL_NORMAL_ARRAY},
                                                                                {"colour array", GL_COLOR_ARRAY}}) {
    enabled(name, cap);
  }
  GLint active = 0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  for (int unit = 0; unit < 3; ++unit) {
    glActiveTexture(GL_TEXTURE0 + unit);
    const std::string u = " (unit " + std::to_string(unit) + ")";
    ints(("binding 1D" + u).c_str(), GL_TEXTURE_BINDING_1D, 1);
    ints(("binding 2D" + u).c_str(), GL_TEXTURE_BINDING_2D, 1);
    enabled(("texture 1D" + u).c_str(), GL_TEXTURE_1D);
    enabled(("texture 2D" + u).c_str(), GL_TEXTURE_2D);
    enabled(("texgen S" + u).c_str(), GL_TEXTURE_GEN_S);
    enabled(("texgen R" + u).c_str(), GL_TEXTURE_GEN_R);
    floats(("texture matrix" + u).c_str(), GL_TEXTURE_MATRIX, 16);
    GLint mode = 0;
    glGetTexEnviv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, &mode);
    s["env mode" + u] = {static_cast<double>(mode)};
    GLfloat envColor[4] = {};
    glGetTexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, envColor);
    s["env colour" + u] = {envColor[0], envColor[1], envColor[2], envColor[3]};
    GLint gen = 0;
    glGetTexGeniv(GL_S, GL_TEXTURE_GEN_MODE, &gen);
    s["texgen S mode" + u] = {static_cast<double>(gen)};
  }
  glActiveTexture(static_cast<GLenum>(active));
  return s;
}

TEST_F(FixedFuncTest, RestoresTheHostsState) {
  auto r = FixedRenderer::create(unitSphere(), 32);
  ASSERT_OK(r);

  // A distinctive host state, nothing like GL's defaults or what the path sets.
  GLuint textures[3] = {};
  glGenTextures(3, textures);
  GLuint buffer = 0;
  glGenBuffers(1, &buffer);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, textures[0]);
  glEnable(GL_TEXTURE_2D);
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_DECAL);
  glTexGeni(GL_S, GL_TEXTURE_GEN_MODE, GL_SPHERE_MAP);
  glEnable(GL_TEXTURE_GEN_S);
  glMatrixMode(GL_TEXTURE);
  glLoadMatrixf(glm::value_ptr(glm::scale(glm::mat4(1.0f), {2, 3, 4})));
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_1D, textures[1]);
  glBindTexture(GL_TEXTURE_2D, textures[2]);
  glEnable(GL_TEXTURE_1D);
  const float envColor[4] = {0.1f, 0.2f, 0.3f, 0.4f};
  glTexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, envColor);
  glLoadMatrixf(glm::value_ptr(glm::translate(glm::mat4(1.0f), {5, 6, 7})));
  glActiveTexture(GL_TEXTURE2);
  glClientActiveTexture(GL_TEXTURE1);
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixf(glm::value_ptr(glm::ortho(-3.0f, 5.0f, -2.0f, 7.0f, 1.0f, 9.0f)));
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixf(glm::value_ptr(glm::rotate(glm::mat4(1.0f), 0.7f, glm::vec3(0, 0, 1))));
  glMatrixMode(GL_TEXTURE);
  glViewport(3, 5, 200, 190);
  glScissor(1, 2, 30, 40);
  glEnable(GL_SCISSOR_TEST);
  glClearColor(0.1f, 0.2f, 0.3f, 0.4f);
  glClearDepth(0.75);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE);
  glDepthFunc(GL_GEQUAL);
  glDepthMask(GL_FALSE);
  glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
  glEnable(GL_ALPHA_TEST);
  glAlphaFunc(GL_LESS, 0.25f);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_FRONT);
  glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
  glShadeModel(GL_FLAT);
  glEnable(GL_LIGHTING);
  glEnable(GL_LIGHT3);
  glEnable(GL_FOG);
  const float modelAmbient[4] = {0.3f, 0.1f, 0.2f, 1.0f};
  glLightModelfv(GL_LIGHT_MODEL_AMBIENT, modelAmbient);
  glColor4f(0.3f, 0.6f, 0.9f, 0.5f);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
  glPixelStorei(GL_PACK_ALIGNMENT, 8);
  glPixelTransferf(GL_RED_SCALE, 0.5f);
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glEnableClientState(GL_COLOR_ARRAY);
  glVertexPointer(2, GL_FLOAT, 12, nullptr);

  const auto before = captureState();
  ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  drawEverything(**r);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  const auto after = captureState();
  for (const auto& [name, value] : before) EXPECT_EQ(after.at(name), value) << name << " changed";

  // The host's restored state is live, not just reported: back to a sane state for later tests.
  glDisableClientState(GL_COLOR_ARRAY);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  glDeleteBuffers(1, &buffer);
  glDeleteTextures(3, textures);
  glPixelTransferf(GL_RED_SCALE, 1.0f);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  context_.reset();  // the next test gets a fresh context rather than this one's leftovers
  auto c = makeCompatContext(2, 1);
  ASSERT_TRUE(c.ok());
  context_ = std::move(*c);
}

// ---- 3. into the host's frame (FixedFrame::clear = false) --------------------------------------

// A host frame: colour A and depth 1 on the left half, colour B and depth 0.5 on the right (a wall
// in front of everything the puffs could be). 8-bit values, so they read back exactly.
const glm::vec4 kHostLeft{64 / 255.0f, 128 / 255.0f, 32 / 255.0f, 1.0f};
const glm::vec4 kHostRight{200 / 255.0f, 40 / 255.0f, 90 / 255.0f, 1.0f};

void fillHostFrame() {
  glEnable(GL_SCISSOR_TEST);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glScissor(0, 0, kSize / 2, kSize);
  glClearColor(kHostLeft.r, kHostLeft.g, kHostLeft.b, kHostLeft.a);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glScissor(kSize / 2, 0, kSize / 2, kSize);
  glClearColor(kHostRight.r, kHostRight.g, kHostRight.b, kHostRight.a);
  glClearDepth(0.5);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  glClearDepth(1.0);
}

TEST_F(FixedFuncTest, DrawsIntoTheHostsFrameWithoutClearing) {
  auto r = FixedRenderer::create(unitSphere(), 64);  // the puff pass draws through the 128 x 128 corner
  ASSERT_OK(r);
  // Puffs on both halves at depth 5 (window depth ~0.98): the left one over the host's far depth,
  // partly inside the corner (its disc spans rows ~110..146); the right one behind the wall.
  const std::vector<Billboard> puffs = {{{-1.2f, 0.0f, -5.0f}, 0.8f, 0}, {{1.2f, 0.0f, -5.0f}, 0.8f, 1}};
  FixedFrame frame = makeFrame();
  frame.background = {51 / 255.0f, 102 / 255.0f, 153 / 255.0f, 1.0f};  // 8-bit exact, neither host colour
  // Colours compared as the 8-bit values the framebuffer holds.
  auto bits = [](const glm::vec4& c) { return glm::ivec4(glm::round(c * 255.0f)); };
  auto at = [&](const std::vector<glm::vec4>& px, int x, int y) {
    return bits(px[static_cast<std::size_t>(y) * kSize + x]);
  };

  // Without the option: the frame is cleared as before; the host's colours are gone.
  fillHostFrame();
  ASSERT_OK((*r)->drawFrame(frame, puffs));
  const std::vector<glm::vec4> cleared = readFramebuffer();
  int puffPixels = 0, hostLeft = 0;
  std::vector<bool> puff(cleared.size());
  for (std::size_t i = 0; i < cleared.size(); ++i) {
    puff[i] = bits(cleared[i]) != bits(frame.background);
    puffPixels += puff[i];
    hostLeft += bits(cleared[i]) == bits(kHostLeft) || bits(cleared[i]) == bits(kHostRight);
  }
  EXPECT_GT(puffPixels, 2 * 800);  // two discs of radius ~18 px with outlines
  EXPECT_EQ(hostLeft, 0);

  // With it: every pixel outside the puffs keeps the host's colour exactly (the corner the puff
  // texture is drawn through included); the left puff is drawn as before; the right one is hidden
  // by the host's depth.
  std::vector<std::string> log;
  setCallLog(&log);
  fillHostFrame();
  frame.clear = false;
  ASSERT_OK((*r)->drawFrame(frame, puffs));
  setCallLog(nullptr);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  dumpIfAsked("fixedfunc-host-frame");
  const std::vector<glm::vec4> kept = readFramebuffer();
  int keptHost = 0, changedHost = 0, drawnLeft = 0, wrongLeft = 0, cornerChecked = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * kSize + x;
      const glm::ivec4 host = bits(x < kSize / 2 ? kHostLeft : kHostRight);
      if (!puff[i] || x >= kSize / 2) {
        (at(kept, x, y) == host ? keptHost : changedHost) += 1;
        cornerChecked += x < 128 && y < 128;
      } else {
        (at(kept, x, y) == at(cleared, x, y) ? drawnLeft : wrongLeft) += 1;
      }
    }
  }
  EXPECT_EQ(changedHost, 0) << "host pixels outside the puffs changed (of " << keptHost + changedHost << ")";
  EXPECT_GT(cornerChecked, 128 * 128 - 1200);
  EXPECT_GT(drawnLeft, 800);
  EXPECT_EQ(wrongLeft, 0) << "the left puff differs from the cleared frame's";
  // The host's depth is kept too: read outside the puffs, left 1.0 and right 0.5.
  float depth[2] = {0.0f, 0.0f};
  glReadPixels(10, 10, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, &depth[0]);
  glReadPixels(kSize - 10, 10, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, &depth[1]);
  EXPECT_EQ(depth[0], 1.0f);
  EXPECT_NEAR(depth[1], 0.5f, 1e-6f);
  // Still OpenGL 1.x only: the read-back and rewrite are GL 1.0 calls.
  const std::set<std::string> allowed = gl15EntryPoints();
  for (const std::string& name : std::set<std::string>(log.begin(), log.end()))
    EXPECT_EQ(allowed.count(name), 1u) << name << " is not an OpenGL <= 1.5 function";
  for (const char* name : {"glReadPixels", "glDrawPixels", "glRasterPos2f"})
    EXPECT_EQ(std::count(log.begin(), log.end(), name) > 0, true) << name;
  EXPECT_EQ(std::count(log.begin(), log.end(), "glClear"), 1) << "only the puff pass's own clear";
}

TEST_F(FixedFuncTest, RejectsWhatItCannotDraw) {
  EXPECT_FALSE(FixedRenderer::create(unitSphere(), 48).ok());  // not a power of two
  EXPECT_FALSE(FixedRenderer::create(mesh::TriMesh{}, 64).ok());
  auto r = FixedRenderer::create(unitSphere(), 64);
  ASSERT_TRUE(r.ok());
  FixedFrame frame = makeFrame();
  frame.viewport = {0, 0, 100, 100};
  auto small = (*r)->drawFrame(frame, {});
  ASSERT_FALSE(small.ok());
  EXPECT_NE(small.error().message.find("viewport"), std::string::npos);
  EXPECT_FALSE((*r)->setRamp(core::Image{}).ok());
  FixedObject bad{mesh::makePlane()};
  bad.mesh.normals.pop_back();
  EXPECT_FALSE((*r)->setObjects({bad}).ok());
}

TEST(FixedFuncCore, RefusesACoreProfileContext) {
  auto c = core::createGlContext({});  // 4.5 core
  if (!c) PUFF_SKIP_UNLESS_CI(c.error().message);
  auto r = FixedRenderer::create(unitSphere(), 64);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("compatibility"), std::string::npos) << r.error().message;
}

// ---- 4. the oldest context ------------------------------------------------------------------------

/// One small frame with a billboard at the centre; checks its centre is the puff, not background.
void drawOneBillboard(const std::string& expectVersionPrefix) {
  auto r = FixedRenderer::create(unitSphere(), 32);
  ASSERT_OK(r);
  if (!expectVersionPrefix.empty()) {
    EXPECT_EQ((*r)->contextVersion().rfind(expectVersionPrefix, 0), 0u) << (*r)->contextVersion();
  }
  std::printf("fixedfunc-gl-version: %s\n", (*r)->contextVersion().c_str());
  const FixedFrame frame = makeFrame();
  ASSERT_TRUE((*r)->drawFrame(frame, {{{0.0f, 0.0f, -5.0f}, 1.0f, 2}}).ok());
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  const std::vector<glm::vec4> px = readFramebuffer();
  // The disc has a radius of 22 pixels; 16 pixels right of the centre N.L is about 0.7: lit, and
  // the default ramp is white there, so K_a + K_L (clamped).
  const glm::vec4 lit = px[static_cast<std::size_t>(kSize / 2) * kSize + kSize / 2 + 16];
  EXPECT_NEAR(lit.r, std::min(1.0f, frame.ambientColor.r + frame.lightColor.r), 0.02f);
  EXPECT_NEAR(lit.g, std::min(1.0f, frame.ambientColor.g + frame.lightColor.g), 0.02f);
  const glm::vec4 unlit = px[static_cast<std::size_t>(kSize / 2) * kSize + kSize / 2 - 16];  // black in the ramp
  EXPECT_NEAR(unlit.r, frame.ambientColor.r, 0.02f);
  const glm::vec4 corner = px[0];
  EXPECT_NEAR(corner.b, frame.background.b, 0.02f);
}

TEST(FixedFuncOldestContext, Compatibility21) {
  auto c = makeCompatContext(2, 1);
  if (!c) PUFF_SKIP_UNLESS_CI(c.error().message);
  // OSMesa treats the requested version as a minimum and gives its highest (4.5 compatibility).
  std::printf("asked for 2.1 compatibility, got %s\n", reinterpret_cast<const char*>(glGetString(GL_VERSION)));
  drawOneBillboard("");
}

// Mesa only hands out a context below its highest version through MESA_GL_VERSION_OVERRIDE, read
// once per process: so the test runs itself again in a child process with it set to 1.3, the
// lowest version the path accepts.
TEST(FixedFuncOldestContext, OpenGl13) {
  if (std::getenv("PUFF_FIXEDFUNC_GL13_CHILD") != nullptr) {
    auto c = makeCompatContext(1, 3);
    ASSERT_OK(c);
    drawOneBillboard("1.3");
    return;
  }
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  const std::string command = "PUFF_FIXEDFUNC_GL13_CHILD=1 MESA_GL_VERSION_OVERRIDE=1.3 '" + self +
                              "' --gtest_filter=FixedFuncOldestContext.OpenGl13 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char chunk[4096];
  while (std::fgets(chunk, sizeof chunk, pipe) != nullptr) output += chunk;
  const int status = pclose(pipe);
  EXPECT_EQ(status, 0) << output;
  const auto at = output.find("fixedfunc-gl-version: ");
  ASSERT_NE(at, std::string::npos) << output;
  const std::string version = output.substr(at, output.find('\n', at) - at);
  std::printf("child process: %s\n", version.c_str());
  EXPECT_NE(version.find(": 1.3"), std::string::npos) << version;
  EXPECT_NE(output.find("[  PASSED  ] 1 test"), std::string::npos) << output;
}

}  // namespace
}  // namespace puff::fixedfunc::test
