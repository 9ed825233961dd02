// puffrender's frames: the GL context (falling back to the fixed-function path), then each frame
// rendered and written whole or not at all.
#include <cstdio>
#include <memory>
#include <set>
#include <string>

#include <cli/app.h>
#include <cli/progress.h>
#include <puff/core/colour.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/core/shader.h>
#include <puff/eval/cel_reference.h>
#include <puff/platform/gl_context.h>
#include <puff/render/render.h>
#include <puff/scene/evaluate.h>
#include <puff/support/text.h>

#include "commands.h"

namespace puff::app {

namespace fs = std::filesystem;

namespace {

// Fails before any rendering if an output can never be written: every directory the frames go to
// is created now (and taken back by `directories`, if still empty, when the run fails) and must be
// writable.
Result<void> prepareDirectories(const Plan& plan, core::OutputTransaction& directories) {
  std::set<fs::path> dirs;
  for (int f = plan.first; f <= plan.last && plan.writeFrames; ++f) {
    dirs.insert(fs::path(plan.pattern.name(f)).parent_path());
    if (!plan.pattern.numbered) break;
  }
  for (const fs::path& dir : dirs) {
    if (auto r = directories.prepareDirectory(dir); !r) return r;
  }
  return {};
}

// The context `path` draws in. When the programmable (cel) path cannot run (a context older than
// GL 4.5) and --path was not given, the automatic fallback: says so on stderr in one line and sets
// `path` to fixed. A shader that does not build is not a reason to fall back: making the cel path
// fails with its error.
Result<std::unique_ptr<core::GlContext>> createContext(const Options& o, const scene::Scene& scene,
                                                       render::RenderPath& path) {
  const bool comparing = !o.compare.empty();
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
    return context.error();
  } else if (path == render::RenderPath::kCel && !comparing) {
    if (auto ok = render::SceneRenderer::checkProgrammable(); !ok) whyNotProgrammable = ok.error().message;
  }
  if (whyNotProgrammable.empty()) return context;
  if (o.pathGiven) return Error{"--path cel cannot run here: " + core::oneLine(whyNotProgrammable)};
  context = Error{""};  // the old context goes before the new one is made current
  glOptions.profile = core::GlProfile::kCompatibility;
  glOptions.major = 1, glOptions.minor = 3;
  glOptions.width = scene.width, glOptions.height = scene.height;
  context = core::createGlContext(glOptions);
  if (!context) {
    // The same reason twice (no such backend, no display) is said once.
    if (context.error().message == whyNotProgrammable) return context.error();
    return Error{"the programmable (cel) path cannot run here (" + core::oneLine(whyNotProgrammable) +
                 "), and there is no context for the fixed-function path either: " + context.error().message};
  }
  std::fprintf(stderr, "%s: the programmable (cel) path cannot run here: %s; drawing with the fixed-function path\n",
               cli::name(), core::oneLine(whyNotProgrammable).c_str());
  path = render::RenderPath::kFixed;
  return context;
}

// Renders the plan's frames, each written beside its target and renamed over it only when complete.
int writeFrames(const Options& o, const scene::Scene& scene, const Plan& plan, render::SceneRenderer& renderer) {
  // PNG: display values through the scene's view transform; EXR: the scene-linear frame as it is.
  const core::PixelType type =
      plan.exr ? (o.float32 ? core::PixelType::kFloat : core::PixelType::kHalf) : core::PixelType::kUInt8;
  const core::ViewTransform view = scene::viewTransformFor(scene);
  const fs::path formatHint = plan.exr ? "frame.exr" : "frame.png";
  // Each file's own convention unless the scene says (checkAgainstScene refused straight EXR).
  const core::AlphaMode alpha =
      scene.alpha.value_or(plan.exr ? core::AlphaMode::kPremultiplied : core::AlphaMode::kStraight);
  const int count = plan.last - plan.first + 1;
  SequenceExtras extras(o, scene, plan);
  if (auto r = extras.open(); !r) {
    cli::printError(r.error());
    return 1;
  }
  cli::Progress progress(o.quiet || count == 1);
  for (int f = plan.first; f <= plan.last; ++f) {
    const fs::path target = plan.pattern.name(f);
    progress("frames", f - plan.first, count);
    auto image = renderer.renderFrame(f);
    if (!image) {
      progress.finish();
      cli::printError(image.error());
      return 1;
    }
    if (auto r = extras.add(f, *image); !r) {
      progress.finish();
      cli::printError(r.error());
      return 1;
    }
    if (!plan.writeFrames) continue;
    core::OutputTransaction frame;
    const fs::path temp = frame.stage(target);
    // A transparent frame comes premultiplied (EXR's convention); a PNG gets display values, its
    // alpha straight unless the scene asks for premultiplied.
    const core::Image out = plan.exr            ? std::move(*image)
                            : scene.transparent ? core::viewTransform(*image, view, alpha)
                                                : core::viewTransform(*image, view);
    core::ImageAttributes attributes = plan.exr
                                           ? core::ImageAttributes{{"puff:colorspace", "scene-linear Rec.709"}}
                                           : core::ImageAttributes{{"puff:view", std::string(core::toString(view))}};
    if (scene.transparent) attributes.emplace_back("puff:alpha", std::string(core::toString(alpha)));
    if (auto r = core::writeImage(temp, out, type, attributes, formatHint); !r) {
      progress.finish();
      cli::printError(Error::at(target, r.error().message));
      return 1;
    }
    if (auto r = frame.commit(); !r) {
      progress.finish();
      cli::printError(r.error());
      return 1;
    }
  }
  progress("frames", count, count);
  progress.finish();
  auto said = extras.finish();
  if (!said) {
    cli::printError(said.error());
    return 1;
  }
  if (!o.quiet && plan.writeFrames) {
    if (count == 1) {
      std::printf("%s: wrote %s (%dx%d, frame %d)\n", cli::name(), plan.pattern.name(plan.first).c_str(), scene.width,
                  scene.height, plan.first);
    } else {
      std::printf("%s: wrote %d frames (%dx%d): %s .. %s\n", cli::name(), count, scene.width, scene.height,
                  plan.pattern.name(plan.first).c_str(), plan.pattern.name(plan.last).c_str());
    }
  }
  if (!o.quiet) std::fputs(said->c_str(), stdout);
  return 0;
}

}  // namespace

int renderFrames(const Options& o, scene::Scene scene, const Plan& plan) {
  core::OutputTransaction directories;
  if (auto r = prepareDirectories(plan, directories); !r) {
    cli::printError(r.error());
    return 1;
  }
  if (!o.shaderDir.empty()) core::setShaderDir(o.shaderDir);
  render::RenderPath path = *render::parseRenderPath(o.path);
  auto context = createContext(o, scene, path);
  if (!context) {
    cli::printError(context.error());
    return 1;
  }
  if (!o.compare.empty()) return compareFrames(o, scene, plan);
  if (o.maxError) {
    if (path == render::RenderPath::kFixed) {
      cli::printError(
          "--max-error chooses the media layer's resolution and the nailboards' particles, atlas level "
          "and shadows, and the programmable path that draws them cannot run here");
      return 1;
    }
    if (const int code = chooseModel(o, scene, plan); code != 0) return code;
  }
  if (!o.quiet) {
    for (const std::string& line : render::renderPathInfo(path).omissions(scene)) {
      std::fprintf(stderr, "%s: %s\n", cli::name(), line.c_str());
    }
  }
  // The fixed path draws into the context's own framebuffer (made at the frame's size above):
  // OpenGL 1.x calls only, no framebuffer objects.
  auto renderer = eval::createRenderer(
      scene, path,
      path == render::RenderPath::kFixed ? render::DrawTarget::kContextFramebuffer : render::DrawTarget::kOffscreen);
  if (!renderer) {
    cli::printError(renderer.error());
    return 1;
  }
  if (plan.flipColumns > 0) return writeFlipbook(o, scene, plan, **renderer);
  return writeFrames(o, scene, plan, **renderer);
}

}  // namespace puff::app
