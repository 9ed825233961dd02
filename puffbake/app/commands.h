// puffbake's subcommands, one file each: bake.cpp, mesh.cpp, blackbody.cpp, detail.cpp and cook.cpp. Each
// adds its options to the command line, checks them once parsed (errors are bad usage, exit 2) and
// runs; options.cpp parses and hands the parsed subcommand its run.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include <puff/core/error.h>

#include "options.h"

namespace puff::app {

/// Generator flags shared by `bake` and `mesh`.
struct GeneratorFlags {
  std::string kind;
  bake::GeneratorSpec spec;
  std::optional<int> subdivisions;
  std::uint64_t seed = 1;
  /// Adds -g and the generators' parameters (and -n with `withVariations`) to `app`.
  void add(CLI::App& app, bool withVariations);
  /// The generator the flags ask for; nothing without -g.
  std::optional<bake::GeneratorSpec> finish() const;
};

/// The extension of `p`, lower case (".exr").
std::string lowerExtension(const std::filesystem::path& p);

/// `bake`: the flags read as text or negated, made into Options::bake once parsed.
struct BakeFlags {
  GeneratorFlags generator;
  std::string flange, layout = "hemioct", format = "png", color = "#ffffff", lod = "full";
  bool noMips = false, noSheet = false, printDefaults = false;
};
CLI::App* addBakeCommand(CLI::App& app, Options& o, BakeFlags& flags);
Result<void> finishBake(Options& o, const BakeFlags& flags);
/// --print-defaults: every bake option's default value on stdout; returns the exit code 0.
int printBakeDefaults();
int runBake(const Options& o);

/// `mesh`: `generator` holds the generator flags until parsed.
CLI::App* addMeshCommand(CLI::App& app, Options& o, GeneratorFlags& generator);
int runMesh(const Options& o);

/// `blackbody`.
CLI::App* addBlackbodyCommand(CLI::App& app, Options& o);
Result<void> checkBlackbody(const Options& o);
int runBlackbody(const Options& o);

/// `cook`.
CLI::App* addCookCommand(CLI::App& app, Options& o);
Result<void> checkCook(const Options& o);
int runCook(const Options& o);

/// `detail`.
CLI::App* addDetailCommand(CLI::App& app, Options& o);
Result<void> checkDetail(const Options& o);
int runDetail(const Options& o);

}  // namespace puff::app
