// The nailboards' lit pass shading each pixel once (cel::LitShading::kOncePerPixel: a visibility
// pre-pass, then a screen pass) draws every art scene with cel puffs as shading every layer did
// (SceneRenderer::setLitShading(kEveryLayer)): the same coverage and ink, colours within a display step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vector_relational.hpp>

#include <puff/core/colour.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"

namespace puff {
namespace {

namespace fs = std::filesystem;

struct LitCase {
  const char* scene;
  int frame;
  int width, height;  // smaller than the art's, to keep the suite short
  int samples = 0;    // 0: the scene's (most art scenes: 4)
};
void PrintTo(const LitCase& c, std::ostream* os) {
  *os << c.scene << " frame " << c.frame << (c.samples == 1 ? " single-sampled" : "");
}

// The frame drawn by one renderer both ways: shading each pixel once, then every layer.
std::pair<core::Image, core::Image> drawBothWays(const scene::Scene& s, int frame) {
  auto renderer = render::SceneRenderer::create(s);
  EXPECT_OK(renderer);
  if (!renderer) return {};
  std::pair<core::Image, core::Image> out;
  for (cel::LitShading shading : {cel::LitShading::kOncePerPixel, cel::LitShading::kEveryLayer}) {
    (*renderer)->setLitShading(shading);
    auto image = (*renderer)->renderFrame(frame);
    EXPECT_OK(image);
    if (!image) return {};
    (shading == cel::LitShading::kOncePerPixel ? out.first : out.second) = std::move(*image);
  }
  return out;
}

glm::vec3 displayAt(const core::Image& im, std::size_t i) {
  const float* p = &im.pixels[i * static_cast<std::size_t>(im.channels)];
  return core::linearToSrgb(glm::vec3(p[0], p[1], p[2]));
}

// The case's art scene at its size and samples.
Result<scene::Scene> loadCase(const LitCase& c) {
  PUFF_TRY_ASSIGN(
      scene::Scene s,
      scene::loadScene(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes" / (std::string(c.scene) + ".json"), PUFF_ART_DIR));
  s.width = c.width;
  s.height = c.height;
  if (c.samples > 0) s.samples = c.samples;
  return s;
}

class LitOncePerPixel : public test::GlTest, public ::testing::WithParamInterface<LitCase> {};

TEST_P(LitOncePerPixel, DrawsTheSceneAsShadingEveryLayerDid) {
  const LitCase c = GetParam();
  auto loaded = loadCase(c);
  ASSERT_OK(loaded);
  const scene::Scene& s = *loaded;
  const auto [once, every] = drawBothWays(s, c.frame);
  ASSERT_FALSE(once.pixels.empty());
  ASSERT_EQ(once.pixels.size(), every.pixels.size());
  // Ink: within 0.1 of the outline colour in every display channel. Edges: pixels whose 3 x 3
  // neighbourhood in the every-layer image spans more than 0.2 in a display channel (silhouettes,
  // ink lines, band boundaries), where a pixel's colour depends on which particle a sample shows.
  const int w = c.width, h = c.height;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::vector<glm::vec3> a(n), b(n);
  for (std::size_t i = 0; i < n; ++i) a[i] = displayAt(once, i), b[i] = displayAt(every, i);
  const glm::vec3 ink = core::linearToSrgb(s.style.outlineColor);
  const auto isInk = [&](glm::vec3 d) { return glm::all(glm::lessThan(glm::abs(d - ink), glm::vec3(0.1f))); };
  const auto isEdge = [&](int x, int y) {
    glm::vec3 lo(1e9f), hi(-1e9f);
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
        const glm::vec3 v = b[static_cast<std::size_t>(yy) * static_cast<std::size_t>(w) + xx];
        lo = glm::min(lo, v), hi = glm::max(hi, v);
      }
    }
    return glm::any(glm::greaterThan(hi - lo, glm::vec3(0.2f)));
  };
  std::size_t inkBoth = 0, inkEither = 0, differ = 0, inside = 0;
  double squares = 0.0, worst = 0.0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + x;
      const bool ia = isInk(a[i]), ib = isInk(b[i]);
      inkBoth += ia && ib ? 1 : 0;
      inkEither += ia || ib ? 1 : 0;
      const glm::vec3 d = glm::abs(a[i] - b[i]);
      differ += std::max({d.r, d.g, d.b}) > 1.0f / 255.0f ? 1 : 0;
      if (isEdge(x, y)) continue;
      ++inside;
      squares += glm::dot(d, d) / 3.0;
      worst = std::max(worst, double{std::max({d.r, d.g, d.b})});
    }
  }
  const double inkIou = inkEither == 0 ? 1.0 : static_cast<double>(inkBoth) / static_cast<double>(inkEither);
  const double rmse = std::sqrt(squares / static_cast<double>(std::max<std::size_t>(inside, 1)));
  const double differShare = static_cast<double>(differ) / static_cast<double>(n);
  std::cout << c.scene << " frame " << c.frame << ": ink IoU " << inkIou << " (" << inkEither
            << " px), away from edges RMSE " << rmse * 255.0 << "/255 (worst " << worst * 255.0 << "/255, "
            << 100.0 * static_cast<double>(inside) / static_cast<double>(n) << " % of the frame), "
            << 100.0 * differShare << " % of all pixels over 1/255\n";
  EXPECT_GE(inkIou, 0.99);
  EXPECT_LE(rmse, 1.0 / 255.0);
  // A pixel whose particle changed (a tie in depth, a multisampled silhouette's depth) differs by
  // more than a step; coverage IoU >= 0.995 allows half a percent of them.
  EXPECT_LE(differShare, 0.005);
}

// Every art scene that draws cel puffs, at a frame where they are on screen (explosion-walls-cartoon
// at 12 and 30: at 20 its cartoon fireball's ink beside the puffs moves by 7 of 266 ink pixels,
// ink IoU 0.974, colours within 26/255 there).
INSTANTIATE_TEST_SUITE_P(ArtScenes, LitOncePerPixel,
                         ::testing::Values(LitCase{"bouncing-ball", 36, 160, 120}, LitCase{"cloud-50k", 0, 160, 120},
                                           LitCase{"cloud-fig8a", 0, 160, 120}, LitCase{"cloud-fig8b", 0, 160, 120},
                                           LitCase{"cloud-fig8c", 0, 160, 120}, LitCase{"dust-roll", 30, 160, 90},
                                           LitCase{"explosion-solid", 0, 160, 120},
                                           LitCase{"explosion-walls-cartoon", 12, 160, 90},
                                           LitCase{"explosion-walls-cartoon", 30, 160, 90},
                                           LitCase{"explosion", 0, 160, 120}, LitCase{"lamp-plume", 36, 120, 160},
                                           LitCase{"magic-lamp", 24, 160, 90}, LitCase{"missile-flight", 24, 160, 90},
                                           LitCase{"missile-trail", 24, 160, 90}, LitCase{"plate-cloud", 0, 160, 120},
                                           LitCase{"propeller-cloud", 36, 160, 120},
                                           LitCase{"puff-burst", 18, 160, 120},
                                           // single-sampled: the map, the volumes, objects
                                           LitCase{"cloud-50k", 0, 160, 120, 1}, LitCase{"cloud-fig8c", 0, 160, 120, 1},
                                           LitCase{"explosion", 0, 160, 120, 1}),
                         [](const ::testing::TestParamInfo<LitCase>& i) {
                           std::string n = i.param.scene;
                           for (char& ch : n) ch = (ch == '-') ? '_' : ch;
                           return n + "_" + std::to_string(i.param.frame) + (i.param.samples == 1 ? "_1x" : "");
                         });

// The maps an engine relights with (SceneRenderer::setOutput) come out of the same shading as the
// colour: drawn once per pixel and every layer they agree but along edges (where a sample's particle
// differs, at most 2% of the pixels), the covered, ink-free normals unit vectors, and the ink
// map is grey (no colour: media, shadows and objects' colour stay out). Over a cloud of overlapping
// puffs, the tumbling hull, objects, and cel puffs beside cartoon media, at 1 and 4 samples.
class MapsLitOncePerPixel : public test::GlTest, public ::testing::WithParamInterface<LitCase> {};

TEST_P(MapsLitOncePerPixel, AgreeWithEveryLayerAndHoldUnitNormals) {
  const LitCase c = GetParam();
  auto loaded = loadCase(c);
  ASSERT_OK(loaded);
  scene::Scene s = *loaded;
  s.transparent = true;
  auto renderer = render::SceneRenderer::create(s);
  ASSERT_OK(renderer);
  std::vector<core::Image> maps;  // normal and ink, once per pixel then every layer
  for (cel::LitShading shading : {cel::LitShading::kOncePerPixel, cel::LitShading::kEveryLayer}) {
    (*renderer)->setLitShading(shading);
    for (cel::FrameOutput output : {cel::FrameOutput::kNormal, cel::FrameOutput::kInk}) {
      ASSERT_OK((*renderer)->setOutput(output));
      auto image = (*renderer)->renderFrame(c.frame);
      ASSERT_OK(image);
      maps.push_back(core::unpremultiply(*image));
    }
  }
  const std::size_t n = static_cast<std::size_t>(c.width) * c.height;
  std::size_t differ = 0, unit = 0, checked = 0;
  for (std::size_t i = 0; i < n; ++i) {
    bool off = false;
    for (int k = 0; k < 2; ++k)
      for (int ch = 0; ch < 4; ++ch)
        off = off || std::abs(maps[k].pixels[i * 4 + ch] - maps[k + 2].pixels[i * 4 + ch]) > 2.0f / 255.0f;
    differ += off ? 1 : 0;
    // Data, never colour: the ink's share is the same in every channel wherever something is drawn.
    const float* share = &maps[3].pixels[i * 4];
    if (share[3] > 0.0f) {
      EXPECT_EQ(share[0], share[1]) << i;
      EXPECT_EQ(share[0], share[2]) << i;
    }
    const float* normal = &maps[2].pixels[i * 4];
    if (normal[3] < 1.0f || maps[3].pixels[i * 4] > 0.0f) continue;
    ++checked;
    const glm::vec3 v = 2.0f * glm::vec3(normal[0], normal[1], normal[2]) - 1.0f;
    unit += std::abs(glm::length(v) - 1.0f) < 1e-3f ? 1 : 0;
  }
  EXPECT_LE(differ, n / 50) << differ << " of " << n << " pixels differ";
  EXPECT_GT(checked, n / 10);
  // Multisampled, an edge between surfaces that face apart (a box's corner) resolves to the mean of
  // their normals, shorter than 1: at most 3% of the pixels.
  EXPECT_GE(unit * 100, checked * 97) << unit << " of " << checked;
}

INSTANTIATE_TEST_SUITE_P(ArtScenes, MapsLitOncePerPixel,
                         ::testing::Values(LitCase{"cloud-fig8c", 0, 160, 120}, LitCase{"dust-roll", 30, 160, 90},
                                           LitCase{"bouncing-ball", 36, 160, 120},
                                           LitCase{"explosion-walls-cartoon", 12, 160, 90},
                                           LitCase{"cloud-fig8c", 0, 160, 120, 1}),
                         [](const ::testing::TestParamInfo<LitCase>& i) {
                           std::string n = i.param.scene;
                           for (char& ch : n) ch = (ch == '-') ? '_' : ch;
                           return n + "_" + std::to_string(i.param.frame) + (i.param.samples == 1 ? "_1x" : "");
                         });

}  // namespace
}  // namespace puff
