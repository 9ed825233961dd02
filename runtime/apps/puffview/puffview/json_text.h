// JSON as a person writes it, for saved scenes: one key per line, arrays of numbers on one line.
// (The same layout as puffrender --print-scene.)
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace puff::view {

std::string jsonText(const nlohmann::json& j);

}  // namespace puff::view
