// Oriented puffs turned by the hull only from a size on screen (cel::Style::hullFromPixels), the blend
// below it, and --max-error's choice among the ways (eval::CelKnob::kTumble).
#include "tumble_fixture.h"

#include <optional>
#include <string>
#include <vector>

#include <puff/cel/nailboards.h>
#include <puff/eval/budget.h>

namespace puff::tumble {
namespace {

// Two oriented puffs, lopsided and turned between views, for scenes with an orthoHeight of 2 at
// 240 px (120 px a unit): a large one `size` units across left of the centre, a small one 40 px
// across right of it.
nlohmann::json largePuff(float size) {
  nlohmann::json p = TumbleCases::puff(3, {1, 1, 0}, 37.0f);
  p["position"] = {-0.45, 0, 0};
  p["size"] = size;
  return p;
}
nlohmann::json smallPuff() {
  nlohmann::json p = TumbleCases::puff(1, {1, -1, 0.5f}, 61.0f);
  p["position"] = {0.5, 0, 0};
  p["size"] = 1.0 / 3.0;
  return p;
}

// Style::hullFromPixels: oriented puffs smaller on screen than it take the blend, the others the hull,
// and their shadows alike. Two puffs 96 and 40 px across, in the screen's left and right halves,
// casting on a wall behind them: split at 64 px, the frame is the hull's frame pixel for pixel on the
// large puff's half and the blend's on the small one's; split past both, the blend's frame. Drawn
// as the renderer picks (kAuto: every layer here), with the map's casters, single-sampled; and each
// pixel shaded once (the blend's share through the pre-pass, which the volumes' shadowed pass reads
// again), with shadow volumes, at 2 samples.
TEST_F(TumbleCases, HullFromPixelsSplitsThePuffsBySizeOnScreen) {
  nlohmann::json large = largePuff(0.8f), small = smallPuff();  // 96 and 40 px
  const nlohmann::json wall = nlohmann::json::array(
      {{{"type", "box"}, {"translate", {0, 0, -1}}, {"scale", {4, 3, 1}}, {"albedo", {0.8, 0.8, 0.8}}}});
  struct Setting {
    const char* name;
    cel::LitShading shading;
    const char* shadowMethod;
    int samples;
  };
  for (const Setting& setting : {Setting{"as picked, the map", cel::LitShading::kAuto, "map", 1},
                                 Setting{"once per pixel, volumes", cel::LitShading::kOncePerPixel, "volumes", 2}}) {
    SCOPED_TRACE(setting.name);
    auto frame = [&](const char* tumble, std::optional<float> hullFrom) -> Result<core::Image> {
      nlohmann::json j = sceneJson(hemiAtlas(), nlohmann::json::array({large, small}), wall, tumble);
      j["output"]["samples"] = setting.samples;
      j["camera"]["orthoHeight"] = 2.0;
      j["style"]["shadows"] = true;
      j["style"]["shadowMethod"] = setting.shadowMethod;
      j["light"]["direction"] = {0.3, 0.25, 1.0};
      if (hullFrom) j["style"]["hullFromPixels"] = *hullFrom;
      PUFF_TRY_ASSIGN(auto scene, scene::parseScene(j, dir_ / "case.json"));
      PUFF_TRY_ASSIGN(auto r, render::SceneRenderer::create(scene));
      (r)->setLitShading(setting.shading);
      return (r)->renderFrame(0);
    };
    auto hull = frame("hull", std::nullopt), blend = frame("blend", std::nullopt);
    auto split = frame("hull", 64.0f), allBlend = frame("hull", 4096.0f);
    ASSERT_OK(hull);
    ASSERT_OK(blend);
    ASSERT_OK(split);
    ASSERT_OK(allBlend);
    // Per half: pixels where the split differs from the method it should have used, and where the
    // two methods differ (so that the comparison can tell them apart).
    int wrong[2] = {0, 0}, methodsDiffer[2] = {0, 0}, notBlend = 0;
    auto differs = [](const core::Image& a, const core::Image& b, int x, int y) {
      for (int c = 0; c < 3; ++c)
        if (std::abs(a.at(x, y, c) - b.at(x, y, c)) > 1e-6f) return true;
      return false;
    };
    for (int y = 0; y < hull->height; ++y)
      for (int x = 0; x < hull->width; ++x) {
        const int half = x < hull->width / 2 ? 0 : 1;
        wrong[half] += differs(*split, half == 0 ? *hull : *blend, x, y);
        methodsDiffer[half] += differs(*hull, *blend, x, y);
        notBlend += differs(*allBlend, *blend, x, y);
      }
    EXPECT_GT(methodsDiffer[0], 200);
    EXPECT_GT(methodsDiffer[1], 30);
    EXPECT_EQ(wrong[0], 0) << "the large puff's half, of " << methodsDiffer[0] << " where the methods differ";
    EXPECT_EQ(wrong[1], 0) << "the small puff's half, of " << methodsDiffer[1] << " where the methods differ";
    EXPECT_EQ(notBlend, 0);
  }
}

// --max-error's tumble knob (eval::CelKnob::kTumble): the blend, the hull from each of
// eval::kHullFromPixels and the hull on all, each measured against the cel reference of the turned
// meshes, in the order of how many puffs take the hull (not of their times, which tie by noise where
// two draw the same frame); the budget takes the first within it, or the closest when none is.
TEST_F(TumbleCases, TheBudgetMeasuresTheBlendTheSplitsAndTheHull) {
  nlohmann::json large = largePuff(0.9f), small = smallPuff();  // 108 and 40 px
  auto sceneFor = [&] {
    nlohmann::json j = sceneJson(hemiAtlas(), nlohmann::json::array({large, small}));
    j["camera"]["orthoHeight"] = 2.0;
    return scene::parseScene(j, dir_ / "case.json");
  };
  auto scene = sceneFor();
  ASSERT_OK(scene);
  const std::vector<int> frames = {0};
  auto b = eval::measureCelBudget(*scene, frames, {.timedRenders = 1}, eval::CelKnob::kTumble);
  ASSERT_OK(b);
  ASSERT_EQ(b->candidates.size(), eval::kHullFromPixels.size() + 2);
  // In the order of how many puffs take the hull: the blend, the hull from each size down, the hull.
  EXPECT_EQ(b->candidates.front().tumble, cel::TumbleMethod::kBlend);
  for (std::size_t i = 0; i < eval::kHullFromPixels.size(); ++i) {
    EXPECT_EQ(b->candidates[i + 1].tumble, cel::TumbleMethod::kHull);
    EXPECT_EQ(b->candidates[i + 1].hullFromPixels, eval::kHullFromPixels[i]);
  }
  EXPECT_EQ(b->candidates.back().tumble, cel::TumbleMethod::kHull);
  EXPECT_EQ(b->candidates.back().hullFromPixels, 0.0f);
  const eval::CelCandidate *blend = &b->candidates.front(), *hull = &b->candidates.back();
  // The hull is the closer to the turned meshes; from 48 px on only the large puff takes it, which
  // puts the frame between the two.
  EXPECT_LT(hull->worstRmse, blend->worstRmse);
  for (const eval::CelCandidate& c : b->candidates) {
    if (c.hullFromPixels == 48.0f) {
      EXPECT_LT(c.worstRmse, blend->worstRmse);
      EXPECT_GT(c.worstRmse, hull->worstRmse);
    }
  }
  // Within the hull's own error: the first that is, every one with less of the hull missing it.
  auto within = eval::chooseCelBudget(*b, hull->worstRmse);
  ASSERT_OK(within);
  EXPECT_TRUE(within->met);
  EXPECT_LE(b->candidates[within->chosen].worstRmse, hull->worstRmse);
  for (std::size_t i = 0; i < within->chosen; ++i) EXPECT_GT(b->candidates[i].worstRmse, hull->worstRmse);
  EXPECT_NE(eval::celBudgetTable(*b, *within).find("the hull from 48 px"), std::string::npos);
  // Within none: the closest.
  auto none = eval::chooseCelBudget(*b, 1e-9);
  ASSERT_OK(none);
  EXPECT_FALSE(none->met);
  EXPECT_EQ(none->chosen, none->best);
  EXPECT_NE(eval::celBudgetSummary(*b, *none).find("none meets it"), std::string::npos);

  large["oriented"] = false;
  small["oriented"] = false;
  auto flat = sceneFor();
  ASSERT_OK(flat);
  auto refused = eval::measureCelBudget(*flat, frames, {.timedRenders = 1}, eval::CelKnob::kTumble);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("no oriented puffs, so no tumble method to choose"), std::string::npos)
      << refused.error().message;
}

}  // namespace
}  // namespace puff::tumble
