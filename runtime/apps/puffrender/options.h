// puffrender's command line: parsing into one Options value, and the one call that runs it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <cli/frames.h>
#include <puff/core/error.h>

namespace puff::app {

struct Options {
  std::filesystem::path scene;                ///< the scene file
  std::string out;                            ///< output image, or a numbered pattern ("out/f_####.png", "f%04d.exr")
  std::string frames;                         ///< "N" or "A-B"; empty: frame 0, or every frame for a pattern
  std::string format;                         ///< "png" or "exr"; empty: from the output's extension
  bool float32 = false;                       ///< EXR channels as 32-bit floats instead of half
  std::string view;                           ///< "standard" or "filmic": replaces the scene's /output/view
  std::string glBackend;                      ///< empty: PUFF_GL or osmesa
  std::optional<int> width, height, samples;  ///< overrides of the scene's output settings
  std::filesystem::path artDir;               ///< replaces "${PUFF_ART}" in the scene's paths
  std::string shaderDir;
  std::string style;  ///< a style preset replacing the scene's style; empty: the scene's own
  std::string path =
      "cel";  ///< a render::renderPathTable() name; "cel" falls back to "fixed" when the context cannot run it
  bool pathGiven = false;      ///< --path was given: no fallback, the path asked for or an error
  std::string compare;         ///< "A,B" (cel and fixed, either order): render both, report parity
  float toneTolerance = 0.1f;  ///< --compare: per-channel tolerance of "the same tone"
  bool toleranceGiven = false;
  /// --max-error: the largest RMSE (linear colour, (0, 1]) the media may differ from the exact
  /// reference by; puffrender then measures and picks the cheapest media layer resolution within it.
  std::optional<double> maxError;
  /// --flipbook COLSxROWS: the frames go into one sprite sheet (OUT, a single file) of COLS x ROWS
  /// cells, left to right and top to bottom, with a transparent background, and a JSON beside it.
  std::string flipbook;
  /// --loop N with --flipbook: the last N frames cross-fade into the first N, so the sheet loops
  /// without a jump (it holds N frames fewer than were rendered).
  int loop = 0;
  /// --period N: the scene as a loop of N frames (replacing animation.period; 0: no loop).
  std::optional<int> period;
  int padding = 0;         ///< --padding PX with --flipbook: empty texels around each frame in its cell
  bool pow2 = false;       ///< --pow2 with --flipbook: the sheet's sides powers of two
  bool crop = false;       ///< --crop with --flipbook: cells hold the part of the frames the sequence covers
  bool skipEmpty = false;  ///< --skip-empty with --flipbook: leading frames that draw nothing take no cell
  /// --maps LIST with --flipbook: the maps written beside the sheet (kFlipbookMaps' names), in the
  /// order given.
  std::vector<std::string> maps;
  int mapBits = 0;           ///< --map-bits 8|16: the maps' bits a channel (0: not given, 8)
  std::string alpha;         ///< "straight" or "premultiplied": replaces the scene's /output/alpha
  std::string contactSheet;  ///< --contact-sheet: a PNG of the frames as a grid with their numbers
  std::string preview;       ///< --preview: an animated .gif or .mp4 of the frames
  bool printScene = false;
  bool quiet = false;
};

/// Parses argv. Returns the Options, or an exit code when parsing ended the run (--help: 0, bad
/// usage: 2, after printing why).
std::variant<Options, int> parse(int argc, char** argv);

/// Runs the parsed command; returns the process exit code (0 success, 1 failure, 2 bad usage that
/// only the scene could reveal, e.g. --frames beyond the scene's last frame).
int run(const Options& options);

using cli::OutputPattern;
using cli::parseFrameRange;
using cli::parseOutputPattern;

/// "COLSxROWS" (each 1..256) for --flipbook.
Result<std::pair<int, int>> parseFlipbookGrid(const std::string& text);

}  // namespace puff::app
