#include <cli/app.h>

#include <cstdio>
#include <cstdlib>

#include <CLI/CLI.hpp>

#include <puff/support/text.h>

namespace puff::cli {

namespace {
const char* appName = "";
}  // namespace

void detail::setName(const char* name) { appName = name; }

const char* name() { return appName; }

void printError(const std::string& message) {
  std::fprintf(stderr, "%s: error: %s\n", appName, core::oneLine(message).c_str());
}

void printError(const Error& error) { printError(error.message); }

std::filesystem::path defaultArtDir() {
  const char* env = std::getenv("PUFF_ART");
  return env && *env ? std::filesystem::path(env) : std::filesystem::path("build/art");
}

std::optional<int> parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    printError(e.what());
    std::fprintf(stderr, "Run with --help for usage.\n");
    return 2;
  }
  return std::nullopt;
}

}  // namespace puff::cli
