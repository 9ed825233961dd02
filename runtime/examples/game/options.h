// puff_game's command line: its options, checked before any window opens, and how it reports a
// failure (one line on stderr).
#pragma once

#include <filesystem>
#include <string>

struct Options {
  std::filesystem::path atlas;       // the sidecar (DIR/puff.json, or a .json given directly)
  std::filesystem::path screenshot;  // empty: interactive
  int frames = 60, width = 960, height = 540;
};

// Prints "puff_game: WHAT" on stderr; returns 1, the exit status of a failure.
int fail(const std::string& what);

// Returns 0 to run, 1 on bad input (message printed), -1 for --help.
int parseOptions(int argc, char** argv, Options& o);
