// puffrender --flipbook: a frame range as one sprite sheet a game engine animates (Unity's Texture
// Sheet Animation, Godot's particle animation), and the JSON that says how to read it.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>

#include <cli/app.h>
#include <cli/progress.h>
#include <puff/core/colour.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/scene/evaluate.h>

#include "commands.h"

namespace puff::app {

namespace fs = std::filesystem;

int writeFlipbook(const Options& o, const scene::Scene& scene, const Plan& plan, render::SceneRenderer& renderer) {
  const int count = plan.last - plan.first + 1;
  const int w = scene.width, h = scene.height, columns = plan.flipColumns, rows = plan.flipRows;
  const core::ViewTransform view = scene::viewTransformFor(scene);
  // PNG: display values through the view transform, alpha straight unless asked; EXR: scene-linear,
  // premultiplied (checkAgainstScene refused straight EXR).
  const core::AlphaMode alpha =
      scene.alpha.value_or(plan.exr ? core::AlphaMode::kPremultiplied : core::AlphaMode::kStraight);
  core::Image sheet(w * columns, h * rows, 4, 0.0f);  // cells past the last frame stay empty (alpha 0)
  cli::Progress progress(o.quiet || count == 1);
  for (int i = 0; i < count; ++i) {
    progress("frames", i, count);
    auto image = renderer.renderFrame(plan.first + i);
    if (!image) {
      progress.finish();
      cli::printError(image.error());
      return 1;
    }
    // The renderer draws a transparent frame premultiplied, in scene-linear light.
    const core::Image cell = plan.exr ? std::move(*image) : core::viewTransform(*image, view, alpha);
    const int x0 = (i % columns) * w, y0 = (i / columns) * h;
    for (int y = 0; y < h; ++y) {
      std::copy_n(&cell.pixels[cell.index(0, y)], static_cast<std::size_t>(w) * 4,
                  &sheet.pixels[sheet.index(x0, y0 + y)]);
    }
  }
  progress("frames", count, count);
  progress.finish();

  const fs::path target = plan.pattern.name(plan.first);
  fs::path layout = target;
  layout.replace_extension(".json");
  nlohmann::ordered_json j;
  j["format"] = "puff-flipbook";
  j["version"] = 1;
  j["image"] = target.filename().string();
  j["columns"] = columns;
  j["rows"] = rows;
  j["frameCount"] = count;
  j["frameWidth"] = w;
  j["frameHeight"] = h;
  j["order"] = "left to right, then top to bottom; frame i at column i % columns, row i / columns (row 0 at the top)";
  j["fps"] = scene.animation.fps;
  j["firstFrame"] = plan.first;
  j["lastFrame"] = plan.last;
  j["alpha"] = std::string(core::toString(alpha));
  j["colour"] = plan.exr ? "scene-linear Rec.709 (half float)"
                         : "display sRGB, 8 bits, through the " + std::string(core::toString(view)) + " view transform";
  j["scene"] = scene.file.filename().string();

  core::OutputTransaction tx;
  const fs::path stagedSheet = tx.stage(target);
  core::ImageAttributes attributes{{"puff:alpha", std::string(core::toString(alpha))},
                                   {"puff:flipbook", std::to_string(columns) + "x" + std::to_string(rows)}};
  if (plan.exr) {
    attributes.emplace_back("puff:colorspace", "scene-linear Rec.709");
  } else {
    attributes.emplace_back("puff:view", std::string(core::toString(view)));
  }
  const core::PixelType type =
      plan.exr ? (o.float32 ? core::PixelType::kFloat : core::PixelType::kHalf) : core::PixelType::kUInt8;
  if (auto r = core::writeImage(stagedSheet, sheet, type, attributes, plan.exr ? "sheet.exr" : "sheet.png"); !r) {
    cli::printError(Error::at(target, r.error().message));
    return 1;
  }
  if (auto r = core::writeFileBytes(tx.stage(layout), j.dump(2) + "\n", layout); !r) {
    cli::printError(r.error());
    return 1;
  }
  if (auto r = tx.commit(); !r) {
    cli::printError(r.error());
    return 1;
  }
  if (!o.quiet) {
    std::printf("%s: wrote %s (%dx%d: %d frames, %d to %d, in %dx%d cells of %dx%d, %s alpha) and %s\n", cli::name(),
                target.c_str(), sheet.width, sheet.height, count, plan.first, plan.last, columns, rows, w, h,
                std::string(core::toString(alpha)).c_str(), layout.c_str());
  }
  return 0;
}

}  // namespace puff::app
