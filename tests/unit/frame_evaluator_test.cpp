// puff::scene needs no GL: its headers (and the plain value types of cel and media they speak)
// include no GL header, and a scene's frames are evaluated with no context at all. The
// FrameEvaluator's frames are pure functions of the frame number, and its reload rule rebuilds only
// for what placed or simulated the particles.
#include <puff/scene/evaluate.h>
#include <puff/scene/geometry.h>
#include <puff/scene/read.h>
#include <puff/scene/scene.h>
#include <puff/scene/write.h>

#if defined(PUFF_GLAD_GL_H_) || defined(GLAD_GL_H_) || defined(__gl_h_) || defined(__glad_h_)
#error "a puff::scene header includes GL: the scene must be usable without a context"
#endif

#include <gtest/gtest.h>

#include <algorithm>

namespace puff::scene {
namespace {

// Listed particles, a placed emitter, a simulation with an emitter and a collider, and media
// emitted by the simulator: every source of particles a frame has.
constexpr const char* kScene = R"({
  "atlas": "a.json",
  "particles": [{"position": [0, 1, 0], "size": 0.5}],
  "emitters": [{"count": 20, "seed": 3, "radius": 2}],
  "objects": [{"type": "plane", "scale": [10, 1, 10]}, {"type": "sphere", "translate": [0, 0.5, 0]}],
  "animation": {"fps": 24, "frames": 48, "orbit": 10},
  "simulation": {"forces": {"buoyancy": 1, "drag": 1},
                 "emitters": [{"rate": 40, "velocity": [0, 1, 0], "lifetime": 1.5, "seed": 5}]},
  "media": {"emitters": [{"material": "fire", "rate": 30, "lifetime": 1, "seed": 2}],
            "particles": [{"position": [1, 1, 1], "radius": 0.5, "material": "smoke"}]}
})";

Scene parsed(const char* text = kScene) {
  auto s = parseScene(nlohmann::json::parse(text), "evaluator.json");
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return s.ok() ? *s : Scene{};
}

std::unique_ptr<FrameEvaluator> evaluator(const Scene& s, int variations = 4,
                                          MediaEvaluation media = MediaEvaluation::kEvaluate) {
  auto geometry = loadGeometry(s);
  EXPECT_TRUE(geometry.ok());
  auto e = FrameEvaluator::create(s, *geometry, variations, media);
  EXPECT_TRUE(e.ok()) << (e.ok() ? "" : e.error().message);
  return e.ok() ? std::move(*e) : nullptr;
}

void expectSameParticles(const FrameInputs& a, const FrameInputs& b) {
  ASSERT_EQ(a.particles.size(), b.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    EXPECT_EQ(a.particles[i].position, b.particles[i].position) << i;
    EXPECT_EQ(a.particles[i].size, b.particles[i].size) << i;
    EXPECT_EQ(a.particles[i].variation, b.particles[i].variation) << i;
  }
  ASSERT_EQ(a.media.size(), b.media.size());
  for (std::size_t i = 0; i < a.media.size(); ++i) {
    EXPECT_EQ(a.media[i].position, b.media[i].position) << i;
    EXPECT_EQ(a.media[i].radius, b.media[i].radius) << i;
    EXPECT_EQ(a.media[i].seed, b.media[i].seed) << i;
  }
}

TEST(FrameEvaluator, EvaluatesEverySourceOfParticlesWithoutAContext) {
  const Scene s = parsed();
  auto e = evaluator(s);
  ASSERT_TRUE(e);
  const FrameInputs in = e->evaluate(24);
  EXPECT_EQ(in.frame, 24);
  EXPECT_EQ(in.time, frameTime(s, 24));
  EXPECT_EQ(in.time, 1.0f);
  const cel::Camera expected = cameraAt(s, 24);
  EXPECT_EQ(in.camera.position, expected.position) << "the orbit turns the camera";
  const std::vector<cel::Particle> placed = particlesAt(s, 24, 4);
  EXPECT_EQ(placed.size(), 21u) << "the listed particle and the emitter's 20";
  ASSERT_GT(in.simulated, 0u) << "a second of emission at 40 per second";
  EXPECT_EQ(in.particles.size(), placed.size() + in.simulated);
  for (std::size_t i = 0; i < placed.size(); ++i) EXPECT_EQ(in.particles[i].position, placed[i].position);
  ASSERT_GT(in.media.size(), 1u) << "the listed smoke and the simulated fire";
  EXPECT_EQ(in.media[0].position, glm::vec3(1, 1, 1));
  EXPECT_EQ(in.media[0].radius, 0.5f);
  EXPECT_EQ(in.media[0].material, static_cast<std::uint32_t>(s.media->particles[0].materialIndex));
}

TEST(FrameEvaluator, WithoutAnAtlasOrMediaItEvaluatesNeither) {
  const Scene s = parsed();
  auto e = evaluator(s, /*variations=*/0, MediaEvaluation::kSkip);
  ASSERT_TRUE(e);
  const FrameInputs in = e->evaluate(24);
  EXPECT_TRUE(in.particles.empty());
  EXPECT_EQ(in.simulated, 0u);
  EXPECT_TRUE(in.media.empty());
}

TEST(FrameEvaluator, AFrameAloneEqualsTheSameFrameOfASequenceAndOfARewind) {
  const Scene s = parsed();
  auto sequence = evaluator(s), alone = evaluator(s);
  ASSERT_TRUE(sequence && alone);
  FrameInputs last;
  for (int f = 0; f <= 30; ++f) last = sequence->evaluate(f);
  expectSameParticles(alone->evaluate(30), last);
  const FrameInputs early = alone->evaluate(5);  // back in time: the simulators start again
  FrameInputs fresh = evaluator(s)->evaluate(5);
  expectSameParticles(early, fresh);
}

// The simulators step on any number of threads and the frames do not change: 20,000
// simulated smoke puffs and 12,000 fire particles (enough for every thread to get blocks), with
// colliders, at frames 6, 24 and 40, on 1, 2, 3 and 8 threads.
TEST(FrameEvaluator, FramesAreTheSameOnAnyNumberOfThreads) {
  const Scene s = parsed(R"({
    "atlas": "a.json",
    "objects": [{"type": "plane", "scale": [10, 1, 10]}, {"type": "sphere", "translate": [0, 1.5, 0]}],
    "animation": {"fps": 24, "frames": 48},
    "simulation": {"forces": {"buoyancy": 1, "drag": 1, "turbulence": {"strength": 0.5, "scale": 1}, "wind": [0.3, 0, 0],
                              "vortices": [{"position": [0, 2, 0], "axis": [0, 1, 0], "strength": 2, "radius": 1}]},
                   "emitters": [{"rate": 40000, "velocity": [0, 1, 0], "lifetime": 3, "duration": 0.5, "seed": 5}]},
    "media": {"emitters": [{"material": "fire", "rate": 24000, "lifetime": 2, "duration": 0.5, "seed": 2}]}
  })");
  auto geometry = loadGeometry(s);
  ASSERT_TRUE(geometry.ok());
  std::vector<std::unique_ptr<FrameEvaluator>> evaluators;
  for (int threads : {1, 2, 3, 8}) {
    auto e = FrameEvaluator::create(s, *geometry, 4, MediaEvaluation::kEvaluate, threads);
    ASSERT_TRUE(e.ok()) << e.error().message;
    evaluators.push_back(std::move(*e));
  }
  for (int frame : {6, 24, 40}) {
    const FrameInputs one = evaluators[0]->evaluate(frame);
    // 40,000 and 24,000 a second for half a second, living 3 and 2 seconds.
    EXPECT_EQ(one.particles.size(), static_cast<std::size_t>(std::min(frame, 12) * 40000 / 24)) << frame;
    EXPECT_EQ(one.media.size(), static_cast<std::size_t>(std::min(frame, 12) * 24000 / 24)) << frame;
    for (std::size_t k = 1; k < evaluators.size(); ++k) expectSameParticles(one, evaluators[k]->evaluate(frame));
  }
}

TEST(FrameEvaluator, TheCameraCanBeReplaced) {
  const Scene s = parsed();
  auto e = evaluator(s);
  ASSERT_TRUE(e);
  cel::Camera mine;
  mine.position = glm::vec3(7, 8, 9);
  EXPECT_EQ(e->evaluate(3, &mine).camera.position, glm::vec3(7, 8, 9));
}

TEST(FrameEvaluator, ReloadRuleRebuildsOnlyForWhatPlacesOrSimulatesParticles) {
  const Scene s = parsed();
  auto e = evaluator(s);
  ASSERT_TRUE(e);
  Scene looks = s;
  looks.style.outlineWidth = 5.0f;
  looks.camera.fovYDegrees = 30.0f;
  looks.light.color = glm::vec3(0.5f);
  looks.simulation->forces.buoyancy = 3.0f;
  looks.media->forces.drag = 4.0f;
  looks.particleFraction = 0.5f;
  // Curves over life shape what is drawn, read each frame: not a reason to simulate again.
  looks.simulation->emitters[0].overLife.size.ages = {0.0f, 1.0f};
  looks.simulation->emitters[0].overLife.size.values = {1.0f, 0.5f};
  looks.media->emitters[0].emitter.overLife.density.ages = {0.0f};
  looks.media->emitters[0].emitter.overLife.density.values = {2.0f};
  EXPECT_FALSE(e->needsRebuild(looks))
      << "looks, camera, forces, curves over life and the placed share are read per frame";
  for (auto edit : std::initializer_list<void (*)(Scene&)>{
           [](Scene& x) { x.emitters[0].count = 21; },
           [](Scene& x) { x.particles[0].size = 1.0f; },
           [](Scene& x) { x.objects[1].translate.x = 1.0f; },
           [](Scene& x) { x.animation.fps = 30.0f; },
           [](Scene& x) { x.simulation->emitters[0].rate = 41.0f; },
           [](Scene& x) { x.media->emitters[0].growth = 2.0f; },
           [](Scene& x) { x.media->substeps = 3; },
       }) {
    Scene edited = s;
    edit(edited);
    EXPECT_TRUE(e->needsRebuild(edited));
  }
}

TEST(FrameEvaluator, NewForcesSimulateFromTheStartAsASavedSceneWould) {
  const Scene s = parsed();
  Scene windy = s;
  windy.simulation->forces.wind = glm::vec3(3, 0, 0);
  auto edited = evaluator(s);
  ASSERT_TRUE(edited);
  (void)edited->evaluate(20);
  ASSERT_FALSE(edited->needsRebuild(windy));
  ASSERT_TRUE(edited->update(windy).ok());
  expectSameParticles(edited->evaluate(20), evaluator(windy)->evaluate(20));

  Scene wild = s;
  wild.simulation->forces.drag = -1.0f;
  const auto rejected = edited->update(wild);
  ASSERT_FALSE(rejected.ok());
  EXPECT_NE(rejected.error().message.find("/simulation"), std::string::npos) << rejected.error().message;
}

TEST(SceneGeometry, EachMeshFileIsLoadedOnceAndEachPrimitiveMadeOnce) {
  const Scene s = parsed(R"({"objects": [{"type": "box"}, {"type": "sphere"}, {"type": "box", "translate": [3, 0, 0]},
                                          {"type": "plane"}]})");
  auto g = loadGeometry(s);
  ASSERT_TRUE(g.ok()) << g.error().message;
  ASSERT_EQ(g->shapes.size(), 4u);
  EXPECT_EQ(g->shapes[0], g->shapes[2]) << "two boxes share one mesh";
  EXPECT_NE(g->shapes[0], g->shapes[1]);
  EXPECT_EQ(g->shapes[0]->positions.size(), 24u);
  EXPECT_EQ(g->shapes[3]->faceCount(), 2u);
}

TEST(SceneGeometry, AMissingMeshIsAnErrorNamingTheFile) {
  const Scene s = parsed(R"({"objects": [{"type": "mesh", "mesh": "no-such-mesh.obj"}]})");
  auto g = loadGeometry(s);
  ASSERT_FALSE(g.ok());
  EXPECT_NE(g.error().message.find("no-such-mesh.obj"), std::string::npos) << g.error().message;
}

}  // namespace
}  // namespace puff::scene
