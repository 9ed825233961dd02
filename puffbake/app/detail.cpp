// puffbake detail: a detail video, generated or imported from image files (bake/detail.h).
#include <cstdio>

#include <cli/app.h>
#include <puff/core/detail_video.h>

#include "commands.h"

namespace puff::app {

namespace {

// Import flags checked before any file is read (bad usage, exit 2).
std::optional<std::string> importProblem(const DetailOptions& d) {
  if (d.spec.size < core::kMinDetailSize || d.spec.size > core::kMaxDetailSize)
    return "--size must be in [" + std::to_string(core::kMinDetailSize) + ", " + std::to_string(core::kMaxDetailSize) +
           "], got " + std::to_string(d.spec.size);
  const int n = static_cast<int>(d.from.size());
  if (d.loopFrames < 0 || 2 * d.loopFrames > n)
    return "--loop-frames must be in [0, " + std::to_string(n / 2) + "] (half of the " + std::to_string(n) +
           " frames given), got " + std::to_string(d.loopFrames);
  return std::nullopt;
}

}  // namespace

CLI::App* addDetailCommand(CLI::App& app, Options& o) {
  CLI::App* cmd = app.add_subcommand(
      "detail",
      "Write a detail video (a looping greyscale x, y, time texture that perturbs fire temperature and smoke "
      "opacity): tileable, looping noise, or imported from image files with --from. One image, frames stacked top "
      "to bottom, metadata puff:frames");
  bake::DetailSpec& spec = o.detail.spec;
  cmd->add_option("-o,--out", o.out, "Output file: .png (16-bit) or .exr (half float); written whole or not at all")
      ->required();
  cmd->add_option("--size", spec.size, "Width and height in texels (4..4096); imported frames are resampled")
      ->capture_default_str();
  CLI::Option* framesOpt =
      cmd->add_option("--frames", spec.frames, "Frames in the loop (1..1024)")->capture_default_str();
  CLI::Option* seedOpt = cmd->add_option("--seed", spec.seed, "Noise seed")->capture_default_str();
  CLI::Option* octavesOpt = cmd->add_option("--octaves", spec.octaves, "Noise octaves (1..10)")->capture_default_str();
  CLI::Option* frequencyOpt =
      cmd->add_option("--frequency", spec.frequency, "Noise cells across the tile in the first octave (1..256)")
          ->capture_default_str();
  CLI::Option* contrastOpt = cmd->add_option("--contrast", spec.contrast,
                                             "Standard deviation around 0.5 is contrast/6, clipped to [0, 1] (0..16)")
                                 ->capture_default_str();
  CLI::Option* fromOpt = cmd->add_option(
      "--from", o.detail.from,
      "Import these image files instead of generating: any format, all one size, in the order given (a shell glob "
      "such as clip/*.png sorts by name); each becomes luma, resampled to --size x --size");
  for (CLI::Option* gen : {framesOpt, seedOpt, octavesOpt, frequencyOpt, contrastOpt}) gen->excludes(fromOpt);
  cmd->add_option("--loop-frames", o.detail.loopFrames,
                  "With --from: fade the last N frames into the first N to make the clip loop; the output has N "
                  "fewer frames (0..half the frames)")
      ->capture_default_str()
      ->needs(fromOpt);
  cmd->add_flag("-q,--quiet", o.quiet, "Print errors only");
  return cmd;
}

Result<void> checkDetail(const Options& o) {
  if (const std::string ext = lowerExtension(o.out); ext != ".png" && ext != ".exr") {
    return Error{"detail: -o: FILE must end in .png (16-bit) or .exr (half float), got \"" + o.out.string() + "\""};
  }
  auto problem = o.detail.from.empty() ? std::optional<std::string>() : importProblem(o.detail);
  if (o.detail.from.empty()) {
    if (auto v = bake::validate(o.detail.spec); !v) problem = v.error().message;
  }
  if (problem) return Error{*problem};
  return {};
}

int runDetail(const Options& o) {
  const DetailOptions& d = o.detail;
  auto video =
      d.from.empty() ? bake::generateDetailVideo(d.spec) : bake::importDetailVideo(d.from, d.spec.size, d.loopFrames);
  if (!video) {
    cli::printError(video.error());
    return 1;
  }
  if (auto r = core::saveDetailVideo(o.out, *video); !r) {
    cli::printError(r.error());
    return 1;
  }
  if (!o.quiet) {
    const std::string how = d.from.empty() ? "generated, seed " + std::to_string(d.spec.seed)
                                           : "imported from " + std::to_string(d.from.size()) + " files, last " +
                                                 std::to_string(d.loopFrames) + " cross-faded into the first";
    std::printf("%s: wrote %s: detail video %dx%d, %d frames (%s)\n", cli::name(), o.out.c_str(), video->width,
                video->height, video->frames, how.c_str());
  }
  return 0;
}

}  // namespace puff::app
