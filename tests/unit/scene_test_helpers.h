// What the scene tests share (scene_test.cpp, scene_evaluate_test.cpp): the file the scenes are
// read as, and a scene read from JSON text that must read.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <puff/scene/read.h>
#include <puff/scene/scene.h>

#include "support/assert_ok.h"

namespace puff::test {

// The scene file every test reads its text as: relative paths resolve against its directory.
inline const std::filesystem::path kFile = "art/scenes/x.json";

// The scene `text` gives, read as kFile with `artDir`; an error fails the test and gives an empty
// scene.
inline scene::Scene parseOk(const std::string& text, const std::filesystem::path& artDir = {}) {
  auto s = scene::parseScene(nlohmann::json::parse(text), kFile, artDir);
  EXPECT_OK(s);
  return s.ok() ? *s : scene::Scene{};
}

}  // namespace puff::test
