// Where a shadow falls on a puff, by every method: the receiving point is the puff's surface as
// its depth map gives it, not its billboard plane, so a puff's shadow on another puff is where the light's
// cylinder through the caster meets the receiver's visible surface. Checked against ray-sphere geometry with
// an orthographic and a perspective camera, so both ways the map method rebuilds the receiving point from the
// depth offset (cel/nailboard_fs.glsl) are covered.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/volume_clip.h>
#include <puff/core/image.h>
#include <puff/eval/cel_reference.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "support/assert_ok.h"
#include "support/display.h"
#include "support/linear_frame.h"
#include "support/sphere_atlas.h"

namespace puff::shadow_receivers {
namespace {

constexpr int kPx = 128;

enum class Method { kVolumes, kMap, kReference };
enum class Lens { kOrthographic, kPerspective };

struct Case {
  Method method;
  Lens lens;
};

std::string name(Method m) { return m == Method::kVolumes ? "volumes" : m == Method::kMap ? "map" : "reference"; }

std::string caseName(const Case& c) { return name(c.method) + (c.lens == Lens::kOrthographic ? "_ortho" : "_persp"); }

struct MethodName {
  std::string operator()(const ::testing::TestParamInfo<Method>& info) const { return name(info.param); }
};

struct CaseName {
  std::string operator()(const ::testing::TestParamInfo<Case>& info) const { return caseName(info.param); }
};

// The camera: on +z looking at (0, 1, 0), up +y. Orthographic: 6 units tall; perspective: 40 degrees.
constexpr glm::vec3 kEye(0.0f, 1.0f, 8.0f), kTarget(0.0f, 1.0f, 0.0f);
constexpr float kOrthoHeight = 6.0f, kFovY = 40.0f;

// One frame of scene `j` (its atlas path relative to the suite's scratch directory) by method `m`, in display
// values.
core::Image render(const std::filesystem::path& dir, const nlohmann::json& j, Method m) {
  auto parsed = scene::parseScene(j, dir / "scene.json");
  EXPECT_OK(parsed);
  if (!parsed) return {};
  auto renderer = eval::createRenderer(
      *parsed, m == Method::kReference ? render::RenderPath::kReference : render::RenderPath::kCel);
  EXPECT_OK(renderer);
  if (!renderer) return {};
  auto image = (*renderer)->renderFrame(0);
  EXPECT_OK(image);
  return image ? test::display(*image) : core::Image{};
}

class ShadowReceivers : public test::SphereAtlasTest, public ::testing::WithParamInterface<Case> {
 protected:
  static nlohmann::json scene(const Case& c, const glm::vec3& light, const nlohmann::json& particles) {
    const nlohmann::json camera = c.lens == Lens::kOrthographic
                                      ? nlohmann::json{{"position", {kEye.x, kEye.y, kEye.z}},
                                                       {"target", {kTarget.x, kTarget.y, kTarget.z}},
                                                       {"up", {0, 1, 0}},
                                                       {"fovY", 0},
                                                       {"orthoHeight", kOrthoHeight},
                                                       {"near", 1},
                                                       {"far", 20}}
                                      : nlohmann::json{{"position", {kEye.x, kEye.y, kEye.z}},
                                                       {"target", {kTarget.x, kTarget.y, kTarget.z}},
                                                       {"up", {0, 1, 0}},
                                                       {"fovY", kFovY},
                                                       {"near", 1},
                                                       {"far", 20}};
    // Flat shading and no ink: a lit puff pixel is K_a + C K_L = 0.7, a shadowed one K_a = 0.2.
    return {{"output", {{"width", kPx}, {"height", kPx}, {"samples", 1}, {"background", {0.9, 0.9, 0.9}}}},
            {"camera", camera},
            {"light", {{"direction", {light.x, light.y, light.z}}, {"color", {0.5, 0.5, 0.5}}}},
            {"ambient", {{"color", {0.2, 0.2, 0.2}}}},
            {"atlas", sidecar_.string()},
            {"style",
             {{"preset", "cel-shadows"},
              {"shadowMethod", c.method == Method::kMap ? "map" : "volumes"},
              {"shading", false},
              {"outlines", false},
              {"shadowLength", 30}}},
            {"objects", nlohmann::json::array()},
            {"particles", particles}};
  }

  // The eye ray through image point (px, py) (pixels, row 0 at the top): origin and unit direction.
  static void ray(Lens lens, float px, float py, glm::vec3& origin, glm::vec3& dir) {
    const glm::vec2 ndc(2.0f * px / kPx - 1.0f, 1.0f - 2.0f * py / kPx);
    const glm::vec3 forward = glm::normalize(kTarget - kEye), right(1, 0, 0), up(0, 1, 0);
    if (lens == Lens::kOrthographic) {
      origin = kEye + 0.5f * kOrthoHeight * (ndc.x * right + ndc.y * up);
      dir = forward;
    } else {
      const float t = std::tan(0.5f * glm::radians(kFovY));
      origin = kEye;
      dir = glm::normalize(forward + t * (ndc.x * right + ndc.y * up));
    }
  }

  // Where the eye ray (origin o, unit direction d) meets the sphere (centre c, radius r), if it does `inset`
  // inside its rim (the ray's closest approach to the centre is at most r - inset).
  static std::optional<glm::vec3> sphereHit(const glm::vec3& o, const glm::vec3& d, const glm::vec3& c, float r,
                                            float inset) {
    const float b = glm::dot(c - o, d);
    const glm::vec3 closest = o + b * d;
    const float h2 = glm::dot(closest - c, closest - c);
    if (h2 > (r - inset) * (r - inset)) return std::nullopt;
    return closest - std::sqrt(r * r - h2) * d;
  }

  // The nailboard's surface point on the same ray (McGuire & Fein 4.2): the ray meets the billboard plane
  // (view-plane aligned: z = c.z here) at B, and the pixel lies on the ray at B's view-axis distance less the
  // baked depth offset there, sqrt(r^2 - |B - c|^2). With an orthographic camera this is the sphere's own
  // surface; in perspective it is not (here up to about 0.2 units off).
  static std::optional<glm::vec3> nailboardHit(const glm::vec3& o, const glm::vec3& d, const glm::vec3& c, float r,
                                               float inset) {
    const glm::vec3 b = o + ((c.z - o.z) / d.z) * d;
    const float rho = glm::length(glm::vec2(b - c));
    if (rho > r - inset) return std::nullopt;
    const float offset = std::sqrt(r * r - rho * rho),
                dist = o.z - c.z;  // the camera looks along -z
    return o + (b - o) * ((dist - offset) / dist);
  }
};

// A small puff (radius r) above and in front of a large one (radius R), the light from above (a little
// tilted): the small puff's shadow is the cylinder of radius r along the light through its centre, and it
// darkens the large puff's visible surface exactly where the cylinder meets it: two bands across the face,
// above and below its middle, and nowhere on its billboard plane (z = 0 lies outside the cylinder, which runs
// at z = 0.9 +- 0.5). The pixels within 1.5 pixels of the band's edge and of the large puff's rim are not
// counted; of the rest at least 98% agree (measured: 99.3% to 100%).
TEST_P(ShadowReceivers, APuffsShadowFallsOnAnotherPuffsSurface) {
  const Case c = GetParam();
  const float R = 1.5f, r = 0.5f;
  const glm::vec3 lower(0.0f, 0.0f, 0.0f), upper(0.0f, 2.7f, 0.9f);
  const glm::vec3 l = glm::normalize(glm::vec3(0.05f, 1.0f, 0.03f));
  const nlohmann::json small = {{"position", {upper.x, upper.y, upper.z}}, {"size", 2 * r}};
  const nlohmann::json large = {{"position", {lower.x, lower.y, lower.z}}, {"size", 2 * R}};
  // 1: the large puff's visible surface at image point (px, py) lies in the small puff's shadow; 0: it does
  // not; -1: the ray misses the large puff (or grazes its rim).
  auto predicted = [&](float px, float py) {
    glm::vec3 o, d;
    ray(c.lens, px, py, o, d);
    const float inset = 3.0f * kOrthoHeight / kPx;
    const auto p =
        c.method == Method::kReference ? sphereHit(o, d, lower, R, inset) : nailboardHit(o, d, lower, R, inset);
    if (!p) return -1;
    const glm::vec3 v = *p - upper;
    const float along = glm::dot(v, l);  // < 0: below the caster, toward where the light goes
    return along < 0.0f && glm::length(v - along * l) < r ? 1 : 0;
  };
  // Both orders: the caster ids follow the particles' indices (the first is id 1), so a caster or a receiver
  // that is particle 0 is checked too. (The reference, seconds a frame, takes one.)
  for (const bool smallFirst : {true, false}) {
    if (c.method == Method::kReference && !smallFirst) continue;
    const std::string what = caseName(c) + (smallFirst ? ", caster first" : ", receiver first");
    nlohmann::json j = scene(c, l, smallFirst ? nlohmann::json{small, large} : nlohmann::json{large, small});
    const core::Image with = render(dir_, j, c.method);
    j["style"]["shadows"] = false;
    const core::Image without = render(dir_, j, c.method);
    ASSERT_EQ(with.width, kPx);
    ASSERT_EQ(without.width, kPx);
    int both = 0, either = 0, expected = 0, counted = 0;
    for (int y = 0; y < kPx; ++y) {
      for (int x = 0; x < kPx; ++x) {
        const float px = x + 0.5f, py = y + 0.5f;
        const int centre = predicted(px, py);
        if (centre < 0) continue;
        bool sure = true;
        for (const glm::vec2 o : {glm::vec2(1.5f, 0), glm::vec2(-1.5f, 0), glm::vec2(0, 1.5f), glm::vec2(0, -1.5f)}) {
          sure = sure && predicted(px + o.x, py + o.y) == centre;
        }
        if (!sure) continue;
        ++counted;
        const bool a = centre == 1;
        const bool b = with.at(x, y, 0) < without.at(x, y, 0) - 0.1f;
        both += a && b;
        either += a || b;
        expected += a;
      }
    }
    const double iou = either == 0 ? 1.0 : static_cast<double>(both) / either;
    std::printf("%s: shadow IoU %.3f (%d predicted, %d counted)\n", what.c_str(), iou, expected, counted);
    EXPECT_GT(counted, 1500) << what;
    EXPECT_GT(expected, 200) << what;
    EXPECT_GE(iou, 0.98) << what << ": " << both << " of " << either << " pixels agree, " << expected << " predicted";
  }
}

// The shadow starts the bias past the caster's far side (Style::shadowBias, diameters; the far side mirrors
// the near side the depth map gives: sqrt(r^2 - rho^2) behind the centre at rho from the light's axis
// through it). With a bias of half a diameter and the small puff just above the large one, the top of the
// band the cylinder cuts on the large puff lies nearer the caster than that and stays lit; lower down it is
// dark. (The reference has no such bias: its shadow starts a map texel past the caster's surface.)
class ShadowBias : public ShadowReceivers {};  // the cel methods only: the reference has no bias

TEST_P(ShadowBias, AShadowStartsTheBiasPastTheCastersFarSide) {
  const Case c = GetParam();
  const float R = 1.5f, r = 0.5f, bias = 0.5f;
  const glm::vec3 lower(0.0f, 0.0f, 0.0f), upper(0.0f, 2.0f, 0.9f);
  const glm::vec3 l = glm::normalize(glm::vec3(0.05f, 1.0f, 0.03f));
  auto predicted = [&](float px, float py) {
    glm::vec3 o, d;
    ray(c.lens, px, py, o, d);
    const auto p = nailboardHit(o, d, lower, R, 3.0f * kOrthoHeight / kPx);
    if (!p) return -1;
    const glm::vec3 v = *p - upper;
    const float along = glm::dot(v, l);
    const float rho = glm::length(v - along * l);
    return rho < r && -along > std::sqrt(r * r - rho * rho) + bias * 2.0f * r ? 1 : 0;
  };
  nlohmann::json j = scene(c, l,
                           {{{"position", {upper.x, upper.y, upper.z}}, {"size", 2 * r}},
                            {{"position", {lower.x, lower.y, lower.z}}, {"size", 2 * R}}});
  j["style"]["shadowBias"] = bias;
  const core::Image with = render(dir_, j, c.method);
  j["style"]["shadows"] = false;
  const core::Image without = render(dir_, j, c.method);
  ASSERT_EQ(with.width, kPx);
  ASSERT_EQ(without.width, kPx);
  int both = 0, either = 0, expected = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const float px = x + 0.5f, py = y + 0.5f;
      const int centre = predicted(px, py);
      if (centre < 0) continue;
      bool sure = true;
      for (const glm::vec2 o : {glm::vec2(1.5f, 0), glm::vec2(-1.5f, 0), glm::vec2(0, 1.5f), glm::vec2(0, -1.5f)}) {
        sure = sure && predicted(px + o.x, py + o.y) == centre;
      }
      if (!sure) continue;
      const bool a = centre == 1;
      const bool b = with.at(x, y, 0) < without.at(x, y, 0) - 0.1f;
      both += a && b;
      either += a || b;
      expected += a;
    }
  }
  const double iou = either == 0 ? 1.0 : static_cast<double>(both) / either;
  std::printf("%s: shadow past a bias of %g diameters IoU %.3f (%d predicted)\n", caseName(c).c_str(), bias, iou,
              expected);
  EXPECT_GT(expected, 100) << caseName(c);
  EXPECT_GE(iou, 0.95) << caseName(c);
}

INSTANTIATE_TEST_SUITE_P(
    AllMethods, ShadowReceivers,
    ::testing::Values(Case{Method::kVolumes, Lens::kOrthographic}, Case{Method::kVolumes, Lens::kPerspective},
                      Case{Method::kMap, Lens::kOrthographic}, Case{Method::kMap, Lens::kPerspective},
                      Case{Method::kReference, Lens::kOrthographic}, Case{Method::kReference, Lens::kPerspective}),
    CaseName{});
INSTANTIATE_TEST_SUITE_P(CelMethods, ShadowBias,
                         ::testing::Values(Case{Method::kVolumes, Lens::kOrthographic},
                                           Case{Method::kVolumes, Lens::kPerspective},
                                           Case{Method::kMap, Lens::kOrthographic},
                                           Case{Method::kMap, Lens::kPerspective}),
                         CaseName{});

// Opaque objects as receivers and casters (the map, the volumes and the reference), seen from above with an
// orthographic camera (16 pixels per unit, image top = -z) over a white ground plane; light K_L 0.5, ambient
// 0.2: lit ground 0.7, shadowed 0.2 (display values).
class ObjectReceivers : public test::SphereAtlasTest, public ::testing::WithParamInterface<Method> {
 protected:
  static constexpr float kPxPerUnit = 16.0f;

  static nlohmann::json groundScene(Method m, const glm::vec3& light, nlohmann::json objects) {
    objects.push_back({{"type", "plane"}, {"name", "ground"}, {"scale", {12, 1, 12}}, {"albedo", {1, 1, 1}}});
    return {
        {"output", {{"width", kPx}, {"height", kPx}, {"samples", 1}}},
        {"camera",
         {{"position", {0, 10, 0}},
          {"target", {0, 0, 0}},
          {"up", {0, 0, -1}},
          {"fovY", 0},
          {"orthoHeight", 8},
          {"near", 1},
          {"far", 20}}},
        {"light", {{"direction", {light.x, light.y, light.z}}, {"color", {0.5, 0.5, 0.5}}}},
        {"ambient", {{"color", {0.2, 0.2, 0.2}}}},
        {"atlas", sidecar_.string()},
        {"style",
         {{"preset", "cel-shadows"}, {"shadowMethod", m == Method::kMap ? "map" : "volumes"}, {"shadowLength", 30}}},
        {"objects", objects},
        {"particles", nlohmann::json::array()}};
  }

  // World x, z of pixel (x, y) on the ground.
  static glm::vec2 ground(int x, int y) {
    return {(x + 0.5f - kPx / 2.0f) / kPxPerUnit, (y + 0.5f - kPx / 2.0f) / kPxPerUnit};
  }
};

// A box standing on the ground (1 x 1.5 x 1, its base on y = 0) casts the shadow the light projects: the
// ground points whose ray toward the light meets the box. The shadow starts at the box's base (no lit gap
// between the box and its shadow on the far side from the light) and the ground next to its lit sides stays
// lit (no dark rim): both checked on the ring of ground 1.5 to 4 pixels from the box, which the box's own top
// face does not cover.
TEST_P(ObjectReceivers, ABoxOnTheGroundCastsItsShadowFromItsBase) {
  const Method m = GetParam();
  const glm::vec3 half(0.5f, 0.75f, 0.5f);
  for (const glm::vec3& dir : {glm::vec3(0.8f, 1.0f, 0.45f), glm::vec3(-0.5f, 0.7f, -0.9f)}) {
    const glm::vec3 l = glm::normalize(dir);
    const nlohmann::json box = {
        {{"type", "box"}, {"translate", {0, half.y, 0}}, {"scale", {half.x, half.y, half.z}}, {"albedo", {1, 1, 1}}}};
    const core::Image im = render(dir_, groundScene(m, l, box), m);
    ASSERT_EQ(im.width, kPx);
    // Whether the ray from ground point g toward the light meets the box (slab test).
    auto shadowedAt = [&](const glm::vec2& g) {
      const glm::vec3 o(g.x, 0.0f, g.y), lo(-half.x, 0.0f, -half.z), hi(half.x, 2.0f * half.y, half.z);
      float t0 = 0.0f, t1 = 1e30f;
      for (int k = 0; k < 3; ++k) {
        if (std::abs(l[k]) < 1e-9f) {
          if (o[k] < lo[k] || o[k] > hi[k]) return false;
          continue;
        }
        const float ta = (lo[k] - o[k]) / l[k], tb = (hi[k] - o[k]) / l[k];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
      }
      return t1 > t0;
    };
    // Distance on the ground from the box's footprint, in pixels.
    auto fromBox = [&](const glm::vec2& g) {
      const glm::vec2 d = glm::max(glm::abs(g) - glm::vec2(half.x, half.z), glm::vec2(0.0f));
      return glm::length(d) * kPxPerUnit;
    };
    int both = 0, either = 0, expected = 0, ringDark = 0, ringDarkOk = 0, ringLit = 0, ringLitOk = 0;
    for (int y = 0; y < kPx; ++y) {
      for (int x = 0; x < kPx; ++x) {
        const glm::vec2 g = ground(x, y);
        const float away = fromBox(g);
        if (away <= 1.5f) continue;  // the box's top face and its edge
        const bool a = shadowedAt(g);
        bool sure = true;
        for (const glm::vec2 o : {glm::vec2(1.5f, 0), glm::vec2(-1.5f, 0), glm::vec2(0, 1.5f), glm::vec2(0, -1.5f)}) {
          sure = sure && shadowedAt(g + o / kPxPerUnit) == a;
        }
        if (!sure) continue;
        const bool b = std::abs(im.at(x, y, 0) - 0.2f) < 0.1f;
        both += a && b;
        either += a || b;
        expected += a;
        if (away <= 4.0f) {
          (a ? ringDark : ringLit)++;
          (a ? ringDarkOk : ringLitOk) += a == b;
        }
      }
    }
    const double iou = either == 0 ? 1.0 : static_cast<double>(both) / either;
    const std::string what =
        name(m) + " light " + std::to_string(l.x) + "," + std::to_string(l.y) + "," + std::to_string(l.z);
    std::printf(
        "%s: box shadow IoU %.3f; ring by the box: %d of %d dark, %d "
        "of %d lit\n",
        what.c_str(), iou, ringDarkOk, ringDark, ringLitOk, ringLit);
    EXPECT_GT(expected, 200) << what;
    EXPECT_GE(iou, 0.9) << what;
    EXPECT_GT(ringDark, 40) << what;
    EXPECT_GT(ringLit, 40) << what;
    EXPECT_GE(ringDarkOk, 0.95 * ringDark) << what << ": a gap between the box and its shadow";
    EXPECT_GE(ringLitOk, 0.95 * ringLit) << what << ": a dark rim by the box's lit sides";
  }
}

// An object never shadows itself: a sphere and a turned box (smooth Lambert shading, so light falling at a
// slant shows, where the cel ramp's darkest band would hide it), lit from several sides of the camera's, show
// every pixel the light reaches at N.L >= 0.25 the same with shadows on as off. The objects stand apart, so
// neither shadows the other's visible side from these lights.
TEST_P(ObjectReceivers, AnObjectNeverShadowsItself) {
  const Method m = GetParam();
  const nlohmann::json objects = {{{"type", "sphere"},
                                   {"translate", {-1.6, 1.2, 0}},
                                   {"scale", {1, 1, 1}},
                                   {"albedo", {1, 1, 1}},
                                   {"shading", "smooth"}},
                                  {{"type", "box"},
                                   {"translate", {1.6, 0.8, 0}},
                                   {"rotate", {20, 35, 10}},
                                   {"scale", {0.7, 0.7, 0.7}},
                                   {"albedo", {1, 1, 1}},
                                   {"shading", "smooth"}}};
  int lightIndex = 0;
  for (const glm::vec3& dir : {glm::vec3(0.3f, 1.0f, 0.5f), glm::vec3(0.1f, 0.5f, 1.0f), glm::vec3(-0.6f, 0.8f, 0.7f),
                               glm::vec3(0.9f, 0.6f, 0.6f)}) {
    ++lightIndex;
    if (m == Method::kReference && lightIndex % 2 == 0) continue;  // seconds a frame: every other light
    nlohmann::json j = groundScene(m, glm::normalize(dir), objects);
    j["objects"] = objects;  // no ground: nothing but the objects themselves to shadow them
    j["camera"] = {{"position", {0, 4, 9}}, {"target", {0, 1, 0}}, {"fovY", 35}, {"near", 1}, {"far", 30}};
    const core::Image with = render(dir_, j, m);
    j["style"]["shadows"] = false;
    const core::Image without = render(dir_, j, m);
    ASSERT_EQ(with.width, kPx);
    ASSERT_EQ(without.width, kPx);
    int lit = 0, differ = 0;
    for (int y = 0; y < kPx; ++y) {
      for (int x = 0; x < kPx; ++x) {
        if (without.at(x, y, 0) < 0.2f + 0.5f * 0.25f || std::abs(without.at(x, y, 0) - without.at(0, 0, 0)) < 1e-3f)
          continue;  // N.L under 0.25 (where a mesh's interpolated normals disagree with its faces), or the background
        ++lit;
        differ += std::abs(with.at(x, y, 0) - without.at(x, y, 0)) > 2.0f / 255.0f;
      }
    }
    std::printf("%s light %d: %d of %d lit object pixels differ with shadows on\n", name(m).c_str(), lightIndex, differ,
                lit);
    EXPECT_GT(lit, 1000) << name(m);
    EXPECT_EQ(differ, 0) << name(m) << " light " << dir.x << "," << dir.y << "," << dir.z;
  }
}

// A slab (2 x 0.02 x 1.5) 1.5 units above the ground casts the light's projection of it, whatever else casts
// in the scene: a cube far off to the side (its shadow off screen too) makes the map's depth range some 44
// units deep, and the slab's shadow, 1.7 units behind it along the light, stays.
TEST_P(ObjectReceivers, AShadowDoesNotDependOnWhatElseCasts) {
  const Method m = GetParam();
  const glm::vec3 l = glm::normalize(glm::vec3(0.5f, 1.0f, 0.2f));
  const float H = 1.5f;
  const glm::vec2 half(1.0f, 0.75f);
  const nlohmann::json objects = {
      {{"type", "box"}, {"translate", {0, H, 0}}, {"scale", {half.x, 0.01, half.y}}, {"albedo", {1, 1, 1}}},
      {{"type", "box"}, {"translate", {20, 10, 0}}, {"scale", {0.5, 0.5, 0.5}}, {"albedo", {1, 1, 1}}}};
  const core::Image im = render(dir_, groundScene(m, l, objects), m);
  ASSERT_EQ(im.width, kPx);
  const glm::vec2 shift = -H * glm::vec2(l.x, l.z) / l.y;
  auto inside = [&](const glm::vec2& g) {
    const glm::vec2 d = g - shift;
    return std::abs(d.x) < half.x && std::abs(d.y) < half.y;
  };
  int both = 0, either = 0, expected = 0;
  for (int y = 0; y < kPx; ++y) {
    for (int x = 0; x < kPx; ++x) {
      const glm::vec2 g = ground(x, y);
      if (std::abs(g.x) < half.x + 0.1f && std::abs(g.y) < half.y + 0.1f) continue;  // the slab itself
      const bool a = inside(g);
      bool sure = true;
      for (const glm::vec2 o : {glm::vec2(1.5f, 0), glm::vec2(-1.5f, 0), glm::vec2(0, 1.5f), glm::vec2(0, -1.5f)}) {
        sure = sure && inside(g + o / kPxPerUnit) == a;
      }
      if (!sure) continue;
      const bool b = std::abs(im.at(x, y, 0) - 0.2f) < 0.1f;
      both += a && b;
      either += a || b;
      expected += a;
    }
  }
  const double iou = either == 0 ? 1.0 : static_cast<double>(both) / either;
  std::printf("%s: slab shadow beside a far caster IoU %.3f (%d predicted)\n", name(m).c_str(), iou, expected);
  EXPECT_GT(expected, 100) << name(m);
  EXPECT_GE(iou, 0.9) << name(m);
}

// The cel methods and the reference apart: two ctest tests (one a suite), which -j runs side by side.
INSTANTIATE_TEST_SUITE_P(CelMethods, ObjectReceivers, ::testing::Values(Method::kVolumes, Method::kMap), MethodName{});
INSTANTIATE_TEST_SUITE_P(Reference, ObjectReceivers, ::testing::Values(Method::kReference), MethodName{});

// The volume passes' clip covers every pixel the receivers' box touches, partly covered ones too: an
// orthographic camera on +z (8 units tall over 128 pixels: 16 per unit, x = 0 at pixel 64) sees
// x from -1.03 to 2.03 as pixels 47.52 to 96.48, so the scissor runs from pixel 47 to 97 (exclusive).
// (opaque_volume_test's box lands on whole pixels, where rounding either way gives the same.)
TEST(VolumeClip, TakesInThePixelsTheBoxPartlyCovers) {
  cel::Camera cam;
  cam.position = glm::vec3(0, 0, 10);
  cam.target = glm::vec3(0);
  cam.fovYDegrees = 0.0f;
  cam.orthoHeight = 8.0f;
  cam.nearPlane = 1.0f;
  cam.farPlane = 21.0f;
  const cel::Frame f = test::linearFrame(cam, 128, 128);
  cel::Bounds b;
  b.add(glm::vec3(-1.03f, 0.0f, -3.0f));
  b.add(glm::vec3(2.03f, 1.0f, 4.0f));
  const cel::VolumeClip c = cel::volumeClip(f, b);
  ASSERT_FALSE(c.everything);
  ASSERT_FALSE(c.nothing);
  EXPECT_EQ(c.scissor.x, 47);
  EXPECT_EQ(c.scissor.width, 97 - 47);
  EXPECT_EQ(c.scissor.y, 64);
  EXPECT_EQ(c.scissor.height, 16);
}

}  // namespace
}  // namespace puff::shadow_receivers
