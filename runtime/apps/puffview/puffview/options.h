// puffview's command line: parsing into one Options value, and the one call that runs it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace puff::view {

struct Options {
  std::filesystem::path scene;
  /// Batch mode: show frames first..last, then exit ("N": 0..N-1; "A-B": A..B).
  std::optional<std::pair<int, int>> frames;
  bool framesRange = false;  ///< given as A-B, not as a count N (both are checked against the scene's frames)
  /// Batch mode: save the window after the last frame to this file, or, when it holds a frame-number
  /// pattern (shot_####.png), after every frame to its numbered file.
  std::string screenshot;
  bool hideUi = false;                  ///< start with the panels hidden (H shows them)
  std::optional<int> width, height;     ///< window size; default the scene's output size
  std::filesystem::path artDir;         ///< replaces "${PUFF_ART}" in the scene's paths
  std::filesystem::path shaderDir;      ///< read (and watch) shaders here
  std::filesystem::path screenshotDir;  ///< where P / F12 put screenshots; default beside the scene
  std::string path = "cel";             ///< render path
  bool quiet = false;
};

/// Parses argv. Returns the Options, or an exit code when parsing ended the run (--help: 0, bad
/// usage: 2, after printing why).
std::variant<Options, int> parse(int argc, char** argv);

/// Runs the viewer; returns the exit code (0 success, 1 failure).
int run(const Options& options);

}  // namespace puff::view
