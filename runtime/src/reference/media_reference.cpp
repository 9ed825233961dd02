// The media reference: billboard.frag's model per pixel, in double precision, with the exact
// functions where the GPU reads tables (see the header for what is exact and what is shared).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

#include <puff/core/blackbody.h>
#include <puff/core/random.h>
#include <puff/reference/media_reference.h>
#include <puff/support/parallel.h>

#include "media_shared.h"

namespace puff::reference {

namespace {

using detail::haveVideo;
using detail::Mixed;
using detail::Prepared;
using detail::rayThrough;

// One particle's contribution to one ray.
struct Hit {
  double t;  // distance along the ray to the chord's midpoint (or minus the view-axis rank)
  std::uint32_t index;
  double alpha, keep;  // opacity; what is left of the colour behind: 1 - alpha (1 - burn)
  glm::dvec3 radiance;
};

// The shader's detail-window hash (shaders/media/billboard.frag).
using core::lowbias32;

// GL_LINEAR with GL_REPEAT along one axis of n texels: the two texels and the weight of the second.
void repeatAxis(double coord, int n, int& i0, int& i1, double& w) {
  const double u = coord * n - 0.5;
  const double lo = std::floor(u);
  w = u - lo;
  const double k = lo - std::floor(lo / n) * n;  // lo mod n, in [0, n)
  i0 = std::clamp(static_cast<int>(k), 0, n - 1);
  i1 = i0 + 1 == n ? 0 : i0 + 1;
}

}  // namespace

double unitHash(std::uint32_t x) { return static_cast<double>(lowbias32(x) >> 8) / 16777216.0; }

double sampleDetail(const core::DetailVideo* v, double s, double t, double r) {
  if (!haveVideo(v)) return 0.5;
  PUFF_CHECK(v->values.size() == static_cast<std::size_t>(v->width) * v->height * v->frames);
  int x0, x1, y0, y1, k0, k1;
  double wx, wy, wk;
  repeatAxis(s, v->width, x0, x1, wx);
  repeatAxis(t, v->height, y0, y1, wy);
  repeatAxis(r, v->frames, k0, k1, wk);
  // makeDetailTexture flips the rows: texture row y (from the bottom) is the video's row h - 1 - y.
  auto at = [v](int x, int y, int k) { return static_cast<double>(v->values[v->index(x, v->height - 1 - y, k)]); };
  auto plane = [&](int k) {
    const double lo = at(x0, y0, k) * (1 - wx) + at(x1, y0, k) * wx;
    const double hi = at(x0, y1, k) * (1 - wx) + at(x1, y1, k) * wx;
    return lo * (1 - wy) + hi * wy;
  };
  return plane(k0) * (1 - wk) + plane(k1) * wk;
}

Ray pixelRay(const media::Frame& frame, int i, int j) {
  return rayThrough(glm::inverse(glm::dmat4(frame.projection)), frame.orthographic(), frame.viewport.width,
                    frame.viewport.height, i, j);
}

namespace {

// One frame of the reference: the frame's constants and its particles prepared once, then each
// pixel's ray through them.
struct Tracer : detail::FrameConstants {
  std::vector<std::uint32_t> rank;  // each particle's place in the renderer's back-to-front order
  std::vector<Prepared> prepared;
  std::vector<glm::dvec3> constantLe;

  explicit Tracer(const MediaReferenceInput& input) : FrameConstants(input) {
    // Each particle's place in the renderer's back-to-front order (used with viewAxisOrder): its
    // sort key (settings.sort) and the frame's projection, as media::Renderer::draw sorts.
    rank.assign(in.particles.size(), 0);
    if (in.viewAxisOrder) {
      const std::vector<std::uint32_t> order =
          media::backToFront(f.view, in.particles, s.sort,
                             f.orthographic() ? media::Projection::kOrthographic : media::Projection::kPerspective);
      for (std::size_t k = 0; k < order.size(); ++k) rank[order[k]] = static_cast<std::uint32_t>(k);
    }
  }

  // The particles a ray may meet: in camera space, their material mixed, culled as the billboards are.
  Result<void> prepare() {
    PUFF_TRY_ASSIGN(prepared, detail::prepareParticles(in, view));
    // Le(T) per pixel is 95 Planck evaluations; without a temperature video T is one value per
    // particle, so it is computed once.
    constantLe.assign(prepared.size(), glm::dvec3(0.0));
    if (!haveTemperature)
      for (std::size_t k = 0; k < prepared.size(); ++k)
        if (prepared[k].mat.emissive > 0.0) constantLe[k] = emitted(prepared[k].mat.t0 + prepared[k].mat.t1 * 0.5);
    return {};
  }

  glm::dvec3 emitted(double kelvin) const { return detail::emitted(s, yNorm, kelvin); }

  // Every particle the ray from o along dir meets in front of the opaque depth zs.
  void gatherHits(const glm::dvec3& o, const glm::dvec3& dir, double zs, double cosTheta,
                  std::vector<Hit>& hits) const {
    const double fourPi = 4.0 * std::numbers::pi;
    hits.clear();
    for (std::size_t k = 0; k < prepared.size(); ++k) {
      const Prepared& p = prepared[k];
      const glm::dvec3 m = o - p.centre;
      const double b = glm::dot(m, dir);
      const glm::dvec3 across = glm::cross(m, dir);
      if (!(glm::dot(across, across) < p.radius * p.radius)) continue;
      const Mixed& mt = p.mat;
      // The particle's window of the detail videos, at the ray's point nearest the centre.
      const glm::dvec3 closest = o + dir * (-b) - p.centre;
      const double u = p.windowX + (closest.x / (2.0 * p.radius) + 0.5) * mt.window;
      const double v = p.windowY + (closest.y / (2.0 * p.radius) + 0.5) * mt.window;
      double tau = p.tau;
      if (mt.detail != 0.0) {
        const double d = sampleDetail(in.opacityDetail, u, v, p.time0 + time * mt.speed / opacityFrames);
        tau *= std::max(0.0, 1.0 + mt.detail * (2.0 * d - 1.0));
      }
      const double alpha = media::sphereOpacity(o, dir, p.centre, p.radius, tau, zs, nearPlane);
      if (!(alpha > 0.0)) continue;
      glm::dvec3 radiance(0.0);
      if (mt.albedo > 0.0) {  // 0 for emitters: fire turning into smoke scatters linearly more
        const glm::dvec3 c = ambient + lightColor * (fourPi * media::phase(s.phase, cosTheta, mt.g));
        radiance += mt.albedo * mt.color * c;
      }
      if (mt.emissive > 0.0) {
        const glm::dvec3 le = haveTemperature
                                  ? emitted(mt.t0 + mt.t1 * sampleDetail(in.temperatureDetail, u, v,
                                                                         p.time0 + time * mt.speed / temperatureFrames))
                                  : constantLe[k];
        radiance += mt.emissive * mt.emission * exposure * le;
      }
      radiance *= p.tint;
      const double burn = std::clamp(mt.burn, 0.0, 1.0);
      const double t = in.viewAxisOrder ? -static_cast<double>(rank[p.index]) : -b;
      hits.push_back({t, p.index, alpha, 1.0 - alpha * (1.0 - burn), radiance});
    }
  }

  // One row of pixels (GL row j, 0 at the bottom) into out and layer.
  void traceRow(int j, core::Image& out, core::Image* layer) const {
    const int w = f.viewport.width, h = f.viewport.height;
    std::vector<Hit> hits;
    hits.reserve(prepared.size());
    for (int i = 0; i < w; ++i) {
      const std::size_t gl = static_cast<std::size_t>(j) * w + i;
      const Ray ray = rayThrough(invProj, f.orthographic(), w, h, i, j);
      const glm::dvec3& o = ray.origin;
      const glm::dvec3& dir = ray.direction;
      const double lin = in.opaqueDepth.empty() ? 1.0 : in.opaqueDepth[gl];
      const double zs = lin >= 1.0 ? std::numeric_limits<double>::infinity() : nearPlane + lin * (farPlane - nearPlane);
      const double cosTheta = glm::dot(toLight, dir);
      gatherHits(o, dir, zs, cosTheta, hits);
      // Back to front along this ray: farthest chord midpoint first (index breaks ties).
      std::sort(hits.begin(), hits.end(),
                [](const Hit& a, const Hit& b) { return a.t > b.t || (a.t == b.t && a.index < b.index); });
      glm::dvec3 media(0.0);
      double transmittance = 1.0;
      for (const Hit& hit : hits) {
        media = hit.alpha * hit.radiance + media * hit.keep;
        transmittance *= hit.keep;
      }
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
};

}  // namespace

Result<core::Image> renderMediaReference(const MediaReferenceInput& in, core::Image* layer) {
  PUFF_TRY(detail::checkInput(in));
  Tracer tracer(in);
  PUFF_TRY(tracer.prepare());
  const int w = in.frame.viewport.width, h = in.frame.viewport.height;
  core::Image out(w, h, 4, 1.0f);
  if (layer) *layer = core::Image(w, h, 4, 1.0f);
  core::parallelFor(
      static_cast<std::size_t>(h), [&](std::size_t row) { tracer.traceRow(static_cast<int>(row), out, layer); }, 1);
  return out;
}

}  // namespace puff::reference
