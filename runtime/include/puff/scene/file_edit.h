// Saving an edited scene into the artist's own file: only what the edit changed is rewritten.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include <puff/core/error.h>

namespace puff::scene {

/// The text of a scene file after an edit, changed only where the scene changed. `text` is the file
/// as read; `before` is toJson of the scene read from it, `after` toJson of the edited scene. A
/// value that differs is rewritten where it stands (in the style of its place: on one line where
/// the file had it on one line); a field `after` has and the file leaves out (a default the edit
/// moved, a new field) goes at the end of its object; a field `after` no longer has is taken out
/// with its comma. Every other byte of `text` stays: the file's key order, spacing and line breaks,
/// its spellings ("#fff" for [1, 1, 1]) and the fields it leaves at their defaults; new lines end
/// and indent as the file's do.
/// Errors: `text` is not JSON (or holds a number past a double's range), not an object, or nested
/// more than 128 arrays and objects deep.
Result<std::string> editSceneText(const std::string& text, const nlohmann::json& before, const nlohmann::json& after);

}  // namespace puff::scene
