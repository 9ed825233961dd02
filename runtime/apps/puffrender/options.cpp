// puffrender's command line: the options, their checks (alone and against the scene) and the plan
// of which frames go where; the commands themselves are render.cpp, compare.cpp and choose.cpp.
#include "options.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include <CLI/CLI.hpp>

#include <cli/app.h>
#include <puff/core/number_text.h>
#include <puff/eval/budget.h>
#include <puff/render/flipbook.h>
#include <puff/render/path.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>
#include <puff/support/json_read.h>
#include <puff/support/text.h>

#include "commands.h"

namespace puff::app {

namespace fs = std::filesystem;

namespace {

// The plan without -o (only --contact-sheet and/or --preview): no frame files; every frame unless --frames says.
Result<Plan> planWithoutOutput(const Options& o, const scene::Scene& scene) {
  Plan plan;
  plan.writeFrames = false;
  plan.last = scene.animation.frames - 1;
  if (!o.frames.empty()) {
    PUFF_TRY_ASSIGN(auto range, parseFrameRange(o.frames));
    plan.first = range.first;
    plan.last = range.second;
  }
  if (plan.last >= scene.animation.frames) {
    return Error{"--frames " + o.frames + ": the scene has " + std::to_string(scene.animation.frames) +
                 " frame(s), 0 to " + std::to_string(scene.animation.frames - 1) + " (/animation/frames)"};
  }
  return plan;
}

// The frames to render: --frames, else every frame of a numbered output, else frame 0 (a flipbook: planFlipbook).
Result<void> planFrameRange(const Options& o, int frames, Plan& plan) {
  if (!o.frames.empty()) {
    PUFF_TRY_ASSIGN(auto range, parseFrameRange(o.frames));
    plan.first = range.first;
    plan.last = range.second;
    if (plan.last >= frames) {
      return Error{"--frames " + o.frames + ": the scene has " + std::to_string(frames) + " frame(s), 0 to " +
                   std::to_string(frames - 1) + " (/animation/frames)"};
    }
  } else if (!o.flipbook.empty()) {
    plan.last = 0;  // set by planFlipbook: as many frames as the sheet holds
  } else {
    plan.last = plan.pattern.numbered ? frames - 1 : 0;
  }
  return {};
}

// --flipbook of a loop (animation.period): one period without --frames, else whole periods; no
// cross-fade and no skipping, which would break the loop.
Result<void> planLoopSheet(const Options& o, int period, int cells, int frames, Plan& plan) {
  const std::string loop = "the scene is a loop of " + std::to_string(period) + " frames (" +
                           (o.period ? "--period" : "/animation/period") + ")";
  if (o.loop > 0) return Error{"--loop cross-fades, and " + loop + " that repeats without one: leave --loop out"};
  if (o.skipEmpty) return Error{"--skip-empty would cut into the loop: " + loop + ", every frame of it in the sheet"};
  if (period > frames) {
    return Error{"the loop is longer than the scene: " + loop + ", and /animation/frames is " + std::to_string(frames) +
                 ": give the scene at least " + std::to_string(period) + " frames"};
  }
  if (o.frames.empty()) {
    if (period > cells) {
      return Error{"--flipbook " + o.flipbook + " holds " + std::to_string(cells) + " frames, and " + loop +
                   ": give a larger grid or a shorter loop"};
    }
    plan.last = plan.first + period - 1;
  } else if (const int count = plan.last - plan.first + 1; count % period != 0) {
    return Error{"--frames " + o.frames + " holds " + std::to_string(count) + (count == 1 ? " frame" : " frames") +
                 ", and " + loop + ": a sheet loops when it holds whole periods"};
  }
  return {};
}

// --flipbook: the grid, the frames it holds without --frames, and the checks of --loop and the sheet's size.
Result<void> planFlipbook(const Options& o, const scene::Scene& scene, Plan& plan) {
  const int frames = scene.animation.frames;
  const auto grid = *parseFlipbookGrid(o.flipbook);
  plan.flipColumns = grid.first;
  plan.flipRows = grid.second;
  const int cells = grid.first * grid.second;
  if (plan.pattern.numbered) {
    return Error{"-o " + o.out + ": --flipbook writes one sprite sheet: give a single file name, e.g. sheet.png"};
  }
  const int period = scene.animation.period;
  if (period > 0) {
    if (auto ok = planLoopSheet(o, period, cells, frames, plan); !ok) return ok;
  } else if (o.frames.empty()) {
    plan.last = std::min(cells + o.loop, frames) - 1;
  }
  plan.flipLast = o.skipEmpty && o.frames.empty() ? frames - 1 : plan.last;
  const int count = plan.last - plan.first + 1;
  if (o.loop > 0 && 2 * o.loop > count) {
    return Error{"--loop " + std::to_string(o.loop) + ": a loop cross-fades the last " + std::to_string(o.loop) +
                 " frames into the first " + std::to_string(o.loop) + ", and there are " + std::to_string(count) +
                 ": render at least " + std::to_string(2 * o.loop) + " frames"};
  }
  if (count - o.loop > cells) {
    return Error{"--flipbook " + o.flipbook + " holds " + std::to_string(cells) + " frames, and --frames " + o.frames +
                 " asks for " + std::to_string(count - o.loop) +
                 (o.loop > 0 ? " (" + std::to_string(count) + " less the " + std::to_string(o.loop) + " of --loop)"
                             : std::string()) +
                 ": give a larger grid or fewer frames"};
  }
  // The sheet of whole frames: with --crop the cells are smaller, but the frames are held until the
  // crop is known, and they add up to this.
  const render::SheetRequest request{grid.first, grid.second, {0, 0, scene.width, scene.height}, o.padding, o.pow2};
  auto layout = render::layOutSheet(request);
  if (!layout) return Error{"--flipbook " + o.flipbook + (o.pow2 ? " --pow2: " : ": ") + layout.error().message};
  return checkSheetSize(*layout, "--flipbook " + o.flipbook + " of " + std::to_string(scene.width) + "x" +
                                     std::to_string(scene.height) + " frames");
}

// PNG or EXR: --format, else the output's extension; the two must agree when both say.
Result<void> planFormat(const Options& o, Plan& plan) {
  const std::string ext = core::lower(fs::path(plan.pattern.name(plan.first)).extension().string());
  const std::string fromName = ext == ".png" ? "png" : ext == ".exr" ? "exr" : "";
  if (o.format.empty()) {
    if (fromName.empty()) {
      return Error{"-o " + o.out + ": cannot tell the format from the extension \"" + ext +
                   "\"; use .png or .exr, or --format"};
    }
    plan.exr = fromName == "exr";
  } else {
    if (!fromName.empty() && fromName != o.format) {
      return Error{"--format " + o.format + " contradicts the output's extension (" + o.out + ")"};
    }
    plan.exr = o.format == "exr";
  }
  return {};
}

// Checks the options against the scene; errors are usage errors (exit 2).
Result<Plan> makePlan(const Options& o, const scene::Scene& scene) {
  if (o.out.empty()) return planWithoutOutput(o, scene);
  Plan plan;
  PUFF_TRY_ASSIGN(auto pattern, parseOutputPattern(o.out));
  plan.pattern = pattern;
  PUFF_TRY(planFrameRange(o, scene.animation.frames, plan));
  if (!o.flipbook.empty()) PUFF_TRY(planFlipbook(o, scene, plan));
  if (!plan.pattern.numbered && plan.last > plan.first && o.flipbook.empty()) {
    return Error{"-o " + o.out + ": " + std::to_string(plan.last - plan.first + 1) +
                 " frames need a numbered output, e.g. frame_####.png or frame_%04d.png"};
  }
  PUFF_TRY(planFormat(o, plan));
  return plan;
}

// The scene and where its frames go: scene, -o, --frames, --format.
void addOutputOptions(CLI::App& app, Options& o) {
  app.add_option("scene", o.scene, "Scene file (JSON)")->required();
  app.add_option("-o,--out", o.out,
                 "Output image. For a sequence, a name with one %d, %0Nd or run of # (frame_####.png) that the frame "
                 "number fills in; without one, a single frame is written to exactly OUT. Required unless "
                 "--print-scene");
  app.add_option("--frames", o.frames,
                 "Frame N or range A-B (0-based, inclusive). Default: frame 0 for a single OUT, every frame of the "
                 "scene (/animation/frames) for a numbered OUT");
  app.add_option("--format", o.format,
                 "png (8-bit sRGB RGBA, after the view transform) or exr (the scene-linear frame before the view "
                 "transform, half-float RGBA; values above 1 kept). A transparent scene (/output/background "
                 "\"transparent\") writes its coverage as alpha: straight in PNG unless /output/alpha is "
                 "\"premultiplied\", premultiplied in EXR (straight EXR is refused). Default: from OUT's extension "
                 "(.png or .exr)")
      ->check(CLI::IsMember({"png", "exr"}));
  app.add_flag("--float32", o.float32,
               "EXR output: 32-bit float channels instead of half float (the frame is rendered in half floats: "
               "the same values, for tools that want float32 files)");
  app.add_option("--view", o.view,
                 "View transform from scene-linear to the PNG's display values, replacing the scene's /output/view: "
                 "standard (clip, then sRGB) or filmic (highlights rolled off keeping hue). Default: the scene's, "
                 "else filmic for scenes with fire and standard for the rest (docs/colour.md)")
      ->check(CLI::IsMember({"standard", "filmic"}));
}

// How it is drawn: --gl, --width, --height, --samples, --art-dir, --shader-dir, --style, --path.
void addRenderOptions(CLI::App& app, Options& o) {
  std::vector<std::string> presets = scene::stylePresetNames();
  std::string presetList;
  for (const std::string& p : presets) presetList += (presetList.empty() ? "" : ", ") + p;
  app.add_option("--gl", o.glBackend, "GL backend: osmesa, egl or glfw (default: $PUFF_GL, else osmesa)")
      ->check(CLI::IsMember({"osmesa", "egl", "glfw"}));
  app.add_option("--width", o.width, "Output width in pixels, replacing the scene's (1..16384)")
      ->check(CLI::Range(1, 16384));
  app.add_option("--height", o.height, "Output height in pixels, replacing the scene's (1..16384)")
      ->check(CLI::Range(1, 16384));
  app.add_option("--samples", o.samples, "MSAA samples per pixel, replacing the scene's: 1, 2, 4 or 8")
      ->check(CLI::IsMember({1, 2, 4, 8}));
  app.add_option("--art-dir", o.artDir, cli::kArtDirHelp);
  app.add_option("--shader-dir", o.shaderDir, "Read shaders from this directory instead of the built-in copies");
  app.add_option("--style", o.style, "Render with this style preset instead of the scene's style: " + presetList)
      ->check(CLI::IsMember(presets));
  std::string pathHelp =
      "Render path (default: cel; without --path, cel falls back to fixed, saying so, when the context is older "
      "than GL 4.5, and a shader that does not build is an error either way):";
  std::vector<std::string> pathNames;
  for (const render::RenderPathInfo& p : render::renderPathTable()) {
    pathHelp += "\n  " + p.name + ": " + p.description;
    pathNames.push_back(p.name);
  }
  app.add_option("--path", o.path, pathHelp)->check(CLI::IsMember(pathNames));
}

// --compare and its --tolerance (returned, to tell whether it was given).
CLI::Option* addCompareOptions(CLI::App& app, Options& o) {
  app.add_option("--compare", o.compare,
                 "Render every frame with both paths (fixed,cel or cel,fixed) and report how close they come: smoke "
                 "coverage agreement (IoU of the masks) and the share of shared smoke pixels within --tolerance; OUT "
                 "gets [first | second | difference] side by side")
      ->check(CLI::IsMember({"fixed,cel", "cel,fixed"}));
  return app
      .add_option("--tolerance", o.toneTolerance, "--compare: per-channel tone tolerance in [0, 1]. Default: 0.1")
      ->check(CLI::Range(0.0f, 1.0f));
}

// --flipbook's sheet: padding, power-of-two sides, the crop and leading empty frames (docs/flipbooks.md).
void addFlipbookSheetOptions(CLI::App& app, Options& o) {
  app.add_option("--padding", o.padding,
                 "--flipbook: PX empty texels around each frame, on every side, inside its cell (cells stay "
                 "equal, so an engine dividing the sheet by the grid finds them); in a straight-alpha PNG their "
                 "colour is bled from the frame so that filtering and mipmaps do not fringe (premultiplied and "
                 "EXR sheets hold 0 there). Default: 0")
      ->check(CLI::Range(0, render::kMaxSheetPadding))
      ->type_name("PX");
  app.add_flag("--pow2", o.pow2,
               "--flipbook: round the sheet's sides up to powers of two, the margin split around each frame in "
               "its cell; needs a power-of-two grid (4x4, 8x8, 8x4...) so that the cells stay whole texels");
  app.add_flag("--crop", o.crop,
               "--flipbook: cells hold only the rectangle of the frame that some frame of the sequence covers "
               "(one crop for all, so the effect does not jump); the layout JSON records it in pixels and scene "
               "units, and where the camera's target falls in the cell");
  std::string names;
  for (const render::FlipbookMap& m : render::kFlipbookMaps) names += (names.empty() ? "" : ", ") + std::string(m.name);
  app.add_option("--maps", o.maps,
                 "--flipbook: maps of the same cells for an engine that lights the smoke itself, each a PNG "
                 "beside the sheet (SHEET_normal.png, ...) named in the layout JSON with its encoding: " +
                     names + " (docs/flipbooks.md). Comma-separated; the puffs and objects only, no shadows or media")
      ->delimiter(',')
      ->transform([](std::string name) {  // "normal, depth": the names without the spaces around them
        const auto first = name.find_first_not_of(" \t"), last = name.find_last_not_of(" \t");
        return first == std::string::npos ? std::string() : name.substr(first, last - first + 1);
      })
      ->check(CLI::IsMember(render::flipbookMapNames()))
      ->type_name("LIST");
  app.add_option("--map-bits", o.mapBits, "--maps: bits a channel, 8 or 16. Default: 8")
      ->check(CLI::IsMember({8, 16}))
      ->type_name("8|16");
  app.add_flag("--skip-empty", o.skipEmpty,
               "--flipbook: leading frames that draw nothing take no cell; without --frames the sheet is filled "
               "from the first frame that draws something");
}

// --max-error E, kept as text: parseMaxError() reads it.
CLI::Option* addMaxErrorOption(CLI::App& app, std::string& text) {
  std::string sizes;  // "96, 48 or 24"
  for (std::size_t i = 0; i < eval::kHullFromPixels.size(); ++i) {
    sizes += (i == 0                                  ? ""
              : i + 1 == eval::kHullFromPixels.size() ? " or "
                                                      : ", ") +
             core::numberText(eval::kHullFromPixels[i]);
  }
  return app
      .add_option("--max-error", text,
                  "Render with just enough model, measured against the references at the first, "
                  "middle and last of the frames rendered (the worst of them), E an RMSE in (0, 1]. "
                  "Scenes with cel particles: first the fewest of the placed emitters' particles "
                  "(/particleFraction: 1/8, 1/4, 1/2 or all, each larger to fill the same volume), "
                  "then the smallest atlas (/atlasLevel: the atlas from one of its mip levels on), "
                  "whose frames stay within E of the cel reference of the full model (--path "
                  "reference; 8-bit values; e.g. 0.12: the nailboards' own error is about 0.09 on "
                  "the art scenes); if none does, all the particles and the full atlas, with a "
                  "warning. With oriented puffs, then the fastest way to turn them within E (/style/tumble "
                  "and /style/hullFromPixels: the blend, the hull only for puffs " +
                      sizes +
                      " px across "
                      "and more, or the hull on all, in that order), or the closest. "
                      "With shadows on, then the fastest shadows within E (/style/shadowMethod and "
                      "/style/shadowMapScale: the map at 0.25, 0.5, 1 or 2 texels a pixel, or the volumes, "
                      "ordered by their measured time); if none is, the closest. Scenes with media: "
                      "the cheapest media layer resolution (/media/resolution: 0.125, 0.25, 0.5 or 1) "
                      "within E (linear colour, e.g. 0.01) of the exact media reference; if none does, 1. "
                      "Prints the measurements and one line per choice saying what it chose and why on "
                      "stderr; -q: those lines only. The media method and mesh detail (baked into the "
                      "atlas: puffbake --lod auto) are not chosen. Measured frames leave out explosion "
                      "lights, heat shimmer and motion blur (the reference has none); the output keeps "
                      "them")
      ->type_name("E");
}

// Parsed here, not by CLI11, so that nan and inf get the same message as 0 or 2.
Result<double> parseMaxError(const std::string& text) {
  char* end = nullptr;
  const double e = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(e) || !(e > 0.0 && e <= 1.0)) {
    return Error{"--max-error: expected an RMSE in (0, 1] (linear colour, e.g. 0.01), got \"" + text + "\""};
  }
  return e;
}

// The checks of the options alone that CLI11 does not make; errors are usage errors (exit 2).
Result<void> checkOptions(const Options& o) {
  if (o.out.empty() && !o.printScene && o.contactSheet.empty() && o.preview.empty()) {
    return Error{"-o OUT is required (or --contact-sheet, --preview or --print-scene); see --help"};
  }
  if (!o.contactSheet.empty() && core::lower(fs::path(o.contactSheet).extension().string()) != ".png") {
    return Error{"--contact-sheet " + o.contactSheet + ": the contact sheet is a PNG: give a .png name"};
  }
  if (!o.preview.empty()) {
    const std::string ext = core::lower(fs::path(o.preview).extension().string());
    if (ext != ".gif" && ext != ".mp4") {
      return Error{"--preview " + o.preview + ": expected a .gif or .mp4 name (" + previewSupport() + ")"};
    }
  }
  if (!o.contactSheet.empty() && !o.out.empty()) {
    auto pattern = parseOutputPattern(o.out);
    if (pattern && ((!pattern->numbered &&
                     fs::path(pattern->prefix).lexically_normal() == fs::path(o.contactSheet).lexically_normal()) ||
                    (pattern->numbered && o.contactSheet.rfind(pattern->prefix, 0) == 0 &&
                     o.contactSheet.size() > pattern->prefix.size() + pattern->suffix.size() &&
                     o.contactSheet.compare(o.contactSheet.size() - pattern->suffix.size(), pattern->suffix.size(),
                                            pattern->suffix) == 0 &&
                     std::all_of(o.contactSheet.begin() + static_cast<long>(pattern->prefix.size()),
                                 o.contactSheet.end() - static_cast<long>(pattern->suffix.size()),
                                 [](char c) { return c >= '0' && c <= '9'; })))) {
      return Error{"--contact-sheet " + o.contactSheet + " is where -o " + o.out +
                   " writes a frame: give the sheet another name"};
    }
  }
  if ((!o.contactSheet.empty() || !o.preview.empty()) && (!o.flipbook.empty() || !o.compare.empty())) {
    return Error{"--contact-sheet and --preview go with frames rendered as they are, not with --flipbook or --compare"};
  }
  if ((!o.contactSheet.empty() || !o.preview.empty()) && o.maxError && o.out.empty()) {
    return Error{"--max-error chooses the model for the frames written: give -o as well"};
  }
  if (!o.out.empty()) {
    if (auto p = parseOutputPattern(o.out); !p) return p.error();
  }
  if (!o.frames.empty()) {
    if (auto r = parseFrameRange(o.frames); !r) return r.error();
  }
  if (!o.flipbook.empty()) {
    if (auto g = parseFlipbookGrid(o.flipbook); !g) return g.error();
    if (!o.compare.empty()) return Error{"--flipbook and --compare do not go together"};
    if (!o.maps.empty() && o.loop > 0) {
      return Error{
          "--maps and --loop do not go together: --loop cross-fades frames, and a cross-faded normal or "
          "depth is no surface's (a scene that loops, /animation/period or --period, needs no cross-fade)"};
    }
    if (!o.maps.empty() && o.path != "cel")
      return Error{"--maps: only the cel path writes maps; leave out --path " + o.path};
  }
  if (o.mapBits != 0 && o.maps.empty()) return Error{"--map-bits applies to --maps"};
  for (std::size_t i = 0; i < o.maps.size(); ++i) {
    if (std::find(o.maps.begin(), o.maps.begin() + static_cast<std::ptrdiff_t>(i), o.maps[i]) !=
        o.maps.begin() + static_cast<std::ptrdiff_t>(i))
      return Error{"--maps: " + o.maps[i] + " is asked for twice"};
  }
  if (o.flipbook.empty()) {
    for (const auto& [given, name] : {std::pair{o.loop > 0, "--loop"},
                                      {o.padding > 0, "--padding"},
                                      {o.pow2, "--pow2"},
                                      {o.crop, "--crop"},
                                      {o.skipEmpty, "--skip-empty"},
                                      {!o.maps.empty(), "--maps"}}) {
      if (given) return Error{std::string(name) + " applies to a --flipbook"};
    }
  }
  return {};
}

// The checks of the options against the scene, before anything is drawn; errors are usage errors
// (exit 2).
Result<void> checkAgainstScene(const Options& o, const scene::Scene& scene, const Plan& plan) {
  if (!o.maps.empty()) {
    // The maps' depth and motion are measured from the camera: one camera for the whole sheet.
    const cel::Camera first = scene::cameraAt(scene, plan.first);
    for (int f = plan.first + 1; f <= plan.flipLast; ++f) {
      if (scene::cameraAt(scene, f) == first) continue;
      return Error::at(scene.file, "--maps: the camera moves (frame " + std::to_string(f) +
                                       " is seen otherwise than frame " + std::to_string(plan.first) +
                                       "), and the maps' depth and motion are measured from one still camera: set "
                                       "/animation/orbit to 0 and leave out its camera and target paths");
    }
  }
  if (o.float32 && !plan.exr) return Error{"--float32 applies only to EXR output (-o NAME.exr or --format exr)"};
  if (!o.view.empty() && plan.exr) {
    return Error{"--view applies only to PNG output: EXR holds the scene-linear frame before the view transform"};
  }
  if (!o.compare.empty() && plan.exr) return Error{"--compare writes 8-bit PNG comparison images: give -o a .png name"};
  if (!o.alpha.empty() && !scene.transparent) {
    return Error::at(scene.file,
                     "--alpha applies to a transparent frame (/output/background \"transparent\", "
                     "or --flipbook): this scene draws an opaque background");
  }
  if (scene.transparent && plan.exr && scene.alpha == core::AlphaMode::kStraight) {
    return Error::at(scene.file,
                     "/output/alpha: \"straight\" cannot be written to EXR, which stores premultiplied colour (its "
                     "convention): write a PNG, or ask for \"premultiplied\"");
  }
  if (scene.transparent && !o.compare.empty()) {
    return Error::at(scene.file,
                     "/output/background: --compare draws opaque comparison images, not a transparent frame");
  }
  if (o.compare.empty() && o.toleranceGiven) return Error{"--tolerance applies only with --compare"};
  if (!o.compare.empty() && o.path != "cel") {
    return Error{"--path and --compare do not go together: --compare draws with both paths"};
  }
  if (o.maxError) {
    if (!scene.media && !hasCelParticles(scene)) {
      return Error{"--max-error chooses the nailboards' atlas level and the media layer's resolution, and " +
                   o.scene.string() + " has neither cel particles nor media (/media)"};
    }
    if (!o.compare.empty()) {
      return Error{"--max-error and --compare do not go together: --compare draws within the fixed path's limits"};
    }
    if (o.path != "cel") {
      return Error{"--max-error chooses what the programmable (cel) path draws with: leave out --path " + o.path};
    }
  }
  return {};
}

}  // namespace

Result<std::pair<int, int>> parseFlipbookGrid(const std::string& text) {
  const Error bad{"--flipbook: expected COLSxROWS, each 1 to 256 (e.g. 8x8), got \"" + text + "\""};
  const auto x = core::lower(text).find('x');
  if (x == std::string::npos) return bad;
  auto a = parseFrameRange(text.substr(0, x)), b = parseFrameRange(text.substr(x + 1));
  if (!a || !b || a->first != a->second || b->first != b->second) return bad;
  if (a->first < 1 || a->first > 256 || b->first < 1 || b->first > 256) return bad;
  return std::pair{a->first, b->first};
}

std::variant<Options, int> parse(int argc, char** argv) {
  Options o;
  CLI::App app{
      "puffrender: renders a scene file (JSON: camera, light, style, particles, emitters, objects; see "
      "docs/scene-format.md) with cel-shaded nailboards, outlines and shadows (a shadow map, or billboard shadow "
      "volumes: McGuire & Fein "
      "2006) into a PNG or EXR image, or a numbered image sequence.",
      cli::name()};
  app.set_version_flag("--version", "puffrender 0.1.0");
  addOutputOptions(app, o);
  addRenderOptions(app, o);
  CLI::Option* tolerance = addCompareOptions(app, o);
  std::string maxErrorText;
  CLI::Option* maxError = addMaxErrorOption(app, maxErrorText);
  app.add_option("--flipbook", o.flipbook,
                 "Render the frames into one sprite sheet for a game engine's flipbook (Unity's Texture Sheet "
                 "Animation, Godot's particle animation): OUT (one .png or .exr) gets COLSxROWS equal cells, each "
                 "a frame at the output size (or its --crop, inside --padding and --pow2's margin), frame by "
                 "frame left to right and top to bottom, on a transparent background; OUT's name with .json gets "
                 "the layout, frame rate and alpha mode (docs/flipbooks.md). Frames: --frames, else as many from "
                 "frame 0 (--skip-empty: from the first that draws something) as the sheet holds (at most the "
                 "scene's)")
      ->type_name("COLSxROWS");
  app.add_option("--contact-sheet", o.contactSheet,
                 "Also (or, without -o, only) write the frames as one PNG grid, each with its frame number under it, "
                 "thumbnails at most 256 pixels wide, the sheet at most 2048 wide and 8192 tall (one frame in N "
                 "when more do not fit, and it says so); transparent frames over a grey checker")
      ->type_name("FILE.png");
  app.add_option("--preview", o.preview,
                 "Also (or, without -o, only) write the frames as an animated preview at the scene's frame rate, "
                 "looping: .gif through OpenImageIO's GIF writer (256 colours a frame, at most 640 pixels wide) or "
                 ".mp4 (H.264) through the ffmpeg program; " +
                     previewSupport())
      ->type_name("FILE.gif|FILE.mp4");
  app.add_option("--loop", o.loop,
                 "--flipbook: cross-fade the last N frames into the first N (frame A+i of the sheet's first N is "
                 "mixed with the N frames after its last, the weight moving from them to it), so the sheet loops "
                 "without a jump; it holds N frames fewer than are rendered. Ink lines that move are doubled where "
                 "frames mix: --period loops a simulated scene without mixing. Default: 0 (no loop)")
      ->check(CLI::Range(0, 65536))
      ->type_name("N");
  app.add_option("--period", o.period,
                 "Render the scene as a loop of N frames (replacing /animation/period; 0: none): the simulators' "
                 "emitters repeat every N frames and frame 0 starts in the loop, so frame f + N is frame f. A "
                 "--flipbook of a loop holds whole periods (without --frames: frames 0 to N-1) and loops without "
                 "cross-fading. Refused, naming it, when something in the scene does not repeat "
                 "(docs/simulation.md, \"Loops\", lists what)")
      ->check(CLI::Range(0, sim::kMaxPeriod))
      ->type_name("N");
  addFlipbookSheetOptions(app, o);
  app.add_option("--alpha", o.alpha,
                 "How a transparent frame's alpha is written, replacing /output/alpha: straight (colour as it is "
                 "where covered: PNG's convention and the default for PNG) or premultiplied (colour times alpha: "
                 "EXR's, and the only one EXR takes)")
      ->check(CLI::IsMember({"straight", "premultiplied"}));
  app.add_flag("--print-scene", o.printScene,
               "Print the scene as it will be rendered (every field, defaults and the options above applied) as JSON, "
               "and exit without rendering");
  app.add_flag("-q,--quiet", o.quiet, "Print errors only (and --max-error's one-line choice)");

  if (const auto exitCode = cli::parse(app, argc, argv)) return *exitCode;
  o.toleranceGiven = tolerance->count() > 0;
  // Maps come from the cel path alone: no fallback to the fixed path for them.
  o.pathGiven = app.count("--path") > 0 || !o.maps.empty();
  if (maxError->count() > 0) {
    auto e = parseMaxError(maxErrorText);
    if (!e) {
      cli::printError(e.error());
      return 2;
    }
    o.maxError = *e;
  }
  if (auto r = checkOptions(o); !r) {
    cli::printError(r.error());
    return 2;
  }
  if (o.artDir.empty()) o.artDir = cli::defaultArtDir();
  return o;
}

namespace {

// The scene file, read with --period in place of its own loop: --period 0 turns off a loop the file
// could not hold (an orbiting camera), and what --period N cannot loop is the option's error
// (checkLoop, after).
Result<scene::Scene> loadSceneFile(const Options& o) {
  if (!o.period) return scene::loadScene(o.scene, o.artDir);
  PUFF_TRY_ASSIGN(auto j, core::jsonread::loadJsonFile(o.scene));
  if (j.is_object()) {
    if (auto a = j.find("animation"); a != j.end() && a->is_object()) a->erase("period");
  }
  return scene::parseScene(j, o.scene, o.artDir);
}

// Whether the scene draws ink lines: outlined puffs, or cartoon media.
bool drawsInk(const scene::Scene& s) {
  const bool outlined = s.style.outlines && s.style.outlineWidth > 0.0f;
  return (scene::hasParticles(s) && outlined) || (s.media && s.media->settings.style == media::Style::kCartoon);
}

}  // namespace

int run(const Options& o) {
  auto loaded = loadSceneFile(o);
  if (!loaded) {
    cli::printError(loaded.error());
    return 1;
  }
  scene::Scene scene = std::move(*loaded);
  if (o.period) {
    scene.animation.period = *o.period;
    if (auto ok = scene::checkLoop(scene); !ok) {
      cli::printError(Error{"--period " + std::to_string(*o.period) + ": " + ok.error().message});
      return 2;
    }
  }
  if (!o.quiet) {
    for (const std::string& w : scene::sceneWarnings(scene)) {
      std::fprintf(stderr, "%s: warning: %s: %s\n", cli::name(), o.scene.c_str(), w.c_str());
    }
  }
  if (o.width) scene.width = *o.width;
  if (o.height) scene.height = *o.height;
  if (o.samples) scene.samples = *o.samples;
  if (!o.view.empty()) scene.view = core::parseViewTransform(o.view);
  if (!o.flipbook.empty()) {
    scene.transparent = true;  // a sprite sheet's cells are the smoke alone
    if (!scene.plate.empty()) {
      if (!o.quiet) {
        std::fprintf(stderr, "%s: note: a flipbook has a transparent background: the plate %s is left out\n",
                     cli::name(), scene.plate.c_str());
      }
      scene.plate.clear();
    }
  }
  if (!o.alpha.empty()) {
    scene.alpha = o.alpha == "premultiplied" ? core::AlphaMode::kPremultiplied : core::AlphaMode::kStraight;
  }
  if (!o.style.empty()) {
    auto style = scene::stylePreset(o.style);
    if (!style) {
      cli::printError(style.error());
      return 2;
    }
    scene.style = *style;
    scene.stylePreset = o.style;
  }
  if (o.printScene) {
    std::cout << scene::jsonText(scene::toJson(scene)) << "\n";
    return 0;
  }
  auto plan = makePlan(o, scene);
  if (!plan) {
    cli::printError(plan.error());
    return 2;
  }
  if (auto r = checkAgainstScene(o, scene, *plan); !r) {
    cli::printError(r.error());
    return 2;
  }
  if (!o.preview.empty()) {
    if (auto r = checkPreviewTarget(o.preview); !r) {
      cli::printError(r.error());
      return 1;
    }
  }
  if (plan->flipColumns > 0 && o.loop > 0 && !o.quiet && drawsInk(scene)) {
    std::fprintf(stderr,
                 "%s: note: --loop cross-fades frames, doubling the ink lines where the frames it mixes differ; "
                 "--period N loops a simulated scene without mixing\n",
                 cli::name());
  }
  if (plan->flipColumns > 0) {
    if (auto r = checkFlipbookLayoutTarget(o, *plan); !r) {
      cli::printError(r.error());
      return 2;
    }
  }
  return renderFrames(o, scene, *plan);
}

}  // namespace puff::app
