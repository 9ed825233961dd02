// The puffrender tests' fixture: puffrender run in a scratch folder, and a scene that needs no atlas.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "support/cli_test.h"

namespace puff::puffrender_cli_test {

namespace fs = std::filesystem;
using puff::test::CliRun;

// A ground plane and a ball: renders without an atlas.
inline constexpr const char* kGroundScene = R"({
  "output": {"width": 40, "height": 30, "samples": 1, "background": "#336699"},
  "camera": {"position": [0, 3, 6], "target": [0, 0.5, 0]},
  "objects": [{"type": "plane", "scale": [4, 1, 4]}, {"type": "sphere", "translate": [0, 1, 0]}],
  "animation": {"fps": 10, "frames": 4, "orbit": 30}
})";

class PuffrenderCli : public puff::test::CliTest {
 protected:
  PuffrenderCli() : CliTest(PUFFRENDER_EXE, "puffrender") {}

  // Files in dir_ other than the scenes the test wrote.
  std::vector<std::string> outputs() {
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir_.path())) {
      if (e.path().extension() != ".json") names.push_back(fs::relative(e.path(), dir_.path()).string());
    }
    std::sort(names.begin(), names.end());
    return names;
  }
};

}  // namespace puff::puffrender_cli_test
