// The back-to-front sort key (media::SortKey): the power distance |c|^2 - r^2 against the centres'
// view-axis depth on two overlapping spheres of different radii (closed form), both keys stable,
// the orthographic analogue, the scene field /media/sort, and the renderer and the model
// reference ("renderer's order") both sorting by the key they are given.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include <puff/media/media.h>
#include <puff/reference/media_reference.h>
#include <puff/reference/metrics.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

#include "support/assert_ok.h"
#include "support/gl_fixture.h"
#include "support/media_target.h"

namespace puff {
namespace {

using media::SortKey;
using test::sphereAt;

// Two overlapping spheres in camera space (eye at the origin, looking down -z): A, large, centre
// depth 10; B, small, off to the side and 0.4 NEARER along the view axis. Their powers:
//   A: 0^2 + 0^2 + 10^2 - 3^2            = 91
//   B: 3.5^2 + 0^2 + 9.6^2 - 1.2^2       = 12.25 + 92.16 - 1.44 = 102.97
// so the power distance puts B behind A, the view depth A behind B.
const glm::vec3 kCentreA{0.0f, 0.0f, -10.0f}, kCentreB{3.5f, 0.0f, -9.6f};
constexpr float kRadiusA = 3.0f, kRadiusB = 1.2f;

// Where a ray from the eye along unit `d` enters the sphere (c, r): b - sqrt(b^2 - |c|^2 + r^2)
// with b = d.c; NaN when it misses.
double entry(const glm::dvec3& d, const glm::dvec3& c, double r) {
  const double b = glm::dot(d, c), disc = b * b - glm::dot(c, c) + r * r;
  return disc > 0.0 ? b - std::sqrt(disc) : std::nan("");
}

// A camera away from the origin, so the keys are computed from world positions through the view.
glm::mat4 turnedView() { return glm::lookAt(glm::vec3(2, 3, 7), glm::vec3(-1, 0.5f, -2), glm::vec3(0, 1, 0)); }

// The world position whose camera-space position under `view` is `c`.
glm::vec3 world(const glm::mat4& view, const glm::vec3& c) { return glm::vec3(glm::inverse(view) * glm::vec4(c, 1)); }

TEST(MediaSortKey, PowerDistanceOrdersOverlappingSpheresOfDifferentRadiiAsTheirSurfaces) {
  // The two spheres overlap (centres 3.523 apart, radii 4.2 together) and neither holds the other.
  ASSERT_LT(glm::distance(kCentreA, kCentreB), kRadiusA + kRadiusB);
  ASSERT_GT(glm::distance(kCentreA, kCentreB) + kRadiusB, kRadiusA);
  // Along the rays through the lens both cover (angles 0.234 .. 0.298 rad from -z towards +x),
  // A's surface comes first: A is in front and must be composited last. The power distance says
  // so; the centres' depths (A at 10, B at 9.6) say the opposite.
  for (double angle = 0.24; angle <= 0.295; angle += 0.005) {
    const glm::dvec3 d(std::sin(angle), 0.0, -std::cos(angle));
    const double a = entry(d, glm::dvec3(kCentreA), kRadiusA), b = entry(d, glm::dvec3(kCentreB), kRadiusB);
    ASSERT_FALSE(std::isnan(a) || std::isnan(b)) << angle;
    EXPECT_LT(a, b) << angle;
  }
  const glm::mat4 view = turnedView();
  const std::vector<media::Particle> ps = {sphereAt(world(view, kCentreA), kRadiusA),
                                           sphereAt(world(view, kCentreB), kRadiusB)};
  EXPECT_EQ(media::backToFront(view, ps, SortKey::kViewDepth), (std::vector<std::uint32_t>{0, 1}));
  EXPECT_EQ(media::backToFront(view, ps), (std::vector<std::uint32_t>{0, 1}));  // the default key
  EXPECT_EQ(media::backToFront(view, ps, SortKey::kPowerDistance), (std::vector<std::uint32_t>{1, 0}));
}

TEST(MediaSortKey, OrthographicPowerDistanceIsTheViewDepth) {
  // From an eye at infinity along +z the power order is the centres' depth order: the radical
  // plane's normal is c_A - c_B, and the eye lies on B's side iff B's centre is nearer.
  const glm::mat4 view = turnedView();
  std::vector<media::Particle> ps = {sphereAt(world(view, kCentreA), kRadiusA),
                                     sphereAt(world(view, kCentreB), kRadiusB)};
  EXPECT_EQ(media::backToFront(view, ps, SortKey::kPowerDistance, media::Projection::kOrthographic),
            (std::vector<std::uint32_t>{0, 1}));
  for (int i = 0; i < 500; ++i) {
    ps.push_back(sphereAt({static_cast<float>(i % 7), static_cast<float>(i % 5), -static_cast<float>(i % 23)},
                          0.1f + static_cast<float>(i % 11)));
  }
  EXPECT_EQ(media::backToFront(view, ps, SortKey::kPowerDistance, media::Projection::kOrthographic),
            media::backToFront(view, ps));
}

// The keys backToFront promises (ascending = farthest first), for a stable sort to compare with.
std::vector<double> expectedKeys(const glm::mat4& view, const std::vector<media::Particle>& ps, SortKey key) {
  std::vector<double> k;
  for (const media::Particle& p : ps) {
    const glm::dvec3 c(glm::dmat4(view) * glm::dvec4(glm::dvec3(p.position), 1.0));
    const double r = p.radius;
    k.push_back(key == SortKey::kViewDepth ? c.z : -(glm::dot(c, c) - r * r));
  }
  return k;
}

TEST(MediaSortKey, BothKeysSortStably) {
  // Equal keys keep their input order. View depth: the same depth at different x. Power distance:
  // |c|^2 - r^2 = 16 exactly for different centres and radii, in float and double.
  const glm::mat4 identity(1.0f);
  const std::vector<media::Particle> sameDepth = {sphereAt({1, 0, -5}, 1), sphereAt({0, 0, -9}, 1),
                                                  sphereAt({-2, 1, -5}, 3), sphereAt({0, 0, -2}, 1),
                                                  sphereAt({4, 4, -5}, 0.5f)};
  EXPECT_EQ(media::backToFront(identity, sameDepth, SortKey::kViewDepth), (std::vector<std::uint32_t>{1, 0, 2, 4, 3}));
  const std::vector<media::Particle> samePower = {sphereAt({0, 0, -5}, 3),    sphereAt({0, 0, -9}, 1),
                                                  sphereAt({0, 0, -4}, 0),    sphereAt({4, 0, -3}, 3),
                                                  sphereAt({0, 1, -1}, 0.5f), sphereAt({0, 3, -4}, 3)};
  // Powers: 16, 80, 16, 16, 1.75, 16.
  EXPECT_EQ(media::backToFront(identity, samePower, SortKey::kPowerDistance),
            (std::vector<std::uint32_t>{1, 0, 2, 3, 5, 4}));

  // Many particles on a coarse grid (many ties), the camera moved by whole units (so every key is
  // exact in float and double and the ties are real): both keys give what a stable comparison sort
  // of the promised key gives.
  std::vector<media::Particle> many;
  for (int i = 0; i < 20000; ++i) {
    many.push_back(sphereAt(
        {static_cast<float>((i * 7) % 9 - 4), static_cast<float>((i * 3) % 5 - 2), -static_cast<float>((i * 13) % 17)},
        0.25f * static_cast<float>((i * 5) % 8)));
  }
  const glm::mat4 view = glm::translate(glm::mat4(1.0f), glm::vec3(-1, 2, -3));
  for (SortKey key : {SortKey::kViewDepth, SortKey::kPowerDistance}) {
    SCOPED_TRACE(std::string(media::toString(key)));
    const std::vector<double> k = expectedKeys(view, many, key);
    std::vector<std::uint32_t> expected(many.size());
    for (std::size_t i = 0; i < expected.size(); ++i) expected[i] = static_cast<std::uint32_t>(i);
    std::stable_sort(expected.begin(), expected.end(), [&](std::uint32_t a, std::uint32_t b) { return k[a] < k[b]; });
    EXPECT_EQ(media::backToFront(view, many, key), expected);
  }
}

TEST(MediaSortKey, NamesAndTheSceneField) {
  for (SortKey k : {SortKey::kViewDepth, SortKey::kPowerDistance}) EXPECT_EQ(media::parseSortKey(toString(k)), k);
  EXPECT_EQ(media::toString(SortKey::kViewDepth), "view-depth");
  EXPECT_EQ(media::toString(SortKey::kPowerDistance), "power-distance");
  EXPECT_FALSE(media::parseSortKey("depth").has_value());

  auto plain = scene::parseScene(nlohmann::json::parse(R"({"media": {}})"), "x.json");
  ASSERT_OK(plain);
  EXPECT_EQ(plain->media->settings.sort, SortKey::kViewDepth);  // the default
  EXPECT_EQ(scene::toJson(*plain)["media"]["sort"], "view-depth");
  auto power = scene::parseScene(nlohmann::json::parse(R"({"media": {"sort": "power-distance"}})"), "x.json");
  ASSERT_OK(power);
  EXPECT_EQ(power->media->settings.sort, SortKey::kPowerDistance);
  const nlohmann::json out = scene::toJson(*power);
  EXPECT_EQ(out["media"]["sort"], "power-distance");
  auto again = scene::parseScene(out, "x.json");
  ASSERT_OK(again);
  EXPECT_EQ(again->media->settings.sort, SortKey::kPowerDistance);
  auto bad = scene::parseScene(nlohmann::json::parse(R"({"media": {"sort": "depth"}})"), "x.json");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "x.json: /media/sort: expected one of view-depth, power-distance, got \"depth\"");
}

class MediaSortGpu : public test::GlTest {};

TEST_F(MediaSortGpu, TheRendererAndTheModelReferenceSortByTheKey) {
  // A red A and a green B, dense, over black: where they overlap the colour says which one the
  // renderer composited last. In a float target the spherical billboards equal the model reference
  // in the renderer's order (viewAxisOrder) with the same key; the two keys' images differ.
  constexpr int kSize = 65;
  media::Material red = test::plainMaterial(1.0f), green = test::plainMaterial(1.0f);
  red.color = {1, 0, 0};
  green.name = "green";
  green.color = {0, 1, 0};
  const std::vector<media::Material> materials = {red, green};
  std::vector<media::Particle> ps = {sphereAt(kCentreA, kRadiusA), sphereAt(kCentreB, kRadiusB)};
  ps[1].material = 1;
  test::MediaCamera cam;
  cam.fovDegrees = 50.0f;  // B's centre is 20 degrees off the axis
  const media::Frame frame = cam.frame(kSize);
  std::vector<core::Image> gpu, ref;
  for (SortKey key : {SortKey::kViewDepth, SortKey::kPowerDistance}) {
    SCOPED_TRACE(std::string(media::toString(key)));
    media::Settings settings;
    settings.sort = key;
    auto r = media::Renderer::create(settings);
    ASSERT_OK(r);
    ASSERT_OK((*r)->setMaterials(materials));
    test::MediaTarget t(kSize);
    t.clear({0, 0, 0, 1});
    t.bind();
    (*r)->draw(frame, ps, media::Method::kSpherical, t.depth.get());
    const std::vector<glm::vec4> px = t.read();
    core::Image im(kSize, kSize, 4, 1.0f);
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x)
        for (int c = 0; c < 3; ++c) im.at(x, kSize - 1 - y, c) = px[static_cast<std::size_t>(y) * kSize + x][c];
    reference::MediaReferenceInput in;
    in.frame = frame;
    in.particles = ps;
    in.materials = materials;
    in.settings = settings;
    in.viewAxisOrder = true;
    auto exact = reference::renderMediaReference(in);
    ASSERT_OK(exact);
    const reference::ImageError e = reference::imageError(im, *exact);
    EXPECT_LT(e.rmse, 5e-5);
    EXPECT_LT(e.maxAbs, 5e-4);
    gpu.push_back(std::move(im));
    ref.push_back(std::move(*exact));
  }
  EXPECT_GT(reference::imageError(gpu[0], gpu[1]).maxAbs, 0.1);
  // Per ray (the chords' midpoints) the order is the power distance's wherever both are met.
  reference::MediaReferenceInput perRay;
  perRay.frame = frame;
  perRay.particles = ps;
  perRay.materials = materials;
  auto exact = reference::renderMediaReference(perRay);
  ASSERT_OK(exact);
  EXPECT_EQ(reference::imageError(*exact, ref[1]).maxAbs, 0.0);
  EXPECT_GT(reference::imageError(*exact, ref[0]).maxAbs, 0.1);
}

}  // namespace
}  // namespace puff
