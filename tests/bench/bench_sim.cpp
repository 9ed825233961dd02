// Simulator benchmark: one step of N particles (default 50,000) under force sets from light to
// everything at once, single-threaded. Each case: 10 warm-up steps, then the median of --reps
// steps; the ratio is against the streaming floor measured in the same run (one pass of
// x += v * h over the same structure-of-arrays: what no step can beat). Writes CSV (stdout, or
// --csv FILE). Not a test: nothing here fails on a time.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <puff/sim/simulator.h>

#include "harness.h"

namespace {

using namespace puff;

struct Row {
  std::string name, forces;
  std::size_t particles = 0;
  double medianMs = 0.0, minMs = 0.0;
};

// N particles in a 20-unit ball, all born in the first step, living far longer than the run.
sim::Settings base(std::size_t n) {
  sim::Settings s;
  s.fps = 24.0f;
  s.substeps = 1;
  s.maxParticles = n;
  sim::Emitter e;
  e.shape = sim::Emitter::Shape::kSphere;
  e.position = glm::vec3(0.0f, 12.0f, 0.0f);
  e.radius = 10.0f;
  e.rate = static_cast<float>(n) * 24.0f;  // all in the first step
  e.duration = 1.0f / 24.0f;
  e.velocity = glm::vec3(0.0f, 1.0f, 0.0f);
  e.spreadDegrees = 180.0f;
  e.lifetime = 1e5f;
  e.sizeMin = 0.2f, e.sizeMax = 0.6f;
  s.emitters.push_back(e);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  int reps = 50;
  std::size_t n = 50'000;
  std::string csvPath;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
      reps = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--particles") && i + 1 < argc)
      n = static_cast<std::size_t>(std::max(1, std::atoi(argv[++i])));
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc)
      csvPath = argv[++i];
    else {
      std::fprintf(stderr, "usage: puff_bench_sim [--reps N] [--particles N] [--csv FILE]\n");
      return 2;
    }
  }

  std::vector<Row> rows;

  // The floor: one streaming pass over positions and velocities of the same size.
  {
    std::vector<float> px(n, 1.0f), py(n, 2.0f), pz(n, 3.0f), vx(n, 0.1f), vy(n, 0.2f), vz(n, 0.3f);
    const float h = 1.0f / 24.0f;
    const std::vector<double> times = bench::timeRuns(10, reps, [&] {
      for (std::size_t i = 0; i < n; ++i) px[i] += vx[i] * h, py[i] += vy[i] * h, pz[i] += vz[i] * h;
    });
    volatile float sink = px[n / 2] + py[n / 3] + pz[n / 4];
    (void)sink;
    rows.push_back({"floor", "x += v h", n, bench::median(times), *std::min_element(times.begin(), times.end())});
  }

  struct Case {
    const char* name;
    const char* forces;
    sim::Settings settings;
  };
  std::vector<Case> cases;
  {
    sim::Settings s = base(n);
    s.forces.gravity = glm::vec3(0.0f, -0.5f, 0.0f);
    s.forces.buoyancy = 1.0f;
    cases.push_back({"drift", "gravity, buoyancy, drag", s});
  }
  {
    sim::Settings s = base(n);
    s.forces.wind = glm::vec3(2.0f, 0.0f, 0.0f);
    s.forces.drag = 6.0f;
    s.forces.turbulence = {0.5f, 0.75f, 1.2f, 1};
    sim::Collider ground;
    ground.halfExtent = glm::vec3(100.0f, 0.0f, 100.0f);
    s.colliders.push_back(ground);
    cases.push_back({"missile", "wind, turbulence, drag, ground plane", s});
  }
  sim::Settings full = base(n);
  {
    sim::Settings& s = full;
    s.forces.gravity = glm::vec3(0.0f, -0.5f, 0.0f);
    s.forces.buoyancy = 1.0f;
    s.forces.wind = glm::vec3(0.5f, 0.0f, 0.0f);
    s.forces.windVolumes.push_back({glm::vec3(0.0f, 12.0f, 0.0f), glm::vec3(4.0f), glm::vec3(0.0f, 0.0f, 3.0f), 2.0f});
    s.forces.turbulence = {0.5f, 0.75f, 1.2f, 1};
    sim::Vortex v;
    v.position = glm::vec3(0.0f, 12.0f, 0.0f);
    v.strength = 3.0f;
    v.radius = 2.0f;
    v.falloff = 8.0f;
    s.forces.vortices = {v, v};
    s.forces.vortices[1].axis = glm::vec3(1.0f, 0.0f, 0.0f);
    sim::Collider ground, ball, box;
    ground.halfExtent = glm::vec3(100.0f, 0.0f, 100.0f);
    ball.type = sim::Collider::Type::kSphere;
    ball.center = glm::vec3(5.0f, 8.0f, 0.0f);
    ball.halfExtent = glm::vec3(2.0f);
    box.type = sim::Collider::Type::kBox;
    box.center = glm::vec3(-5.0f, 8.0f, 0.0f);
    box.halfExtent = glm::vec3(2.0f, 1.0f, 2.0f);
    s.colliders = {ground, ball, box};
    cases.push_back({"full", "all six forces (2 vortices, a wind volume), plane + sphere + box", s});
  }
  {
    sim::Settings s = full;
    s.integrator = sim::Integrator::kForwardEuler;
    cases.push_back({"full.forward-euler", "as full, the paper's integrator", s});
  }

  for (const Case& c : cases) {
    auto created = sim::Simulator::create(c.settings, 4);
    if (!created) {
      std::fprintf(stderr, "puff_bench_sim: error: %s\n", created.error().message.c_str());
      return 1;
    }
    sim::Simulator& simulator = **created;
    // 10 warm-up steps: the first steps include the births.
    const std::vector<double> times = bench::timeRuns(10, reps, [&] { simulator.step(); });
    rows.push_back(
        {c.name, c.forces, simulator.size(), bench::median(times), *std::min_element(times.begin(), times.end())});
    std::fprintf(stderr, "puff_bench_sim: %-20s %zu particles: %.3f ms per step\n", c.name, simulator.size(),
                 rows.back().medianMs);
  }

  std::string csv = "case,particles,reps,median_ms,min_ms,ratio_to_floor,ns_per_particle,forces\n";
  const double floorMs = rows.front().medianMs;
  for (const Row& r : rows) {
    bench::appendf(csv, "%s,%zu,%d,%.4f,%.4f,%.2f,%.1f,\"%s\"\n", r.name.c_str(), r.particles, reps, r.medianMs,
                   r.minMs, r.medianMs / floorMs, r.medianMs * 1e6 / static_cast<double>(r.particles),
                   r.forces.c_str());
  }
  return bench::writeCsv("puff_bench_sim", csvPath, csv) ? 0 : 1;
}
