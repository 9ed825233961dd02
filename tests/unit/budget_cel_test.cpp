// The cel budget: atlas levels, shadow methods and particle counts measured against the cel reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <puff/bake/baker.h>
#include <puff/core/atlas.h>
#include <puff/eval/budget.h>
#include <puff/render/render.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

#include "support/assert_ok.h"
#include "support/sphere_atlas.h"

namespace puff {
namespace {
// ---- the cel path: atlas levels -------------------------------------------------------------------

class CelBudget : public test::SphereAtlasTest {
 protected:
  // Two sphere puffs (or those of `atlas`), shaded and outlined, 96 x 72, orthographic, two frames.
  static scene::Scene scene(int atlasLevel = 0, const std::filesystem::path& atlas = {}) {
    nlohmann::json j = {
        {"output", {{"width", 96}, {"height", 72}, {"samples", 1}, {"background", {0.9, 0.9, 0.9}}}},
        {"camera",
         {{"position", {0, 0, 10}}, {"target", {0, 0, 0}}, {"fovY", 0}, {"orthoHeight", 6}, {"near", 1}, {"far", 20}}},
        {"light", {{"direction", {0.4, 0.8, 0.45}}, {"color", {0.6, 0.6, 0.6}}}},
        {"ambient", {{"color", {0.2, 0.2, 0.25}}}},
        {"atlas", (atlas.empty() ? sidecar_ : atlas).string()},
        {"atlasLevel", atlasLevel},
        {"style", {{"preset", "cel"}, {"outlineWidth", 1.5}}},
        {"particles", {{{"position", {0.3, 0.2, 0}}, {"size", 3.0}}, {{"position", {-1.2, -0.8, 1}}, {"size", 2.0}}}},
        {"animation", {{"frames", 2}, {"fps", 4}, {"orbit", 20}}}};
    auto s = scene::parseScene(j, dir_ / "scene.json");
    EXPECT_OK(s);
    return s ? *s : scene::Scene{};
  }
};

// A level is the atlas with its finest levels dropped: every texel size shrinks by 2^level and the
// new level 0 is the old level `level`, texel for texel.
TEST_F(CelBudget, AnAtlasLevelIsTheAtlasWithoutItsFinestMips) {
  auto atlas = core::loadAtlas(sidecar_);
  ASSERT_OK(atlas);
  const core::AtlasDesc& d = atlas->desc;
  const int deepest = core::deepestAtlasLevel(d);
  EXPECT_GE(deepest, 2);
  EXPECT_EQ(d.cellSize % (1 << deepest), 0);
  EXPECT_EQ(d.margin % (1 << deepest), 0);
  auto two = core::atlasFromLevel(*atlas, 2);
  ASSERT_OK(two);
  EXPECT_EQ(two->desc.cellSize, d.cellSize / 4);
  EXPECT_EQ(two->desc.margin, d.margin / 4);
  EXPECT_EQ(two->desc.contentSize, d.contentSize / 4);
  EXPECT_EQ(two->desc.width, d.width / 4);
  EXPECT_FLOAT_EQ(two->desc.distanceRange, d.distanceRange / 4);
  EXPECT_FLOAT_EQ(two->desc.flangeTexels, d.flangeTexels / 4);
  EXPECT_EQ(two->desc.mipLevels, d.mipLevels - 2);
  EXPECT_EQ(two->desc.cells[0].rect[2], d.cells[0].rect[2] / 4);
  for (const auto& [name, levels] : atlas->maps) {
    ASSERT_EQ(two->maps.at(name).size(), levels.size() - 2) << name;
    EXPECT_EQ(two->maps.at(name)[0].pixels, levels[2].pixels) << name;
  }
  EXPECT_LT(core::atlasTextureBytes(two->desc), core::atlasTextureBytes(d) / 15);
  auto tooDeep = core::atlasFromLevel(*atlas, deepest + 1);
  ASSERT_FALSE(tooDeep.ok());
  EXPECT_NE(tooDeep.error().message.find("is not in [0, " + std::to_string(deepest) + "]"), std::string::npos)
      << tooDeep.error().message;

  // The scene's field, read, written and refused past the atlas's depth.
  EXPECT_EQ(scene(2).atlasLevel, 2);
  EXPECT_EQ(scene::toJson(scene(2)).at("atlasLevel"), 2);
  auto r = render::SceneRenderer::create(scene(deepest + 1));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("/atlasLevel: atlas level"), std::string::npos) << r.error().message;
}

// A lumpy art puff (variation 1), so that coarser levels lose what the reference's mesh keeps: a
// sphere's maps are smooth enough that its 16-texel level draws it as well as its 128-texel one
// (their RMSE against the reference differed by 1.5%, either way round).
TEST_F(CelBudget, EveryLevelIsMeasuredAndTheBudgetPicksTheSmallestWithinIt) {
  auto sources =
      bake::loadSources({std::filesystem::path(PUFF_SOURCE_DIR) / "art" / "puffs" / "variation-1.obj"}, std::nullopt);
  ASSERT_OK(sources);
  bake::BakeOptions o;
  o.cellSize = 128;
  o.outDir = dir_ / "lumpy";
  o.contactSheet = false;
  auto lumpy = bake::bakeAtlas(*sources, o);
  ASSERT_OK(lumpy);
  const int frames[] = {0, 1};
  auto b = eval::measureCelBudget(scene(0, lumpy->sidecar), frames, {.timedRenders = 1});
  ASSERT_OK(b);
  ASSERT_GE(b->candidates.size(), 3u);
  EXPECT_EQ(b->frames, (std::vector<int>{0, 1}));
  for (std::size_t i = 0; i + 1 < b->candidates.size(); ++i) {
    EXPECT_EQ(b->candidates[i].atlasLevel, b->candidates[i + 1].atlasLevel + 1) << "deepest (cheapest) first";
    EXPECT_LT(b->candidates[i].atlasBytes, b->candidates[i + 1].atlasBytes);
  }
  EXPECT_EQ(b->candidates.back().atlasLevel, 0);
  for (const eval::CelCandidate& c : b->candidates) {
    ASSERT_EQ(c.rmse.size(), 2u);
    EXPECT_GT(c.worstRmse, 0.0);  // the nailboards are not the meshes
    EXPECT_GE(c.cellSize, 16);
  }
  // The smallest atlas is the farthest from the reference, the full one among the closest.
  const double smallest = b->candidates.front().worstRmse, full = b->candidates.back().worstRmse;
  EXPECT_GT(smallest, full);
  auto all = eval::chooseCelBudget(*b, 1.0);
  ASSERT_TRUE(all.ok());
  EXPECT_TRUE(all->met);
  EXPECT_EQ(all->chosen, 0u);
  auto tiny = eval::chooseCelBudget(*b, 1e-6);
  ASSERT_TRUE(tiny.ok());
  EXPECT_FALSE(tiny->met);
  EXPECT_EQ(tiny->chosen, b->candidates.size() - 1);
  EXPECT_NE(eval::celBudgetWarning(*b, *tiny).find("cannot be met by the nailboards"), std::string::npos);
  EXPECT_NE(eval::celBudgetSummary(*b, *all).find("atlas level " + std::to_string(b->candidates[0].atlasLevel)),
            std::string::npos)
      << eval::celBudgetSummary(*b, *all);
  EXPECT_NE(eval::celBudgetTable(*b, *all).find("<- chosen"), std::string::npos);
  EXPECT_FALSE(eval::chooseCelBudget(*b, 0.0).ok());

  // The references reused (puffrender measures the particle count and then the atlas against the
  // same ones): the same errors, no time spent on references; references of other frames are refused.
  ASSERT_EQ(b->references.size(), 2u);
  auto again = eval::measureCelBudget(scene(0, lumpy->sidecar), frames, {.timedRenders = 1}, eval::CelKnob::kAtlasLevel,
                                      b->references);
  ASSERT_OK(again);
  EXPECT_EQ(again->referenceMs, 0.0);
  for (std::size_t i = 0; i < b->candidates.size(); ++i)
    EXPECT_EQ(again->candidates[i].rmse, b->candidates[i].rmse) << "level " << b->candidates[i].atlasLevel;
  EXPECT_FALSE(eval::measureCelBudget(scene(), std::span(frames).first(1), {.timedRenders = 1},
                                      eval::CelKnob::kAtlasLevel, b->references)
                   .ok());

  // Bad input.
  scene::Scene bare = scene();
  bare.particles.clear();
  EXPECT_FALSE(eval::measureCelBudget(bare, frames).ok());
  const int outside[] = {5};
  EXPECT_FALSE(eval::measureCelBudget(scene(), outside).ok());
}

// The shadows knob: the map at every scale and the volumes, each measured against the reference at
// both frames and ordered by their measured time; a huge budget takes the fastest, a tiny one the
// closest (not the slowest); a scene without shadows is refused, naming /style/shadows.
TEST_F(CelBudget, ShadowsAreMeasuredAndTheFastestWithinTheBudgetIsChosen) {
  const int frames[] = {0, 1};
  scene::Scene s = scene();
  s.style.shadows = true;
  s.light.direction = {0.6f, 0.3f, -0.2f};  // from the side and behind: the puffs shadow each other
  auto b = eval::measureCelBudget(s, frames, {.timedRenders = 1}, eval::CelKnob::kShadows);
  ASSERT_OK(b);
  ASSERT_EQ(b->candidates.size(), eval::kShadowMapScales.size() + 1);
  int volumes = 0;
  std::vector<float> scales;
  for (std::size_t i = 0; i < b->candidates.size(); ++i) {
    const eval::CelCandidate& c = b->candidates[i];
    ASSERT_EQ(c.rmse.size(), 2u);
    EXPECT_GT(c.worstRmse, 0.0);
    if (i > 0) {
      EXPECT_LE(b->candidates[i - 1].medianMs, c.medianMs) << "ordered by measured time";
    }
    if (c.shadowMethod == cel::ShadowMethod::kVolumes) {
      ++volumes;
    } else {
      scales.push_back(c.shadowMapScale);
    }
  }
  EXPECT_EQ(volumes, 1);
  std::sort(scales.begin(), scales.end());
  EXPECT_EQ(scales, std::vector<float>(eval::kShadowMapScales.begin(), eval::kShadowMapScales.end()));
  // The shadows change the image: the candidates do not all measure the same error.
  double lo = 1.0, hi = 0.0;
  for (const eval::CelCandidate& c : b->candidates) {
    lo = std::min(lo, c.worstRmse);
    hi = std::max(hi, c.worstRmse);
  }
  EXPECT_GT(hi, lo);
  auto all = eval::chooseCelBudget(*b, 1.0);
  ASSERT_TRUE(all.ok());
  EXPECT_TRUE(all->met);
  EXPECT_EQ(all->chosen, 0u);
  EXPECT_NE(eval::celBudgetSummary(*b, *all).find("the fastest measured"), std::string::npos)
      << eval::celBudgetSummary(*b, *all);
  auto tiny = eval::chooseCelBudget(*b, 1e-6);
  ASSERT_TRUE(tiny.ok());
  EXPECT_FALSE(tiny->met);
  EXPECT_EQ(b->candidates[tiny->chosen].worstRmse, lo) << "the closest, whatever its time";
  EXPECT_NE(eval::celBudgetTable(*b, *tiny).find("shadow volumes"), std::string::npos);
  EXPECT_NE(eval::celBudgetTable(*b, *tiny).find("shadow map at scale 0.25"), std::string::npos);

  auto none = eval::measureCelBudget(scene(), frames, {.timedRenders = 1}, eval::CelKnob::kShadows);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("/style/shadows"), std::string::npos) << none.error().message;
}

// Fewer, bigger particles: a placed emitter's first round(count * f) particles, each (1/f)^(1/3)
// times larger, so N d^3 (the volume they fill) stays; listed particles are kept as they are.
TEST_F(CelBudget, AParticleFractionKeepsTheFirstParticlesAndTheirVolume) {
  scene::Scene s = scene();
  scene::EmitterSpec e;
  e.count = 40;
  e.seed = 3;
  e.radius = 1.5f;
  s.emitters.push_back(e);
  const std::vector<cel::Particle> all = scene::particlesAt(s, 0, 1);
  ASSERT_EQ(all.size(), 2u + 40u);
  s.particleFraction = 0.25f;
  const std::vector<cel::Particle> quarter = scene::particlesAt(s, 0, 1);
  ASSERT_EQ(quarter.size(), 2u + 10u);
  for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(quarter[i].size, all[i].size) << "listed particles stay";
  double volumeAll = 0.0, volumeQuarter = 0.0;
  for (std::size_t i = 2; i < quarter.size(); ++i) {
    EXPECT_EQ(quarter[i].position, all[i].position) << "the first particles are the same ones";
    EXPECT_NEAR(quarter[i].size, all[i].size * std::cbrt(4.0f), 1e-5f);
  }
  for (std::size_t i = 2; i < all.size(); ++i) volumeAll += std::pow(all[i].size, 3.0);
  for (std::size_t i = 2; i < quarter.size(); ++i) volumeQuarter += std::pow(quarter[i].size, 3.0);
  EXPECT_NEAR(volumeQuarter / volumeAll, 1.0, 0.35);  // the same volume on average (10 of 40 samples)
  EXPECT_FLOAT_EQ(scene::toJson(s).at("particleFraction").get<float>(), 0.25f);
  nlohmann::json bad = scene::toJson(s);
  for (double f : {0.0, 1.5, -0.25}) {
    bad["particleFraction"] = f;
    auto parsed = scene::parseScene(bad, dir_ / "bad.json");
    ASSERT_FALSE(parsed.ok()) << f;
    EXPECT_NE(parsed.error().message.find("/particleFraction: expected a number in (0, 1]"), std::string::npos)
        << parsed.error().message;
  }
}

TEST_F(CelBudget, TheParticleCountIsMeasuredAgainstTheFullModel) {
  scene::Scene s = scene();
  s.particles.clear();
  scene::EmitterSpec e;
  e.count = 48;
  e.seed = 9;
  e.radius = 1.6f;
  e.sizeMin = 0.5f;
  e.sizeMax = 0.9f;
  s.emitters.push_back(e);
  const int frames[] = {0};
  auto b = eval::measureCelBudget(s, frames, {.timedRenders = 1}, eval::CelKnob::kParticleFraction);
  ASSERT_OK(b);
  ASSERT_EQ(b->candidates.size(), eval::kParticleFractions.size());
  EXPECT_EQ(b->candidates[0].particles, 6u);  // 48 / 8
  EXPECT_EQ(b->candidates.back().particles, 48u);
  for (std::size_t i = 0; i + 1 < b->candidates.size(); ++i)
    EXPECT_LT(b->candidates[i].particles, b->candidates[i + 1].particles) << "fewest (cheapest) first";
  // All the particles are closer to the full model than an eighth of them.
  EXPECT_GT(b->candidates.front().worstRmse, b->candidates.back().worstRmse);
  auto c = eval::chooseCelBudget(*b, 1.0);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c->chosen, 0u);
  EXPECT_NE(eval::celBudgetSummary(*b, *c).find("particles 1/8 (6)"), std::string::npos)
      << eval::celBudgetSummary(*b, *c);
  EXPECT_NE(eval::celBudgetTable(*b, *c).find("<- chosen"), std::string::npos);
  // Only placed emitters are thinned: a scene of listed particles has no count to choose.
  auto none = eval::measureCelBudget(scene(), frames, {.timedRenders = 1}, eval::CelKnob::kParticleFraction);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("no particle count to choose"), std::string::npos) << none.error().message;
}

}  // namespace
}  // namespace puff
