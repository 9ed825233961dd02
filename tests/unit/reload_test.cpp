// SceneRenderer::update keeps what an edit does not touch (each path's and the evaluator's reload
// rule) and rebuilds the rest. Whatever it keeps, the frame after an edit must be exactly the frame
// a renderer made from scratch for the edited scene draws: a field missing from a reload rule would
// show here as the old look.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

struct Edit {
  std::string what;
  std::function<void(scene::Scene&)> apply;
};

// A compatibility-profile context: the fixed path draws in it too.
class Reload : public test::GlSuite<true> {
 protected:
  static scene::Scene load(const char* name) {
    auto s = scene::loadScene(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / name, PUFF_ART_DIR);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    scene::Scene out = s.ok() ? *s : scene::Scene{};
    out.width = 96;
    out.height = 72;
    return out;
  }

  // One renderer takes every edit in turn; after each, its frame must equal a fresh renderer's.
  void expectEditsDrawAsFromScratch(scene::Scene s, render::RenderPath path, int frame,
                                    const std::vector<Edit>& edits) {
    auto edited = render::SceneRenderer::create(s, path);
    ASSERT_OK(edited);
    ASSERT_OK((*edited)->renderFrame(frame));
    for (const Edit& e : edits) {
      SCOPED_TRACE(e.what);
      e.apply(s);
      ASSERT_OK((*edited)->update(s));
      auto after = (*edited)->renderFrame(frame);
      ASSERT_OK(after);
      auto fresh = render::SceneRenderer::create(s, path);
      ASSERT_OK(fresh);
      auto expected = (*fresh)->renderFrame(frame);
      ASSERT_OK(expected);
      EXPECT_EQ(after->pixels, expected->pixels);
    }
  }
};

const fs::path kRamps = fs::path(PUFF_SOURCE_DIR) / "art" / "ramps";

std::vector<Edit> celEdits() {
  return {
      {"outline width", [](scene::Scene& s) { s.style.outlineWidth = 4.0f; }},
      {"shadows off", [](scene::Scene& s) { s.style.shadows = false; }},
      {"light", [](scene::Scene& s) { s.light.direction = glm::vec3(-1.0f, 0.5f, 0.2f); }},
      {"ambient colour", [](scene::Scene& s) { s.ambientColor = glm::vec3(0.4f, 0.1f, 0.1f); }},
      {"background", [](scene::Scene& s) { s.background = glm::vec3(0.1f, 0.2f, 0.3f); }},
      {"camera", [](scene::Scene& s) { s.camera.position += glm::vec3(1.0f, 0.5f, 0.0f); }},
      {"ramp", [](scene::Scene& s) { s.ramp = kRamps / "three-tone-hue.png"; }},
      {"smooth ramp", [](scene::Scene& s) { s.rampSmooth = !s.rampSmooth; }},
      {"atlas level", [](scene::Scene& s) { s.atlasLevel = 1; }},
      {"emitter count", [](scene::Scene& s) { s.emitters.at(0).count -= 20; }},
      {"particle fraction", [](scene::Scene& s) { s.particleFraction = 0.5f; }},
      {"an object added",
       [](scene::Scene& s) {
         scene::ObjectSpec ground;
         ground.translate = glm::vec3(0.0f, -1.5f, 0.0f);
         ground.scale = glm::vec3(6.0f, 1.0f, 6.0f);
         s.objects.push_back(ground);
       }},
      {"the object moved", [](scene::Scene& s) { s.objects.back().translate.y = -1.0f; }},
      {"the object's colour", [](scene::Scene& s) { s.objects.back().albedo = glm::vec3(0.2f, 0.6f, 0.2f); }},
      {"samples", [](scene::Scene& s) { s.samples = 1; }},
  };
}

TEST_F(Reload, CelEditsDrawAsARendererMadeForTheEditedScene) {
  expectEditsDrawAsFromScratch(load("cloud-fig8c.json"), render::RenderPath::kCel, 0, celEdits());
}

TEST_F(Reload, FixedEditsDrawAsARendererMadeForTheEditedScene) {
  std::vector<Edit> edits = celEdits();
  edits.push_back({"outline scale", [](scene::Scene& s) { s.fixed.outlineScale = 1.4f; }});
  edits.push_back({"cell size", [](scene::Scene& s) { s.fixed.cellSize = 32; }});
  edits.push_back({"frame size", [](scene::Scene& s) { s.width = 80, s.height = 64; }});
  expectEditsDrawAsFromScratch(load("cloud-fig8c.json"), render::RenderPath::kFixed, 0, edits);
}

TEST_F(Reload, MediaAndSimulationEditsDrawAsARendererMadeForTheEditedScene) {
  const std::vector<Edit> edits = {
      {"method", [](scene::Scene& s) { s.media->method = media::Method::kPlanar; }},
      {"layer resolution", [](scene::Scene& s) { s.media->resolution = 0.25f; }},
      {"a material's density", [](scene::Scene& s) { s.media->materials.at(0).density *= 2.0f; }},
      {"exposure", [](scene::Scene& s) { s.media->settings.exposure = 2.0f; }},
      {"shimmer", [](scene::Scene& s) { s.media->compose.shimmerPixels = 0.0f; }},
      {"a light",
       [](scene::Scene& s) {
         if (!s.media->lights.empty()) s.media->lights[0].color = glm::vec3(0.2f, 0.4f, 1.0f);
       }},
      {"forces", [](scene::Scene& s) { s.media->forces.wind = glm::vec3(2.0f, 0.0f, 0.0f); }},
      {"an emitter's rate", [](scene::Scene& s) { s.media->emitters.at(0).emitter.rate *= 0.5f; }},
      {"growth", [](scene::Scene& s) { s.media->emitters.at(0).growth += 1.0f; }},
      {"substeps", [](scene::Scene& s) { s.media->substeps += 1; }},
      {"motion blur", [](scene::Scene& s) { s.media->motionBlurFrames = 2; }},
      {"a wall moved", [](scene::Scene& s) { s.objects.back().translate.x += 0.5f; }},
      {"fps", [](scene::Scene& s) { s.animation.fps = 30.0f; }},
  };
  expectEditsDrawAsFromScratch(load("explosion-walls.json"), render::RenderPath::kCel, 12, edits);
}

}  // namespace
}  // namespace puff
