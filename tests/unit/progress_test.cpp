// The tools' progress lines (cli/progress.h): what they say (elapsed time, rate, time left) and when
// they say it, on a terminal and in a log, against a clock the test moves.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include <cli/app.h>
#include <cli/progress.h>

namespace puff::cli {
namespace {

TEST(ProgressText, DurationsReadAsAPersonWouldSayThem) {
  EXPECT_EQ(formatDuration(0.0), "0.0 s");
  EXPECT_EQ(formatDuration(1.44), "1.4 s");
  EXPECT_EQ(formatDuration(9.94), "9.9 s");
  EXPECT_EQ(formatDuration(9.96), "10 s");
  EXPECT_EQ(formatDuration(12.5), "13 s");  // halves round up
  EXPECT_EQ(formatDuration(59.4), "59 s");
  EXPECT_EQ(formatDuration(59.6), "1 min 00 s");
  EXPECT_EQ(formatDuration(185.0), "3 min 05 s");
  EXPECT_EQ(formatDuration(3725.0), "1 h 02 min");
  EXPECT_EQ(formatDuration(-3.0), "0.0 s");
}

TEST(ProgressText, SaysDoneTotalElapsedRateAndTimeLeft) {
  // 30 of 120 in 12 s: 2.5 per second, 90 left take 36 s.
  EXPECT_EQ(formatProgress("frames", 30, 120, 12.0), "frames 30/120 (25%), 12 s, 2.5/s, about 36 s left");
  // Fast work: a whole number per second.
  EXPECT_EQ(formatProgress("rasterizing", 38, 75, 2.0), "rasterizing 38/75 (50%), 2.0 s, 19/s, about 1.9 s left");
  // Slow work: seconds each. 2 of 72 frames in 9 s: 4.5 s each, 70 left take 5 min 15 s.
  EXPECT_EQ(formatProgress("frames", 2, 72, 9.0), "frames 2/72 (2%), 9.0 s, 4.5 s each, about 5 min 15 s left");
  // Nothing done yet: no rate, no time left. All done: the rate, nothing left.
  EXPECT_EQ(formatProgress("loading meshes", 0, 3, 0.0), "loading meshes 0/3 (0%), 0.0 s");
  EXPECT_EQ(formatProgress("writing", 20, 20, 4.0), "writing 20/20 (100%), 4.0 s, 5.0/s");
  // A stage first heard of with 5 done: the rate counts the steps since (15 in 3 s).
  EXPECT_EQ(formatProgress("writing", 20, 40, 3.0, 5), "writing 20/40 (50%), 3.0 s, 5.0/s, about 4.0 s left");
  // An unknown total: the count alone.
  EXPECT_EQ(formatProgress("steps", 7, 0, 1.0), "steps 7, 1.0 s, 7.0/s");
}

// A Progress writing to a temporary file, with a clock the test sets.
struct Recorder {
  explicit Recorder(bool terminal) : file(std::tmpfile()), progress(false, file, terminal, [this] { return now; }) {}
  ~Recorder() { std::fclose(file); }
  std::string text() {
    std::fflush(file);
    std::rewind(file);
    std::string s;
    char b[4096];
    std::size_t n;
    while ((n = std::fread(b, 1, sizeof b, file)) > 0) s.append(b, n);
    return s;
  }
  std::vector<std::string> lines() {
    std::vector<std::string> out;
    std::string s = text(), line;
    for (char c : s) {
      if (c == '\n') {
        out.push_back(line);
        line.clear();
      } else {
        line += c;
      }
    }
    if (!line.empty()) out.push_back(line);
    return out;
  }
  double now = 0.0;
  std::FILE* file;
  Progress progress;
};

TEST(ProgressLines, WorkThatEndsWithinASecondShowsNothing) {
  for (bool terminal : {false, true}) {
    Recorder r(terminal);
    for (int i = 0; i <= 10; ++i) {
      r.now = 0.09 * i;
      r.progress("rasterizing", i, 10);
    }
    r.progress.finish();
    EXPECT_EQ(r.text(), "") << "terminal " << terminal;
  }
}

TEST(ProgressLines, ALogGetsPlainLinesAtTheStartEachQuarterTheEndAndEveryTenSeconds) {
  Recorder r(false);
  // 100 frames, 0.5 s each: the first second is quiet, then a line at frame 2, each quarter, the
  // end, and one ten seconds after the last line where no quarter fell.
  for (int i = 0; i <= 100; ++i) {
    r.now = 0.5 * i;
    r.progress("frames", i, 100);
  }
  const std::vector<std::string> lines = r.lines();
  const std::string name = std::string(cli::name()) + ": ";
  std::vector<std::string> expected = {
      "frames 2/100 (2%), 1.0 s, 2.0/s, about 49 s left",
      "frames 22/100 (22%), 11 s, 2.0/s, about 39 s left",  // ten seconds on
      "frames 25/100 (25%), 13 s, 2.0/s, about 38 s left",  // a quarter
      "frames 45/100 (45%), 23 s, 2.0/s, about 28 s left",  "frames 50/100 (50%), 25 s, 2.0/s, about 25 s left",
      "frames 70/100 (70%), 35 s, 2.0/s, about 15 s left",  "frames 75/100 (75%), 38 s, 2.0/s, about 13 s left",
      "frames 95/100 (95%), 48 s, 2.0/s, about 2.5 s left", "frames 100/100 (100%), 50 s, 2.0/s",
  };
  ASSERT_EQ(lines.size(), expected.size()) << r.text();
  for (std::size_t i = 0; i < lines.size(); ++i) EXPECT_EQ(lines[i], name + expected[i]);
  EXPECT_EQ(r.text().find('\r'), std::string::npos);
}

TEST(ProgressLines, ANewStageStartsItsOwnClockAndSaysSo) {
  Recorder r(false);
  r.now = 5.0;  // past the first second
  r.progress("rasterizing", 0, 4);
  r.now = 7.0;
  r.progress("rasterizing", 4, 4);
  r.progress("writing", 0, 2);
  r.now = 8.0;
  r.progress("writing", 2, 2);
  const std::string name = std::string(cli::name()) + ": ";
  const std::vector<std::string> lines = r.lines();
  ASSERT_EQ(lines.size(), 4u) << r.text();
  EXPECT_EQ(lines[0], name + "rasterizing 0/4 (0%), 0.0 s");
  EXPECT_EQ(lines[1], name + "rasterizing 4/4 (100%), 2.0 s, 2.0/s");
  EXPECT_EQ(lines[2], name + "writing 0/2 (0%), 0.0 s");
  EXPECT_EQ(lines[3], name + "writing 2/2 (100%), 1.0 s, 2.0/s");
}

TEST(ProgressLines, ATerminalGetsOneLineRewrittenInPlaceAndKeptWhenAStageEnds) {
  Recorder r(true);
  for (int i = 0; i <= 40; ++i) {  // 1/16 s apart: at most ten updates a second
    r.now = 1.0 + 0.0625 * i;
    r.progress("frames", i, 40);
  }
  r.now = 4.0;
  r.progress("writing", 1, 3);
  r.progress.finish();
  const std::string t = r.text();
  // Every update starts at the line's start and clears what a longer one left.
  const auto count = [&](const std::string& needle) {
    std::size_t n = 0;
    for (std::size_t at = t.find(needle); at != std::string::npos; at = t.find(needle, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("\r"), count("\x1b[K"));
  EXPECT_EQ(count("\r"), 22u) << t;  // every other of 41 calls, and the writing stage's one
  // The finished stage keeps its line; the stage left unfinished is ended by finish().
  EXPECT_NE(t.find("frames 40/40 (100%), 2.5 s, 16/s\x1b[K\n"), std::string::npos) << t;
  EXPECT_NE(t.find("writing 1/3 (33%), 0.0 s\x1b[K\n"), std::string::npos) << t;
  EXPECT_EQ(t.back(), '\n');

  // A stage that reaches its end ends its line at once, before anything else is printed.
  Recorder ended(true);
  ended.now = 5.0;
  ended.progress("writing", 0, 2);
  ended.now = 6.0;
  ended.progress("writing", 2, 2);
  EXPECT_EQ(ended.text().back(), '\n') << ended.text();
}

TEST(ProgressLines, AnnounceShowsASlowPhaseAtOnceAndQuietShowsNothing) {
  Recorder r(false);
  r.progress.announce("loading meshes", 3);
  const std::string name = std::string(cli::name()) + ": ";
  EXPECT_EQ(r.text(), name + "loading meshes 0/3 (0%), 0.0 s\n");

  std::FILE* f = std::tmpfile();
  {
    Progress quiet(true, f, false, [] { return 100.0; });
    quiet.announce("loading meshes", 3);
    quiet("loading meshes", 3, 3);
  }
  EXPECT_EQ(std::ftell(f), 0L);
  std::fclose(f);
}

}  // namespace
}  // namespace puff::cli
