// Curves over a particle's life: keyframed size and density over normalized age, on
// placed emitters, the simulation's emitters and media emitters. Checked against closed forms and
// against the documented default life they replace; read, written and round-tripped; frames stay
// pure functions of the frame number.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include <puff/core/colour.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/geometry.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

namespace puff::scene {
namespace {

using sim::LifeCurve;

LifeCurve curve(std::vector<float> ages, std::vector<float> values, bool smooth = false) {
  LifeCurve c;
  c.ages = std::move(ages);
  c.values = std::move(values);
  c.interp = smooth ? LifeCurve::Interp::kSmooth : LifeCurve::Interp::kLinear;
  return c;
}

TEST(LifeCurve, LinearAndSmoothBetweenKeysHeldOutside) {
  const LifeCurve tent = curve({0.0f, 0.5f, 1.0f}, {0.0f, 1.0f, 0.0f});
  EXPECT_FLOAT_EQ(tent.at(0.25f), 0.5f);
  EXPECT_FLOAT_EQ(tent.at(0.5f), 1.0f);
  EXPECT_FLOAT_EQ(tent.at(0.75f), 0.5f);
  EXPECT_FLOAT_EQ(tent.at(1.0f), 0.0f);
  // Smooth: t -> t^2 (3 - 2t) in each segment; flat at the keys, the same at a segment's middle.
  const LifeCurve smooth = curve({0.0f, 0.5f, 1.0f}, {0.0f, 1.0f, 0.0f}, true);
  EXPECT_FLOAT_EQ(smooth.at(0.25f), 0.5f);
  EXPECT_FLOAT_EQ(smooth.at(0.125f), 0.25f * 0.25f * (3.0f - 0.5f));
  EXPECT_FLOAT_EQ(smooth.at(0.875f), 0.25f * 0.25f * (3.0f - 0.5f));
  // Held before the first key and after the last; one key is a constant.
  const LifeCurve late = curve({0.2f, 0.8f}, {3.0f, 1.0f});
  EXPECT_FLOAT_EQ(late.at(0.0f), 3.0f);
  EXPECT_FLOAT_EQ(late.at(0.1f), 3.0f);
  EXPECT_FLOAT_EQ(late.at(0.9f), 1.0f);
  EXPECT_FLOAT_EQ(late.at(0.5f), 2.0f);
  EXPECT_FLOAT_EQ(curve({0.3f}, {2.0f}).at(0.9f), 2.0f);
  EXPECT_TRUE(LifeCurve{}.empty());
}

TEST(LifeCurve, AColourCurveMixesItsKeysAndIsWhiteWithout) {
  sim::ColourCurve c;
  c.ages = {0.2f, 0.6f};
  c.values = {glm::vec3(1.0f, 0.5f, 0.0f), glm::vec3(0.0f, 0.5f, 1.0f)};
  EXPECT_EQ(c.at(0.0f), c.values[0]) << "held before the first key";
  EXPECT_EQ(c.at(1.0f), c.values[1]) << "held after the last";
  const glm::vec3 mid = c.at(0.3f);  // a quarter of the way
  EXPECT_FLOAT_EQ(mid.r, 0.75f);
  EXPECT_FLOAT_EQ(mid.g, 0.5f);
  EXPECT_FLOAT_EQ(mid.b, 0.25f);
  c.interp = LifeCurve::Interp::kSmooth;
  EXPECT_FLOAT_EQ(c.at(0.3f).r, 1.0f - 0.25f * 0.25f * (3.0f - 0.5f));
  EXPECT_FLOAT_EQ(c.at(0.4f).b, 0.5f) << "the middle of a segment is the same either way";
  EXPECT_EQ(sim::ColourCurve{}.at(0.5f), glm::vec3(1.0f));
}

Scene parsed(const std::string& text) {
  auto s = parseScene(nlohmann::json::parse(text), "curves.json");
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return s.ok() ? *s : Scene{};
}

// A placed emitter of particles that live 2 s, born over 4 s, seen at 3 s; `overLife` is its curves.
std::string placed(const std::string& overLife) {
  return R"({"atlas": "a.json", "emitters": [{"count": 400, "seed": 7, "radius": 2, "birthSpread": 4,
             "lifetime": 2, "sizeMin": 0.5, "sizeMax": 1.5)" +
         (overLife.empty() ? std::string() : ", \"overLife\": " + overLife) + "}]}";
}

TEST(LifeCurves, APlacedEmittersSizeCurveReplacesItsDefaultLife) {
  const float t = 3.0f;
  const int frame = static_cast<int>(t * 24.0f);
  const auto at = [&](const std::string& overLife) { return particlesAt(parsed(placed(overLife)), frame, 1); };
  const auto births = at(R"({"size": {"keys": [[0, 1]]}})");  // constant 1: the birth sizes
  const auto doubled = at(R"({"size": {"keys": [[0, 2]]}})");
  const auto linear = at(R"({"size": {"keys": [[0, 1], [1, 0]]}})");  // 1 - life
  const auto standard = at("");
  ASSERT_GT(births.size(), 100u);
  ASSERT_EQ(doubled.size(), births.size());
  ASSERT_EQ(linear.size(), births.size());
  ASSERT_EQ(standard.size(), births.size()) << "curves change sizes, not who is alive";
  int checked = 0;
  for (std::size_t i = 0; i < births.size(); ++i) {
    EXPECT_EQ(doubled[i].position, births[i].position);
    EXPECT_FLOAT_EQ(doubled[i].size, 2.0f * births[i].size);
    // The default life: the same shrink, and a growth over the first tenth of the life.
    const float life = 1.0f - linear[i].size / births[i].size;
    ASSERT_GE(life, 0.0f);
    ASSERT_LE(life, 1.0f);
    EXPECT_NEAR(standard[i].size, linear[i].size * celBirthGrowth(life), 1e-5f) << i;
    checked += life < kCelBirthGrowth ? 1 : 0;
  }
  EXPECT_GT(checked, 0) << "some particles are young enough to be growing";
}

// A simulated smoke emitter and a media emitter, each with curves given by `cel` and `media`.
std::string simulated(const std::string& cel, const std::string& media) {
  return R"({"atlas": "a.json", "animation": {"fps": 24, "frames": 48},
    "simulation": {"forces": {"buoyancy": 1, "drag": 1},
                   "emitters": [{"rate": 40, "velocity": [0, 1, 0], "lifetime": 1.5, "seed": 5, "sizeMin": 0.4,
                                 "sizeMax": 0.8, "overLife": )" +
         cel + R"(}]},
    "media": {"emitters": [{"material": "fire", "rate": 30, "lifetime": 1, "seed": 2, "density": 2,
                            "overLife": )" +
         media + "}]}}";
}

FrameInputs evaluate(const std::string& text, int frame) {
  const Scene s = parsed(text);
  auto geometry = loadGeometry(s);
  EXPECT_TRUE(geometry.ok());
  auto e = FrameEvaluator::create(s, *geometry, 4);
  EXPECT_TRUE(e.ok()) << (e.ok() ? "" : e.error().message);
  return e.ok() ? (*e)->evaluate(frame) : FrameInputs{};
}

TEST(LifeCurves, SimulatedAndMediaCurvesShapeWhatIsDrawnNotTheSimulation) {
  const FrameInputs ones = evaluate(
      simulated(R"({"size": {"keys": [[0, 1]]}})", R"({"size": {"keys": [[0, 1]]}, "density": {"keys": [[0, 1]]}})"),
      30);
  const FrameInputs threes = evaluate(
      simulated(R"({"size": {"keys": [[0, 3]]}})", R"({"size": {"keys": [[0, 3]]}, "density": {"keys": [[0, 3]]}})"),
      30);
  const FrameInputs linear =
      evaluate(simulated(R"({"size": {"keys": [[0, 1], [1, 0]]}})", R"({"density": {"keys": [[0, 1], [1, 0]]}})"), 30);
  const FrameInputs standard = evaluate(simulated("{}", "{}"), 30);
  ASSERT_GT(ones.simulated, 10u);
  ASSERT_GT(ones.media.size(), 10u);
  for (const FrameInputs* in : {&threes, &linear, &standard}) {
    ASSERT_EQ(in->particles.size(), ones.particles.size()) << "the same simulation";
    ASSERT_EQ(in->media.size(), ones.media.size());
  }
  for (std::size_t i = 0; i < ones.particles.size(); ++i) {
    EXPECT_EQ(threes.particles[i].position, ones.particles[i].position) << "curves do not move particles";
    EXPECT_FLOAT_EQ(threes.particles[i].size, 3.0f * ones.particles[i].size);
    const float life = 1.0f - linear.particles[i].size / ones.particles[i].size;
    EXPECT_NEAR(standard.particles[i].size, linear.particles[i].size * celBirthGrowth(life), 1e-5f) << i;
  }
  for (std::size_t i = 0; i < ones.media.size(); ++i) {
    const media::Particle &one = ones.media[i], &three = threes.media[i];
    EXPECT_EQ(three.position, one.position);
    EXPECT_FLOAT_EQ(three.radius, 3.0f * one.radius);
    EXPECT_FLOAT_EQ(one.density, 2.0f) << "the emitter's density times 1";
    EXPECT_FLOAT_EQ(three.density, 6.0f);
    // The media's default life: growth 0 keeps the birth radius; the density fades in and falls
    // linearly, the linear curve without the fade in.
    EXPECT_FLOAT_EQ(standard.media[i].radius, one.radius);
    EXPECT_NEAR(linear.media[i].density, 2.0f * (1.0f - one.life), 1e-5f);
    EXPECT_NEAR(standard.media[i].density, linear.media[i].density * mediaBirthFade(one.life), 1e-5f) << i;
  }
}

// Colour tints what is drawn: the cel puffs' tint is the curve's display value at their age; the
// media's is that value decoded (they light in linear), and a temperature curve gives each fire
// particle its own T0 at its age. Neither moves a particle or changes its size.
TEST(LifeCurves, ColourAndTemperatureCurvesTintAndHeatWhatIsDrawn) {
  const std::string colour = R"("color": {"keys": [[0, [1, 0.5, 0.25]], [1, "#3399ff"]]})";
  const std::string smooth = R"("color": {"keys": [[0, [1, 0.5, 0.25]], [1, "#3399ff"]], "interp": "smooth"})";
  const std::string heat = R"("temperature": {"keys": [[0, 3000], [0.5, 1800], [1, 900]]})";
  // The same simulation with linear size curves, whose sizes tell each cel puff's age.
  const FrameInputs ages = evaluate(simulated(R"({"size": {"keys": [[0, 1], [1, 0]]}})", "{}"), 30);
  const FrameInputs ones = evaluate(simulated(R"({"size": {"keys": [[0, 1]]}})", "{}"), 30);
  const FrameInputs tinted = evaluate(
      simulated("{" + colour + R"(, "size": {"keys": [[0, 1], [1, 0]]}})", "{" + colour + ", " + heat + "}"), 30);
  const FrameInputs smoothed = evaluate(simulated("{" + smooth + "}", "{" + smooth + "}"), 30);
  const FrameInputs plain = evaluate(simulated("{}", "{}"), 30);
  ASSERT_GT(ages.simulated, 10u);
  ASSERT_EQ(tinted.particles.size(), ages.particles.size());
  ASSERT_EQ(ones.particles.size(), ages.particles.size());
  ASSERT_EQ(plain.particles.size(), ages.particles.size());
  const glm::vec3 birth(1.0f, 0.5f, 0.25f), death(0x33 / 255.0f, 0x99 / 255.0f, 1.0f);
  int young = 0, old = 0;
  for (std::size_t i = 0; i < ages.particles.size(); ++i) {
    const float life = 1.0f - ages.particles[i].size / ones.particles[i].size;
    const glm::vec3 want = birth + (death - birth) * life;
    // The curve's display value, decoded: a cel particle's tint is scene-linear.
    const glm::vec3 wantLinear = core::srgbToLinear(want);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(tinted.particles[i].tint[c], wantLinear[c], 1e-5f) << i << " channel " << c;
    EXPECT_EQ(tinted.particles[i].position, ages.particles[i].position);
    EXPECT_EQ(tinted.particles[i].size, ages.particles[i].size) << "colour does not change sizes";
    EXPECT_EQ(plain.particles[i].tint, glm::vec3(1.0f)) << "no curve: untinted";
    const float s = life * life * (3.0f - 2.0f * life);
    const glm::vec3 wantSmooth = core::srgbToLinear(birth + (death - birth) * s);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(smoothed.particles[i].tint[c], wantSmooth[c], 1e-5f);
    young += life < 0.3f ? 1 : 0;
    old += life > 0.6f ? 1 : 0;
  }
  EXPECT_GT(young, 0);
  EXPECT_GT(old, 0);
  ASSERT_GT(tinted.media.size(), 10u);
  ASSERT_EQ(plain.media.size(), tinted.media.size());
  for (std::size_t i = 0; i < tinted.media.size(); ++i) {
    const media::Particle &p = tinted.media[i], &q = plain.media[i];
    const glm::vec3 want = core::srgbToLinear(birth + (death - birth) * p.life);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p.tint[c], want[c], 1e-5f) << i << " channel " << c;
    const float kelvin = p.life < 0.5f ? 3000.0f - 1200.0f * p.life / 0.5f : 1800.0f - 900.0f * (p.life - 0.5f) / 0.5f;
    EXPECT_NEAR(p.temperature, kelvin, 0.05f) << "life " << p.life;
    EXPECT_EQ(p.position, q.position);
    EXPECT_EQ(p.radius, q.radius);
    EXPECT_EQ(p.density, q.density);
    EXPECT_EQ(q.tint, glm::vec3(1.0f));
    EXPECT_EQ(q.temperature, 0.0f) << "no curve: the material's temperature";
  }
}

TEST(LifeCurves, FramesWithCurvesArePureFunctionsOfTheFrameNumber) {
  const std::string text = simulated(
      R"({"size": {"keys": [[0, 0.2], [0.3, 1], [1, 0.5]], "interp": "smooth"}, "color": {"keys": [[0, "#ff0000"], [1, "#0000ff"]]}})",
      R"({"density": {"keys": [[0, 0], [0.2, 1], [1, 0]], "interp": "smooth"}, "temperature": {"keys": [[0, 3000], [1, 1000]]}})");
  const Scene s = parsed(text);
  auto geometry = loadGeometry(s);
  ASSERT_TRUE(geometry.ok());
  auto sequence = FrameEvaluator::create(s, *geometry, 4);
  auto alone = FrameEvaluator::create(s, *geometry, 4);
  ASSERT_TRUE(sequence.ok() && alone.ok());
  FrameInputs last;
  for (int f = 0; f <= 20; ++f) last = (*sequence)->evaluate(f);
  const FrameInputs one = (*alone)->evaluate(20);
  ASSERT_EQ(one.particles.size(), last.particles.size());
  for (std::size_t i = 0; i < one.particles.size(); ++i) {
    EXPECT_EQ(one.particles[i].size, last.particles[i].size);
    EXPECT_EQ(one.particles[i].tint, last.particles[i].tint);
  }
  ASSERT_EQ(one.media.size(), last.media.size());
  for (std::size_t i = 0; i < one.media.size(); ++i) {
    EXPECT_EQ(one.media[i].density, last.media[i].density);
    EXPECT_EQ(one.media[i].tint, last.media[i].tint);
    EXPECT_EQ(one.media[i].temperature, last.media[i].temperature);
  }
}

TEST(LifeCurves, AreWrittenAndReadBackAndBadOnesNameTheField) {
  const Scene s = parsed(simulated(
      R"({"size": {"keys": [[0, 0.2], [0.3, 1], [1, 0.5]], "interp": "smooth"}, "color": {"keys": [[0.5, "#80ff00"]]}})",
      R"({"density": {"keys": [[0.1, 2]]}, "color": {"keys": [[0, [1, 0.9, 0.2]], [1, [0.1, 0.1, 0.1]]], "interp": "smooth"},
          "temperature": {"keys": [[0, 2800], [1, 1100]]}})"));
  Scene withPlaced = s;
  withPlaced.emitters =
      parsed(placed(R"({"size": {"keys": [[0, 1], [1, 0.25]]}, "color": {"keys": [[0, [0, 0, 0]], [1, [1, 1, 1]]]}})"))
          .emitters;
  ASSERT_EQ(withPlaced.media->emitters[0].emitter.overLife.temperature.values, (std::vector<float>{2800.0f, 1100.0f}));
  ASSERT_EQ(withPlaced.simulation->emitters[0].overLife.color.values[0], glm::vec3(128 / 255.0f, 1.0f, 0.0f));
  ASSERT_EQ(withPlaced.emitters[0].overLife.color.values.size(), 2u);
  const nlohmann::json j = toJson(withPlaced);
  auto back = parseScene(j, "curves.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->simulation->emitters[0].overLife, withPlaced.simulation->emitters[0].overLife);
  EXPECT_EQ(back->media->emitters[0].emitter.overLife, withPlaced.media->emitters[0].emitter.overLife);
  EXPECT_EQ(back->emitters[0].overLife, withPlaced.emitters[0].overLife);
  EXPECT_EQ(back->simulation->emitters[0].overLife.size.interp, LifeCurve::Interp::kSmooth);
  EXPECT_EQ(back->emitters[0].overLife.size.values, (std::vector<float>{1.0f, 0.25f}));
  // No curves: written as {}, read as none.
  EXPECT_EQ(toJson(parsed(placed("")))["emitters"][0]["overLife"], nlohmann::json::object());

  const auto error = [](const std::string& text) {
    auto r = parseScene(nlohmann::json::parse(text), "curves.json");
    return r.ok() ? std::string("(read)") : r.error().message;
  };
  EXPECT_NE(error(placed(R"({"size": {"keys": [[0, 1], [0, 2]]}})"))
                .find("/emitters/0/overLife/size/keys/1/0: expected an age after the previous key's (0)"),
            std::string::npos);
  EXPECT_NE(
      error(placed(R"({"size": {"keys": [[1.5, 1]]}})")).find("/overLife/size/keys/0/0: expected an age in [0, 1]"),
      std::string::npos);
  EXPECT_NE(error(placed(R"({"size": {"keys": [[0, -1]]}})")).find("/overLife/size/keys/0/1"), std::string::npos);
  EXPECT_NE(error(placed(R"({"size": {"keys": []}})")).find("/overLife/size/keys: expected 1 to 64 keys"),
            std::string::npos);
  EXPECT_NE(error(placed(R"({"size": {"keys": [[0, 1]], "interp": "cubic"}})")).find("/overLife/size/interp"),
            std::string::npos);
  EXPECT_NE(error(placed(R"({"size": {"keys": [0, 1]}})")).find("/overLife/size/keys/0: expected a key [age, value]"),
            std::string::npos);
  // Nailboards draw no density; placed particles that live forever have no life to shape.
  EXPECT_NE(error(placed(R"({"density": {"keys": [[0, 1]]}})")).find("/emitters/0/overLife"), std::string::npos);
  // Colours are colours; cel puffs have no temperature; media that do not emit have none to shape.
  EXPECT_NE(error(placed(R"({"color": {"keys": [[0, [2, 0, 0]]]}})")).find("/emitters/0/overLife/color/keys/0/1"),
            std::string::npos);
  EXPECT_NE(error(placed(R"({"color": {"keys": [[0, 1]]}})")).find("/overLife/color/keys/0/1"), std::string::npos);
  EXPECT_NE(error(placed(R"({"temperature": {"keys": [[0, 2000]]}})"))
                .find("/emitters/0/overLife/temperature: cel puffs have no temperature"),
            std::string::npos);
  EXPECT_NE(error(simulated(R"({"temperature": {"keys": [[0, 2000]]}})", "{}"))
                .find("/simulation/emitters/0/overLife/temperature: cel puffs have no temperature"),
            std::string::npos);
  std::string smoke = simulated("{}", R"({"temperature": {"keys": [[0, 2000]]}})");
  smoke.replace(smoke.find("\"fire\""), 6, "\"smoke\"");
  EXPECT_NE(error(smoke).find("/media/emitters/0/overLife/temperature: material \"smoke\" does not emit"),
            std::string::npos)
      << error(smoke);
  EXPECT_NE(error(simulated("{}", R"({"temperature": {"keys": [[0, 0]]}})")).find("/overLife/temperature/keys/0/1"),
            std::string::npos);
  std::string forever = placed(R"({"size": {"keys": [[0, 1]]}})");
  forever.replace(forever.find("\"lifetime\": 2"), 13, "\"lifetime\": 0");
  EXPECT_NE(error(forever).find("curves over life need a \"lifetime\" > 0"), std::string::npos) << error(forever);
}

}  // namespace
}  // namespace puff::scene
