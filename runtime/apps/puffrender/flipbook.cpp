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

namespace {

// Where map `m` of sheet `target` goes: beside it, STEM_name.png.
fs::path mapPath(const fs::path& target, const render::FlipbookMap& m) {
  return target.parent_path() / (target.stem().string() + "_" + std::string(m.name) + ".png");
}

// Whether `path` is a map puffrender wrote (its "puff:map" attribute names map `name`).
bool writtenAsMap(const fs::path& path, const std::string& name) {
  core::ImageFileInfo info;
  if (!core::readImage(path, &info)) return false;
  for (const auto& [key, value] : info.attributes) {
    if (key == "puff:map" && value == name) return true;
  }
  return false;
}

// The maps asked for may replace only maps: files this sheet's layout `j` (null: none) names as its
// maps, or that puffrender wrote as that map.
Result<void> checkMapTargets(const Options& o, const fs::path& target, const nlohmann::json& j) {
  for (const std::string& name : o.maps) {
    const fs::path path = mapPath(target, *render::findFlipbookMap(name));
    std::error_code ec;
    if (!fs::exists(path, ec)) continue;
    const bool ours = (j.is_object() && j.contains("maps") && j["maps"].is_object() && j["maps"].contains(name) &&
                       j["maps"][name].is_object() && j["maps"][name].value("image", "") == path.filename().string()) ||
                      writtenAsMap(path, name);
    if (!ours) {
      return Error{"-o " + target.string() + ": the " + name + " map goes to " + path.string() +
                   ", which exists and is not a map puffrender wrote; it is left alone: give the sheet another name"};
    }
  }
  return {};
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
  if (!fs::exists(layout, ec)) return checkMapTargets(o, target, nlohmann::json());
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
  return checkMapTargets(o, target, j);
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

// One frame as its cell takes it: the colour (scene-linear, premultiplied) and each map asked for
// (--maps, in its order: the map's values, premultiplied by the coverage).
struct FrameImages {
  core::Image colour;
  std::vector<core::Image> maps;
};

// The maps asked for and how depth is encoded (the same for every frame).
struct MapRequest {
  std::vector<const render::FlipbookMap*> maps;
  render::MapRanges ranges;  // as the maps are drawn (SceneRenderer::setOutput)
  float motionRange = 1.0f;  // the motion map's: texels either side of no motion in the file
  int bits = 8;
};

// Takes cell `cell`'s frame (the loop's cross-fade done).
using PlaceCell = std::function<void(int cell, FrameImages frame)>;

// Mixes a late frame with head frame `from` (cell j of a --loop N), giving `from` weight (j + 1) / (N + 1).
// (A loop has no maps: parse refuses --maps with --loop.)
FrameImages crossFade(FrameImages mixed, const FrameImages& from, int j, int loop) {
  const float weight = static_cast<float>(j + 1) / static_cast<float>(loop + 1);
  for (std::size_t k = 0; k < mixed.colour.pixels.size(); ++k) {
    mixed.colour.pixels[k] = (1.0f - weight) * mixed.colour.pixels[k] + weight * from.colour.pixels[k];
  }
  return mixed;
}

// The motion map is drawn with this range (pixels) and decoded (mapCellValues), then encoded with
// the sequence's largest motion (encodeMotion): a float target keeps a hundredth of a pixel at it.
constexpr float kMotionDrawRange = 16384.0f;

// A map frame as drawn (straight) to what its cell takes: a texel it covers as it is (a motion
// frame's, 0.5 + m / (2 kMotionDrawRange), decoded to m in texels, x right and y up), one it does
// not the map's `nothing` (no motion), which the bleed then replaces where a covered texel reaches.
void mapCellValues(core::Image& image, const render::FlipbookMap& map) {
  const bool motion = map.output == cel::FrameOutput::kMotion;
  for (std::size_t i = 0; i < image.pixels.size(); i += static_cast<std::size_t>(image.channels)) {
    float* t = &image.pixels[i];
    if (t[3] <= 0.0f) {
      for (int c = 0; c < 3; ++c) t[c] = motion ? 0.0f : map.nothing[c];
    } else if (motion) {
      for (int c = 0; c < 2; ++c) t[c] = (t[c] - 0.5f) * 2.0f * kMotionDrawRange;
      t[2] = 0.0f;
    }
  }
}

// The motion sheet in texels to the file's encoding, with the sequence's largest motion as its
// range (at least a texel); returns that range.
float encodeMotion(core::Image& sheet) {
  float largest = 0.0f;
  for (std::size_t i = 0; i < sheet.pixels.size(); i += static_cast<std::size_t>(sheet.channels)) {
    largest = std::max({largest, std::abs(sheet.pixels[i]), std::abs(sheet.pixels[i + 1])});
  }
  const float range = std::max(1.0f, std::ceil(largest));
  for (std::size_t i = 0; i < sheet.pixels.size(); i += static_cast<std::size_t>(sheet.channels)) {
    for (int c = 0; c < 2; ++c) sheet.pixels[i + c] = 0.5f + sheet.pixels[i + c] / (2.0f * range);
  }
  return range;
}

// Frame `frame`'s maps, drawn after its colour; the renderer is left drawing colour.
Result<std::vector<core::Image>> renderMaps(render::SceneRenderer& renderer, int frame, const MapRequest& request) {
  std::vector<core::Image> maps;
  for (const render::FlipbookMap* m : request.maps) {
    PUFF_TRY(renderer.setOutput(m->output, request.ranges));
    auto image = renderer.renderFrame(frame);
    (void)renderer.setOutput(cel::FrameOutput::kColour);  // the colour output is every path's
    if (!image) return image.error();
    maps.push_back(std::move(*image));
  }
  return maps;
}

// Hands the k-th of n kept frames to its cell. --loop N: the first N frames wait in `head` for the
// last N; cell j < N is the mix of frame j (weight (j + 1) / (N + 1)) and frame n - N + j,
// premultiplied in scene-linear light, so the sheet's last cell runs on into its first.
void dispatch(int k, int n, int loop, FrameImages frame, std::vector<FrameImages>& head, const PlaceCell& place) {
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
                                const SheetSpec& spec, const MapRequest& maps, bool stream, const PlaceCell& place) {
  const int wanted = plan.last - plan.first + 1, loop = o.loop;
  Sequence seq;
  std::vector<FrameImages> held, head;
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
    auto mapImages = renderMaps(renderer, frame, maps);
    if (!mapImages) {
      progress.finish();
      return mapImages.error();
    }
    FrameImages images{std::move(*image), std::move(*mapImages)};
    if (stream) {
      dispatch(kept, wanted, loop, std::move(images), head, place);
    } else {
      held.push_back(std::move(images));
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

// The smallest rectangle holding every texel any frame's colour covers (render::coverageBox over all).
render::PixelRect sequenceCoverage(const std::vector<FrameImages>& frames, float threshold) {
  render::PixelRect box;
  for (const FrameImages& f : frames) {
    const render::PixelRect b = render::coverageBox(std::span(&f.colour, 1), threshold);
    if (b.empty()) continue;
    if (box.empty()) {
      box = b;
      continue;
    }
    const int x1 = std::max(box.x + box.width, b.x + b.width), y1 = std::max(box.y + box.height, b.y + b.height);
    box.x = std::min(box.x, b.x);
    box.y = std::min(box.y, b.y);
    box.width = x1 - box.x;
    box.height = y1 - box.y;
  }
  return box;
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

// The layout's "maps": each map's file and encoding.
nlohmann::ordered_json mapsLayout(const MapRequest& request, const render::SheetLayout& layout,
                                  const cel::Camera& camera, const fs::path& target) {
  nlohmann::ordered_json maps = nlohmann::ordered_json::object();
  for (const render::FlipbookMap* m : request.maps) {
    nlohmann::ordered_json j;
    j["image"] = mapPath(target, *m).filename().string();
    j["channels"] = m->channels;
    j["bits"] = request.bits;
    j["encoding"] = std::string(m->encoding);
    if (m->output == cel::FrameOutput::kDepth) {
      // Each frame's distance is measured from its own camera; a flipbook's camera does not move.
      j["targetDistance"] = sevenDigits(glm::length(camera.target - camera.position));
      j["depthRange"] = sevenDigits(request.ranges.depth);
    }
    if (m->output == cel::FrameOutput::kMotion) {
      j["motionRange"] = request.motionRange;
      // A decoded value (2 R - 1, 2 G - 1) of 1 as a share of the cell: Unity VFX Graph's Motion Vector Scale.
      j["motionRangeInCell"] = {sevenDigits(request.motionRange / layout.cellWidth),
                                sevenDigits(request.motionRange / layout.cellHeight)};
    }
    j["uncovered"] =
        "where the map covers nothing (no puff or object), a texel it covers nearby in the cell (breadth first); in a "
        "cell it covers nowhere, nothing: normal facing the camera, depth and ink 0, no motion";
    maps[std::string(m->name)] = j;
  }
  return maps;
}

// The layout JSON written beside the sheet: how an engine reads the cells, and what they hold.
nlohmann::ordered_json flipbookLayout(const Options& o, const scene::Scene& scene, const Sequence& seq,
                                      const render::SheetLayout& l, const SheetSpec& s, const MapRequest& maps,
                                      const fs::path& target) {
  const int cellsUsed = seq.cells;
  const cel::Camera camera = scene::cameraAt(scene, seq.first);
  const double unit = sceneUnitsPerTexel(camera, scene.height);
  nlohmann::ordered_json j;
  j["format"] = "puff-flipbook";
  j["version"] = 3;
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
  if (!maps.maps.empty()) j["maps"] = mapsLayout(maps, l, camera, target);
  j["scene"] = scene.file.filename().string();
  return j;
}

// The first `channels` channels of `sheet`.
core::Image channelsOf(const core::Image& sheet, int channels) {
  core::Image out(sheet.width, sheet.height, channels);
  const std::size_t n = static_cast<std::size_t>(sheet.width) * sheet.height;
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < channels; ++c) {
      out.pixels[i * channels + c] = sheet.pixels[i * sheet.channels + c];
    }
  }
  return out;
}

// Stages every map sheet in `tx`; false (the error printed) if one fails.
bool stageMaps(core::OutputTransaction& tx, const MapRequest& request, const std::vector<core::Image>& sheets,
               const fs::path& target) {
  for (std::size_t k = 0; k < request.maps.size(); ++k) {
    const render::FlipbookMap& m = *request.maps[k];
    const fs::path path = mapPath(target, m);
    const core::ImageAttributes attributes{{"puff:map", std::string(m.name)},
                                           {"puff:encoding", std::string(m.encoding)}};
    const core::PixelType type = request.bits == 16 ? core::PixelType::kUInt16 : core::PixelType::kUInt8;
    if (auto r = core::writeImage(tx.stage(path), channelsOf(sheets[k], m.channels), type, attributes, path); !r) {
      cli::printError(Error::at(path, r.error().message));
      return false;
    }
  }
  return true;
}

// Writes the sheet, its maps and its layout as one transaction; false (the error printed) if any step fails.
bool writeSheetAndLayout(const Options& o, const SheetSpec& s, const render::SheetLayout& l, const core::Image& sheet,
                         const MapRequest& maps, const std::vector<core::Image>& mapSheets, const fs::path& target,
                         const fs::path& layout, const nlohmann::ordered_json& j) {
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
  if (!stageMaps(tx, maps, mapSheets, target)) return false;
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
  MapRequest maps;
  for (const std::string& name : o.maps) maps.maps.push_back(render::findFlipbookMap(name));  // parse checked them
  // Depth: half the rendered frame's larger side either side of the target (what the cells can show).
  maps.ranges.depth = static_cast<float>(sceneUnitsPerTexel(scene::cameraAt(scene, plan.first), scene.height) *
                                         std::max(scene.width, scene.height) * 0.5);
  maps.ranges.motion = kMotionDrawRange;
  maps.bits = o.mapBits == 0 ? 8 : o.mapBits;
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
  std::vector<core::Image> mapSheets(maps.maps.size());
  std::vector<FrameImages> cells;
  auto intoSheet = [&](int i, const FrameImages& frame) {
    if (sheet.empty()) {
      sheet = core::Image(layout->sheetWidth(), layout->sheetHeight(), 4, 0.0f);  // empty cells: alpha 0
      for (std::size_t k = 0; k < mapSheets.size(); ++k) {
        // Empty cells hold the map's `nothing` (motion: 0 texels until encodeMotion).
        const render::FlipbookMap& map = *maps.maps[k];
        const bool motion = map.output == cel::FrameOutput::kMotion;
        mapSheets[k] = core::Image(sheet.width, sheet.height, 4, 0.0f);
        for (std::size_t i = 0; i < mapSheets[k].pixels.size(); i += 4) {
          for (int c = 0; c < 3; ++c) mapSheets[k].pixels[i + c] = motion ? 0.0f : map.nothing[c];
        }
      }
    }
    const core::Image display = spec.exr ? frame.colour : core::viewTransform(frame.colour, spec.view, spec.alpha);
    render::placeCell(sheet, *layout, i, render::cellOf(display, *layout, bleed, spec.covered()));
    // Maps are data: straight, and bled into every uncovered texel (what an engine's filter reads there).
    for (std::size_t k = 0; k < mapSheets.size(); ++k) {
      core::Image values = core::unpremultiply(frame.maps[k]);
      mapCellValues(values, *maps.maps[k]);
      render::placeCell(mapSheets[k], *layout, i, render::cellOf(values, *layout, true, spec.covered()));
    }
  };
  const PlaceCell place = [&](int i, FrameImages frame) {
    if (!o.crop) return intoSheet(i, frame);
    if (cells.size() <= static_cast<std::size_t>(i)) cells.resize(static_cast<std::size_t>(i) + 1);
    cells[static_cast<std::size_t>(i)] = std::move(frame);
  };
  auto seq = renderSequence(o, plan, renderer, spec, maps, !o.crop && !(o.skipEmpty && o.loop > 0), place);
  if (!seq) {
    cli::printError(seq.error());
    return 1;
  }
  if (o.crop) {
    const render::PixelRect crop = sequenceCoverage(cells, spec.covered());
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
  for (std::size_t k = 0; k < maps.maps.size(); ++k) {
    if (maps.maps[k]->output == cel::FrameOutput::kMotion && !mapSheets[k].empty())
      maps.motionRange = encodeMotion(mapSheets[k]);
  }
  const nlohmann::ordered_json j = flipbookLayout(o, scene, *seq, *layout, spec, maps, target);
  if (!writeSheetAndLayout(o, spec, *layout, sheet, maps, mapSheets, target, layoutPath, j)) return 1;
  printFlipbookSummary(o, *seq, *layout, spec, target, layoutPath);
  if (!o.quiet && !maps.maps.empty() && !hasCelParticles(scene)) {
    std::printf(
        "%s: note: the maps hold the puffs and objects alone, and %s has no cel puffs: its media are in the "
        "colour sheet only\n",
        cli::name(), scene.file.filename().c_str());
  }
  if (!o.quiet && !maps.maps.empty()) {
    std::string names;
    for (const render::FlipbookMap* m : maps.maps) names += (names.empty() ? "" : ", ") + mapPath(target, *m).string();
    std::printf("%s: wrote the maps %s (%d bits a channel; the layout says how each is encoded)\n", cli::name(),
                names.c_str(), maps.bits);
  }
  return 0;
}

}  // namespace puff::app
