// Reading a scene file: every value checked, every problem reported at its JSON pointer.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include <puff/core/error.h>
#include <puff/scene/scene.h>

namespace puff::scene {

/// Parses and validates. Errors read "FILE: /json/pointer: what was expected" (JSON syntax errors:
/// "FILE:LINE:COLUMN: ..."). Unknown keys are errors too (a typo must not be silently ignored).
/// `artDir` replaces a leading "${PUFF_ART}" in paths.
Result<Scene> parseScene(const nlohmann::json& j, const std::filesystem::path& file,
                         const std::filesystem::path& artDir = {});
/// `text`, when given, receives the file's text as read, once the scene loads (what an editor saves
/// its edits into: scene/file_edit.h).
Result<Scene> loadScene(const std::filesystem::path& file, const std::filesystem::path& artDir = {},
                        std::string* text = nullptr);

}  // namespace puff::scene
