// What puffbake's, puffrender's and puffview's `main`s share: the app's name at the start of every
// message, CLI11 parsing with one outcome for --help, --version and bad usage, and the last guard
// around the run. Exit codes: 0 success, 1 failure, 2 bad usage.
#pragma once

#include <exception>
#include <filesystem>
#include <new>
#include <optional>
#include <string>
#include <variant>

#include <puff/core/error.h>
#include <puff/io/openimageio.h>

namespace CLI {
class App;
}

namespace puff::cli {

/// The app's name that starts every message ("puffbake: error: ..."), as main() below was given it.
const char* name();

/// Prints "NAME: error: MESSAGE" on stderr, one line (a message of several lines is joined:
/// core::oneLine).
void printError(const std::string& message);
void printError(const Error& error);

/// Parses argv with `app`. Returns nothing when there is a command to run, else the exit code:
/// 0 after printing --help or --version, 2 after printing CLI11's message as an error and a pointer
/// to --help.
std::optional<int> parse(CLI::App& app, int argc, char** argv);

/// What "${PUFF_ART}" in a scene's paths stands for when --art-dir is not given: $PUFF_ART, else
/// build/art (where the build bakes art/), relative to the working directory.
std::filesystem::path defaultArtDir();
/// --art-dir's help, the same in every tool that reads scenes.
inline constexpr const char* kArtDirHelp =
    "Directory that \"${PUFF_ART}\" in the scene's paths stands for (default: $PUFF_ART, else build/art)";

namespace detail {
void setName(const char* name);
}

/// A whole `main`: names the app, installs the OpenImageIO codec (the tools read and write artists'
/// PNG and EXR files as well as cooked images), parses argv (`parse` gives the Options, or the exit code when
/// parsing ended the run) and runs the Options (`run` gives the exit code). Errors travel as
/// puff::Error values; the catch here is the last guard for what a library may throw (out of
/// memory, a system error), so even then the user gets one line and exit code 1, not an abort, and
/// staged outputs are removed as the stack unwinds.
template <class Options>
int main(const char* appName, int argc, char** argv, std::variant<Options, int> (*parse)(int, char**),
         int (*run)(const Options&)) {
  detail::setName(appName);
  io::useOpenImageIO();
  try {
    auto parsed = parse(argc, argv);
    if (const int* exitCode = std::get_if<int>(&parsed)) return *exitCode;
    return run(std::get<Options>(parsed));
  } catch (const std::bad_alloc&) {
    printError("out of memory");
  } catch (const std::exception& e) {
    printError(e.what());
  }
  return 1;
}

}  // namespace puff::cli
