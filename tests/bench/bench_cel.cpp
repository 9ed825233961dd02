// Cel rendering benchmark: the same particles at the same overdraw drawn three ways, timed
// in one run so the ratios compare methods on one machine:
//   floor       bare alpha-tested textured quads (NailboardRenderer::drawBaseline) writing the
//               nailboards' linear depth (gl_FragDepth, shaders/cel/sprite.frag), no offset
//   nailboards  cel shading, per-pixel linear depth (gl_FragDepth) and outlines (ShadePass::kLit),
//               as the renderer picks its shading (cel::LitShading::kAuto, by how deep the quads stack)
//   nailboards.once  each pixel shaded once: the visibility pre-pass, then the screen pass
//               (LitShading::kOncePerPixel)
//   nailboards.every-layer  every layer shaded as it is drawn (LitShading::kEveryLayer): what the
//               one-layer shading bought
//   nailboards.depth  the nailboards' depth alone (ShadePass::kDepthOnly: the packed map's read, the
//               depth offset and the silhouette's discard, no colour): what a depth pre-pass costs
//   full-volumes  the frame with shadows by volumes: kLit, billboard shadow volumes into the
//               stencil, kShadowed (Style::shadowMethod kVolumes)
//   full-map    the frame with shadows by a map: the particles drawn from the light into a
//               cel::ShadowMap (casters), then kLit looking it up (Style::shadowMethod kMap)
// Every frame clears the target, uploads the frame block and the particles (16 bytes each), draws,
// and ends with glFinish(). Per case: the floor, the nailboards and full-map alternate frame by
// frame (so a load change on a shared machine hits all), 2 warm-up rounds, then the median of
// --reps rounds. full-map is also timed pass by pass (full-map.casters: clear, uploads and the
// light's pass; full-map.lit: the lit pass). The volumes' full frame follows, timed pass by pass (glFinish between its
// passes; --no-split drops them) to show which pass dominates. It is slow on llvmpipe, so: a first frame over 2 s gets
// 1 warm-up and at most 3 timed frames; over 15 s that first frame is the only one; and a case whose frame is predicted
// (from the last measured full frame, scaled by particles x pixels) to exceed
// --max-frame-s is skipped and written with its prediction instead of a time.
//
// Overdraw is the same at every count: particles fill a box seen at view-axis distances
// d in [kNear, kFar], so for a quad of world side s the expected screen fraction is
//   (s * f / d)^2 / 4 per quad, f = 1 / tan(fovY / 2), E[1 / d^2] = 1 / (kNear * kFar),
// and N quads cover O screens when
//   s = 2 * tan(fovY / 2) * sqrt(O * kNear * kFar / N)            (quad side, world units)
// with O = kOverdraw = 4. The quad is the whole atlas cell, so the puff's diameter (Particle::size)
// is s * contentSize / cellSize. The overdraw actually reached (quads clipped to the screen) is
// measured on the CPU and written to the CSV.
//
// Writes CSV (stdout, or --csv FILE written atomically) and prints a table on stderr.
// Not a test: nothing here fails on a time.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <glm/geometric.hpp>

#include <puff/bake/baker.h>
#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/cel/shadow_map.h>
#include <puff/cel/volume_clip.h>
#include <puff/core/atlas.h>
#include <puff/core/gl.h>
#include <puff/io/openimageio.h>

#include <puff/core/image.h>
#include <puff/gl_api.h>
#include <puff/mesh/mesh.h>
#include <puff/platform/gl_context.h>

#include "bench_usage.h"
#include "harness.h"
#include "support/gl_target.h"

namespace {

namespace fs = std::filesystem;
using namespace puff;
using bench::Clock;
using bench::msBetween;
using bench::msSince;
using bench::splitmix64;
using bench::uniform;

// Scene: camera on +z looking at the origin; the box spans view-axis distances [kNear, kFar].
constexpr float kFovYDegrees = 45.0f;
constexpr float kCameraZ = 8.0f;
constexpr float kNear = 6.0f, kFar = 10.0f;  // box z in [kCameraZ - kFar, kCameraZ - kNear]
constexpr float kHalfWidth = 2.2f;           // box x and y in [-kHalfWidth, kHalfWidth]
constexpr float kOverdraw = 4.0f;            // summed quad area / screen area, at every count (--overdraw)
constexpr float kFloorGap = 0.2f;            // the floor plane sits this far below the box
constexpr std::uint64_t kSeed = 0x5eedc0ffee15bad5ull;
constexpr int kWarmUp = 2;
// A method whose first warm-up frame takes longer than kSlowFrameMs runs 1 warm-up and at most
// kSlowReps timed frames; see main for kVerySlowFrameMs. Keeps the run within minutes on llvmpipe.
constexpr double kSlowFrameMs = 2000.0, kVerySlowFrameMs = 15000.0;
constexpr int kSlowReps = 3;

float tanHalfFov() { return std::tan(0.5f * kFovYDegrees * 3.14159265358979f / 180.0f); }

// World side of the quad (the whole atlas cell) so that `count` quads cover `overdraw` screens.
float quadSide(std::size_t count, float overdraw) {
  return 2.0f * tanHalfFov() * std::sqrt(overdraw * kNear * kFar / static_cast<float>(count));
}

std::vector<cel::Particle> makeParticles(std::size_t count, float overdraw, const core::AtlasDesc& atlas) {
  std::uint64_t state = kSeed;
  const float size =
      quadSide(count, overdraw) * static_cast<float>(atlas.contentSize) / static_cast<float>(atlas.cellSize);
  std::vector<cel::Particle> ps(count);
  for (cel::Particle& p : ps) {
    p.position.x = uniform(state, -kHalfWidth, kHalfWidth);
    p.position.y = uniform(state, -kHalfWidth, kHalfWidth);
    p.position.z = uniform(state, kCameraZ - kFar, kCameraZ - kNear);
    p.size = size;
    p.variation = static_cast<int>(splitmix64(state) % 4);
  }
  return ps;
}

// Summed screen area of the quads (clipped to the screen) over the screen area.
double measuredOverdraw(const std::vector<cel::Particle>& ps, float side) {
  const double f = 1.0 / tanHalfFov();
  double sum = 0;
  for (const cel::Particle& p : ps) {
    const double d = kCameraZ - p.position.z;
    const double cx = p.position.x * f / d, cy = p.position.y * f / d, h = 0.5 * side * f / d;  // NDC
    const double w = std::max(0.0, std::min(1.0, cx + h) - std::max(-1.0, cx - h));
    const double hgt = std::max(0.0, std::min(1.0, cy + h) - std::max(-1.0, cy - h));
    sum += w * hgt;
  }
  return sum / 4.0;
}

struct Target : test::OffscreenTarget {
  explicit Target(int n) : OffscreenTarget(n) {}
  void bindAndClear() const { clear(glm::vec4(0.55f, 0.7f, 0.9f, 1.0f)); }
  Result<void> writePng(const fs::path& path) const {
    return core::writeImage(path, readImage(), core::PixelType::kUInt8);
  }
};

enum class Method { kFloor, kNailboards, kFull, kFullMap, kDepthOnly, kEveryLayer, kOnce };
constexpr const char* kMethodNames[] = {
    "floor", "nailboards", "full-volumes", "full-map", "nailboards.depth", "nailboards.every-layer", "nailboards.once"};

// One frame's time; for kFull with split timing also each pass: clear + uploads + lit nailboards,
// shadow volumes, shadowed nailboards.
struct FrameTime {
  double total = 0;
  double pass[3] = {0, 0, 0};
};

struct Bench {
  cel::NailboardRenderer& renderer;
  cel::FrameBlock& block;
  const cel::Ramp& ramp;
  cel::ShadowMap& map;
  cel::Style style;
  glm::vec4 floorPlane{0.0f};
  bool split = true;
  std::size_t bytesUploaded = 0;

  cel::Style mapStyle() const {
    cel::Style s = style;
    s.shadowMethod = cel::ShadowMethod::kMap;
    return s;
  }

  FrameTime frame(const Target& target, const cel::Frame& f, const std::vector<cel::Particle>& ps, Method m) {
    FrameTime t;
    const auto t0 = Clock::now();
    target.bindAndClear();
    PUFF_CHECK(block.upload(f).ok());
    ramp.bind();
    bytesUploaded = renderer.upload(ps).bytesUploaded;
    switch (m) {
      case Method::kFloor:
        renderer.drawBaseline(style);
        break;
      case Method::kNailboards:
        renderer.drawNailboards(style, cel::ShadePass::kLit);
        break;
      case Method::kDepthOnly:
        renderer.drawNailboards(style, cel::ShadePass::kDepthOnly);
        break;
      case Method::kEveryLayer:
        renderer.setLitShading(cel::LitShading::kEveryLayer);
        renderer.drawNailboards(style, cel::ShadePass::kLit);
        renderer.setLitShading(cel::LitShading::kAuto);
        break;
      case Method::kOnce:
        renderer.setLitShading(cel::LitShading::kOncePerPixel);
        renderer.drawNailboards(style, cel::ShadePass::kLit);
        renderer.setLitShading(cel::LitShading::kAuto);
        break;
      case Method::kFullMap: {
        map.prepare(f, cel::particleBounds(ps), mapStyle());
        map.beginCasters();
        renderer.drawShadowCasters(style, f);
        if (split) glFinish();
        const auto t1 = Clock::now();
        target.bind();
        cel::Frame lit = f;
        lit.shadow = map.lookup();
        PUFF_CHECK(block.upload(lit).ok());
        map.bind();
        renderer.drawNailboards(style, cel::ShadePass::kLit);
        if (split) {
          glFinish();
          t.pass[0] = msBetween(t0, t1);
          t.pass[1] = msSince(t1);
        }
        break;
      }
      case Method::kFull: {
        renderer.drawNailboards(style, cel::ShadePass::kLit);
        if (split) glFinish();
        const auto t1 = Clock::now();
        // Clipped to the receivers (the particles: the bench draws no floor), as the cel path clips.
        renderer.drawShadowVolumes(style, floorPlane, cel::volumeClip(f, cel::particleBounds(ps)));
        if (split) glFinish();
        const auto t2 = Clock::now();
        renderer.drawNailboards(style, cel::ShadePass::kShadowed);
        if (split) {
          glFinish();
          t.pass[0] = msBetween(t0, t1);
          t.pass[1] = msBetween(t1, t2);
          t.pass[2] = msSince(t2);
        }
        break;
      }
    }
    glFinish();
    t.total = msSince(t0);
    return t;
  }
};

struct Row {
  std::size_t particles = 0;
  int size = 0;
  std::string method;
  int reps = 0;  // 0: not measured (see note)
  double medianMs = 0, minMs = 0, ratio = 0;
  double bytesPerParticle = 0, overdraw = 0, quadPx = 0;
  std::string note;
};

std::vector<int> parseList(const char* s) {
  std::vector<int> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(std::atoi(item.c_str()));
  return out;
}

// How many warm-up and timed frames a method gets, from its first warm-up frame.
void framesFor(double firstFrameMs, int reps, int& warmUp, int& timed) {
  warmUp = kWarmUp;
  timed = reps;
  if (firstFrameMs > kSlowFrameMs) {
    warmUp = 1;
    timed = std::min(reps, kSlowReps);
  }
  if (firstFrameMs > kVerySlowFrameMs) timed = 1;
}

}  // namespace

int main(int argc, char** argv) {
  puff::io::useOpenImageIO();
  int reps = 5;
  double maxFrameS = 100.0;
  std::string csvPath, dumpDir;
  std::vector<int> counts{1000, 10000, 50000}, sizes{512, 1024};
  bool runNailboards = true, runFull = true, runMap = true, split = true;
  float stacking = kOverdraw;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
      reps = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc)
      csvPath = argv[++i];
    else if (!std::strcmp(argv[i], "--counts") && i + 1 < argc)
      counts = parseList(argv[++i]);
    else if (!std::strcmp(argv[i], "--sizes") && i + 1 < argc)
      sizes = parseList(argv[++i]);
    else if (!std::strcmp(argv[i], "--max-frame-s") && i + 1 < argc)
      maxFrameS = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--no-full"))
      runFull = false;
    else if (!std::strcmp(argv[i], "--no-nailboards"))
      runNailboards = false;
    else if (!std::strcmp(argv[i], "--no-map"))
      runMap = false;
    else if (!std::strcmp(argv[i], "--overdraw") && i + 1 < argc)
      stacking = static_cast<float>(std::atof(argv[++i]));
    else if (!std::strcmp(argv[i], "--no-split"))
      split = false;
    else if (!std::strcmp(argv[i], "--dump") && i + 1 < argc)
      dumpDir = argv[++i];
    else {
      std::fprintf(
          puff::bench::usageStream(argv[i]),
          "usage: puff_bench_cel [--reps N] [--csv FILE] [--counts 1000,10000,50000] [--sizes 512,1024]\n"
          "                      [--max-frame-s S (100)] [--no-full] [--no-nailboards] [--no-map] [--no-split]\n"
          "                      [--overdraw O (4)] [--dump DIR]\n"
          "  --no-full: without full-volumes (the slow one); --no-map: without full-map\n"
          "  --overdraw: the screens the quads cover in all (the CSV's overdraw is what they reached)\n");
      return puff::bench::usageExit(argv[i]);
    }
  }
  for (int v : counts) {
    if (v < 1) return std::fprintf(stderr, "puff_bench_cel: error: --counts must be positive\n"), 2;
  }
  if (!(stacking > 0.0f && stacking <= 64.0f))
    return std::fprintf(stderr, "puff_bench_cel: error: --overdraw must be in (0, 64]\n"), 2;
  for (int v : sizes) {
    if (v < 1 || v > 16384) return std::fprintf(stderr, "puff_bench_cel: error: --sizes must be in [1, 16384]\n"), 2;
  }

  auto context = core::createGlContext({});
  if (!context) {
    std::fprintf(stderr, "puff_bench_cel: error: %s\n", context.error().message.c_str());
    return 1;
  }
  std::fprintf(stderr, "puff_bench_cel: %s\n", (*context)->describe().c_str());

  // A lumpy 4-variation atlas, baked in-process (front view only, as the paper's particles).
  const fs::path bakeDir = fs::temp_directory_path() / ("puff_bench_cel-" + std::to_string(::getpid()));
  std::unique_ptr<core::Atlas> atlas;
  {
    std::vector<bake::PuffSource> sources(4);
    for (int i = 0; i < 4; ++i) {
      mesh::LumpyParams p;  // pinned, so figures stay comparable when the generator's defaults change
      p.subdivisions = 5;
      p.amplitude = 0.25f;
      p.frequency = 2.0f;
      p.octaves = 3;
      p.seed = 1 + static_cast<std::uint64_t>(i);
      sources[static_cast<std::size_t>(i)].mesh = mesh::generateLumpy(p);
      sources[static_cast<std::size_t>(i)].provenance.generator = "lumpy";
    }
    bake::BakeOptions o;
    o.cellSize = 128;
    o.outDir = bakeDir;
    o.contactSheet = false;
    auto baked = bake::bakeAtlas(sources, o);
    if (!baked) {
      std::fprintf(stderr, "puff_bench_cel: error: bake: %s\n", baked.error().message.c_str());
      return 1;
    }
    auto loaded = core::loadAtlas(baked->sidecar);
    fs::remove_all(bakeDir);
    if (!loaded) {
      std::fprintf(stderr, "puff_bench_cel: error: %s\n", loaded.error().message.c_str());
      return 1;
    }
    atlas = std::make_unique<core::Atlas>(std::move(*loaded));
  }
  auto created = cel::NailboardRenderer::create();
  if (!created) {
    std::fprintf(stderr, "puff_bench_cel: error: %s\n", created.error().message.c_str());
    return 1;
  }
  std::unique_ptr<cel::NailboardRenderer> renderer = std::move(*created);
  if (auto r = renderer->setAtlas(*atlas); !r) {
    std::fprintf(stderr, "puff_bench_cel: error: %s\n", r.error().message.c_str());
    return 1;
  }
  cel::FrameBlock block;
  const cel::Ramp ramp = cel::Ramp::twoTone();
  cel::ShadowMap shadowMap;
  Bench bench{*renderer, block, ramp, shadowMap, {}, {}, split};
  bench.style.shadows = true;  // outlines, shading and the rest at their defaults
  // The plane y = yBottom, kFloorGap below the box: floorPlane = (0, 1, 0, -yBottom).
  const float yBottom = -kHalfWidth - kFloorGap;
  bench.floorPlane = glm::vec4(0.0f, 1.0f, 0.0f, -yBottom);

  cel::Camera camera;
  camera.position = glm::vec3(0.0f, 0.0f, kCameraZ);
  camera.target = glm::vec3(0.0f);
  camera.fovYDegrees = kFovYDegrees;
  camera.nearPlane = 0.5f;
  camera.farPlane = 30.0f;

  std::vector<Row> rows;
  double lastFullMs = 0, lastFullWork = 0;  // for predicting the next full frame
  const auto runStart = Clock::now();
  for (int count : counts) {
    const std::vector<cel::Particle> ps = makeParticles(static_cast<std::size_t>(count), stacking, atlas->desc);
    const float side = quadSide(static_cast<std::size_t>(count), stacking);
    const double overdraw = measuredOverdraw(ps, side);
    for (int size : sizes) {
      const Target target(size);
      cel::Frame frame = cel::Frame::fromCamera(camera, size, size);
      frame.depth = cel::DepthConvention::kLinear;  // Puff's own renderer's, as the benchmark has always drawn
      frame.light.direction = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));
      frame.light.color = puff::core::srgbToLinear(glm::vec3(0.75f));
      frame.ambient = puff::core::srgbToLinear(glm::vec3(0.3f));
      const double quadPx = side / (2.0 * tanHalfFov() * kCameraZ) * size;  // at the box's middle depth
      double floorMs = 0;

      auto dump = [&](Method m) {
        if (dumpDir.empty()) return;
        const fs::path png = fs::path(dumpDir) / (std::string(kMethodNames[static_cast<int>(m)]) + "_" +
                                                  std::to_string(count) + "_" + std::to_string(size) + ".png");
        if (auto r = target.writePng(png); !r) std::fprintf(stderr, "puff_bench_cel: %s\n", r.error().message.c_str());
      };
      auto addRow = [&](const std::string& name, const std::vector<double>& times, const std::string& note = {}) {
        Row row;
        row.particles = static_cast<std::size_t>(count);
        row.size = size;
        row.method = name;
        row.reps = static_cast<int>(times.size());
        if (!times.empty()) {
          row.medianMs = bench::median(times);
          row.minMs = *std::min_element(times.begin(), times.end());
          if (name == "floor") floorMs = row.medianMs;
          row.ratio = row.medianMs / floorMs;
        }
        row.bytesPerParticle = static_cast<double>(bench.bytesUploaded) / count;
        row.overdraw = overdraw;
        row.quadPx = quadPx;
        row.note = note;
        rows.push_back(row);
        if (times.empty()) {
          std::fprintf(stderr, "puff_bench_cel: %6d particles %5d^2 %-14s %s\n", count, size, name.c_str(),
                       note.c_str());
        } else {
          std::fprintf(
              stderr,
              "puff_bench_cel: %6d particles %5d^2 %-14s median %9.2f ms  x%7.2f  (%zu frames, %.0f s so far)\n", count,
              size, name.c_str(), row.medianMs, row.ratio, times.size(), msSince(runStart) / 1000.0);
        }
      };
      auto checkGl = [&](const char* what) {
        if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
          std::fprintf(stderr, "puff_bench_cel: error: GL error 0x%04x in %s\n", e, what);
          std::exit(1);
        }
      };

      // Floor and nailboards, alternating frame by frame.
      std::vector<Method> fast{Method::kFloor};
      if (runNailboards) fast.push_back(Method::kNailboards);
      if (runNailboards) fast.push_back(Method::kDepthOnly);
      if (runNailboards) fast.push_back(Method::kEveryLayer);
      if (runNailboards) fast.push_back(Method::kOnce);
      if (runMap) fast.push_back(Method::kFullMap);
      int warmUp = kWarmUp, timed = reps;
      for (int w = 0; w < warmUp; ++w) {
        double slowest = 0;
        for (Method m : fast) slowest = std::max(slowest, bench.frame(target, frame, ps, m).total);
        if (w == 0) framesFor(slowest, reps, warmUp, timed);
      }
      std::vector<std::vector<double>> fastTimes(fast.size());
      std::vector<double> mapPasses[2];
      for (int r = 0; r < timed; ++r) {
        for (std::size_t k = 0; k < fast.size(); ++k) {
          const FrameTime t = bench.frame(target, frame, ps, fast[k]);
          fastTimes[k].push_back(t.total);
          if (fast[k] == Method::kFullMap) {
            mapPasses[0].push_back(t.pass[0]);
            mapPasses[1].push_back(t.pass[1]);
          }
        }
      }
      checkGl("floor, nailboards or full-map");
      for (std::size_t k = 0; k < fast.size(); ++k) {
        addRow(kMethodNames[static_cast<int>(fast[k])], fastTimes[k],
               fast[k] == Method::kFullMap
                   ? "map " + std::to_string(shadowMap.plan().width) + "x" + std::to_string(shadowMap.plan().height)
                   : std::string());
        if (fast[k] == Method::kFullMap && split) {
          addRow("full-map.casters", mapPasses[0], "clear + uploads + the casters into the map inside full-map");
          addRow("full-map.lit", mapPasses[1], "lit nailboards looking up the map inside full-map");
        }
        if (!dumpDir.empty()) {
          bench.frame(target, frame, ps, fast[k]);
          dump(fast[k]);
        }
      }
      if (!runFull) continue;

      // The full frame with shadows, unless it is predicted to take too long.
      const double work = static_cast<double>(count) * size * size;
      const double predictedMs = lastFullWork > 0 ? lastFullMs * work / lastFullWork : 0;
      if (predictedMs > maxFrameS * 1000.0) {
        char note[128];
        std::snprintf(note, sizeof note, "skipped: predicted %.0f s per frame (over --max-frame-s %.0f)",
                      predictedMs / 1000.0, maxFrameS);
        addRow("full-volumes", {}, note);
        continue;
      }
      // A first frame over kVerySlowFrameMs is itself the one timed frame: shaders are compiled
      // by then (the floor and nailboards ran), and a second frame would cost minutes.
      const FrameTime first = bench.frame(target, frame, ps, Method::kFull);
      std::vector<double> totals, passes[3];
      auto record = [&](const FrameTime& t) {
        totals.push_back(t.total);
        for (int k = 0; k < 3; ++k) passes[k].push_back(t.pass[k]);
      };
      std::string fullNote;
      if (first.total > kVerySlowFrameMs) {
        record(first);
        fullNote = "1 frame without warm-up (over 15 s)";
      } else {
        framesFor(first.total, reps, warmUp, timed);
        for (int w = 1; w < warmUp; ++w) bench.frame(target, frame, ps, Method::kFull);
        for (int r = 0; r < timed; ++r) record(bench.frame(target, frame, ps, Method::kFull));
      }
      dump(Method::kFull);
      checkGl("full");
      lastFullMs = bench::median(totals);
      lastFullWork = work;
      addRow("full-volumes", totals, fullNote);
      if (split) {
        addRow("full-volumes.lit", passes[0], "clear + uploads + lit nailboards inside full-volumes");
        addRow("full-volumes.volumes", passes[1], "shadow-volume pass alone inside full-volumes");
        addRow("full-volumes.shadowed", passes[2], "shadowed nailboards pass inside full-volumes");
      }
    }
  }

  // valid: for the methods measured against the floor (nailboards, full), 0 when one is faster
  // than the floor of its count and size (then no ratio: the floor did not bound it); empty for
  // the floor itself and for the passes inside the full frame (parts, not methods).
  std::string csv =
      "particles,size,method,reps,median_ms,min_ms,ratio_to_floor,bytes_per_particle,overdraw,quad_px,note,valid\n";
  for (const Row& r : rows) {
    const bool method = r.method == "nailboards" || r.method == "full-volumes" || r.method == "full-map";
    if (r.reps > 0) {
      const bool valid = !method || r.ratio >= 1.0;
      std::string ratio;
      if (valid) bench::appendf(ratio, "%.3f", r.ratio);
      bench::appendf(csv, "%zu,%d,%s,%d,%.2f,%.2f,%s,%.1f,%.2f,%.1f,%s,%s\n", r.particles, r.size, r.method.c_str(),
                     r.reps, r.medianMs, r.minMs, ratio.c_str(), r.bytesPerParticle, r.overdraw, r.quadPx,
                     r.note.c_str(), method ? (valid ? "1" : "0") : "");
    } else {
      bench::appendf(csv, "%zu,%d,%s,0,,,,%.1f,%.2f,%.1f,%s,\n", r.particles, r.size, r.method.c_str(),
                     r.bytesPerParticle, r.overdraw, r.quadPx, r.note.c_str());
    }
  }
  if (!bench::writeCsv("puff_bench_cel", csvPath, csv)) return 1;

  // The table: per count and size, each method's median and its ratio to the floor.
  std::fprintf(stderr, "\n%9s %5s %9s %20s %20s %20s %20s %5s\n", "particles", "size", "floor ms", "nailboards ms (x)",
               "full-map ms (x)", "full-volumes ms (x)", "volume pass ms (x)", "B/p");
  auto cell = [](const Row* r) {
    char b[64];
    if (!r || r->reps == 0)
      std::snprintf(b, sizeof b, "%20s", "-");
    else if (r->ratio < 1.0)
      std::snprintf(b, sizeof b, "%10.1f (%7s)", r->medianMs, "INVALID");  // below the floor
    else
      std::snprintf(b, sizeof b, "%10.1f (%7.2f)", r->medianMs, r->ratio);
    return std::string(b);
  };
  for (const Row& f : rows) {
    if (f.method != "floor") continue;
    auto find = [&](const char* m) -> const Row* {
      for (const Row& r : rows) {
        if (r.particles == f.particles && r.size == f.size && r.method == m) return &r;
      }
      return nullptr;
    };
    std::fprintf(stderr, "%9zu %5d %9.2f %s %s %s %s %5.1f\n", f.particles, f.size, f.medianMs,
                 cell(find("nailboards")).c_str(), cell(find("full-map")).c_str(), cell(find("full-volumes")).c_str(),
                 cell(find("full-volumes.volumes")).c_str(), f.bytesPerParticle);
  }
  return 0;
}
