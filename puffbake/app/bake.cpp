// puffbake bake: mesh files and/or generated puffs into an atlas (bake/baker.h).
#include <cstdio>
#include <filesystem>
#include <functional>

#include <cli/app.h>
#include <cli/progress.h>
#include <puff/core/number_text.h>
#include <puff/core/shader.h>
#include <puff/mesh/mesh.h>
#include <puff/platform/gl_context.h>
#include <puff/support/json_read.h>

#include "commands.h"

namespace puff::app {

namespace {

// Meshes of this many bytes in all take seconds to read (a 13 MB OBJ: about 1 s here).
constexpr std::uintmax_t kAnnounceMeshBytes = 32u << 20;

// "6" (texels) or "3%" (of the cell).
std::optional<bake::FlangeWidth> parseFlange(const std::string& text) {
  bake::FlangeWidth f;
  std::string s = text;
  f.fractionOfCell = !s.empty() && s.back() == '%';
  if (f.fractionOfCell) s.pop_back();
  try {
    std::size_t used = 0;
    f.value = std::stof(s, &used);
    if (used != s.size()) return std::nullopt;
  } catch (...) {
    return std::nullopt;
  }
  if (f.fractionOfCell) f.value /= 100.0f;
  return f;
}

// "#rrggbb", "#rgb" or "r,g,b" with components in [0,1].
std::optional<glm::vec3> parseColor(const std::string& s) {
  if (!s.empty() && s[0] == '#') return core::jsonread::parseHexColor(s);
  glm::vec3 c;
  char tail;
  if (std::sscanf(s.c_str(), "%f,%f,%f%c", &c.r, &c.g, &c.b, &tail) != 3) return std::nullopt;
  return c;
}

std::string flangeText(const bake::FlangeWidth& f) {
  return f.fractionOfCell ? core::numberText(f.value * 100.0f) + "%" : core::numberText(f.value);
}

// What the bake wrote: LOD results, the atlas, the contact sheet.
void printBakeResult(const bake::BakeReport& result) {
  const core::AtlasDesc& d = result.desc;
  for (std::size_t i = 0; i < result.lod.size(); ++i) {
    if (const auto& lod = result.lod[i]) {
      std::printf(
          "%s: lod: variation %zu: %zu -> %zu faces (mean normal error %.4f = %.2f/255, silhouette %.2f texels, "
          "mean depth error %.5f diameters = %.2f/255, mean colour error %.5f = %.2f/255, %d trials)%s%s\n",
          cli::name(), i, lod->facesBefore, lod->facesAfter, static_cast<double>(lod->normalError),
          static_cast<double>(lod->normalError * 255.0f), static_cast<double>(lod->silhouetteError),
          static_cast<double>(lod->depthError), static_cast<double>(lod->depthError * 255.0f),
          static_cast<double>(lod->colorError), static_cast<double>(lod->colorError * 255.0f), lod->evaluations,
          i < result.lodMeshes.size() ? ": " : "", i < result.lodMeshes.size() ? result.lodMeshes[i].c_str() : "");
    }
  }
  std::printf("%s: wrote %s: %d variation(s) x %d view(s), %dx%d atlas of %d-texel cells, %d mip level(s), %zu files\n",
              cli::name(), result.sidecar.c_str(), d.variations, d.views, d.width, d.height, d.cellSize, d.mipLevels,
              result.files.size());
  if (!result.contactSheet.empty()) {
    std::printf("%s: contact sheet: %s", cli::name(), result.contactSheet.c_str());
    if (result.contactSheetRows < d.variations) {
      std::printf(" (the first %d of %d variations)", result.contactSheetRows, d.variations);
    }
    std::printf("\n");
  }
  if (!result.viewSheets.empty()) {
    std::printf("%s: views of each variation: %s", cli::name(), result.viewSheets.front().c_str());
    if (result.viewSheets.size() > 1) std::printf(" .. %s", result.viewSheets.back().filename().c_str());
    std::printf("\n");
  }
}

}  // namespace

CLI::App* addBakeCommand(CLI::App& app, Options& o, BakeFlags& flags) {
  CLI::App* cmd = app.add_subcommand("bake", std::string("Bake mesh files (") + mesh::kMeshFormatsRead +
                                                 "; one variation each) and/or generated puffs");
  cmd->add_option("meshes", o.inputs, "Puff mesh files, one variation each");
  flags.generator.add(*cmd, true);
  cmd->add_option("-o,--out", o.bake.outDir, "Output directory (created if missing)")->capture_default_str();
  cmd->add_option("--name", o.bake.name,
                  "File prefix: NAME.json (the sidecar), NAME_color.HASH.png (maps named by their content), ...")
      ->capture_default_str();
  cmd->add_option(
         "-s,--size", o.bake.cellSize,
         "Cell size in texels, per variation and view (8..16384; the flange and a guard band each side must leave the "
         "puff 4 texels, so the default flange needs 10 or more; a bake that would need more than 12 GiB is refused)")
      ->capture_default_str();
  cmd->add_option("--supersample", o.bake.supersample,
                  "Samples per texel side for clean edges; 0 = auto (4, fewer for cells above 1024)")
      ->capture_default_str();
  flags.flange = flangeText(o.bake.flange);
  cmd->add_option("--flange", flags.flange,
                  "Outline flange width: texels (\"6\") or percent of the cell (\"3%\"); 0 = none")
      ->capture_default_str();
  cmd->add_option("--views", o.bake.viewGrid,
                  "Views per variation as an N x N grid of directions (1 = front only; more also writes each view's "
                  "far side, the back map, for puffs that tumble)")
      ->capture_default_str();
  cmd->add_option("--view-layout", flags.layout, "View grid: hemioct (front hemisphere) or oct (whole sphere)")
      ->check(CLI::IsMember({"hemioct", "oct"}))
      ->capture_default_str();
  cmd->add_option("--format", flags.format, "Map files: png (8-bit maps, 16-bit distance) or exr (half float)")
      ->check(CLI::IsMember({"png", "exr"}))
      ->capture_default_str();
  cmd->add_option("--color", flags.color,
                  "Diffuse colour of meshes without vertex colours: #rrggbb, #rgb or r,g,b in [0,1]")
      ->capture_default_str();
  cmd->add_flag("--no-mips", flags.noMips, "Write level 0 only");
  cmd->add_flag(
      "--no-contact-sheet", flags.noSheet,
      "Skip NAME_contact.png (and NAME_contact_vN.png); the sheets of an atlas this bake replaces are removed "
      "with it");
  cmd->add_option("--lod", flags.lod,
                  "full: bake meshes as given; auto: decimate each to the fewest faces within the tolerances and "
                  "write the chosen mesh beside the atlas (NAME_lodI.HASH.ply, named in the sidecar)")
      ->check(CLI::IsMember({"full", "auto"}))
      ->capture_default_str();
  cmd->add_option("--lod-normal-tolerance", o.bake.lodNormalTolerance,
                  "--lod auto: mean encoded normal error allowed, per channel (1/255 = 0.00392)")
      ->capture_default_str();
  cmd->add_option("--lod-silhouette-tolerance", o.bake.lodSilhouetteTolerance,
                  "--lod auto: silhouette displacement allowed, texels")
      ->capture_default_str();
  cmd->add_option("--lod-depth-tolerance", o.bake.lodDepthTolerance,
                  "--lod auto: mean depth-offset error allowed, puff diameters (1/255 = 0.00392, one step of the "
                  "8-bit map the renderer keeps depth in)")
      ->capture_default_str();
  cmd->add_option("--lod-color-tolerance", o.bake.lodColorTolerance,
                  "--lod auto: mean colour error allowed per channel, sRGB-encoded [0, 1] (1/255 = 0.00392); "
                  "matters for meshes with vertex colours")
      ->capture_default_str();
  cmd->add_option("--gl", o.glBackend, "GL backend: osmesa, egl or glfw (default: $PUFF_GL, else osmesa)")
      ->check(CLI::IsMember({"osmesa", "egl", "glfw"}));
  cmd->add_option("--shader-dir", o.shaderDir, "Read shaders from this directory instead of the built-in copies");
  cmd->add_flag("-q,--quiet", o.quiet, "Print errors only");
  cmd->add_flag("--print-defaults", flags.printDefaults, "Print every bake option's default value and exit");
  return cmd;
}

Result<void> finishBake(Options& o, const BakeFlags& flags) {
  o.generator = flags.generator.finish();
  auto f = parseFlange(flags.flange);
  if (!f) return Error{"--flange: expected texels (\"6\") or a percentage (\"3%\"), got \"" + flags.flange + "\""};
  o.bake.flange = *f;
  auto c = parseColor(flags.color);
  if (!c) return Error{"--color: expected #rrggbb, #rgb or r,g,b, got \"" + flags.color + "\""};
  o.bake.defaultColor = *c;
  o.bake.viewLayout = flags.layout == "oct" ? bake::ViewLayout::kOct : bake::ViewLayout::kHemiOct;
  o.bake.format = flags.format == "exr" ? bake::MapFormat::kExr : bake::MapFormat::kPng;
  o.bake.mips = !flags.noMips;
  o.bake.contactSheet = !flags.noSheet;
  o.bake.lodAuto = flags.lod == "auto";
  if (o.inputs.empty() && !o.generator) return Error{"bake: nothing to bake: give mesh files or --generate KIND"};
  return {};
}

int printBakeDefaults() {
  bake::BakeOptions d;
  std::printf(
      "size = %d\nsupersample = 0 (auto)\nflange = %s\nviews = %d\nview-layout = hemioct\nformat = png\n"
      "color = #ffffff\nmips = on\ncontact-sheet = on\nlod = full\nlod-normal-tolerance = %g\n"
      "lod-silhouette-tolerance = %g\nlod-depth-tolerance = %g\nlod-color-tolerance = %g\nname = %s\nout = %s\n"
      "variations = %d (with --generate)\n",
      d.cellSize, flangeText(d.flange).c_str(), d.viewGrid, static_cast<double>(d.lodNormalTolerance),
      static_cast<double>(d.lodSilhouetteTolerance), static_cast<double>(d.lodDepthTolerance),
      static_cast<double>(d.lodColorTolerance), d.name.c_str(), d.outDir.c_str(), bake::GeneratorSpec{}.count);
  return 0;
}

int runBake(const Options& o) {
  cli::Progress progress(o.quiet);
  // Large meshes take seconds to read before there is a step to count: said at once.
  std::uintmax_t bytes = 0;
  for (const auto& file : o.inputs) {
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(file, ec);
    if (!ec) bytes += size;
  }
  if (bytes >= kAnnounceMeshBytes) progress.announce("loading meshes", static_cast<long long>(o.inputs.size()));
  auto sources = bake::loadSources(o.inputs, o.generator, std::ref(progress));
  progress.finish();
  if (!sources) {
    cli::printError(sources.error());
    return 1;
  }
  for (const bake::PuffSource& s : *sources) {
    if (s.separatedFaces > 0 && !o.quiet) {
      std::printf("%s: %s: %zu non-manifold face%s split onto their own vertices\n", cli::name(),
                  s.provenance.path.c_str(), s.separatedFaces, s.separatedFaces == 1 ? "" : "s");
    }
    if (s.volumeFraction < mesh::kFlatVolumeFraction && !o.quiet) {
      std::fprintf(stderr,
                   "%s: warning: %s is flat (it encloses %.2g%% of its bounding sphere): it bakes as a card, "
                   "with a puff's depth and normals only where the mesh has them\n",
                   cli::name(), s.provenance.path.c_str(), 100.0 * s.volumeFraction);
    }
  }
  if (auto v = bake::validate(o.bake, static_cast<int>(sources->size())); !v) {
    cli::printError(v.error());
    return 2;
  }
  if (!o.shaderDir.empty()) core::setShaderDir(o.shaderDir);
  core::GlContextOptions glOptions;
  glOptions.backend = o.glBackend;
  auto context = core::createGlContext(glOptions);
  if (!context) {
    cli::printError(context.error());
    return 1;
  }
  auto result = bake::bakeAtlas(*sources, o.bake, std::ref(progress));
  progress.finish();
  if (!result) {
    cli::printError(result.error());
    return 1;
  }
  if (!o.quiet) printBakeResult(*result);
  return 0;
}

}  // namespace puff::app
