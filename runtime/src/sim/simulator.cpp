// The smoke simulator; simulator.h gives the model and the integrator.
#include <puff/sim/simulator.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>
#include <utility>

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

namespace {

// The keys around `age` and the weight of the later one, for ages.front() < age < ages.back().
std::pair<std::size_t, float> lifeSegment(const std::vector<float>& ages, float age, LifeCurve::Interp interp) {
  std::size_t i = 1;
  while (i < ages.size() && ages[i] < age) ++i;
  float t = (age - ages[i - 1]) / (ages[i] - ages[i - 1]);
  if (interp == LifeCurve::Interp::kSmooth) t = t * t * (3.0f - 2.0f * t);
  return {i, t};
}

}  // namespace

float LifeCurve::at(float age) const {
  if (ages.empty()) return 1.0f;
  if (!(age > ages.front())) return values.front();
  if (age >= ages.back()) return values.back();
  const auto [i, t] = lifeSegment(ages, age, interp);
  return values[i - 1] + (values[i] - values[i - 1]) * t;
}

glm::vec3 ColourCurve::at(float age) const {
  if (ages.empty()) return glm::vec3(1.0f);
  if (!(age > ages.front())) return values.front();
  if (age >= ages.back()) return values.back();
  const auto [i, t] = lifeSegment(ages, age, interp);
  return values[i - 1] + (values[i] - values[i - 1]) * t;
}

glm::vec3 Path::at(double t) const {
  if (times.empty()) return glm::vec3(0.0f);
  if (t <= times.front()) return points.front();
  if (t >= times.back()) return points.back();
  const std::size_t i = segmentOf(times, t);
  if (points[i - 1] == points[i]) return points[i];  // a still segment is exactly still (mix would round)
  const double t0 = times[i - 1], t1 = times[i];
  const float f = static_cast<float>(std::clamp((t - t0) / (t1 - t0), 0.0, 1.0));
  return glm::mix(points[i - 1], points[i], f);
}

glm::quat Path::rotationAt(double t) const {
  if (rotations.empty() || rotations.size() != times.size()) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  if (t <= times.front()) return rotations.front();
  if (t >= times.back()) return rotations.back();
  const std::size_t i = segmentOf(times, t);
  const double t0 = times[i - 1], t1 = times[i];
  const float f = static_cast<float>(std::clamp((t - t0) / (t1 - t0), 0.0, 1.0));
  return glm::normalize(glm::slerp(rotations[i - 1], rotations[i], f));
}

bool Path::moves() const {
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (points[i] != points[0] || (i < rotations.size() && rotations[i] != rotations[0])) return true;
  }
  return false;
}

glm::vec3 Path::velocityAt(double t) const {
  if (times.size() < 2 || t < times.front() || t >= times.back()) return glm::vec3(0.0f);
  const std::size_t i = segmentOf(times, t);
  return (points[i] - points[i - 1]) / (times[i] - times[i - 1]);
}

// ---- the simulator -------------------------------------------------------------------------------

namespace {

// Particles moved together through air, integration, collisions and ageing while their arrays
// stay in cache (14 arrays of 2048 floats: 112 KB, in the second-level cache), and the unit the
// threads share the work out in. Measured on 50,000 particles (the bench's full case): 256 to
// 8192 run alike on one thread; on two, 256 and 512 were 10-25% slower than 1024 to 4096.
constexpr std::size_t kBlock = 2048;
// Fewer particles than this per thread are not worth waking a thread for.
constexpr std::size_t kMinPerThread = 4096;

// Ages particles by h and marks in `keep` those that live on: finite and younger than their
// lifetime. Returns how many do not, and how many of those are not finite in `nonFinite`.
// Branch-free, so it vectorizes.
PUFF_SIM_KERNEL std::size_t ageRange(const float* __restrict X, const float* __restrict Y, const float* __restrict Z,
                                     const float* __restrict VX, const float* __restrict VY, const float* __restrict VZ,
                                     const float* __restrict L, float h, float* __restrict A,
                                     std::uint8_t* __restrict keep, std::size_t n, std::size_t& nonFinite) {
  std::uint32_t gone = 0, bad = 0;  // 32-bit: with size_t counters GCC 12 does not vectorize the loop
  for (std::size_t i = 0; i < n; ++i) {
    const float a = A[i] + h;
    // Finite: |x| <= max (false for infinities and NaN).
    constexpr float kMax = std::numeric_limits<float>::max();
    const bool finite = (std::abs(X[i]) <= kMax) & (std::abs(Y[i]) <= kMax) & (std::abs(Z[i]) <= kMax) &
                        (std::abs(VX[i]) <= kMax) & (std::abs(VY[i]) <= kMax) & (std::abs(VZ[i]) <= kMax);
    const bool lives = finite & (a < L[i]);
    A[i] = a;
    keep[i] = lives ? 1 : 0;
    gone += lives ? 0 : 1;
    bad += finite ? 0 : 1;
  }
  nonFinite = bad;
  return gone;
}

}  // namespace

void Simulator::Impl::advance(StepStats& st) {
  // Scene time: frame 0 is at 0, the preroll before it.
  const double t0 = static_cast<double>(step - prerollSteps) * h, t1 = static_cast<double>(step + 1 - prerollSteps) * h;
  const std::size_t n = size();
  // What every particle reads, resolved once.
  stepVortices = liveVortices(t0);
  stepTurbulenceOffset = turbulenceOffset(step - prerollSteps);
  prepareColliders(t0, t1);
  ux.resize(n), uy.resize(n), uz.resize(n), radii.resize(n), keep.resize(n);
  if (!meshes.empty()) ox.resize(n), oy.resize(n), oz.resize(n);
  // Each thread takes blocks of kBlock particles in order from its own contiguous share (so the
  // hardware prefetcher streams within it, not into another thread's blocks), then from the
  // others' shares until none is left, so a thread the scheduler runs late takes fewer. Each
  // particle is computed the same whichever thread takes its block; the counts are integers,
  // summed in any order.
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  const int parts = static_cast<int>(
      std::min<std::size_t>(static_cast<std::size_t>(threads), std::max<std::size_t>(1, n / kMinPerThread)));
  struct alignas(64) Share {
    std::atomic<std::size_t> next{0};
    std::size_t end = 0;
  };
  std::vector<Share> shares(static_cast<std::size_t>(parts));
  for (std::size_t t = 0; t < shares.size(); ++t) {
    shares[t].next.store(blocks * t / shares.size(), std::memory_order_relaxed);
    shares[t].end = blocks * (t + 1) / shares.size();
  }
  std::vector<detail::BlockStats> counts(static_cast<std::size_t>(parts));
  auto part = [&](int t) {
    detail::BlockStats mine;
    for (std::size_t k = 0; k < shares.size(); ++k) {
      Share& share = shares[(static_cast<std::size_t>(t) + k) % shares.size()];
      for (std::size_t b = share.next.fetch_add(1, std::memory_order_relaxed); b < share.end;
           b = share.next.fetch_add(1, std::memory_order_relaxed)) {
        const detail::BlockStats c = moveRange(b * kBlock, std::min(n, (b + 1) * kBlock));
        mine.collisions += c.collisions, mine.died += c.died, mine.nonFinite += c.nonFinite;
      }
    }
    counts[static_cast<std::size_t>(t)] = mine;
  };
  if (workers && parts > 1)
    workers->run(parts, part);
  else
    part(0);
  std::size_t removed = 0;
  for (const detail::BlockStats& c : counts) {
    st.collisions += c.collisions, st.died += c.died, st.nonFinite += c.nonFinite;
    removed += c.died + c.nonFinite;
  }
  if (removed > 0) compact();
  const std::size_t before = size();
  ox.clear(), oy.clear(), oz.clear();
  spawn(step - prerollSteps, st);
  const float* born[3] = {ox.data(), oy.data(), oz.data()};
  if (!s.colliders.empty() && size() > before) {
    radii.resize(size());
    st.collisions += collide(before, size(), born);
  }
  shedVortices(t0, t1);
  ++step;
}

detail::BlockStats Simulator::Impl::moveRange(std::size_t begin, std::size_t end) {
  detail::BlockStats out;
  const float hf = static_cast<float>(h);
  const bool haveMesh = !meshes.empty();
  for (std::size_t b = begin; b < end; b += kBlock) {
    const std::size_t e = std::min(end, b + kBlock);
    airRange(b, e);
    if (haveMesh) {  // where the particles start, for the mesh colliders' segment test
      std::copy(px.begin() + b, px.begin() + e, ox.begin() + b);
      std::copy(py.begin() + b, py.begin() + e, oy.begin() + b);
      std::copy(pz.begin() + b, pz.begin() + e, oz.begin() + b);
    }
    integrateRange(b, e);
    if (!s.colliders.empty()) {
      // Where the particles started, for the mesh colliders (none without a mesh: then no start).
      const float* prev[3] = {nullptr, nullptr, nullptr};
      if (haveMesh) prev[0] = ox.data() + b, prev[1] = oy.data() + b, prev[2] = oz.data() + b;
      out.collisions += collide(b, e, prev);
    }
    std::size_t nonFinite = 0;
    const std::size_t dead =
        ageRange(px.data() + b, py.data() + b, pz.data() + b, vx.data() + b, vy.data() + b, vz.data() + b,
                 life.data() + b, hf, age.data() + b, keep.data() + b, e - b, nonFinite);
    out.nonFinite += nonFinite;
    out.died += dead - nonFinite;
  }
  return out;
}

void Simulator::Impl::setThreads(int count) {
  const int resolved = count > 0 ? count : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  s.threads = count;
  if (resolved == threads && (resolved == 1 || workers)) return;
  threads = resolved;
  workers = resolved > 1 ? std::make_unique<detail::Workers>(resolved) : nullptr;
}

void Simulator::Impl::clear() {
  for (auto* v : {&px, &py, &pz, &vx, &vy, &vz, &age, &life, &size0, &density0, &qx, &qy, &qz, &qw, &wx, &wy, &wz})
    v->clear();
  variation.clear(), oriented.clear(), emitterOf.clear(), id.clear();
  shed.clear();
}

namespace {

// Keeps the entries whose flag is set, in order; returns how many.
template <class T>
std::size_t keepFlagged(std::vector<T>& v, const std::vector<std::uint8_t>& keep) {
  std::size_t out = 0;
  for (std::size_t i = 0; i < keep.size(); ++i) {
    v[out] = v[i];
    out += keep[i];
  }
  v.resize(out);
  return out;
}

}  // namespace

void Simulator::Impl::compact() {
  for (auto* v : {&px, &py, &pz, &vx, &vy, &vz, &age, &life, &size0, &density0, &qx, &qy, &qz, &qw, &wx, &wy, &wz})
    keepFlagged(*v, keep);
  keepFlagged(variation, keep), keepFlagged(oriented, keep);
  keepFlagged(emitterOf, keep), keepFlagged(id, keep);
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
  // Two steps more than the longest life: ages are summed in float, and one that rounds short must
  // not leave a particle alive at frame period that frame 0 lacks.
  constexpr std::int64_t kLoopMargin = 2;
  if (m.s.period > 0) {  // a loop starts in its steady state: every particle alive at frame 0 was born in the preroll
    for (const Emitter& e : m.s.emitters)
      m.prerollSteps =
          std::max(m.prerollSteps, static_cast<std::int64_t>(std::ceil(detail::longestLife(e) / m.h)) + kLoopMargin);
  }
  for (Collider& c : m.s.colliders) {
    c.rotation = glm::normalize(c.rotation);  // the box and plane use it as a rotation
    if (c.type == Collider::Type::kMesh) m.meshes.emplace_back(c);
  }
  m.prepareTurbulence();
  m.setThreads(m.s.threads);
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
  if (impl_->s.period > 0) {
    if (auto ok = validateLoopForces(forces, "/forces"); !ok) return ok.error();
  }
  impl_->s.forces = forces;
  impl_->prepareTurbulence();
  return {};
}

Result<void> Simulator::setThreads(int threads) {
  if (threads < 0 || threads > kMaxThreads)
    return Error{"threads: expected an integer in [0, " + std::to_string(kMaxThreads) + "], got " +
                 std::to_string(threads)};
  impl_->setThreads(threads);
  return {};
}

int Simulator::threads() const { return impl_->threads; }

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
  return impl_->air(p, impl_->step - impl_->prerollSteps, impl_->liveVortices(t));
}

std::size_t Simulator::liveVortices() const { return impl_->s.forces.vortices.size() + impl_->shed.size(); }

}  // namespace puff::sim
