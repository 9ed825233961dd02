// Wall time for the stats and budgets Puff reports: milliseconds on the steady clock.
#pragma once

#include <chrono>

namespace puff::core {

using Clock = std::chrono::steady_clock;

/// Milliseconds of wall time from `start` to now.
inline double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace puff::core
