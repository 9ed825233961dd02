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

namespace {

// How the sheet's cells are drawn and laid out: the cell size, the grid and the colour encoding.
struct SheetSpec {
  int w, h, columns, rows;
  core::ViewTransform view;
  core::AlphaMode alpha;
  bool exr;
};

// Copies one frame (scene-linear, premultiplied, as the renderer draws it) into the sheet's cell `slot`.
void placeCell(core::Image& sheet, int slot, const core::Image& linear, const SheetSpec& s) {
  core::Image cell = s.exr ? linear : core::viewTransform(linear, s.view, s.alpha);
  if (!s.exr && s.alpha == core::AlphaMode::kStraight) bleedColour(cell);
  const int x0 = (slot % s.columns) * s.w, y0 = (slot / s.columns) * s.h;
  for (int y = 0; y < s.h; ++y) {
    std::copy_n(&cell.pixels[cell.index(0, y)], static_cast<std::size_t>(s.w) * 4,
                &sheet.pixels[sheet.index(x0, y0 + y)]);
  }
}

// Mixes a late frame with head frame `from` (cell j of a --loop N), giving `from` weight (j + 1) / (N + 1).
core::Image crossFade(core::Image mixed, const core::Image& from, int j, int loop) {
  const float weight = static_cast<float>(j + 1) / static_cast<float>(loop + 1);
  for (std::size_t k = 0; k < mixed.pixels.size(); ++k) {
    mixed.pixels[k] = (1.0f - weight) * mixed.pixels[k] + weight * from.pixels[k];
  }
  return mixed;
}

// Renders the plan's frames into the sheet's cells, with progress; false (the error printed) if one fails.
bool renderCells(const Options& o, const Plan& plan, render::SceneRenderer& renderer, const SheetSpec& spec,
                 core::Image& sheet) {
  const int count = plan.last - plan.first + 1;
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
      return false;
    }
    if (i < loop) {
      head.push_back(std::move(*image));
    } else if (i < cellsUsed) {
      placeCell(sheet, i, *image, spec);
    } else {
      const int j = i - cellsUsed;
      placeCell(sheet, j, crossFade(std::move(*image), head[static_cast<std::size_t>(j)], j, loop), spec);
    }
  }
  progress("frames", count, count);
  progress.finish();
  return true;
}

// The layout JSON written beside the sheet: how an engine reads the cells, and what they hold.
nlohmann::ordered_json flipbookLayout(const Options& o, const scene::Scene& scene, const Plan& plan, const SheetSpec& s,
                                      const fs::path& target, int cellsUsed) {
  nlohmann::ordered_json j;
  j["format"] = "puff-flipbook";
  j["version"] = 1;
  j["image"] = target.filename().string();
  j["columns"] = s.columns;
  j["rows"] = s.rows;
  j["frameCount"] = cellsUsed;
  j["frameWidth"] = s.w;
  j["frameHeight"] = s.h;
  j["order"] = "left to right, then top to bottom; frame i at column i % columns, row i / columns (row 0 at the top)";
  j["fps"] = scene.animation.fps;
  j["firstFrame"] = plan.first;
  j["lastFrame"] = plan.last - o.loop;
  j["loop"] = o.loop;  // frames cross-faded: the sheet's cell j < loop also holds frame lastFrame + 1 + j
  j["alpha"] = std::string(core::toString(s.alpha));
  j["colour"] = s.exr ? (o.float32 ? "scene-linear Rec.709 (32-bit float)" : "scene-linear Rec.709 (half float)")
                      : "display sRGB, 8 bits, through the " + std::string(core::toString(s.view)) + " view transform";
  j["scene"] = scene.file.filename().string();
  return j;
}

// Writes the sheet and its layout as one transaction; false (the error printed) if any step fails.
bool writeSheetAndLayout(const Options& o, const SheetSpec& s, const core::Image& sheet, const fs::path& target,
                         const fs::path& layout, const nlohmann::ordered_json& j) {
  core::OutputTransaction tx;
  const fs::path stagedSheet = tx.stage(target);
  core::ImageAttributes attributes{{"puff:alpha", std::string(core::toString(s.alpha))},
                                   {"puff:flipbook", std::to_string(s.columns) + "x" + std::to_string(s.rows)}};
  if (s.exr) {
    attributes.emplace_back("puff:colorspace", "scene-linear Rec.709");
  } else {
    attributes.emplace_back("puff:view", std::string(core::toString(s.view)));
  }
  const core::PixelType type =
      s.exr ? (o.float32 ? core::PixelType::kFloat : core::PixelType::kHalf) : core::PixelType::kUInt8;
  if (auto r = core::writeImage(stagedSheet, sheet, type, attributes, s.exr ? "sheet.exr" : "sheet.png"); !r) {
    cli::printError(Error::at(target, r.error().message));
    return false;
  }
  if (auto r = core::writeFileBytes(tx.stage(layout), j.dump(2) + "\n", layout); !r) {
    cli::printError(r.error());
    return false;
  }
  if (auto r = tx.commit(); !r) {
    cli::printError(r.error());
    return false;
  }
  return true;
}

// Prints what was written (unless -q): the sheet, the loop's cross-fade and any empty cells.
void printFlipbookSummary(const Options& o, const Plan& plan, const SheetSpec& s, const core::Image& sheet,
                          const fs::path& target, const fs::path& layout, int cellsUsed) {
  if (o.quiet) return;
  const int loop = o.loop, columns = s.columns, rows = s.rows;
  std::printf("%s: wrote %s (%dx%d: %d frame%s, %d to %d, in %dx%d cells of %dx%d, %s alpha) and %s\n", cli::name(),
              target.c_str(), sheet.width, sheet.height, cellsUsed, cellsUsed == 1 ? "" : "s", plan.first,
              plan.last - loop, columns, rows, s.w, s.h, std::string(core::toString(s.alpha)).c_str(), layout.c_str());
  if (loop > 0) {
    std::printf("%s: looped: frames %d to %d cross-faded into the first %d cells\n", cli::name(), plan.last - loop + 1,
                plan.last, loop);
  }
  if (cellsUsed < columns * rows) {
    std::printf(
        "%s: note: the last %d cell%s of the sheet are empty (frameCount in the layout says how many hold "
        "frames)\n",
        cli::name(), columns * rows - cellsUsed, columns * rows - cellsUsed == 1 ? "" : "s");
  }
}

}  // namespace

int writeFlipbook(const Options& o, const scene::Scene& scene, const Plan& plan, render::SceneRenderer& renderer) {
  const int count = plan.last - plan.first + 1;
  const core::ViewTransform view = scene::viewTransformFor(scene);
  // PNG: display values through the view transform, alpha straight unless asked; EXR: scene-linear,
  // premultiplied (checkAgainstScene refused straight EXR).
  const core::AlphaMode alpha =
      scene.alpha.value_or(plan.exr ? core::AlphaMode::kPremultiplied : core::AlphaMode::kStraight);
  const SheetSpec spec{scene.width, scene.height, plan.flipColumns, plan.flipRows, view, alpha, plan.exr};
  // Cells past the last frame stay empty (alpha 0).
  core::Image sheet(spec.w * spec.columns, spec.h * spec.rows, 4, 0.0f);
  if (!renderCells(o, plan, renderer, spec, sheet)) return 1;
  const int cellsUsed = count - o.loop;

  const fs::path target = plan.pattern.name(plan.first);
  fs::path layout = target;
  layout.replace_extension(".json");
  const nlohmann::ordered_json j = flipbookLayout(o, scene, plan, spec, target, cellsUsed);
  if (!writeSheetAndLayout(o, spec, sheet, target, layout, j)) return 1;
  printFlipbookSummary(o, plan, spec, sheet, target, layout, cellsUsed);
  return 0;
}

}  // namespace puff::app
