// puffrender --flipbook: a frame range as one sprite sheet a game engine animates (Unity's Texture
// Sheet Animation, Godot's particle animation), and the JSON that says how to read it.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <vector>

#include <cli/app.h>
#include <cli/progress.h>
#include <puff/core/colour.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/scene/evaluate.h>

#include "commands.h"

namespace puff::app {

namespace fs = std::filesystem;

namespace {

// A straight-alpha cell: every uncovered texel (alpha 0) takes the colour of the nearest covered one
// (breadth first over the 4 neighbours). Alpha is untouched, so nothing drawn changes, but an engine
// filtering or mipmapping the sheet mixes covered colours with their own instead of with black:
// no dark fringe around the smoke.
void bleedColour(core::Image& cell) {
  const int w = cell.width, h = cell.height;
  std::vector<int> queue;
  std::vector<char> filled(static_cast<std::size_t>(w) * h, 0);
  for (int i = 0; i < w * h; ++i) {
    if (cell.pixels[static_cast<std::size_t>(i) * 4 + 3] > 0.0f)
      filled[static_cast<std::size_t>(i)] = 1, queue.push_back(i);
  }
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const int i = queue[q], x = i % w, y = i / w;
    const int next[4] = {x > 0 ? i - 1 : -1, x + 1 < w ? i + 1 : -1, y > 0 ? i - w : -1, y + 1 < h ? i + w : -1};
    for (int n : next) {
      if (n < 0 || filled[static_cast<std::size_t>(n)]) continue;
      filled[static_cast<std::size_t>(n)] = 1;
      for (int c = 0; c < 3; ++c) {
        cell.pixels[static_cast<std::size_t>(n) * 4 + static_cast<std::size_t>(c)] =
            cell.pixels[static_cast<std::size_t>(i) * 4 + static_cast<std::size_t>(c)];
      }
      queue.push_back(n);
    }
  }
}

}  // namespace

Result<void> checkFlipbookLayoutTarget(const Options& o, const Plan& plan) {
  const fs::path target = plan.pattern.name(plan.first);
  fs::path layout = target;
  layout.replace_extension(".json");
  std::error_code ec;
  if (fs::equivalent(layout, o.scene, ec) || layout.lexically_normal() == o.scene.lexically_normal()) {
    return Error{"-o " + target.string() + ": the flipbook's layout would be written to " + layout.string() +
                 ", the scene itself: give the sheet another name"};
  }
  if (!fs::exists(layout, ec)) return {};
  // Only a flipbook layout of this same sheet is replaced: never an atlas sidecar, a scene, or the
  // layout of another sheet (sheet.png and sheet.exr would share sheet.json).
  auto text = core::readFileBytes(layout);
  nlohmann::json j = text ? nlohmann::json::parse(*text, nullptr, false) : nlohmann::json();
  if (!j.is_object() || j.value("format", "") != "puff-flipbook") {
    return Error{"-o " + target.string() + ": the flipbook's layout goes to " + layout.string() +
                 ", which exists and is not a flipbook layout; it is left alone: give the sheet another name"};
  }
  if (j.value("image", "") != target.filename().string()) {
    return Error{"-o " + target.string() + ": " + layout.string() + " is the layout of another sheet (" +
                 j.value("image", "") + "); it is left alone: give the sheet another name"};
  }
  return {};
}

int writeFlipbook(const Options& o, const scene::Scene& scene, const Plan& plan, render::SceneRenderer& renderer) {
  const int count = plan.last - plan.first + 1;
  const int w = scene.width, h = scene.height, columns = plan.flipColumns, rows = plan.flipRows;
  const core::ViewTransform view = scene::viewTransformFor(scene);
  // PNG: display values through the view transform, alpha straight unless asked; EXR: scene-linear,
  // premultiplied (checkAgainstScene refused straight EXR).
  const core::AlphaMode alpha =
      scene.alpha.value_or(plan.exr ? core::AlphaMode::kPremultiplied : core::AlphaMode::kStraight);
  core::Image sheet(w * columns, h * rows, 4, 0.0f);  // cells past the last frame stay empty (alpha 0)
  const auto place = [&](int slot, const core::Image& linear) {
    // The renderer draws a transparent frame premultiplied, in scene-linear light.
    core::Image cell = plan.exr ? linear : core::viewTransform(linear, view, alpha);
    if (!plan.exr && alpha == core::AlphaMode::kStraight) bleedColour(cell);
    const int x0 = (slot % columns) * w, y0 = (slot / columns) * h;
    for (int y = 0; y < h; ++y) {
      std::copy_n(&cell.pixels[cell.index(0, y)], static_cast<std::size_t>(w) * 4,
                  &sheet.pixels[sheet.index(x0, y0 + y)]);
    }
  };
  // --loop N: the first N frames wait for the last N; cell j < N is the mix of frame j (weight
  // (j + 1) / (N + 1)) and frame count - N + j, premultiplied in scene-linear light, so the sheet's
  // last cell (frame count - N - 1) runs on into its first.
  const int loop = o.loop, cellsUsed = count - loop;
  std::vector<core::Image> head;
  cli::Progress progress(o.quiet || count == 1);
  for (int i = 0; i < count; ++i) {
    progress("frames", i, count);
    auto image = renderer.renderFrame(plan.first + i);
    if (!image) {
      progress.finish();
      cli::printError(image.error());
      return 1;
    }
    if (i < loop) {
      head.push_back(std::move(*image));
    } else if (i < cellsUsed) {
      place(i, *image);
    } else {
      const int j = i - cellsUsed;
      const float weight = static_cast<float>(j + 1) / static_cast<float>(loop + 1);
      core::Image mixed = std::move(*image);
      const core::Image& from = head[static_cast<std::size_t>(j)];
      for (std::size_t k = 0; k < mixed.pixels.size(); ++k) {
        mixed.pixels[k] = (1.0f - weight) * mixed.pixels[k] + weight * from.pixels[k];
      }
      place(j, mixed);
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
  j["frameCount"] = cellsUsed;
  j["frameWidth"] = w;
  j["frameHeight"] = h;
  j["order"] = "left to right, then top to bottom; frame i at column i % columns, row i / columns (row 0 at the top)";
  j["fps"] = scene.animation.fps;
  j["firstFrame"] = plan.first;
  j["lastFrame"] = plan.last - loop;
  j["loop"] = loop;  // frames cross-faded: the sheet's cell j < loop also holds frame lastFrame + 1 + j
  j["alpha"] = std::string(core::toString(alpha));
  j["colour"] = plan.exr ? (o.float32 ? "scene-linear Rec.709 (32-bit float)" : "scene-linear Rec.709 (half float)")
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
    std::printf("%s: wrote %s (%dx%d: %d frame%s, %d to %d, in %dx%d cells of %dx%d, %s alpha) and %s\n", cli::name(),
                target.c_str(), sheet.width, sheet.height, cellsUsed, cellsUsed == 1 ? "" : "s", plan.first,
                plan.last - loop, columns, rows, w, h, std::string(core::toString(alpha)).c_str(), layout.c_str());
    if (loop > 0) {
      std::printf("%s: looped: frames %d to %d cross-faded into the first %d cells\n", cli::name(),
                  plan.last - loop + 1, plan.last, loop);
    }
    if (cellsUsed < columns * rows) {
      std::printf(
          "%s: note: the last %d cell%s of the sheet are empty (frameCount in the layout says how many hold "
          "frames)\n",
          cli::name(), columns * rows - cellsUsed, columns * rows - cellsUsed == 1 ? "" : "s");
    }
  }
  return 0;
}

}  // namespace puff::app
