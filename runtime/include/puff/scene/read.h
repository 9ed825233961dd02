// Reading a scene file: every value checked, every problem reported at its JSON pointer.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include <puff/core/error.h>
#include <puff/scene/scene.h>

namespace puff::scene {

/// Parses and validates. Errors read "FILE: /json/pointer: what was expected" (JSON syntax errors:
/// "FILE:LINE:COLUMN: ..."). Unknown keys are errors too (a typo must not be silently ignored).
/// `artDir` replaces a leading "${PUFF_ART}" in paths.
Result<Scene> parseScene(const nlohmann::json& j, const std::filesystem::path& file,
                         const std::filesystem::path& artDir = {});
Result<Scene> loadScene(const std::filesystem::path& file, const std::filesystem::path& artDir = {});

}  // namespace puff::scene
