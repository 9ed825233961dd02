// Shader files, the include step and program building. The include step numbers every file it
// pulls in as a GLSL source string (`#line LINE STRING`), so the driver's log says "string 2, line
// 7" and we can turn that back into "shaders/common/noise.glsl:7".
#include <puff/core/shader.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>

#include <puff/gl_api.h>
#include <puff/support/embedded.h>

namespace fs = std::filesystem;

namespace puff::core {

namespace {

struct Stage {
  const char* extension;
  GLenum type;
};
// Pipeline order: listShaderPrograms() lists a program's files in this order.
constexpr Stage kStages[] = {
    {".vert", GL_VERTEX_SHADER},   {".tesc", GL_TESS_CONTROL_SHADER}, {".tese", GL_TESS_EVALUATION_SHADER},
    {".geom", GL_GEOMETRY_SHADER}, {".frag", GL_FRAGMENT_SHADER},     {".comp", GL_COMPUTE_SHADER},
};
constexpr const char* kIncludeExtension = ".glsl";

std::optional<std::size_t> stageIndex(const std::string& name) {
  const std::string ext = fs::path(name).extension().string();
  for (std::size_t i = 0; i < std::size(kStages); ++i)
    if (ext == kStages[i].extension) return i;
  return std::nullopt;
}

bool isShaderFileName(const std::string& name) {
  return stageIndex(name) || fs::path(name).extension() == kIncludeExtension;
}

// ---- where the files come from -----------------------------------------------------------------

// How messages name a shader file: under the directory the shaders are read from (setShaderDir,
// --shader-dir, PUFF_SHADER_DIR), so the name is a path the user can open; "shaders/" (the source
// tree's directory) for the built-in copies.
std::string shown(const std::string& file) {
  const fs::path dir = shaderDir();
  return dir.empty() ? "shaders/" + file : (dir / file).string();
}

std::mutex gDirMutex;
std::optional<fs::path> gDirOverride;  // set by setShaderDir with a non-empty path

const fs::path& environmentDir() {
  static const fs::path dir = [] {
    const char* env = std::getenv("PUFF_SHADER_DIR");
    return env != nullptr ? fs::path(env) : fs::path();
  }();
  return dir;
}

/// "bake/../common/x.glsl" -> "common/x.glsl"; nullopt for names that leave the shaders root.
std::optional<std::string> normalizeName(const std::string& name) {
  const fs::path p = fs::path(name).lexically_normal();
  const std::string s = p.generic_string();
  if (s.empty() || s == "." || p.is_absolute() || s == ".." || s.starts_with("../")) return std::nullopt;
  return s;
}

Error notFound(const std::string& name, const fs::path& dir) {
  return Error{"shader file not found: " + name + (dir.empty() ? "" : " (shader dir " + dir.string() + ")")};
}

// ---- the include step ----------------------------------------------------------------------------

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

std::string_view trimLeft(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  return s;
}

/// The directive name of a preprocessor line ("version", "include", ...), or "" for other lines.
std::string_view directive(std::string_view line, std::string_view* rest) {
  line = trimLeft(line);
  if (line.empty() || line.front() != '#') return {};
  line = trimLeft(line.substr(1));
  std::size_t n = 0;
  while (n < line.size() && std::isalpha(static_cast<unsigned char>(line[n]))) ++n;
  if (rest != nullptr) *rest = line.substr(n);
  return line.substr(0, n);
}

/// The path of `#include "path"` (trailing // comment allowed), or an error text.
std::optional<std::string> includePath(std::string_view rest, std::string* problem) {
  rest = trimLeft(rest);
  if (rest.empty() || rest.front() != '"') {
    *problem = "malformed #include: write #include \"path/relative/to/shaders.glsl\"";
    return std::nullopt;
  }
  const std::size_t close = rest.find('"', 1);
  if (close == std::string_view::npos) {
    *problem = "malformed #include: missing closing quote";
    return std::nullopt;
  }
  std::string_view tail = trimLeft(rest.substr(close + 1));
  if (!tail.empty() && tail.back() == '\r') tail.remove_suffix(1);
  if (!tail.empty() && !tail.starts_with("//")) {
    *problem = "malformed #include: unexpected text after the path";
    return std::nullopt;
  }
  return std::string(rest.substr(1, close - 1));
}

class Preprocessor {
 public:
  std::vector<std::string> files;  // source-string number -> file name

  Result<std::string> run(const std::string& name) {
    PUFF_TRY(expand(name, nullptr));
    return std::move(out_);
  }

 private:
  std::set<std::string> included_;  // every file pulled in so far (include-once semantics)
  std::vector<std::string> chain_;  // the files being expanded, outermost first (cycle detection)
  std::string out_;

  static std::string where(const std::string& file, std::size_t line) {
    return shown(file) + ":" + std::to_string(line) + ": ";
  }

  /// Appends `name`'s text. `from` is "file:line: " of the #include, or null for the main file.
  Result<void> expand(const std::string& name, const std::string* from) {
    Result<std::string> text = shaderFileSource(name);
    if (!text) return Error{(from ? *from : std::string()) + text.error().message};
    const bool isMain = from == nullptr;
    const std::size_t index = files.size();
    files.push_back(name);
    included_.insert(name);
    chain_.push_back(name);
    if (!isMain) out_ += "#line 1 " + std::to_string(index) + "\n";

    // Lines before #version may only be comments or blank; an #include there would put code (and
    // our #line directives) ahead of the #version line, which must come first.
    bool seenVersion = false;
    const std::vector<std::string> lines = splitLines(*text);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const std::size_t lineNo = i + 1;
      std::string_view rest;
      const std::string_view d = directive(lines[i], &rest);
      if (d == "version") {
        if (!isMain) return Error{where(name, lineNo) + "#version belongs in the stage file, not in an include"};
        seenVersion = true;
      } else if (d == "include") {
        std::string problem;
        const std::optional<std::string> raw = includePath(rest, &problem);
        if (!raw) return Error{where(name, lineNo) + problem};
        const std::optional<std::string> target = normalizeName(*raw);
        if (!target) return Error{where(name, lineNo) + "include path leaves the shaders root: " + *raw};
        if (isMain && !seenVersion && text->find("#version") != std::string::npos)
          return Error{where(name, lineNo) + "#include before #version"};
        if (std::find(chain_.begin(), chain_.end(), *target) != chain_.end()) {
          std::string cycle;
          for (const std::string& f : chain_) cycle += f + " -> ";
          return Error{where(name, lineNo) + "include cycle: " + cycle + *target};
        }
        if (included_.count(*target) != 0) {
          out_ += "// (already included: " + *target + ")\n";  // keeps this file's line numbering
          continue;
        }
        const std::string here = where(name, lineNo);
        PUFF_TRY(expand(*target, &here));
        // Back in this file: the next line is lineNo + 1 of source string `index`.
        out_ += "#line " + std::to_string(lineNo + 1) + " " + std::to_string(index) + "\n";
        continue;
      }
      out_ += lines[i];
      out_ += '\n';
    }
    chain_.pop_back();
    return {};
  }
};

// ---- the driver's log ----------------------------------------------------------------------------

bool parseNumber(std::string_view s, std::size_t* pos, std::size_t* value) {
  const std::size_t start = *pos;
  std::size_t v = 0;
  while (*pos < s.size() && std::isdigit(static_cast<unsigned char>(s[*pos])))
    v = v * 10 + static_cast<std::size_t>(s[(*pos)++] - '0');
  *value = v;
  return *pos > start;
}

bool consume(std::string_view s, std::size_t* pos, std::string_view token) {
  if (s.substr(*pos).starts_with(token)) {
    *pos += token.size();
    return true;
  }
  return false;
}

/// Rewrites one log line's location. Understands Mesa "S:L(C): msg", NVIDIA "S(L) : msg" and the
/// "ERROR: S:L: msg" form of other drivers; other lines are prefixed with the stage file.
std::string rewriteLogLine(std::string_view line, const std::vector<std::string>& files) {
  const auto fileName = [&](std::size_t s) {
    return s < files.size() ? shown(files[s]) : shown(files.front()) + " (source string " + std::to_string(s) + ")";
  };
  std::size_t pos = 0, s = 0, l = 0, c = 0;
  std::string prefix;  // "ERROR: " style severity, moved after the location
  if (consume(line, &pos, "ERROR: "))
    prefix = "error: ";
  else if (consume(line, &pos, "WARNING: "))
    prefix = "warning: ";
  const std::size_t afterPrefix = pos;
  if (parseNumber(line, &pos, &s)) {
    std::size_t p = pos;
    // Mesa: 0:12(5): error: ...
    if (consume(line, &p, ":") && parseNumber(line, &p, &l) && consume(line, &p, "(") && parseNumber(line, &p, &c) &&
        consume(line, &p, "): "))
      return fileName(s) + ":" + std::to_string(l) + ":" + std::to_string(c) + ": " + prefix +
             std::string(line.substr(p));
    // NVIDIA: 0(12) : error C1008: ...
    p = pos;
    if (consume(line, &p, "(") && parseNumber(line, &p, &l) && consume(line, &p, ")") &&
        (consume(line, &p, " : ") || consume(line, &p, ": ")))
      return fileName(s) + ":" + std::to_string(l) + ": " + prefix + std::string(line.substr(p));
    // AMD, Intel on Windows, ANGLE: ERROR: 0:12: ...
    p = pos;
    if (consume(line, &p, ":") && parseNumber(line, &p, &l) && consume(line, &p, ": "))
      return fileName(s) + ":" + std::to_string(l) + ": " + prefix + std::string(line.substr(p));
  }
  return shown(files.front()) + ": " + prefix + std::string(line.substr(afterPrefix));
}

/// One line per problem, errors ahead of warnings so the first line says what broke.
std::vector<std::string> logProblems(const std::string& log, const std::vector<std::string>& files,
                                     const std::string& fallback) {
  std::vector<std::string> problems;
  for (std::string line : splitLines(log)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == '\0' || line.back() == ' ')) line.pop_back();
    if (!trimLeft(line).empty()) problems.push_back(rewriteLogLine(line, files));
  }
  std::stable_partition(problems.begin(), problems.end(), [](const std::string& p) {
    std::string lowered = p;
    std::transform(lowered.begin(), lowered.end(), lowered.begin(), [](unsigned char ch) { return std::tolower(ch); });
    return lowered.find("error") != std::string::npos;
  });
  if (problems.empty()) problems.push_back(fallback);
  return problems;
}

std::string shaderLog(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, static_cast<GLsizei>(log.size()), nullptr, log.data());
  return log;
}

std::string programLog(GLuint program) {
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetProgramInfoLog(program, static_cast<GLsizei>(log.size()), nullptr, log.data());
  return log;
}

std::string join(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += (out.empty() ? "" : "\n") + l;
  return out;
}

}  // namespace

std::string rewriteShaderLog(const std::string& log, const std::vector<std::string>& files) {
  PUFF_CHECK(!files.empty());
  const std::vector<std::string> problems = logProblems(log, files, "");
  return problems.size() == 1 && problems.front().empty() ? std::string() : join(problems);
}

void setShaderDir(const fs::path& dir) {
  std::lock_guard lock(gDirMutex);
  if (dir.empty())
    gDirOverride.reset();
  else
    gDirOverride = dir;
}

fs::path shaderDir() {
  {
    std::lock_guard lock(gDirMutex);
    if (gDirOverride) return *gDirOverride;
  }
  return environmentDir();
}

Result<std::string> shaderFileSource(const std::string& name) {
  const fs::path dir = shaderDir();
  const std::optional<std::string> normal = normalizeName(name);
  if (!normal) return notFound(name, dir);
  if (dir.empty()) {
    for (const EmbeddedFile* f = embeddedShaders(); f->name != nullptr; ++f)
      if (*normal == f->name) return std::string(f->data, f->size);
    return notFound(*normal, dir);
  }
  std::error_code ec;
  const fs::path path = dir / *normal;
  if (!fs::is_regular_file(path, ec)) return notFound(*normal, dir);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) return Error::at(path, "cannot read shader file");
  return text.str();
}

Result<std::string> preprocessShader(const std::string& name, std::vector<std::string>* files) {
  Preprocessor pre;
  Result<std::string> out = pre.run(name);
  if (files != nullptr) *files = std::move(pre.files);
  return out;
}

std::vector<std::string> listShaderFiles() {
  std::vector<std::string> names;
  const fs::path dir = shaderDir();
  if (dir.empty()) {
    for (const EmbeddedFile* f = embeddedShaders(); f->name != nullptr; ++f) names.emplace_back(f->name);
  } else {
    std::error_code ec;
    for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      if (!it->is_regular_file(ec)) continue;
      const std::string name = it->path().lexically_relative(dir).generic_string();
      if (isShaderFileName(name)) names.push_back(name);  // skips editor backups, READMEs
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::pair<std::string, std::vector<std::string>>> listShaderPrograms() {
  std::map<std::string, std::vector<std::string>> programs;
  for (const std::string& name : listShaderFiles()) {
    if (name.starts_with("common/") || !stageIndex(name)) continue;
    const std::string stem = (fs::path(name).parent_path() / fs::path(name).stem()).generic_string();
    programs[stem].push_back(name);
  }
  std::vector<std::pair<std::string, std::vector<std::string>>> out;
  for (auto& [stem, stages] : programs) {
    std::sort(stages.begin(), stages.end(),
              [](const std::string& a, const std::string& b) { return *stageIndex(a) < *stageIndex(b); });
    out.emplace_back(stem, std::move(stages));
  }
  return out;
}

Result<Program> buildProgram(const std::vector<std::string>& stageFiles) {
  if (stageFiles.empty()) return Error{"buildProgram: no stage files given"};
  if (puff_glad_glCreateShader == nullptr)
    return Error{
        "buildProgram: Puff's GL functions are not loaded: make a GL 4.5 context current and call "
        "puff::core::initGl(getProcAddress)"};

  std::vector<ShaderObject> shaders;
  std::vector<std::string> problems;
  for (const std::string& file : stageFiles) {
    const std::optional<std::size_t> stage = stageIndex(file);
    if (!stage) {
      problems.push_back(shown(file) + ": not a shader stage (use .vert .tesc .tese .geom .frag .comp)");
      continue;
    }
    std::vector<std::string> files;
    Result<std::string> source = preprocessShader(file, &files);
    if (!source) {
      problems.push_back(source.error().message);
      continue;
    }
    ShaderObject shader(glCreateShader(kStages[*stage].type));
    const char* text = source->c_str();
    const GLint length = static_cast<GLint>(source->size());
    glShaderSource(shader.get(), 1, &text, &length);
    glCompileShader(shader.get());
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.get(), GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
      for (std::string& p : logProblems(shaderLog(shader.get()), files, shown(file) + ": compile failed (no log)"))
        problems.push_back(std::move(p));
      continue;
    }
    shaders.push_back(std::move(shader));
  }
  if (!problems.empty()) return Error{join(problems)};

  Program program(glCreateProgram());
  for (const ShaderObject& s : shaders) glAttachShader(program.get(), s.get());
  glLinkProgram(program.get());
  for (const ShaderObject& s : shaders) glDetachShader(program.get(), s.get());
  GLint ok = GL_FALSE;
  glGetProgramiv(program.get(), GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    std::string names;
    for (const std::string& f : stageFiles) names += (names.empty() ? "" : " + ") + shown(f);
    std::vector<std::string> lines;
    for (std::string line : splitLines(programLog(program.get()))) {
      while (!line.empty() && (line.back() == '\r' || line.back() == '\0' || line.back() == ' ')) line.pop_back();
      if (!trimLeft(line).empty()) lines.push_back("link " + names + ": " + line);
    }
    if (lines.empty()) lines.push_back("link " + names + ": failed (no log)");
    return Error{join(lines)};
  }
  std::string names;
  for (const std::string& f : stageFiles) names += (names.empty() ? "" : " + ") + f;
  labelObject(GL_PROGRAM, program.get(), names);
  return program;
}

}  // namespace puff::core
