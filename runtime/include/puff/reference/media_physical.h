// The physical media reference: the particles as a continuous 3D medium, the SUM of one density
// field per particle, integrated along every pixel's ray in double precision. Beside the model
// reference (media_reference.h, the renderer's own per-sphere model), it tells how far that model
// is from the light transport it stands for: where spheres overlap, the model composites them one
// after another, the medium absorbs each particle's light by all the others around it.
//
// THE FIELD. Particle j (centre c, radius r, extinction tau_j = material density * particle
// density, the model's tau) is the extinction coefficient, in 1 / world unit,
//     sigma_j(x) = 2 tau_j (1 - rho / r) * detail_j(x)   for rho = |x - c| < r, 0 outside,
// detail_j(x) = max(0, 1 + amount * (2 D(x) - 1)) the model's opacity detail factor (1 without an
// opacity video). A line at distance d from the centre (h = sqrt(r^2 - d^2), no detail) sees the
// optical depth
//     tau_line(d) = 2 tau [h - (d^2 / r) ln((r + h) / d)]        (2 tau r at d = 0)
// where the model's is tau (1 - d / r) 2 h: equal through the centre (2 tau r), more everywhere
// else, 1.24 times at d = r / 2 and 4/3 towards the rim; the sphere holds 2 pi tau r^3 / 3 in all,
// 1.22 times the model's 4 pi tau r^3 (1/3 - pi/16). (docs/media.md, "The physical reference".)
//
// THE SOURCE. At x, particle j emits and scatters toward the eye sigma_j(x) * S_j(x), with the
// model's L_j as S_j (linear RGB radiance):
//     S_j(x) = (1 - e) a color C + e emission exposure max(0, Le(T(x)))
//     C      = ambient + lightColor 4 pi P(cos theta, g)     (single scattering, unshadowed)
// T(x) = T0 + T1 D_temperature(x), clamped to the settings' kelvin range. The materials are mixed
// by `becomes` exactly as the model mixes them. The detail videos are read at the model's window
// coordinates with uv = (x - c).xy / (2 r) + 0.5 in camera space: the projection of the sample
// point onto the particle's billboard, so D(x) is a function of the 3D point (constant along the
// camera's z inside one particle).
//
// BURN (Ilmonen), which no medium has, is defined as a mixture: a particle of burn b is, for the
// light of everything else (the other particles' light and the opaque background), present with
// weight (1 - b) and absent with weight b; its own light it always absorbs. Light that leaves the
// point at s on the ray reaches the eye with
//     K_j(s) = b_j + (1 - b_j) exp(-tau_j(s))    (tau_j(s): j's optical depth from the eye to s)
// through each foreign particle j, and exp(-tau_i(s)) through its own particle i, so
//     M = sum_i Integral sigma_i(s) S_i(s) exp(-tau_i(s)) prod_{j != i} K_j(s) ds
//     T = prod_j K_j(end),   image = opaque * T + M.
// With burn 0 everywhere this is the radiative transfer equation, L = Integral T(s) S(s) ds +
// T_end opaque. A lone sphere gives exactly the model's Ilmonen Eq. 3 with alpha = 1 -
// exp(-tau_line): M = alpha L, T = 1 - alpha (1 - b); so do disjoint spheres. (The exponent form
// exp(-(1 - b) tau) for the background does not: at b = 1/2, tau = 1 it gives 0.607, Eq. 3 0.684.)
//
// THE RAY is the model's (pixelRay): clipped by the near plane and the opaque depth as the model
// clips chords, particles culled as the model culls them (none is clipped by the far plane).
//
// QUADRATURE. Per ray, only the particles whose sphere it meets; their entry and exit points and
// the points nearest their centres (where the field has a kink) split the ray into segments with
// a fixed set of particles; each segment is integrated by composite Simpson with panels of at most
// `step`: every particle's optical depth by Simpson (the midpoint's by the quadratic through the
// panel's three values), M by Simpson over the three nodes. Exact for the optical depth through
// the centre; O(step^4) for smooth fields. The opacity and temperature details are trilinear in
// their texels, so the integrand has kinks where the ray crosses texel planes and the order drops
// there. Le(T) with a temperature video comes from a table of the exact function every 0.25 K,
// unclipped, interpolated by cubics and then clipped at 0; in the tests it equals Planck's law to
// the float layer's precision. Without a temperature video, Le is exact.
//
// COST (llvmpipe VM, 2 AMD EPYC cores, Release): puff_bench_media's 263 particles at 320 x 240 over
// its floor and wall, automatic step (tolerance 1e-4): 1.8 s (final step 0.113 after 1 halving),
// 3.9 to 4.8 s with temperature and opacity videos; the model reference takes 0.11 to 0.16 s and
// 0.66 to 0.72 s. More in docs/media.md, "The physical reference".
#pragma once

#include <puff/core/error.h>
#include <puff/core/image.h>
#include <puff/reference/media_reference.h>

namespace puff::reference {

struct PhysicalOptions {
  /// Largest Simpson panel along a ray, world units (> 0), or 0: automatic (see below).
  double step = 0.0;
  /// Automatic step: start at half the largest radius, halve until the image (RGB, linear) changes
  /// by less than this RMSE from one halving to the next (> 0).
  double tolerance = 1e-4;
  /// Automatic step: at most this many halvings (0 .. 24); report.converged says if it was enough.
  int maxHalvings = 12;
};

/// How the returned image was made.
struct PhysicalReport {
  double step = 0.0;        ///< the panel size of the returned image, world units (0: no particle on screen)
  int halvings = 0;         ///< automatic: halvings after the first image (fixed step: 0)
  double lastChange = 0.0;  ///< automatic: RGB RMSE of the returned image against the one at twice the step
  bool converged = false;   ///< automatic: lastChange < tolerance (fixed step, or nothing to integrate: true)
  int images = 0;           ///< images rendered (the cost is about twice the last one's)
};

/// The physical reference image, in the same convention as renderMediaReference: RGBA, width x
/// height, row 0 at the TOP, alpha 1, linear colour, not clamped; `layer` (optional) gets rgb = M
/// (premultiplied radiance) and alpha = T, so image = opaque * T + M. The integral has no order,
/// so input.viewAxisOrder must be false (rejected rather than ignored). Errors: everything renderMediaReference rejects
/// (same text), viewAxisOrder set, a step that is negative or not finite, a tolerance <= 0 or not finite, maxHalvings
/// outside 0 .. 24. Rows run in parallel (core::parallelFor); the result does not depend on the thread count.
Result<core::Image> renderMediaPhysical(const MediaReferenceInput& input, const PhysicalOptions& options,
                                        core::Image* layer = nullptr, PhysicalReport* report = nullptr);

}  // namespace puff::reference
