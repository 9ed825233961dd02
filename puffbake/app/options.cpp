// puffbake's command line: the subcommands' options (each subcommand's own file adds them), the
// parse, and the run of the parsed subcommand.
#include "options.h"

#include <cctype>

#include <cli/app.h>
#include <puff/support/text.h>

#include "commands.h"

namespace puff::app {

namespace fs = std::filesystem;

void GeneratorFlags::add(CLI::App& app, bool withVariations) {
  app.add_option("-g,--generate", kind, "Generate puffs instead of (or after) mesh files: sphere, lumpy or cluster")
      ->check(CLI::IsMember({"sphere", "lumpy", "cluster"}));
  app.add_option("--subdivisions", subdivisions,
                 "Icosphere subdivision level (sphere/lumpy default 4/5, 0..7; cluster spheres default 3, 0..6)");
  app.add_option("--seed", seed, "Random seed; variation i uses seed + i")->capture_default_str();
  app.add_option("--amplitude", spec.lumpy.amplitude, "lumpy: radial displacement, fraction of the radius")
      ->capture_default_str();
  app.add_option("--frequency", spec.lumpy.frequency, "lumpy: noise frequency over the sphere")->capture_default_str();
  app.add_option("--octaves", spec.lumpy.octaves, "lumpy: fractal noise octaves")->capture_default_str();
  app.add_option("--count", spec.cluster.count, "cluster: spheres per puff")->capture_default_str();
  app.add_option("--radius-min", spec.cluster.radiusMin, "cluster: smallest sphere radius")->capture_default_str();
  app.add_option("--radius-max", spec.cluster.radiusMax, "cluster: largest sphere radius")->capture_default_str();
  app.add_option("--spread", spec.cluster.spread, "cluster: how far sphere centres scatter")->capture_default_str();
  if (withVariations) {
    app.add_option("-n,--variations", spec.count, "Puffs to generate (each its own variation)")->capture_default_str();
  }
}

std::optional<bake::GeneratorSpec> GeneratorFlags::finish() const {
  if (kind.empty()) return std::nullopt;
  bake::GeneratorSpec s = spec;
  s.kind = kind;
  s.lumpy.seed = s.cluster.seed = seed;
  if (subdivisions) s.sphere.subdivisions = s.lumpy.subdivisions = s.cluster.subdivisions = *subdivisions;
  return s;
}

std::string lowerExtension(const fs::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

std::variant<Options, int> parse(int argc, char** argv) {
  Options o;
  CLI::App app{
      "puffbake: bakes 3D puff meshes into atlases of camera-space normal + depth, colour + dilated "
      "coverage and signed distance to the silhouette (McGuire & Fein 2006, Fig. 3 / Eq. 1), with a JSON "
      "sidecar and a contact sheet; writes the fire and smoke media's black-body ramp and detail videos "
      "(Umenhoffer et al. 2006, §3); and cooks assets for games that load them without an image library.",
      cli::name()};
  app.require_subcommand(1);
  app.set_version_flag("--version", "puffbake 0.1.0");
  BakeFlags bakeFlags;
  CLI::App* bakeCmd = addBakeCommand(app, o, bakeFlags);
  GeneratorFlags meshGenerator;
  CLI::App* meshCmd = addMeshCommand(app, o, meshGenerator);
  CLI::App* blackbodyCmd = addBlackbodyCommand(app, o);
  CLI::App* detailCmd = addDetailCommand(app, o);
  CLI::App* cookCmd = addCookCommand(app, o);

  if (const auto exitCode = cli::parse(app, argc, argv)) return *exitCode;
  if (bakeFlags.printDefaults) return printBakeDefaults();
  Result<void> checked;
  if (bakeCmd->parsed()) {
    o.command = Command::kBake;
    checked = finishBake(o, bakeFlags);
  } else if (meshCmd->parsed()) {
    o.command = Command::kMesh;
    o.generator = meshGenerator.finish();
  } else if (blackbodyCmd->parsed()) {
    o.command = Command::kBlackbody;
    checked = checkBlackbody(o);
  } else if (detailCmd->parsed()) {
    o.command = Command::kDetail;
    checked = checkDetail(o);
  } else if (cookCmd->parsed()) {
    o.command = Command::kCook;
    checked = checkCook(o);
  }
  if (!checked) {
    cli::printError(checked.error());
    return 2;
  }
  return o;
}

int run(const Options& o) {
  switch (o.command) {
    case Command::kBake:
      return runBake(o);
    case Command::kMesh:
      return runMesh(o);
    case Command::kBlackbody:
      return runBlackbody(o);
    case Command::kDetail:
      return runDetail(o);
    case Command::kCook:
      return runCook(o);
    case Command::kNone:
      break;
  }
  return 2;
}

}  // namespace puff::app
