// Progress of long work (a bake, a sequence of frames) on stderr, for the tools' users: what is being
// done, how far along, how long it has taken, how fast it goes and when it will end.
//
// On a terminal it is one line, rewritten in place (at most ten times a second); in a log (stderr not
// a terminal) it is plain lines: when a stage starts, at each quarter, at its end, and at least every
// ten seconds. Nothing is shown for work that ends within a second, unless asked for (announce).
#pragma once

#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>

namespace puff::cli {

/// "1.4 s", "3 min 05 s", "1 h 02 min": a duration for a person to read.
std::string formatDuration(double seconds);

/// The text of one progress line (without the app's name): "rasterizing 38/75 (50%), 3.4 s, 11/s,
/// about 3.3 s left". `elapsed`: seconds since the stage was first heard of, with `doneThen` steps
/// done; the rate and the time left come from the steps done since (left out until one is, and the
/// time left once all are).
std::string formatProgress(std::string_view stage, long long done, long long total, double elapsed,
                           long long doneThen = 0);

class Progress {
 public:
  using Clock = std::function<double()>;  ///< seconds, monotonic

  /// `quiet`: show nothing. `terminal`: stderr is a terminal (one line rewritten in place).
  explicit Progress(bool quiet);
  /// For tests: where the lines go, whether that is a terminal, and the clock.
  Progress(bool quiet, std::FILE* out, bool terminal, Clock clock);
  ~Progress() { finish(); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// `done` of `total` steps of `stage` are done. A new stage name starts a new stage (its rate and
  /// time left are its own).
  void operator()(std::string_view stage, long long done, long long total);
  /// Shows `stage` at once, even within the first second: for a phase known to be slow before it
  /// has anything to count (loading large meshes).
  void announce(std::string_view stage, long long total);
  /// Ends a line left open on a terminal, so that what is printed next starts on its own line.
  void finish();

 private:
  void show(double now, long long done, long long total);

  bool quiet_, terminal_;
  std::FILE* out_;
  Clock clock_;
  double start_ = 0.0, stageStart_ = 0.0, lastShown_ = -1e30;
  std::string stage_;
  long long stageDone_ = 0;  ///< steps done when the stage was first heard of
  int lastQuarter_ = -1;
  bool open_ = false, anyShown_ = false, announced_ = false;
};

}  // namespace puff::cli
