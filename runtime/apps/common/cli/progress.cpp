#include "cli/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "cli/app.h"

namespace puff::cli {

std::string formatDuration(double seconds) {
  char b[48];
  seconds = std::max(0.0, seconds);
  if (seconds < 9.95) {
    std::snprintf(b, sizeof b, "%.1f s", seconds);
  } else if (seconds < 59.5) {
    std::snprintf(b, sizeof b, "%ld s", std::lround(seconds));
  } else if (seconds < 3600.0 - 0.5) {
    const long s = std::lround(seconds);
    std::snprintf(b, sizeof b, "%ld min %02ld s", s / 60, s % 60);
  } else {
    const long m = std::lround(seconds / 60.0);
    std::snprintf(b, sizeof b, "%ld h %02ld min", m / 60, m % 60);
  }
  return b;
}

std::string formatProgress(std::string_view stage, long long done, long long total, double elapsed,
                           long long doneThen) {
  std::string s(stage);
  char b[96];
  if (total > 0) {
    done = std::clamp(done, 0LL, total);
    std::snprintf(b, sizeof b, " %lld/%lld (%lld%%)", done, total, 100 * done / total);
  } else {
    std::snprintf(b, sizeof b, " %lld", std::max(done, 0LL));
  }
  s += b;
  s += ", " + formatDuration(elapsed);
  const long long counted = done - std::clamp(doneThen, 0LL, done);
  if (counted > 0 && elapsed > 0.0) {
    const double rate = static_cast<double>(counted) / elapsed;
    if (rate >= 9.95) {
      std::snprintf(b, sizeof b, ", %.0f/s", rate);
    } else if (rate >= 0.995) {
      std::snprintf(b, sizeof b, ", %.1f/s", rate);
    } else {
      std::snprintf(b, sizeof b, ", %s each", formatDuration(elapsed / static_cast<double>(counted)).c_str());
    }
    s += b;
    const double left = total > 0 && done < total ? static_cast<double>(total - done) / rate : 0.0;
    if (left >= 0.05) s += ", about " + formatDuration(left) + " left";
  }
  return s;
}

namespace {
double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

Progress::Progress(bool quiet) : Progress(quiet, stderr, ::isatty(2) != 0, steadySeconds) {}

Progress::Progress(bool quiet, std::FILE* out, bool terminal, Clock clock)
    : quiet_(quiet), terminal_(terminal), out_(out), clock_(std::move(clock)) {
  start_ = stageStart_ = clock_();
}

void Progress::finish() {
  if (open_) std::fputc('\n', out_), std::fflush(out_);
  open_ = false;
}

void Progress::announce(std::string_view stage, long long total) {
  if (quiet_) return;
  announced_ = true;
  (*this)(stage, 0, total);
}

void Progress::operator()(std::string_view stage, long long done, long long total) {
  if (quiet_) return;
  const double now = clock_();
  const bool newStage = stage != stage_;
  if (newStage) {
    // A terminal line left on a stage that did not reach its end is ended, so that it stays readable.
    finish();
    stage_ = std::string(stage);
    stageStart_ = now;
    stageDone_ = done;
    lastQuarter_ = -1;
    lastShown_ = -1e30;
  }
  if (!anyShown_ && !announced_ && now - start_ < 1.0) return;  // work that ends within a second shows nothing
  const bool end = total > 0 && done >= total;
  const int quarter = total > 0 ? static_cast<int>(4 * std::clamp(done, 0LL, total) / total) : 0;
  bool due;
  if (terminal_) {
    due = newStage || lastShown_ < -1e29 || end || now - lastShown_ >= 0.1;
  } else {
    due = lastShown_ < -1e29 || end || quarter != lastQuarter_ || now - lastShown_ >= 10.0;
  }
  if (!due) return;
  show(now, done, total);
  lastQuarter_ = quarter;
  if (end && terminal_) finish();  // a finished stage keeps its line
}

void Progress::show(double now, long long done, long long total) {
  const std::string text = formatProgress(stage_, done, total, now - stageStart_, stageDone_);
  if (terminal_) {
    // "\x1b[K" clears what a longer previous line left on the right.
    std::fprintf(out_, "\r%s: %s\x1b[K", name(), text.c_str());
    open_ = true;
  } else {
    std::fprintf(out_, "%s: %s\n", name(), text.c_str());
  }
  std::fflush(out_);
  lastShown_ = now;
  anyShown_ = true;
}

}  // namespace puff::cli
