// The media budget: choosing a layer resolution, measuring it against the references, puffrender --max-error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/packing.hpp>

#include <puff/core/colour.h>
#include <puff/core/image.h>
#include <puff/eval/budget.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/cli_test.h"
#include "support/gl_fixture.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

const fs::path kExplosion = fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / "explosion-walls.json";
constexpr int kFireFrames[] = {5, 20};  // the fireball (5) and fire turning into soot (20)

eval::MediaBudget syntheticBudget(std::vector<double> worst) {
  eval::MediaBudget b;
  b.frames = {0, 5};
  for (std::size_t i = 0; i < worst.size(); ++i) {
    eval::MediaCandidate c;
    c.resolution = eval::kMediaResolutions[i];
    c.rmse = {worst[i] / 2, worst[i]};
    c.worstRmse = worst[i];
    // Region figures that tell the columns apart in the table.
    c.regions.worstRmseMedia = 2.0 * worst[i];
    c.regions.worstRmseBand = 3.0 * worst[i];
    c.regions.worstSsim = 1.0 - worst[i];
    c.medianMs = 10.0 * static_cast<double>(1 << i);  // 10, 20, 40, 80
    b.candidates.push_back(c);
  }
  return b;
}

// ---- choosing (no GL) -------------------------------------------------------------------------------

TEST(BudgetFrames, FirstMiddleAndLastWithoutRepeats) {
  EXPECT_EQ(eval::budgetFrames(0, 71), (std::vector<int>{0, 36, 71}));
  EXPECT_EQ(eval::budgetFrames(10, 20), (std::vector<int>{10, 15, 20}));
  EXPECT_EQ(eval::budgetFrames(0, 2), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(eval::budgetFrames(3, 4), (std::vector<int>{3, 4}));
  EXPECT_EQ(eval::budgetFrames(7, 7), (std::vector<int>{7}));
}

TEST(BudgetChoice, TheCheapestWithinTheBudgetWithoutAssumingMonotony) {
  const eval::MediaBudget b = syntheticBudget({0.03, 0.02, 0.01, 0.005});
  auto c = eval::chooseMediaResolution(b, 0.015);
  ASSERT_OK(c);
  EXPECT_TRUE(c->met);
  EXPECT_EQ(c->chosen, 2u);
  EXPECT_EQ(eval::budgetSummary(b, *c),
            "--max-error 0.015: media resolution 0.5 (worst RMSE 0.0100 over frames 0, 5; 0.25 misses with 0.0200; "
            "1 would cost 2.0x as much)");
  EXPECT_EQ(eval::budgetWarning(b, *c), "");
  // The bound is inclusive.
  EXPECT_EQ(eval::chooseMediaResolution(b, 0.02)->chosen, 1u);
  // A cheaper candidate that happens to be better than a dearer one is still the cheapest.
  const eval::MediaBudget bumpy = syntheticBudget({0.02, 0.03, 0.01, 0.012});
  EXPECT_EQ(eval::chooseMediaResolution(bumpy, 0.025)->chosen, 0u);
  EXPECT_EQ(eval::chooseMediaResolution(bumpy, 0.011)->chosen, 2u);
  // None qualifies: the dearest, and the best measured in the warning.
  c = eval::chooseMediaResolution(bumpy, 0.001);
  ASSERT_TRUE(c.ok());
  EXPECT_FALSE(c->met);
  EXPECT_EQ(c->chosen, 3u);
  EXPECT_EQ(c->best, 2u);
  EXPECT_EQ(eval::budgetWarning(bumpy, *c),
            "--max-error 0.001 cannot be met: the smallest worst RMSE measured is 0.0100 (media resolution 0.5); "
            "rendering at 1");
  const std::string table = eval::budgetTable(bumpy, *c);
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 5) << table;
  EXPECT_EQ(table.rfind("  resolution  worst RMSE  media RMSE   band RMSE    SSIM  median ms\n", 0), 0u) << table;
  EXPECT_NE(table.find("           1      0.0120      0.0240      0.0360  0.9880       80.0  <- chosen\n"),
            std::string::npos)
      << table;
  // Measured against the physical reference too: its whole-frame RMSE beside the model's.
  eval::MediaBudget physical = bumpy;
  for (eval::MediaCandidate& k : physical.candidates) {
    k.rmsePhysical = {0.05, 0.04};
    k.worstRmsePhysical = 0.05;
  }
  const std::string both = eval::budgetTable(physical, *c);
  EXPECT_EQ(both.rfind("  resolution  worst RMSE  vs physical  media RMSE", 0), 0u) << both;
  EXPECT_NE(both.find("           1      0.0120       0.0500      0.0240"), std::string::npos) << both;
}

TEST(BudgetChoice, BudgetsOutsideZeroToOneAreErrors) {
  const eval::MediaBudget b = syntheticBudget({0.03, 0.02, 0.01, 0.005});
  for (double e : {0.0, -1.0, 2.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    auto c = eval::chooseMediaResolution(b, e);
    ASSERT_FALSE(c.ok()) << e;
    EXPECT_NE(c.error().message.find("(0, 1]"), std::string::npos) << c.error().message;
  }
  EXPECT_TRUE(eval::chooseMediaResolution(b, 1.0).ok());
  EXPECT_FALSE(eval::chooseMediaResolution(eval::MediaBudget{}, 0.5).ok());
}

// ---- measuring (GL) ---------------------------------------------------------------------------------

Result<scene::Scene> smallExplosion() {
  PUFF_TRY_ASSIGN(auto scene, scene::loadScene(kExplosion, PUFF_ART_DIR));
  scene.width = 96;
  scene.height = 72;
  return scene;
}

class BudgetExplosion : public test::GlTest {
 protected:
  // Measured once for the suite: about 7 s on llvmpipe, most of it the references (model and physical).
  void SetUp() override {
    test::GlTest::SetUp();
    if (budget_ || !error_.empty()) return;
    auto scene = smallExplosion();
    ASSERT_OK(scene);
    eval::MediaBudgetOptions options;
    options.timedRenders = 1;
    options.physical = true;  // 96 x 72: about a second more
    auto b = eval::measureMediaBudget(*scene, kFireFrames, options);
    if (!b) {
      error_ = b.error().message;
      return;
    }
    budget_ = std::move(*b);
    for (const eval::MediaCandidate& c : budget_->candidates) {
      std::printf("resolution %5.3f: rmse %.5f (frame 5) %.5f (frame 20), median %.1f ms\n", c.resolution, c.rmse[0],
                  c.rmse[1], c.medianMs);
      std::printf("  worst: physical %.5f, media %.5f / %.5f, band %.5f / %.5f, ssim %.4f / %.4f (model / physical)\n",
                  c.worstRmsePhysical, c.regions.worstRmseMedia, c.regionsPhysical.worstRmseMedia,
                  c.regions.worstRmseBand, c.regionsPhysical.worstRmseBand, c.regions.worstSsim,
                  c.regionsPhysical.worstSsim);
    }
    for (std::size_t k = 0; k < budget_->frames.size() && k < budget_->mediaPixels.size(); ++k) {
      std::printf("frame %d: %zu media pixels (%zu physical), %zu in the clip band\n", budget_->frames[k],
                  budget_->mediaPixels[k], budget_->mediaPixelsPhysical[k], budget_->bandPixels[k]);
    }
  }
  const eval::MediaBudget& budget() {
    EXPECT_TRUE(error_.empty()) << error_;
    return *budget_;
  }
  static void TearDownTestSuite() {
    budget_.reset();
    test::GlTest::TearDownTestSuite();
  }
  static inline std::optional<eval::MediaBudget> budget_;
  static inline std::string error_;
};

TEST_F(BudgetExplosion, EveryResolutionIsMeasuredAtEveryFrame) {
  ASSERT_TRUE(error_.empty()) << error_;
  const eval::MediaBudget& b = budget();
  EXPECT_EQ(b.frames, (std::vector<int>{5, 20}));
  ASSERT_EQ(b.candidates.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    const eval::MediaCandidate& c = b.candidates[i];
    EXPECT_EQ(c.resolution, eval::kMediaResolutions[i]);
    ASSERT_EQ(c.rmse.size(), 2u);
    EXPECT_EQ(c.worstRmse, std::max(c.rmse[0], c.rmse[1]));
    EXPECT_GT(c.medianMs, 0.0);
  }
  EXPECT_GT(b.referenceMs, 0.0);
}

TEST_F(BudgetExplosion, FullResolutionIsClosestToTheReference) {
  ASSERT_TRUE(error_.empty()) << error_;
  const std::vector<eval::MediaCandidate>& c = budget().candidates;
  for (std::size_t i = 0; i + 1 < c.size(); ++i) {
    EXPECT_GT(c[i].worstRmse, c.back().worstRmse) << "resolution " << c[i].resolution;
  }
  // The eighth-size layer misses the fire's detail by far more than the full-size one does.
  EXPECT_GT(c.front().worstRmse, 2.0 * c.back().worstRmse);
  // Apples to apples: at full resolution only the 16-bit layer, the view-axis order and the 8-bit
  // output separate the GPU from the reference (ReferenceGpu measures 6e-4 on its cloud); a wrong
  // opaque layer, row order or frame would show as tenths.
  EXPECT_LT(c.back().worstRmse, 0.01);
}

// The region figures against each reference: filled per frame, finite, in range, the worst
// over the frames, and consistent with the whole-frame RMSE they are part of.
void expectRegions(const eval::RegionErrors& e, double rmseWhole, const std::vector<double>& whole,
                   const std::vector<std::size_t>& mediaPixels, const std::vector<std::size_t>& bandPixels) {
  const std::size_t frames = whole.size();
  ASSERT_EQ(e.rmseMedia.size(), frames);
  ASSERT_EQ(e.rmseBand.size(), frames);
  ASSERT_EQ(e.ssim.size(), frames);
  for (std::size_t k = 0; k < frames; ++k) {
    EXPECT_TRUE(std::isfinite(e.rmseMedia[k]) && std::isfinite(e.rmseBand[k]) && std::isfinite(e.ssim[k]));
    EXPECT_GE(e.rmseMedia[k], 0.0);
    EXPECT_GE(e.rmseBand[k], 0.0);
    EXPECT_GE(e.ssim[k], -1.0);
    EXPECT_LE(e.ssim[k], 1.0);
    // A mask's squared errors are part of the whole frame's: rmse_mask^2 n_mask <= rmse^2 n (RMSE is
    // over the R, G, B values of the counted pixels).
    const double n = 96.0 * 72.0;
    EXPECT_LE(e.rmseMedia[k] * e.rmseMedia[k] * static_cast<double>(mediaPixels[k]),
              whole[k] * whole[k] * n * (1.0 + 1e-9));
    EXPECT_LE(e.rmseBand[k] * e.rmseBand[k] * static_cast<double>(bandPixels[k]),
              whole[k] * whole[k] * n * (1.0 + 1e-9));
  }
  EXPECT_EQ(e.worstRmseMedia, *std::max_element(e.rmseMedia.begin(), e.rmseMedia.end()));
  EXPECT_EQ(e.worstRmseBand, *std::max_element(e.rmseBand.begin(), e.rmseBand.end()));
  EXPECT_EQ(e.worstSsim, *std::min_element(e.ssim.begin(), e.ssim.end()));
  // The fire is where the error is: over its pixels the RMSE is larger than over the whole frame.
  EXPECT_GT(e.worstRmseMedia, rmseWhole);
}

TEST_F(BudgetExplosion, ErrorsWhereTheMethodsDifferAreMeasuredAgainstBothReferences) {
  ASSERT_TRUE(error_.empty()) << error_;
  const eval::MediaBudget& b = budget();
  ASSERT_EQ(b.mediaPixels.size(), 2u);
  ASSERT_EQ(b.mediaPixelsPhysical.size(), 2u);
  ASSERT_EQ(b.bandPixels.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    // The fireball covers part of the frame, and it meets the ground and walls.
    EXPECT_GT(b.mediaPixels[k], 96u * 72u / 20) << "frame " << b.frames[k];
    EXPECT_LT(b.mediaPixels[k], 96u * 72u) << "frame " << b.frames[k];
    EXPECT_GT(b.mediaPixelsPhysical[k], 0u) << "frame " << b.frames[k];
    EXPECT_GT(b.bandPixels[k], 0u) << "frame " << b.frames[k];
    EXPECT_LT(b.bandPixels[k], 96u * 72u) << "frame " << b.frames[k];
  }
  EXPECT_GT(b.physicalMs, 0.0);
  for (const eval::MediaCandidate& c : b.candidates) {
    SCOPED_TRACE(c.resolution);
    expectRegions(c.regions, c.worstRmse, c.rmse, b.mediaPixels, b.bandPixels);
    ASSERT_EQ(c.rmsePhysical.size(), 2u);
    EXPECT_EQ(c.worstRmsePhysical, std::max(c.rmsePhysical[0], c.rmsePhysical[1]));
    expectRegions(c.regionsPhysical, c.worstRmsePhysical, c.rmsePhysical, b.mediaPixelsPhysical, b.bandPixels);
  }
  // At full resolution what is left against the model reference is the GPU's evaluation of the model;
  // against the physical one the model's own error (its per-sphere falloff) adds to it.
  const eval::MediaCandidate& full = b.candidates.back();
  EXPECT_GT(full.worstRmsePhysical, full.worstRmse);
  EXPECT_GT(full.regions.worstSsim, full.regionsPhysical.worstSsim);
  // The eighth-size layer blurs the fire: less similar in structure than the full-size one.
  EXPECT_LT(b.candidates.front().regions.worstSsim, full.regions.worstSsim);
  // The choice reads the whole-frame RMSE against the model reference only.
  eval::MediaBudget swapped = b;
  for (eval::MediaCandidate& c : swapped.candidates) {
    c.regions.worstRmseMedia = c.regions.worstRmseBand = 1.0;
    c.regions.worstSsim = -1.0;
    c.worstRmsePhysical = 1.0;
  }
  for (double e : {1.0, b.candidates[2].worstRmse, 1e-6}) {
    EXPECT_EQ(eval::chooseMediaResolution(swapped, e)->chosen, eval::chooseMediaResolution(b, e)->chosen) << e;
  }
}

TEST_F(BudgetExplosion, WithoutMediaParticlesTheRegionsAreEmptyAndTheImagesAgree) {
  // Closed form: no particle, so no media pixel and no clip band (their RMSE is 0 by definition), and
  // the frame is its opaque layer, which is what the reference composes over: RMSE 0 and SSIM 1 up to
  // the float layer's rounding.
  auto scene = smallExplosion();
  ASSERT_TRUE(scene.ok());
  scene->media->particles.clear();
  scene->media->emitters.clear();
  const int frame[] = {5};
  eval::MediaBudgetOptions options;
  options.timedRenders = 1;
  options.physical = true;
  auto b = eval::measureMediaBudget(*scene, frame, options);
  ASSERT_OK(b);
  EXPECT_EQ(b->mediaPixels, (std::vector<std::size_t>{0}));
  EXPECT_EQ(b->mediaPixelsPhysical, (std::vector<std::size_t>{0}));
  EXPECT_EQ(b->bandPixels, (std::vector<std::size_t>{0}));
  for (const eval::MediaCandidate& c : b->candidates) {
    SCOPED_TRACE(c.resolution);
    for (const eval::RegionErrors* e : {&c.regions, &c.regionsPhysical}) {
      EXPECT_EQ(e->worstRmseMedia, 0.0);
      EXPECT_EQ(e->worstRmseBand, 0.0);
      EXPECT_NEAR(e->worstSsim, 1.0, 1e-9);
    }
    EXPECT_LT(c.worstRmse, 1e-6);
    EXPECT_LT(c.worstRmsePhysical, 1e-6);
  }
}

TEST_F(BudgetExplosion, AHugeBudgetTakesTheCheapest) {
  ASSERT_TRUE(error_.empty()) << error_;
  auto c = eval::chooseMediaResolution(budget(), 1.0);
  ASSERT_TRUE(c.ok());
  EXPECT_TRUE(c->met);
  EXPECT_EQ(c->chosen, 0u);
  const std::string s = eval::budgetSummary(budget(), *c);
  EXPECT_EQ(s.rfind("--max-error 1: media resolution 0.125 (worst RMSE ", 0), 0u) << s;
  EXPECT_NE(s.find("over frames 5, 20; the cheapest; 0.25 would cost "), std::string::npos) << s;
}

TEST_F(BudgetExplosion, ATinyBudgetCannotBeMetAndTakesTheDearest) {
  ASSERT_TRUE(error_.empty()) << error_;
  auto c = eval::chooseMediaResolution(budget(), 1e-6);
  ASSERT_TRUE(c.ok());
  EXPECT_FALSE(c->met);
  EXPECT_EQ(c->chosen, 3u);
  EXPECT_EQ(c->best, 3u);
  EXPECT_NE(eval::budgetWarning(budget(), *c).find("--max-error 1e-06 cannot be met"), std::string::npos);
  EXPECT_NE(eval::budgetSummary(budget(), *c).find("media resolution 1, the dearest"), std::string::npos);
}

TEST_F(BudgetExplosion, ABudgetBetweenTwoMeasuredErrorsTakesTheCheaperThatMeetsIt) {
  ASSERT_TRUE(error_.empty()) << error_;
  const std::vector<eval::MediaCandidate>& c = budget().candidates;
  // Half way between 1/2's worst error and the better of 1/8 and 1/4: only 1/2 and 1 meet it.
  const double cheaper = std::min(c[0].worstRmse, c[1].worstRmse);
  ASSERT_GT(cheaper, c[2].worstRmse) << "1/2 measured no better than a cheaper resolution";
  const double e = 0.5 * (cheaper + c[2].worstRmse);
  auto choice = eval::chooseMediaResolution(budget(), e);
  ASSERT_TRUE(choice.ok());
  EXPECT_TRUE(choice->met);
  EXPECT_EQ(choice->chosen, 2u);
  EXPECT_NE(eval::budgetSummary(budget(), *choice).find("0.25 misses with"), std::string::npos);
  // Just under 1/2's own error: 1.
  EXPECT_EQ(eval::chooseMediaResolution(budget(), c[2].worstRmse * 0.999)->chosen, 3u);
}

TEST_F(BudgetExplosion, TheErrorsAreTheSameEveryTime) {
  ASSERT_TRUE(error_.empty()) << error_;
  auto scene = smallExplosion();
  ASSERT_TRUE(scene.ok());
  const int frame[] = {20};
  auto again = eval::measureMediaBudget(*scene, frame, eval::MediaBudgetOptions{1});
  ASSERT_OK(again);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(again->candidates[i].rmse[0], budget().candidates[i].rmse[1]);
}

TEST_F(BudgetExplosion, TheRendererHandsOutWhatItComposedOver) {
  auto scene = smallExplosion();
  ASSERT_TRUE(scene.ok());
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  EXPECT_FALSE((*renderer)->lastMediaFrame().ok());  // nothing drawn yet
  ASSERT_TRUE((*renderer)->renderFrame(5).ok());
  auto in = (*renderer)->lastMediaFrame();
  ASSERT_OK(in);
  EXPECT_EQ(in->frame.viewport.width, 96);
  EXPECT_EQ(in->frame.viewport.height, 72);
  EXPECT_GT(in->particles.size(), 20u);
  ASSERT_EQ(in->opaqueColor.size(), 96u * 72u);
  ASSERT_EQ(in->opaqueDepth.size(), 96u * 72u);
  // The sky (no surface) and the walls and ground; the colour scene-linear, as half floats hold it.
  EXPECT_EQ(*std::max_element(in->opaqueDepth.begin(), in->opaqueDepth.end()), 1.0f);
  EXPECT_LT(*std::min_element(in->opaqueDepth.begin(), in->opaqueDepth.end()), 0.5f);
  const glm::vec3 c = in->opaqueColor[96 * 36 + 48];
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(glm::unpackHalf1x16(glm::packHalf1x16(c[k])), c[k]);  // exactly a half float
  }
  // The top-left pixel (the last row, GL order) is the sky: the scene's background, decoded.
  const glm::vec3 sky = in->opaqueColor[96 * 71];
  const glm::vec3 background = core::srgbToLinear(scene->background);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(sky[k], background[k], 1e-3f * background[k] + 1e-6f);
}

TEST_F(BudgetExplosion, BadInputIsAnError) {
  auto scene = smallExplosion();
  ASSERT_TRUE(scene.ok());
  const int outside[] = {72};
  auto r = eval::measureMediaBudget(*scene, outside);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("/animation/frames"), std::string::npos) << r.error().message;
  EXPECT_FALSE(eval::measureMediaBudget(*scene, std::span<const int>{}).ok());
  const int one[] = {0};
  EXPECT_FALSE(eval::measureMediaBudget(*scene, one, eval::MediaBudgetOptions{0}).ok());
  scene::Scene bare = *scene;
  bare.media.reset();
  r = eval::measureMediaBudget(bare, one);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("/media"), std::string::npos) << r.error().message;
}

// ---- puffrender --max-error -------------------------------------------------------------------------

class BudgetCli : public test::CliTest {
 protected:
  BudgetCli() : CliTest(PUFFRENDER_EXE, "puffrender") {}
  std::string explosion() const {
    return kExplosion.string() + " --art-dir " + std::string(PUFF_ART_DIR) + " --width 96 --height 72";
  }
};

TEST_F(BudgetCli, SaysWhatItChoseAndWhyAndRendersWithIt) {
  const fs::path out = dir_ / "ex_##.png";
  test::CliRun r = run(explosion() + " --frames 4-6 --max-error 0.05 -o " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("  resolution  worst RMSE  media RMSE   band RMSE    SSIM  median ms\n"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("<- chosen"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("puffrender: --max-error 0.05: media resolution "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" over frames 4, 5, 6"), std::string::npos) << r.err;
  for (int f : {4, 5, 6}) {
    auto image = core::readImage(dir_ / ("ex_0" + std::to_string(f) + ".png"));
    ASSERT_OK(image);
    EXPECT_EQ(image->width, 96);
    EXPECT_EQ(image->height, 72);
  }
  // -q: the one-line summary only; a budget nothing meets: the dearest, said on that line.
  r = run(explosion() + " --frames 5 --max-error 1e-6 -q -o " + (dir_ / "tiny.png").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.rfind("puffrender: --max-error 1e-06: media resolution 1, the dearest (no resolution meets it", 0),
            0u)
      << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "tiny.png"));
  // Without -q the warning has its own line.
  r = run(explosion() + " --frames 5 --max-error 1e-6 -o " + (dir_ / "tiny.png").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("puffrender: warning: --max-error 1e-06 cannot be met"), std::string::npos) << r.err;
}

TEST_F(BudgetCli, NeedsASceneWithMediaOrCelParticles) {
  const fs::path scene = write("ground.json", R"({"output": {"width": 40, "height": 30, "samples": 1},
                                                   "objects": [{"type": "plane"}]})");
  test::CliRun r = run(scene.string() + " --max-error 0.01 -o " + (dir_ / "x.png").string());
  expectOneLineError(r, "--max-error", 2);
  EXPECT_NE(r.err.find("has neither cel particles nor media"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
  expectOneLineError(run(explosion() + " --max-error 0.01 --path fixed -o " + (dir_ / "x.png").string()), "--max-error",
                     2);
}

TEST_F(BudgetCli, BadBudgetsExitTwo) {
  for (const char* e : {"0", "-1", "nan", "2", "inf", "0.01x"}) {
    SCOPED_TRACE(e);
    const test::CliRun r = run(explosion() + " --max-error=" + e + " -o " + (dir_ / "x.png").string());
    expectOneLineError(r, "--max-error", 2);
  }
  expectOneLineError(run(explosion() + " --max-error -1 -o " + (dir_ / "x.png").string()), "got \"-1\"", 2);
  EXPECT_EQ(run(explosion() + " --max-error= -o " + (dir_ / "x.png").string()).exitCode, 2);
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
  const test::CliRun help = run("--help");
  EXPECT_NE(help.out.find("--max-error"), std::string::npos);
  EXPECT_NE(help.out.find("/particleFraction"), std::string::npos);
  EXPECT_NE(help.out.find("mesh detail (baked into the atlas: puffbake --lod auto) are not chosen"), std::string::npos);
}

}  // namespace
}  // namespace puff
