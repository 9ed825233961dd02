// Shader programs from files under shaders/, one stage per file, embedded into the binaries at
// build time. `#include "common/x.glsl"` (path relative to the shaders/ root) is resolved by a
// small include step that emits `#line` directives, so a compile error names the real file and
// line: "shaders/bake/puff.frag:12: error: ...". A directory override (setShaderDir or the
// PUFF_SHADER_DIR environment variable) reads the files from disk instead, for live editing.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <puff/core/error.h>
#include <puff/core/gl.h>

namespace puff::core {

/// Reads shaders from DIR (the shaders/ root) instead of the embedded copies; empty restores the
/// default (PUFF_SHADER_DIR if set, else embedded).
void setShaderDir(const std::filesystem::path& dir);
/// The directory shaders are read from, or empty when embedded copies are used.
std::filesystem::path shaderDir();

/// The source of one shader file, e.g. "bake/puff.frag", with includes not yet resolved.
Result<std::string> shaderFileSource(const std::string& name);

/// The source with includes resolved and #line directives inserted. `files` receives the file
/// names in the order of their #line source-string numbers (index 0 is `name`).
Result<std::string> preprocessShader(const std::string& name, std::vector<std::string>* files = nullptr);

/// Names of all shader files available (embedded, or under the override directory), sorted.
std::vector<std::string> listShaderFiles();

/// A program built from stage files, e.g. {"bake/puff.vert", "bake/puff.frag"}. The stage comes
/// from the extension: .vert .frag .geom .comp .tesc .tese. A compile or link error is one
/// message naming each file and line the driver complained about.
Result<Program> buildProgram(const std::vector<std::string>& stageFiles);

/// Rewrites a driver's compile log so that each location "S:L" (source string S, as numbered by
/// preprocessShader's `files`) reads "shaders/<files[S]>:L". Knows Mesa ("0:12(5): error: ..."),
/// NVIDIA ("0(12) : error C1008: ...") and "ERROR: 0:12: ..." logs; other lines are prefixed with
/// files[0]. One line per problem, errors before warnings; "" for an empty log. `files` must not
/// be empty. buildProgram uses this; it is public so the formats can be tested without each driver.
std::string rewriteShaderLog(const std::string& log, const std::vector<std::string>& files);

/// Every program the shaders directory defines: files sharing a path without extension form one
/// program ("bake/puff.vert" + "bake/puff.frag" -> "bake/puff"). Files under common/ are
/// includes only. Returns program names with their stage files.
std::vector<std::pair<std::string, std::vector<std::string>>> listShaderPrograms();

}  // namespace puff::core
