#include "options.h"

#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include <cli/app.h>

#include <puff/core/blackbody.h>
#include <puff/core/detail_video.h>
#include <puff/core/gl_context.h>
#include <puff/core/shader.h>

namespace puff::app {

namespace fs = std::filesystem;

namespace {

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

// "#rrggbb" or "r,g,b" with components in [0,1].
std::optional<glm::vec3> parseColor(const std::string& s) {
  glm::vec3 c;
  if (s.size() == 7 && s[0] == '#') {
    unsigned r, g, b;
    if (std::sscanf(s.c_str() + 1, "%2x%2x%2x", &r, &g, &b) != 3) return std::nullopt;
    return glm::vec3(r, g, b) / 255.0f;
  }
  char tail;
  if (std::sscanf(s.c_str(), "%f,%f,%f%c", &c.r, &c.g, &c.b, &tail) != 3) return std::nullopt;
  return c;
}

std::string flangeText(const bake::FlangeWidth& f) {
  char b[32];
  if (f.fractionOfCell)
    std::snprintf(b, sizeof b, "%g%%", static_cast<double>(f.value * 100.0f));
  else
    std::snprintf(b, sizeof b, "%g", static_cast<double>(f.value));
  return b;
}

// Generator flags shared by `bake` and `mesh`.
struct GeneratorFlags {
  std::string kind;
  bake::GeneratorSpec spec;
  void add(CLI::App& app, bool withVariations) {
    app.add_option("-g,--generate", kind, "Generate puffs instead of (or after) mesh files: sphere, lumpy or cluster")
        ->check(CLI::IsMember({"sphere", "lumpy", "cluster"}));
    app.add_option("--subdivisions", subdivisions,
                   "Icosphere subdivision level (sphere/lumpy default 4/5, 0..7; cluster spheres default 3, 0..6)");
    app.add_option("--seed", seed, "Random seed; variation i uses seed + i")->capture_default_str();
    app.add_option("--amplitude", spec.lumpy.amplitude, "lumpy: radial displacement, fraction of the radius")
        ->capture_default_str();
    app.add_option("--frequency", spec.lumpy.frequency, "lumpy: noise frequency over the sphere")
        ->capture_default_str();
    app.add_option("--octaves", spec.lumpy.octaves, "lumpy: fractal noise octaves")->capture_default_str();
    app.add_option("--count", spec.cluster.count, "cluster: spheres per puff")->capture_default_str();
    app.add_option("--radius-min", spec.cluster.radiusMin, "cluster: smallest sphere radius")->capture_default_str();
    app.add_option("--radius-max", spec.cluster.radiusMax, "cluster: largest sphere radius")->capture_default_str();
    app.add_option("--spread", spec.cluster.spread, "cluster: how far sphere centres scatter")->capture_default_str();
    if (withVariations) {
      app.add_option("-n,--variations", spec.count, "Puffs to generate (each its own variation)")
          ->capture_default_str();
    }
  }
  std::optional<int> subdivisions;
  std::uint64_t seed = 1;
  std::optional<bake::GeneratorSpec> finish() {
    if (kind.empty()) return std::nullopt;
    bake::GeneratorSpec s = spec;
    s.kind = kind;
    s.lumpy.seed = s.cluster.seed = seed;
    if (subdivisions) s.sphere.subdivisions = s.lumpy.subdivisions = s.cluster.subdivisions = *subdivisions;
    return s;
  }
};

// Progress on stderr, only for work that takes more than about a second.
class Progress {
 public:
  explicit Progress(bool quiet) : quiet_(quiet), tty_(::isatty(2) != 0), start_(std::chrono::steady_clock::now()) {}
  ~Progress() { finish(); }
  /// Ends a progress line left open on a terminal, so what is printed next starts on its own line.
  void finish() {
    if (shown_ && tty_) std::fputc('\n', stderr);
    shown_ = false;
  }
  void operator()(std::string_view stage, int done, int total) {
    if (quiet_) return;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (elapsed < 1.0 && !shown_) return;
    const int percent = total > 0 ? 100 * done / total : 100;
    if (tty_) {
      std::fprintf(stderr, "\r%s: %.*s %d/%d (%d%%)   ", cli::name(), static_cast<int>(stage.size()), stage.data(),
                   done, total, percent);
    } else if (stage != lastStage_ || percent / 25 != lastQuarter_ || done == total) {
      std::fprintf(stderr, "%s: %.*s %d/%d\n", cli::name(), static_cast<int>(stage.size()), stage.data(), done, total);
      lastQuarter_ = percent / 25;
    }
    lastStage_ = std::string(stage);
    shown_ = true;
    std::fflush(stderr);
  }

 private:
  bool quiet_, tty_, shown_ = false;
  std::chrono::steady_clock::time_point start_;
  std::string lastStage_;
  int lastQuarter_ = -1;
};

int runMesh(const Options& o) {
  if (o.meshOut.empty()) {
    cli::printError("mesh: -o FILE is required");
    return 2;
  }
  if (o.inputs.size() + (o.generator ? 1 : 0) != 1) {
    cli::printError("mesh: give exactly one mesh file or --generate KIND");
    return 2;
  }
  std::optional<bake::GeneratorSpec> gen = o.generator;
  if (gen) gen->count = 1;
  auto sources = bake::loadSources(o.inputs, gen);
  if (!sources) {
    cli::printError(sources.error());
    return 1;
  }
  const mesh::TriMesh& m = sources->front().mesh;
  if (auto r = mesh::saveMesh(m, o.meshOut); !r) {
    cli::printError(r.error());
    return 1;
  }
  if (!o.quiet) {
    std::printf("%s: wrote %s (%zu faces, %zu vertices, unit bounding sphere)\n", cli::name(), o.meshOut.c_str(),
                m.faceCount(), m.positions.size());
  }
  return 0;
}

int runBake(const Options& o) {
  auto sources = bake::loadSources(o.inputs, o.generator);
  if (!sources) {
    cli::printError(sources.error());
    return 1;
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
  Progress progress(o.quiet);
  auto result = bake::bakeAtlas(*sources, o.bake, std::ref(progress));
  progress.finish();
  if (!result) {
    cli::printError(result.error());
    return 1;
  }
  if (o.quiet) return 0;
  const core::AtlasDesc& d = result->desc;
  for (std::size_t i = 0; i < result->lod.size(); ++i) {
    if (const auto& lod = result->lod[i]) {
      std::printf(
          "%s: lod: variation %zu: %zu -> %zu faces (mean normal error %.4f = %.2f/255, silhouette %.2f texels, %d "
          "trials)\n",
          cli::name(), i, lod->facesBefore, lod->facesAfter, static_cast<double>(lod->normalError),
          static_cast<double>(lod->normalError * 255.0f), static_cast<double>(lod->silhouetteError), lod->evaluations);
    }
  }
  std::printf("%s: wrote %s: %d variation(s) x %d view(s), %dx%d atlas of %d-texel cells, %d mip level(s), %zu files\n",
              cli::name(), result->sidecar.c_str(), d.variations, d.views, d.width, d.height, d.cellSize, d.mipLevels,
              result->files.size());
  if (!result->contactSheet.empty()) {
    std::printf("%s: contact sheet: %s", cli::name(), result->contactSheet.c_str());
    if (result->contactSheetCells < static_cast<int>(d.cells.size())) {
      std::printf(" (the first %d of %zu cells)", result->contactSheetCells, d.cells.size());
    }
    std::printf("\n");
  }
  return 0;
}

// "%g": 1000, 3200, 1e+05.
std::string numberText(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

std::string lowerExtension(const fs::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// The blackbody flags' ranges (core::makeBlackbodyRamp's), named as the user typed them.
std::optional<std::string> blackbodyProblem(const BlackbodyOptions& b) {
  const std::string top = numberText(core::kMaxKelvin);
  if (!(b.minKelvin > 0.0 && b.minKelvin < core::kMaxKelvin))
    return "--min must be in (0, " + top + ") kelvin, got " + numberText(b.minKelvin);
  if (!(b.maxKelvin > b.minKelvin && b.maxKelvin <= core::kMaxKelvin))
    return "--max must be above --min (" + numberText(b.minKelvin) + ") and at most " + top + " kelvin, got " +
           numberText(b.maxKelvin);
  if (b.size < 2 || b.size > core::kMaxBlackbodyTexels)
    return "--size must be in [2, " + std::to_string(core::kMaxBlackbodyTexels) + "], got " + std::to_string(b.size);
  if (!(b.normalizeKelvin > 0.0 && b.normalizeKelvin <= core::kMaxKelvin))
    return "--normalize must be in (0, " + top + "] kelvin, got " + numberText(b.normalizeKelvin);
  return std::nullopt;
}

// Import flags checked before any file is read (bad usage, exit 2).
std::optional<std::string> importProblem(const DetailOptions& d) {
  if (d.spec.size < core::kMinDetailSize || d.spec.size > core::kMaxDetailSize)
    return "--size must be in [" + std::to_string(core::kMinDetailSize) + ", " + std::to_string(core::kMaxDetailSize) +
           "], got " + std::to_string(d.spec.size);
  const int n = static_cast<int>(d.from.size());
  if (d.loopFrames < 0 || 2 * d.loopFrames > n)
    return "--loop-frames must be in [0, " + std::to_string(n / 2) + "] (half of the " + std::to_string(n) +
           " frames given), got " + std::to_string(d.loopFrames);
  return std::nullopt;
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
                o.out.c_str(), numberText(b.minKelvin).c_str(), numberText(b.maxKelvin).c_str(), b.size,
                numberText(b.normalizeKelvin).c_str());
  }
  return 0;
}

int runDetail(const Options& o) {
  const DetailOptions& d = o.detail;
  auto video =
      d.from.empty() ? bake::generateDetailVideo(d.spec) : bake::importDetailVideo(d.from, d.spec.size, d.loopFrames);
  if (!video) {
    cli::printError(video.error());
    return 1;
  }
  if (auto r = core::saveDetailVideo(o.out, *video); !r) {
    cli::printError(r.error());
    return 1;
  }
  if (!o.quiet) {
    const std::string how = d.from.empty() ? "generated, seed " + std::to_string(d.spec.seed)
                                           : "imported from " + std::to_string(d.from.size()) + " files, last " +
                                                 std::to_string(d.loopFrames) + " cross-faded into the first";
    std::printf("%s: wrote %s: detail video %dx%d, %d frames (%s)\n", cli::name(), o.out.c_str(), video->width,
                video->height, video->frames, how.c_str());
  }
  return 0;
}

}  // namespace

std::variant<Options, int> parse(int argc, char** argv) {
  Options o;
  CLI::App app{
      "puffbake: bakes 3D puff meshes into atlases of camera-space normal + depth, colour + dilated "
      "coverage and signed distance to the silhouette (McGuire & Fein 2006, Fig. 3 / Eq. 1), with a JSON "
      "sidecar and a contact sheet; and writes the fire and smoke media's black-body ramp and detail videos "
      "(Umenhoffer et al. 2006, §3).",
      cli::name()};
  app.require_subcommand(1);
  app.set_version_flag("--version", "puffbake 0.1.0");

  CLI::App* bakeCmd =
      app.add_subcommand("bake", "Bake mesh files (OBJ, OFF, PLY, STL; one variation each) and/or generated puffs");
  bakeCmd->add_option("meshes", o.inputs, "Puff mesh files, one variation each");
  GeneratorFlags bakeGen;
  bakeGen.add(*bakeCmd, true);
  bakeCmd->add_option("-o,--out", o.bake.outDir, "Output directory (created if missing)")->capture_default_str();
  bakeCmd->add_option("--name", o.bake.name, "File prefix: NAME.json, NAME_color.png, ...")->capture_default_str();
  bakeCmd
      ->add_option(
          "-s,--size", o.bake.cellSize,
          "Cell size in texels, per variation and view (8..16384; a bake that would need more than 12 GiB is refused)")
      ->capture_default_str();
  bakeCmd
      ->add_option("--supersample", o.bake.supersample,
                   "Samples per texel side for clean edges; 0 = auto (4, fewer for cells above 1024)")
      ->capture_default_str();
  std::string flange = flangeText(o.bake.flange);
  bakeCmd
      ->add_option("--flange", flange, "Outline flange width: texels (\"6\") or percent of the cell (\"3%\"); 0 = none")
      ->capture_default_str();
  bakeCmd->add_option("--views", o.bake.viewGrid, "Views per variation as an N x N grid of directions (1 = front only)")
      ->capture_default_str();
  std::string layout = "hemioct";
  bakeCmd->add_option("--view-layout", layout, "View grid: hemioct (front hemisphere) or oct (whole sphere)")
      ->check(CLI::IsMember({"hemioct", "oct"}))
      ->capture_default_str();
  std::string format = "png";
  bakeCmd->add_option("--format", format, "Map files: png (8-bit maps, 16-bit distance) or exr (half float)")
      ->check(CLI::IsMember({"png", "exr"}))
      ->capture_default_str();
  std::string color = "#ffffff";
  bakeCmd->add_option("--color", color, "Diffuse colour of meshes without vertex colours: #rrggbb or r,g,b in [0,1]")
      ->capture_default_str();
  bool noMips = false, noSheet = false;
  bakeCmd->add_flag("--no-mips", noMips, "Write level 0 only");
  bakeCmd->add_flag("--no-contact-sheet", noSheet, "Skip NAME_contact.png");
  std::string lod = "full";
  bakeCmd
      ->add_option("--lod", lod,
                   "full: bake meshes as given; auto: decimate each to the fewest faces within the tolerances")
      ->check(CLI::IsMember({"full", "auto"}))
      ->capture_default_str();
  bakeCmd
      ->add_option("--lod-normal-tolerance", o.bake.lodNormalTolerance,
                   "--lod auto: mean encoded normal error allowed, per channel (1/255 = 0.00392)")
      ->capture_default_str();
  bakeCmd
      ->add_option("--lod-silhouette-tolerance", o.bake.lodSilhouetteTolerance,
                   "--lod auto: silhouette displacement allowed, texels")
      ->capture_default_str();
  bakeCmd->add_option("--gl", o.glBackend, "GL backend: osmesa, egl or glfw (default: $PUFF_GL, else osmesa)")
      ->check(CLI::IsMember({"osmesa", "egl", "glfw"}));
  bakeCmd->add_option("--shader-dir", o.shaderDir, "Read shaders from this directory instead of the built-in copies");
  bakeCmd->add_flag("-q,--quiet", o.quiet, "Print errors only");
  bool printDefaults = false;
  bakeCmd->add_flag("--print-defaults", printDefaults, "Print every bake option's default value and exit");

  CLI::App* meshCmd =
      app.add_subcommand("mesh", "Write a generated puff, or a normalized copy of a mesh file, as OBJ/OFF/PLY/STL");
  meshCmd->add_option("mesh", o.inputs, "Mesh file to normalize (or use --generate)");
  GeneratorFlags meshGen;
  meshGen.add(*meshCmd, false);
  meshCmd->add_option("-o,--out", o.meshOut, "Output mesh file; the extension picks the format")->required();
  meshCmd->add_flag("-q,--quiet", o.quiet, "Print errors only");

  CLI::App* blackbodyCmd = app.add_subcommand(
      "blackbody",
      "Write the black-body colour ramp fire is shaded with (Planck's law seen by the CIE 1931 2-degree observer, in "
      "linear sRGB, luminance 1 at --normalize; negative out-of-gamut components kept) as an N x 1 RGB float EXR");
  blackbodyCmd->add_option("-o,--out", o.out, "Output file, .exr (written whole or not at all)")->required();
  blackbodyCmd->add_option("--min", o.blackbody.minKelvin, "Temperature of the first texel, kelvin (0 < min < max)")
      ->capture_default_str();
  blackbodyCmd->add_option("--max", o.blackbody.maxKelvin, "Temperature of the last texel, kelvin (at most 100000)")
      ->capture_default_str();
  blackbodyCmd->add_option("--size", o.blackbody.size, "Texels, evenly spaced in temperature (2..65536)")
      ->capture_default_str();
  blackbodyCmd
      ->add_option("--normalize", o.blackbody.normalizeKelvin,
                   "Temperature whose luminance becomes 1, kelvin (0 < T <= 100000); hotter is brighter")
      ->capture_default_str();
  blackbodyCmd->add_flag("-q,--quiet", o.quiet, "Print errors only");

  CLI::App* detailCmd = app.add_subcommand(
      "detail",
      "Write a detail video (a looping greyscale x, y, time texture that perturbs fire temperature and smoke "
      "opacity): tileable, looping noise, or imported from image files with --from. One image, frames stacked top "
      "to bottom, metadata puff:frames");
  bake::DetailSpec& spec = o.detail.spec;
  detailCmd
      ->add_option("-o,--out", o.out, "Output file: .png (16-bit) or .exr (half float); written whole or not at all")
      ->required();
  detailCmd->add_option("--size", spec.size, "Width and height in texels (4..4096); imported frames are resampled")
      ->capture_default_str();
  CLI::Option* framesOpt =
      detailCmd->add_option("--frames", spec.frames, "Frames in the loop (1..1024)")->capture_default_str();
  CLI::Option* seedOpt = detailCmd->add_option("--seed", spec.seed, "Noise seed")->capture_default_str();
  CLI::Option* octavesOpt =
      detailCmd->add_option("--octaves", spec.octaves, "Noise octaves (1..10)")->capture_default_str();
  CLI::Option* frequencyOpt =
      detailCmd->add_option("--frequency", spec.frequency, "Noise cells across the tile in the first octave (1..256)")
          ->capture_default_str();
  CLI::Option* contrastOpt = detailCmd
                                 ->add_option("--contrast", spec.contrast,
                                              "Standard deviation around 0.5 is contrast/6, clipped to [0, 1] (0..16)")
                                 ->capture_default_str();
  CLI::Option* fromOpt = detailCmd->add_option(
      "--from", o.detail.from,
      "Import these image files instead of generating: any format, all one size, in the order given (a shell glob "
      "such as clip/*.png sorts by name); each becomes luma, resampled to --size x --size");
  for (CLI::Option* gen : {framesOpt, seedOpt, octavesOpt, frequencyOpt, contrastOpt}) gen->excludes(fromOpt);
  detailCmd
      ->add_option("--loop-frames", o.detail.loopFrames,
                   "With --from: fade the last N frames into the first N to make the clip loop; the output has N "
                   "fewer frames (0..half the frames)")
      ->capture_default_str()
      ->needs(fromOpt);
  detailCmd->add_flag("-q,--quiet", o.quiet, "Print errors only");

  if (const auto exitCode = cli::parse(app, argc, argv)) return *exitCode;

  if (printDefaults) {
    bake::BakeOptions d;
    std::printf(
        "size = %d\nsupersample = 0 (auto)\nflange = %s\nviews = %d\nview-layout = hemioct\nformat = png\n"
        "color = #ffffff\nmips = on\ncontact-sheet = on\nlod = full\nlod-normal-tolerance = %g\n"
        "lod-silhouette-tolerance = %g\nname = %s\nout = %s\nvariations = %d (with --generate)\n",
        d.cellSize, flangeText(d.flange).c_str(), d.viewGrid, static_cast<double>(d.lodNormalTolerance),
        static_cast<double>(d.lodSilhouetteTolerance), d.name.c_str(), d.outDir.c_str(), bake::GeneratorSpec{}.count);
    return 0;
  }
  if (bakeCmd->parsed()) {
    o.command = Command::kBake;
    o.generator = bakeGen.finish();
    auto f = parseFlange(flange);
    if (!f) {
      cli::printError("--flange: expected texels (\"6\") or a percentage (\"3%\"), got \"" + flange + "\"");
      return 2;
    }
    o.bake.flange = *f;
    auto c = parseColor(color);
    if (!c) {
      cli::printError("--color: expected #rrggbb or r,g,b, got \"" + color + "\"");
      return 2;
    }
    o.bake.defaultColor = *c;
    o.bake.viewLayout = layout == "oct" ? bake::ViewLayout::kOct : bake::ViewLayout::kHemiOct;
    o.bake.format = format == "exr" ? bake::MapFormat::kExr : bake::MapFormat::kPng;
    o.bake.mips = !noMips;
    o.bake.contactSheet = !noSheet;
    o.bake.lodAuto = lod == "auto";
    if (o.inputs.empty() && !o.generator) {
      cli::printError("bake: nothing to bake: give mesh files or --generate KIND");
      return 2;
    }
  } else if (meshCmd->parsed()) {
    o.command = Command::kMesh;
    o.generator = meshGen.finish();
  } else if (blackbodyCmd->parsed()) {
    o.command = Command::kBlackbody;
    if (lowerExtension(o.out) != ".exr") {
      cli::printError("blackbody: -o: the ramp is a float EXR, so FILE must end in .exr, got \"" + o.out.string() +
                      "\"");
      return 2;
    }
    if (auto problem = blackbodyProblem(o.blackbody)) {
      cli::printError(*problem);
      return 2;
    }
  } else {
    o.command = Command::kDetail;
    if (const std::string ext = lowerExtension(o.out); ext != ".png" && ext != ".exr") {
      cli::printError("detail: -o: FILE must end in .png (16-bit) or .exr (half float), got \"" + o.out.string() +
                      "\"");
      return 2;
    }
    auto problem = o.detail.from.empty() ? std::optional<std::string>() : importProblem(o.detail);
    if (o.detail.from.empty()) {
      if (auto v = bake::validate(o.detail.spec); !v) problem = v.error().message;
    }
    if (problem) {
      cli::printError(*problem);
      return 2;
    }
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
    case Command::kNone:
      break;
  }
  return 2;
}

}  // namespace puff::app
