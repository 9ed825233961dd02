// puffbench's cel part: the nailboards and the fixed-function path against the cel
// reference (RenderPath::kReference: the actual puff meshes, true outer silhouettes, exact shadows)
// over their cost parameters: the atlas's cell size (64 .. 1024 texels, baked here from the scene's
// source meshes), the puff mesh's level of detail (the atlas baked from decimated meshes; the fixed
// path drawing a decimated mesh) and the particle count (263 .. 50,000 on cloud-50k). Each point:
// the median frame time, its ratio to the same frame without particles (opaque pass, clear and
// read-back: the floor every configuration pays), and the error against the reference of the very
// same particles: RMSE and PSNR of the 8-bit output values over the frame, RMSE over the pixels where
// either image shows puffs, coverage IoU and outline IoU (the ink).
#include "puffbench_cel.h"

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include <puff/bake/baker.h>
#include <puff/core/number_text.h>
#include <puff/eval/budget.h>
#include <puff/eval/cel_reference.h>
#include <puff/eval/compare.h>
#include <puff/mesh/mesh.h>
#include <puff/reference/metrics.h>
#include <puff/scene/evaluate.h>
#include <puff/scene/read.h>

#include "harness.h"

namespace puffbench {

namespace fs = std::filesystem;
using namespace puff;
using bench::Clock;

namespace {

struct Errors {
  double rmse = 0.0, rmsePuffs = 0.0, coverageIoU = 1.0, outlineIoU = 1.0;
};

// Worst over the frames: largest RMSE, smallest IoUs. Each image is judged against its own bare frame
// (the same frame without particles, drawn by the same path: the fixed path and the reference shade
// and antialias objects their own ways) for the masks. RMSE over the whole frame (what the image
// costs, as --max-error measures it) and over the pixels where either image shows puffs.
Errors compare(const Frames& a, const Frames& aBare, const Frames& ref, const Frames& refBare, const glm::vec3& ink) {
  Errors e;
  for (std::size_t i = 0; i < a.images.size(); ++i) {
    const std::vector<bool> ma = reference::coverageMask(a.images[i], aBare.images[i]);
    const std::vector<bool> mr = reference::coverageMask(ref.images[i], refBare.images[i]);
    std::vector<bool> either(ma.size());
    for (std::size_t k = 0; k < ma.size(); ++k) either[k] = ma[k] || mr[k];
    e.rmse = std::max(e.rmse, reference::imageError(a.images[i], ref.images[i]).rmse);
    e.rmsePuffs = std::max(e.rmsePuffs, reference::imageError(a.images[i], ref.images[i], either).rmse);
    e.coverageIoU = std::min(e.coverageIoU, reference::maskIoU(ma, mr));
    e.outlineIoU =
        std::min(e.outlineIoU, reference::maskIoU(reference::inkMask(a.images[i], aBare.images[i], ink),
                                                  reference::inkMask(ref.images[i], refBare.images[i], ink)));
  }
  return e;
}

// Bakes the scene atlas's source meshes (each decimated to 1 / `decimation` of its faces when > 1)
// at `cellSize` into `dir`, with puffbake's defaults otherwise. Returns the sidecar.
Result<fs::path> bake(const fs::path& sidecar, int cellSize, int decimation, const fs::path& dir, std::size_t* faces) {
  PUFF_TRY_ASSIGN(auto desc, core::loadAtlasDesc(sidecar));
  std::vector<fs::path> files;
  for (const core::AtlasSource& s : desc.sources) {
    if (s.path.empty()) return Error{sidecar.string() + ": puffbench re-bakes from mesh files; a source was generated"};
    files.push_back(fs::path(s.path).is_relative() ? sidecar.parent_path() / s.path : fs::path(s.path));
  }
  PUFF_TRY_ASSIGN(auto sources, bake::loadSources(files, std::nullopt));
  *faces = 0;
  for (bake::PuffSource& s : sources) {
    if (decimation > 1) s.mesh = mesh::decimate(s.mesh, std::max<std::size_t>(20, s.mesh.faceCount() / decimation));
    *faces += s.mesh.faceCount();
  }
  bake::BakeOptions o;
  o.cellSize = cellSize;
  o.outDir = dir;
  o.contactSheet = false;
  o.defaultColor = desc.sources.front().defaultColor;
  PUFF_TRY_ASSIGN(auto report, bake::bakeAtlas(sources, o));
  return report.sidecar;
}

}  // namespace

Result<void> timeFrame(render::SceneRenderer& renderer, int frame, int reps, std::vector<double>& times) {
  for (int i = 0; i < reps; ++i) {
    const auto t0 = Clock::now();
    if (auto im = renderer.renderFrame(frame); !im) return im.error();
    times.push_back(bench::msSince(t0));
  }
  return {};
}

// Renders `frames` with `path` (the reference with its default sampling), each once untimed (the
// image) and then `reps` times timed.
Result<Frames> renderFrames(const scene::Scene& scene, render::RenderPath path, std::span<const int> frames, int reps,
                            bool fillRateFloor) {
  PUFF_TRY_ASSIGN(auto r, eval::createRenderer(scene, path));
  (r)->setFillRateFloor(fillRateFloor);
  Frames out;
  std::vector<double> times;
  for (int f : frames) {
    render::FrameStats stats;
    PUFF_TRY_ASSIGN(auto image, (r)->renderFrame(f, &stats));
    out.images.push_back(std::move(image));
    out.particles = std::max(out.particles, stats.particles);
    PUFF_TRY(timeFrame(*r, f, reps, times));
  }
  out.ms = bench::median(times);
  return out;
}

namespace {

// A row of scene `scene`: frames `f` measured against the references (the particles' errors, compare()).
CelRow measuredRow(const std::string& scene, const std::string& path, const std::string& parameter, double value,
                   const std::string& label, int width, int height, const Frames& f, double floorMs, const Frames& bare,
                   const Frames& ref, const Frames& refBare, const glm::vec3& ink) {
  CelRow r;
  r.scene = scene;
  r.path = path;
  r.parameter = parameter;
  r.value = value;
  r.label = label;
  r.particles = f.particles;
  r.width = width;
  r.height = height;
  r.ms = f.ms;
  r.floorMs = floorMs;
  r.bareMs = bare.ms;
  const Errors e = compare(f, bare, ref, refBare, ink);
  r.rmse = e.rmse;
  r.rmsePuffs = e.rmsePuffs;
  r.coverageIoU = e.coverageIoU;
  r.outlineIoU = e.outlineIoU;
  return r;
}

// How the oriented puffs of scene `name` turn (what --max-error chooses, eval::CelKnob::kTumble), at
// the scene's own size: each way's frames against the cel reference of the turned meshes.
Result<void> addTumbleRows(const CelBenchOptions& opt, const std::string& name, std::vector<CelRow>& rows) {
  const auto t0 = Clock::now();
  PUFF_TRY_ASSIGN(auto loaded, scene::loadScene(opt.sceneDir / (name + ".json"), opt.artDir));
  scene::Scene scene = loaded;
  scene.media.reset();
  if (scene::orientedPuffs(scene).empty()) return Error{name + ": no oriented puffs, so no tumble rows"};
  const std::vector<int> frames = eval::budgetFrames(0, scene.animation.frames - 1);
  const glm::vec3 ink = scene::celStyleFor(scene).outlineColor;
  PUFF_TRY_ASSIGN(auto bare, renderFrames(eval::withoutParticles(scene), render::RenderPath::kCel, frames, opt.reps));
  PUFF_TRY_ASSIGN(auto ref, renderFrames(scene, render::RenderPath::kReference, frames, 0));
  PUFF_TRY_ASSIGN(auto refBare, renderFrames(eval::withoutParticles(scene), render::RenderPath::kReference, frames, 0));
  PUFF_TRY_ASSIGN(auto fillFloor, renderFrames(scene, render::RenderPath::kCel, frames, opt.reps, true));
  std::vector<std::pair<float, std::string>> ways{{cel::kMaxHullFromPixels, "blend"}};
  for (float from : eval::kHullFromPixels) ways.emplace_back(from, "hull from " + core::numberText(from) + " px");
  ways.emplace_back(0.0f, "hull");
  for (const auto& [from, label] : ways) {
    scene::Scene s = scene;
    s.style.tumble = from >= cel::kMaxHullFromPixels ? cel::TumbleMethod::kBlend : cel::TumbleMethod::kHull;
    s.style.hullFromPixels = from >= cel::kMaxHullFromPixels ? 0.0f : from;
    PUFF_TRY_ASSIGN(auto f, renderFrames(s, render::RenderPath::kCel, frames, opt.reps));
    rows.push_back(measuredRow(name, "cel", "tumble", from, label, scene.width, scene.height, f, fillFloor.ms, bare,
                               ref, refBare, ink));
  }
  std::fprintf(stderr, "puffbench: %s: oriented puffs by the blend, the hull from a size and the hull (%.1f s)\n",
               name.c_str(), std::chrono::duration<double>(Clock::now() - t0).count());
  return {};
}

}  // namespace

Result<std::vector<CelRow>> runCelBench(const CelBenchOptions& opt) {
  std::vector<CelRow> rows;
  const fs::path work = fs::temp_directory_path() / ("puffbench-cel-" + std::to_string(::getpid()));
  fs::remove_all(work);
  const bench::ScopedDir cleanup{work};

  auto log = [&](const std::string& what, Clock::time_point t0) {
    std::fprintf(stderr, "puffbench: %s (%.1f s)\n", what.c_str(),
                 std::chrono::duration<double>(Clock::now() - t0).count());
  };

  for (const std::string& name : opt.scenes) {
    PUFF_TRY_ASSIGN(auto loaded, scene::loadScene(opt.sceneDir / (name + ".json"), opt.artDir));
    scene::Scene scene = loaded;
    if (scene.atlas.empty()) return Error{name + ": not a cel scene (no atlas)"};
    scene.width = opt.width;
    scene.height = opt.height;
    scene.media.reset();
    const std::vector<int> frames = eval::budgetFrames(0, scene.animation.frames - 1);
    const glm::vec3 ink = scene::celStyleFor(scene).outlineColor;  // scene-linear, as the frames are
    const auto t0 = Clock::now();
    // The programmable path's scene, and the same within the fixed path's limits (both references).
    const scene::Scene fixedScene = eval::restrictToFixedLimits(scene);
    PUFF_TRY_ASSIGN(auto bare, renderFrames(eval::withoutParticles(scene), render::RenderPath::kCel, frames, opt.reps));
    PUFF_TRY_ASSIGN(auto bareFixed,
                    renderFrames(eval::withoutParticles(fixedScene), render::RenderPath::kFixed, frames, opt.reps));
    PUFF_TRY_ASSIGN(auto bareCelLimits,
                    renderFrames(eval::withoutParticles(fixedScene), render::RenderPath::kCel, frames, opt.reps));
    PUFF_TRY_ASSIGN(auto ref, renderFrames(scene, render::RenderPath::kReference, frames, 0));
    PUFF_TRY_ASSIGN(auto refBare,
                    renderFrames(eval::withoutParticles(scene), render::RenderPath::kReference, frames, 0));
    PUFF_TRY_ASSIGN(auto refFixed, renderFrames(fixedScene, render::RenderPath::kReference, frames, 0));
    PUFF_TRY_ASSIGN(auto refFixedBare,
                    renderFrames(eval::withoutParticles(fixedScene), render::RenderPath::kReference, frames, 0));
    // The fill-rate floors: the scene's particles as bare alpha-tested quads, same frames; the fixed
    // path's rows against its own (GL 1.x quads, within the fixed path's limits).
    PUFF_TRY_ASSIGN(auto fillFloor, renderFrames(scene, render::RenderPath::kCel, frames, opt.reps, true));
    PUFF_TRY_ASSIGN(auto fixedFloor, renderFrames(fixedScene, render::RenderPath::kFixed, frames, opt.reps, true));
    log(name + ": floors and references", t0);

    auto add = [&](const std::string& path, const std::string& parameter, double value, const Frames& f,
                   const Frames& bareFrames, const Frames& reference, const Frames& referenceBare,
                   const std::string& label) {
      rows.push_back(measuredRow(name, path, parameter, value, label, opt.width, opt.height, f,
                                 path == "fixed" ? fixedFloor.ms : fillFloor.ms, bareFrames, reference, referenceBare,
                                 ink));
    };

    // Atlas resolution: the nailboards with the scene's puffs baked at each cell size.
    for (int cell : opt.atlasCells) {
      const auto t1 = Clock::now();
      std::size_t faces = 0;
      PUFF_TRY_ASSIGN(auto sidecar, bake(scene.atlas, cell, 1, work / (name + "-cell" + std::to_string(cell)), &faces));
      scene::Scene s = scene;
      s.atlas = sidecar;
      PUFF_TRY_ASSIGN(auto f, renderFrames(s, render::RenderPath::kCel, frames, opt.reps));
      add("cel", "atlas", cell, f, bare, ref, refBare, std::to_string(cell));
      log(name + ": nailboards, atlas cells " + std::to_string(cell), t1);
    }
    // Mesh level of detail: the atlas (256-texel cells) baked from decimated meshes; the fixed path
    // drawing the first variation's mesh decimated alike. The reference keeps the full meshes.
    for (int k : opt.decimations) {
      const auto t1 = Clock::now();
      std::size_t faces = 0;
      PUFF_TRY_ASSIGN(auto sidecar, bake(scene.atlas, 256, k, work / (name + "-lod" + std::to_string(k)), &faces));
      scene::Scene s = scene;
      s.atlas = sidecar;
      PUFF_TRY_ASSIGN(auto f, renderFrames(s, render::RenderPath::kCel, frames, opt.reps));
      add("cel", "lod", static_cast<double>(faces), f, bare, ref, refBare, std::to_string(faces));
      // The fixed path's puff: the first source mesh at this level of detail, written beside the atlas.
      PUFF_TRY_ASSIGN(auto desc, core::loadAtlasDesc(scene.atlas));
      fs::path first = desc.sources.front().path;
      if (first.is_relative()) first = scene.atlas.parent_path() / first;
      PUFF_TRY_ASSIGN(auto full, mesh::loadMesh(first));
      const mesh::TriMesh m = k > 1 ? mesh::decimate(full, std::max<std::size_t>(20, full.faceCount() / k)) : full;
      const fs::path puff = work / (name + "-lod" + std::to_string(k)) / "fixed-puff.obj";
      if (auto ok = mesh::saveMesh(m, puff); !ok) return ok.error();
      scene::Scene lodScene = fixedScene;
      lodScene.fixed.puff = puff;
      PUFF_TRY_ASSIGN(auto ff, renderFrames(lodScene, render::RenderPath::kFixed, frames, opt.reps));
      add("fixed", "lod", static_cast<double>(m.faceCount()), ff, bareFixed, refFixed, refFixedBare,
          std::to_string(m.faceCount()));
      // The programmable path within the same limits, for the fixed path to be read against.
      if (k == 1) {
        PUFF_TRY_ASSIGN(auto cf, renderFrames(fixedScene, render::RenderPath::kCel, frames, opt.reps));
        add("cel-fixed-limits", "lod", static_cast<double>(faces), cf, bareCelLimits, refFixed, refFixedBare,
            std::to_string(faces));
      }
      log(name + ": level of detail 1/" + std::to_string(k), t1);
    }
  }

  // Particle count: cloud-50k's emitters scaled (a scene's first N particles are the same whatever
  // its count), the error against the reference of the same particles at frame 0.
  if (!opt.counts.empty()) {
    PUFF_TRY_ASSIGN(auto loaded, scene::loadScene(opt.sceneDir / "cloud-50k.json", opt.artDir));
    scene::Scene base = loaded;
    base.width = opt.width;
    base.height = opt.height;
    std::size_t total = 0;
    for (const scene::EmitterSpec& e : base.emitters) total += static_cast<std::size_t>(e.count);
    const std::vector<int> frame0{0};
    PUFF_TRY_ASSIGN(auto bare, renderFrames(eval::withoutParticles(base), render::RenderPath::kCel, frame0, opt.reps));
    const scene::Scene baseFixed = eval::restrictToFixedLimits(base);
    PUFF_TRY_ASSIGN(auto bareFixed,
                    renderFrames(eval::withoutParticles(baseFixed), render::RenderPath::kFixed, frame0, opt.reps));
    PUFF_TRY_ASSIGN(auto refBare,
                    renderFrames(eval::withoutParticles(base), render::RenderPath::kReference, frame0, 0));
    PUFF_TRY_ASSIGN(auto refFixedBare,
                    renderFrames(eval::withoutParticles(baseFixed), render::RenderPath::kReference, frame0, 0));
    // Rows of one cel and one fixed measurement of cloud-50k against the references given (none:
    // not measured).
    auto addCountRows = [&](const std::string& parameter, double value, const std::string& label, const Frames& cel,
                            const Frames& fixed, double floorMs, double fixedFloorMs, const Frames* ref,
                            const Frames* refFixed) {
      for (int which = 0; which < 2; ++which) {
        const Frames& x = which == 0 ? cel : fixed;
        CelRow r;
        r.scene = "cloud-50k";
        r.path = which == 0 ? "cel" : "fixed";
        r.parameter = parameter;
        r.value = value;
        r.label = label;
        r.particles = x.particles;
        r.width = opt.width;
        r.height = opt.height;
        r.ms = x.ms;
        r.floorMs = which == 0 ? floorMs : fixedFloorMs;
        r.bareMs = which == 0 ? bare.ms : bareFixed.ms;
        if (ref) {
          const Errors e = which == 0 ? compare(x, bare, *ref, refBare, base.style.outlineColor)
                                      : compare(x, bareFixed, *refFixed, refFixedBare, base.style.outlineColor);
          r.rmse = e.rmse;
          r.rmsePuffs = e.rmsePuffs;
          r.coverageIoU = e.coverageIoU;
          r.outlineIoU = e.outlineIoU;
        } else {
          r.rmse = r.rmsePuffs = std::nan("");
          r.coverageIoU = r.outlineIoU = std::nan("");
        }
        rows.push_back(r);
      }
    };
    // The largest count measured against its reference: the full model of the fraction sweep below.
    struct FullModel {
      scene::Scene scene;
      std::size_t count = 0;
      Frames ref, refFixed;
    };
    std::optional<FullModel> full;
    for (std::size_t n : opt.counts) {
      const auto t1 = Clock::now();
      scene::Scene s = base;
      std::size_t placed = 0;
      for (std::size_t i = 0; i < s.emitters.size(); ++i) {
        const std::size_t share = i + 1 == s.emitters.size()
                                      ? n - placed
                                      : static_cast<std::size_t>(std::llround(double(n) * s.emitters[i].count / total));
        s.emitters[i].count = static_cast<int>(share);
        placed += share;
      }
      const scene::Scene sf = eval::restrictToFixedLimits(s);
      PUFF_TRY_ASSIGN(auto f, renderFrames(s, render::RenderPath::kCel, frame0, opt.reps));
      PUFF_TRY_ASSIGN(auto fillFloor, renderFrames(s, render::RenderPath::kCel, frame0, opt.reps, true));
      PUFF_TRY_ASSIGN(auto ff, renderFrames(sf, render::RenderPath::kFixed, frame0, opt.reps));
      PUFF_TRY_ASSIGN(auto fixedFloor, renderFrames(sf, render::RenderPath::kFixed, frame0, opt.reps, true));
      const bool measureError = n <= opt.referenceLimit;
      Frames ref, refFixed;
      if (measureError) {
        PUFF_TRY_ASSIGN(auto r, renderFrames(s, render::RenderPath::kReference, frame0, 0));
        ref = std::move(r);
        PUFF_TRY_ASSIGN(auto rf, renderFrames(sf, render::RenderPath::kReference, frame0, 0));
        refFixed = std::move(rf);
      }
      addCountRows("count", static_cast<double>(n), std::to_string(n), f, ff, fillFloor.ms, fixedFloor.ms,
                   measureError ? &ref : nullptr, measureError ? &refFixed : nullptr);
      if (measureError) full = FullModel{s, n, std::move(ref), std::move(refFixed)};
      log("cloud-50k: " + std::to_string(n) + " particles" + (measureError ? "" : " (no reference: above the limit)"),
          t1);
    }
    // Fewer, bigger particles (Scene::particleFraction, what --max-error chooses) against the
    // reference of the full model: the largest count measured above.
    if (full) {
      for (float f : eval::kParticleFractions) {
        const auto t1 = Clock::now();
        scene::Scene s = full->scene;
        s.particleFraction = f;
        PUFF_TRY_ASSIGN(auto cel, renderFrames(s, render::RenderPath::kCel, std::vector<int>{0}, opt.reps));
        PUFF_TRY_ASSIGN(auto fixed, renderFrames(eval::restrictToFixedLimits(s), render::RenderPath::kFixed,
                                                 std::vector<int>{0}, opt.reps));
        PUFF_TRY_ASSIGN(auto floor, renderFrames(s, render::RenderPath::kCel, std::vector<int>{0}, opt.reps, true));
        PUFF_TRY_ASSIGN(auto fixedFloor, renderFrames(eval::restrictToFixedLimits(s), render::RenderPath::kFixed,
                                                      std::vector<int>{0}, opt.reps, true));
        char label[64];
        std::snprintf(label, sizeof label, "1/%d of %zu", static_cast<int>(std::lround(1.0 / f)), full->count);
        addCountRows("fraction", f, label, cel, fixed, floor.ms, fixedFloor.ms, &full->ref, &full->refFixed);
        log(std::string("cloud-50k: ") + label + " particles, each larger", t1);
      }
    }
  }
  for (const std::string& name : opt.tumbleScenes) PUFF_TRY(addTumbleRows(opt, name, rows));
  markParetoFronts(rows);
  return rows;
}

void markParetoFronts(std::vector<CelRow>& rows) {
  // Per scene and parameter, over every path: nothing else as fast and as close, better in one.
  for (CelRow& a : rows) {
    a.pareto = std::isfinite(a.rmse);
    for (const CelRow& b : rows) {
      if (!a.pareto) break;
      if (&a == &b || b.scene != a.scene || b.parameter != a.parameter || !std::isfinite(b.rmse)) continue;
      if (b.ms <= a.ms && b.rmse <= a.rmse && (b.ms < a.ms || b.rmse < a.rmse)) a.pareto = false;
    }
  }
}

std::string celCsv(const std::vector<CelRow>& rows) {
  std::string csv =
      "scene,path,parameter,value,label,particles,width,height,median_ms,floor_ms,ratio_to_floor,rmse,psnr_db,"
      "coverage_iou,outline_iou,pareto,rmse_puffs,bare_ms,valid\n";
  for (const CelRow& r : rows) {
    const double psnr = !std::isfinite(r.rmse) ? std::nan("") : r.rmse > 0.0 ? -20.0 * std::log10(r.rmse) : 999.0;
    // A row faster than its floor: invalid (valid 0), ratio left empty.
    bench::appendf(csv, "%s,%s,%s,%g,%s,%zu,%d,%d,%.3f,%.3f,%s,%.6f,%.2f,%.4f,%.4f,%d,%.6f,%.3f,%d\n", r.scene.c_str(),
                   r.path.c_str(), r.parameter.c_str(), r.value, r.label.c_str(), r.particles, r.width, r.height, r.ms,
                   r.floorMs, bench::ratioToFloor(r.ms, r.floorMs).c_str(), r.rmse, psnr, r.coverageIoU, r.outlineIoU,
                   r.pareto ? 1 : 0, r.rmsePuffs, r.bareMs, bench::validAgainstFloor(r.ms, r.floorMs) ? 1 : 0);
  }
  return csv;
}

}  // namespace puffbench
