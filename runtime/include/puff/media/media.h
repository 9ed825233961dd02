// The translucent half of Puff: fire, smoke and dust as particle spheres of participating medium
// (Umenhoffer, Szirmay-Kalos & Szijártó 2006), drawn back to front into a float layer and
// composited over the opaque scene (Layers, layers.h).
//
// Each particle j is a sphere of radius r with extinction density tau, albedo a and a phase
// function P; a ray that travels Δs inside it sees (Umenhoffer Eq. 1, 2)
//     alpha = 1 - exp(-tau * (1 - d / r) * Δs)          (d: distance from the centre to the ray)
//     L     = I * (1 - alpha) + alpha * a * C + alpha * (1 - a) * Le
// where C is the in-scattered light (ambient + the light through the phase function) and Le the
// emission (fire: a black body at T = T0 + T1 * detail). Δs is the ray's EXACT path through the
// sphere, clipped by the opaque depth and the near plane, never negative (the paper's snippet goes
// negative when a surface lies in front of the sphere, and measures d in the billboard plane; we
// intersect the pixel's ray with the sphere). The falloff (1 - d/r) is the paper's.
//
// Blending is Ilmonen et al.'s five-component colour: the shader outputs premultiplied
// colour alpha * L_j and alpha_c = alpha * (1 - burn); the blend unit computes
//     c = fg * alpha + bg * (1 - alpha * (1 - burn))         (Ilmonen Eq. 3)
// with glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA), so burn 0 is the physical transparency
// blend and burn 1 is additive (fire). The layer's alpha channel holds the transmittance of what
// lies behind: it starts at 1 and is multiplied by (1 - alpha_c) per particle.
//
// Methods (one shader family, selected per draw):
//  - kPlanar: the classic billboard through the sphere's centre, depth-tested against the
//    opaque depth (it cuts into walls) and clipped whole by the near plane (it pops).
//  - kSoftLinear: planar, faded near opaque surfaces by clamp((Zs - z) / size, 0, 1) (Ilmonen §3).
//  - kSoftSCurve: planar, faded with Lorach's S-curve of the same ratio (RTR3 §10.6).
//  - kSpherical: quads perpendicular to the camera's z at the sphere's far point, depth test off,
//    opacity from the clipped path length (Umenhoffer §2).
// Planar methods use the same per-pixel profile as the spherical one for an unoccluded sphere
// (Δs = the full chord), so the four differ only where the medium meets surfaces or the camera.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <puff/core/blackbody.h>
#include <puff/core/detail_video.h>
#include <puff/core/error.h>
#include <puff/core/gl.h>

namespace puff::media {

enum class Method { kPlanar, kSoftLinear, kSoftSCurve, kSpherical };
std::string_view toString(Method m);
std::optional<Method> parseMethod(std::string_view name);  ///< planar, soft-linear, soft-scurve, spherical

enum class PhaseModel {
  kCornetteShanks,    ///< the form Umenhoffer §3.1 prints (and calls Henyey–Greenstein); not isotropic at g = 0
  kHenyeyGreenstein,  ///< (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^1.5)
};
std::string_view toString(PhaseModel m);
std::optional<PhaseModel> parsePhaseModel(std::string_view name);  ///< cornette-shanks, henyey-greenstein

/// The phase function in 1/sr: integrates to 1 over the sphere for g in (-1, 1). cosTheta is the
/// cosine between the light's direction of travel and the scattered direction (1 = forward).
double phase(PhaseModel model, double cosTheta, double g);

/// What one kind of particle is made of. The paper's defaults: smoke a = 0.2, tau = 0.4; dust
/// a = 0.9, tau = 0.4; fire emits (a = 0). Every value is checked by validate().
struct Material {
  std::string name;
  float albedo = 0.2f;           ///< a, [0, 1]
  float density = 0.4f;          ///< tau, extinction per world unit, [0, 1e4]
  glm::vec3 color{1.0f};         ///< tint of the scattered light, each in [0, 1]
  float g = 0.0f;                ///< phase asymmetry, [-0.95, 0.95]
  bool emissive = false;         ///< a black-body emitter (fire): Le from the temperature, albedo ignored
  float temperature = 2500;      ///< T0, kelvin, [0, 1e5]
  float temperatureRange = 700;  ///< T1: T = T0 + T1 * detail, kelvin, [-1e5, 1e5]
  float emission = 1.0f;         ///< scales Le, [0, 1e4]
  float burn = 0.0f;             ///< Ilmonen's burn, [0, 1]: 0 blends as a medium, 1 adds
  float detail = 0.5f;           ///< opacity perturbation by the detail video (non-emissive), [0, 1]
  float detailWindow = 0.3f;     ///< share of the detail video's width one particle shows, (0, 1]
  float detailSpeed = 8.0f;      ///< detail video frames per second of scene time, [0, 1e3]
  float shimmer = 0.0f;          ///< heat-shimmer weight this material writes, [0, 1] (fire: 1)
  /// Over its life a particle turns into another material (fire into smoke): between life
  /// fractions transitionStart and transitionEnd every value above is interpolated towards
  /// material `becomes` (an index into the renderer's table; -1 = stays).
  int becomes = -1;
  float transitionStart = 0.3f, transitionEnd = 0.8f;  ///< 0 <= start <= end <= 1
};

/// The paper's materials: "smoke" (a 0.2, tau 0.4), "dust" (a 0.9, tau 0.4), "fire" (emissive,
/// T = 2500 + 700 * detail, burn 1, shimmer 1).
Material smokeMaterial();
Material dustMaterial();
Material fireMaterial();

/// "FIELD: expected ..., got ..." for the first bad value; `count` is the table size (for becomes).
Result<void> validate(const Material& m, int count);

/// One particle as the GPU sees it: 32 bytes.
struct Particle {
  glm::vec3 position{0.0f};    ///< world space
  float radius = 0.5f;         ///< world units, >= 0 (0 draws nothing)
  std::uint32_t material = 0;  ///< index into the material table
  float life = 0.0f;           ///< age / lifetime, [0, 1]
  float density = 1.0f;        ///< multiplies the material's tau (a fading particle), >= 0
  std::uint32_t seed = 0;      ///< picks its window of the detail video and its time offset
};
static_assert(sizeof(Particle) == 32);

/// Everything about the frame a media draw needs.
struct Frame {
  glm::mat4 view{1.0f}, projection{1.0f};
  float nearPlane = 0.1f, farPlane = 100.0f;
  bool orthographic = false;
  glm::vec3 lightDirection{0.4f, 1.0f, 0.3f};  ///< world space, toward the light
  glm::vec3 lightColor{1.0f};                  ///< radiance an isotropic medium scatters to the eye
  glm::vec3 ambient{0.25f};                    ///< isotropic in-scattered radiance
  float time = 0.0f;                           ///< seconds (animates the detail video)
  /// The viewport drawn into (the media layer): origin and size in pixels; rays go through pixel
  /// centres. The depth texture is read at the same pixels.
  int x = 0, y = 0, width = 0, height = 0;
};

struct Settings {
  PhaseModel phase = PhaseModel::kCornetteShanks;
  float minKelvin = 1000.0f, maxKelvin = 10000.0f;  ///< the black-body texture's range
  float normalizeKelvin = 3200.0f;                  ///< luminance 1 at this temperature
  float exposure = 1.0f;                            ///< scales every emission, [0, 1e4]
};

struct DrawStats {
  std::size_t particles = 0;  ///< drawn (radius > 0)
  double sortMs = 0.0;        ///< CPU time sorting back to front
};

class Renderer {
 public:
  /// Builds the programs, the black-body texture (1024 texels over the settings' range) and the
  /// phase texture. Needs a current GL 4.5 context.
  static Result<std::unique_ptr<Renderer>> create(const Settings& settings = {});
  ~Renderer();

  /// Replaces the material table (1..32 materials, each validated).
  Result<void> setMaterials(std::vector<Material> materials);
  /// The detail videos: `temperature` for emissive materials, `opacity` for the others. Without
  /// one, that detail is a constant 0.5 (no perturbation).
  void setDetail(const core::DetailVideo* temperature, const core::DetailVideo* opacity);

  /// Draws `particles` (sorted back to front here) into the current framebuffer, whose colour
  /// attachment 0 is the media layer (float RGBA: premultiplied radiance, transmittance in alpha)
  /// and attachment 1 (if `shimmer`) the heat-shimmer offsets (RG). `depth` is a texture of the
  /// opaque scene's LINEAR depth ((-z - near) / (far - near)) at the target's resolution (R32F, or a
  /// depth texture), read at each pixel's offset from the viewport's origin. The viewport must be
  /// (frame.x, frame.y, frame.width, frame.height). Sets the GL state it needs; leaves blending,
  /// depth test and depth clamp off, every colour write mask on and its program unbound.
  void draw(const Frame& frame, std::span<const Particle> particles, Method method, GLuint depth, bool shimmer = false,
            DrawStats* stats = nullptr);

  const std::vector<Material>& materials() const;

  /// Benchmarks (issue 7): draw the same quads with the same blending but a fragment program that
  /// computes nothing (shaders/media/floor.frag): the fill-rate floor any billboard method pays.
  void setFillRateFloor(bool on);

 private:
  Renderer();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Indices of `particles` from farthest to nearest along the view axis (stable: equal depths keep
/// their order). A radix sort: O(n), about a millisecond for 50k on one core.
std::vector<std::uint32_t> backToFront(const glm::mat4& view, std::span<const Particle> particles);

/// Opacity of one particle for a ray (CPU, double precision; the shader's formula): origin and
/// unit direction in camera space (looking down -z), `sceneDepth` and `nearPlane` as distances
/// along the view axis. Never negative; 0 when the ray misses.
double sphereOpacity(const glm::dvec3& origin, const glm::dvec3& direction, const glm::dvec3& centre, double radius,
                     double tau, double sceneDepth, double nearPlane);

}  // namespace puff::media
