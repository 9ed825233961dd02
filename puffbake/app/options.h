// puffbake's command line: parsing into one Options value, and the one call that runs it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <puff/bake/baker.h>

namespace puff::app {

enum class Command { kNone, kBake, kMesh };

struct Options {
  Command command = Command::kNone;
  std::vector<std::filesystem::path> inputs;  ///< mesh files
  std::optional<bake::GeneratorSpec> generator;
  bake::BakeOptions bake;
  std::filesystem::path meshOut;  ///< `puffbake mesh -o FILE`
  std::string glBackend;          ///< empty: PUFF_GL or osmesa
  std::string shaderDir;
  bool quiet = false;
};

/// Parses argv. Returns the Options, or an exit code when parsing ended the run (--help: 0,
/// --print-defaults: 0, bad usage: 2, after printing why).
std::variant<Options, int> parse(int argc, char** argv);

/// Runs the parsed command; returns the process exit code (0 success, 1 failure).
int run(const Options& options);

}  // namespace puff::app
