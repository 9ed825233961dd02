// Tumbling puffs against the cel reference (tumble.h). Each pose is one oriented puff in its own
// square of a grid (yaw across, pitch down, one frame per roll), orthographic, so every square shows
// the same puff at the same size: the nailboards and the reference are judged square by square.
#include <puff/core/stopwatch.h>
#include <puff/eval/tumble.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <puff/core/atlas.h>
#include <puff/core/colour.h>
#include <puff/eval/cel_reference.h>
#include <puff/reference/metrics.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

namespace puff::eval {

namespace fs = std::filesystem;

namespace {

constexpr float kSpacing = 1.5f;    // a square is 1.5 puff diameters: neighbours' ink never meets
const glm::vec3 kBackground(0.9f);  // the scene's clear colour: a display (sRGB-encoded) value
constexpr float kAmbient = 0.25f;   // display value: the ambient light

struct Grid {
  int columns = 0, rows = 0, square = 0;  // square: pixels per side
};

// Angles from `from` every `step`: below `to`, or up to it with `inclusive`.
std::vector<int> sweep(int from, int to, int step, bool inclusive = false) {
  std::vector<int> v;
  for (int a = from; a < to || (inclusive && a == to); a += step) v.push_back(a);
  return v;
}

// The grid's columns (yaws) and rows (pitches).
std::vector<int> yawsOf(const TumbleOptions& o) { return sweep(o.offsetDegrees, 360, o.stepDegrees); }
std::vector<int> pitchesOf(const TumbleOptions& o) { return sweep(-90 + o.offsetDegrees, 90, o.stepDegrees, true); }

Grid gridFor(const TumbleOptions& o) {
  Grid g;
  g.columns = static_cast<int>(yawsOf(o).size());
  g.rows = static_cast<int>(pitchesOf(o).size());
  g.square = static_cast<int>(std::lround(kSpacing * static_cast<float>(o.puffPixels)));
  return g;
}

glm::quat poseRotation(const TumblePose& p) {
  auto about = [](int degrees, glm::vec3 axis) { return glm::angleAxis(glm::radians(float(degrees)), axis); };
  return about(p.yaw, {0, 1, 0}) * about(p.pitch, {1, 0, 0}) * about(p.roll, {0, 0, 1});
}

Result<void> checkOptions(const TumbleOptions& o) {
  if (o.stepDegrees < 1 || 90 % o.stepDegrees != 0) {
    return Error{"tumble sweep: the step (" + std::to_string(o.stepDegrees) + " degrees) must divide 90"};
  }
  if (o.offsetDegrees < 0 || o.offsetDegrees >= o.stepDegrees) {
    return Error{"tumble sweep: the offset (" + std::to_string(o.offsetDegrees) + " degrees) must be in [0, " +
                 std::to_string(o.stepDegrees) + ")"};
  }
  if (o.puffPixels < 8 || o.puffPixels > 512) return Error{"tumble sweep: puffs of 8 to 512 pixels"};
  return {};
}

// The scene of one roll's grid: an orthographic camera on +z, a light from the upper left front,
// outlines and Eq. 2 shading, no shadows (each pose alone is judged).
Result<scene::Scene> gridScene(const fs::path& atlas, const TumbleOptions& o, int roll, int variations,
                               cel::TumbleMethod method = cel::TumbleMethod::kHull, bool outlines = true) {
  const Grid g = gridFor(o);
  const float unit = 1.0f;  // a puff's diameter, world units
  const float pxPerUnit = static_cast<float>(o.puffPixels) / unit;
  const int width = g.columns * g.square, height = g.rows * g.square;
  const nlohmann::json j = {{"output",
                             {{"width", width},
                              {"height", height},
                              {"samples", 1},
                              {"background", {kBackground.x, kBackground.y, kBackground.z}}}},
                            {"camera",
                             {{"position", {0, 0, 50}},
                              {"target", {0, 0, 0}},
                              {"up", {0, 1, 0}},
                              {"fovY", 0},
                              {"orthoHeight", static_cast<float>(height) / pxPerUnit},
                              {"near", 1},
                              {"far", 100}}},
                            {"light", {{"direction", {-0.4, 0.5, 0.77}}, {"color", {0.7, 0.7, 0.7}}}},
                            {"ambient", {{"color", {kAmbient, kAmbient, kAmbient}}}},
                            {"atlas", atlas.string()},
                            {"style",
                             {{"outlines", outlines},
                              {"outlineWidth", o.outlineWidth},
                              {"shading", true},
                              {"shadows", false},
                              {"tumble", std::string(cel::toString(method))}}}};
  PUFF_TRY_ASSIGN(auto s, scene::parseScene(j, atlas.parent_path() / "tumble-sweep.json"));
  const std::vector<int> yaws = yawsOf(o), pitches = pitchesOf(o);
  int index = 0;
  for (std::size_t r = 0; r < pitches.size(); ++r) {
    for (std::size_t c = 0; c < yaws.size(); ++c, ++index) {
      scene::ParticleSpec p;
      const float x = (static_cast<float>(c) + 0.5f) * kSpacing * unit - 0.5f * width / pxPerUnit;
      const float y = 0.5f * height / pxPerUnit - (static_cast<float>(r) + 0.5f) * kSpacing * unit;
      p.position = glm::vec3(x, y, 0.0f);
      p.size = unit;
      p.variation = index % std::max(1, variations);
      p.oriented = true;
      p.orientation = poseRotation(TumblePose{yaws[c], pitches[r], roll});
      s.particles.push_back(p);
    }
  }
  return s;
}

Result<core::Image> renderOnce(const scene::Scene& s, render::RenderPath path, std::vector<double>* times) {
  // Both point-sampled at pixel centres (one sample a pixel, the reference not supersampled): the
  // masks compare where the silhouettes and bands lie, not how two antialiasing filters spread
  // their edges (a 3 x 3 box against 4 MSAA samples alone moves the masks by a fraction of a pixel
  // all around).
  PUFF_TRY_ASSIGN(auto r, path == render::RenderPath::kReference
                              ? createCelReference(s, CelReferenceOptions{.supersample = 1})
                              : createRenderer(s, path));
  auto image = (r)->renderFrame(0);
  if (!image || !times) return image;
  for (int i = 0; i < 3; ++i) {
    const auto t0 = core::Clock::now();
    if (auto again = (r)->renderFrame(0); !again) return again.error();
    times->push_back(core::millisecondsSince(t0));
  }
  return image;
}

// One square of an image as its own image.
core::Image square(const core::Image& im, int col, int row, int side) {
  core::Image out(side, side, im.channels);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
      for (int c = 0; c < im.channels; ++c) out.at(x, y, c) = im.at(col * side + x, row * side + y, c);
  return out;
}

// The pixels `outlined` covers and `body` (the same frame drawn without outlines) does not.
std::vector<bool> inkBand(const core::Image& outlined, const core::Image& body, const core::Image& background) {
  std::vector<bool> ink = reference::coverageMask(outlined, background);
  const std::vector<bool> bare = reference::coverageMask(body, background);
  for (std::size_t i = 0; i < ink.size(); ++i) ink[i] = ink[i] && !bare[i];
  return ink;
}

int variationsOf(const fs::path& atlas) {
  auto d = core::loadAtlasDesc(atlas);
  return d ? std::max(1, d->variations) : 1;
}

// The pixels `a` covers and `b` does not (extra), and the reverse (missing), as fractions of `b`'s.
void differences(const std::vector<bool>& a, const std::vector<bool>& b, double& extra, double& missing) {
  std::size_t more = 0, fewer = 0, covered = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    more += a[i] && !b[i];
    fewer += b[i] && !a[i];
    covered += b[i];
  }
  extra = covered ? static_cast<double>(more) / static_cast<double>(covered) : 0.0;
  missing = covered ? static_cast<double>(fewer) / static_cast<double>(covered) : 0.0;
}

// A reference whose frames, frames without outlines and rolls do not match one to one is an error.
Result<void> checkReference(const TumbleReference& reference) {
  if (reference.bodies.size() != reference.frames.size() || reference.frames.size() != reference.rolls.size()) {
    return Error{"tumble sweep: the reference has " + std::to_string(reference.frames.size()) + " frames, " +
                 std::to_string(reference.bodies.size()) + " without outlines and " +
                 std::to_string(reference.rolls.size()) + " rolls (make it with renderTumbleReference)"};
  }
  return {};
}

// The background a square is judged against: the clear colour as the frames hold it (frames are
// scene-linear), and a square of it.
struct Background {
  glm::vec3 linear;
  core::Image square;
};

Background backgroundOf(const Grid& g) {
  Background bg{core::srgbToLinear(kBackground), core::Image(g.square, g.square, 4)};
  for (int y = 0; y < g.square; ++y)
    for (int x = 0; x < g.square; ++x)
      for (int c = 0; c < 4; ++c) bg.square.at(x, y, c) = c < 3 ? bg.linear[c] : 1.0f;
  return bg;
}

// One roll's grid drawn by the nailboards: with outlines (timed into `times`, when given) and
// without.
struct RollFrames {
  core::Image outlined, body;
};

Result<RollFrames> renderRoll(const fs::path& atlas, const TumbleOptions& o, int roll, int variations,
                              cel::TumbleMethod method, std::vector<double>* times) {
  PUFF_TRY_ASSIGN(auto s, gridScene(atlas, o, roll, variations, method));
  PUFF_TRY_ASSIGN(auto image, renderOnce(s, render::RenderPath::kCel, times));
  PUFF_TRY_ASSIGN(auto bare, gridScene(atlas, o, roll, variations, method, false));
  PUFF_TRY_ASSIGN(auto body, renderOnce(bare, render::RenderPath::kCel, nullptr));
  return RollFrames{std::move(image), std::move(body)};
}

// The nailboards' frames of roll `f` must be the size of the reference's.
Result<void> checkFrameSizes(const RollFrames& frames, const TumbleReference& reference, std::size_t f) {
  const core::Image& ref = reference.frames[f];
  for (const core::Image* im : {&frames.outlined, &frames.body, &reference.bodies[f]}) {
    if (im->width == ref.width && im->height == ref.height) continue;
    return Error{"tumble sweep: the reference frames are " + std::to_string(ref.width) + "x" +
                 std::to_string(ref.height) + ", its frames without outlines " +
                 std::to_string(reference.bodies[f].width) + "x" + std::to_string(reference.bodies[f].height) +
                 ", the nailboards' " + std::to_string(frames.outlined.width) + "x" +
                 std::to_string(frames.outlined.height)};
  }
  return {};
}

// One pose's square of the nailboards' frame (a) and the reference's (b), each with outlines and
// without (body).
struct PoseSquares {
  core::Image a, b, aBody, bBody;
};

// Pose `p`'s coverage and ink measured in its squares: IoUs and the differences either way. The
// yardstick checks itself on the way: an error where its masks would be wrong.
Result<void> measurePose(const PoseSquares& s, const Background& bg, const TumbleOptions& o, TumblePose& p) {
  // A square's corner lies outside its puff (half a diameter from the centre of a square 1.5
  // diameters wide), so it must read as background.
  for (const core::Image* im : {&s.a, &s.b}) {
    if (reference::coverageMask(*im, bg.square)[0]) {
      return Error{"tumble sweep: a square's corner is not the background colour (" + std::to_string(im->at(0, 0, 0)) +
                   " against " + std::to_string(bg.linear.x) + "): the coverage masks would be wrong"};
    }
  }
  const std::vector<bool> coveredA = reference::coverageMask(s.a, bg.square),
                          coveredB = reference::coverageMask(s.b, bg.square);
  p.coverageIoU = reference::maskIoU(coveredA, coveredB);
  differences(coveredA, coveredB, p.coverageExtra, p.coverageMissing);
  differences(reference::coverageMask(s.aBody, bg.square), reference::coverageMask(s.bBody, bg.square), p.bodyExtra,
              p.bodyMissing);
  // Ink: what the outlines add to the puff, the pixels covered with them and not without (the
  // body alone, drawn again without outlines). From coverage, not colour: the nailboards'
  // ink mixes with the body within half a pixel of the silhouette (its antialiased inner
  // edge), the reference's does not, and a colour threshold would take a mixed pixel on a lit
  // body for body and one on the dark band for ink.
  const std::vector<bool> inkA = inkBand(s.a, s.aBody, bg.square), inkB = inkBand(s.b, s.bBody, bg.square);
  // The yardstick checks itself again: the reference's ink rings its puff (at least a
  // quarter of a ring of the outline's width around a circle the puff's size). A fault that
  // drew both the same, with outlines or without, would leave both masks empty: IoU 1.
  const auto refInk = std::count(inkB.begin(), inkB.end(), true);
  const double ring = 0.25 * std::numbers::pi * o.puffPixels * o.outlineWidth;
  if (o.outlineWidth > 0.0f && static_cast<double>(refInk) < ring) {
    return Error{"tumble sweep: the reference's ink covers " + std::to_string(refInk) + " pixels of pose yaw " +
                 std::to_string(p.yaw) + " pitch " + std::to_string(p.pitch) + " roll " + std::to_string(p.roll) +
                 ", under a quarter of a ring of the outline's width (" + std::to_string(static_cast<int>(ring)) +
                 "): the ink masks would be wrong"};
  }
  p.outlineIoU = reference::maskIoU(inkA, inkB);
  return {};
}

// Every pose of roll `f`'s grid measured, square by square, row by row, appended to `poses`.
Result<void> measureRoll(const RollFrames& frames, const TumbleReference& reference, std::size_t f,
                         const Background& bg, int variations, std::vector<TumblePose>& poses) {
  const TumbleOptions& o = reference.options;
  const int side = gridFor(o).square;
  const std::vector<int> yaws = yawsOf(o), pitches = pitchesOf(o);
  int index = 0;
  for (std::size_t r = 0; r < pitches.size(); ++r) {
    for (std::size_t c = 0; c < yaws.size(); ++c, ++index) {
      if (std::abs(pitches[r]) == 90 && yaws[c] != 0) continue;  // the same poses as yaw 0
      const int col = static_cast<int>(c), row = static_cast<int>(r);
      const PoseSquares s{square(frames.outlined, col, row, side), square(reference.frames[f], col, row, side),
                          square(frames.body, col, row, side), square(reference.bodies[f], col, row, side)};
      TumblePose p{yaws[c], pitches[r], reference.rolls[f], index % variations};
      PUFF_TRY(measurePose(s, bg, o, p));
      poses.push_back(p);
    }
  }
  return {};
}

// The least and the mean IoUs of the poses, taken in their order.
void summarize(TumbleResult& out) {
  double sumCoverage = 0.0, sumOutline = 0.0;
  for (const TumblePose& p : out.poses) {
    out.minCoverageIoU = std::min(out.minCoverageIoU, p.coverageIoU);
    out.minOutlineIoU = std::min(out.minOutlineIoU, p.outlineIoU);
    sumCoverage += p.coverageIoU;
    sumOutline += p.outlineIoU;
  }
  if (!out.poses.empty()) {
    out.meanCoverageIoU = sumCoverage / static_cast<double>(out.poses.size());
    out.meanOutlineIoU = sumOutline / static_cast<double>(out.poses.size());
  }
}

}  // namespace

std::vector<TumblePose> tumblePoses(int stepDegrees) {
  std::vector<TumblePose> out;
  if (stepDegrees < 1 || 90 % stepDegrees != 0) return out;
  for (int roll : sweep(0, 360, stepDegrees))
    for (int pitch : sweep(-90, 90, stepDegrees, true))
      for (int yaw : sweep(0, 360, stepDegrees)) {
        if (std::abs(pitch) == 90 && yaw != 0) continue;
        out.push_back(TumblePose{yaw, pitch, roll});
      }
  return out;
}

std::vector<TumblePose> tumbleGridPoses(const TumbleOptions& options) {
  std::vector<TumblePose> out;
  if (!checkOptions(options)) return out;
  for (int pitch : pitchesOf(options))
    for (int yaw : yawsOf(options)) {
      if (std::abs(pitch) == 90 && yaw != 0) continue;  // the same poses as yaw 0
      out.push_back(TumblePose{yaw, pitch, 0});
    }
  return out;
}

Result<TumbleReference> renderTumbleReference(const fs::path& atlas, const TumbleOptions& options,
                                              std::vector<int> rolls) {
  PUFF_TRY(checkOptions(options));
  if (rolls.empty()) rolls = sweep(0, 360, options.stepDegrees);
  TumbleReference ref;
  ref.options = options;
  ref.rolls = rolls;
  const int variations = variationsOf(atlas);
  for (int roll : rolls) {
    for (bool outlines : {true, false}) {
      PUFF_TRY_ASSIGN(auto s, gridScene(atlas, options, roll, variations, cel::TumbleMethod::kHull, outlines));
      PUFF_TRY_ASSIGN(auto image, renderOnce(s, render::RenderPath::kReference, nullptr));
      (outlines ? ref.frames : ref.bodies).push_back(std::move(image));
    }
  }
  return ref;
}

Result<TumbleResult> measureTumble(const fs::path& atlas, const TumbleReference& reference, cel::TumbleMethod method,
                                   double* msPerFrame) {
  const TumbleOptions& o = reference.options;
  PUFF_TRY(checkOptions(o));
  PUFF_TRY(checkReference(reference));
  const int variations = variationsOf(atlas);
  const Background bg = backgroundOf(gridFor(o));
  TumbleResult out;
  std::vector<double> times;
  for (std::size_t f = 0; f < reference.rolls.size(); ++f) {
    PUFF_TRY_ASSIGN(const RollFrames frames,
                    renderRoll(atlas, o, reference.rolls[f], variations, method, msPerFrame ? &times : nullptr));
    PUFF_TRY(checkFrameSizes(frames, reference, f));
    PUFF_TRY(measureRoll(frames, reference, f, bg, variations, out.poses));
  }
  summarize(out);
  if (msPerFrame && !times.empty()) {
    std::sort(times.begin(), times.end());
    *msPerFrame = times[times.size() / 2];
  }
  return out;
}

}  // namespace puff::eval
