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
#include <puff/core/parallel.h>
#include <puff/core/random.h>
#include <puff/reference/media_reference.h>

namespace puff::reference {

namespace {

constexpr int kMaxMaterials = 32;  // media::Renderer's table size

// A material after `becomes`, as the shader mixes it (MaterialGpu's fields), in double precision.
struct Mixed {
  glm::dvec3 color{1.0};
  double albedo = 0, density = 0, g = 0, emissive = 0, emission = 0, t0 = 0, t1 = 0, burn = 0, detail = 0, window = 0,
         speed = 0;
};

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

// One particle, prepared once per frame.
struct Prepared {
  glm::dvec3 centre{0.0};  // camera space
  double radius = 0.0;
  Mixed mat;
  double tau = 0.0;                            // material density * particle density, before detail
  double windowX = 0, windowY = 0, time0 = 0;  // the seed's place and time in the detail videos
  std::uint32_t index = 0;
};

// One particle's contribution to one ray.
struct Hit {
  double t;  // distance along the ray to the chord's midpoint (or minus the view-axis rank)
  std::uint32_t index;
  double alpha, keep;  // opacity; what is left of the colour behind: 1 - alpha (1 - burn)
  glm::dvec3 radiance;
};

// The shader's detail-window hash (shaders/media/billboard.frag).
using core::lowbias32;

bool haveVideo(const core::DetailVideo* v) { return v != nullptr && v->width > 0 && v->height > 0 && v->frames > 0; }

// GL_LINEAR with GL_REPEAT along one axis of n texels: the two texels and the weight of the second.
void repeatAxis(double coord, int n, int& i0, int& i1, double& w) {
  const double u = coord * n - 0.5;
  const double lo = std::floor(u);
  w = u - lo;
  const double k = lo - std::floor(lo / n) * n;  // lo mod n, in [0, n)
  i0 = std::clamp(static_cast<int>(k), 0, n - 1);
  i1 = i0 + 1 == n ? 0 : i0 + 1;
}

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

std::string number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
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
  return rayThrough(glm::inverse(glm::dmat4(frame.projection)), frame.orthographic, frame.width, frame.height, i, j);
}

namespace {

// The input's checks (sizes, materials, settings), in the renderer's words.
Result<void> checkInput(const MediaReferenceInput& in) {
  const media::Frame& f = in.frame;
  const int w = f.width, h = f.height;
  const std::string at = "media reference: ";
  if (w < 1 || h < 1 || w > 16384 || h > 16384)
    return Error{at + "frame size " + std::to_string(w) + "x" + std::to_string(h) + " outside 1..16384"};
  const std::size_t pixels = static_cast<std::size_t>(w) * h;
  if (!in.opaqueColor.empty() && in.opaqueColor.size() != pixels)
    return Error{at + "opaque colour: expected " + std::to_string(pixels) + " pixels, got " +
                 std::to_string(in.opaqueColor.size())};
  if (!in.opaqueDepth.empty() && in.opaqueDepth.size() != pixels)
    return Error{at + "opaque depth: expected " + std::to_string(pixels) + " pixels, got " +
                 std::to_string(in.opaqueDepth.size())};
  const int count = static_cast<int>(in.materials.size());
  if (count < 1 || count > kMaxMaterials)
    return Error{at + "materials: expected 1 to " + std::to_string(kMaxMaterials) + ", got " + std::to_string(count)};
  for (const media::Material& m : in.materials)
    if (auto ok = media::validate(m, count); !ok) return Error{at + ok.error().message};
  const media::Settings& s = in.settings;
  if (!(s.exposure >= 0.0f && s.exposure <= 1e4f))
    return Error{at + "exposure: expected a number in [0, 10000], got " + number(s.exposure)};
  // The same range checks (and error text) the renderer's ramp makes.
  if (auto ramp = core::makeBlackbodyRamp(s.minKelvin, s.maxKelvin, 2, s.normalizeKelvin); !ramp)
    return Error{at + ramp.error().message};
  return {};
}

// One frame of the reference: the frame's constants and its particles prepared once, then each
// pixel's ray through them.
struct Tracer {
  const MediaReferenceInput& in;
  const media::Frame& f;
  const media::Settings& s;
  double yNorm = 0.0;
  glm::dmat4 view{1.0}, invProj{1.0};
  double nearPlane = 0.0, farPlane = 0.0;
  glm::dvec3 toLight{0.0}, ambient{0.0}, lightColor{0.0};
  double time = 0.0, exposure = 0.0;
  bool haveTemperature = false, haveOpacity = false;
  double temperatureFrames = 1.0, opacityFrames = 1.0;
  std::vector<std::uint32_t> rank;  // each particle's place in the renderer's back-to-front order
  std::vector<Prepared> prepared;
  std::vector<glm::dvec3> constantLe;

  explicit Tracer(const MediaReferenceInput& input) : in(input), f(input.frame), s(input.settings) {
    yNorm = core::blackbodyXYZ(s.normalizeKelvin).y;
    view = glm::dmat4(f.view);
    invProj = glm::inverse(glm::dmat4(f.projection));
    nearPlane = f.nearPlane;
    farPlane = f.farPlane;
    glm::dvec3 l(f.lightDirection);
    l = glm::length(l) > 0.0 ? glm::normalize(l) : glm::dvec3(0, 1, 0);
    toLight = glm::normalize(glm::dvec3(view * glm::dvec4(l, 0.0)));
    ambient = glm::dvec3(f.ambient);
    lightColor = glm::dvec3(f.lightColor);
    time = f.time;
    exposure = s.exposure;
    haveTemperature = haveVideo(in.temperatureDetail);
    haveOpacity = haveVideo(in.opacityDetail);
    temperatureFrames = haveTemperature ? in.temperatureDetail->frames : 1;
    opacityFrames = haveOpacity ? in.opacityDetail->frames : 1;
    // Each particle's place in the renderer's back-to-front order (used with viewAxisOrder).
    rank.assign(in.particles.size(), 0);
    if (in.viewAxisOrder) {
      const std::vector<std::uint32_t> order = media::backToFront(f.view, in.particles);
      for (std::size_t k = 0; k < order.size(); ++k) rank[order[k]] = static_cast<std::uint32_t>(k);
    }
  }

  // The particles a ray may meet: in camera space, their material mixed, culled as the billboards are.
  Result<void> prepare() {
    const std::string at = "media reference: ";
    const int count = static_cast<int>(in.materials.size());
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
        const double t =
            end > start ? std::clamp((life - start) / (end - start), 0.0, 1.0) : (life < start ? 0.0 : 1.0);
        q.mat = mix(q.mat, fromMaterial(in.materials[static_cast<std::size_t>(m.becomes)]), t);
      }
      q.tau = q.mat.density * static_cast<double>(p.density);
      q.windowX = unitHash(p.seed);
      q.windowY = unitHash(p.seed ^ 0x68bc21ebu);
      q.time0 = unitHash(p.seed ^ 0x02e5be93u);
      q.index = static_cast<std::uint32_t>(k);
      prepared.push_back(q);
    }
    // Le(T) per pixel is 95 Planck evaluations; without a temperature video T is one value per
    // particle, so it is computed once.
    constantLe.assign(prepared.size(), glm::dvec3(0.0));
    if (!haveTemperature)
      for (std::size_t k = 0; k < prepared.size(); ++k)
        if (prepared[k].mat.emissive > 0.0) constantLe[k] = emitted(prepared[k].mat.t0 + prepared[k].mat.t1 * 0.5);
    return {};
  }

  glm::dvec3 emitted(double kelvin) const {
    kelvin = std::clamp(kelvin, static_cast<double>(s.minKelvin), static_cast<double>(s.maxKelvin));
    return glm::max(core::xyzToLinearSrgb(core::blackbodyXYZ(kelvin) / yNorm), glm::dvec3(0.0));
  }

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
      const double burn = std::clamp(mt.burn, 0.0, 1.0);
      const double t = in.viewAxisOrder ? -static_cast<double>(rank[p.index]) : -b;
      hits.push_back({t, p.index, alpha, 1.0 - alpha * (1.0 - burn), radiance});
    }
  }

  // One row of pixels (GL row j, 0 at the bottom) into out and layer.
  void traceRow(int j, core::Image& out, core::Image* layer) const {
    const int w = f.width, h = f.height;
    std::vector<Hit> hits;
    hits.reserve(prepared.size());
    for (int i = 0; i < w; ++i) {
      const std::size_t gl = static_cast<std::size_t>(j) * w + i;
      const Ray ray = rayThrough(invProj, f.orthographic, w, h, i, j);
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
  PUFF_TRY(checkInput(in));
  Tracer tracer(in);
  PUFF_TRY(tracer.prepare());
  const int w = in.frame.width, h = in.frame.height;
  core::Image out(w, h, 4, 1.0f);
  if (layer) *layer = core::Image(w, h, 4, 1.0f);
  core::parallelFor(
      static_cast<std::size_t>(h), [&](std::size_t row) { tracer.traceRow(static_cast<int>(row), out, layer); }, 1);
  return out;
}

}  // namespace puff::reference
