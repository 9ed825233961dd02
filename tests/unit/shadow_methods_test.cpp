// Shadows by every method: the billboard shadow volumes, the shadow map and the cel
// reference, each checked against what geometry says, over light directions, map scales, shadow
// lengths and caster kinds, not at one point:
//  - a sphere puff's shadow on the ground is the light's projection of it: an ellipse of semi-axes
//    R across the light and R / l_y along it, centred H l_xz / l_y from below the puff;
//  - a puff never shadows itself, from any side the light comes;
//  - a shadow ends shadowLength along the light;
//  - opaque objects shadow the ground and the puffs (the map and the reference; docs/cel-rendering.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <puff/bake/baker.h>
#include <puff/cel/shadow_map.h>
#include <puff/eval/cel_reference.h>
#include <puff/mesh/mesh.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/display.h"
#include "support/linear_frame.h"
#include "support/sphere_atlas.h"

namespace puff {
namespace {

constexpr int kPx = 128;
constexpr float kPxPerUnit = 16.0f;  // orthoHeight 8 over 128 pixels
constexpr float kAmbient = 0.2f, kLitGround = 0.7f;

enum class Method { kVolumes, kMap, kReference };
std::string name(Method m) { return m == Method::kVolumes ? "volumes" : m == Method::kMap ? "map" : "reference"; }

class ShadowMethods : public test::SphereAtlasTest {
 protected:
  // Camera straight down at the ground (orthographic, 16 px per unit, image top = -z), white ground,
  // light K_L 0.5 toward `light`, ambient 0.2: lit ground 0.7, shadowed 0.2 (display values).
  static nlohmann::json groundScene(const glm::vec3& light, const nlohmann::json& style,
                                    const nlohmann::json& particles, nlohmann::json objects = nlohmann::json::array()) {
    objects.push_back({{"type", "plane"}, {"name", "ground"}, {"scale", {12, 1, 12}}, {"albedo", {1, 1, 1}}});
    return {{"output", {{"width", kPx}, {"height", kPx}, {"samples", 1}}},
            {"camera",
             {{"position", {0, 10, 0}},
              {"target", {0, 0, 0}},
              {"up", {0, 0, -1}},
              {"fovY", 0},
              {"orthoHeight", 8},
              {"near", 1},
              {"far", 20}}},
            {"light", {{"direction", {light.x, light.y, light.z}}, {"color", {0.5, 0.5, 0.5}}}},
            {"ambient", {{"color", {kAmbient, kAmbient, kAmbient}}}},
            {"atlas", sidecar_.string()},
            {"style", style},
            {"objects", objects},
            {"particles", particles}};
  }

  static nlohmann::json style(Method m, nlohmann::json extra = nlohmann::json::object()) {
    nlohmann::json s = {{"preset", "cel-shadows"}, {"shadowMethod", m == Method::kMap ? "map" : "volumes"}};
    for (auto& [k, v] : extra.items()) s[k] = v;
    return s;
  }

  static core::Image render(const nlohmann::json& j, Method m) {
    auto scene = scene::parseScene(j, dir_ / "scene.json");
    EXPECT_OK(scene);
    if (!scene) return {};
    auto renderer = eval::createRenderer(
        *scene, m == Method::kReference ? render::RenderPath::kReference : render::RenderPath::kCel);
    EXPECT_OK(renderer);
    if (!renderer) return {};
    auto image = (*renderer)->renderFrame(0);
    EXPECT_OK(image);
    return image ? test::display(*image) : core::Image{};
  }

  // World x, z of pixel (x, y) on the ground.
  static glm::vec2 ground(int x, int y) {
    return {(x + 0.5f - kPx / 2.0f) / kPxPerUnit, (y + 0.5f - kPx / 2.0f) / kPxPerUnit};
  }
  static bool shadowed(const core::Image& im, int x, int y) { return std::abs(im.at(x, y, 0) - kAmbient) < 0.1f; }

  // The shadowed ground pixels of `im` that `counted` keeps, row by row.
  template <class Counted>
  static std::vector<bool> shadowMask(const core::Image& im, Counted counted) {
    std::vector<bool> mask(static_cast<std::size_t>(kPx) * kPx);
    for (int y = 0; y < kPx; ++y)
      for (int x = 0; x < kPx; ++x) mask[static_cast<std::size_t>(y) * kPx + x] = counted(x, y) && shadowed(im, x, y);
    return mask;
  }

  // `m` saved as NAME/NAME.obj under the suite's directory (so the reference loads the mesh itself)
  // and baked beside it: one view, 128-texel cells, a 4-texel flange. The sidecar.
  static std::filesystem::path bakeMesh(const mesh::TriMesh& m, const std::string& name) {
    const std::filesystem::path obj = dir_ / name / (name + ".obj");
    std::filesystem::create_directories(obj.parent_path());
    EXPECT_OK(mesh::saveMesh(m, obj));
    auto sources = bake::loadSources({obj}, std::nullopt);
    EXPECT_OK(sources);
    if (!sources) return {};
    bake::BakeOptions o;
    o.cellSize = 128;
    o.flange = {4.0f, false};
    o.outDir = obj.parent_path();
    o.contactSheet = false;
    auto baked = bake::bakeAtlas(*sources, o);
    EXPECT_OK(baked);
    return baked ? baked->sidecar : std::filesystem::path();
  }

  // Scene `j` with its puffs alone (no ground), drawn with shadows and without, shading off: the
  // pixels that differ (a puff shadowing itself) and the puffs' pixels.
  struct SelfShadow {
    int differ = 0, puff = 0;
  };
  static SelfShadow selfShadow(nlohmann::json j, Method m) {
    j["objects"] = nlohmann::json::array();
    j["style"]["shading"] = false;
    const core::Image with = render(j, m);
    j["style"]["shadows"] = false;
    const core::Image without = render(j, m);
    SelfShadow r;
    EXPECT_EQ(with.width, kPx);
    EXPECT_EQ(without.width, kPx);
    if (with.width != kPx || without.width != kPx) return r;
    for (int y = 0; y < kPx; ++y) {
      for (int x = 0; x < kPx; ++x) {
        r.puff += std::abs(without.at(x, y, 0) - without.at(0, 0, 0)) > 0.05f;
        r.differ += std::abs(with.at(x, y, 0) - without.at(x, y, 0)) > 2.0f / 255.0f;
      }
    }
    return r;
  }
};

// IoU of the shadowed ground pixels with `inside` over the pixels `counted` keeps.
template <class Inside, class Counted>
double shadowIoU(const core::Image& im, Inside inside, Counted counted, int* predicted = nullptr) {
  int both = 0, either = 0, pred = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      if (!counted(x, y)) continue;
      const bool a = inside(x, y);
      const bool b = std::abs(im.at(x, y, 0) - kAmbient) < 0.1f;
      both += a && b;
      either += a || b;
      pred += a;
    }
  }
  if (predicted) *predicted = pred;
  return either == 0 ? 1.0 : static_cast<double>(both) / either;
}

// The angle (degrees, [0, 180)) of the principal axis of a kPx x kPx mask's set pixels.
double principalAxisDegrees(const std::vector<bool>& mask) {
  double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      if (!mask[static_cast<std::size_t>(y) * kPx + x]) continue;
      n += 1, sx += x, sy += y, sxx += double(x) * x, syy += double(y) * y, sxy += double(x) * y;
    }
  }
  if (n == 0) return 0.0;
  const double mx = sx / n, my = sy / n;
  double a = 0.5 * std::atan2(2.0 * (sxy / n - mx * my), (sxx / n - mx * mx) - (syy / n - my * my)) * 180.0 / M_PI;
  return a < 0 ? a + 180.0 : a;
}

class ShadowOfASphere : public ShadowMethods, public ::testing::WithParamInterface<Method> {};

// A sphere puff of radius R at height H; lights at 30, 45 and 60 degrees of elevation from four
// azimuths. The shadow is the ellipse the light projects, within the pixels its edge and the puff
// (with its outline) do not cover.
TEST_P(ShadowOfASphere, OnTheGroundIsTheLightsProjection) {
  const Method m = GetParam();
  const float R = 0.6f, H = 1.6f;
  // The reference takes seconds a frame: fewer angles for it.
  const bool few = m == Method::kReference;
  for (float elevation : {30.0f, 45.0f, 60.0f}) {
    for (float azimuth : {0.0f, 90.0f, 200.0f, 315.0f}) {
      if (few && (elevation == 45.0f || azimuth == 90.0f || azimuth == 315.0f)) continue;
      const float el = glm::radians(elevation), az = glm::radians(azimuth);
      const glm::vec3 l(std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az));
      const core::Image im = render(groundScene(l, style(m), {{{"position", {0, H, 0}}, {"size", 2 * R}}}), m);
      ASSERT_EQ(im.width, kPx);
      const glm::vec2 centre = -H * glm::vec2(l.x, l.z) / l.y;
      const glm::vec2 along = glm::normalize(glm::vec2(l.x, l.z)), across(-along.y, along.x);
      auto ellipse = [&](int x, int y) {
        const glm::vec2 d = ground(x, y) - centre;
        const float a = glm::dot(d, along) * l.y / R, b = glm::dot(d, across) / R;
        return a * a + b * b;
      };
      auto inside = [&](int x, int y) { return ellipse(x, y) < 1.0f; };
      // Away from the puff seen from above (its disc and outline) and from the ellipse's edge (a pixel).
      auto counted = [&](int x, int y) {
        if (glm::length(ground(x, y)) < R + 3.0f / kPxPerUnit) return false;
        return std::abs(std::sqrt(ellipse(x, y)) - 1.0f) > 1.5f / (kPxPerUnit * R);
      };
      int predicted = 0;
      const double iou = shadowIoU(im, inside, counted, &predicted);
      EXPECT_GT(predicted, 100) << elevation << "/" << azimuth;
      EXPECT_GE(iou, 0.9) << name(m) << " elevation " << elevation << " azimuth " << azimuth;
    }
  }
}

// A lone puff lit from 14 directions (the axes, above and below, the diagonals, from behind): with
// shadows on, every pixel is what it is with shadows off. Shading off, so a shadowed pixel would
// show as the ambient term against the flat lit colour. The map and the reference know which caster
// a texel saw, so this holds for them at any bias. The volumes cannot: a volume starts at the far side
// the puff's depth map gives, mirrored, and only the bias keeps the puff's own surface out of it. At
// the default bias (0.05 diameters) they may still clip a dotted line of pixels along the terminator
// the light sees, where the depth map's far side falls steeply to the billboard plane and the start
// cap read there is least sure (with shading on that line lies in q's dark band anyway): at most 3%
// of the puff's pixels (measured: up to 40 of about 1,400, with lights from below the horizon).
TEST_P(ShadowOfASphere, APuffNeverShadowsItself) {
  const Method m = GetParam();
  const nlohmann::json particles = {{{"position", {0.3, 1.2, -0.2}}, {"size", 2.4}}};
  int lightIndex = 0;
  for (const glm::vec3& l : {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1),
                             glm::vec3(0, 0, -1), glm::vec3(0.2f, -1, 0.1f), glm::vec3(1, 1, 1), glm::vec3(-1, 1, -1),
                             glm::vec3(1, -0.3f, 1), glm::vec3(-1, 0.5f, 1), glm::vec3(0.3f, 0.2f, -1),
                             glm::vec3(-0.7f, 1, 0.1f), glm::vec3(0.05f, 1, 0.02f), glm::vec3(1, 0.05f, -0.4f)}) {
    // The reference has no bias to vary and takes seconds a frame: every other direction, once.
    if (m == Method::kReference && (++lightIndex % 2 == 0)) continue;
    for (float bias : {0.0f, 0.05f}) {
      if (m == Method::kReference && bias > 0.0f) continue;
      if (m == Method::kVolumes && bias == 0.0f) continue;  // the volumes' only guard is the bias
      const SelfShadow r = selfShadow(groundScene(l, style(m, {{"shadowBias", bias}}), particles), m);
      EXPECT_GT(r.puff, 1000);
      EXPECT_LE(r.differ, m == Method::kVolumes ? 3 * r.puff / 100 : 0)
          << name(m) << " light " << l.x << "," << l.y << "," << l.z << " bias " << bias;
    }
  }
}

// Light at 45 degrees: the ground is H / sin 45 along the light from the puff's centre. A shadow
// shorter than that leaves the ground lit; one well past it shades the ellipse.
TEST_P(ShadowOfASphere, EndsShadowLengthAlongTheLight) {
  const Method m = GetParam();
  const float R = 0.5f, H = 2.0f;
  const glm::vec3 l = glm::normalize(glm::vec3(1, 1, 0));
  const float toGround = H / l.y;
  for (float length : {0.5f * toGround, 1.5f * toGround}) {
    const core::Image im =
        render(groundScene(l, style(m, {{"shadowLength", length}}), {{{"position", {0, H, 0}}, {"size", 2 * R}}}), m);
    ASSERT_EQ(im.width, kPx);
    int shadowedPixels = 0;
    for (int y = 0; y < kPx; ++y) {
      for (int x = 0; x < kPx; ++x) {
        if (glm::length(ground(x, y)) > R + 0.4f && shadowed(im, x, y)) ++shadowedPixels;
      }
    }
    // The ellipse R x R sqrt2 covers pi R^2 sqrt2 = 1.11 square units, 284 pixels.
    if (length < toGround) {
      EXPECT_EQ(shadowedPixels, 0) << name(m) << " length " << length;
    } else {
      EXPECT_GT(shadowedPixels, 200) << name(m) << " length " << length;
    }
  }
}

// The cel methods and the reference apart: two ctest tests (one a suite), which -j runs side by side.
INSTANTIATE_TEST_SUITE_P(CelMethods, ShadowOfASphere, ::testing::Values(Method::kVolumes, Method::kMap),
                         [](const auto& p) { return name(p.param); });
INSTANTIATE_TEST_SUITE_P(Reference, ShadowOfASphere, ::testing::Values(Method::kReference),
                         [](const auto& p) { return name(p.param); });

// The map's resolution follows the screen: at shadowMapScale 0.25 a texel spans 4 pixels and the
// ellipse's edge is blockier, but its area stays; at 4 it matches the volumes' sharpness.
TEST_F(ShadowMethods, MapScaleTradesSharpnessNotPlace) {
  const float R = 0.6f, H = 1.6f;
  const glm::vec3 l = glm::normalize(glm::vec3(-0.6f, 1, 0.4f));
  const glm::vec2 centre = -H * glm::vec2(l.x, l.z) / l.y;
  const glm::vec2 along = glm::normalize(glm::vec2(l.x, l.z)), across(-along.y, along.x);
  auto ellipse = [&](int x, int y) {
    const glm::vec2 d = ground(x, y) - centre;
    const float a = glm::dot(d, along) * l.y / R, b = glm::dot(d, across) / R;
    return a * a + b * b;
  };
  double previous = 0.0;
  for (float scale : {0.25f, 1.0f, 4.0f}) {
    const core::Image im = render(
        groundScene(l, style(Method::kMap, {{"shadowMapScale", scale}}), {{{"position", {0, H, 0}}, {"size", 2 * R}}}),
        Method::kMap);
    ASSERT_EQ(im.width, kPx);
    auto counted = [&](int x, int y) { return glm::length(ground(x, y)) > R + 3.0f / kPxPerUnit; };
    const double iou = shadowIoU(
        im, [&](int x, int y) { return ellipse(x, y) < 1.0f; }, counted);
    EXPECT_GE(iou, scale < 1.0f ? 0.8 : 0.9) << "scale " << scale;
    EXPECT_GE(iou, previous - 0.01) << "finer maps are no worse: scale " << scale;
    previous = iou;
  }
}

// An unoriented long puff (an ellipsoid 3 x 1 x 1.5, one baked view, seen from above, its long
// axis along the screen's x) under six lights: each method's ground shadow lies along the puff as
// the reference's mesh casts it (the eye's right carried across the light), not turned 90 degrees,
// and covers much the same pixels.
TEST_F(ShadowMethods, ALongPuffsShadowLiesAlongItAsTheReferenceCastsIt) {
  mesh::TriMesh m = mesh::generateSphere({5});
  for (glm::vec3& p : m.positions) p *= glm::vec3(1.0f, 0.33f, 0.5f);
  mesh::computeNormals(m);
  mesh::normalizeToUnitSphere(m);
  const std::filesystem::path atlas = bakeMesh(m, "long");
  ASSERT_FALSE(atlas.empty());
  const float H = 1.5f;
  // Lights high and oblique (about 35 degrees of elevation: there the eye's right, carried across
  // the light, turns furthest from the ground's x).
  for (const glm::vec3& dir : {glm::vec3(0.5f, 1, 0), glm::vec3(0, 1, 0.6f), glm::vec3(-0.4f, 1, 0.4f),
                               glm::vec3(0.3f, 1, -0.5f), glm::vec3(1.1f, 1, 0.9f), glm::vec3(-1.3f, 1, -0.4f)}) {
    const glm::vec3 l = glm::normalize(dir);
    nlohmann::json j = groundScene(l, style(Method::kMap), {{{"position", {0, H, 0}}, {"size", 3.0}}});
    j["atlas"] = atlas.string();
    const core::Image ref = render(j, Method::kReference);
    ASSERT_EQ(ref.width, kPx);
    // The ground away from the puff seen from above (its ellipse and ink, grown a little).
    auto counted = [&](int x, int y) {
      const glm::vec2 g = ground(x, y);
      return (g.x / 1.7f) * (g.x / 1.7f) + (g.y / 0.6f) * (g.y / 0.6f) > 1.0f;
    };
    const std::vector<bool> refMask = shadowMask(ref, counted);
    for (Method m2 : {Method::kMap, Method::kVolumes}) {
      j["style"]["shadowMethod"] = m2 == Method::kMap ? "map" : "volumes";
      const core::Image im = render(j, m2);
      ASSERT_EQ(im.width, kPx);
      const double iou = shadowIoU(
          im, [&](int x, int y) { return bool(refMask[static_cast<std::size_t>(y) * kPx + x]); }, counted);
      // The front view's silhouette is not the ellipsoid's seen from the light: the shapes differ a
      // little (measured 0.69-0.80), their direction not at all: a shadow turned 90 degrees (the light's
      // own up, as before) fails the axis check.
      EXPECT_GE(iou, 0.65) << name(m2) << " light " << l.x << "," << l.y << "," << l.z;
      const double a = principalAxisDegrees(shadowMask(im, counted)), b = principalAxisDegrees(refMask);
      const double d = std::fmod(std::abs(a - b), 180.0);
      EXPECT_LT(std::min(d, 180.0 - d), 10.0) << name(m2) << ": shadow axis " << a << ", the reference's " << b;
    }
  }
}

// An unoriented puff with one lobe (a sphere drawn out toward its upper right), under oblique lights:
// the light sees its front view in the light-facing frame (the eye's right carried across the
// light, up completing it), so the lobe's shadow falls where the reference's mesh casts it. A
// frame turned the other way round (up and down exchanged) mirrors the lobe; a symmetric puff
// cannot tell.
TEST_F(ShadowMethods, AnUnorientedPuffsLobeShadowsWhereTheReferenceCastsIt) {
  mesh::TriMesh m = mesh::generateSphere({5});
  const glm::vec3 lobe = glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f));
  for (glm::vec3& p : m.positions) {
    const float t = std::max(0.0f, glm::dot(p, lobe));
    p += lobe * (0.8f * t * t * t);
  }
  mesh::computeNormals(m);
  mesh::normalizeToUnitSphere(m);
  const std::filesystem::path atlas = bakeMesh(m, "lobe");
  ASSERT_FALSE(atlas.empty());
  for (const glm::vec3& dir : {glm::vec3(1.1f, 1, 0.9f), glm::vec3(-1.3f, 1, -0.4f), glm::vec3(0.2f, 1, 1.2f)}) {
    const glm::vec3 l = glm::normalize(dir);
    nlohmann::json j = groundScene(l, style(Method::kMap), {{{"position", {0, 1.5, 0}}, {"size", 3.0}}});
    j["atlas"] = atlas.string();
    const core::Image ref = render(j, Method::kReference);
    ASSERT_EQ(ref.width, kPx);
    // The ground away from the puff seen from above (its bounding circle and ink).
    auto counted = [&](int x, int y) { return glm::length(ground(x, y)) > 1.5f + 3.0f / kPxPerUnit; };
    const std::vector<bool> refMask = shadowMask(ref, counted);
    EXPECT_GT(std::count(refMask.begin(), refMask.end(), true), 150);
    for (Method m2 : {Method::kMap, Method::kVolumes}) {
      j["style"]["shadowMethod"] = m2 == Method::kMap ? "map" : "volumes";
      const core::Image im = render(j, m2);
      ASSERT_EQ(im.width, kPx);
      const double iou = shadowIoU(
          im, [&](int x, int y) { return bool(refMask[static_cast<std::size_t>(y) * kPx + x]); }, counted);
      std::printf("lobed puff lit toward (%.1f, %.1f, %.1f), %s: shadow IoU %.3f against the reference\n", dir.x, dir.y,
                  dir.z, name(m2).c_str(), iou);
      // Measured 0.84-0.95 for both methods; the lobe mirrored (the frame upside down) gives 0.64-0.70.
      EXPECT_GE(iou, 0.76) << name(m2) << " light " << l.x << "," << l.y << "," << l.z;
    }
  }
}

// A lumpy puff (a cluster of five spheres: bumps and hollows on every silhouette), baked at test
// time with its mesh on disk so the reference casts the mesh itself. Two things the sphere tests
// cannot see:
//  - it never shadows itself, though its lumps face each other: lit from eight sides, shadows on
//    change nothing (the map), or little along the terminator (the volumes, which start at the far
//    side the depth map gives, mirrored: a lumpy puff's back is not its front mirrored);
//  - its shadow on the ground has the shape of its silhouette, as the reference's mesh casts it,
//    not a disc of its radius (a displaced sphere would not do: seen from any side, its lumps fill
//    out a nearly round silhouette).
TEST_F(ShadowMethods, ALumpyPuffNeverShadowsItselfAndCastsItsOwnShape) {
  mesh::ClusterParams cp;
  cp.count = 5;
  cp.radiusMin = 0.3f;
  cp.radiusMax = 0.5f;
  cp.spread = 0.7f;
  cp.seed = 11;
  mesh::TriMesh m = mesh::generateCluster(cp);
  mesh::normalizeToUnitSphere(m);
  const std::filesystem::path atlas = bakeMesh(m, "lumpy");
  ASSERT_FALSE(atlas.empty());
  const nlohmann::json particles = {{{"position", {0, 1.5, 0}}, {"size", 3.0}}};

  for (Method method : {Method::kMap, Method::kVolumes}) {
    for (const glm::vec3& dir : {glm::vec3(1, 0.3f, 0), glm::vec3(-1, 0.6f, 0.2f), glm::vec3(0, 1, 0),
                                 glm::vec3(0.3f, 0.4f, 1), glm::vec3(0.2f, 0.5f, -1), glm::vec3(1, -0.4f, 1),
                                 glm::vec3(-0.6f, 1, -0.6f), glm::vec3(0.7f, 0.1f, -0.7f)}) {
      nlohmann::json j = groundScene(glm::normalize(dir), style(method), particles);
      j["atlas"] = atlas.string();
      const auto [differ, puff] = selfShadow(j, method);
      EXPECT_GT(puff, 800);
      // Measured for the volumes: 0 to 75 of 1,015 pixels (7.4%, lit from a low side); 0 from
      // straight above. A volume started in front of its puff shades half of it.
      std::printf("cluster puff lit toward (%.1f, %.1f, %.1f), %s: %d of %d pixels self-shadowed\n", dir.x, dir.y,
                  dir.z, name(method).c_str(), differ, puff);
      EXPECT_LE(differ, method == Method::kVolumes ? puff / 10 : 0)
          << name(method) << " light " << dir.x << "," << dir.y << "," << dir.z;
    }
  }

  const nlohmann::json high = {{{"position", {0, 3.5, 0}}, {"size", 2.4}}};
  for (float azimuth : {0.0f, 100.0f, 230.0f}) {
    const float el = glm::radians(58.0f), az = glm::radians(azimuth);
    const glm::vec3 l(std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az));
    nlohmann::json j = groundScene(l, style(Method::kMap), high);
    j["atlas"] = atlas.string();
    const core::Image ref = render(j, Method::kReference);
    ASSERT_EQ(ref.width, kPx);
    // The ground away from the puff seen from above (within its bounding circle and ink).
    auto counted = [&](int x, int y) { return glm::length(ground(x, y)) > 1.2f + 3.0f / kPxPerUnit; };
    const std::vector<bool> refMask = shadowMask(ref, counted);
    const auto refCount = static_cast<int>(std::count(refMask.begin(), refMask.end(), true));
    EXPECT_GT(refCount, 150) << "azimuth " << azimuth;
    for (Method m2 : {Method::kMap, Method::kVolumes}) {
      j["style"]["shadowMethod"] = m2 == Method::kMap ? "map" : "volumes";
      const core::Image im = render(j, m2);
      ASSERT_EQ(im.width, kPx);
      const double iou = shadowIoU(
          im, [&](int x, int y) { return bool(refMask[static_cast<std::size_t>(y) * kPx + x]); }, counted);
      std::printf("lumpy shadow, azimuth %.0f, %s: IoU %.3f against the reference (%d px)\n", azimuth, name(m2).c_str(),
                  iou, refCount);
      // The eye's view of the silhouette stands for the light's, 32 degrees away: measured 0.70-0.80
      // for both methods. A round silhouette of the puff's radius (the volumes cut by a constant
      // radius) gives 0.43-0.46.
      EXPECT_GE(iou, 0.6) << name(m2) << " azimuth " << azimuth;
    }
  }
}

// chooseShadowMap: texels per world unit = scale x the eye's pixels per world unit at the casters'
// centre; capped by maxSize (evenly), at least 16 a side; nothing to cast: a map that shadows nothing.
TEST(ShadowMapPlan, ResolutionFollowsTheScreenAndIsCapped) {
  cel::Camera cam;
  cam.position = {0, 0, 10};
  cam.target = {0, 0, 0};
  cam.fovYDegrees = 0.0f;
  cam.orthoHeight = 8.0f;
  cel::Frame eye = test::linearFrame(cam, 256, 128);
  eye.light.direction = {0, 0, 1};  // along the view: the map's plane is the screen's
  cel::Style st;
  cel::Bounds box;
  box.add(glm::vec3(-1, -1, -1));
  box.add(glm::vec3(1, 1, 1));
  const cel::ShadowMapPlan p = cel::chooseShadowMap(eye, box, st);
  EXPECT_NEAR(p.texelsPerUnit, 128.0f / 8.0f, 1e-3f);  // 16 pixels per unit
  EXPECT_EQ(p.width, 32);
  EXPECT_EQ(p.height, 32);
  EXPECT_TRUE(p.lookup.enabled);
  st.shadowMapScale = 4.0f;
  const cel::ShadowMapPlan fine = cel::chooseShadowMap(eye, box, st, 100);
  EXPECT_EQ(fine.width, 100);                     // 128 wanted, capped (a texel spare for the lattice)
  EXPECT_NEAR(fine.texelsPerUnit, 49.5f, 1e-3f);  // 99 texels over the box's 2 units
  // The corners of the box land inside the map, and its middle in the middle.
  const glm::vec4 c = p.lookup.worldToMap * glm::vec4(0, 0, 0, 1);
  EXPECT_NEAR(c.x, 0.0f, 1e-5f);
  EXPECT_NEAR(c.y, 0.0f, 1e-5f);
  for (int i = 0; i < 8; ++i) {
    const glm::vec4 k = p.lookup.worldToMap * glm::vec4((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1, 1);
    EXPECT_LE(std::abs(k.x), 1.0f + 1e-5f);
    EXPECT_LE(std::abs(k.y), 1.0f + 1e-5f);
    EXPECT_GT(k.z, -1.0f);
    EXPECT_LT(k.z, 1.0f);
  }
  // A tolerance of one texel; the length in map depth units.
  const float depthRange = p.light.farPlane - p.light.nearPlane;
  EXPECT_NEAR(p.lookup.tolerance * depthRange, 1.0f / 16.0f, 1e-4f);
  EXPECT_NEAR(p.lookup.length * depthRange, st.shadowLength, 1e-3f);
  // Perspective: pixels per unit at the centre's distance.
  cam.fovYDegrees = 90.0f;
  const cel::Frame persp = test::linearFrame(cam, 128, 128);
  st.shadowMapScale = 1.0f;
  // 6.4 pixels per unit, rounded to a quarter octave: 2^(11/4) = 6.73.
  EXPECT_NEAR(cel::chooseShadowMap(persp, box, st).texelsPerUnit, std::exp2(11.0f / 4.0f), 1e-3f);
  // The lattice is fixed to the world: casters moved by 10.3 texels along x move the region by whole
  // texels, and the resolution does not change.
  cel::Bounds moved;
  moved.add(glm::vec3(-1 + 10.3f / 16.0f, -1, -1));
  moved.add(glm::vec3(1 + 10.3f / 16.0f, 1, 1));
  const cel::ShadowMapPlan q = cel::chooseShadowMap(eye, moved, st);
  EXPECT_EQ(q.texelsPerUnit, p.texelsPerUnit);
  const glm::vec4 a = p.lookup.worldToMap * glm::vec4(0.5f, 0.25f, 0, 1);
  const glm::vec4 b = q.lookup.worldToMap * glm::vec4(0.5f, 0.25f, 0, 1);
  // The same world point's texel coordinates in both maps differ by whole texels.
  auto texel = [](const glm::vec4& ndc, const cel::ShadowMapPlan& plan) {
    return glm::vec2((ndc.x * 0.5f + 0.5f) * plan.width, (ndc.y * 0.5f + 0.5f) * plan.height);
  };
  const glm::vec2 shift = texel(a, p) - texel(b, q);
  EXPECT_NEAR(shift.x, std::round(shift.x), 2e-3f) << "whole texels";
  EXPECT_NEAR(std::abs(shift.x), 10.0f, 1.0f);
  EXPECT_NEAR(shift.y, 0.0f, 2e-3f);
  EXPECT_FALSE(cel::chooseShadowMap(eye, cel::Bounds{}, st).lookup.enabled);
}

class ObjectShadows : public ShadowMethods, public ::testing::WithParamInterface<Method> {};

// A thin square slab (side S, 0.02 thick: a box's scale is its half extents; at height H) between the light and the
// ground: its shadow is the square moved H l_xz / l_y across the ground (its thickness adds under a pixel at these
// angles).
TEST_P(ObjectShadows, AnObjectShadowsTheGround) {
  const Method m = GetParam();
  const float S = 1.5f, H = 1.5f;
  for (const glm::vec3& dir : {glm::vec3(0.5f, 1, 0.2f), glm::vec3(-0.3f, 1, -0.6f)}) {
    const glm::vec3 l = glm::normalize(dir);
    const nlohmann::json slab = {
        {{"type", "box"}, {"translate", {0, H, 0}}, {"scale", {0.5 * S, 0.01, 0.5 * S}}, {"albedo", {1, 1, 1}}}};
    const core::Image im = render(groundScene(l, style(m), nlohmann::json::array(), slab), m);
    ASSERT_EQ(im.width, kPx);
    const glm::vec2 shift = -H * glm::vec2(l.x, l.z) / l.y;
    auto inside = [&](int x, int y) {
      const glm::vec2 d = ground(x, y) - shift;
      return std::abs(d.x) < 0.5f * S && std::abs(d.y) < 0.5f * S;
    };
    auto counted = [&](int x, int y) {
      const glm::vec2 g = ground(x, y), d = g - shift;
      if (std::abs(g.x) < 0.5f * S + 0.1f && std::abs(g.y) < 0.5f * S + 0.1f) return false;  // the slab itself
      const float edge = std::min(std::abs(std::abs(d.x) - 0.5f * S), std::abs(std::abs(d.y) - 0.5f * S));
      return edge > 1.5f / kPxPerUnit;
    };
    int predicted = 0;
    const double iou = shadowIoU(im, inside, counted, &predicted);
    EXPECT_GT(predicted, 100);
    EXPECT_GE(iou, 0.9) << name(m) << " light " << l.x << "," << l.y << "," << l.z;
  }
}

// A slab, or a plane (which the map leaves out of its fit but must still draw: its depth range
// reaches it), straight above a puff, light from above: the puff's visible top is in its shadow
// (ambient only); without it the puff is lit.
TEST_P(ObjectShadows, AnObjectShadowsAPuff) {
  const Method m = GetParam();
  for (const char* kind : {"box", "plane"}) {
    SCOPED_TRACE(kind);
    const nlohmann::json slab = {
        {{"type", kind}, {"translate", {0, 3, 0}}, {"scale", {3, 0.05, 3}}, {"albedo", {1, 1, 1}}}};
    const nlohmann::json puff = {{{"position", {0, 1, 0}}, {"size", 1.6}}};
    nlohmann::json j = groundScene(glm::vec3(0.05f, 1, 0.1f), style(m, {{"shading", false}}), puff, slab);
    // Seen from the side, below the slab.
    j["camera"] = {{"position", {0, 1, 10}}, {"target", {0, 1, 0}}, {"fovY", 0},
                   {"orthoHeight", 8},       {"near", 1},           {"far", 20}};
    const core::Image with = render(j, m);
    j["objects"] = nlohmann::json::array({j["objects"][1]});  // the ground alone
    const core::Image without = render(j, m);
    ASSERT_EQ(with.width, kPx);
    int puffPixels = 0, darkened = 0;
    for (int y = 0; y < kPx; ++y) {
      for (int x = 0; x < kPx; ++x) {
        const glm::vec2 w((x + 0.5f - 64.0f) / kPxPerUnit, 1.0f - (y + 0.5f - 64.0f) / kPxPerUnit);
        if (glm::length(w - glm::vec2(0, 1)) > 0.7f) continue;  // inside the puff's disc, off its ink
        ++puffPixels;
        darkened += with.at(x, y, 0) < without.at(x, y, 0) - 0.1f;
      }
    }
    EXPECT_GT(puffPixels, 300);
    EXPECT_GT(darkened, 0.95 * puffPixels) << name(m);
  }
}

INSTANTIATE_TEST_SUITE_P(MapAndReference, ObjectShadows, ::testing::Values(Method::kMap, Method::kReference),
                         [](const auto& p) { return name(p.param); });

}  // namespace
}  // namespace puff
