// The exact CPU reference for the translucent media (puff::media): the particle model the GPU
// renderers approximate, evaluated for every pixel in double precision. Tests and benchmarks
// measure the renderers (spherical, planar, soft; layers at 1 .. 1/8 size) against it.
//
// For the pixel (x, y) of a width x height frame (y = 0 the BOTTOM row, as GL counts) the ray goes
// through the pixel centre: ndc = ((x + 0.5) / width, (y + 0.5) / height) * 2 - 1 through the
// inverse projection, from the eye along normalize(far point) (perspective) or from the camera
// plane along -z (orthographic), in camera space. Along it, for every particle j:
//     alpha_j = 1 - exp(-tau_j * (1 - d_j / r_j) * Δs_j)                        (Umenhoffer Eq. 2)
//     L_j     = a * color * C + e * emission * exposure * max(0, Le(T))
//               (a: the albedo, 0 for an emissive material; e: 1 emissive, 0 not; see below)
//     C       = ambient + lightColor * 4π P(cos θ, g)                             (Umenhoffer Eq. 1)
// and the colour, starting from the opaque pixel (or `background`), is composited back to front
//     c = alpha_j * L_j + c * (1 - alpha_j * (1 - burn_j))                        (Ilmonen Eq. 3)
// which is the layers' `opaque * T + M` (layers.h) with M and T accumulated in the same order.
//
// EXACT here (what the GPU approximates):
//  - Δs: the ray's chord through the sphere, clipped by the opaque surface (the per-pixel linear
//    depth, turned into a distance along the view axis; depth >= 1 is no surface) and by the near
//    plane, never negative: media::sphereOpacity in double precision.
//  - P: media::phase evaluated per pixel (the GPU reads a 512 x 256 table, bilinear in sin(θ/2)
//    and g), with the shader's convention cos θ = dot(unit camera-space direction TOWARD the light,
//    ray direction) = the cosine between the light's travel and the light scattered to the eye.
//  - Le: Planck's law through the CIE 1931 observer (core::blackbodyXYZ -> core::xyzToLinearSrgb),
//    divided by Y at settings.normalizeKelvin like core::makeBlackbodyRamp, per pixel (the GPU
//    reads a 1024-texel ramp), then clamped at 0 per channel as the shader clamps.
//  - Detail videos: the core::DetailVideo's float values (the GPU holds them as 16-bit floats),
//    sampled trilinearly with repeat wrap in all three axes at the shader's coordinates, the rows
//    flipped as makeDetailTexture flips them (texture t = 0 is the video's bottom row).
//  - Order: per ray, by the distance along THIS ray to each chord's midpoint (the point of the ray
//    nearest the sphere's centre), farthest first; the GPU sorts once per frame by settings.sort
//    (the centres' view-axis depth by default, or their power distance |c|^2 - r^2), which differs
//    where overlapping spheres lie off the view axis.
//  - Arithmetic: doubles throughout (the GPU: 32-bit floats, a 32-bit float layer, a half-float
//    scene-linear opaque colour target); no clamping of the result.
//
// DELIBERATELY THE RENDERER'S MODEL (the choices, not approximations, that the two share):
//  - the paper's falloff (1 - d / r), d the distance from the centre to the ray;
//  - tau_j = material.density * particle.density, times the opacity detail factor
//    max(0, 1 + amount * (2 D - 1)); D = 0.5 (no change) without an opacity video;
//  - the detail window: the video coordinates (hash(seed), hash(seed ^ 0x68bc21eb)) + uv * window,
//    time hash(seed ^ 0x02e5be93) + time * detailSpeed / frames, uv = (point of the ray nearest the
//    centre - centre).xy / (2 r) + 0.5 in camera space; the shader's hash, bit for bit;
//  - T = T0 + T1 * D_temperature, clamped to [settings.minKelvin, settings.maxKelvin] (the ramp's
//    range); D_temperature = 0.5 without a temperature video;
//  - `becomes`: every value (colour, albedo, density, g, the emissive weight e, emission, T0, T1,
//    burn, detail amount, window, speed) mixed linearly by f = clamp((life - start) / (end - start))
//    (a step at `start` when end == start), one step only (the target's own `becomes` is ignored);
//    an emissive material's albedo and opacity-detail amount count as 0 (as media::Renderer uploads
//    them), so scattered light and the opacity detail fade in linearly when fire becomes smoke;
//  - particles of radius <= 0, wholly in front of the near plane (-z + r < near) or wholly beyond
//    the far plane (-z - r > far) are skipped; a sphere partly beyond the far plane is NOT clipped
//    there (only the opaque depth and the near plane clip chords).
//
// tests/unit/reference_gpu_test.cpp: in a float target and with viewAxisOrder, billboard.frag equals
// this to an RMSE of about 1e-5 (32-bit arithmetic and the GPU's tables); everything else the full
// GPU path differs by is the order, the float layer's blending and the half-float opaque colour.
#pragma once

#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

#include <puff/core/detail_video.h>
#include <puff/core/error.h>
#include <puff/core/image.h>
#include <puff/media/media.h>

namespace puff::reference {

/// Everything one reference frame needs. Spans are borrowed for the duration of the call.
struct MediaReferenceInput {
  /// The FULL-SIZE frame: view, projection, near/far, orthographic, light, ambient, time, width and
  /// height (pixels, >= 1). x and y (the viewport origin) are ignored: pixels count from (0, 0).
  media::Frame frame;
  std::span<const media::Particle> particles;
  std::span<const media::Material> materials;  ///< 1 .. 32, each media::validate()d
  media::Settings settings;                    ///< phase model, black-body range and normalization, exposure
  /// Detail videos, as media::Renderer::setDetail takes them (nullptr: a constant 0.5).
  const core::DetailVideo* temperatureDetail = nullptr;
  const core::DetailVideo* opacityDetail = nullptr;
  /// The opaque layer at width x height, row 0 at the BOTTOM (GL order): linear RGB colour, and
  /// linear depth (-z - near) / (far - near) (>= 1: no surface). Either may be empty: no colour is
  /// `background` everywhere, no depth is no surface anywhere (the background at infinity).
  std::span<const glm::vec3> opaqueColor;
  std::span<const float> opaqueDepth;
  glm::vec3 background{0.0f};
  /// Composite in the renderer's order instead (media::backToFront with settings.sort: one order for
  /// the whole frame), to tell how much of a difference the order makes.
  bool viewAxisOrder = false;
};

/// The reference image: RGBA, width x height, row 0 at the TOP (core::Image's convention), alpha 1,
/// linear colour, not clamped. `layer` (optional) receives the media layer the same way: rgb the
/// premultiplied radiance M, alpha the transmittance T, so image = opaque * T + M.
/// Errors (bad input): a frame of no pixels, materials that do not validate or are not 1 .. 32, a
/// particle whose material index is outside the table, opaque spans of the wrong size, settings
/// that core::makeBlackbodyRamp rejects or an exposure outside [0, 1e4]. Rows run in parallel
/// (core::parallelFor); the result does not depend on the thread count. Cost: per pixel, every
/// particle; 640 x 360 with 263 particles takes about 0.35 s on 2 cores, 4 s with a temperature
/// video (then Planck's law is integrated per pixel for every fire particle).
Result<core::Image> renderMediaReference(const MediaReferenceInput& input, core::Image* layer = nullptr);

/// The camera-space ray through the centre of pixel (i, j) (j = 0 the bottom row) of `frame`, as
/// the reference and billboard.frag build it: origin at the eye (perspective) or on the camera
/// plane z = 0 (orthographic), unit direction.
struct Ray {
  glm::dvec3 origin{0.0}, direction{0.0, 0.0, -1.0};
};
Ray pixelRay(const media::Frame& frame, int i, int j);

/// The shader's per-seed hash (billboard.frag `unitHash`): a value in [0, 1) with 24 bits.
double unitHash(std::uint32_t x);

/// Samples a detail video as the GPU's GL_LINEAR | GL_REPEAT 3D texture does at texture
/// coordinates (s, t, r), t = 0 at the video's BOTTOM row; nullptr gives 0.5.
double sampleDetail(const core::DetailVideo* video, double s, double t, double r);

}  // namespace puff::reference
