// The media's functions that draw nothing: the phase functions, the back-to-front sort, material validation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/media/media.h>

#include "support/media_target.h"

namespace puff {
namespace {

using test::sphereAt;
TEST(MediaPhase, BothModelsIntegrateToOne) {
  for (media::PhaseModel model : {media::PhaseModel::kHenyeyGreenstein, media::PhaseModel::kCornetteShanks}) {
    for (double g : {-0.5, 0.0, 0.3, 0.8}) {
      double sum = 0.0;
      const int n = 20000;
      for (int i = 0; i < n; ++i) {  // midpoint rule over cos in [-1, 1], times 2 pi
        const double c = -1.0 + (i + 0.5) * 2.0 / n;
        sum += media::phase(model, c, g) * 2.0 / n * 2.0 * std::numbers::pi;
      }
      EXPECT_NEAR(sum, 1.0, 1e-4) << media::toString(model) << " g " << g;
    }
  }
  EXPECT_NEAR(media::phase(media::PhaseModel::kHenyeyGreenstein, 0.3, 0.0), 1.0 / (4.0 * std::numbers::pi), 1e-12);
  // The paper's form is Rayleigh-shaped at g = 0: not isotropic.
  EXPECT_NEAR(media::phase(media::PhaseModel::kCornetteShanks, 1.0, 0.0), 3.0 / (8.0 * std::numbers::pi), 1e-12);
  EXPECT_NEAR(media::phase(media::PhaseModel::kCornetteShanks, 0.0, 0.0), 3.0 / (16.0 * std::numbers::pi), 1e-12);
}

// Forward and back, where g matters: c = cos of the angle between the light's travel and the
// scattered direction, so g > 0 scatters forward (c = 1). Values worked by hand from the printed
// formulas, at g = 0.5: Henyey-Greenstein (1 - g^2) / (4 pi (1 + g^2 -+ 2g)^1.5) = 0.75 / (4 pi
// 0.125) forward, 0.75 / (4 pi 3.375) back; Cornette-Shanks 3/2 (1 - g^2)/(2 + g^2) (1 + c^2) /
// (1 + g^2 -+ 2g)^1.5 / (4 pi) = 8 / (4 pi) forward, 8 / 27 / (4 pi) back. (Integrating to one and
// the g = 0 values cannot see the angle reversed.)
TEST(MediaPhase, ForwardScatteringIsWhereGPoints) {
  const double fourPi = 4.0 * std::numbers::pi;
  EXPECT_NEAR(media::phase(media::PhaseModel::kHenyeyGreenstein, 1.0, 0.5), 6.0 / fourPi, 1e-12);
  EXPECT_NEAR(media::phase(media::PhaseModel::kHenyeyGreenstein, -1.0, 0.5), (0.75 / 3.375) / fourPi, 1e-12);
  EXPECT_NEAR(media::phase(media::PhaseModel::kCornetteShanks, 1.0, 0.5), 8.0 / fourPi, 1e-12);
  EXPECT_NEAR(media::phase(media::PhaseModel::kCornetteShanks, -1.0, 0.5), (8.0 / 27.0) / fourPi, 1e-12);
  // g < 0 mirrors it.
  EXPECT_NEAR(media::phase(media::PhaseModel::kHenyeyGreenstein, -1.0, -0.5), 6.0 / fourPi, 1e-12);
}

TEST(MediaSort, BackToFrontIsStableAndFarthestFirst) {
  std::vector<media::Particle> ps;
  const float zs[] = {-3, -10, -3, 2, -7.5f, -0.0f, -10};
  for (float z : zs) ps.push_back(sphereAt({1, 2, z}, 1));
  const glm::mat4 view(1.0f);
  const auto order = media::backToFront(view, ps);
  const std::vector<std::uint32_t> expected = {1, 6, 4, 0, 2, 5, 3};
  EXPECT_EQ(order, expected);
  // A large shuffled set comes out monotone.
  std::vector<media::Particle> many;
  for (int i = 0; i < 50000; ++i)
    many.push_back(sphereAt({0, 0, -std::fmod(static_cast<float>(i) * 7.31f, 100.0f) + 1.0f}, 1));
  const glm::mat4 turned = glm::lookAt(glm::vec3(3, 4, 5), glm::vec3(0), glm::vec3(0, 1, 0));
  const auto o = media::backToFront(turned, many);
  ASSERT_EQ(o.size(), many.size());
  for (std::size_t i = 1; i < o.size(); ++i)
    ASSERT_LE((turned * glm::vec4(many[o[i - 1]].position, 1)).z, (turned * glm::vec4(many[o[i]].position, 1)).z);
}

TEST(MediaMaterial, ValidationNamesTheField) {
  media::Material m = media::smokeMaterial();
  m.albedo = 1.5f;
  auto r = media::validate(m, 1);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "smoke: albedo: expected a number in [0, 1], got 1.5");
  m = media::fireMaterial();
  m.becomes = 3;
  EXPECT_NE(media::validate(m, 2).error().message.find("becomes"), std::string::npos);
  m.becomes = -1;
  m.transitionStart = 0.9f;
  m.transitionEnd = 0.2f;
  EXPECT_NE(media::validate(m, 2).error().message.find("transitionEnd"), std::string::npos);
}

}  // namespace
}  // namespace puff
