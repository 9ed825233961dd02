// The plain values the media path speaks and a scene file describes: methods, materials, a
// particle, a frame, settings, explosion lights and composition. No GL: puff::scene and tools
// include this without a context.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <puff/core/error.h>
#include <puff/core/frame.h>

namespace puff::media {

/// How a particle sphere becomes pixels (media.h says what each draws). kPlanarTextured is the
/// classic textured billboard the paper timed (a baked falloff texture, no per-pixel path).
enum class Method { kPlanar, kSoftLinear, kSoftSCurve, kSpherical, kPlanarTextured };
std::string_view toString(Method m);
/// planar, soft-linear, soft-scurve, spherical, planar-textured
std::optional<Method> parseMethod(std::string_view name);

enum class PhaseModel {
  kCornetteShanks,    ///< the form Umenhoffer §3.1 prints (and calls Henyey–Greenstein); not isotropic at g = 0
  kHenyeyGreenstein,  ///< (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^1.5)
};
std::string_view toString(PhaseModel m);
std::optional<PhaseModel> parsePhaseModel(std::string_view name);  ///< cornette-shanks, henyey-greenstein

/// The key the particles are sorted back to front by, once per frame (media::backToFront), for the
/// GPU's compositing order and the model reference's "renderer's order". c is the sphere's centre
/// in camera space, r its radius.
enum class SortKey {
  kViewDepth,  ///< the centre's depth along the view axis, -c.z
  /// The power distance of the eye from the sphere, |c|^2 - r^2 (the squared tangent length when
  /// the eye is outside; negative inside). It orders the cells of the spheres' power diagram along
  /// every ray from the eye, so of two overlapping spheres of different radii the larger one, whose
  /// radical plane lies nearer the smaller one's centre, can come nearer than its centre's depth
  /// says. Orthographic cameras: the eye is at infinity along +z, where the power order is the
  /// centres' view-axis depth (the radical plane's normal is c_i - c_j, and which side of it the
  /// eye lies on is the sign of (c_i - c_j).z), so this key equals kViewDepth there.
  kPowerDistance,
};
std::string_view toString(SortKey k);
std::optional<SortKey> parseSortKey(std::string_view name);  ///< view-depth, power-distance

/// The phase function in 1/sr: integrates to 1 over the sphere for g in (-1, 1). cosTheta is the
/// cosine between the light's direction of travel and the scattered direction (1 = forward).
double phase(PhaseModel model, double cosTheta, double g);

/// The fastest a material's detail video may play (Material::detailSpeed), frames a second.
inline constexpr float kMaxDetailSpeed = 1e3f;

/// What one kind of particle is made of. The paper's defaults: smoke a = 0.2, tau = 0.4; dust
/// a = 0.9, tau = 0.4; fire emits (a = 0). Every value is checked by validate().
struct Material {
  std::string name;
  float albedo = 0.2f;           ///< a, [0, 1]
  float density = 0.4f;          ///< tau, extinction per world unit, [0, 1e4]
  glm::vec3 color{1.0f};         ///< tint of the scattered light, scene-linear, each in [0, 1]
  float g = 0.0f;                ///< phase asymmetry, [-0.95, 0.95]
  bool emissive = false;         ///< a black-body emitter (fire): Le from the temperature, albedo ignored
  float temperature = 2500;      ///< T0, kelvin, [0, 1e5]
  float temperatureRange = 700;  ///< T1: T = T0 + T1 * detail, kelvin, [-1e5, 1e5]
  float emission = 1.0f;         ///< scales Le, [0, 1e4]
  float burn = 0.0f;             ///< Ilmonen's burn, [0, 1]: 0 blends as a medium, 1 adds
  float detail = 0.5f;           ///< opacity perturbation by the detail video (non-emissive), [0, 1]
  float detailWindow = 0.3f;     ///< share of the detail video's width one particle shows, (0, 1]
  float detailSpeed = 8.0f;      ///< detail video frames per second of scene time, [0, kMaxDetailSpeed]
  float shimmer = 0.0f;          ///< heat-shimmer weight this material writes, [0, 1] (fire: 1)
  /// Over its life a particle turns into another material (fire into smoke): between life
  /// fractions transitionStart and transitionEnd every value above is interpolated towards
  /// material `becomes` (an index into the renderer's table; -1 = stays).
  int becomes = -1;
  float transitionStart = 0.3f, transitionEnd = 0.8f;  ///< 0 <= start <= end <= 1
  bool operator==(const Material&) const = default;
};

/// The paper's materials: "smoke" (a 0.2, tau 0.4), "dust" (a 0.9, tau 0.4), "fire" (emissive,
/// T = 2500 + 700 * detail, burn 1, shimmer 1).
Material smokeMaterial();
Material dustMaterial();
Material fireMaterial();

/// "FIELD: expected ..., got ..." for the first bad value; `count` is the table size (for becomes).
Result<void> validate(const Material& m, int count);

/// One particle as the GPU sees it: 48 bytes.
struct Particle {
  glm::vec3 position{0.0f};    ///< world space
  float radius = 0.5f;         ///< world units, >= 0 (0 draws nothing)
  std::uint32_t material = 0;  ///< index into the material table
  float life = 0.0f;           ///< age / lifetime, [0, 1]
  float density = 1.0f;        ///< multiplies the material's tau (a fading particle), >= 0
  std::uint32_t seed = 0;      ///< picks its window of the detail video and its time offset
  /// Multiplies the light the particle scatters and emits: scene-linear, each channel >= 0 (a
  /// scene file's colour curve is a display value, decoded before it gets here). White: untinted.
  glm::vec3 tint{1.0f};
  /// > 0: replaces the material's T0 (kelvin; the detail still adds T1 x detail); <= 0: the
  /// material's (mixed across a `becomes` transition). Matters only where the material emits.
  float temperature = 0.0f;
};
static_assert(sizeof(Particle) == 48);

/// Everything about the frame a media draw needs: what every Puff frame has (core/frame.h: the
/// camera, the light and ambient in scene-linear, the viewport drawn into, the depth convention of
/// the host's depth the media are tested against) and the time.
struct Frame : core::SharedFrame {
  Frame() = default;
  /// The shared part from `shared`, the time 0.
  explicit Frame(const core::SharedFrame& shared) : core::SharedFrame(shared) {}

  float time = 0.0f;  ///< seconds (animates the detail video)
};

/// Whether Renderer::draw writes the heat-shimmer offsets (the target's attachment 1) or leaves them.
enum class Shimmer { kOff, kWritten };

/// The cartoon fire's default palette, DISPLAY sRGB from the core out: a pale yellow core, orange,
/// then a red-orange rim (hues 49, 32 and 14 degrees; HSV saturation 0.55, 0.85, 0.89).
std::vector<glm::vec3> defaultFireColors();

/// How the media layer becomes pixels (docs/media.md, "Cartoon media").
enum class Style {
  kPhotoreal,  ///< the papers' translucent media: the layer composed as it was integrated
  kCartoon,    ///< flat bands and ink (CartoonStyle), in the style of McGuire & Fein's smoke
};
std::string_view toString(Style s);
std::optional<Style> parseStyle(std::string_view name);  ///< photoreal, cartoon

/// The cartoon style (beyond the papers). The layer's accumulated opacity A (over-composited, burn
/// ignored: cartoon fire occludes) decides what is drawn: nothing below `threshold`; above it flat
/// opacity tiers, band k of `opacityBands` drawing theta + (1 - theta) (k + 1) / n (the top one
/// opaque); an ink band `outlineWidth` pixels wide outside the iso-line A = theta, from a distance
/// field of the whole layer, so overlapping particles share one outline (Fig. 5). Where emitting
/// medium is most of what is seen, the colour is that of the band its mean temperature falls in:
/// [coolKelvin, hotKelvin] split into equal bands, coolest first, each drawing a colour of
/// `fireColors` (the artist's palette; the hottest band the first colour) or, with no palette, the
/// black-body Le at its centre (`fireBands` of them); elsewhere the medium's scattered light,
/// unpremultiplied (so flat within a tier).
struct CartoonStyle {
  float threshold = 0.35f;  ///< the ink's iso-line, accumulated opacity in (0, 1)
  int opacityBands = 2;     ///< [1, 8]
  /// The fire's band colours from the core (the hottest band) out to the rim, DISPLAY sRGB values
  /// each in [0, 1], at most 8: decoded to linear and drawn times the medium's emission and the
  /// exposure. Empty: black-body bands. Default: defaultFireColors().
  std::vector<glm::vec3> fireColors = defaultFireColors();
  int fireBands = 3;             ///< black-body bands when fireColors is empty, [1, 8]
  float coolKelvin = 1400.0f;    ///< (0, 1e5), < hotKelvin
  float hotKelvin = 3000.0f;     ///< (0, 1e5]
  bool outlines = true;          ///< off: no ink (the fill keeps its antialiased edge)
  float outlineWidth = 2.0f;     ///< pixels of the output image, [0, 64]
  glm::vec3 outlineColor{0.0f};  ///< the ink, scene-linear, each in [0, 1]
  bool operator==(const CartoonStyle&) const = default;
};
/// "FIELD: expected ..., got ..." for the first bad value.
Result<void> validate(const CartoonStyle& s);
/// How many fire bands `s` draws: its palette's colours, or fireBands black-body ones.
int fireBandCount(const CartoonStyle& s);

struct Settings {
  PhaseModel phase = PhaseModel::kCornetteShanks;
  float minKelvin = 1000.0f, maxKelvin = 10000.0f;  ///< the black-body texture's range
  float normalizeKelvin = 3200.0f;                  ///< luminance 1 at this temperature
  float exposure = 1.0f;                            ///< scales every emission, [0, 1e4]
  SortKey sort = SortKey::kViewDepth;               ///< back-to-front order (docs/media.md, "Sorting")
  /// kCartoon: Renderer::draw also writes the cartoon attributes (media.h) and Layers draw bands and
  /// ink from them (Layers::compose with a CartoonCompose).
  Style style = Style::kPhotoreal;
  CartoonStyle cartoon;
  bool operator==(const Settings&) const = default;
};

/// One explosion's light on the scene. A frame composes at most 8 that shine (intensity and radius
/// > 0): Layers::compose uses the first 8, HostLayers::composeOver refuses more.
struct ExplosionLight {
  glm::vec3 center{0.0f};              ///< world space
  float radius = 1.0f;                 ///< world units, > 0
  glm::vec3 color{1.0f, 0.6f, 0.25f};  ///< scene-linear
  float intensity = 1.0f;              ///< >= 0 (0: off)
  bool modulate = false;               ///< multiply the surface by mix(1, color, weight) instead of adding
  bool fullAtBack = false;             ///< full intensity from the sphere's back instead of its centre
};

struct ComposeSettings {
  bool depthAware = true;      ///< depth-aware upsampling (layers.h; false: plain bilinear, halos)
  float shimmerPixels = 0.0f;  ///< heat-shimmer displacement, full-resolution pixels per unit offset (fractional)
  /// Depth-aware upsampling: layer texels within this share of the pixel's view distance count
  /// fully as the same surface; their weight falls to 0 at five times it.
  float depthTolerance = 0.02f;
  bool operator==(const ComposeSettings&) const = default;
};

}  // namespace puff::media
