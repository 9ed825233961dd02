// Simulator benchmark: one step of N particles (default 50,000) under force sets from light to
// everything at once, on each thread count of --threads (default 1; 0 = hardware concurrency;
// a list such as 1,2 runs every case on each, the counts' simulators stepped in turns of 10 steps
// so the machine's load falls on all alike). Each case and count: 10 warm-up steps, then the median of
// --reps steps; the ratio is against the single-threaded streaming floor measured in
// the same run (one pass of x += v * h over the same structure-of-arrays: what no step can beat on
// one thread), and speedup_vs_1_thread against the same case on 1 thread when the list holds 1.
// The states the thread counts reach are compared particle by particle: they must be equal (the
// run fails otherwise). Writes CSV (stdout, or --csv FILE). Not a test: nothing fails on a time.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <puff/io/openimageio.h>
#include <puff/sim/simulator.h>

#include "bench_usage.h"
#include "harness.h"

namespace {

using namespace puff;

struct Row {
  std::string name, forces;
  int threads = 1;
  std::size_t particles = 0;
  double medianMs = 0.0, minMs = 0.0;
  double speedup = 0.0;  // against the same case on 1 thread; 0 = not measured
};

// "1,2,0" -> {1, 2, hardware concurrency}; empty on a malformed list.
std::vector<int> parseThreads(const char* text) {
  std::vector<int> out;
  std::string item;
  const std::string all = std::string(text) + ",";
  for (char c : all) {
    if (c != ',') {
      if (c < '0' || c > '9' || item.size() > 3) return {};
      item += c;
      continue;
    }
    if (item.empty()) return {};
    int t = std::atoi(item.c_str());
    if (t == 0) t = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    if (t > sim::kMaxThreads) return {};
    out.push_back(t);
    item.clear();
  }
  return out;
}

// Whether two simulators hold the same particles, bit for bit.
bool sameState(const sim::Simulator& a, const sim::Simulator& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const sim::ParticleState p = a.particle(i), q = b.particle(i);
    if (std::memcmp(&p.position, &q.position, sizeof p.position) ||
        std::memcmp(&p.velocity, &q.velocity, sizeof p.velocity) || std::memcmp(&p.size, &q.size, sizeof p.size) ||
        std::memcmp(&p.age, &q.age, sizeof p.age) || p.id != q.id)
      return false;
  }
  return true;
}

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
  puff::io::useOpenImageIO();
  int reps = 50;
  std::size_t n = 50'000;
  std::string csvPath;
  std::vector<int> threadCounts = {1};
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
      reps = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--particles") && i + 1 < argc)
      n = static_cast<std::size_t>(std::max(1, std::atoi(argv[++i])));
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc)
      csvPath = argv[++i];
    else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc && !(threadCounts = parseThreads(argv[++i])).empty())
      continue;
    else {
      std::fprintf(puff::bench::usageStream(argv[i]),
                   "usage: puff_bench_sim [--reps N] [--particles N] [--threads N[,N...]] [--csv FILE]\n"
                   "  --threads: thread counts to run every case on, each in [0, %d] (0 = hardware concurrency)\n",
                   sim::kMaxThreads);
      return puff::bench::usageExit(argv[i]);
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
    rows.push_back({"floor", "x += v h", 1, n, bench::median(times), *std::min_element(times.begin(), times.end())});
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
    // One simulator per thread count, stepped in turn (runs of 10 steps each, round after round),
    // so a change in what else the shared machine runs falls on every count alike.
    std::vector<std::unique_ptr<sim::Simulator>> sims;
    for (int threads : threadCounts) {
      sim::Settings settings = c.settings;
      settings.threads = threads;
      auto created = sim::Simulator::create(settings, 4);
      if (!created) {
        std::fprintf(stderr, "puff_bench_sim: error: %s\n", created.error().message.c_str());
        return 1;
      }
      sims.push_back(std::move(*created));
    }
    std::vector<std::vector<double>> times(sims.size());
    // Runs of 10 consecutive steps per count, as a simulation steps (a pool whose threads went to
    // sleep between runs pays the wake-up once per run); the first run is the warm-up, whose first
    // steps include the births.
    constexpr int kRun = 10;
    for (int done = 0; done < kRun + reps; done += kRun) {
      for (std::size_t k = 0; k < sims.size(); ++k) {
        for (int j = 0; j < std::min(kRun, kRun + reps - done); ++j) {
          const auto t0 = bench::Clock::now();
          sims[k]->step();
          const double ms = bench::msSince(t0);
          if (done >= kRun) times[k].push_back(ms);
        }
      }
    }
    double oneThreadMs = 0.0;
    for (std::size_t k = 0; k < sims.size(); ++k) {
      const int threads = threadCounts[k];
      Row row{c.name,
              c.forces,
              threads,
              sims[k]->size(),
              bench::median(times[k]),
              *std::min_element(times[k].begin(), times[k].end())};
      if (threads == 1 && !(oneThreadMs > 0.0)) oneThreadMs = row.medianMs;
      std::fprintf(stderr, "puff_bench_sim: %-20s %d thread%s %zu particles: %.3f ms per step\n", c.name, threads,
                   threads == 1 ? ": " : "s:", sims[k]->size(), row.medianMs);
      rows.push_back(row);
      if (k > 0 && !sameState(*sims.front(), *sims[k])) {
        std::fprintf(stderr, "puff_bench_sim: error: %s: %d threads reached a different state than %d\n", c.name,
                     threads, threadCounts.front());
        return 1;
      }
    }
    // The speed-up of every count of this case against 1 thread, when 1 ran.
    for (Row& r : rows) {
      if (r.name != c.name || !(oneThreadMs > 0.0)) continue;
      r.speedup = oneThreadMs / r.medianMs;
      if (r.threads != 1)
        std::fprintf(stderr, "puff_bench_sim: %-20s %d threads: %.2fx the speed of 1\n", c.name, r.threads, r.speedup);
    }
  }

  std::string csv =
      "case,threads,particles,reps,median_ms,min_ms,ratio_to_floor,ns_per_particle,speedup_vs_1_thread,forces\n";
  const double floorMs = rows.front().medianMs;
  for (const Row& r : rows) {
    char speedup[32] = "";
    if (r.speedup > 0.0) std::snprintf(speedup, sizeof speedup, "%.2f", r.speedup);
    bench::appendf(csv, "%s,%d,%zu,%d,%.4f,%.4f,%.2f,%.1f,%s,\"%s\"\n", r.name.c_str(), r.threads, r.particles, reps,
                   r.medianMs, r.minMs, r.medianMs / floorMs, r.medianMs * 1e6 / static_cast<double>(r.particles),
                   speedup, r.forces.c_str());
  }
  return bench::writeCsv("puff_bench_sim", csvPath, csv) ? 0 : 1;
}
