// Popping measured live, on the cel path: art/scenes/lamp-plume.json's smoke simulated
// frame by frame while puffs are born and die, as scene::FrameEvaluator hands the puffs to the
// renderers. Each drawn puff is matched to the simulator's particle at the same position (the same
// deterministic simulation run beside it), which gives its id, age and birth size, so a puff's
// drawn size can be followed from the frame it first appears to the frame it dies. (An image metric
// cannot see this on the cel path: the ink edges of moving puffs already give pixel second
// differences near 2 at any resolution.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>

#include <puff/scene/evaluate.h>
#include <puff/scene/geometry.h>
#include <puff/scene/read.h>
#include <puff/sim/simulator.h>

#include "support/assert_ok.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

TEST(CelBirthGrowth, IsASmoothstepOverTheFirstTenthOfTheLife) {
  EXPECT_EQ(scene::celBirthGrowth(0.0f), 0.0f);
  EXPECT_FLOAT_EQ(scene::celBirthGrowth(0.05f), 0.5f);
  EXPECT_EQ(scene::celBirthGrowth(0.1f), 1.0f);
  EXPECT_EQ(scene::celBirthGrowth(0.7f), 1.0f);
  // C1 at both ends: the slope vanishes at birth and where the growth ends (mid slope 15).
  const float h = 1e-4f;
  EXPECT_LT(scene::celBirthGrowth(h) / h, 0.05f);
  EXPECT_LT((1.0f - scene::celBirthGrowth(0.1f - h)) / h, 0.05f);
}

// Without the growth every newborn puff appears at its full birth size in one frame (first drawn
// size / birth size = 1 - age / lifetime, about 0.99). With it the first drawn size is at most the
// smoothstep one frame into the growth (lamp-plume's puffs live 2.5 s: the growth spans 6 frames at
// 24 fps, smoothstep(1/6) = 0.074), and no frame-to-frame step of a puff exceeds the smoothstep's
// largest step over those frames (0.26 of its birth size) plus the shrink.
TEST(CelPopping, PuffsGrowInInsteadOfAppearingAtFullSize) {
  auto scene = scene::loadScene(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / "lamp-plume.json", PUFF_ART_DIR);
  ASSERT_OK(scene);
  ASSERT_TRUE(scene->simulation.has_value());
  auto geometry = scene::loadGeometry(*scene);
  ASSERT_OK(geometry);
  auto evaluator = scene::FrameEvaluator::create(*scene, *geometry, 1, scene::MediaEvaluation::kSkip);
  ASSERT_OK(evaluator);
  auto settings = scene::simulationSettings(*scene, *geometry);
  ASSERT_OK(settings);
  ASSERT_TRUE(settings->has_value());
  auto sim = sim::Simulator::create(std::move(**settings), 1);
  ASSERT_OK(sim);

  struct Track {
    int firstFrame = -1;
    float birthSize = 0.0f, lastRelative = 0.0f;
  };
  std::map<std::uint32_t, Track> tracks;
  float firstRelative = 0.0f, largestStep = 0.0f;
  std::size_t births = 0, deaths = 0, livePrevious = 0;
  const int last = std::min(72, scene->animation.frames - 1);
  for (int f = 0; f <= last; ++f) {
    const scene::FrameInputs in = (*evaluator)->evaluate(f);
    (*sim)->advanceToFrame(f);
    std::map<std::uint32_t, float> drawn;
    for (const cel::Particle& p : in.particles) {
      for (std::size_t i = 0; i < (*sim)->size(); ++i) {
        const sim::ParticleState s = (*sim)->particle(i);
        if (s.position != p.position) continue;
        const float birth = s.size / std::max(1e-6f, 1.0f - s.age / s.lifetime);
        drawn[s.id] = p.size / birth;
        Track& t = tracks[s.id];
        if (t.firstFrame < 0) {
          t.firstFrame = f, t.birthSize = birth;
          if (f > 0) ++births, firstRelative = std::max(firstRelative, p.size / birth);
        } else {
          largestStep = std::max(largestStep, std::abs(p.size / birth - t.lastRelative));
        }
        t.lastRelative = p.size / birth;
        break;
      }
    }
    if (f > 0 && drawn.size() < livePrevious) deaths += livePrevious - drawn.size();
    livePrevious = drawn.size();
  }
  std::printf("cel births %zu, deaths %zu: first drawn size <= %.3f of the birth size; largest step %.3f\n", births,
              deaths, firstRelative, largestStep);
  EXPECT_GT(births, 50u) << "a live plume";
  EXPECT_LT(firstRelative, 0.2f);
  EXPECT_LT(largestStep, 0.35f);
}

}  // namespace
}  // namespace puff
