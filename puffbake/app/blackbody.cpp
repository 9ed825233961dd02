// puffbake blackbody: the black-body colour ramp fire is shaded with (core/blackbody.h).
#include <cstdio>

#include <cli/app.h>
#include <puff/core/blackbody.h>
#include <puff/core/number_text.h>

#include "commands.h"

namespace puff::app {

namespace {

// The blackbody flags' ranges (core::makeBlackbodyRamp's), named as the user typed them.
std::optional<std::string> blackbodyProblem(const BlackbodyOptions& b) {
  const std::string top = core::numberText(core::kMaxKelvin);
  if (!(b.minKelvin > 0.0 && b.minKelvin < core::kMaxKelvin))
    return "--min must be in (0, " + top + ") kelvin, got " + core::numberText(b.minKelvin);
  if (!(b.maxKelvin > b.minKelvin && b.maxKelvin <= core::kMaxKelvin))
    return "--max must be above --min (" + core::numberText(b.minKelvin) + ") and at most " + top + " kelvin, got " +
           core::numberText(b.maxKelvin);
  if (b.size < 2 || b.size > core::kMaxBlackbodyTexels)
    return "--size must be in [2, " + std::to_string(core::kMaxBlackbodyTexels) + "], got " + std::to_string(b.size);
  if (!(b.normalizeKelvin > 0.0 && b.normalizeKelvin <= core::kMaxKelvin))
    return "--normalize must be in (0, " + top + "] kelvin, got " + core::numberText(b.normalizeKelvin);
  return std::nullopt;
}

}  // namespace

CLI::App* addBlackbodyCommand(CLI::App& app, Options& o) {
  CLI::App* cmd = app.add_subcommand(
      "blackbody",
      "Write the black-body colour ramp fire is shaded with (Planck's law seen by the CIE 1931 2-degree observer, in "
      "linear sRGB, luminance 1 at --normalize; negative out-of-gamut components kept) as an N x 1 RGB float EXR");
  cmd->add_option("-o,--out", o.out, "Output file, .exr (written whole or not at all)")->required();
  cmd->add_option("--min", o.blackbody.minKelvin, "Temperature of the first texel, kelvin (0 < min < max)")
      ->capture_default_str();
  cmd->add_option("--max", o.blackbody.maxKelvin, "Temperature of the last texel, kelvin (at most 100000)")
      ->capture_default_str();
  cmd->add_option("--size", o.blackbody.size, "Texels, evenly spaced in temperature (2..65536)")->capture_default_str();
  cmd->add_option("--normalize", o.blackbody.normalizeKelvin,
                  "Temperature whose luminance becomes 1, kelvin (0 < T <= 100000); hotter is brighter")
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", o.quiet, "Print errors only");
  return cmd;
}

Result<void> checkBlackbody(const Options& o) {
  if (lowerExtension(o.out) != ".exr") {
    return Error{"blackbody: -o: the ramp is a float EXR, so FILE must end in .exr, got \"" + o.out.string() + "\""};
  }
  if (auto problem = blackbodyProblem(o.blackbody)) return Error{*problem};
  return {};
}

int runBlackbody(const Options& o) {
  const BlackbodyOptions& b = o.blackbody;
  auto ramp = core::makeBlackbodyRamp(b.minKelvin, b.maxKelvin, b.size, b.normalizeKelvin);
  if (!ramp) {  // the ranges were checked while parsing: what is left is a bad combination
    cli::printError(ramp.error());
    return 2;
  }
  if (auto r = core::writeBlackbodyRamp(o.out, *ramp); !r) {
    cli::printError(r.error());
    return 1;
  }
  if (!o.quiet) {
    std::printf("%s: wrote %s: black-body ramp %s..%s K in %d texels (linear sRGB, luminance 1 at %s K)\n", cli::name(),
                o.out.c_str(), core::numberText(b.minKelvin).c_str(), core::numberText(b.maxKelvin).c_str(), b.size,
                core::numberText(b.normalizeKelvin).c_str());
  }
  return 0;
}

}  // namespace puff::app
