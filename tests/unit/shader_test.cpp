// Shader files: the embedded copies are the files in shaders/, every program there builds, and the
// include step keeps errors pointing at the real file and line.
#include <gtest/gtest.h>

#include <puff/core/shader.h>
#include <puff/gl_api.h>
#include <puff/platform/gl_context.h>
#include <puff/shader_blocks.h>
#include <puff/support/embedded.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace fs = std::filesystem;

namespace puff::core {
namespace {

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

std::unique_ptr<GlContext> osmesaCore45() {
  GlContextOptions options;
  options.backend = "osmesa";
  Result<std::unique_ptr<GlContext>> context = createGlContext(options);
  EXPECT_OK(context);
  return context ? std::move(*context) : nullptr;
}

// ---- the real shaders ------------------------------------------------------------------------------

TEST(ShaderEmbedded, EqualsTheFilesOnDisk) {
  const fs::path root = fs::path(PUFF_SOURCE_DIR) / "shaders";
  std::set<std::string> embedded;
  for (const EmbeddedFile* f = embeddedShaders(); f->name != nullptr; ++f) {
    embedded.insert(f->name);
    EXPECT_EQ(f->data[f->size], '\0') << f->name << ": the data is NUL-terminated";
    EXPECT_EQ(std::string(f->data, f->size), readFile(root / f->name)) << f->name << " differs from the file on disk";
  }
  EXPECT_TRUE(std::is_sorted(embedded.begin(), embedded.end()));
  // Every shader file on disk is embedded (a stage the embedding glob misses would be unbuildable
  // from an installed binary).
  const std::set<std::string> kExtensions = {".vert", ".tesc", ".tese", ".geom", ".frag", ".comp", ".glsl"};
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file() || kExtensions.count(entry.path().extension().string()) == 0) continue;
    const std::string name = entry.path().lexically_relative(root).generic_string();
    EXPECT_EQ(embedded.count(name), 1u) << name << " is on disk but not embedded";
  }
  EXPECT_FALSE(embedded.empty());
}

TEST(ShaderPrograms, EveryProgramCompilesAndLinksOnOSMesaCore45) {
  setShaderDir({});
  std::unique_ptr<GlContext> context = osmesaCore45();
  ASSERT_NE(context, nullptr);
  const auto programs = listShaderPrograms();
  ASSERT_FALSE(programs.empty()) << "no shader programs found: the embedding is broken";
  bool sawBake = false;
  for (const auto& [name, stages] : programs) {
    SCOPED_TRACE(name);
    EXPECT_FALSE(name.starts_with("common/"));
    sawBake |= name == "bake/puff";
    Result<Program> program = buildProgram(stages);
    ASSERT_OK(program);
    EXPECT_TRUE(*program);
    EXPECT_TRUE(glIsProgram(program->get()));
  }
  EXPECT_TRUE(sawBake);
  EXPECT_EQ(drainGlErrors(), "");
}

// The C++/GLSL contract (shaders/common/contract.glsl): every uniform block any program declares
// has a C++ mirror (puff/shader_blocks.h) of the size GL lays it out at, and every mirror is used.
TEST(ShaderContract, EveryUniformBlockIsTheSizeOfItsCppMirror) {
  setShaderDir({});
  std::unique_ptr<GlContext> context = osmesaCore45();
  ASSERT_NE(context, nullptr);
  const std::map<std::string, std::size_t> mirrors = {
      {"FrameBlock", sizeof(shader::FrameBlockData)},
      {"MediaBlock", sizeof(shader::MediaBlockData)},
      {"MaterialBlock", sizeof(shader::MaterialGpu) * shader::kMaxMaterials},
      {"ComposeBlock", sizeof(shader::ComposeBlockData)},
      {"CartoonBlock", sizeof(shader::CartoonBlockData)},
  };
  std::map<std::string, int> programsDeclaring;
  for (const auto& [name, stages] : listShaderPrograms()) {
    SCOPED_TRACE(name);
    Result<Program> program = buildProgram(stages);
    ASSERT_OK(program);
    const GLuint p = program->get();
    GLint blocks = 0;
    glGetProgramiv(p, GL_ACTIVE_UNIFORM_BLOCKS, &blocks);
    for (GLint i = 0; i < blocks; ++i) {
      char block[128] = {};
      glGetActiveUniformBlockName(p, static_cast<GLuint>(i), sizeof block, nullptr, block);
      GLint size = 0;
      glGetActiveUniformBlockiv(p, static_cast<GLuint>(i), GL_UNIFORM_BLOCK_DATA_SIZE, &size);
      const auto mirror = mirrors.find(block);
      ASSERT_NE(mirror, mirrors.end()) << block << " has no C++ mirror: add one to puff/shader_blocks.h and here";
      EXPECT_EQ(static_cast<std::size_t>(size), mirror->second)
          << block << ": GL's std140 size against the C++ mirror's";
      ++programsDeclaring[block];
    }
  }
  for (const auto& [block, size] : mirrors) EXPECT_GT(programsDeclaring[block], 0) << "no program declares " << block;
  EXPECT_EQ(drainGlErrors(), "");
}

// The contract is where a uniform's location and a shade pass's number are written: no shader
// writes one as a bare number.
TEST(ShaderContract, NoShaderWritesAUniformLocationOrAShadePassAsANumber) {
  const fs::path root = fs::path(PUFF_SOURCE_DIR) / "shaders";
  const std::regex location(R"(layout\s*\(\s*location\s*=\s*[0-9]+\s*\)\s*uniform)");
  const std::regex pass(R"(uPass\s*[!=<>]=?\s*[0-9])");
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    ++files;
    const std::string text = readFile(entry.path());
    const std::string name = entry.path().lexically_relative(root).generic_string();
    EXPECT_FALSE(std::regex_search(text, location)) << name << ": a uniform location belongs in common/contract.glsl";
    EXPECT_FALSE(std::regex_search(text, pass)) << name << ": a shade pass is PUFF_PASS_* (common/contract.glsl)";
  }
  EXPECT_GT(files, 50);
}

// Arrays sized by the contract's limits, and uniforms at the contract's locations, as GL sees them.
TEST(ShaderContract, ArraysAndLocationsAreTheContractsInTheLinkedPrograms) {
  setShaderDir({});
  std::unique_ptr<GlContext> context = osmesaCore45();
  ASSERT_NE(context, nullptr);
  auto blur = buildProgram({"media/fullscreen.vert", "media/blur.frag"});
  ASSERT_OK(blur);
  const GLuint p = blur->get();
  EXPECT_EQ(glGetUniformLocation(p, "uCount"), shader::loc::kBlurCount);
  EXPECT_EQ(glGetUniformLocation(p, "uWeights"), shader::loc::kBlurWeights);
  EXPECT_EQ(glGetUniformLocation(p, "uViewport"), shader::loc::kBlurViewport);
  GLuint index = GL_INVALID_INDEX;
  const char* weights = "uWeights";
  glGetUniformIndices(p, 1, &weights, &index);
  ASSERT_NE(index, GL_INVALID_INDEX);
  GLint length = 0;
  glGetActiveUniformsiv(p, 1, &index, GL_UNIFORM_SIZE, &length);
  EXPECT_EQ(length, shader::kMaxBlurFrames);
  auto opaque = buildProgram({"cel/opaque.vert", "cel/opaque.frag"});
  ASSERT_OK(opaque);
  const GLuint o = opaque->get();
  EXPECT_EQ(glGetUniformLocation(o, "uModel"), shader::loc::kOpaqueModel);
  EXPECT_EQ(glGetUniformLocation(o, "uNormalMatrix"), shader::loc::kOpaqueNormalMatrix);
  EXPECT_EQ(glGetUniformLocation(o, "uAlbedo"), shader::loc::kOpaqueAlbedo);
  EXPECT_EQ(glGetUniformLocation(o, "uPass"), shader::loc::kOpaquePass);
  EXPECT_EQ(glGetUniformLocation(o, "uId"), shader::loc::kOpaqueId);
  EXPECT_EQ(drainGlErrors(), "");
}

// The nailboards compile one program per shade pass (nailboard_fs.glsl, PUFF_SHADE_PASS), so a
// pass carries none of the code it does not run: GL reports a uniform only where a linked program
// uses it. The lit pass reads the colour map, the ramp and the shadow map; the shadowed pass (ambient
// only) none of them; the depth-only pass not even the ambient gradient, nor the outline's colour.
TEST(ShaderPrograms, EachNailboardShadePassCarriesOnlyItsOwnCode) {
  setShaderDir({});
  std::unique_ptr<GlContext> context = osmesaCore45();
  ASSERT_NE(context, nullptr);
  const std::vector<std::string> litOnly = {"uColor", "uRamp", "uShading", "uShadowMapId"};
  const std::vector<std::string> colourPasses = {"uGradient", "uOutlineColor"};
  for (const auto& [vertex, fragment] : std::vector<std::pair<std::string, std::string>>{
           {"nailboard", "nailboard"}, {"nailboard_views", "nailboard_views"}, {"nailboard_views", "nailboard_hull"}}) {
    for (const std::string pass : {"", "_shadowed", "_depth"}) {
      SCOPED_TRACE(fragment + pass);
      auto program = buildProgram({"cel/" + vertex + ".vert", "cel/" + fragment + pass + ".frag"});
      ASSERT_OK(program);
      const GLuint p = program->get();
      EXPECT_NE(glGetUniformLocation(p, "uPacked"), -1) << "every pass reads the depth and the silhouette";
      for (const std::string& name : litOnly) {
        EXPECT_EQ(glGetUniformLocation(p, name.c_str()) != -1, pass.empty()) << name;
      }
      for (const std::string& name : colourPasses) {
        EXPECT_EQ(glGetUniformLocation(p, name.c_str()) != -1, pass != "_depth") << name;
      }
    }
  }
  EXPECT_EQ(drainGlErrors(), "");
}

TEST(ShaderPrograms, BakeProgramHasItsStagesInPipelineOrder) {
  setShaderDir({});
  for (const auto& [name, stages] : listShaderPrograms()) {
    if (name == "bake/puff") {
      EXPECT_EQ(stages, (std::vector<std::string>{"bake/puff.vert", "bake/puff.frag"}));
    }
  }
}

TEST(ShaderFile, MissingFileIsNamed) {
  setShaderDir({});
  Result<std::string> source = shaderFileSource("bake/nope.frag");
  ASSERT_FALSE(source);
  EXPECT_EQ(source.error().message, "shader file not found: bake/nope.frag");
  Result<std::string> escape = shaderFileSource("../CMakeLists.txt");
  ASSERT_FALSE(escape) << "names may not leave the shaders root";
}

// ---- the include step, on a temporary shaders directory -------------------------------------------

class ShaderInclude : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(dir_ / "common");
    fs::create_directories(dir_ / "test");
    setShaderDir(dir_.path());
  }
  void TearDown() override { setShaderDir({}); }
  // How messages name a file of the shader directory in use: its path there, one the user can open.
  std::string shown(const std::string& name) const { return (dir_.path() / name).string(); }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name, std::ios::binary) << text; }
  /// A fragment shader that includes `includes` (one per line) and then has `body` after main.
  void writeMain(const std::string& name, const std::vector<std::string>& includes, const std::string& body = "") {
    std::string text = "#version 450 core\n";
    for (const std::string& inc : includes) text += "#include \"" + inc + "\"\n";
    text += "out vec4 oColor;\nvoid main() { oColor = vec4(1.0); }\n" + body;
    write(name, text);
  }
  puff::test::ScopedTempDir dir_{"puff_shader_test"};
};

TEST_F(ShaderInclude, ShaderDirOverridesTheEmbeddedFiles) {
  EXPECT_EQ(shaderDir(), dir_.path());
  write("test/a.vert", "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n");
  write("test/a.frag", "#version 450 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n");
  write("test/only.comp", "#version 450 core\nlayout(local_size_x = 1) in;\nvoid main() {}\n");
  write("common/x.glsl", "float x() { return 1.0; }\n");
  write("test/notes.txt", "not a shader\n");
  EXPECT_EQ(listShaderFiles(),
            (std::vector<std::string>{"common/x.glsl", "test/a.frag", "test/a.vert", "test/only.comp"}));
  const auto programs = listShaderPrograms();
  ASSERT_EQ(programs.size(), 2u);
  EXPECT_EQ(programs[0].first, "test/a");
  EXPECT_EQ(programs[0].second, (std::vector<std::string>{"test/a.vert", "test/a.frag"}));
  EXPECT_EQ(programs[1].first, "test/only");
  setShaderDir({});
  EXPECT_TRUE(shaderDir().empty() || std::getenv("PUFF_SHADER_DIR") != nullptr);
  EXPECT_TRUE(shaderFileSource("bake/puff.frag")) << "the embedded copies are back";
}

TEST_F(ShaderInclude, NestedIncludeAppearsOnceAndVersionStaysFirst) {
  write("common/leaf.glsl", "float leafValue() { return 0.25; }  // LEAF-MARKER\n");
  write("common/mid.glsl", "// mid\n#include \"common/leaf.glsl\"\nfloat midValue() { return leafValue() * 2.0; }\n");
  // leaf.glsl is reached twice: directly and through mid.glsl.
  write("test/main.frag",
        "#version 450 core\n"
        "#include \"common/mid.glsl\"\n"
        "#include \"common/leaf.glsl\"  // again\n"
        "out vec4 oColor;\n"
        "void main() { oColor = vec4(midValue() + leafValue()); }\n");
  std::vector<std::string> files;
  Result<std::string> source = preprocessShader("test/main.frag", &files);
  ASSERT_OK(source);
  EXPECT_EQ(source->rfind("#version 450 core\n", 0), 0u) << *source;
  EXPECT_EQ(count(*source, "LEAF-MARKER"), 1u) << *source;
  EXPECT_EQ(count(*source, "midValue() {"), 1u) << *source;
  EXPECT_EQ(files, (std::vector<std::string>{"test/main.frag", "common/mid.glsl", "common/leaf.glsl"}));
  EXPECT_EQ(count(*source, "#include"), 0u) << *source;

  std::unique_ptr<GlContext> context = osmesaCore45();
  ASSERT_NE(context, nullptr);
  write("test/main.vert",
        "#version 450 core\n#include \"common/leaf.glsl\"\nvoid main() { gl_Position = vec4(leafValue()); }\n");
  Result<Program> program = buildProgram({"test/main.vert", "test/main.frag"});
  EXPECT_OK(program);
}

TEST_F(ShaderInclude, CycleIsAnError) {
  write("common/a.glsl", "#include \"common/b.glsl\"\n");
  write("common/b.glsl", "// b\n#include \"common/a.glsl\"\n");
  writeMain("test/main.frag", {"common/a.glsl"});
  Result<std::string> source = preprocessShader("test/main.frag");
  ASSERT_FALSE(source);
  EXPECT_EQ(
      source.error().message,
      shown("common/b.glsl") + ":2: include cycle: test/main.frag -> common/a.glsl -> common/b.glsl -> common/a.glsl");
}

TEST_F(ShaderInclude, MissingIncludeNamesTheIncludingFileAndLine) {
  write("common/ok.glsl", "float ok() { return 1.0; }\n");
  writeMain("test/main.frag", {"common/ok.glsl", "common/nope.glsl"});  // the second include is line 3
  Result<std::string> source = preprocessShader("test/main.frag");
  ASSERT_FALSE(source);
  EXPECT_EQ(source.error().message, shown("test/main.frag") +
                                        ":3: shader file not found: common/nope.glsl (shader dir " +
                                        dir_.path().string() + ")");
}

TEST_F(ShaderInclude, MalformedIncludeIsAnError) {
  write("test/main.frag", "#version 450 core\n#include <common/x.glsl>\n");
  Result<std::string> source = preprocessShader("test/main.frag");
  ASSERT_FALSE(source);
  EXPECT_EQ(source.error().message.rfind(shown("test/main.frag") + ":2: malformed #include", 0), 0u)
      << source.error().message;
}

TEST_F(ShaderInclude, ErrorInAnIncludedFileNamesThatFileAndLine) {
  std::unique_ptr<GlContext> context = osmesaCore45();
  ASSERT_NE(context, nullptr);
  // first.glsl shifts the source-string numbers so a mix-up would show.
  write("common/first.glsl", "// first\n// second line\nfloat first() { return 1.0; }\n");
  write("common/broken.glsl",
        "// A deliberately broken include.\n"
        "float fine() { return 1.0; }\n"
        "\n"
        "float broken() { return 1.0 +; }\n"  // line 4
        "float after() { return 2.0; }\n");
  writeMain("test/main.frag", {"common/first.glsl", "common/broken.glsl"});
  write("test/main.vert", "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n");
  Result<Program> program = buildProgram({"test/main.vert", "test/main.frag"});
  ASSERT_FALSE(program);
  const std::string& message = program.error().message;
  const std::string firstLine = message.substr(0, message.find('\n'));
  EXPECT_EQ(firstLine.rfind(shown("common/broken.glsl") + ":4:", 0), 0u) << message;
  EXPECT_NE(firstLine.find("error"), std::string::npos) << message;
  EXPECT_EQ(message.find("first.glsl"), std::string::npos) << message;
}

TEST_F(ShaderInclude, ErrorInTheMainFileNamesItAndTheLineAfterIncludes) {
  std::unique_ptr<GlContext> context = osmesaCore45();
  ASSERT_NE(context, nullptr);
  write("common/two.glsl", "// one\nfloat two() { return 2.0; }\n// three\n");
  write("common/one.glsl", "#include \"common/two.glsl\"\nfloat one() { return two() - 1.0; }\n");
  // Line 7 of main.frag (after #version, two includes, two lines of main and a blank) is broken.
  writeMain("test/main.frag", {"common/one.glsl", "common/two.glsl"}, "\nvec3 broken = undefinedThing;\n");
  write("test/main.vert", "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n");
  Result<Program> program = buildProgram({"test/main.vert", "test/main.frag"});
  ASSERT_FALSE(program);
  const std::string& message = program.error().message;
  EXPECT_EQ(message.rfind(shown("test/main.frag") + ":7:", 0), 0u) << message;
  EXPECT_NE(message.find("undefinedThing"), std::string::npos) << message;
}

TEST_F(ShaderInclude, LinkErrorNamesTheStageFiles) {
  std::unique_ptr<GlContext> context = osmesaCore45();
  ASSERT_NE(context, nullptr);
  write("test/main.vert", "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n");
  write("test/main.frag",
        "#version 450 core\nin vec3 vMissing;\nout vec4 c;\nvoid main() { c = vec4(vMissing, 1.0); }\n");
  Result<Program> program = buildProgram({"test/main.vert", "test/main.frag"});
  ASSERT_FALSE(program);
  const std::string& message = program.error().message;
  EXPECT_EQ(message.rfind("link " + shown("test/main.vert") + " + " + shown("test/main.frag") + ": ", 0), 0u)
      << message;
  EXPECT_NE(message.find("vMissing"), std::string::npos) << message;
}

TEST_F(ShaderInclude, UnknownStageExtensionIsAnError) {
  std::unique_ptr<GlContext> context = osmesaCore45();
  ASSERT_NE(context, nullptr);
  write("test/main.shader", "#version 450 core\n");
  Result<Program> program = buildProgram({"test/main.shader"});
  ASSERT_FALSE(program);
  EXPECT_EQ(program.error().message.rfind(shown("test/main.shader") + ": not a shader stage", 0), 0u)
      << program.error().message;
}

// ---- log formats of drivers we cannot run here ------------------------------------------------------

TEST(ShaderLog, RewritesMesaNvidiaAndOtherLocations) {
  const std::vector<std::string> files = {"cel/nailboard.frag", "common/depth.glsl"};
  EXPECT_EQ(rewriteShaderLog("0:12(5): error: syntax error, unexpected '+'\n", files),
            "shaders/cel/nailboard.frag:12:5: error: syntax error, unexpected '+'");
  EXPECT_EQ(rewriteShaderLog("1(7) : error C1008: undefined variable \"x\"\n", files),
            "shaders/common/depth.glsl:7: error C1008: undefined variable \"x\"");
  EXPECT_EQ(rewriteShaderLog("ERROR: 1:3: 'y' : undeclared identifier\n", files),
            "shaders/common/depth.glsl:3: error: 'y' : undeclared identifier");
  // Warnings go after errors so the first line says what broke; location-less lines name the stage.
  EXPECT_EQ(rewriteShaderLog("0:2(1): warning: unused\n1:9(3): error: bad\nsomething else\n", files),
            "shaders/common/depth.glsl:9:3: error: bad\nshaders/cel/nailboard.frag:2:1: warning: unused\n"
            "shaders/cel/nailboard.frag: something else");
  EXPECT_EQ(rewriteShaderLog("", files), "");
}

}  // namespace
}  // namespace puff::core
