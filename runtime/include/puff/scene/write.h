// Writing a scene back as JSON: every field, in the form the reader takes back unchanged.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include <puff/scene/scene.h>

namespace puff::scene {

/// The scene written back as JSON (every field): every default shown, or an editor's save.
nlohmann::json toJson(const Scene& scene);
/// JSON as a person writes it (a tool printing a scene, an editor's save): one key per line, arrays
/// of numbers ([x, y, z]) on one line. No trailing newline.
std::string jsonText(const nlohmann::json& j);

}  // namespace puff::scene
