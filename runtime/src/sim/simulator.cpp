// The smoke simulator; simulator.h gives the model and the integrator.
#include <puff/sim/simulator.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "simulator_impl.h"

namespace puff::sim {

// ---- paths ---------------------------------------------------------------------------------------

namespace {

// The segment [i - 1, i] holding t, for times.front() < t < times.back(): compared in double, and
// clamped, so a t that rounds to the last key as a float still finds a segment.
std::size_t segmentOf(const std::vector<float>& times, double t) {
  const auto it = std::upper_bound(times.begin(), times.end(), t,
                                   [](double value, float key) { return value < static_cast<double>(key); });
  return std::clamp<std::size_t>(static_cast<std::size_t>(it - times.begin()), 1, times.size() - 1);
}

}  // namespace

glm::vec3 Path::at(double t) const {
  if (times.empty()) return glm::vec3(0.0f);
  if (t <= times.front()) return points.front();
  if (t >= times.back()) return points.back();
  const std::size_t i = segmentOf(times, t);
  const double t0 = times[i - 1], t1 = times[i];
  const float f = static_cast<float>(std::clamp((t - t0) / (t1 - t0), 0.0, 1.0));
  return glm::mix(points[i - 1], points[i], f);
}

glm::vec3 Path::velocityAt(double t) const {
  if (times.size() < 2 || t < times.front() || t >= times.back()) return glm::vec3(0.0f);
  const std::size_t i = segmentOf(times, t);
  return (points[i] - points[i - 1]) / (times[i] - times[i - 1]);
}

// ---- the simulator -------------------------------------------------------------------------------

void Simulator::Impl::advance(StepStats& st) {
  // Scene time: frame 0 is at 0, the preroll before it.
  const double t0 = static_cast<double>(step - prerollSteps) * h, t1 = static_cast<double>(step + 1 - prerollSteps) * h;
  const std::size_t n = size();
  airAll(t0);
  const bool haveMesh = !meshes.empty();
  if (haveMesh) ox = px, oy = py, oz = pz;
  integrate();
  const float* prev[3] = {ox.data(), oy.data(), oz.data()};
  if (!s.colliders.empty()) st.collisions += collide(0, n, prev, t0, t1);
  // Age, and remove the dead and the non-finite, keeping the order.
  const float hf = static_cast<float>(h);
  std::size_t out = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float a = age[i] + hf;
    const bool finite = std::isfinite(px[i]) && std::isfinite(py[i]) && std::isfinite(pz[i]) && std::isfinite(vx[i]) &&
                        std::isfinite(vy[i]) && std::isfinite(vz[i]);
    if (!finite) ++st.nonFinite;
    if (a >= life[i] || !finite) {
      if (finite) ++st.died;
      continue;
    }
    if (out != i) move(i, out);
    age[out] = a;
    ++out;
  }
  resize(out);
  const std::size_t before = size();
  ox.clear(), oy.clear(), oz.clear();
  spawn(t0, t1, st);
  const float* born[3] = {ox.data(), oy.data(), oz.data()};
  if (!s.colliders.empty()) st.collisions += collide(before, size(), born, t0, t1);
  shedVortices(t0, t1);
  ++step;
}

void Simulator::Impl::clear() {
  for (auto* v : {&px, &py, &pz, &vx, &vy, &vz, &age, &life, &size0, &density0, &qx, &qy, &qz, &qw, &wx, &wy, &wz})
    v->clear();
  variation.clear(), oriented.clear(), emitterOf.clear(), id.clear();
  shed.clear();
}

void Simulator::Impl::move(std::size_t from, std::size_t to) {
  for (auto* v : {&px, &py, &pz, &vx, &vy, &vz, &age, &life, &size0, &density0, &qx, &qy, &qz, &qw, &wx, &wy, &wz})
    (*v)[to] = (*v)[from];
  variation[to] = variation[from], oriented[to] = oriented[from];
  emitterOf[to] = emitterOf[from], id[to] = id[from];
}

void Simulator::Impl::resize(std::size_t n) {
  for (auto* v : {&px, &py, &pz, &vx, &vy, &vz, &age, &life, &size0, &density0, &qx, &qy, &qz, &qw, &wx, &wy, &wz})
    v->resize(n);
  variation.resize(n), oriented.resize(n), emitterOf.resize(n), id.resize(n);
}

Simulator::Simulator() : impl_(std::make_unique<Impl>()) {}
Simulator::~Simulator() = default;

Result<std::unique_ptr<Simulator>> Simulator::create(Settings settings, int variations) {
  if (auto ok = validate(settings); !ok) return ok.error();
  if (variations < 1 || variations > 256) return Error{"variations: expected an integer in [1, 256]"};
  std::unique_ptr<Simulator> sim(new Simulator());
  Impl& m = *sim->impl_;
  m.s = std::move(settings);
  m.variations = variations;
  m.h = 1.0 / (static_cast<double>(m.s.fps) * m.s.substeps);
  m.prerollSteps = static_cast<std::int64_t>(std::llround(m.s.preroll / m.h));
  for (Collider& c : m.s.colliders) {
    c.rotation = glm::normalize(c.rotation);  // the box and plane use it as a rotation
    if (c.type == Collider::Type::kMesh) m.meshes.emplace_back(c);
  }
  m.prepareTurbulence();
  sim->reset();
  return sim;
}

void Simulator::reset() {
  impl_->clear();
  impl_->step = 0;
  StepStats st;
  while (impl_->step < impl_->prerollSteps) impl_->advance(st);
}

void Simulator::step(StepStats* stats) {
  StepStats st;
  impl_->advance(stats ? *stats : st);
}

void Simulator::advanceToFrame(int frame, StepStats* stats) {
  PUFF_CHECK(frame >= 0);
  const std::int64_t target = impl_->prerollSteps + static_cast<std::int64_t>(frame) * impl_->s.substeps;
  if (target < impl_->step) reset();
  StepStats st;
  while (impl_->step < target) impl_->advance(stats ? *stats : st);
}

Result<void> Simulator::setForces(const Forces& forces) {
  if (auto ok = validate(forces); !ok) return ok.error();
  impl_->s.forces = forces;
  impl_->prepareTurbulence();
  return {};
}

const Settings& Simulator::settings() const { return impl_->s; }
double Simulator::time() const { return static_cast<double>(impl_->step - impl_->prerollSteps) * impl_->h; }
std::int64_t Simulator::stepIndex() const { return impl_->step; }

int Simulator::frame() const {
  const std::int64_t k = impl_->step - impl_->prerollSteps;
  if (k < 0 || k % impl_->s.substeps != 0) return -1;
  return static_cast<int>(k / impl_->s.substeps);
}

std::size_t Simulator::size() const { return impl_->size(); }

ParticleState Simulator::particle(std::size_t i) const {
  const Impl& m = *impl_;
  PUFF_CHECK(i < m.size());
  const float left = std::max(0.0f, 1.0f - m.age[i] / m.life[i]);
  ParticleState p;
  p.position = {m.px[i], m.py[i], m.pz[i]};
  p.velocity = {m.vx[i], m.vy[i], m.vz[i]};
  p.size = m.size0[i] * left;
  p.density = m.density0[i] * left;
  p.variation = m.variation[i];
  p.oriented = m.oriented[i] != 0;
  p.birthSize = m.size0[i];
  p.age = m.age[i];
  p.lifetime = m.life[i];
  p.emitter = static_cast<int>(m.emitterOf[i]);
  p.id = m.id[i];
  glm::quat q(m.qw[i], m.qx[i], m.qy[i], m.qz[i]);
  const glm::vec3 w(m.wx[i], m.wy[i], m.wz[i]);
  const float speed = glm::length(w);
  if (speed > 0.0f) q = glm::angleAxis(speed * m.age[i], w / speed) * q;
  p.orientation = q;
  return p;
}

glm::vec3 Simulator::airVelocity(const glm::vec3& p) const {
  const double t = time();
  return impl_->air(p, t, impl_->liveVortices(t));
}

std::size_t Simulator::liveVortices() const { return impl_->s.forces.vortices.size() + impl_->shed.size(); }

}  // namespace puff::sim
