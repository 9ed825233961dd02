// puffbake cook: assets rewritten as Puff's cooked images, which a game reads without an image
// library (bake/cook.h).
#include <cstdio>

#include <cli/app.h>
#include <puff/bake/cook.h>
#include <puff/core/image.h>

#include "commands.h"

namespace puff::app {

namespace {

// "812 bytes", "12.1 KiB", "3.34 MiB".
std::string size(std::uintmax_t bytes) {
  char b[32];
  if (bytes < 1024) {
    std::snprintf(b, sizeof b, "%ju bytes", bytes);
  } else if (bytes < 1024 * 1024) {
    std::snprintf(b, sizeof b, "%.1f KiB", static_cast<double>(bytes) / 1024.0);
  } else {
    std::snprintf(b, sizeof b, "%.2f MiB", static_cast<double>(bytes) / (1024.0 * 1024.0));
  }
  return b;
}

}  // namespace

CLI::App* addCookCommand(CLI::App& app, Options& o) {
  CLI::App* cmd = app.add_subcommand(
      "cook",
      "Rewrite an atlas (its .json sidecar) or one image (a ramp, gradient, detail video or black-body ramp) as "
      "Puff's cooked images (.puffimg: a small header and the raw pixels), which puff::core reads with no image "
      "library, so a game that ships them links neither puff::io nor OpenImageIO. Every value is kept: each image "
      "in the type its file held, with its puff: attributes");
  cmd->add_option("input", o.cookInput, "An atlas sidecar (.json) or an image file")->required();
  cmd->add_option("-o,--out", o.out,
                  "For an atlas, the cooked sidecar STEM.json: its maps are written beside it as STEM_MAP.HASH.puffimg "
                  "(HASH: the content's; a --lod auto mesh as STEM_lodN.HASH), and an atlas already there is replaced "
                  "whole; for an image, "
                  "the .puffimg file. Written whole or not at all")
      ->required();
  cmd->add_flag("-q,--quiet", o.quiet, "Print errors only");
  return cmd;
}

Result<void> checkCook(const Options& o) {
  const bool atlas = lowerExtension(o.cookInput) == ".json";
  if (atlas && lowerExtension(o.out) != ".json") {
    return Error{"cook: -o: an atlas cooks into a sidecar, so -o must end in .json, got \"" + o.out.string() + "\""};
  }
  if (!atlas && !core::isCookedImagePath(o.out)) {
    return Error{"cook: -o: an image cooks into a .puffimg file, got \"" + o.out.string() + "\""};
  }
  return {};
}

int runCook(const Options& o) {
  const bool atlas = lowerExtension(o.cookInput) == ".json";
  auto cooked = atlas ? bake::cookAtlas(o.cookInput, o.out) : bake::cookImage(o.cookInput, o.out);
  if (!cooked) {
    cli::printError(cooked.error());
    return 1;
  }
  if (!o.quiet) {
    std::printf("%s: wrote %s: %s cooked into %zu file%s, %s (the source: %s)\n", cli::name(), o.out.c_str(),
                atlas ? "atlas" : "image", cooked->files.size(), cooked->files.size() == 1 ? "" : "s",
                size(cooked->bytesWritten).c_str(), size(cooked->bytesRead).c_str());
  }
  return 0;
}

}  // namespace puff::app
