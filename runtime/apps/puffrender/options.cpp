#include "options.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <set>
#include <tuple>

#include <CLI/CLI.hpp>

#include <cli/app.h>

#include <puff/core/files.h>
#include <puff/core/gl_context.h>
#include <puff/core/image.h>
#include <puff/core/shader.h>
#include <puff/render/budget.h>
#include <puff/render/compare.h>
#include <puff/render/render.h>
#include <puff/render/scene.h>

namespace puff::app {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The art directory when --art-dir is not given: $PUFF_ART, else build/art (where the build bakes
// art/), relative to the working directory.
fs::path defaultArtDir() {
  const char* env = std::getenv("PUFF_ART");
  return env && *env ? fs::path(env) : fs::path("build/art");
}

// Everything run() needs once the scene is known: which frames go where, in which format.
struct Plan {
  OutputPattern pattern;
  int first = 0, last = 0;
  bool exr = false;
};

// Checks the options against the scene; errors are usage errors (exit 2).
Result<Plan> makePlan(const Options& o, const render::Scene& scene) {
  Plan plan;
  auto pattern = parseOutputPattern(o.out);
  if (!pattern) return pattern.error();
  plan.pattern = *pattern;
  const int frames = scene.animation.frames;
  if (!o.frames.empty()) {
    auto range = parseFrameRange(o.frames);
    if (!range) return range.error();
    plan.first = range->first;
    plan.last = range->second;
    if (plan.last >= frames) {
      return Error{"--frames " + o.frames + ": the scene has " + std::to_string(frames) + " frame(s), 0 to " +
                   std::to_string(frames - 1) + " (/animation/frames)"};
    }
  } else {
    plan.last = plan.pattern.numbered ? frames - 1 : 0;
  }
  if (!plan.pattern.numbered && plan.last > plan.first) {
    return Error{"-o " + o.out + ": " + std::to_string(plan.last - plan.first + 1) +
                 " frames need a numbered output, e.g. frame_####.png or frame_%04d.png"};
  }
  const std::string ext = lower(fs::path(plan.pattern.name(plan.first)).extension().string());
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
  return plan;
}

// --compare A,B: every frame by both paths, and without particles for the masks; OUT gets the side
// by side image, stdout a line per frame and a summary.
int compareFrames(const Options& o, const render::Scene& scene, const Plan& plan) {
  const std::string first = o.compare.substr(0, o.compare.find(','));
  const std::string second = o.compare.substr(o.compare.find(',') + 1);
  const render::RenderPath pa = *render::parseRenderPath(first), pb = *render::parseRenderPath(second);
  std::vector<std::string> changes;
  const render::Scene limited = render::restrictToFixedLimits(scene, &changes);
  const render::Scene bare = render::withoutParticles(limited);
  if (!changes.empty() && !o.quiet) {
    std::string list;
    for (const std::string& c : changes) list += (list.empty() ? "" : ", ") + c;
    std::printf("%s: comparing within the fixed path's limits: %s\n", cli::name(), list.c_str());
  }
  std::unique_ptr<render::SceneRenderer> ra, rb, ra0, rb0;
  for (auto [slot, sc, p] : {std::tuple{&ra, &limited, pa}, std::tuple{&rb, &limited, pb}, std::tuple{&ra0, &bare, pa},
                             std::tuple{&rb0, &bare, pb}}) {
    auto r = render::SceneRenderer::create(*sc, p);
    if (!r) {
      cli::printError(r.error());
      return 1;
    }
    *slot = std::move(*r);
  }
  double worstIou = 1.0, worstTone = 1.0;
  const int count = plan.last - plan.first + 1;
  for (int f = plan.first; f <= plan.last; ++f) {
    core::Image images[4];
    render::SceneRenderer* renderers[4] = {ra.get(), ra0.get(), rb.get(), rb0.get()};
    for (int i = 0; i < 4; ++i) {
      auto image = renderers[i]->renderFrame(f);
      if (!image) {
        cli::printError(image.error());
        return 1;
      }
      images[i] = std::move(*image);
    }
    core::Image side;
    const render::Parity p = render::compareFrames(images[0], images[1], images[2], images[3], o.toneTolerance, &side);
    worstIou = std::min(worstIou, p.iou);
    worstTone = std::min(worstTone, p.toneShare);
    const fs::path target = plan.pattern.name(f);
    core::OutputTransaction out;
    const fs::path temp = out.stage(target);
    if (auto r = core::writeImage(temp, side, core::PixelType::kUInt8, {}, "frame.png"); !r) {
      cli::printError(Error::at(target, r.error().message));
      return 1;
    }
    if (auto r = out.commit(); !r) {
      cli::printError(r.error());
      return 1;
    }
    char tone[96];
    if (p.both > 0) {
      std::snprintf(tone, sizeof tone, "tone within %.2f on %.1f%% of shared smoke pixels", o.toneTolerance,
                    100.0 * p.toneShare);
    } else {
      std::snprintf(tone, sizeof tone, "no shared smoke pixels to compare tones on");
    }
    std::printf(
        "%s: frame %d: smoke coverage IoU %.3f (%s %zu px, %s %zu px, both %zu); %s; mean |difference| %.3f "
        "over the smoke -> %s\n",
        cli::name(), f, p.iou, first.c_str(), p.maskA, second.c_str(), p.maskB, p.both, tone, p.meanAbsDiff,
        target.c_str());
  }
  if (count > 1) {
    std::printf("%s: %d frames: lowest IoU %.3f, lowest tone agreement %.1f%%\n", cli::name(), count, worstIou,
                100.0 * worstTone);
  }
  return 0;
}

// --max-error: measures every media layer resolution at up to three of the frames to render, against
// the exact reference, and sets the cheapest within the budget on `scene` (render/budget.h).
// Returns 0, or the exit code of a failure (after saying why).
int chooseMediaResolution(const Options& o, render::Scene& scene, const Plan& plan) {
  const std::vector<int> frames = render::budgetFrames(plan.first, plan.last);
  if (!o.quiet) {
    std::string list;
    for (int f : frames) list += (list.empty() ? "" : ", ") + std::to_string(f);
    std::fprintf(stderr, "%s: --max-error %g: measuring media resolutions 0.125 to 1 against the reference at %s %s\n",
                 cli::name(), *o.maxError, frames.size() == 1 ? "frame" : "frames", list.c_str());
    std::fflush(stderr);
  }
  auto budget = render::measureMediaBudget(scene, frames);
  if (!budget) {
    cli::printError(budget.error());
    return 1;
  }
  auto choice = render::chooseMediaResolution(*budget, *o.maxError);
  if (!choice) {  // parse() checked the value
    cli::printError("--max-error: " + choice.error().message);
    return 2;
  }
  if (!o.quiet) {
    std::fprintf(stderr, "%s", render::budgetTable(*budget, *choice).c_str());
    if (!choice->met)
      std::fprintf(stderr, "%s: warning: %s\n", cli::name(), render::budgetWarning(*budget, *choice).c_str());
  }
  std::fprintf(stderr, "%s: %s\n", cli::name(), render::budgetSummary(*budget, *choice).c_str());
  std::fflush(stderr);
  scene.media->resolution = budget->candidates[choice->chosen].resolution;
  return 0;
}

// --max-error on a scene with cel particles: measures one of the nailboards' run-time parameters
// (the share of the emitters' particles, or the atlas level) against the cel reference of the full
// model and sets the cheapest within the budget on `scene` (render/budget.h).
int chooseCelModel(const Options& o, render::Scene& scene, const Plan& plan, render::CelKnob knob,
                   std::vector<core::Image>* references) {
  const std::vector<int> frames = render::budgetFrames(plan.first, plan.last);
  const bool atlas = knob == render::CelKnob::kAtlasLevel;
  if (!o.quiet) {
    std::string list;
    for (int f : frames) list += (list.empty() ? "" : ", ") + std::to_string(f);
    std::fprintf(stderr, "%s: --max-error %g: measuring %s against the cel reference at %s %s\n", cli::name(),
                 *o.maxError,
                 atlas ? "the atlas at each mip level" : "1/8, 1/4, 1/2 and all of the emitters' particles",
                 frames.size() == 1 ? "frame" : "frames", list.c_str());
    std::fflush(stderr);
  }
  auto budget = render::measureCelBudget(scene, frames, {}, knob, *references);
  if (!budget) {
    cli::printError(budget.error());
    return 1;
  }
  auto choice = render::chooseCelBudget(*budget, *o.maxError);
  if (!choice) {
    cli::printError("--max-error: " + choice.error().message);
    return 2;
  }
  if (!o.quiet) {
    std::fprintf(stderr, "%s", render::celBudgetTable(*budget, *choice).c_str());
    if (!choice->met)
      std::fprintf(stderr, "%s: warning: %s\n", cli::name(), render::celBudgetWarning(*budget, *choice).c_str());
  }
  std::fprintf(stderr, "%s: %s\n", cli::name(), render::celBudgetSummary(*budget, *choice).c_str());
  std::fflush(stderr);
  *references = std::move(budget->references);  // the next parameter measures against the same
  const render::CelCandidate& c = budget->candidates[choice->chosen];
  if (atlas) {
    scene.atlasLevel = c.atlasLevel;
  } else {
    scene.particleFraction = c.particleFraction;
  }
  return 0;
}

int renderFrames(const Options& o, render::Scene scene, const Plan& plan) {
  // Fail before any rendering if an output can never be written: every directory the frames go
  // to is created now (and taken back, if still empty, when the run fails) and must be writable.
  core::OutputTransaction directories;
  std::set<fs::path> dirs;
  for (int f = plan.first; f <= plan.last; ++f) {
    dirs.insert(fs::path(plan.pattern.name(f)).parent_path());
    if (!plan.pattern.numbered) break;
  }
  for (const fs::path& dir : dirs) {
    if (auto r = directories.prepareDirectory(dir); !r) {
      cli::printError(r.error());
      return 1;
    }
  }

  if (!o.shaderDir.empty()) core::setShaderDir(o.shaderDir);
  const bool comparing = !o.compare.empty();
  render::RenderPath path = *render::parseRenderPath(o.path);
  core::GlContextOptions glOptions;
  glOptions.backend = o.glBackend;
  glOptions.width = glOptions.height = 16;  // frames are drawn into the renderer's own target
  if (comparing) {
    glOptions.profile = core::GlProfile::kCompatibility;  // both paths in one context
  } else if (path == render::RenderPath::kFixed) {
    // The oldest context the platform gives: compatibility, asked for 1.3, the path's minimum (Mesa
    // gives its highest compatibility version when it can).
    // Its own framebuffer is the frame's size: a GL 1.x/2.x context has no framebuffer objects.
    glOptions.profile = core::GlProfile::kCompatibility;
    glOptions.major = 1, glOptions.minor = 3;
    glOptions.width = scene.width, glOptions.height = scene.height;
  }
  auto context = core::createGlContext(glOptions);
  std::string whyNotProgrammable;
  if (!context && path == render::RenderPath::kCel && !comparing) {
    whyNotProgrammable = context.error().message;
  } else if (!context) {
    cli::printError(context.error());
    return 1;
  } else if (path == render::RenderPath::kCel && !comparing) {
    if (auto ok = render::SceneRenderer::checkProgrammable(); !ok) whyNotProgrammable = ok.error().message;
  }
  if (!whyNotProgrammable.empty()) {
    // The automatic fallback: an old context, or a programmable path that does not build.
    context = Error{""};  // the old context goes before the new one is made current
    glOptions.profile = core::GlProfile::kCompatibility;
    glOptions.major = 1, glOptions.minor = 3;
    glOptions.width = scene.width, glOptions.height = scene.height;
    context = core::createGlContext(glOptions);
    if (!context) {
      cli::printError("the programmable (cel) path cannot run here (" + whyNotProgrammable +
                      "), and there is no context for the fixed-function path either: " + context.error().message);
      return 1;
    }
    std::fprintf(stderr,
                 "%s: the programmable (cel) path cannot run here: %s\n%s: drawing with the fixed-function path\n",
                 cli::name(), whyNotProgrammable.c_str(), cli::name());
    path = render::RenderPath::kFixed;
  }
  if (comparing) return compareFrames(o, scene, plan);
  if (o.maxError) {
    if (path == render::RenderPath::kFixed) {
      cli::printError(
          "--max-error chooses the media layer's resolution and the nailboards' atlas level, and the "
          "programmable path that draws them cannot run here");
      return 1;
    }
    // parse() made sure the path is cel and there is something to choose.
    const bool cel = !scene.atlas.empty() && (!scene.particles.empty() || !scene.emitters.empty() ||
                                              (scene.simulation && !scene.simulation->emitters.empty()));
    if (cel) {
      // Fewer particles first (the frame time), then the smallest atlas for them (the memory), both
      // against the same references of the full model.
      std::vector<core::Image> references;
      if (!scene.emitters.empty()) {
        if (const int code = chooseCelModel(o, scene, plan, render::CelKnob::kParticleFraction, &references); code != 0)
          return code;
      }
      if (const int code = chooseCelModel(o, scene, plan, render::CelKnob::kAtlasLevel, &references); code != 0)
        return code;
    }
    if (scene.media) {
      if (const int code = chooseMediaResolution(o, scene, plan); code != 0) return code;
    }
  }
  if (path == render::RenderPath::kFixed && scene.media && !o.quiet) {
    std::fprintf(stderr, "%s: the fixed-function path draws no fire, smoke or dust: /media is left out\n", cli::name());
  }
  if (path == render::RenderPath::kReference && scene.media && !o.quiet) {
    std::fprintf(stderr, "%s: the cel reference draws no fire, smoke or dust: /media is left out\n", cli::name());
  }
  // The fixed path draws into the context's own framebuffer (made at the frame's size above):
  // OpenGL 1.x calls only, no framebuffer objects.
  auto renderer = render::SceneRenderer::create(scene, path, path == render::RenderPath::kFixed);
  if (!renderer) {
    cli::printError(renderer.error());
    return 1;
  }

  const core::PixelType type = plan.exr ? core::PixelType::kHalf : core::PixelType::kUInt8;
  const fs::path formatHint = plan.exr ? "frame.exr" : "frame.png";
  const int count = plan.last - plan.first + 1;
  for (int f = plan.first; f <= plan.last; ++f) {
    const fs::path target = plan.pattern.name(f);
    if (!o.quiet && count > 1) {
      std::fprintf(stderr, "%s: frame %d (%d/%d) -> %s\n", cli::name(), f, f - plan.first + 1, count, target.c_str());
      std::fflush(stderr);
    }
    auto image = (*renderer)->renderFrame(f);
    if (!image) {
      cli::printError(image.error());
      return 1;
    }
    // Each frame is written beside its target and renamed over it only when complete.
    core::OutputTransaction frame;
    const fs::path temp = frame.stage(target);
    if (auto r = core::writeImage(temp, *image, type, {}, formatHint); !r) {
      cli::printError(Error::at(target, r.error().message));
      return 1;
    }
    if (auto r = frame.commit(); !r) {
      cli::printError(r.error());
      return 1;
    }
  }
  if (!o.quiet) {
    if (count == 1) {
      std::printf("%s: wrote %s (%dx%d, frame %d)\n", cli::name(), plan.pattern.name(plan.first).c_str(), scene.width,
                  scene.height, plan.first);
    } else {
      std::printf("%s: wrote %d frames (%dx%d): %s .. %s\n", cli::name(), count, scene.width, scene.height,
                  plan.pattern.name(plan.first).c_str(), plan.pattern.name(plan.last).c_str());
    }
  }
  return 0;
}

}  // namespace

std::string OutputPattern::name(int frame) const {
  if (!numbered) return prefix;
  std::string number = std::to_string(frame);
  if (static_cast<int>(number.size()) < digits) number.insert(0, static_cast<std::size_t>(digits) - number.size(), '0');
  return prefix + number + suffix;
}

Result<OutputPattern> parseOutputPattern(const std::string& out) {
  OutputPattern p;
  std::size_t start = std::string::npos, end = 0;
  int found = 0;
  for (std::size_t i = 0; i < out.size();) {
    if (out[i] == '#') {
      std::size_t j = i;
      while (j < out.size() && out[j] == '#') ++j;
      ++found, start = i, end = j;
      p.digits = static_cast<int>(j - i);
      i = j;
    } else if (out[i] == '%') {
      // "%d" or "%0Nd" with N in 1..9.
      if (i + 1 < out.size() && out[i + 1] == 'd') {
        ++found, start = i, end = i + 2, p.digits = 0;
        i += 2;
      } else if (i + 3 < out.size() && out[i + 1] == '0' && out[i + 2] >= '1' && out[i + 2] <= '9' &&
                 out[i + 3] == 'd') {
        ++found, start = i, end = i + 4, p.digits = out[i + 2] - '0';
        i += 4;
      } else {
        ++i;
      }
    } else {
      ++i;
    }
  }
  if (found > 1) return Error{"-o " + out + ": more than one frame-number pattern (%d, %0Nd or ###)"};
  if (found == 0) {
    p.prefix = out;
    return p;
  }
  p.numbered = true;
  p.prefix = out.substr(0, start);
  p.suffix = out.substr(end);
  return p;
}

Result<std::pair<int, int>> parseFrameRange(const std::string& text) {
  auto number = [](const std::string& s) -> std::optional<int> {
    if (s.empty() || s.size() > 9 || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      return std::nullopt;
    }
    return std::stoi(s);
  };
  const Error bad{"--frames: expected a frame N or a range A-B (0-based, inclusive), got \"" + text + "\""};
  const auto dash = text.find('-');
  if (dash == std::string::npos) {
    auto n = number(text);
    if (!n) return bad;
    return std::pair{*n, *n};
  }
  auto a = number(text.substr(0, dash)), b = number(text.substr(dash + 1));
  if (!a || !b) return bad;
  if (*a > *b) return Error{"--frames " + text + ": the range ends before it starts"};
  return std::pair{*a, *b};
}

std::variant<Options, int> parse(int argc, char** argv) {
  Options o;
  std::vector<std::string> presets = render::stylePresetNames();
  std::string presetList;
  for (const std::string& p : presets) presetList += (presetList.empty() ? "" : ", ") + p;
  CLI::App app{
      "puffrender: renders a scene file (JSON: camera, light, style, particles, emitters, objects; see "
      "docs/scene-format.md) with cel-shaded nailboards, outlines and billboard shadow volumes (McGuire & Fein "
      "2006) into a PNG or EXR image, or a numbered image sequence.",
      cli::name()};
  app.set_version_flag("--version", "puffrender 0.1.0");
  app.add_option("scene", o.scene, "Scene file (JSON)")->required();
  app.add_option("-o,--out", o.out,
                 "Output image. For a sequence, a name with one %d, %0Nd or run of # (frame_####.png) that the frame "
                 "number fills in; without one, a single frame is written to exactly OUT. Required unless "
                 "--print-scene");
  app.add_option("--frames", o.frames,
                 "Frame N or range A-B (0-based, inclusive). Default: frame 0 for a single OUT, every frame of the "
                 "scene (/animation/frames) for a numbered OUT");
  app.add_option("--format", o.format,
                 "png (8-bit RGBA) or exr (half-float RGBA). Default: from OUT's extension (.png or .exr)")
      ->check(CLI::IsMember({"png", "exr"}));
  app.add_option("--gl", o.glBackend, "GL backend: osmesa, egl or glfw (default: $PUFF_GL, else osmesa)")
      ->check(CLI::IsMember({"osmesa", "egl", "glfw"}));
  app.add_option("--width", o.width, "Output width in pixels, replacing the scene's (1..16384)")
      ->check(CLI::Range(1, 16384));
  app.add_option("--height", o.height, "Output height in pixels, replacing the scene's (1..16384)")
      ->check(CLI::Range(1, 16384));
  app.add_option("--samples", o.samples, "MSAA samples per pixel, replacing the scene's: 1, 2, 4 or 8")
      ->check(CLI::IsMember({1, 2, 4, 8}));
  app.add_option("--art-dir", o.artDir,
                 "Directory that \"${PUFF_ART}\" in the scene's paths stands for (default: $PUFF_ART, else build/art)");
  app.add_option("--shader-dir", o.shaderDir, "Read shaders from this directory instead of the built-in copies");
  app.add_option("--style", o.style, "Render with this style preset instead of the scene's style: " + presetList)
      ->check(CLI::IsMember(presets));
  app.add_option(
         "--path", o.path,
         "Render path: cel (programmable GL 4.5: nailboards, flange outlines, shadow volumes; falls back to fixed, "
         "saying so, when the context cannot run it) or fixed (GL 1.x fixed function, McGuire & Fein 4.4: one "
         "light, uniform ambient, no shadows) or reference (the image the nailboards approximate: every "
         "particle's actual puff mesh, Eq. 2 per pixel, outlines around the true silhouettes, exact shadows; "
         "supersampled 3x3 and slow; no media). Default: cel")
      ->check(CLI::IsMember({"cel", "fixed", "reference"}));
  app.add_option("--compare", o.compare,
                 "Render every frame with both paths (fixed,cel or cel,fixed) and report how close they come: smoke "
                 "coverage agreement (IoU of the masks) and the share of shared smoke pixels within --tolerance; OUT "
                 "gets [first | second | difference] side by side")
      ->check(CLI::IsMember({"fixed,cel", "cel,fixed"}));
  auto* tolerance =
      app.add_option("--tolerance", o.toneTolerance, "--compare: per-channel tone tolerance in [0, 1]. Default: 0.1")
          ->check(CLI::Range(0.0f, 1.0f));
  std::string maxErrorText;
  auto* maxError = app.add_option("--max-error", maxErrorText,
                                  "Render with just enough model, measured against the references at the first, "
                                  "middle and last of the frames rendered (the worst of them), E an RMSE in (0, 1]. "
                                  "Scenes with cel particles: first the fewest of the placed emitters' particles "
                                  "(/particleFraction: 1/8, 1/4, 1/2 or all, each larger to fill the same volume), "
                                  "then the smallest atlas (/atlasLevel: the atlas from one of its mip levels on), "
                                  "whose frames stay within E of the cel reference of the full model (--path "
                                  "reference; 8-bit values; e.g. 0.12: the nailboards' own error is about 0.09 on "
                                  "the art scenes); if none does, all the particles and the full atlas, with a "
                                  "warning. Scenes with media: "
                                  "the cheapest media layer resolution (/media/resolution: 0.125, 0.25, 0.5 or 1) "
                                  "within E (linear colour, e.g. 0.01) of the exact media reference; if none does, 1. "
                                  "Prints the measurements and one line per choice saying what it chose and why on "
                                  "stderr; -q: those lines only. The media method and mesh detail (baked into the "
                                  "atlas: puffbake --lod auto) are not chosen. Measured frames leave out explosion "
                                  "lights, heat shimmer and motion blur (the reference has none); the output keeps "
                                  "them")
                       ->type_name("E");
  app.add_flag("--print-scene", o.printScene,
               "Print the scene as it will be rendered (every field, defaults and the options above applied) as JSON, "
               "and exit without rendering");
  app.add_flag("-q,--quiet", o.quiet, "Print errors only (and --max-error's one-line choice)");

  if (const auto exitCode = cli::parse(app, argc, argv)) return *exitCode;
  o.toleranceGiven = tolerance->count() > 0;
  if (maxError->count() > 0) {
    // Parsed here, not by CLI11, so that nan and inf get the same message as 0 or 2.
    char* end = nullptr;
    const double e = std::strtod(maxErrorText.c_str(), &end);
    if (maxErrorText.empty() || end != maxErrorText.c_str() + maxErrorText.size() || !std::isfinite(e) ||
        !(e > 0.0 && e <= 1.0)) {
      cli::printError("--max-error: expected an RMSE in (0, 1] (linear colour, e.g. 0.01), got \"" + maxErrorText +
                      "\"");
      return 2;
    }
    o.maxError = e;
  }
  if (o.out.empty() && !o.printScene) {
    cli::printError("-o OUT is required (or --print-scene); see --help");
    return 2;
  }
  if (!o.out.empty()) {
    if (auto p = parseOutputPattern(o.out); !p) {
      cli::printError(p.error());
      return 2;
    }
  }
  if (!o.frames.empty()) {
    if (auto r = parseFrameRange(o.frames); !r) {
      cli::printError(r.error());
      return 2;
    }
  }
  if (o.artDir.empty()) o.artDir = defaultArtDir();
  return o;
}

int run(const Options& o) {
  auto loaded = render::loadScene(o.scene, o.artDir);
  if (!loaded) {
    cli::printError(loaded.error());
    return 1;
  }
  render::Scene scene = std::move(*loaded);
  if (o.width) scene.width = *o.width;
  if (o.height) scene.height = *o.height;
  if (o.samples) scene.samples = *o.samples;
  if (!o.style.empty()) {
    auto style = render::stylePreset(o.style);
    if (!style) {
      cli::printError(style.error());
      return 2;
    }
    scene.style = *style;
    scene.stylePreset = o.style;
  }
  if (o.printScene) {
    std::cout << render::jsonText(render::toJson(scene)) << "\n";
    return 0;
  }
  auto plan = makePlan(o, scene);
  if (!plan) {
    cli::printError(plan.error());
    return 2;
  }
  if (!o.compare.empty() && plan->exr) {
    cli::printError("--compare writes 8-bit PNG comparison images: give -o a .png name");
    return 2;
  }
  if (o.compare.empty() && o.toleranceGiven) {
    cli::printError("--tolerance applies only with --compare");
    return 2;
  }
  if (!o.compare.empty() && o.path != "cel") {
    cli::printError("--path and --compare do not go together: --compare draws with both paths");
    return 2;
  }
  if (o.maxError) {
    const bool cel = !scene.atlas.empty() && (!scene.particles.empty() || !scene.emitters.empty() ||
                                              (scene.simulation && !scene.simulation->emitters.empty()));
    if (!scene.media && !cel) {
      cli::printError("--max-error chooses the nailboards' atlas level and the media layer's resolution, and " +
                      o.scene.string() + " has neither cel particles nor media (/media)");
      return 2;
    }
    if (!o.compare.empty()) {
      cli::printError("--max-error and --compare do not go together: --compare draws within the fixed path's limits");
      return 2;
    }
    if (o.path != "cel") {
      cli::printError("--max-error chooses what the programmable (cel) path draws with: leave out --path " + o.path);
      return 2;
    }
  }
  return renderFrames(o, scene, *plan);
}

}  // namespace puff::app
