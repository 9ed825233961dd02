// The physical media reference (media_physical.h): the sum of the particles' density fields,
// integrated along every pixel's ray by composite Simpson between the points where the set of
// particles the ray is in changes.
#include <puff/core/number_text.h>
#include <puff/reference/media_physical.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include <puff/core/blackbody.h>
#include <puff/reference/metrics.h>
#include <puff/support/parallel.h>

#include "media_shared.h"

namespace puff::reference {

namespace {

using detail::Prepared;

constexpr double kLeTableKelvin = 0.25;  // spacing of the Le(T) table used with a temperature video

// One particle on one ray: its clipped chord and its state while the ray is integrated.
struct ChordHit {
  std::uint32_t k;       // index into PhysicalTracer::prepared
  double enter, exit;    // the chord, clipped by the near plane and the opaque surface
  double nearest;        // the ray parameter nearest the centre (the field's kink)
  double burn;           // clamped to [0, 1]
  glm::dvec3 scattered;  // (1 - e) a color C along this ray (linear RGB)
  double tau = 0.0;      // optical depth from `enter` to where the integration has come
  bool done = false;     // passed: its factor K is final
  double sigma0 = 0.0;   // the field and source at the current panel's first node
  glm::dvec3 source0{0.0};
};

// log K for a particle of burn b whose optical depth so far is tau: the log of what it leaves of
// light that is not its own, b + (1 - b) exp(-tau) (exactly -tau for b = 0, so large tau is fine).
double logKeep(double b, double tau) { return b == 0.0 ? -tau : std::log(b + (1.0 - b) * std::exp(-tau)); }

// One frame: its constants, its particles prepared once, then each pixel's ray.
struct PhysicalTracer : detail::FrameConstants {
  std::vector<Prepared> prepared;
  std::vector<glm::dvec3> constantLe;  // without a temperature video: Le(T0 + T1 / 2) per particle
  std::vector<glm::dvec3> leTable;     // with one: unclipped Le every kLeTableKelvin from minKelvin

  explicit PhysicalTracer(const MediaReferenceInput& input) : FrameConstants(input) {}

  Result<void> prepare() {
    PUFF_TRY_ASSIGN(prepared, detail::prepareParticles(in, view));
    constantLe.assign(prepared.size(), glm::dvec3(0.0));
    bool anyEmitter = false;
    for (std::size_t k = 0; k < prepared.size(); ++k) {
      if (!(prepared[k].mat.emissive > 0.0)) continue;
      anyEmitter = true;
      if (!haveTemperature) constantLe[k] = detail::emitted(s, yNorm, prepared[k].mat.t0 + prepared[k].mat.t1 * 0.5);
    }
    // With a temperature video T varies along every ray: Planck's law per sample would be 95
    // exponentials, so it is tabulated once, finely enough to be exact at the reference's tolerance.
    if (haveTemperature && anyEmitter) {
      // Unclipped linear sRGB (smooth in T), clipped at 0 after the interpolation as the shader clips.
      const double lo = s.minKelvin, hi = s.maxKelvin;
      const std::size_t n =
          std::max<std::size_t>(4, static_cast<std::size_t>(std::ceil((hi - lo) / kLeTableKelvin)) + 1);
      leTable.resize(n);
      for (std::size_t i = 0; i < n; ++i)
        leTable[i] = core::xyzToLinearSrgb(core::blackbodyXYZ(lo + kLeTableKelvin * static_cast<double>(i)) / yNorm);
    }
    return {};
  }

  double largestRadius() const {
    double r = 0.0;
    for (const Prepared& p : prepared) r = std::max(r, p.radius);
    return r;
  }

  // Le(kelvin) from the table: the cubic through the four nearest entries (inside the table at its
  // ends), then clipped at 0 like detail::emitted.
  glm::dvec3 tableLe(double kelvin) const {
    kelvin = std::clamp(kelvin, static_cast<double>(s.minKelvin), static_cast<double>(s.maxKelvin));
    const double x = (kelvin - s.minKelvin) / kLeTableKelvin;
    const std::size_t last = leTable.size() - 4;
    const std::size_t base = std::min(static_cast<std::size_t>(std::max(0.0, std::floor(x) - 1.0)), last);
    const double t = x - static_cast<double>(base);  // in [0, 3] but at the ends
    const double w0 = -(t - 1) * (t - 2) * (t - 3) / 6, w1 = t * (t - 2) * (t - 3) / 2, w2 = -t * (t - 1) * (t - 3) / 2,
                 w3 = t * (t - 1) * (t - 2) / 6;
    const glm::dvec3 le = leTable[base] * w0 + leTable[base + 1] * w1 + leTable[base + 2] * w2 + leTable[base + 3] * w3;
    return glm::max(le, glm::dvec3(0.0));
  }

  // Particle hit.k's extinction (1 / world unit) and source (linear RGB radiance) at x.
  void field(const ChordHit& hit, const glm::dvec3& x, double& sigma, glm::dvec3& source) const {
    const Prepared& p = prepared[hit.k];
    const detail::Mixed& mt = p.mat;
    const glm::dvec3 rel = x - p.centre;
    const double falloff = 1.0 - glm::length(rel) / p.radius;
    // The detail window at the point's projection onto the billboard (camera-space xy).
    const double u = p.windowX + (rel.x / (2.0 * p.radius) + 0.5) * mt.window;
    const double v = p.windowY + (rel.y / (2.0 * p.radius) + 0.5) * mt.window;
    double tau = p.tau;
    if (mt.detail != 0.0) {
      const double d = sampleDetail(in.opacityDetail, u, v, p.time0 + time * mt.speed / opacityFrames);
      tau *= std::max(0.0, 1.0 + mt.detail * (2.0 * d - 1.0));
    }
    sigma = 2.0 * tau * std::max(0.0, falloff);
    source = hit.scattered;
    if (mt.emissive > 0.0) {
      const glm::dvec3 le = haveTemperature
                                ? tableLe(mt.t0 + mt.t1 * sampleDetail(in.temperatureDetail, u, v,
                                                                       p.time0 + time * mt.speed / temperatureFrames))
                                : constantLe[hit.k];
      source += mt.emissive * mt.emission * exposure * le;
    }
    source *= p.tint;
  }

  // The particles the ray meets between tNear and tScene, in prepared order.
  void gatherHits(const glm::dvec3& o, const glm::dvec3& dir, double tNear, double tScene, double cosTheta,
                  std::vector<ChordHit>& hits) const {
    const double fourPi = 4.0 * std::numbers::pi;
    hits.clear();
    for (std::size_t k = 0; k < prepared.size(); ++k) {
      const Prepared& p = prepared[k];
      const glm::dvec3 m = o - p.centre;
      const double b = glm::dot(m, dir);
      const glm::dvec3 across = glm::cross(m, dir);
      const double d2 = glm::dot(across, across);
      if (!(d2 < p.radius * p.radius)) continue;
      const double w = std::sqrt(p.radius * p.radius - d2);
      const double enter = std::max(-b - w, tNear), exit = std::min(-b + w, tScene);
      if (!(exit > enter)) continue;
      ChordHit h{};
      h.k = static_cast<std::uint32_t>(k);
      h.enter = enter;
      h.exit = exit;
      h.nearest = -b;
      h.burn = std::clamp(p.mat.burn, 0.0, 1.0);
      h.scattered = glm::dvec3(0.0);
      if (p.mat.albedo > 0.0) {
        const glm::dvec3 c = ambient + lightColor * (fourPi * media::phase(s.phase, cosTheta, p.mat.g));
        h.scattered = p.mat.albedo * p.mat.color * c;
      }
      hits.push_back(h);
    }
  }

  // M (premultiplied radiance) and T along one ray, with Simpson panels of at most `step`.
  void integrate(const glm::dvec3& o, const glm::dvec3& dir, std::vector<ChordHit>& hits, double step,
                 std::vector<double>& cuts, std::vector<ChordHit*>& active, glm::dvec3& radiance,
                 double& transmittance) const {
    radiance = glm::dvec3(0.0);
    cuts.clear();
    for (const ChordHit& h : hits) {
      cuts.push_back(h.enter);
      cuts.push_back(h.exit);
      if (h.nearest > h.enter && h.nearest < h.exit) cuts.push_back(h.nearest);
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    double passedLogKeep = 0.0;  // sum of log K of the particles already left behind
    // Per node of a panel: each active particle's field and source (3 nodes: start, middle, end).
    std::vector<double> sigmaM, sigma1, tauM, tau1;
    std::vector<glm::dvec3> sourceM, source1;
    for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
      const double a = cuts[c], b = cuts[c + 1];
      active.clear();
      for (ChordHit& h : hits) {
        if (!h.done && h.exit <= a) {
          h.done = true;
          passedLogKeep += logKeep(h.burn, h.tau);
        }
        if (!h.done && h.enter <= a && h.exit >= b) active.push_back(&h);
      }
      if (active.empty()) continue;
      const std::size_t na = active.size();
      sigmaM.resize(na);
      sigma1.resize(na);
      tauM.resize(na);
      tau1.resize(na);
      sourceM.resize(na);
      source1.resize(na);
      const glm::dvec3 xa = o + dir * a;
      for (ChordHit* h : active) field(*h, xa, h->sigma0, h->source0);
      const int panels = std::max(1, static_cast<int>(std::ceil((b - a) / step)));
      for (int q = 0; q < panels; ++q) {
        const double s0 = a + (b - a) * q / panels, s1 = q + 1 == panels ? b : a + (b - a) * (q + 1) / panels;
        const double len = s1 - s0, sm = 0.5 * (s0 + s1);
        const glm::dvec3 xm = o + dir * sm, x1 = o + dir * s1;
        double lk0 = passedLogKeep, lkM = passedLogKeep, lk1 = passedLogKeep;
        for (std::size_t j = 0; j < na; ++j) {
          const ChordHit& h = *active[j];
          field(h, xm, sigmaM[j], sourceM[j]);
          field(h, x1, sigma1[j], source1[j]);
          // The optical depth at the middle: the integral of the quadratic through the three values.
          tauM[j] = h.tau + len / 24.0 * (5.0 * h.sigma0 + 8.0 * sigmaM[j] - sigma1[j]);
          tau1[j] = h.tau + len / 6.0 * (h.sigma0 + 4.0 * sigmaM[j] + sigma1[j]);
          lk0 += logKeep(h.burn, h.tau);
          lkM += logKeep(h.burn, tauM[j]);
          lk1 += logKeep(h.burn, tau1[j]);
        }
        // Each source seen through its own particle (exp(-tau_i)) and the others' K (exp of the
        // sum of log K without its own).
        glm::dvec3 f0(0.0), fM(0.0), f1(0.0);
        for (std::size_t j = 0; j < na; ++j) {
          const ChordHit& h = *active[j];
          f0 += h.sigma0 * h.source0 * std::exp(lk0 - logKeep(h.burn, h.tau) - h.tau);
          fM += sigmaM[j] * sourceM[j] * std::exp(lkM - logKeep(h.burn, tauM[j]) - tauM[j]);
          f1 += sigma1[j] * source1[j] * std::exp(lk1 - logKeep(h.burn, tau1[j]) - tau1[j]);
        }
        radiance += len / 6.0 * (f0 + 4.0 * fM + f1);
        for (std::size_t j = 0; j < na; ++j) {
          ChordHit& h = *active[j];
          h.tau = tau1[j];
          h.sigma0 = sigma1[j];
          h.source0 = source1[j];
        }
      }
    }
    double logT = passedLogKeep;
    for (const ChordHit& h : hits)
      if (!h.done) logT += logKeep(h.burn, h.tau);
    transmittance = std::exp(logT);
  }

  // One row of pixels (GL row j, 0 at the bottom) into out and layer.
  void traceRow(int j, double step, core::Image& out, core::Image* layer) const {
    const int w = f.viewport.width, h = f.viewport.height;
    std::vector<ChordHit> hits;
    hits.reserve(prepared.size());
    std::vector<double> cuts;
    std::vector<ChordHit*> active;
    for (int i = 0; i < w; ++i) {
      const std::size_t gl = static_cast<std::size_t>(j) * w + i;
      const Ray ray = detail::rayThrough(invProj, f.orthographic(), w, h, i, j);
      const glm::dvec3& o = ray.origin;
      const glm::dvec3& dir = ray.direction;
      const double lin = in.opaqueDepth.empty() ? 1.0 : in.opaqueDepth[gl];
      const double zs = lin >= 1.0 ? std::numeric_limits<double>::infinity() : nearPlane + lin * (farPlane - nearPlane);
      // The view-axis distances of the near plane and the surface as ray parameters (as
      // media::sphereOpacity clips).
      const double cosA = -dir.z, oz = -o.z;
      const double tNear = (nearPlane - oz) / cosA, tScene = (zs - oz) / cosA;
      gatherHits(o, dir, tNear, tScene, glm::dot(toLight, dir), hits);
      glm::dvec3 media(0.0);
      double transmittance = 1.0;
      if (!hits.empty()) integrate(o, dir, hits, step, cuts, active, media, transmittance);
      const glm::dvec3 opaque = in.opaqueColor.empty() ? glm::dvec3(in.background) : glm::dvec3(in.opaqueColor[gl]);
      const glm::dvec3 c = opaque * transmittance + media;
      const int y = h - 1 - j;  // core::Image: row 0 at the top
      for (int ch = 0; ch < 3; ++ch) out.at(i, y, ch) = static_cast<float>(c[ch]);
      if (layer) {
        for (int ch = 0; ch < 3; ++ch) layer->at(i, y, ch) = static_cast<float>(media[ch]);
        layer->at(i, y, 3) = static_cast<float>(transmittance);
      }
    }
  }

  void render(double step, core::Image& out, core::Image* layer) const {
    const int w = f.viewport.width, h = f.viewport.height;
    out = core::Image(w, h, 4, 1.0f);
    if (layer) *layer = core::Image(w, h, 4, 1.0f);
    core::parallelFor(
        static_cast<std::size_t>(h), [&](std::size_t row) { traceRow(static_cast<int>(row), step, out, layer); }, 1);
  }
};

Result<void> checkOptions(const MediaReferenceInput& in, const PhysicalOptions& o) {
  const std::string at = "media physical reference: ";
  if (in.viewAxisOrder) return Error{at + "viewAxisOrder: the integral has no order; expected false"};
  if (!(std::isfinite(o.step) && o.step >= 0.0))
    return Error{at + "step: expected 0 (automatic) or a positive length, got " + core::numberText(o.step)};
  if (!(std::isfinite(o.tolerance) && o.tolerance > 0.0))
    return Error{at + "tolerance: expected a positive number, got " + core::numberText(o.tolerance)};
  if (o.maxHalvings < 0 || o.maxHalvings > 24)
    return Error{at + "maxHalvings: expected 0 to 24, got " + std::to_string(o.maxHalvings)};
  return {};
}

}  // namespace

Result<core::Image> renderMediaPhysical(const MediaReferenceInput& in, const PhysicalOptions& options,
                                        core::Image* layer, PhysicalReport* report) {
  PUFF_TRY(detail::checkInput(in));
  PUFF_TRY(checkOptions(in, options));
  PhysicalTracer tracer(in);
  PUFF_TRY(tracer.prepare());
  PhysicalReport r;
  core::Image out;
  const double largest = tracer.largestRadius();
  if (options.step > 0.0 || largest == 0.0) {
    // A fixed step, or no particle to integrate (any step gives the same image).
    r.step = largest == 0.0 ? 0.0 : options.step;
    r.converged = true;
    tracer.render(options.step > 0.0 ? options.step : 1.0, out, layer);
    r.images = 1;
  } else {
    r.step = 0.5 * largest;
    tracer.render(r.step, out, layer);
    r.images = 1;
    core::Image next, nextLayer;
    while (r.halvings < options.maxHalvings) {
      r.step *= 0.5;
      ++r.halvings;
      tracer.render(r.step, next, layer ? &nextLayer : nullptr);
      ++r.images;
      r.lastChange = imageError(next, out).rmse;
      std::swap(out, next);
      if (layer) std::swap(*layer, nextLayer);
      if (r.lastChange < options.tolerance) {
        r.converged = true;
        break;
      }
    }
  }
  if (report) *report = r;
  return out;
}

}  // namespace puff::reference
