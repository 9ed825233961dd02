// The smoke simulator (McGuire & Fein §3): smoke as tracer particles in air that six
// artist-controlled forces move: vortex, buoyancy, gravity, wind, turbulence and drag toward the
// local air velocity. Particles collide with rigid bodies but not with each other, and dissipate:
// density falls linearly to zero over a particle's lifetime, and its size with it, so it shrinks
// to nothing instead of popping.
//
// Model. Wind (global and local volumes), vortices and turbulence define the AIR velocity u(x, t);
// gravity and buoyancy are accelerations. A particle obeys
//     dv/dt = g + buoyancy * density * up + drag * (u(x, t) - v)
// so drag is what couples smoke to the air: with drag 0 a particle is ballistic and the air fields
// do nothing to it; with a large drag it follows the air exactly.
//
// Integration. Fixed steps of 1 / (fps * substeps) seconds. Within a step u and the accelerations
// are held and the equation above is integrated exactly (exponential integrator), so the velocity
// stays between its start and its target u + a/drag for ANY drag * step: unconditionally stable.
// The paper's forward Euler (Integrator::kForwardEuler, kept for comparison) multiplies the
// velocity error by (1 - drag * step) per step and diverges once drag * step > 2.
//
// Time. Every time in the settings (paths, emitter start and stop, shedding) is scene time: frame
// f is at f / fps, and the preroll runs before 0 (an emitter meant to fill it starts at -preroll).
//
// Loops. With Settings::period the simulation repeats every `period` frames (P = period / fps
// seconds): births repeat each period with the same random numbers, the turbulence's drift closes
// on itself over a period, and nothing moves on a path, so a particle born at t + P retraces the
// one born at t. The preroll is at least the longest lifetime, so frame 0 is already in the loop:
// frame f + period draws what frame f does, and a flipbook of one period loops without a seam.
//
// Determinism. Every random number is a hash of (seed, emitter, particle index) and time is
// counted in whole steps, so a frame depends only on the settings and its number: frame k is
// reached by simulating from the start (reset + advanceToFrame), bit-identical on one machine.
//
// Threads. Settings::threads (or setThreads) splits each step's particles between threads. Every
// particle's air, integration, collisions and ageing read and write only that particle, counts
// are integers, and births, removal and vortex shedding stay on the calling thread, so the state
// after any number of steps is bit-identical for every thread count.
//
// Storage is structure-of-arrays; stepping touches only the arrays it needs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <puff/core/error.h>

namespace puff::sim {

/// A point moving through keyframes: linear between them, held before the first and after the
/// last. Empty: always at the origin. Times strictly increase (seconds).
struct Path {
  std::vector<float> times;
  std::vector<glm::vec3> points;
  /// Empty, or one unit quaternion per key: a turning body (a dynamic scene object's simulated
  /// trajectory), slerped between keys and held outside them; it turns about the body's origin.
  std::vector<glm::quat> rotations;
  glm::vec3 at(double t) const;
  glm::vec3 velocityAt(double t) const;  ///< slope of the segment at t; zero outside the keys
  glm::quat rotationAt(double t) const;  ///< identity without rotations
  bool empty() const { return times.empty(); }
  bool moves() const;  ///< some key's place or turn differs from the first's
  bool operator==(const Path&) const = default;
};

/// A value over a particle's life ("curves over life"): keys of (normalized age in [0, 1],
/// value >= 0), ages strictly increasing; linear between keys, or smooth (a smoothstep in each
/// segment: flat at every key), held before the first key and after the last. Empty: no curve (the
/// emitter's default, below).
struct LifeCurve {
  enum class Interp { kLinear, kSmooth };
  Interp interp = Interp::kLinear;
  std::vector<float> ages, values;
  float at(float age) const;
  bool empty() const { return ages.empty(); }
  bool operator==(const LifeCurve&) const = default;
};

/// A colour over a particle's life: keys of (normalized age, display colour in [0, 1]^3), as
/// LifeCurve's (same interpolation, held outside the keys). Empty: white (no tint).
struct ColourCurve {
  LifeCurve::Interp interp = LifeCurve::Interp::kLinear;
  std::vector<float> ages;
  std::vector<glm::vec3> values;  ///< display values (sRGB-encoded), each in [0, 1]
  glm::vec3 at(float age) const;
  bool empty() const { return ages.empty(); }
  bool operator==(const ColourCurve&) const = default;
};

/// What an emitter's particles do over their life, as drawn: `size` multiplies the birth size
/// (replacing the default: a smooth growth over the first tenth of the life, then a linear shrink
/// to nothing for cel puffs; 1 + growth * age for media), `density` multiplies the birth density
/// (replacing the default fade in and linear fall to 0 of media). `color` tints the particle (a
/// display value, decoded to the scene-linear tint both paths' particles take: cel puffs multiply
/// Eq. 2's C by it, media the light a particle scatters and emits). `temperature` (kelvin; media fire only) replaces
/// the material's T0. The simulator's own dynamics (buoyancy from density, collision radius) keep
/// the default linear fall.
struct LifeCurves {
  LifeCurve size, density;
  ColourCurve color;
  LifeCurve temperature;
  bool empty() const { return size.empty() && density.empty() && color.empty() && temperature.empty(); }
  bool operator==(const LifeCurves&) const = default;
};

/// A line vortex: air turns about `axis` through `position` (plus its path's position). Its
/// tangential speed is the Lamb–Oseen profile scaled so it peaks at `strength` (world units / s;
/// negative turns the other way) at 1.12 core radii: linear inside the core, 1/r outside. `falloff`
/// (world units, 0 = none) multiplies by exp(-(r / falloff)^2) so the swirl ends; `length` (world
/// units, 0 = infinite line) by exp(-(axial distance / (length / 2))^2).
struct Vortex {
  glm::vec3 position{0.0f};
  glm::vec3 axis{0.0f, 1.0f, 0.0f};  ///< non-zero; normalized on use
  float strength = 1.0f;
  float radius = 0.5f;   ///< core radius, > 0
  float falloff = 0.0f;  ///< >= 0
  float length = 0.0f;   ///< >= 0
  Path path;             ///< a moving vortex: its position is `position` + path(t)
  std::string attach;    ///< the scene object it rides on (the scene copies that object's path)
  /// > 0: every shedInterval seconds the moving vortex leaves a copy behind at its current place
  /// (a propeller's wake); each copy's strength fades linearly to 0 over shedLifetime seconds.
  float shedInterval = 0.0f;
  float shedLifetime = 1.0f;  ///< > 0
  bool operator==(const Vortex&) const = default;
};

/// Air moving at `velocity` inside the box center +- halfExtent, fading to none over `feather`
/// world units outside it (0 = hard edge).
struct WindVolume {
  glm::vec3 center{0.0f};
  glm::vec3 halfExtent{1.0f};
  glm::vec3 velocity{0.0f};
  float feather = 0.0f;
  bool operator==(const WindVolume&) const = default;
};

/// Divergence-free noise (the curl of a smooth periodic noise potential, Bridson 2007), added to
/// the air velocity: swirls about `scale` world units across (the field repeats every 4 * scale),
/// `strength` world units / s RMS, the field drifting `speed` swirls per second, so the air at a
/// point changes over about 1 / `speed` seconds.
struct Turbulence {
  float strength = 0.0f;  ///< >= 0; 0 = off
  float scale = 1.0f;     ///< > 0
  float speed = 0.5f;     ///< >= 0
  std::uint32_t seed = 1;
  bool operator==(const Turbulence&) const = default;
};

struct Forces {
  glm::vec3 gravity{0.0f};  ///< acceleration, world units / s^2 (smoke is nearly weightless)
  float buoyancy = 0.0f;    ///< upward acceleration per unit density, world units / s^2
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float drag = 2.0f;     ///< 1 / s, >= 0: how fast a particle takes the air's velocity
  glm::vec3 wind{0.0f};  ///< global air velocity, world units / s
  std::vector<WindVolume> windVolumes;
  Turbulence turbulence;
  std::vector<Vortex> vortices;
  bool operator==(const Forces&) const = default;
};

/// Particles are born at `rate` per second for `duration` seconds from `start` (0: forever)
/// in a shape around `position` + path(t). Path emitters spawn each particle at its own instant
/// inside the step, so a fast emitter (a missile's tail) leaves a continuous trail. In a loop
/// (Settings::period, P seconds) an emitter runs every period: for min(duration, P) seconds from
/// start + kP (all of every period when duration is 0), its rate rounded to a whole number of
/// births (at least one) in that time, evenly spaced.
struct Emitter {
  enum class Shape {
    kPoint,
    kSphere,  ///< uniform in a ball of `radius`
    kDisc,    ///< uniform in a disc of `radius` perpendicular to `normal`
  };
  Shape shape = Shape::kPoint;
  glm::vec3 position{0.0f};
  float radius = 0.5f;                 ///< >= 0
  glm::vec3 normal{0.0f, 1.0f, 0.0f};  ///< disc normal
  Path path;                           ///< a moving emitter: at `position` + path(t)
  std::string attach;                  ///< the scene object it rides on (the scene copies that object's path)
  float rate = 10.0f;                  ///< particles per second, >= 0
  float start = 0.0f;                  ///< seconds
  float duration = 0.0f;               ///< seconds of emission from start, >= 0; 0 = never stops
  std::uint32_t seed = 1;
  glm::vec3 velocity{0.0f, 1.0f, 0.0f};  ///< initial velocity, world units / s
  float spreadDegrees = 0.0f;            ///< [0, 180]: the direction varies inside this cone
  float speedSpread = 0.0f;              ///< [0, 1]: speed scaled by 1 +- this
  float inheritVelocity = 0.0f;          ///< share of the path's own velocity added
  float density = 1.0f;                  ///< (0, 1e3]; falls linearly to 0 at the end of life
  float sizeMin = 0.5f, sizeMax = 1.0f;  ///< diameter at birth, world units, 0 <= min <= max
  float lifetime = 2.0f;                 ///< seconds, > 0
  float lifetimeSpread = 0.0f;           ///< [0, 1): lifetime scaled by 1 +- this
  std::vector<int> variations;           ///< allowed atlas variations; empty = 0 .. variations-1
  bool oriented = false;                 ///< random orientation (multi-view atlases)
  float spin = 0.0f;                     ///< random angular velocity up to this, radians / s
  LifeCurves overLife;                   ///< size, density, colour (temperature: media) over the life, as drawn
  bool operator==(const Emitter&) const = default;
};

/// A rigid body particles cannot enter. The particle is a sphere of `collisionRadius` times its
/// current radius; on contact it is put back on the surface and loses its velocity into the
/// surface (smoke slides along what it meets), and `friction` in [0, 1] of its sliding velocity.
struct Collider {
  enum class Type {
    kPlane,   ///< the square center +- (halfExtent.x, 0, halfExtent.z) in the rotated frame; solid below (-y)
    kSphere,  ///< radius halfExtent.x
    kBox,     ///< center +- halfExtent in the rotated frame
    kMesh,    ///< closed triangle mesh, world space (`positions`, `indices`): kept out by its surface
  };
  Type type = Type::kPlane;
  std::string name;  ///< for messages
  glm::vec3 center{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 halfExtent{1.0f};
  std::vector<glm::vec3> positions;  ///< kMesh
  std::vector<std::uint32_t> indices;
  float friction = 0.0f;
  Path path;  ///< a moving body: its position is center + path (meshes: every vertex + path)
  bool operator==(const Collider&) const = default;
};

enum class Integrator {
  kExponential,   ///< exact for drag over each step (the default; stable for any step)
  kForwardEuler,  ///< the paper's; diverges when drag * step > 2 (kept to show it)
};

struct Settings {
  float fps = 24.0f;     ///< frames per second, > 0
  int substeps = 4;      ///< steps per frame, [1, 1000]
  float preroll = 0.0f;  ///< seconds simulated before frame 0, >= 0
  /// Frames in one loop, [0, kMaxPeriod]; 0 = no loop (see "Loops" above). In a loop no emitter,
  /// vortex or collider moves along its path, and the preroll simulated is at least the longest
  /// lifetime.
  int period = 0;
  std::size_t maxParticles = 200'000;  ///< budget; births beyond it are dropped (counted)
  float collisionRadius = 0.5f;        ///< share of a particle's radius that collides, [0, 1]
  Integrator integrator = Integrator::kExponential;
  /// Threads a step runs on, [0, kMaxThreads]; 0 = std::thread::hardware_concurrency(). Changes
  /// the speed only: the results are bit-identical for every count (see "Threads" above). Scene
  /// files do not store it.
  int threads = 1;
  Forces forces;
  std::vector<Emitter> emitters;
  std::vector<Collider> colliders;
  bool operator==(const Settings&) const = default;
};

/// The most particles a budget may ask for (about 64 bytes each: 1.3 GB).
constexpr std::size_t kMaxParticleBudget = 20'000'000;

/// The most frames a loop may hold (Settings::period).
constexpr int kMaxPeriod = 100'000;

/// The most threads a simulator may be given.
constexpr int kMaxThreads = 256;

/// The largest magnitude any position, velocity, strength or acceleration may have (world units,
/// seconds): beyond it float arithmetic would lose the particles.
constexpr float kMaxMagnitude = 1e6f;

/// In a loop (Settings::period > 0), the most particles its emitters can hold at once: each one's
/// births a period times the periods its longest life spans, summed. 0 without a loop. Births the
/// budget (maxParticles) drops fall differently each period, so a loop that reaches it does not repeat.
std::size_t loopPeakParticles(const Settings& settings);

/// Checks every value: "emitters/2/rate: expected a number >= 0, got -1". The pointers are
/// relative to the Settings (a scene prefixes its own).
Result<void> validate(const Settings& settings);
Result<void> validate(const Forces& forces, const std::string& pointer = "/forces");

/// The state of one particle, read out for rendering.
struct ParticleState {
  glm::vec3 position;
  glm::vec3 velocity;
  float size;     ///< current diameter: birth size * (1 - age / lifetime)
  float density;  ///< current density: birth density * (1 - age / lifetime)
  int variation;
  bool oriented;
  glm::quat orientation;
  float birthSize;   ///< diameter at birth
  float age;         ///< seconds since birth
  float lifetime;    ///< seconds it lives
  int emitter;       ///< index of the emitter in Settings::emitters
  std::uint32_t id;  ///< a hash of (seed, emitter, birth index): stable for the particle's life
};

struct StepStats {
  std::size_t born = 0, died = 0, dropped = 0;  ///< dropped: births refused by the budget
  std::size_t collisions = 0;
  std::size_t nonFinite = 0;  ///< particles removed because their state stopped being finite
};

class Simulator {
 public:
  /// Validates (see validate) and prepares the colliders and the turbulence field. `variations` is
  /// the atlas's variation count (>= 1) for emitters that pick any.
  static Result<std::unique_ptr<Simulator>> create(Settings settings, int variations = 1);
  ~Simulator();

  /// Back to time 0 with no particles, then the preroll.
  void reset();
  /// One fixed step of 1 / (fps * substeps) seconds.
  void step(StepStats* stats = nullptr);
  /// Steps until the time of frame `frame` (>= 0); from the start again when `frame` lies behind.
  void advanceToFrame(int frame, StepStats* stats = nullptr);

  /// Replaces the forces (live editing); the particles keep going under the new ones. Invalid
  /// forces are refused (as validate words it) and the old ones kept.
  Result<void> setForces(const Forces& forces);
  /// Changes Settings::threads (0 = hardware concurrency) from the next step on; the particles are
  /// kept, and the results are the same as with any other count. Refuses a count outside
  /// [0, kMaxThreads].
  Result<void> setThreads(int threads);
  int threads() const;  ///< the threads a step runs on now (0 resolved), >= 1
  const Settings& settings() const;

  /// Scene time in seconds: frame f is at f / fps; negative during the preroll.
  double time() const;
  std::int64_t stepIndex() const;  ///< steps since the start
  int frame() const;               ///< the frame the state is at, if it is at one; else -1
  std::size_t size() const;        ///< live particles
  ParticleState particle(std::size_t i) const;
  /// The air velocity at `p` now (wind, volumes, vortices, turbulence), world units / s.
  glm::vec3 airVelocity(const glm::vec3& p) const;
  std::size_t liveVortices() const;  ///< the settings' vortices plus shed copies alive now

 private:
  Simulator();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace puff::sim
