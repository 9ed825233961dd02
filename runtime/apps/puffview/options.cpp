#include <puffview/options.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>

#include <CLI/CLI.hpp>

#include <cli/app.h>
#include <cli/frames.h>
#include <cli/progress.h>

#include <puff/core/limits.h>
#include <puff/render/path.h>
#include <puffview/viewer.h>

namespace puff::view {

namespace fs = std::filesystem;

namespace {

// --frames: a count N (frames 0 to N-1) or a range A-B, into `o`. Returns the exit code when the text
// is neither (after printing why).
std::optional<int> readFrames(const std::string& framesText, Options& o) {
  const bool range = framesText.find('-') != std::string::npos;
  auto frames = cli::parseFrameRange(framesText);
  if (!frames && frames.error().message.find("ends before") != std::string::npos) {
    cli::printError(frames.error());
    return 2;
  }
  if (!frames) {
    cli::printError(
        Error{"--frames: expected a count N (frames 0 to N-1) or a range A-B (0-based, inclusive), "
              "got \"" +
              framesText + "\""});
    return 2;
  }
  if (range) {
    o.frames = *frames;
    o.framesRange = true;
  } else if (frames->first < 1) {
    cli::printError("--frames " + framesText + ": show at least one frame");
    return 2;
  } else {
    o.frames = std::pair{0, frames->first - 1};
  }
  return std::nullopt;
}

// --screenshot: a .png name, with at most one frame-number pattern. Returns the exit code when it is
// not (after printing why).
std::optional<int> checkScreenshotName(const std::string& screenshot) {
  std::string ext = fs::path(screenshot).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".png") {
    cli::printError("--screenshot " + screenshot + ": screenshots are PNG: give a .png name");
    return 2;
  }
  if (auto p = cli::parseOutputPattern(screenshot, "--screenshot"); !p) {
    cli::printError(p.error());
    return 2;
  }
  return std::nullopt;
}

}  // namespace

std::variant<Options, int> parse(int argc, char** argv) {
  Options o;
  std::vector<std::string> pathNames;
  std::string pathList;
  for (const render::RenderPathInfo& p : render::renderPaths()) {
    pathNames.push_back(p.name);
    pathList += "\n  " + p.name + ": " + p.description;
  }
  CLI::App app{
      "puffview: the artist's live viewer. Opens a scene file (JSON, see docs/scene-format.md) in a window with "
      "panels for every style and simulation setting; edits show at once and can be saved back to the file. The "
      "scene, its atlas, ramp, gradient, meshes and (with --shader-dir or $PUFF_SHADER_DIR) shaders are reloaded "
      "when they change on disk.\n"
      "Keys: Space play/pause, . or Right step, Left step back, R or Home restart, P or F12 screenshot, F orbit/fly "
      "camera, C reset camera, H hide panels, Ctrl+Z undo, Ctrl+Y or Ctrl+Shift+Z redo, Ctrl+S save, Esc or Ctrl+Q "
      "quit "
      "(asking first when edits are unsaved; keys typed into a panel's field or popup stay there). Unsaved edits "
      "are kept beside the scene (.NAME.puffview-autosave) and offered back if puffview stops without saving. Mouse "
      "(orbit): left "
      "drag turns, right or middle drag pans, "
      "wheel zooms; (fly): WASD/QE move, right drag looks.",
      cli::name()};
  app.set_version_flag("--version", "puffview 0.1.0");
  app.add_option("scene", o.scene, "Scene file (JSON)")->required();
  std::string framesText;
  app.add_option("--frames", framesText,
                 "Batch mode: N shows frames 0 to N-1, A-B frames A to B (0-based, inclusive, within the scene's "
                 "/animation/frames), one per displayed frame (no wall clock, so every run shows the same frames), "
                 "then exits")
      ->type_name("N|A-B");
  app.add_option("--screenshot", o.screenshot,
                 "Batch mode: save the window as drawn for the last frame to this PNG, or, for a name with one %d, "
                 "%0Nd or run of # (shot_####.png), every frame to its numbered file (implies --frames 1 when "
                 "--frames is not given)");
  app.add_flag("--hide-ui", o.hideUi,
               "Start with the panels hidden (H shows them); screenshots then show the scene only");
  app.add_option("--width", o.width,
                 "Image width in pixels (default: the scene's output width, at most 1920); the window adds the docked "
                 "panel's 400 when the panels are shown")
      ->check(CLI::Range(16, core::kMaxImageSize));
  app.add_option("--height", o.height,
                 "Image height in pixels (default: the scene's output height, at most 1200); the window is at least "
                 "480 tall when the panels are shown")
      ->check(CLI::Range(16, core::kMaxImageSize));
  app.add_option("--art-dir", o.artDir, cli::kArtDirHelp);
  app.add_option("--shader-dir", o.shaderDir,
                 "Read shaders from this directory instead of the built-in copies, and reload when they change");
  app.add_option("--screenshot-dir", o.screenshotDir,
                 "Where P / F12 save screenshots (default: beside the scene file)");
  app.add_option("--path", o.path, "Render path (default cel). Available:" + pathList)->check(CLI::IsMember(pathNames));
  app.add_flag("-q,--quiet", o.quiet, "Print errors only");

  if (const auto exitCode = cli::parse(app, argc, argv)) return *exitCode;
  if (!framesText.empty()) {
    if (const auto exitCode = readFrames(framesText, o)) return *exitCode;
  }
  if (!o.screenshot.empty()) {
    if (const auto exitCode = checkScreenshotName(o.screenshot)) return *exitCode;
  }
  if (!o.screenshot.empty() && !o.frames) o.frames = std::pair{0, 0};
  if (o.artDir.empty()) o.artDir = cli::defaultArtDir();
  return o;
}

int run(const Options& o) {
  ViewerOptions vo;
  vo.scene = o.scene;
  vo.artDir = o.artDir;
  vo.shaderDir = o.shaderDir;
  vo.path = o.path;
  vo.width = o.width.value_or(0);
  vo.height = o.height.value_or(0);
  vo.ui = !o.hideUi;
  vo.screenshotDir = o.screenshotDir;
  vo.quiet = o.quiet || o.frames.has_value();
  auto viewer = Viewer::open(vo);
  if (!viewer) {
    cli::printError(viewer.error());
    return 1;
  }
  if (!o.frames) return (*viewer)->runInteractive();
  const int first = o.frames->first, last = o.frames->second;  // named, not bound: a lambda captures `last`
  // Frames past the scene's end are refused in both forms: playing stops or loops at its last frame,
  // and puffrender refuses them too.
  if (const int frames = (*viewer)->scene().animation.frames; last >= frames) {
    const std::string given =
        o.framesRange ? std::to_string(first) + "-" + std::to_string(last) : std::to_string(last + 1);
    cli::printError("--frames " + given + ": the scene has " + std::to_string(frames) + " frame(s), 0 to " +
                    std::to_string(frames - 1) + " (/animation/frames)");
    return 2;
  }
  const cli::OutputPattern pattern =
      o.screenshot.empty() ? cli::OutputPattern{} : *cli::parseOutputPattern(o.screenshot);
  // A numbered name takes every frame; a plain one the last.
  const auto shotFor = [&](int f) -> fs::path {
    if (o.screenshot.empty() || (!pattern.numbered && f != last)) return {};
    return pattern.name(f);
  };
  cli::Progress progress(o.quiet || first == last);
  auto r = (*viewer)->runBatch(first, last, shotFor, [&](int done, int total) { progress("frames", done, total); });
  progress.finish();
  if (!r) {
    cli::printError(r.error());
    return 1;
  }
  if (!o.quiet && !o.screenshot.empty()) {
    const glm::ivec2 size = (*viewer)->framebufferSize();
    if (pattern.numbered && last > first) {
      std::printf("%s: wrote %d frames (%dx%d): %s .. %s\n", cli::name(), last - first + 1, size.x, size.y,
                  pattern.name(first).c_str(), pattern.name(last).c_str());
    } else {
      std::printf("%s: wrote %s (%dx%d, frame %d)\n", cli::name(), pattern.name(last).c_str(), size.x, size.y, last);
    }
  }
  return 0;
}

}  // namespace puff::view
