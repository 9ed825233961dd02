// The translucent half of Puff: fire, smoke and dust as particle spheres of participating medium
// (Umenhoffer, Szirmay-Kalos & Szijártó 2006), drawn back to front into a float layer and
// composited over the opaque scene (Layers, layers.h).
//
// Each particle j is a sphere of radius r with extinction density tau, albedo a and a phase
// function P; a ray that travels Δs inside it sees (Umenhoffer Eq. 2, and Eq. 1 with its emission
// weight replaced, below)
//     alpha = 1 - exp(-tau * (1 - d / r) * Δs)          (d: distance from the centre to the ray)
//     L     = I * (1 - alpha) + alpha * (a * color * C + e * emission * exposure * Le)
// where C is the in-scattered light (ambient + the light through the phase function), Le the
// black-body emission at T = T0 + T1 * detail (linear sRGB, clipped at 0 per channel), and e the
// emissive weight: 1 for an emissive material (whose albedo a counts as 0: fire scatters nothing)
// and 0 for the others. The paper weights Le by (1 - a) instead; the two agree for every material
// alone (fire: a = 0, e = 1; smoke and dust have no Le) and differ only inside a `becomes`
// transition, where a and e are both mixed linearly (fire into smoke: a = f * a_smoke,
// e = 1 - f, not 1 - f * a_smoke). Δs is the ray's EXACT path through the
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
//  - kPlanarTextured: the classic textured billboard the paper timed as "planar" (its own
//    program, billboard_textured.vert/.frag): a camera-facing quad of half side r through the
//    centre, its opacity 1 - exp(-tau * r * w) with w read from a baked falloff texture (the lone
//    sphere's profile, falloffWeight), no ray/sphere intersection and no path clipping; depth-tested
//    against the opaque depth all or nothing, clipped whole by the near plane. Same material terms,
//    so its image differs from the others only in the opacity's shape (the texture's resolution,
//    the quad in the centre's plane) and in its clipping.
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
#include <puff/media/bindings.h>
#include <puff/media/types.h>

namespace puff::media {

struct DrawStats {
  std::size_t particles = 0;  ///< drawn (radius > 0)
  double sortMs = 0.0;        ///< CPU time sorting back to front
};

class Renderer {
 public:
  /// Builds the programs, the black-body texture (1024 texels over the settings' range) and the
  /// phase texture, and points the programs at `bindings` (validated: media::validate). Needs a
  /// current GL 4.5 context. Leaves GL_UNPACK_ALIGNMENT = 4; no bound object changed.
  static Result<std::unique_ptr<Renderer>> create(const Settings& settings = {}, const Bindings& bindings = {});
  ~Renderer();

  /// Replaces the material table (1..32 materials, each validated).
  Result<void> setMaterials(std::vector<Material> materials);
  /// The detail videos: `temperature` for emissive materials, `opacity` for the others. Without
  /// one, that detail is a constant 0.5 (no perturbation).
  void setDetail(const core::DetailVideo* temperature, const core::DetailVideo* opacity);

  /// Draws `particles` (sorted back to front here) into the current framebuffer, whose colour
  /// attachment 0 is the media layer (float RGBA: premultiplied radiance, transmittance in alpha)
  /// and attachment 1 (with Shimmer::kWritten) the heat-shimmer offsets (RG). With Settings::style kCartoon,
  /// attachment 0 holds the scattered light only, and attachments 2 and 3 (float RGBA, cleared to 0)
  /// get the cartoon attributes (shaders/common/media.glsl, cartoonOutputs), all over-composited
  /// with burn ignored: LayersBase::beginMedia(Style::kCartoon) makes such a target. `depth` is a texture of the
  /// opaque scene's LINEAR depth ((-z - near) / (far - near)) at the target's resolution (R32F, or a
  /// depth texture), read at each pixel's offset from the viewport's origin. The viewport must be
  /// frame.viewport. Sets every GL state it needs and queries none.
  /// Leaves (docs/media.md, "Host state"; a core::HostStateGuard restores it all):
  ///   no program, no vertex array; blending off on draw buffers 0 and 1 (0 to 3 for the cartoon
  ///   style, whose four it draws; the others' blending and masks are the host's), with draw buffer 0's
  ///   functions (GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE_MINUS_SRC_ALPHA) and draw buffer
  ///   1's (GL_ONE, GL_ONE), draw buffers 2 and 3's (GL_ONE, GL_ONE_MINUS_SRC_ALPHA) and their equations
  ///   GL_FUNC_ADD; depth test, stencil test, culling,
  ///   scissor test, alpha to coverage, rasterizer discard and depth clamp off;
  ///   polygon mode GL_FILL; depth write mask on; colour write masks on for the draw buffers it draws;
  ///   uniform buffer bindings `mediaBlock` and `materialBlock` (whole buffers) and storage buffer
  ///   binding `particles` (a range) = its buffers; units `depth` (2D: `depth`), `blackbody` (1D),
  ///   `phase` (2D), `temperatureDetail` and `opacityDetail` (3D) and `falloff` (2D) = its
  ///   textures, each with sampler binding 0. The generic buffer bindings, framebuffers, viewport
  ///   and active texture unit are untouched. Nothing at all when no particle has a radius > 0.
  void draw(const Frame& frame, std::span<const Particle> particles, Method method, core::GlId depth,
            Shimmer shimmer = Shimmer::kOff, DrawStats* stats = nullptr);

  const std::vector<Material>& materials() const;

  /// Benchmarks: draw each method's own quads with its blending and depth state but a fragment
  /// program that computes nothing (shaders/media/floor.frag; floor_depth_tested.frag for planar
  /// and planar-textured, which keep their depth test against the opaque depth): the fill-rate
  /// floor that method pays.
  void setFillRateFloor(bool on);

 private:
  Renderer();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// planar-textured's falloff texture is kFalloffTexels x kFalloffTexels texels over the quad.
inline constexpr int kFalloffTexels = 65;
/// The lone sphere's optical path per radius at `rho` radii from its centre seen head-on,
/// 2 (1 - rho) sqrt(1 - rho^2) (the falloff (1 - d/r) times the chord / r); 0 outside. What the
/// falloff texture holds at each texel centre: the opacity is 1 - exp(-tau * r * weight).
double falloffWeight(double rho);

/// The projection a sort's eye has: at a point, or at infinity along the view axis.
enum class Projection { kPerspective, kOrthographic };

/// Indices of `particles` from farthest to nearest by `key` (types.h): the centres' view-axis depth
/// or the power distance |c|^2 - r^2 of the eye (c = view * position, camera space; computed in
/// double, sorted as a 32-bit float). With kOrthographic, kPowerDistance is the view-axis depth
/// (the power order from an eye at infinity along the view axis). Stable: equal keys keep their
/// input order. An LSD radix sort: O(n), about a millisecond for 50k on one core. media::Renderer
/// sorts with its Settings::sort and the frame's projection.
std::vector<std::uint32_t> backToFront(const glm::mat4& view, std::span<const Particle> particles,
                                       SortKey key = SortKey::kViewDepth,
                                       Projection projection = Projection::kPerspective);

/// Opacity of one particle for a ray (CPU, double precision; the shader's formula): origin and
/// unit direction in camera space (looking down -z), `sceneDepth` and `nearPlane` as distances
/// along the view axis. Never negative; 0 when the ray misses.
double sphereOpacity(const glm::dvec3& origin, const glm::dvec3& direction, const glm::dvec3& centre, double radius,
                     double tau, double sceneDepth, double nearPlane);

}  // namespace puff::media
