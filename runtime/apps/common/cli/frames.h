// What puffrender and puffview share about sequences: which frames ("N" or "A-B") and where each goes
// (a file name with one frame-number pattern).
#pragma once

#include <string>
#include <utility>

#include <puff/core/error.h>

namespace puff::cli {

/// Where frame N goes: a name with its one "%d", "%0Nd" or run of '#' replaced by the number
/// (zero-padded to the run's length).
struct OutputPattern {
  std::string prefix, suffix;
  int digits = 0;         ///< zero-padding width; 0 = none
  bool numbered = false;  ///< false: every frame goes to `prefix` (a single file)
  std::string name(int frame) const;
};
/// Errors (as text for a usage message, starting "FLAG NAME: ") for more than one pattern in `out`.
Result<OutputPattern> parseOutputPattern(const std::string& out, const std::string& flag = "-o");

/// "N" or "A-B" (inclusive, A <= B, non-negative); errors name `flag`.
Result<std::pair<int, int>> parseFrameRange(const std::string& text, const std::string& flag = "--frames");

}  // namespace puff::cli
