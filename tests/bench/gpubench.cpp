// puff_gpubench: what Puff's frames cost on the machine at hand, each beside its floor, from cooked
// scenes (puff_cook_scene), in one run of a few minutes on a GPU. It links no image library and no
// window system: only libEGL (puff_platform_egl), so tests/bench/gpu.sh can pack it with the few
// shared libraries it needs and run it where nothing was built (docs/bench/gpu.md).
//
// Cases (--scenes DIR holds the cooked cloud-50k.json, dust-roll.json and explosion-walls.json):
//   nailboards    cloud-50k's puffs thinned to N (scene.particleFraction = N / 50000: fewer, bigger
//                 puffs filling the same cloud), S x S pixels, no shadows; N 1k, 10k, 50k; S 512, 1024
//   full-map      the same with shadows by the map
//   full-volumes  the same with shadows by volumes
//                 (these three: the baseline is the case with its lit nailboards shading every layer,
//                 GROUP.every-layer-N-S, SceneRenderer::setLitShading)
//   cloud-50k     the scene as it is, at 1920 x 1080
//   blend, hull   dust-roll frames 30-35 at 960 x 540, its oriented puffs drawn by blending views /
//                 by the hull (style.tumble); the hull's baseline is the blend
//   hull-no-occluders  the hull with every fragment marched (SceneRenderer::setHullOcclusion kNone):
//                 what the occluders buy; baseline the blend (not in --quick)
//   hull-from-P   (group tumble-split) the same, the hull only for puffs P pixels across and more
//                 (style.hullFromPixels, P 48 and 96), the blend for the rest; baseline the blend
//                 (not in --quick)
//   no-media      explosion-walls frame 20 at 960 x 540 without its media (particles, emitters and
//                 lights removed): the media rows' baseline
//   media-R       explosion-walls frame 20 at 960 x 540, the media layer at R of the frame (1, 1/2,
//                 1/4, 1/8)
// every one at MSAA samples 1 and 4 (--quick: cloud-50k, tumble and media at 480 x 270). The floor
// is the same frame with SceneRenderer::setFillRateFloor (every particle a bare alpha-tested quad;
// docs/bench/README.md).
//
// Times: GL_TIME_ELAPSED around the case's frames (what the GPU spent) and the wall clock to
// glFinish() (what the CPU added: the simulation, sorting, uploads), per frame. Each round draws the
// case, its floor and its baseline one after the other, so a change of load hits all of them; the
// medians of --reps rounds after --warm-up rounds (a case whose first frame takes longer than
// --max-frame-s: that round alone, `rounds` 1 in the CSV). The frames are drawn into a framebuffer
// of the case's size (RGBA16F, depth 24 + stencil 8, the case's samples) as a game's frame would be
// (SceneRenderer::drawFrame); nothing timed is read back. On llvmpipe the timer query does not time the
// rasterizer (it runs in its own threads): read the wall clock there (docs/bench/gpu.md).
//
// Each row also holds a hash of the case's first frame and of its floor's (Target::hash: what was
// drawn, told apart without a picture). Writes CSV (--csv FILE, atomically; else stdout),
// GL_RENDERER in every row, and prints each row
// on stderr as it is measured. Not a test: nothing here fails on a time.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include <puff/core/gl.h>
#include <puff/core/shader.h>
#include <puff/gl_api.h>
#include <puff/platform/gl_context.h>
#include <puff/render/render.h>
#include <puff/scene/read.h>

#include "harness.h"

namespace {

namespace fs = std::filesystem;
using namespace puff;
using bench::appendf;
using bench::Clock;
using bench::msSince;

constexpr const char* kTool = "puff_gpubench";

struct Options {
  fs::path scenes;
  std::string csv;
  int reps = 5, warmUp = 2;
  std::vector<int> samples{1, 4};
  std::vector<int> counts{1000, 10000, 50000};  ///< the nailboard cases' puffs
  std::vector<int> sizes{512, 1024};            ///< the nailboard cases' frame sides
  bool quick = false;                           ///< the smallest case of each group, one round: proves the binary runs
  std::vector<std::string> groups;              ///< the groups to run; empty: all
  fs::path shaderDir;                           ///< read the shaders here instead of the built-in copies
  double maxFrameS = 1e9;                       ///< a case whose first frame takes longer is timed by that round alone
};

struct Case {
  std::string group, name, scene;  ///< scene: the cooked scene's file name in --scenes
  int width = 0, height = 0, samples = 1;
  std::vector<int> frames{0};
  std::function<void(scene::Scene&)> edit = [](scene::Scene&) {};
  std::string baseline;  ///< another case's name (same samples), measured in the same rounds; empty: none
  /// The baseline is this case with its lit nailboards shading every layer
  /// (SceneRenderer::setLitShading), named `baseline`: what shading each pixel once buys.
  bool baselineEveryLayer = false;
  bool everyLayer = false;                                       ///< the nailboards' lit pass shades every layer
  cel::HullOcclusion hullOcclusion = cel::HullOcclusion::kAuto;  ///< the tumbling hull's
};

struct Timing {
  double gpuMs = 0.0, wallMs = 0.0;  ///< per frame
};

// The cases in the order they run (see the file's comment).
std::vector<Case> plan(const Options& o) {
  std::vector<Case> cases;
  const std::vector<int> counts = o.quick ? std::vector<int>{o.counts.front()} : o.counts;
  const std::vector<int> sizes = o.quick ? std::vector<int>{o.sizes.front()} : o.sizes;
  for (int samples : o.samples) {
    for (int size : sizes) {
      for (int n : counts) {
        const float fraction = static_cast<float>(n) / 50000.0f;
        auto cel = [fraction](bool shadows, cel::ShadowMethod method) {
          return [=](scene::Scene& s) {
            s.particleFraction = fraction;
            s.style.shadows = shadows;
            s.style.shadowMethod = method;
          };
        };
        const std::string tag = "-" + std::to_string(n) + "-" + std::to_string(size);
        cases.push_back({"nailboards",
                         "nailboards" + tag,
                         "cloud-50k.json",
                         size,
                         size,
                         samples,
                         {0},
                         cel(false, cel::ShadowMethod::kMap),
                         "nailboards.every-layer" + tag,
                         true});
        cases.push_back({"full-map",
                         "full-map" + tag,
                         "cloud-50k.json",
                         size,
                         size,
                         samples,
                         {0},
                         cel(true, cel::ShadowMethod::kMap),
                         "full-map.every-layer" + tag,
                         true});
        cases.push_back({"full-volumes",
                         "full-volumes" + tag,
                         "cloud-50k.json",
                         size,
                         size,
                         samples,
                         {0},
                         cel(true, cel::ShadowMethod::kVolumes),
                         "full-volumes.every-layer" + tag,
                         true});
      }
    }
    const int cloudWidth = o.quick ? 480 : 1920, cloudHeight = o.quick ? 270 : 1080;
    cases.push_back({"cloud-50k",
                     "cloud-50k-" + std::to_string(cloudHeight),
                     "cloud-50k.json",
                     cloudWidth,
                     cloudHeight,
                     samples,
                     {0},
                     [](scene::Scene&) {},
                     ""});
    const std::vector<int> tumbleFrames = o.quick ? std::vector<int>{30} : std::vector<int>{30, 31, 32, 33, 34, 35};
    const int w = o.quick ? 480 : 960, h = o.quick ? 270 : 540;  // the tumble and media cases' frame
    auto tumble = [](cel::TumbleMethod m) { return [=](scene::Scene& s) { s.style.tumble = m; }; };
    cases.push_back(
        {"tumble", "blend", "dust-roll.json", w, h, samples, tumbleFrames, tumble(cel::TumbleMethod::kBlend), ""});
    cases.push_back(
        {"tumble", "hull", "dust-roll.json", w, h, samples, tumbleFrames, tumble(cel::TumbleMethod::kHull), "blend"});
    Case marchedAll{
        "tumble", "hull-no-occluders", "dust-roll.json", w, h, samples, tumbleFrames, tumble(cel::TumbleMethod::kHull),
        "blend"};
    marchedAll.hullOcclusion = cel::HullOcclusion::kNone;
    if (!o.quick) cases.push_back(marchedAll);
    // The hull only for puffs that large on screen, the blend for the rest (not in --quick's one case).
    for (const int from : o.quick ? std::vector<int>{} : std::vector<int>{48, 96}) {
      cases.push_back({"tumble-split", "hull-from-" + std::to_string(from), "dust-roll.json", w, h, samples,
                       tumbleFrames,
                       [=](scene::Scene& s) {
                         s.style.tumble = cel::TumbleMethod::kHull;
                         s.style.hullFromPixels = static_cast<float>(from);
                       },
                       "blend"});
    }
    cases.push_back({"media",
                     "no-media",
                     "explosion-walls.json",
                     w,
                     h,
                     samples,
                     {20},
                     [](scene::Scene& s) {
                       s.media->particles.clear();
                       s.media->emitters.clear();
                       s.media->lights.clear();
                     },
                     ""});
    const std::vector<float> resolutions =
        o.quick ? std::vector<float>{0.5f} : std::vector<float>{1.0f, 0.5f, 0.25f, 0.125f};
    for (float r : resolutions) {
      char name[32];
      std::snprintf(name, sizeof name, "media-%g", static_cast<double>(r));
      cases.push_back({"media",
                       name,
                       "explosion-walls.json",
                       w,
                       h,
                       samples,
                       {20},
                       [r](scene::Scene& s) { s.media->resolution = r; },
                       "no-media"});
    }
  }
  return cases;
}

// A game's frame: colour RGBA16F (scene-linear), depth 24 + stencil 8, `samples` samples.
class Target {
 public:
  Target(int width, int height, int samples)
      : width_(width),
        height_(height),
        fbo_(core::makeFramebuffer()),
        color_(core::makeRenderbuffer()),
        depth_(core::makeRenderbuffer()) {
    const int s = samples > 1 ? samples : 0;
    glNamedRenderbufferStorageMultisample(color_.get(), s, GL_RGBA16F, width, height);
    glNamedRenderbufferStorageMultisample(depth_.get(), s, GL_DEPTH24_STENCIL8, width, height);
    glNamedFramebufferRenderbuffer(fbo_.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_.get());
    glNamedFramebufferRenderbuffer(fbo_.get(), GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_.get());
  }
  bool complete() const { return glCheckNamedFramebufferStatus(fbo_.get(), GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE; }
  void bind() const { glBindFramebuffer(GL_FRAMEBUFFER, fbo_.get()); }
  core::Viewport viewport() const { return {0, 0, width_, height_}; }
  /// What the frame drawn last shows, as a hash (FNV-1a of its resolved half-float colour): tells
  /// frames apart without a picture (a floor from its case), never timed.
  std::string hash() const {
    core::Framebuffer resolved = core::makeFramebuffer();
    core::Renderbuffer color = core::makeRenderbuffer();
    glNamedRenderbufferStorage(color.get(), GL_RGBA16F, width_, height_);
    glNamedFramebufferRenderbuffer(resolved.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color.get());
    glBlitNamedFramebuffer(fbo_.get(), resolved.get(), 0, 0, width_, height_, 0, 0, width_, height_,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
    std::string bytes(static_cast<std::size_t>(width_) * height_ * 8, '\0');
    glBindFramebuffer(GL_READ_FRAMEBUFFER, resolved.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_HALF_FLOAT, bytes.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    return core::fnv1a64Hex(bytes);
  }

 private:
  int width_, height_;
  core::Framebuffer fbo_;
  core::Renderbuffer color_, depth_;
};

// One configuration ready to draw: its renderer and its frames.
struct Setup {
  std::unique_ptr<render::SceneRenderer> renderer;
  std::vector<int> frames;
};

Result<Setup> setUp(const Options& o, const Case& c, bool floor) {
  PUFF_TRY_ASSIGN(scene::Scene s, scene::loadScene(o.scenes / c.scene));
  if ((c.group == "media") != s.media.has_value()) return Error::at(o.scenes / c.scene, "has no media");
  c.edit(s);
  s.width = c.width;
  s.height = c.height;
  s.samples = c.samples;
  Setup setup;
  PUFF_TRY_ASSIGN(setup.renderer, render::SceneRenderer::create(s, render::RenderPath::kCel));
  setup.renderer->setFillRateFloor(floor);
  setup.renderer->setLitShading(c.everyLayer ? cel::LitShading::kEveryLayer : cel::LitShading::kAuto);
  setup.renderer->setHullOcclusion(c.hullOcclusion);
  setup.frames = c.frames;
  return setup;
}

// Draws the setup's frames once into `target`; the GPU's and the wall's time per frame.
Result<Timing> drawOnce(Setup& setup, const Target& target, GLuint query, std::size_t* particles) {
  target.bind();
  const auto t0 = Clock::now();
  glBeginQuery(GL_TIME_ELAPSED, query);
  for (int frame : setup.frames) {
    render::FrameStats stats;
    PUFF_TRY(setup.renderer->drawFrame(frame, target.viewport(), &stats));
    if (particles) *particles = std::max(*particles, stats.particles + stats.mediaParticles);
  }
  glEndQuery(GL_TIME_ELAPSED);
  glFinish();
  const double wall = msSince(t0);
  GLuint64 ns = 0;
  glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
  const double n = static_cast<double>(setup.frames.size());
  return Timing{static_cast<double>(ns) * 1e-6 / n, wall / n};
}

struct Measured {
  Timing at, floor, baseline;
  std::string image, floorImage;  ///< Target::hash of the case's frame and of its floor's
  std::size_t particles = 0;
  int rounds = 0;  ///< timed rounds the medians are of
};

// The case, its floor and its baseline (if any), round by round; the medians.
Result<Measured> measure(const Options& o, const Case& c, const Case* baseline) {
  const Target target(c.width, c.height, c.samples);
  if (!target.complete())
    return Error{c.name + ": the " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                 " target is incomplete"};
  std::vector<Setup> setups;
  PUFF_TRY_ASSIGN(auto at, setUp(o, c, false));
  PUFF_TRY_ASSIGN(auto floor, setUp(o, c, true));
  setups.push_back(std::move(at));
  setups.push_back(std::move(floor));
  if (baseline) {
    PUFF_TRY_ASSIGN(auto base, setUp(o, *baseline, false));
    setups.push_back(std::move(base));
  }
  GLuint query = 0;
  glGenQueries(1, &query);
  // A first query answered before any is timed: some drivers (llvmpipe) answer a query object's very
  // first use with garbage.
  glBeginQuery(GL_TIME_ELAPSED, query);
  glEndQuery(GL_TIME_ELAPSED);
  GLuint64 primed = 0;
  glGetQueryObjectui64v(query, GL_QUERY_RESULT, &primed);
  std::vector<std::vector<double>> gpu(setups.size()), wall(setups.size());
  Measured m;
  int warmUp = o.quick ? 1 : o.warmUp, reps = o.quick ? 1 : o.reps;
  for (int round = 0; round < warmUp + reps; ++round) {
    for (std::size_t i = 0; i < setups.size(); ++i) {
      auto t = drawOnce(setups[i], target, query, i == 0 ? &m.particles : nullptr);
      if (!t) {
        glDeleteQueries(1, &query);
        return Error{c.name + ": " + t.error().message};
      }
      // A case slower than --max-frame-s is measured by this first round alone.
      if (round == 0 && i == 0 && t->wallMs > o.maxFrameS * 1000.0) {
        warmUp = 0;
        reps = 1;
      }
      if (round == 0 && i < 2) (i == 0 ? m.image : m.floorImage) = target.hash();
      if (round < warmUp) continue;
      gpu[i].push_back(t->gpuMs);
      wall[i].push_back(t->wallMs);
    }
  }
  m.rounds = reps;
  glDeleteQueries(1, &query);
  Timing* out[] = {&m.at, &m.floor, &m.baseline};
  for (std::size_t i = 0; i < setups.size(); ++i) *out[i] = {bench::median(gpu[i]), bench::median(wall[i])};
  return m;
}

std::string ratio(double a, double b) {
  if (!(b > 0.0)) return {};
  char t[32];
  std::snprintf(t, sizeof t, "%.3f", a / b);
  return t;
}

// The renderer's name without commas (a CSV field).
std::string rendererName() {
  const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  std::string s = name ? name : "unknown";
  std::replace(s.begin(), s.end(), ',', ';');
  return s;
}

constexpr const char* kHeader =
    "group,case,scene,width,height,samples,particles,frames,rounds,gpu_ms,wall_ms,floor_gpu_ms,floor_wall_ms,"
    "gpu_over_floor,wall_over_floor,baseline,baseline_gpu_ms,baseline_wall_ms,gpu_over_baseline,wall_over_baseline,"
    "image,floor_image,"
    "renderer\n";

void appendRow(std::string& csv, const Case& c, const Measured& m, const std::string& gpuName) {
  const bool base = !c.baseline.empty();
  char baseGpu[32] = "", baseWall[32] = "";
  if (base) {
    std::snprintf(baseGpu, sizeof baseGpu, "%.4f", m.baseline.gpuMs);
    std::snprintf(baseWall, sizeof baseWall, "%.4f", m.baseline.wallMs);
  }
  appendf(csv, "%s,%s,%s,%d,%d,%d,%zu,%zu,%d,%.4f,%.4f,%.4f,%.4f,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s\n", c.group.c_str(),
          c.name.c_str(), c.scene.c_str(), c.width, c.height, c.samples, m.particles, c.frames.size(), m.rounds,
          m.at.gpuMs, m.at.wallMs, m.floor.gpuMs, m.floor.wallMs, ratio(m.at.gpuMs, m.floor.gpuMs).c_str(),
          ratio(m.at.wallMs, m.floor.wallMs).c_str(), c.baseline.c_str(), baseGpu, baseWall,
          base ? ratio(m.at.gpuMs, m.baseline.gpuMs).c_str() : "",
          base ? ratio(m.at.wallMs, m.baseline.wallMs).c_str() : "", m.image.c_str(), m.floorImage.c_str(),
          gpuName.c_str());
}

// Whether the CSV can be written at `path` (no file is touched): not a directory, and its folder,
// or the nearest existing folder above it, writable.
Result<void> csvWritable(const fs::path& path) {
  if (path.empty()) return {};
  std::error_code ec;
  if (fs::is_directory(path, ec)) return Error::at(path, "is a directory");
  fs::path dir = fs::absolute(path, ec).parent_path();
  while (!dir.empty() && !fs::exists(dir, ec) && dir != dir.parent_path()) dir = dir.parent_path();
  if (!fs::is_directory(dir, ec)) return Error::at(dir, "not a directory");
  if (access(dir.c_str(), W_OK) != 0) return Error::at(dir, "cannot write here");
  return {};
}

int usage(const char* message) {
  std::fprintf(stderr, "%s: error: %s\nRun with --help for usage.\n", kTool, message);
  return 2;
}

constexpr const char* kHelp =
    "usage: puff_gpubench --scenes DIR [--csv FILE] [--reps N] [--warm-up N] [--samples LIST] [--counts LIST]\n"
    "                     [--sizes LIST] [--groups LIST] [--shader-dir DIR] [--max-frame-s S] [--quick]\n"
    "What Puff's frames cost on this machine's GL (PUFF_GL: egl, the only backend it has), each beside its\n"
    "fill-rate floor: nailboards, the full frame with the map's and the volumes' shadows (1k, 10k, 50k puffs\n"
    "at 512^2 and 1024^2), cloud-50k at 1920x1080, dust-roll's hull against its blend, explosion-walls'\n"
    "media at each layer resolution against the frame without media; MSAA samples 1 and 4.\n"
    "  --scenes DIR    the cooked scenes cloud-50k.json, dust-roll.json, explosion-walls.json (puff_cook_scene)\n"
    "  --csv FILE      write the CSV here (atomically); default stdout\n"
    "  --reps N        timed rounds per case, the median kept (default 5)\n"
    "  --warm-up N     untimed rounds first (default 2)\n"
    "  --samples LIST  MSAA samples, comma-separated, each 1, 2, 4 or 8 (default 1,4)\n"
    "  --counts LIST   the nailboard cases' puff counts, each in [1, 50000] (default 1000,10000,50000)\n"
    "  --sizes LIST    the nailboard cases' frame sides in pixels, each in [16, 4096] (default 512,1024)\n"
    "  --groups LIST   run only these groups: nailboards, full-map, full-volumes, cloud-50k, tumble,\n"
    "                  tumble-split, media\n"
    "  --shader-dir DIR read the shaders from DIR instead of the built-in copies (a variant's cost)\n"
    "  --max-frame-s S a case whose first frame takes longer than S seconds is timed by that round alone\n"
    "                  (default: no limit; llvmpipe's report run uses it)\n"
    "  --quick         one small case per group, one warm-up and one timed round: shows the binary runs here\n"
    "Not a test: nothing fails on a time. tests/bench/gpu.sh packs and runs it (docs/bench/gpu.md).\n";

// Parses argv into `o`; returns the exit code when the run ends here (help, bad usage), else -1.
int parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    auto count = [&](int& out, int min) {
      const char* v = value();
      char* end = nullptr;
      const long n = v ? std::strtol(v, &end, 10) : 0;
      if (!v || *end != '\0' || n < min || n > 1000) return false;
      out = static_cast<int>(n);
      return true;
    };
    // A comma-separated list of whole numbers in [min, max] into `out`.
    auto list = [&](std::vector<int>& out, long min, long max) {
      const char* v = value();
      out.clear();
      for (const char* p = v; p && *p;) {
        char* end = nullptr;
        const long n = std::strtol(p, &end, 10);
        if (end == p || *p == ' ' || n < min || n > max || (*end != ',' && *end != '\0')) return false;
        out.push_back(static_cast<int>(n));
        if (*end == ',' && end[1] == '\0') return false;  // "1," names nothing after the comma
        p = *end == ',' ? end + 1 : end;
      }
      return !out.empty();
    };
    if (a == "--help" || a == "-h") {
      std::fputs(kHelp, stdout);
      return 0;
    } else if (a == "--scenes") {
      const char* v = value();
      if (!v) return usage("--scenes needs a directory");
      o.scenes = v;
    } else if (a == "--csv") {
      const char* v = value();
      if (!v) return usage("--csv needs a file");
      o.csv = v;
    } else if (a == "--reps") {
      if (!count(o.reps, 1)) return usage("--reps needs a whole number in [1, 1000]");
    } else if (a == "--warm-up") {
      if (!count(o.warmUp, 0)) return usage("--warm-up needs a whole number in [0, 1000]");
    } else if (a == "--samples") {
      if (!list(o.samples, 1, 8) || std::any_of(o.samples.begin(), o.samples.end(), [](int n) { return n & (n - 1); }))
        return usage("--samples takes 1, 2, 4 or 8, comma-separated");
    } else if (a == "--counts") {
      if (!list(o.counts, 1, 50000)) return usage("--counts takes puff counts in [1, 50000], comma-separated");
    } else if (a == "--sizes") {
      if (!list(o.sizes, 16, 4096)) return usage("--sizes takes frame sides in [16, 4096], comma-separated");
    } else if (a == "--max-frame-s") {
      const char* v = value();
      char* end = nullptr;
      const double x = v ? std::strtod(v, &end) : 0.0;
      if (!v || *end != '\0' || !(x > 0.0)) return usage("--max-frame-s needs a number of seconds > 0");
      o.maxFrameS = x;
    } else if (a == "--groups") {
      const char* v = value();
      if (!v) return usage("--groups needs a comma-separated list");
      std::string names = v;
      for (std::size_t at = 0; at <= names.size();) {
        const std::size_t end = std::min(names.find(',', at), names.size());
        o.groups.push_back(names.substr(at, end - at));
        at = end + 1;
      }
    } else if (a == "--shader-dir") {
      const char* v = value();
      if (!v) return usage("--shader-dir needs a directory");
      o.shaderDir = v;
    } else if (a == "--quick") {
      o.quick = true;
    } else {
      return usage(("unknown argument \"" + a + "\"").c_str());
    }
  }
  if (o.scenes.empty()) return usage("--scenes DIR is required");
  for (const std::string& g : o.groups) {
    static const char* const known[] = {"nailboards", "full-map",     "full-volumes", "cloud-50k",
                                        "tumble",     "tumble-split", "media"};
    if (std::find_if(std::begin(known), std::end(known), [&](const char* k) { return g == k; }) == std::end(known))
      return usage(("--groups: no group \"" + g +
                    "\" (nailboards, full-map, full-volumes, cloud-50k, tumble, tumble-split, media)")
                       .c_str());
  }
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (const int code = parse(argc, argv, o); code >= 0) return code;
  core::GlContextOptions contextOptions;
  contextOptions.backend = "egl";
  auto context = core::createGlContext(contextOptions);
  if (!context) {
    std::fprintf(stderr, "%s: error: no GL 4.5 context through EGL: %s\n", kTool, context.error().message.c_str());
    return 1;
  }
  const std::string gpuName = rendererName();
  std::fprintf(stderr, "%s: %s\n", kTool, gpuName.c_str());
  GLint maxSamples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  for (int n : o.samples) {
    if (n > maxSamples) {
      std::fprintf(stderr, "%s: error: --samples %d: this GL draws at most %d samples a pixel\n", kTool, n, maxSamples);
      return 1;
    }
  }
  // The CSV is written after every case (so a run cut short keeps what it measured): a place it
  // cannot be written is found before anything is timed.
  if (auto writable = csvWritable(o.csv); !writable) {
    std::fprintf(stderr, "%s: error: --csv %s\n", kTool, writable.error().message.c_str());
    return 1;
  }
  if (!o.shaderDir.empty()) core::setShaderDir(o.shaderDir);
  std::vector<Case> cases = plan(o);
  if (!o.groups.empty()) {
    std::erase_if(
        cases, [&](const Case& c) { return std::find(o.groups.begin(), o.groups.end(), c.group) == o.groups.end(); });
  }
  std::string csv = kHeader;
  const auto t0 = Clock::now();
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const Case* baseline = nullptr;
    for (const Case& b : cases) {
      if (!c.baseline.empty() && b.name == c.baseline && b.samples == c.samples) baseline = &b;
    }
    std::optional<Case> everyLayer;
    if (c.baselineEveryLayer) {
      everyLayer = c;
      everyLayer->name = c.baseline;
      everyLayer->everyLayer = true;
      everyLayer->baseline.clear();
      everyLayer->baselineEveryLayer = false;
      baseline = &*everyLayer;
    }
    auto m = measure(o, c, baseline);
    if (!m) {
      std::fprintf(stderr, "%s: error: %s\n", kTool, m.error().message.c_str());
      return 1;
    }
    appendRow(csv, c, *m, gpuName);
    if (!o.csv.empty() && !bench::writeCsv(kTool, o.csv, csv)) return 1;
    std::fprintf(stderr, "[%zu/%zu %.0f s] %-26s %dx%d s%d: gpu %.3f ms (%sx floor), wall %.3f ms (%sx floor)\n", i + 1,
                 cases.size(), msSince(t0) / 1000.0, c.name.c_str(), c.width, c.height, c.samples, m->at.gpuMs,
                 ratio(m->at.gpuMs, m->floor.gpuMs).c_str(), m->at.wallMs,
                 ratio(m->at.wallMs, m->floor.wallMs).c_str());
  }
  return o.csv.empty() ? (bench::writeCsv(kTool, o.csv, csv) ? 0 : 1) : 0;
}
