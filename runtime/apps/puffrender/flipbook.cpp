// puffrender --flipbook: a frame range as one sprite sheet a game engine animates (Unity's Texture
// Sheet Animation, Godot's particle animation), and the JSON that says how to read it.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

#include <cli/app.h>
#include <cli/progress.h>
#include <puff/core/colour.h>
#include <puff/core/files.h>
#include <puff/core/image.h>
#include <puff/core/number_text.h>
#include <puff/render/flipbook.h>
#include <puff/scene/evaluate.h>

#include "commands.h"

namespace puff::app {

namespace fs = std::filesystem;

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

Result<void> checkSheetSize(const render::SheetLayout& layout, const std::string& what) {
  const long long w = static_cast<long long>(layout.columns) * layout.cellWidth;
  const long long h = static_cast<long long>(layout.rows) * layout.cellHeight;
  if (const std::string problem = core::imageLimitProblem(w, h, 4, core::ImageLimits{"a flipbook"}); !problem.empty()) {
    return Error{what + ": " + problem + "; give a smaller grid, --width or --height"};
  }
  return {};
}

namespace {

// How the cells are encoded: the colour's view transform and alpha, and whether the sheet is EXR.
struct SheetSpec {
  core::ViewTransform view;
  core::AlphaMode alpha;
  bool exr;
  // The alpha above which a texel is drawn: what the sheet's encoding keeps (8 bits round below half
  // a step to 0; half floats keep any positive alpha).
  float covered() const { return exr ? 0.0f : 0.5f / 255.0f; }
};

// Which frames went into the cells.
struct Sequence {
  int cells = 0;    // cells that hold a frame
  int first = 0;    // the frame in the first cell (--loop: also mixed with the frames after the last)
  int skipped = 0;  // leading frames that drew nothing, left out by --skip-empty
};

// Takes cell `cell`'s frame (scene-linear, premultiplied, the loop's cross-fade done).
using PlaceCell = std::function<void(int cell, core::Image linear)>;

// Mixes a late frame with head frame `from` (cell j of a --loop N), giving `from` weight (j + 1) / (N + 1).
core::Image crossFade(core::Image mixed, const core::Image& from, int j, int loop) {
  const float weight = static_cast<float>(j + 1) / static_cast<float>(loop + 1);
  for (std::size_t k = 0; k < mixed.pixels.size(); ++k) {
    mixed.pixels[k] = (1.0f - weight) * mixed.pixels[k] + weight * from.pixels[k];
  }
  return mixed;
}

// Hands the k-th of n kept frames to its cell. --loop N: the first N frames wait in `head` for the
// last N; cell j < N is the mix of frame j (weight (j + 1) / (N + 1)) and frame n - N + j,
// premultiplied in scene-linear light, so the sheet's last cell runs on into its first.
void dispatch(int k, int n, int loop, core::Image frame, std::vector<core::Image>& head, const PlaceCell& place) {
  const int cellsUsed = n - loop;
  if (k < loop) {
    head.push_back(std::move(frame));
  } else if (k < cellsUsed) {
    place(k, std::move(frame));
  } else {
    const int j = k - cellsUsed;
    place(j, crossFade(std::move(frame), head[static_cast<std::size_t>(j)], j, loop));
  }
}

// Renders the plan's frames, with progress: as many as the plan counts, from plan.first, leading empty
// ones left out with --skip-empty (then up to plan.flipLast), each handed to its cell. `stream`: as it
// is drawn (the count is known: the plan's); else once all are drawn (--skip-empty with --loop, whose
// tail depends on how many drew something), holding them until then.
Result<Sequence> renderSequence(const Options& o, const Plan& plan, render::SceneRenderer& renderer,
                                const SheetSpec& spec, bool stream, const PlaceCell& place) {
  const int wanted = plan.last - plan.first + 1, loop = o.loop;
  Sequence seq;
  std::vector<core::Image> held, head;
  int kept = 0;
  cli::Progress progress(o.quiet || wanted == 1);
  for (int frame = plan.first; frame <= plan.flipLast && kept < wanted; ++frame) {
    progress("frames", kept, wanted);
    auto image = renderer.renderFrame(frame);
    if (!image) {
      progress.finish();
      return image.error();
    }
    if (o.skipEmpty && kept == 0 && !render::covers(*image, spec.covered())) {
      ++seq.skipped;
      continue;
    }
    if (stream) {
      dispatch(kept, wanted, loop, std::move(*image), head, place);
    } else {
      held.push_back(std::move(*image));
    }
    ++kept;
  }
  progress("frames", wanted, wanted);
  progress.finish();
  if (kept == 0) {
    return Error{"--skip-empty: frames " + std::to_string(plan.first) + " to " + std::to_string(plan.flipLast) +
                 " draw nothing: no frame to put in the sheet"};
  }
  if (2 * loop > kept) {
    return Error{"--loop " + std::to_string(loop) + ": " + std::to_string(kept) + " frames draw something after the " +
                 std::to_string(seq.skipped) + " empty ones --skip-empty left out, and a loop of " +
                 std::to_string(loop) + " needs " + std::to_string(2 * loop)};
  }
  for (int k = 0; k < static_cast<int>(held.size()); ++k) {
    dispatch(k, kept, loop, std::move(held[static_cast<std::size_t>(k)]), head, place);
  }
  seq.first = plan.first + seq.skipped;
  seq.cells = kept - loop;
  return seq;
}

// `v` to the 7 significant digits the scene's single-precision camera holds.
double sevenDigits(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.7g", v);
  return std::strtod(text, nullptr);
}

// Scene units one texel spans at the camera's target (orthographic: at every depth).
double sceneUnitsPerTexel(const cel::Camera& camera, int height) {
  const double distance = glm::length(glm::dvec3(camera.target) - glm::dvec3(camera.position));
  return camera.fovYDegrees <= 0.0f
             ? static_cast<double>(camera.orthoHeight) / height
             : 2.0 * distance * std::tan(glm::radians(static_cast<double>(camera.fovYDegrees)) * 0.5) / height;
}

// The layout JSON written beside the sheet: how an engine reads the cells, and what they hold.
nlohmann::ordered_json flipbookLayout(const Options& o, const scene::Scene& scene, const Sequence& seq,
                                      const render::SheetLayout& l, const SheetSpec& s, const fs::path& target) {
  const int cellsUsed = seq.cells;
  const cel::Camera camera = scene::cameraAt(scene, seq.first);
  const double unit = sceneUnitsPerTexel(camera, scene.height);
  nlohmann::ordered_json j;
  j["format"] = "puff-flipbook";
  j["version"] = 2;
  j["image"] = target.filename().string();
  j["columns"] = l.columns;
  j["rows"] = l.rows;
  j["frameCount"] = cellsUsed;
  j["cellWidth"] = l.cellWidth;
  j["cellHeight"] = l.cellHeight;
  j["frameWidth"] = l.crop.width;
  j["frameHeight"] = l.crop.height;
  j["frameOffset"] = {l.offsetX, l.offsetY};
  j["padding"] = l.padding;
  j["powerOfTwo"] = l.pow2;
  j["crop"] = {{"cropped", o.crop},           {"x", l.crop.x},           {"y", l.crop.y},
               {"width", l.crop.width},       {"height", l.crop.height}, {"renderWidth", scene.width},
               {"renderHeight", scene.height}};
  j["sceneUnitsPerTexel"] = sevenDigits(unit);
  j["sceneUnitsMeasured"] = camera.fovYDegrees <= 0.0f
                                ? std::string("orthographic camera: the same at every depth")
                                : "perspective camera: at the distance of its target, " +
                                      core::numberText(glm::length(camera.target - camera.position)) + " units";
  j["cellSizeInSceneUnits"] = {sevenDigits(unit * l.cellWidth), sevenDigits(unit * l.cellHeight)};
  // The camera's target projects to the rendered frame's centre.
  j["pivot"] = {(l.offsetX - l.crop.x + 0.5 * scene.width) / l.cellWidth,
                (l.offsetY - l.crop.y + 0.5 * scene.height) / l.cellHeight};
  j["order"] = "left to right, then top to bottom; frame i at column i % columns, row i / columns (row 0 at the top)";
  j["fps"] = scene.animation.fps;
  j["firstFrame"] = seq.first;
  j["lastFrame"] = seq.first + cellsUsed - 1;
  j["skippedFrames"] = seq.skipped;
  j["loop"] = o.loop;  // frames cross-faded: the sheet's cell j < loop also holds frame lastFrame + 1 + j
  j["period"] = scene.animation.period;  // a loop's frames: frame lastFrame + 1 is frame firstFrame
  j["alpha"] = std::string(core::toString(s.alpha));
  j["colour"] = s.exr ? (o.float32 ? "scene-linear Rec.709 (32-bit float)" : "scene-linear Rec.709 (half float)")
                      : "display sRGB, 8 bits, through the " + std::string(core::toString(s.view)) + " view transform";
  j["scene"] = scene.file.filename().string();
  return j;
}

// Writes the sheet and its layout as one transaction; false (the error printed) if any step fails.
bool writeSheetAndLayout(const Options& o, const SheetSpec& s, const render::SheetLayout& l, const core::Image& sheet,
                         const fs::path& target, const fs::path& layout, const nlohmann::ordered_json& j) {
  core::OutputTransaction tx;
  const fs::path stagedSheet = tx.stage(target);
  core::ImageAttributes attributes{{"puff:alpha", std::string(core::toString(s.alpha))},
                                   {"puff:flipbook", std::to_string(l.columns) + "x" + std::to_string(l.rows)}};
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

// Prints what was written (unless -q): the sheet, the crop and padding, skipped frames, the loop's
// cross-fade and any empty cells.
void printFlipbookSummary(const Options& o, const Sequence& seq, const render::SheetLayout& l, const SheetSpec& s,
                          const fs::path& target, const fs::path& layout) {
  if (o.quiet) return;
  const int cellsUsed = seq.cells, cells = l.columns * l.rows;
  std::printf("%s: wrote %s (%dx%d: %d frame%s, %d to %d, in %dx%d cells of %dx%d, %s alpha) and %s\n", cli::name(),
              target.c_str(), l.sheetWidth(), l.sheetHeight(), cellsUsed, cellsUsed == 1 ? "" : "s", seq.first,
              seq.first + cellsUsed - 1, l.columns, l.rows, l.cellWidth, l.cellHeight,
              std::string(core::toString(s.alpha)).c_str(), layout.c_str());
  if (o.crop || l.padding > 0 || l.pow2) {
    std::printf("%s: each cell holds the frames' %dx%d at (%d, %d)%s at (%d, %d) in the cell\n", cli::name(),
                l.crop.width, l.crop.height, l.crop.x, l.crop.y, o.crop ? ", the sequence's coverage," : "", l.offsetX,
                l.offsetY);
  }
  if (seq.skipped > 0) {
    std::printf("%s: skipped %d leading frame%s that draw%s nothing\n", cli::name(), seq.skipped,
                seq.skipped == 1 ? "" : "s", seq.skipped == 1 ? "s" : "");
  }
  if (o.loop > 0) {
    if (o.loop == 1) {
      std::printf("%s: looped: frame %d cross-faded into the first cell\n", cli::name(), seq.first + cellsUsed);
    } else {
      std::printf("%s: looped: frames %d to %d cross-faded into the first %d cells\n", cli::name(),
                  seq.first + cellsUsed, seq.first + cellsUsed + o.loop - 1, o.loop);
    }
  }
  if (cellsUsed < cells) {
    std::printf(
        "%s: note: the last %d cell%s of the sheet %s empty (frameCount in the layout says how many hold "
        "frames)\n",
        cli::name(), cells - cellsUsed, cells - cellsUsed == 1 ? "" : "s", cells - cellsUsed == 1 ? "is" : "are");
  }
}

}  // namespace

int writeFlipbook(const Options& o, const scene::Scene& scene, const Plan& plan, render::SceneRenderer& renderer) {
  // PNG: display values through the view transform, alpha straight unless asked; EXR: scene-linear,
  // premultiplied (checkAgainstScene refused straight EXR).
  const SheetSpec spec{scene::viewTransformFor(scene),
                       scene.alpha.value_or(plan.exr ? core::AlphaMode::kPremultiplied : core::AlphaMode::kStraight),
                       plan.exr};
  const bool bleed = !spec.exr && spec.alpha == core::AlphaMode::kStraight;
  const render::SheetRequest request{
      plan.flipColumns, plan.flipRows, {0, 0, scene.width, scene.height}, o.padding, o.pow2};
  // Without --crop the layout is known before anything is drawn and each frame goes into the sheet as
  // it comes; with it the frames wait for their crop (planFlipbook checked that the uncropped sheet,
  // which they add up to, is within the limits).
  auto layout = render::layOutSheet(request);
  if (!layout) {
    cli::printError(Error{"--flipbook " + o.flipbook + ": " + layout.error().message});
    return 1;
  }
  core::Image sheet;
  std::vector<core::Image> cells;
  auto intoSheet = [&](int i, const core::Image& linear) {
    if (sheet.empty())
      sheet = core::Image(layout->sheetWidth(), layout->sheetHeight(), 4, 0.0f);  // empty cells: alpha 0
    const core::Image display = spec.exr ? linear : core::viewTransform(linear, spec.view, spec.alpha);
    render::placeCell(sheet, *layout, i, render::cellOf(display, *layout, bleed, spec.covered()));
  };
  const PlaceCell place = [&](int i, core::Image linear) {
    if (!o.crop) return intoSheet(i, linear);
    if (cells.size() <= static_cast<std::size_t>(i)) cells.resize(static_cast<std::size_t>(i) + 1);
    cells[static_cast<std::size_t>(i)] = std::move(linear);
  };
  auto seq = renderSequence(o, plan, renderer, spec, !o.crop && !(o.skipEmpty && o.loop > 0), place);
  if (!seq) {
    cli::printError(seq.error());
    return 1;
  }
  if (o.crop) {
    const render::PixelRect crop = render::coverageBox(cells, spec.covered());
    if (crop.empty()) {
      cli::printError(Error{"--crop: frames " + std::to_string(seq->first) + " to " +
                            std::to_string(seq->first + seq->cells - 1) +
                            " draw nothing: there is nothing to crop to"});
      return 1;
    }
    layout = render::layOutSheet({plan.flipColumns, plan.flipRows, crop, o.padding, o.pow2});
    if (!layout) {
      cli::printError(Error{"--flipbook " + o.flipbook + ": " + layout.error().message});
      return 1;
    }
    for (std::size_t i = 0; i < cells.size(); ++i) intoSheet(static_cast<int>(i), cells[i]);
  }

  const fs::path target = plan.pattern.name(plan.first);
  fs::path layoutPath = target;
  layoutPath.replace_extension(".json");
  const nlohmann::ordered_json j = flipbookLayout(o, scene, *seq, *layout, spec, target);
  if (!writeSheetAndLayout(o, spec, *layout, sheet, target, layoutPath, j)) return 1;
  printFlipbookSummary(o, *seq, *layout, spec, target, layoutPath);
  return 0;
}

}  // namespace puff::app
