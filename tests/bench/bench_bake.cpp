// Bake-time benchmark: 4 lumpy variations at 256^2 and 1024^2 cells, with and without --lod auto.
// Each case: one warm-up bake, then the median of --reps bakes; the ratio is against the
// 256^2 full-detail case measured in the same run. Writes CSV (stdout, or --csv FILE).
// Not a test: nothing here fails on a time.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <puff/bake/baker.h>
#include <puff/io/openimageio.h>
#include <puff/platform/gl_context.h>

#include "bench_usage.h"
#include "harness.h"

namespace {

namespace fs = std::filesystem;
using namespace puff;

struct Case {
  const char* name;
  int cellSize;
  bool lod;
};

}  // namespace

int main(int argc, char** argv) {
  puff::io::useOpenImageIO();
  int reps = 3;
  int subdivisions = 5;
  std::string csvPath;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
      reps = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--subdivisions") && i + 1 < argc)
      subdivisions = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc)
      csvPath = argv[++i];
    else {
      std::fprintf(puff::bench::usageStream(argv[i]), "usage: puff_bench [--reps N] [--subdivisions N] [--csv FILE]\n");
      return puff::bench::usageExit(argv[i]);
    }
  }
  auto context = core::createGlContext({});
  if (!context) {
    std::fprintf(stderr, "puff_bench: error: %s\n", context.error().message.c_str());
    return 1;
  }
  std::fprintf(stderr, "puff_bench: %s\n", (*context)->describe().c_str());

  std::vector<bake::PuffSource> sources(4);
  for (int i = 0; i < 4; ++i) {
    mesh::LumpyParams p;  // pinned, so figures stay comparable when the generator's defaults change
    p.subdivisions = subdivisions;
    p.amplitude = 0.25f;
    p.frequency = 2.0f;
    p.octaves = 3;
    p.seed = 1 + static_cast<std::uint64_t>(i);
    sources[static_cast<std::size_t>(i)].mesh = mesh::generateLumpy(p);
    sources[static_cast<std::size_t>(i)].provenance.generator = "lumpy";
  }
  const fs::path out = fs::temp_directory_path() / "puff_bench_out";
  const Case cases[] = {
      {"256_full", 256, false}, {"256_lod_auto", 256, true}, {"1024_full", 1024, false}, {"1024_lod_auto", 1024, true}};
  FILE* csv = csvPath.empty() ? stdout : std::fopen(csvPath.c_str(), "w");
  if (!csv) {
    std::fprintf(stderr, "puff_bench: error: %s: cannot write\n", csvPath.c_str());
    return 1;
  }
  std::fprintf(csv, "case,cell_size,lod_auto,variations,faces_in,faces_baked,reps,median_ms,ratio_to_256_full\n");
  double baseline = 0;
  for (const Case& c : cases) {
    bake::BakeOptions o;
    o.cellSize = c.cellSize;
    o.lodAuto = c.lod;
    o.outDir = out;
    std::vector<double> times;
    std::size_t facesIn = 0, facesBaked = 0;
    for (int r = -1; r < reps; ++r) {  // r == -1: warm-up
      const auto t0 = bench::Clock::now();
      auto result = bake::bakeAtlas(sources, o);
      const auto t1 = bench::Clock::now();
      if (!result) {
        std::fprintf(stderr, "puff_bench: error: %s\n", result.error().message.c_str());
        return 1;
      }
      facesIn = facesBaked = 0;
      for (const auto& s : result->desc.sources) {
        facesIn += s.faces;
        facesBaked += s.facesBaked;
      }
      if (r >= 0) times.push_back(bench::msBetween(t0, t1));
    }
    const double median = bench::median(times);
    if (baseline == 0) baseline = median;
    std::fprintf(csv, "%s,%d,%d,4,%zu,%zu,%d,%.1f,%.3f\n", c.name, c.cellSize, c.lod ? 1 : 0, facesIn, facesBaked, reps,
                 median, median / baseline);
    std::fflush(csv);
    std::fprintf(stderr, "puff_bench: %s: median %.1f ms\n", c.name, median);
  }
  if (csv != stdout) std::fclose(csv);
  fs::remove_all(out);
  return 0;
}
