// puffbake's command line: parsing into one Options value, and the one call that runs it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <puff/bake/baker.h>
#include <puff/bake/detail.h>

namespace puff::app {

enum class Command { kNone, kBake, kMesh, kBlackbody, kDetail, kCook };

/// `puffbake blackbody`: the black-body colour ramp (core/blackbody.h).
struct BlackbodyOptions {
  double minKelvin = 1000, maxKelvin = 10000;
  int size = 1024;
  double normalizeKelvin = 3200;
};

/// `puffbake detail`: a generated detail video, or one imported from image files (--from).
struct DetailOptions {
  bake::DetailSpec spec;                    ///< generation (size is used by import too)
  std::vector<std::filesystem::path> from;  ///< frames to import; empty: generate
  int loopFrames = 8;                       ///< import: frames cross-faded into the first ones
};

struct Options {
  Command command = Command::kNone;
  std::vector<std::filesystem::path> inputs;  ///< mesh files
  std::optional<bake::GeneratorSpec> generator;
  bake::BakeOptions bake;
  std::filesystem::path meshOut;    ///< `puffbake mesh -o FILE`
  std::filesystem::path out;        ///< `puffbake blackbody|detail|cook -o FILE`
  std::filesystem::path cookInput;  ///< `puffbake cook INPUT`
  BlackbodyOptions blackbody;
  DetailOptions detail;
  std::string glBackend;  ///< empty: PUFF_GL or osmesa
  std::string shaderDir;
  bool quiet = false;
};

/// Parses argv. Returns the Options, or an exit code when parsing ended the run (--help: 0,
/// --print-defaults: 0, bad usage: 2, after printing why).
std::variant<Options, int> parse(int argc, char** argv);

/// Runs the parsed command; returns the process exit code (0 success, 1 failure).
int run(const Options& options);

}  // namespace puff::app
