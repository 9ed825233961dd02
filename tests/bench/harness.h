// What the benchmarks share: the clock, timed runs after warm-up runs and their median, the one
// splitmix64 generator their particles come from, and the CSV written to stdout or to a file.
// Header-only; every benchmark links puff_core. Not a test: nothing here fails on a time.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <puff/core/files.h>

#include <puff/core/random.h>
#include <puff/support/statistics.h>

namespace puff::bench {

using Clock = std::chrono::steady_clock;

/// Milliseconds from `t0` to `t1`.
inline double msBetween(Clock::time_point t0, Clock::time_point t1) {
  return std::chrono::duration<double, std::milli>(t1 - t0).count();
}
/// Milliseconds from `t0` to now.
inline double msSince(Clock::time_point t0) { return msBetween(t0, Clock::now()); }

using core::median;  // the median of a run's times

/// Runs `run()` `warmUp` + `reps` times, each run timed alone, and returns the last `reps` times (ms).
template <class Run>
std::vector<double> timeRuns(int warmUp, int reps, Run&& run) {
  std::vector<double> times;
  for (int r = 0; r < warmUp + reps; ++r) {
    const auto t0 = Clock::now();
    run();
    const double ms = msSince(t0);
    if (r >= warmUp) times.push_back(ms);
  }
  return times;
}

/// Whether a time can stand against its fill-rate floor (the same work with the fragment stage
/// doing the minimum): true without a floor (floorMs <= 0) or when it is not faster than the floor.
/// A run faster than its floor measured noise or a floor that is not one; its row is marked
/// invalid (CSV `valid` 0) and gets no ratio.
/// A work directory removed (with what is in it) when the scope ends, errors ignored.
struct ScopedDir {
  std::filesystem::path dir;
  ~ScopedDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

inline bool validAgainstFloor(double ms, double floorMs) { return !(floorMs > 0.0) || ms >= floorMs; }
/// ms / floorMs as CSV text ("%.3f"), empty without a floor or when the run is below it.
inline std::string ratioToFloor(double ms, double floorMs) {
  if (!(floorMs > 0.0) || !validAgainstFloor(ms, floorMs)) return {};
  char b[32];
  std::snprintf(b, sizeof b, "%.3f", ms / floorMs);
  return b;
}

/// splitmix64 (Steele, Lea and Flood 2014): the next value of the sequence that starts at `state`.
inline std::uint64_t splitmix64(std::uint64_t& state) {
  state += core::kGoldenGamma;
  return core::mix64(state);
}
/// Uniform in [lo, hi): the top 24 bits of the next splitmix64 value as a float fraction.
inline float uniform(std::uint64_t& state, float lo, float hi) {
  return lo + (hi - lo) * static_cast<float>(splitmix64(state) >> 40) / 16777216.0f;
}

/// Appends printf-style text (a CSV line) to `out`.
[[gnu::format(printf, 2, 3)]] inline void appendf(std::string& out, const char* format, ...) {
  std::va_list args;
  va_start(args, format);
  std::va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  if (n > 0) {
    const std::size_t at = out.size();
    out.resize(at + static_cast<std::size_t>(n) + 1);
    std::vsnprintf(out.data() + at, static_cast<std::size_t>(n) + 1, format, again);
    out.resize(at + static_cast<std::size_t>(n));
  }
  va_end(again);
}

/// Writes `csv` to `path` (atomically), or to stdout when `path` is empty. A failure is printed as
/// "TOOL: error: ..." and returns false.
inline bool writeCsv(const char* tool, const std::string& path, const std::string& csv) {
  if (path.empty()) {
    std::fputs(csv.c_str(), stdout);
    return true;
  }
  if (auto w = core::writeFileAtomic(path, csv); !w) {
    std::fprintf(stderr, "%s: error: %s\n", tool, w.error().message.c_str());
    return false;
  }
  return true;
}

}  // namespace puff::bench
