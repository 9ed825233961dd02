// The helpers both media references share (media_shared.h).
#include "media_shared.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

#include <puff/core/blackbody.h>
#include <puff/core/limits.h>
#include <puff/core/number_text.h>
#include <puff/shader_contract.h>

namespace puff::reference::detail {

namespace {}  // namespace

Mixed fromMaterial(const media::Material& m) {
  Mixed r;
  r.color = glm::dvec3(m.color);
  r.emissive = m.emissive ? 1.0 : 0.0;
  r.albedo = m.emissive ? 0.0 : m.albedo;  // as media::Renderer uploads it: fire scatters nothing
  // An emitter's opacity detail is 0 (as media::Renderer uploads it): tau stays continuous while
  // fire turns into smoke.
  r.detail = m.emissive ? 0.0 : m.detail;
  r.density = m.density;
  r.g = m.g;
  r.emission = m.emission;
  r.t0 = m.temperature;
  r.t1 = m.temperatureRange;
  r.burn = m.burn;
  r.window = m.detailWindow;
  r.speed = m.detailSpeed;
  return r;
}

Mixed mix(const Mixed& a, const Mixed& b, double f) {
  auto l = [f](double x, double y) { return x + (y - x) * f; };
  Mixed r;
  r.color = a.color + (b.color - a.color) * f;
  r.albedo = l(a.albedo, b.albedo);
  r.density = l(a.density, b.density);
  r.g = l(a.g, b.g);
  r.emissive = l(a.emissive, b.emissive);
  r.emission = l(a.emission, b.emission);
  r.t0 = l(a.t0, b.t0);
  r.t1 = l(a.t1, b.t1);
  r.burn = l(a.burn, b.burn);
  r.detail = l(a.detail, b.detail);
  r.window = l(a.window, b.window);
  r.speed = l(a.speed, b.speed);
  return r;
}

bool haveVideo(const core::DetailVideo* v) { return v != nullptr && v->width > 0 && v->height > 0 && v->frames > 0; }

Ray rayThrough(const glm::dmat4& invProj, bool orthographic, int width, int height, int i, int j) {
  const double nx = (i + 0.5) / width * 2.0 - 1.0, ny = (j + 0.5) / height * 2.0 - 1.0;
  Ray r;
  if (orthographic) {
    const glm::dvec4 pn = invProj * glm::dvec4(nx, ny, -1.0, 1.0);
    r.origin = glm::dvec3(pn.x / pn.w, pn.y / pn.w, 0.0);
    r.direction = glm::dvec3(0.0, 0.0, -1.0);
  } else {
    const glm::dvec4 pf = invProj * glm::dvec4(nx, ny, 1.0, 1.0);
    r.direction = glm::normalize(glm::dvec3(pf) / pf.w);
  }
  return r;
}

Result<void> checkInput(const MediaReferenceInput& in) {
  const media::Frame& f = in.frame;
  const int w = f.viewport.width, h = f.viewport.height;
  const std::string at = "media reference: ";
  if (w < 1 || h < 1 || w > core::kMaxImageSize || h > core::kMaxImageSize)
    return Error{at + "frame size " + std::to_string(w) + "x" + std::to_string(h) + " outside 1.." +
                 std::to_string(core::kMaxImageSize)};
  const std::size_t pixels = static_cast<std::size_t>(w) * h;
  if (!in.opaqueColor.empty() && in.opaqueColor.size() != pixels)
    return Error{at + "opaque colour: expected " + std::to_string(pixels) + " pixels, got " +
                 std::to_string(in.opaqueColor.size())};
  if (!in.opaqueDepth.empty() && in.opaqueDepth.size() != pixels)
    return Error{at + "opaque depth: expected " + std::to_string(pixels) + " pixels, got " +
                 std::to_string(in.opaqueDepth.size())};
  const int count = static_cast<int>(in.materials.size());
  if (count < 1 || count > shader::kMaxMaterials)
    return Error{at + "materials: expected 1 to " + std::to_string(shader::kMaxMaterials) + ", got " +
                 std::to_string(count)};
  for (const media::Material& m : in.materials)
    if (auto ok = media::validate(m, count); !ok) return Error{at + ok.error().message};
  const media::Settings& s = in.settings;
  if (!(s.exposure >= 0.0f && s.exposure <= 1e4f))
    return Error{at + "exposure: expected a number in [0, 10000], got " + core::numberText(s.exposure)};
  // The same range checks (and error text) the renderer's ramp makes.
  if (auto ramp = core::makeBlackbodyRamp(s.minKelvin, s.maxKelvin, 2, s.normalizeKelvin); !ramp)
    return Error{at + ramp.error().message};
  return {};
}

Result<std::vector<Prepared>> prepareParticles(const MediaReferenceInput& in, const glm::dmat4& view) {
  const std::string at = "media reference: ";
  const int count = static_cast<int>(in.materials.size());
  const double nearPlane = in.frame.nearPlane, farPlane = in.frame.farPlane;
  std::vector<Prepared> prepared;
  prepared.reserve(in.particles.size());
  for (std::size_t k = 0; k < in.particles.size(); ++k) {
    const media::Particle& p = in.particles[k];
    if (p.material >= static_cast<std::uint32_t>(count))
      return Error{at + "particles/" + std::to_string(k) + "/material: expected an index below " +
                   std::to_string(count) + ", got " + std::to_string(p.material)};
    Prepared q;
    q.centre = glm::dvec3(view * glm::dvec4(glm::dvec3(p.position), 1.0));
    q.radius = p.radius;
    const double dz = -q.centre.z;
    // billboard.vert's cull: nothing to draw, wholly in front of the near plane or beyond the far.
    if (!(q.radius > 0.0) || dz + q.radius < nearPlane || dz - q.radius > farPlane) continue;
    const media::Material& m = in.materials[p.material];
    q.mat = fromMaterial(m);
    if (m.becomes >= 0) {
      const double start = m.transitionStart, end = m.transitionEnd, life = p.life;
      const double t = end > start ? std::clamp((life - start) / (end - start), 0.0, 1.0) : (life < start ? 0.0 : 1.0);
      q.mat = mix(q.mat, fromMaterial(in.materials[static_cast<std::size_t>(m.becomes)]), t);
    }
    if (p.temperature > 0.0f) q.mat.t0 = p.temperature;  // the particle's own T0 over its life
    q.tint = glm::max(glm::dvec3(p.tint), glm::dvec3(0.0));
    q.tau = q.mat.density * static_cast<double>(p.density);
    q.windowX = unitHash(p.seed);
    q.windowY = unitHash(p.seed ^ 0x68bc21ebu);
    q.time0 = unitHash(p.seed ^ 0x02e5be93u);
    q.index = static_cast<std::uint32_t>(k);
    prepared.push_back(q);
  }
  return prepared;
}

glm::dvec3 emitted(const media::Settings& s, double yNorm, double kelvin) {
  kelvin = std::clamp(kelvin, static_cast<double>(s.minKelvin), static_cast<double>(s.maxKelvin));
  return glm::max(core::xyzToLinearSrgb(core::blackbodyXYZ(kelvin) / yNorm), glm::dvec3(0.0));
}

glm::dvec3 toLightCamera(const media::Frame& f, const glm::dmat4& view) {
  glm::dvec3 l(f.light.direction);
  l = glm::length(l) > 0.0 ? glm::normalize(l) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::dvec3(view * glm::dvec4(l, 0.0)));
}

FrameConstants::FrameConstants(const MediaReferenceInput& input) : in(input), f(input.frame), s(input.settings) {
  yNorm = core::blackbodyXYZ(s.normalizeKelvin).y;
  view = glm::dmat4(f.view);
  invProj = glm::inverse(glm::dmat4(f.projection));
  nearPlane = f.nearPlane;
  farPlane = f.farPlane;
  toLight = toLightCamera(f, view);
  ambient = glm::dvec3(f.ambient);
  lightColor = glm::dvec3(f.light.color);
  time = f.time;
  exposure = s.exposure;
  haveTemperature = haveVideo(in.temperatureDetail);
  haveOpacity = haveVideo(in.opacityDetail);
  temperatureFrames = haveTemperature ? in.temperatureDetail->frames : 1;
  opacityFrames = haveOpacity ? in.opacityDetail->frames : 1;
}

}  // namespace puff::reference::detail
