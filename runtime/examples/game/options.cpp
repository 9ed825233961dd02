// puff_game's command line (options.h).
#include "options.h"

#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <string_view>
#include <system_error>

int fail(const std::string& what) {
  std::fprintf(stderr, "puff_game: %s\n", what.c_str());
  return 1;
}

namespace {

constexpr const char* kHelp =
    "puff_game: a small GLFW game scene with Puff's cel smoke (from the simulator)"
#if GAME_MEDIA_FIRE
    " and media fire"
#endif
    " drawn into the game's own frame.\n"
    "Usage: puff_game --atlas DIR [--screenshot FILE.png [--frames N]] [--width W] [--height H]\n"
    "  --atlas DIR          a cooked atlas: DIR/puff.json (or the sidecar .json itself), e.g. from\n"
    "                       `puffbake bake -g lumpy -o baked`, then\n"
    "                       `puffbake cook baked/puff.json -o DIR/puff.json`; required. The game\n"
    "                       links no image library, so it reads cooked atlases (.puffimg maps) only\n"
    "  --screenshot FILE    render --frames frames at a fixed 1/60 s step, write the last one as an\n"
    "                       8-bit sRGB PNG and exit; without it the window runs until closed (Esc)\n"
    "  --frames N           frames before the screenshot, >= 1 (default 60)\n"
    "  --width W, --height H  the frame in pixels, 16..8192 (default 960 x 540)\n"
    "  --help               this text\n"
    "Needs a display (X11 or Xvfb: xvfb-run -a puff_game ...) and GL 4.5.\n";

bool parseInt(std::string_view s, int lo, int hi, int& out) {
  int v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc{} || end != s.data() + s.size() || v < lo || v > hi) return false;
  out = v;
  return true;
}

}  // namespace

int parseOptions(int argc, char** argv, Options& o) {
  bool framesGiven = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "--help" || a == "-h") {
      std::fputs(kHelp, stdout);
      return -1;
    }
    if (i + 1 >= argc) return fail(std::string(a) + ": unknown option or missing value (see --help)");
    const std::string_view v = argv[++i];
    if (a == "--atlas") {
      o.atlas = v;
    } else if (a == "--screenshot") {
      o.screenshot = v;
    } else if (a == "--frames") {
      if (!parseInt(v, 1, 100000, o.frames))
        return fail("--frames: expected an integer in [1, 100000], got " + std::string(v));
      framesGiven = true;
    } else if (a == "--width") {
      if (!parseInt(v, 16, 8192, o.width))
        return fail("--width: expected an integer in [16, 8192], got " + std::string(v));
    } else if (a == "--height") {
      if (!parseInt(v, 16, 8192, o.height))
        return fail("--height: expected an integer in [16, 8192], got " + std::string(v));
    } else {
      return fail(std::string(a) + ": unknown option (see --help)");
    }
  }
  if (o.atlas.empty()) return fail("--atlas DIR is required (a cooked atlas: see --help)");
  if (framesGiven && o.screenshot.empty()) return fail("--frames needs --screenshot");
  std::error_code ec;
  if (std::filesystem::is_directory(o.atlas, ec)) o.atlas /= "puff.json";
  if (!std::filesystem::is_regular_file(o.atlas, ec))
    return fail("no atlas at " + o.atlas.string() + " (a cooked atlas: see --help)");
  if (!o.screenshot.empty()) {
    // Checked before any frame is drawn, so a bad path costs nothing.
    const std::filesystem::path dir = o.screenshot.has_parent_path() ? o.screenshot.parent_path() : ".";
    if (!std::filesystem::is_directory(dir, ec) || ::access(dir.c_str(), W_OK) != 0)
      return fail("cannot write the screenshot " + o.screenshot.string() + ": " + dir.string() +
                  " is not a writable directory");
    if (std::filesystem::is_directory(o.screenshot, ec))
      return fail("cannot write the screenshot " + o.screenshot.string() + ": it is a directory");
  }
  return 0;
}
