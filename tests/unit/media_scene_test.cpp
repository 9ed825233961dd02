// The media art scenes: golden frames, a frame alone equal to the same frame of a
// sequence, the camera flying into smoke without popping, and the scene file's media section.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include <puff/render/render.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

#include "golden/golden.h"
#include "support/assert_ok.h"
#include "support/display.h"
#include "support/gl_fixture.h"

namespace puff::media_scene {
namespace {

namespace fs = std::filesystem;

fs::path sceneFile(const std::string& name) { return fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / (name + ".json"); }

struct MediaCase {
  const char* scene;
  int frame;
};
void PrintTo(const MediaCase& c, std::ostream* os) { *os << c.scene << " frame " << c.frame; }

class MediaSceneGolden : public test::GlTest, public ::testing::WithParamInterface<MediaCase> {};

// The cel scenes' tolerance and its check (test::expectSceneGolden: 3/255 per channel, 0.2% of pixels).
TEST_P(MediaSceneGolden, MatchesReference) {
  const MediaCase c = GetParam();
  auto scene = scene::loadScene(sceneFile(c.scene), PUFF_ART_DIR);
  ASSERT_OK(scene);
  ASSERT_TRUE(scene->media.has_value());
  auto renderer = render::SceneRenderer::create(*scene);
  ASSERT_OK(renderer);
  render::FrameStats stats;
  auto image = (*renderer)->renderFrame(c.frame, &stats);
  ASSERT_OK(image);
  EXPECT_GT(stats.mediaParticles, 20u);
  test::expectSceneGolden(test::display(*image, scene::viewTransformFor(*scene)),
                          "scene-" + std::string(c.scene) + "-" + std::to_string(c.frame));
}

INSTANTIATE_TEST_SUITE_P(ArtScenes, MediaSceneGolden,
                         ::testing::Values(MediaCase{"explosion-walls", 5}, MediaCase{"explosion-walls", 20},
                                           MediaCase{"smoke-flythrough", 30}, MediaCase{"fire-to-smoke", 48},
                                           // The cartoon style: bands and ink, beside cel puffs.
                                           MediaCase{"explosion-walls-cartoon", 20},
                                           MediaCase{"fire-to-smoke-cartoon", 48}),
                         [](const ::testing::TestParamInfo<MediaCase>& i) {
                           std::string n = i.param.scene;
                           for (char& ch : n) ch = (ch == '-') ? '_' : ch;
                           return n + "_" + std::to_string(i.param.frame);
                         });

class MediaScenes : public test::GlTest {};

scene::Scene smaller(scene::Scene s, int width, int height) {
  s.width = width;
  s.height = height;
  return s;
}

TEST_F(MediaScenes, AFrameAloneEqualsTheSameFrameOfASequence) {
  auto scene = scene::loadScene(sceneFile("explosion-walls"), PUFF_ART_DIR);
  ASSERT_OK(scene);
  const scene::Scene s = smaller(*scene, 160, 120);
  auto sequence = render::SceneRenderer::create(s);
  ASSERT_OK(sequence);
  core::Image inSequence;
  for (int f = 0; f <= 9; ++f) {
    auto image = (*sequence)->renderFrame(f);
    ASSERT_OK(image);
    if (f == 9) inSequence = std::move(*image);
  }
  auto alone = render::SceneRenderer::create(s);
  ASSERT_TRUE(alone.ok());
  auto image = (*alone)->renderFrame(9);
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image->pixels, inSequence.pixels);
}

TEST_F(MediaScenes, MotionBlurIsTheWeightedSumOfTheLastFramesAndAFrameAloneEqualsTheSequence) {
  auto scene = scene::loadScene(sceneFile("explosion-walls"), PUFF_ART_DIR);
  ASSERT_OK(scene);
  scene::Scene sharp = smaller(*scene, 128, 96);
  sharp.samples = 1;
  scene::Scene blurred = sharp;
  blurred.media->motionBlurFrames = 3;
  blurred.media->motionBlurPersistence = 0.5f;
  auto a = render::SceneRenderer::create(sharp);
  ASSERT_OK(a);
  std::vector<core::Image> frames;
  for (int f = 0; f <= 8; ++f) frames.push_back(*(*a)->renderFrame(f));
  auto sequence = render::SceneRenderer::create(blurred);
  ASSERT_TRUE(sequence.ok());
  core::Image last;
  for (int f = 0; f <= 8; ++f) last = *(*sequence)->renderFrame(f);
  // sum of p^i F(8 - i), i = 0..3, over sum of p^i (each F rounded to 8 bits here, not there).
  const float w[4] = {1.0f, 0.5f, 0.25f, 0.125f};
  float worst = 0.0f;
  for (std::size_t i = 0; i < last.pixels.size(); ++i) {
    if (i % 4 == 3) continue;
    float sum = 0.0f;
    for (int k = 0; k < 4; ++k) sum += w[k] * frames[static_cast<std::size_t>(8 - k)].pixels[i];
    worst = std::max(worst, std::abs(sum / 1.875f - last.pixels[i]));
  }
  EXPECT_LT(worst, 2.0f / 255.0f);
  EXPECT_NE(last.pixels, frames[8].pixels);  // it did blur
  auto alone = render::SceneRenderer::create(blurred);
  ASSERT_TRUE(alone.ok());
  EXPECT_EQ((*alone)->renderFrame(8)->pixels, last.pixels);
  // Frame 1 has one frame before it: weights 1 and 0.5 over 1.5.
  auto early = render::SceneRenderer::create(blurred);
  const core::Image one = *(*early)->renderFrame(1);
  for (std::size_t i = 0; i < one.pixels.size(); i += 97) {
    if (i % 4 == 3) continue;
    EXPECT_NEAR(one.pixels[i], (frames[1].pixels[i] + 0.5f * frames[0].pixels[i]) / 1.5f, 2.0f / 255.0f);
  }
}

// The temporal metric: the second difference of consecutive frames along the camera path,
// |f[k+1] - 2 f[k] + f[k-1]| per pixel and channel. Smooth motion keeps it near the 8-bit rounding
// of the images (a few /255); a particle that pops in or out of view shows as a spike of its
// opacity. Returns the largest value over every pixel of every frame.
double largestSecondDifference(render::SceneRenderer& r, int first, int last) {
  std::vector<core::Image> frames;
  for (int f = first; f <= last; ++f) {
    auto image = r.renderFrame(f);
    EXPECT_OK(image);
    frames.push_back(std::move(*image));
  }
  double worst = 0.0;
  for (std::size_t k = 1; k + 1 < frames.size(); ++k) {
    for (std::size_t i = 0; i < frames[k].pixels.size(); ++i) {
      if (i % 4 == 3) continue;
      worst = std::max(worst, static_cast<double>(std::abs(frames[k + 1].pixels[i] - 2.0f * frames[k].pixels[i] +
                                                           frames[k - 1].pixels[i])));
    }
  }
  return worst;
}

TEST_F(MediaScenes, FlyingIntoSmokePopsWithPlanarBillboardsNotSpherical) {
  // The camera flies at 1 unit/s (1/24 per frame) through three dense smoke spheres against a black
  // sky. A planar billboard vanishes whole when its centre crosses the near plane: a jump of its
  // full opacity (1 - e^-3 = 0.95 at its centre). A spherical billboard only changes slope when
  // the camera enters or leaves it: tau * step = 1.5 / 24 = 0.06 at most.
  const auto j = nlohmann::json::parse(R"({
    "output": {"width": 32, "height": 24, "samples": 1, "background": [0, 0, 0]},
    "camera": {"position": [0, 0, 6], "target": [0, 0, 0], "near": 0.05, "far": 50},
    "ambient": {"color": [1, 1, 1]},
    "light": {"color": [0, 0, 0]},
    "animation": {"fps": 24, "frames": 289,
                  "cameraPath": [{"time": 0, "position": [0, 0, 6]}, {"time": 12, "position": [0, 0, -6]}],
                  "targetPath": [{"time": 0, "position": [0, 0, 0]}, {"time": 12, "position": [0, 0, -12]}]},
    "media": {"resolution": 1,
              "materials": [{"name": "smoke", "albedo": 1, "density": 1.5, "detail": 0}],
              "particles": [{"position": [0.2, 0.1, 4]}, {"position": [-0.3, 0, 0]}, {"position": [0, -0.2, -4]}]}
  })");
  auto scene = scene::parseScene(j, "flythrough.json");
  ASSERT_OK(scene);
  auto spherical = render::SceneRenderer::create(*scene);
  ASSERT_OK(spherical);
  const double smooth = largestSecondDifference(**spherical, 0, 288);
  scene->media->method = media::Method::kPlanar;
  auto planar = render::SceneRenderer::create(*scene);
  ASSERT_OK(planar);
  const double popping = largestSecondDifference(**planar, 0, 288);
  std::printf("largest second difference: spherical %.4f, planar %.4f\n", smooth, popping);
  EXPECT_LT(smooth, 0.06 + 3.0 / 255.0);  // the slope change, plus 8-bit rounding
  EXPECT_GT(popping, 0.5);
}

TEST_F(MediaScenes, PlanarTexturedRendersFromASceneFile) {
  // "method": "planar-textured" read, written back, and drawn: one dense smoke sphere against a
  // black sky. The classic billboard shows the lone sphere's profile, at the centre as bright as
  // the spherical billboard's (both 1 - exp(-2 tau r) there); nothing outside the quad.
  const auto j = nlohmann::json::parse(R"({
    "output": {"width": 48, "height": 48, "samples": 1, "background": [0, 0, 0]},
    "camera": {"position": [0, 0, 6], "target": [0, 0, 0], "fovY": 40, "near": 0.5, "far": 30},
    "ambient": {"color": [1, 1, 1]},
    "light": {"color": [0, 0, 0]},
    "media": {"method": "planar-textured", "resolution": 1,
              "materials": [{"name": "smoke", "albedo": 1, "density": 1, "detail": 0}],
              "particles": [{"position": [0, 0, 0], "radius": 1.2}]}
  })");
  auto scene = scene::parseScene(j, "textured.json");
  ASSERT_OK(scene);
  ASSERT_EQ(scene->media->method, media::Method::kPlanarTextured);
  const nlohmann::json out = scene::toJson(*scene);
  EXPECT_EQ(out["media"]["method"], "planar-textured");
  auto textured = render::SceneRenderer::create(*scene);
  ASSERT_OK(textured);
  auto image = (*textured)->renderFrame(0);
  ASSERT_OK(image);
  scene->media->method = media::Method::kSpherical;
  auto spherical = render::SceneRenderer::create(*scene);
  ASSERT_OK(spherical);
  auto sphImage = (*spherical)->renderFrame(0);
  ASSERT_OK(sphImage);
  // Black background, albedo 1, ambient 1: the pixel is the opacity (before the output encoding,
  // the same for both images).
  const float centre = image->at(24, 24, 0), sphCentre = sphImage->at(24, 24, 0);
  EXPECT_GT(centre, 0.5f);
  EXPECT_NEAR(centre, sphCentre, 3.0f / 255.0f);
  EXPECT_EQ(image->at(0, 0, 0), 0.0f);
}

TEST_F(MediaScenes, MediaSectionRoundTripsThroughJson) {
  auto scene = scene::loadScene(sceneFile("explosion-walls"), PUFF_ART_DIR);
  ASSERT_OK(scene);
  const nlohmann::json j = scene::toJson(*scene);
  auto again = scene::parseScene(j, scene->file, PUFF_ART_DIR);
  ASSERT_OK(again);
  EXPECT_EQ(scene::toJson(*again), j);
  ASSERT_TRUE(again->media.has_value());
  EXPECT_EQ(again->media->materials.size(), 4u);
  EXPECT_EQ(again->media->materials[0].becomes, 1);  // fire becomes soot
  EXPECT_EQ(again->media->emitters.size(), 3u);
}

TEST_F(MediaScenes, EveryMediaFieldSurvivesAWriteAndARead) {
  const auto j = nlohmann::json::parse(R"({
    "objects": [{"type": "box", "name": "cart", "path": [{"time": 0, "position": [0, 0, 0]},
                                                          {"time": 2, "position": [4, 0, 0]}]}],
    "animation": {"cameraPath": [{"time": 0, "position": [0, 1, 9]}, {"time": 1, "position": [0, 1, 5]}]},
    "media": {
      "method": "soft-scurve", "resolution": 0.25, "phase": "henyey-greenstein", "exposure": 2,
      "blackbody": {"minKelvin": 800, "maxKelvin": 9000, "normalizeKelvin": 3000},
      "shimmer": 3, "depthAware": false, "depthTolerance": 0.05,
      "motionBlur": {"frames": 2, "persistence": 0.25},
      "materials": [{"name": "hot", "preset": "fire", "becomes": "cold", "transitionStart": 0.1, "transitionEnd": 0.7},
                    {"name": "cold", "preset": "dust", "g": 0.4, "detailSpeed": 3}],
      "particles": [{"position": [1, 2, 3], "radius": 0.5, "material": "cold", "life": 0.25, "density": 2, "seed": 7}],
      "emitters": [{"material": "hot", "attach": "cart", "rate": 20, "density": 3, "growth": 0.5}],
      "forces": {"buoyancy": 1, "vortices": [{"attach": "cart", "strength": 2}]},
      "substeps": 3, "preroll": 0.5, "maxParticles": 500, "collisionRadius": 0.25,
      "lights": [{"center": [0, 1, 0], "radius": 2, "intensity": 0.75, "mode": "modulate", "full": "back"}]
    }
  })");
  auto scene = scene::parseScene(j, "x.json");
  ASSERT_OK(scene);
  const scene::MediaSpec& m = *scene->media;
  // Attached emitters and vortices ride on the cart.
  ASSERT_FALSE(m.emitters[0].emitter.path.empty());
  EXPECT_EQ(m.emitters[0].emitter.path.at(2.0), glm::vec3(4, 0, 0));
  EXPECT_EQ(m.forces.vortices[0].path.at(1.0), glm::vec3(2, 0, 0));
  const nlohmann::json out = scene::toJson(*scene);
  auto again = scene::parseScene(out, "x.json");
  ASSERT_OK(again);
  EXPECT_EQ(scene::toJson(*again), out);
  const scene::MediaSpec& n = *again->media;
  EXPECT_EQ(n.method, media::Method::kSoftSCurve);
  EXPECT_EQ(n.resolution, 0.25f);
  EXPECT_EQ(n.settings.phase, media::PhaseModel::kHenyeyGreenstein);
  EXPECT_EQ(n.settings.minKelvin, 800.0f);
  EXPECT_EQ(n.compose.depthAware, false);
  EXPECT_EQ(n.motionBlurFrames, 2);
  EXPECT_EQ(n.materials[0].becomes, 1);
  EXPECT_EQ(n.materials[1].detailSpeed, 3.0f);
  ASSERT_EQ(n.particles.size(), 1u);
  EXPECT_EQ(n.particles[0].materialIndex, 1);
  EXPECT_EQ(n.particles[0].seed, 7u);
  EXPECT_EQ(n.emitters[0].emitter.density, 3.0f);
  EXPECT_EQ(n.emitters[0].emitter.path.at(2.0), glm::vec3(4, 0, 0));
  EXPECT_EQ(n.lights[0].intensityAt(5.0), 0.75f);
  EXPECT_TRUE(n.lights[0].modulate);
  EXPECT_TRUE(n.lights[0].fullAtBack);
  EXPECT_EQ(again->animation.cameraPath.at(0.5), glm::vec3(0, 1, 7));
}

TEST_F(MediaScenes, BadMediaFieldsNameThePointer) {
  const struct {
    const char* json;
    const char* message;
  } cases[] = {
      {R"({"media": {"resolution": 0.3}})", "/media/resolution: expected 1, 0.5, 0.25 or 0.125, got 0.3"},
      {R"({"media": {"method": "flat"}})",
       "/media/method: expected one of planar, soft-linear, soft-scurve, spherical, planar-textured, got \"flat\""},
      {R"({"media": {"particles": [{"material": "steam"}]}})",
       "/media/particles/0/material: expected the name of a material (smoke, dust, fire), got \"steam\""},
      {R"({"media": {"materials": [{"name": "a", "albedo": 2}]}})",
       "/media/materials/0/albedo: expected a number in [0, 1], got 2"},
      {R"({"media": {"materials": [{"name": "a", "becomes": "b"}]}})",
       "/media/materials/0/becomes: expected the name of a material (a), got \"b\""},
      {R"({"media": {"emitters": [{"material": "fire", "lifetime": 0}]}})",
       "/media/emitters/0/lifetime: expected a lifetime in seconds > 0, got 0"},
      {R"({"media": {"blackbody": {"minKelvin": 5000, "maxKelvin": 4000}}})",
       "/media/blackbody/maxKelvin: expected maxKelvin > minKelvin, got 4000"},
      {R"({"media": {"emitters": [{"material": "fire", "variations": [1]}]}})",
       "/media/emitters/0/variations: unknown key: media particles are spheres (no atlas variation or orientation)"},
      {R"({"media": {"emitters": [{"attach": "nothing"}]}})",
       "/media/emitters/0/attach: expected the name of a scene object (there are none), got \"nothing\""},
  };
  for (const auto& c : cases) {
    auto s = scene::parseScene(nlohmann::json::parse(c.json), "x.json");
    ASSERT_FALSE(s.ok()) << c.json;
    EXPECT_EQ(s.error().message, std::string("x.json: ") + c.message);
  }
}

}  // namespace
}  // namespace puff::media_scene
