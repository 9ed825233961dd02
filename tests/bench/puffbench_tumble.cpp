// puffbench's tumble part: the multi-view atlas's size against its accuracy. The art's four
// puffs are baked with each view layout (oct: the whole sphere; hemioct: the front hemisphere, back
// views mirrored), grid (grid x grid views a variation) and cell size; each atlas's oriented
// nailboards are turned through the sweep of eval::tumblePoses (yaw, pitch and roll every 15 degrees)
// and compared pose by pose with ONE cel reference of the same poses (eval::renderTumbleReference:
// it turns the actual meshes, so it depends on the meshes and the sweep only, not on the atlas).
// Each atlas is measured twice: its puffs drawn by marching the hull of their views (cel::Style::tumble
// "hull", the default) and by blending four views ("blend").
// Per atlas and method: its GL texture memory (core::atlasTextureBytes), coverage IoU and outline IoU over the
// poses (smallest, mean, and the share of poses at the bars: coverage >= 0.95, outline >= 0.5),
// and the median time of a frame of the pose grid (nailboards only). Not a test: nothing fails here.
#include "puffbench_tumble.h"

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>

#include <puff/bake/baker.h>
#include <puff/core/atlas.h>
#include <puff/eval/tumble.h>

#include "harness.h"

namespace puffbench {

namespace fs = std::filesystem;
using namespace puff;
using bench::Clock;

namespace {

Result<bake::ViewLayout> layoutOf(const std::string& name) {
  if (name == "oct") return bake::ViewLayout::kOct;
  if (name == "hemioct") return bake::ViewLayout::kHemiOct;
  return Error{"tumble: view layout '" + name + "': oct or hemioct"};
}

}  // namespace

Result<std::vector<TumbleAtlas>> parseTumbleAtlases(const std::string& list) {
  std::vector<TumbleAtlas> out;
  for (std::size_t at = 0; at <= list.size();) {
    const std::size_t comma = std::min(list.find(',', at), list.size());
    const std::string item = list.substr(at, comma - at);
    at = comma + 1;
    if (item.empty()) continue;
    const std::size_t digit = item.find_first_of("0123456789");
    if (digit == std::string::npos || digit == 0 || item.find_first_not_of("0123456789", digit) != std::string::npos) {
      return Error{"tumble: atlas '" + item + "': a layout and its grid, e.g. oct5 or hemioct3"};
    }
    TumbleAtlas a{item.substr(0, digit), std::stoi(item.substr(digit))};
    if (auto l = layoutOf(a.layout); !l) return l.error();
    if (a.grid < 2 || a.grid > 16) return Error{"tumble: atlas '" + item + "': a grid of 2 to 16 views a side"};
    out.push_back(a);
  }
  if (out.empty()) return Error{"tumble: no atlases given"};
  return out;
}

Result<std::vector<TumbleRow>> runTumbleBench(const TumbleBenchOptions& opt) {
  const auto start = Clock::now();
  auto log = [&](const std::string& what) {
    std::fprintf(stderr, "puffbench: tumble: %s (%.1f s)\n", what.c_str(),
                 std::chrono::duration<double>(Clock::now() - start).count());
  };
  const fs::path work = fs::temp_directory_path() / ("puffbench-tumble-" + std::to_string(::getpid()));
  fs::remove_all(work);
  const bench::ScopedDir cleanup{work};

  std::vector<fs::path> meshes;
  for (const char* m : {"variation-1.obj", "variation-2.ply", "variation-3.off", "variation-4.stl"})
    meshes.push_back(opt.puffDir / m);
  PUFF_TRY_ASSIGN(auto sources, bake::loadSources(meshes, std::nullopt));

  eval::TumbleOptions tumble;
  tumble.stepDegrees = opt.stepDegrees;
  std::optional<eval::TumbleReference> reference;
  std::vector<TumbleRow> rows;
  for (const TumbleAtlas& a : opt.atlases) {
    PUFF_TRY_ASSIGN(auto layout, layoutOf(a.layout));
    for (int cell : opt.cellSizes) {
      const std::string name = a.layout + std::to_string(a.grid) + "-" + std::to_string(cell);
      bake::BakeOptions o;
      o.cellSize = cell;
      o.viewGrid = a.grid;
      o.viewLayout = layout;
      o.outDir = work / name;
      o.contactSheet = false;
      PUFF_TRY_ASSIGN(auto baked, bake::bakeAtlas(sources, o));
      log(name + ": baked");
      if (!reference) {
        // The reference turns the source meshes the sidecar names: the same for every atlas here.
        PUFF_TRY_ASSIGN(auto r, eval::renderTumbleReference(baked.sidecar, tumble));
        reference = std::move(r);
        log("the reference of " + std::to_string(eval::tumblePoses(tumble.stepDegrees).size()) + " poses, " +
            std::to_string(reference->rolls.size()) + " frames");
      }
      for (cel::TumbleMethod method : {cel::TumbleMethod::kHull, cel::TumbleMethod::kBlend}) {
        double ms = 0.0;
        PUFF_TRY_ASSIGN(auto result, eval::measureTumble(baked.sidecar, *reference, method, &ms));
        TumbleRow r;
        r.layout = a.layout;
        r.method = std::string(cel::toString(method));
        r.grid = a.grid;
        r.views = a.grid * a.grid;
        r.cellSize = cell;
        r.atlasBytes = core::atlasTextureBytes(baked.desc);
        r.poses = result.poses.size();
        r.minCoverageIoU = result.minCoverageIoU;
        r.meanCoverageIoU = result.meanCoverageIoU;
        r.minOutlineIoU = result.minOutlineIoU;
        r.meanOutlineIoU = result.meanOutlineIoU;
        std::size_t coverageOk = 0, outlineOk = 0;
        const eval::TumblePose* worst = nullptr;
        double extra = 0.0, missing = 0.0, bodyExtra = 0.0, bodyMissing = 0.0, bodyMin = 1.0;
        std::size_t bodyOk = 0;
        for (const eval::TumblePose& p : result.poses) {
          coverageOk += p.coverageIoU >= 0.95;
          outlineOk += p.outlineIoU >= 0.5;
          if (!worst || p.coverageIoU < worst->coverageIoU) worst = &p;
          extra += p.coverageExtra;
          missing += p.coverageMissing;
          bodyExtra += p.bodyExtra;
          bodyMissing += p.bodyMissing;
          // IoU = |A and B| / |A or B| = (1 - missing) / (1 + extra), both fractions of B's pixels.
          const double bodyIoU = (1.0 - p.bodyMissing) / (1.0 + p.bodyExtra);
          bodyMin = std::min(bodyMin, bodyIoU);
          bodyOk += bodyIoU >= 0.95;
        }
        if (worst) {
          // Whether the puffs are drawn too large or too small: the mean over the poses, and the
          // worst pose's (fractions of the reference's pixels).
          const double n = static_cast<double>(result.poses.size());
          char line[384];
          std::snprintf(line, sizeof line,
                        "%s: coverage extra / missing mean %.4f / %.4f; without outlines %.4f / %.4f, IoU min %.4f "
                        "(%.1f%% >= 0.95); worst pose yaw %d pitch %d roll %d "
                        "variation %d: IoU %.4f, extra %.4f, missing %.4f",
                        r.method.c_str(), extra / n, missing / n, bodyExtra / n, bodyMissing / n, bodyMin,
                        100.0 * static_cast<double>(bodyOk) / n, worst->yaw, worst->pitch, worst->roll,
                        worst->variation, worst->coverageIoU, worst->coverageExtra, worst->coverageMissing);
          log(name + ": " + line);
        }
        if (r.poses > 0) {
          r.coverageShare = static_cast<double>(coverageOk) / static_cast<double>(r.poses);
          r.outlineShare = static_cast<double>(outlineOk) / static_cast<double>(r.poses);
        }
        r.ms = ms;
        rows.push_back(r);
        log(name + ": measured, " + r.method);
      }
      std::error_code ec;
      fs::remove_all(o.outDir, ec);  // the next atlas needs its own; this one is done
    }
  }
  return rows;
}

std::string tumbleCsv(const std::vector<TumbleRow>& rows) {
  std::string csv =
      "layout,grid,views,cell_size,atlas_bytes,poses,coverage_iou_min,coverage_iou_mean,coverage_share_095,"
      "outline_iou_min,outline_iou_mean,outline_share_05,median_ms,method\n";
  for (const TumbleRow& r : rows) {
    bench::appendf(csv, "%s,%d,%d,%d,%zu,%zu,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.3f,%s\n", r.layout.c_str(), r.grid,
                   r.views, r.cellSize, r.atlasBytes, r.poses, r.minCoverageIoU, r.meanCoverageIoU, r.coverageShare,
                   r.minOutlineIoU, r.meanOutlineIoU, r.outlineShare, r.ms, r.method.c_str());
  }
  return csv;
}

}  // namespace puffbench
