// Private to puff::sim: the simulator's state (Simulator::Impl) and the pieces its files share.
// simulator.cpp steps it and keeps the arrays; forces.cpp works out the air and integrates;
// colliders.cpp puts particles back outside the colliders; emit.cpp gives birth to particles and
// sheds the moving vortices' wakes; workers.h is the thread pool.
//
// A step resolves what is shared (live vortices, turbulence offset, colliders where they are) once,
// then moves the particles in blocks: air, integration, collisions and ageing run on one block
// while it is in cache, and the blocks are split between threads. Every per-particle operation
// reads and writes only that particle, so the result does not depend on the split; counts are
// integers summed after. Births, removal and shedding stay serial.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <puff/sim/simulator.h>
#include <glm/common.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "curl_noise.h"
#include "workers.h"

namespace puff::sim {

namespace detail {

// A mesh collider: world-space triangles binned in a uniform grid.
struct MeshGrid {
  std::vector<glm::vec3> a, e1, e2, n;  // vertex 0, edges, unit normal
  glm::vec3 lo{0.0f}, hi{0.0f}, cell{1.0f};
  glm::ivec3 dims{1};
  std::vector<std::uint32_t> start, items;

  explicit MeshGrid(const Collider& c);
  glm::ivec3 cellOf(const glm::vec3& p) const {
    // Clamped while still float: a far-away point must not overflow the int conversion.
    return glm::ivec3(glm::clamp(glm::floor((p - lo) / cell), glm::vec3(0.0f), glm::vec3(dims - 1)));
  }
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * dims.y + static_cast<std::size_t>(y)) * dims.x + static_cast<std::size_t>(x);
  }

  // The first crossing of the segment p -> q with the surface: its parameter and the triangle.
  bool firstHit(const glm::vec3& p, const glm::vec3& q, float& tHit, std::uint32_t& triHit) const;
};

struct ShedVortex {
  glm::vec3 position, axis;
  float strength, radius, falloff, length;
  double born, lifetime;
};

// A vortex resolved for one step: where it is and how strong.
struct LiveVortex {
  glm::vec3 center, axis;
  float scale;        // strength / peak * radius
  float invRadius2;   // 1 / radius^2
  float invFalloff2;  // 0 = none
  float invHalfLength2;
  float cutoff2;  // beyond this squared distance it adds nothing worth computing
};

// A collider resolved for one step: where it is and its frame.
struct StepCollider {
  Collider::Type type = Collider::Type::kPlane;
  glm::mat3 frame{1.0f};  // plane: world to local (rows: x, normal, z); box: local to world
  glm::vec3 center{0.0f}, halfExtent{0.0f};
  glm::vec3 up{0.0f};  // sphere: the way out from its very centre
  float keep = 1.0f;   // 1 - friction
  // Meshes: which one, its offset at the step's start and end, and its velocity.
  std::size_t mesh = 0;
  glm::vec3 offset0{0.0f}, offset1{0.0f}, velocity{0.0f};
};

// A loop's births (Settings::period): an emitter runs for `window` seconds of every period, with
// `perPeriod` births spaced evenly through it (its rate rounded; 0 when the rate is).
struct LoopBirths {
  double period = 0.0, window = 0.0;
  std::int64_t perPeriod = 0;
};
inline LoopBirths loopBirths(const Emitter& e, double period) {
  LoopBirths b;
  b.period = period;
  b.window = e.duration > 0.0f ? std::min(static_cast<double>(e.duration), period) : period;
  b.perPeriod = e.rate > 0.0f ? std::max<std::int64_t>(1, std::llround(e.rate * b.window)) : 0;
  return b;
}

// The longest life an emitter gives (its lifetime stretched by its spread), seconds.
inline double longestLife(const Emitter& e) { return static_cast<double>(e.lifetime) * (1.0 + e.lifetimeSpread); }

// What one block of particles counted.
struct BlockStats {
  std::size_t collisions = 0, died = 0, nonFinite = 0;
};

}  // namespace detail

// validate.cpp: a loop's check of forces set while it runs (validate checks them at create).
Result<void> validateLoopForces(const Forces& forces, const std::string& pointer);

struct Simulator::Impl {
  Settings s;
  int variations = 1;
  double h = 0.0;
  std::int64_t prerollSteps = 0;
  std::int64_t step = 0;
  std::unique_ptr<detail::CurlField> curl;
  std::uint32_t curlSeed = 0;
  glm::vec3 loopDrift{0.0f};             // a loop's turbulence drift: whole lattice tiles per period
  std::vector<detail::MeshGrid> meshes;  // one per kMesh collider, in order
  std::vector<detail::ShedVortex> shed;

  // Structure of arrays.
  std::vector<float> px, py, pz, vx, vy, vz, age, life, size0, density0;
  std::vector<float> qx, qy, qz, qw, wx, wy, wz;  // birth orientation, angular velocity
  std::vector<std::uint8_t> variation, oriented;
  std::vector<std::uint32_t> emitterOf, id;  // which emitter; a hash of (seed, emitter, birth index)
  // Scratch, one entry per particle: air velocity, previous position, collision radius, and
  // whether the particle lives on after this step.
  std::vector<float> ux, uy, uz, ox, oy, oz, radii;
  std::vector<std::uint8_t> keep;

  // Threads (Settings::threads resolved, >= 1) and the pool of the threads past the first.
  int threads = 1;
  std::unique_ptr<detail::Workers> workers;

  // Resolved once per step, read by every block.
  std::vector<detail::LiveVortex> stepVortices;
  glm::vec3 stepTurbulenceOffset{0.0f};
  std::vector<detail::StepCollider> stepColliders;

  std::size_t size() const { return px.size(); }

  // simulator.cpp: one step, the threads, and the arrays.
  void advance(StepStats& st);
  void setThreads(int count);
  // Particles [begin, end) through the step: air, integration, collisions, ageing (in blocks).
  detail::BlockStats moveRange(std::size_t begin, std::size_t end);
  void clear();
  void compact();  // drops the particles whose `keep` is 0, keeping the order

  // forces.cpp: the air and the integrator.
  void prepareTurbulence();
  double loopSeconds() const;  // a loop's period in seconds (Settings::period > 0)
  std::vector<detail::LiveVortex> liveVortices(double t) const;
  float turbulenceInvTile() const;
  // At step boundary b (time b * h): a loop's offset from b modulo the period's steps, exactly.
  glm::vec3 turbulenceOffset(std::int64_t b) const;
  glm::vec3 air(const glm::vec3& p, std::int64_t b, const std::vector<detail::LiveVortex>& vortices) const;
  // The air at particles [begin, end) into ux/uy/uz, from stepVortices and stepTurbulenceOffset.
  void airRange(std::size_t begin, std::size_t end);
  void integrateRange(std::size_t begin, std::size_t end);

  // colliders.cpp: stepColliders for the step t0 -> t1, then the contacts of particles
  // [begin, end) (their radii into `radii`). `prev` (x, y, z arrays indexed from `begin`) is
  // where the particles were before they moved, for the mesh colliders.
  void prepareColliders(double t0, double t1);
  std::size_t collide(std::size_t begin, std::size_t end, const float* const* prev);

  // emit.cpp
  void spawn(std::int64_t b0, StepStats& st);  // births in the step from boundary b0 (time b0 * h) to b0 + 1
  void shedVortices(double t0, double t1);
};

}  // namespace puff::sim
