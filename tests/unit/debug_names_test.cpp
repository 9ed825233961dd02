// Names in a capture (RenderDoc, apitrace): in a context with KHR_debug, every GL object the cel and
// media paths make carries a "puff: ..." label, and every pass is a debug group named after it, as a
// capture tool reads them back.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <puff/gl_api.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"

namespace {

namespace fs = std::filesystem;
using namespace puff;

// The debug groups pushed while it is installed (GL_DEBUG_TYPE_PUSH_GROUP from the application),
// and how many were popped.
struct Groups {
  std::vector<std::string> pushed;
  int popped = 0;
};

void GLAPIENTRY recordGroup(GLenum source, GLenum type, GLuint, GLenum, GLsizei length, const GLchar* message,
                            const void* user) {
  if (source != GL_DEBUG_SOURCE_APPLICATION) return;
  auto* groups = static_cast<Groups*>(const_cast<void*>(user));
  if (type == GL_DEBUG_TYPE_PUSH_GROUP) groups->pushed.emplace_back(message, static_cast<std::size_t>(length));
  if (type == GL_DEBUG_TYPE_POP_GROUP) ++groups->popped;
}

class DebugNames : public test::GlTest {
 protected:
  // One frame of an art scene at a small size, drawn and read back.
  void render(const std::string& name, int frame) {
    SCOPED_TRACE(name);
    auto s = scene::loadScene(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / (name + ".json"), PUFF_ART_DIR);
    ASSERT_OK(s);
    s->width = 160;
    s->height = 90;
    auto r = render::SceneRenderer::create(*s);
    ASSERT_OK(r);
    ASSERT_OK((*r)->renderFrame(frame));
    renderers_.push_back(std::move(*r));
  }
  std::vector<std::unique_ptr<render::SceneRenderer>> renderers_;
};

// Oriented puffs by the hull with map shadows over a ground (dust-roll), the photoreal media
// (explosion-walls) and the cartoon media (explosion-walls-cartoon): every live program, texture,
// buffer, framebuffer, renderbuffer and vertex array is labelled "puff: ...".
TEST_F(DebugNames, EveryObjectTheRenderersMakeIsLabelled) {
  ASSERT_TRUE(core::hasDebugNames()) << "this GL has no KHR_debug";
  render("dust-roll", 30);
  render("explosion-walls", 20);
  render("explosion-walls-cartoon", 20);
  struct Kind {
    GLenum label;
    GLboolean (*alive)(GLuint);
    const char* name;
  };
  const Kind kinds[] = {{GL_PROGRAM, [](GLuint i) { return glIsProgram(i); }, "program"},
                        {GL_TEXTURE, [](GLuint i) { return glIsTexture(i); }, "texture"},
                        {GL_BUFFER, [](GLuint i) { return glIsBuffer(i); }, "buffer"},
                        {GL_FRAMEBUFFER, [](GLuint i) { return glIsFramebuffer(i); }, "framebuffer"},
                        {GL_RENDERBUFFER, [](GLuint i) { return glIsRenderbuffer(i); }, "renderbuffer"},
                        {GL_VERTEX_ARRAY, [](GLuint i) { return glIsVertexArray(i); }, "vertex array"}};
  std::map<std::string, int> counts;
  std::set<std::string> labels;
  for (const Kind& k : kinds) {
    for (GLuint id = 1; id < 2048; ++id) {
      if (!k.alive(id)) continue;
      char text[256] = {};
      GLsizei length = 0;
      glGetObjectLabel(k.label, id, sizeof text, &length, text);
      const std::string label(text, static_cast<std::size_t>(length));
      EXPECT_EQ(label.rfind("puff: ", 0), 0u) << k.name << " " << id << " is labelled \"" << label << "\"";
      ++counts[k.name];
      labels.insert(label);
    }
  }
  for (const Kind& k : kinds) EXPECT_GT(counts[k.name], 0) << "no live " << k.name << " was found";
  for (const char* label : {"puff: cel/nailboard_views.vert + cel/nailboard_hull.frag", "puff: shadow map: depth",
                            "puff: media layers: media", "puff: cartoon media: ink seeds", "puff: frame target"})
    EXPECT_TRUE(labels.count(label)) << label;
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

// Each pass is a debug group named after it, every group popped.
TEST_F(DebugNames, EachPassIsADebugGroupNamedAfterIt) {
  ASSERT_TRUE(core::hasDebugNames()) << "this GL has no KHR_debug";
  Groups groups;
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(recordGroup, &groups);
  render("dust-roll", 30);
  render("explosion-walls", 20);
  render("explosion-walls-cartoon", 20);
  glDebugMessageCallback(nullptr, nullptr);
  glDisable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDisable(GL_DEBUG_OUTPUT);
  const std::set<std::string> pushed(groups.pushed.begin(), groups.pushed.end());
  for (const char* pass :
       {"puff: nailboards (lit)", "puff: nailboards (shadow casters)", "puff: opaque objects (lit)",
        "puff: opaque objects (shadow casters)", "puff: media particles", "puff: media: resolve the opaque frame",
        "puff: media compose", "puff: cartoon media: field, ink and compose"})
    EXPECT_TRUE(pushed.count(pass)) << pass;
  EXPECT_EQ(groups.popped, static_cast<int>(groups.pushed.size()));
  for (const std::string& g : groups.pushed) EXPECT_EQ(g.rfind("puff: ", 0), 0u) << g;
}

}  // namespace
