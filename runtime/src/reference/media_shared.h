// What the two media references share (media_reference.cpp, the renderer's model; media_physical.cpp,
// the physical field): the input's checks, the particles prepared in camera space with their
// material mixed by `becomes`, the frame's constants and the black-body emission. Internal to
// puff_reference; the public functions are in puff/reference/media_reference.h and media_physical.h.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <puff/core/error.h>
#include <puff/reference/media_reference.h>

namespace puff::reference::detail {

/// A material after `becomes`, as the shader mixes it (MaterialGpu's fields), in double precision.
/// color is a linear RGB tint; albedo and the opacity-detail amount are 0 for emitters, as
/// media::Renderer uploads them.
struct Mixed {
  glm::dvec3 color{1.0};
  double albedo = 0, density = 0, g = 0, emissive = 0, emission = 0, t0 = 0, t1 = 0, burn = 0, detail = 0, window = 0,
         speed = 0;
};

Mixed fromMaterial(const media::Material& m);
/// Every value linearly from a (f = 0) to b (f = 1).
Mixed mix(const Mixed& a, const Mixed& b, double f);

/// One particle, prepared once per frame.
struct Prepared {
  glm::dvec3 centre{0.0};  ///< camera space
  double radius = 0.0;
  Mixed mat;
  double tau = 0.0;                            ///< material density * particle density, before detail
  glm::dvec3 tint{1.0};                        ///< the particle's: multiplies what it scatters and emits
  double windowX = 0, windowY = 0, time0 = 0;  ///< the seed's place and time in the detail videos
  std::uint32_t index = 0;                     ///< in the input's particle span
};

/// A detail video with texels (nullptr or an empty one reads as a constant 0.5).
bool haveVideo(const core::DetailVideo* v);

/// The ray through pixel (i, j) (j = 0 the bottom row) for the inverse projection `invProj`.
Ray rayThrough(const glm::dmat4& invProj, bool orthographic, int width, int height, int i, int j);

/// The input's checks (frame size, opaque spans, materials, settings); errors start "media reference: ".
Result<void> checkInput(const MediaReferenceInput& in);

/// The particles a ray may meet, in input order: in camera space (`view`), their material mixed
/// (then T0 the particle's own temperature where it has one, and its tint taken, clamped at 0),
/// culled as the billboards are (radius <= 0, wholly in front of the near plane or beyond the far
/// plane). Error: a particle's material index outside the table.
Result<std::vector<Prepared>> prepareParticles(const MediaReferenceInput& in, const glm::dmat4& view);

/// The black body's emitted colour at `kelvin` as the shader uses it: clamped to the settings'
/// range, linear sRGB scaled so luminance is 1 at settings.normalizeKelvin (yNorm: the Y of
/// core::blackbodyXYZ there), negative components clipped to 0.
glm::dvec3 emitted(const media::Settings& s, double yNorm, double kelvin);

/// The camera-space unit vector toward the light (the frame's world-space lightDirection through
/// `view`; straight up when it is zero).
glm::dvec3 toLightCamera(const media::Frame& f, const glm::dmat4& view);

/// What both references take from the input before tracing a frame: its matrices, planes, light and
/// time in double precision, the black body's normalization, and which detail videos there are.
/// Their tracers derive from it.
struct FrameConstants {
  const MediaReferenceInput& in;
  const media::Frame& f;
  const media::Settings& s;
  double yNorm = 0.0;  ///< Y of core::blackbodyXYZ at settings.normalizeKelvin
  glm::dmat4 view{1.0}, invProj{1.0};
  double nearPlane = 0.0, farPlane = 0.0;
  glm::dvec3 toLight{0.0}, ambient{0.0}, lightColor{0.0};
  double time = 0.0, exposure = 0.0;
  bool haveTemperature = false, haveOpacity = false;
  double temperatureFrames = 1.0, opacityFrames = 1.0;  ///< each video's frame count (1 without one)

  explicit FrameConstants(const MediaReferenceInput& input);
};

}  // namespace puff::reference::detail
