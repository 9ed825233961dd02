// Spherical billboards benchmark: Umenhoffer et al. 2006's two measurements redone on
// media::Renderer + media::Layers, in one process and one GL 4.5 context.
//
//  table1  (the paper's Table 1) spherical billboards against the paper's classic textured
//          billboards (planar-textured: a baked falloff texture, hardware-style depth test) and
//          against Puff's planar method (the spherical shader with the chord unclipped and a depth
//          test) at 0, 263, 526, 1052 and 1578 particles, media layer at half resolution, 512 x 512
//          output. As in the paper, the billboards shrink as the count grows (radius r ~ 1 /
//          sqrt(N), chosen so that the summed projected disc area is kOverdraw screens at every
//          count), so the fragment work stays about constant. 0 particles: compose only.
//          Each method also runs as its own fill-rate floor (media::Renderer::setFillRateFloor:
//          its quads, depth test, depth clamp and blending, the fragment stage writing a
//          constant), with the same heat-shimmer setting; the six cases alternate frame by frame.
//          A method whose pass is faster than its floor's is marked invalid (valid 0, no ratio).
//  fig12   (the paper's Fig. 12) the spherical method with 1052 particles at layer scales 1, 1/2,
//          1/4 and 1/8 of a 1024 x 1024 output; the four scales alternate frame by frame.
//
// A frame, each part ended by glFinish() and timed with std::chrono::steady_clock:
//   downsample  Layers::resolveOpaque: the opaque colour + depth resolve and the nearest-depth
//               downsample to the layer's resolution
//   pass        Layers::beginMedia (clears the layer) + Renderer::draw: the back-to-front sort
//               (sort_ms, from DrawStats), the particle upload and the particle draw
//   compose     Layers::compose into an RGBA8 target of the output size (depth-aware upsampling,
//               heat shimmer on)
// Table 1's frame is pass + compose (frame_ms); Fig. 12's is downsample + pass + compose (total_ms).
// 2 warm-up rounds, then the median of --reps rounds (default 5), each column's median taken over
// its own per-frame values. The opaque pass is not timed: its framebuffer is filled once per
// layer set by scissored clears, row by row (a floor and a wall, both cutting through the
// particle ball, sky above), which gives every row its exact linear depth.
//
// Particles: an explosion-like ball from a splitmix64 PRNG with a fixed seed, in the paper's
// proportions (16 dust, 135 fire, 112 smoke of 263): fire in a ball of radius 1.2, smoke and dust
// in a ball of radius 2, centred 8 units in front of the camera (45 degree vertical field of view).
// Overdraw (summed area / screen area) is measured on the CPU two ways: overdraw_disc, of the
// discs of radius f r / d (f = 1 / tan(fovY / 2), d the centre's view-axis distance; the overdraw
// the radii are chosen by), and overdraw_quad, of the quads the vertex shader emits for them (clipped to the
// screen: the pixels the rasterizer shades; each method's own quads: planar's bound at the centre, the
// silhouette's box for spherical, f r / d for planar-textured).
//  sort    media::backToFront alone (CPU, one thread) for 1578, 10k and 50k particles: sort_ms.
//
// Error (the two measurements with the error added): for every table1 and fig12 case, one
// more frame (heat shimmer off, untimed) read back and compared with the exact reference
// (puff::reference::renderMediaReference over the same resolved opaque layer, same particles,
// materials and detail video, clamped to [0, 1] as the 8-bit target is): RMSE in linear colour,
// rmse_vs_reference. --no-error skips it (the references take a few minutes on 2 cores).
//
// Writes CSV (stdout, or --csv FILE written atomically) and prints tables on stderr.
// Not a test: nothing here fails on a time.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/vec4.hpp>

#include <puff/core/detail_video.h>
#include <puff/core/gl.h>
#include <puff/core/image.h>
#include <puff/gl_api.h>
#include <puff/io/openimageio.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>
#include <puff/platform/gl_context.h>
#include <puff/reference/media_reference.h>
#include <puff/reference/metrics.h>

#include "bench_usage.h"
#include "harness.h"

namespace {

namespace fs = std::filesystem;
using namespace puff;
using bench::Clock;
using bench::msBetween;
using bench::splitmix64;
using bench::uniform;

constexpr float kFovYDegrees = 45.0f;
constexpr float kCameraZ = 8.0f;  // camera at (0, 0, kCameraZ) looking at the ball's centre, the origin
constexpr float kNearPlane = 0.5f, kFarPlane = 30.0f;
constexpr float kBallRadius = 2.0f, kFireRadius = 1.2f;
constexpr float kOverdraw = 4.0f;  // summed projected disc area / screen area, at every count
// The opaque scene: a floor at y = kFloorY and a wall facing the camera at z = kWallZ, from the
// floor up to y = kWallTop; both cut through the particle ball.
constexpr float kFloorY = -1.6f, kWallZ = -0.6f, kWallTop = 2.8f;
constexpr std::uint64_t kSeed = 0x5eedc0ffee15bad5ull;
constexpr int kWarmUp = 2;
constexpr int kTableSize = 512, kFigSize = 1024, kFigParticles = 1052;
constexpr int kTableCounts[] = {0, 263, 526, 1052, 1578};
constexpr float kFigScales[] = {1.0f, 0.5f, 0.25f, 0.125f};
constexpr float kShimmerPixels = 3.0f;

float focal() { return 1.0f / std::tan(0.5f * kFovYDegrees * 3.14159265358979f / 180.0f); }

// Materials: 0 smoke, 1 dust, 2 fire (the renderer's table below).
std::vector<media::Particle> makeParticles(int count) {
  std::uint64_t state = kSeed;
  std::vector<media::Particle> ps(static_cast<std::size_t>(count));
  for (media::Particle& p : ps) {
    const float u = uniform(state, 0.0f, 263.0f);  // 16 dust, 135 fire, 112 smoke of 263
    p.material = u < 16.0f ? 1u : u < 151.0f ? 2u : 0u;
    const float ball = p.material == 2u ? kFireRadius : kBallRadius;
    glm::vec3 q;
    do {
      const float z = uniform(state, -1, 1), y = uniform(state, -1, 1), x = uniform(state, -1, 1);  // z first
      q = glm::vec3(x, y, z);
    } while (glm::dot(q, q) > 1.0f);
    p.position = q * ball;
    p.life = uniform(state, 0.0f, 1.0f);
    p.density = 1.0f;
    p.seed = static_cast<std::uint32_t>(splitmix64(state) >> 32);
  }
  return ps;
}

// Sets every radius to the one that makes the summed projected disc area kOverdraw screens.
float setRadius(std::vector<media::Particle>& ps) {
  if (ps.empty()) return 0.0f;
  const double f = focal();
  double unit = 0;  // screens covered at radius 1: pi (f / d)^2 / 4 each (NDC screen area 4)
  for (const media::Particle& p : ps) {
    const double d = kCameraZ - p.position.z;
    unit += 3.14159265358979 * f * f / (d * d) / 4.0;
  }
  const float r = static_cast<float>(std::sqrt(kOverdraw / unit));
  for (media::Particle& p : ps) p.radius = r;
  return r;
}

struct Overdraw {
  double disc = 0, quad = 0;
  double texturedQuad = 0;   ///< planar-textured's quads (half side f r / d), clipped to the screen
  double sphericalQuad = 0;  ///< spherical's quads (the silhouette's box), clipped to the screen
  int discsCrossingEdge = 0;
};

// Summed disc area (unclipped) and summed quad area (clipped to the screen), per screen area.
// `layerPx`: the media layer's side in pixels (the spherical quad's margin is an eighth of one).
Overdraw measureOverdraw(const std::vector<media::Particle>& ps, int layerPx) {
  const double f = focal();
  Overdraw o;
  for (const media::Particle& p : ps) {
    const double d = kCameraZ - p.position.z, r = p.radius;
    const double cx = p.position.x * f / d, cy = p.position.y * f / d, rd = r * f / d;  // NDC
    o.disc += 3.14159265358979 * rd * rd / 4.0;
    if (std::abs(cx) + rd > 1.0 || std::abs(cy) + rd > 1.0) ++o.discsCrossingEdge;
    // billboard.vert (planar or spherical: the same projected size): half side f r / (d - r) (1 + |c.xy| / d).
    const double h = f * r / (d - r) * (1.0 + std::hypot(p.position.x, p.position.y) / d);
    const double w = std::max(0.0, std::min(1.0, cx + h) - std::max(-1.0, cx - h));
    const double hgt = std::max(0.0, std::min(1.0, cy + h) - std::max(-1.0, cy - h));
    o.quad += w * hgt / 4.0;
    // billboard_textured.vert: half side r in the centre's plane, f r / d in NDC.
    const double wt = std::max(0.0, std::min(1.0, cx + rd) - std::max(-1.0, cx - rd));
    const double ht = std::max(0.0, std::min(1.0, cy + rd) - std::max(-1.0, cy - rd));
    o.texturedQuad += wt * ht / 4.0;
    // billboard.vert, spherical: the box between the tangent lines from the eye, f (x / dz) at their
    // slopes, an eighth of a layer pixel (0.25 / layerPx in NDC) wider on each side.
    const auto extent = [&](double c, double& lo, double& hi) {
      const double t = std::sqrt(c * c + d * d - r * r), m = 0.25 / layerPx;
      lo = f * (c * t - r * d) / (d * t + r * c) - m;
      hi = f * (c * t + r * d) / (d * t - r * c) + m;
    };
    double x0, x1, y0, y1;
    extent(p.position.x, x0, x1);
    extent(p.position.y, y0, y1);
    o.sphericalQuad += std::max(0.0, std::min(1.0, x1) - std::max(-1.0, x0)) *
                       std::max(0.0, std::min(1.0, y1) - std::max(-1.0, y0)) / 4.0;
  }
  return o;
}

// A looping greyscale detail video of value noise (fixed seed), for both the fire's temperature
// and the smoke's opacity perturbation, so the shader reads a real 3D texture as in the paper.
core::DetailVideo makeDetail() {
  core::DetailVideo v;
  v.width = v.height = 64;
  v.frames = 16;
  v.values.resize(static_cast<std::size_t>(v.width) * v.height * v.frames);
  std::uint64_t state = kSeed ^ 0xde7a11ull;
  for (float& x : v.values) x = uniform(state, 0.0f, 1.0f);
  v.source = "puff_bench_media: uniform value noise";
  return v;
}

// Fills the opaque framebuffer: each row's colour and linear depth by a scissored clear.
void fillOpaque(const media::Layers& layers) {
  const GLuint fbo = layers.opaqueFramebuffer();
  const int w = layers.width(), h = layers.height();
  const float t = 1.0f / focal();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glEnable(GL_SCISSOR_TEST);
  for (int y = 0; y < h; ++y) {
    const float ny = (static_cast<float>(y) + 0.5f) / static_cast<float>(h) * 2.0f - 1.0f;
    float distance = 0.0f;  // along the view axis; 0: sky
    glm::vec4 color(0.45f, 0.62f, 0.85f, 1.0f);
    const float wallDistance = kCameraZ - kWallZ, wallY = ny * t * wallDistance;
    if (ny < 0.0f && -kFloorY / (-ny * t) < wallDistance) {
      distance = -kFloorY / (-ny * t);
      color = glm::vec4(0.35f, 0.33f, 0.3f, 1.0f);
    } else if (wallY >= kFloorY && wallY <= kWallTop) {
      distance = wallDistance;
      color = glm::vec4(0.55f, 0.3f, 0.22f, 1.0f);
    }
    const float linear =
        distance > 0.0f ? std::clamp((distance - kNearPlane) / (kFarPlane - kNearPlane), 0.0f, 1.0f) : 1.0f;
    glScissor(0, y, w, 1);
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &color.x);
    glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, linear, 0);
  }
  glDisable(GL_SCISSOR_TEST);
}

// The compose target: an RGBA8 texture of the output size.
struct Output {
  core::Framebuffer fbo = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
  int size;
  explicit Output(int s) : size(s) {
    glTextureStorage2D(color.get(), 1, GL_RGBA8, s, s);
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  }
  core::Image image() const {
    std::vector<float> px(static_cast<std::size_t>(size) * size * 4);
    glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
    core::Image im(size, size, 3);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x)
        for (int c = 0; c < 3; ++c) im.at(x, size - 1 - y, c) = px[(static_cast<std::size_t>(y) * size + x) * 4 + c];
    return im;
  }
};

media::Frame makeFrame(const media::Layers& layers) {
  media::Frame f;
  f.view = glm::lookAt(glm::vec3(0.0f, 0.0f, kCameraZ), glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  f.projection = glm::perspective(glm::radians(kFovYDegrees), 1.0f, kNearPlane, kFarPlane);
  f.nearPlane = kNearPlane;
  f.farPlane = kFarPlane;
  f.light.direction = glm::vec3(0.4f, 1.0f, 0.3f);
  f.light.color = glm::vec3(0.8f);
  f.ambient = glm::vec3(0.25f);
  f.time = 0.5f;
  f.viewport.width = layers.mediaWidth();
  f.viewport.height = layers.mediaHeight();
  return f;
}

struct FrameTime {
  double downsample = 0, sort = 0, pass = 0, compose = 0;
};

// One case: a layer set, its output and its particles, drawn with one method.
struct Case {
  std::unique_ptr<media::Layers> layers;
  std::unique_ptr<Output> output;
  const std::vector<media::Particle>* particles = nullptr;
  media::Method method = media::Method::kSpherical;
  std::vector<FrameTime> times;
  bool floor = false;  ///< draw as the method's fill-rate floor
};

FrameTime drawFrame(media::Renderer& renderer, Case& c, bool shimmer = true) {
  media::Layers& layers = *c.layers;
  const media::Frame f = makeFrame(layers);
  FrameTime t;
  const auto t0 = Clock::now();
  layers.resolveOpaque();
  glFinish();
  const auto t1 = Clock::now();
  layers.beginMedia();
  media::DrawStats stats;
  renderer.setFillRateFloor(c.floor);
  renderer.draw(f, *c.particles, c.method, layers.mediaDepth(),
                shimmer ? media::Shimmer::kWritten : media::Shimmer::kOff, &stats);
  renderer.setFillRateFloor(false);
  glFinish();
  const auto t2 = Clock::now();
  const core::Viewport vp{0, 0, layers.width(), layers.height()};
  media::ComposeSettings cs;
  cs.shimmerPixels = shimmer ? kShimmerPixels : 0.0f;
  layers.compose(c.output->fbo.get(), vp, f, {}, cs);
  glFinish();
  const auto t3 = Clock::now();
  t.downsample = msBetween(t0, t1);
  t.sort = stats.sortMs;
  t.pass = msBetween(t1, t2);
  t.compose = msBetween(t2, t3);
  return t;
}

// Warm-up rounds, then timed rounds; each round draws every case once, in order.
void runRounds(media::Renderer& renderer, std::vector<Case*> cases, int reps) {
  for (int w = 0; w < kWarmUp; ++w)
    for (Case* c : cases) drawFrame(renderer, *c);
  for (int r = 0; r < reps; ++r)
    for (Case* c : cases) c->times.push_back(drawFrame(renderer, *c));
}

void checkGl(const char* what) {
  if (const std::string e = core::drainGlErrors(); !e.empty()) {
    std::fprintf(stderr, "puff_bench_media: error: GL error in %s: %s\n", what, e.c_str());
    std::exit(1);
  }
}

struct Row {
  std::string experiment, method;
  int particles = 0, outputPx = 0, layerPx = 0;
  float scale = 1.0f, radius = 0.0f;
  Overdraw overdraw;
  int reps = 0;
  double downsample = 0, sort = 0, pass = 0, compose = 0, frame = 0, total = 0;
  // table1: this / planar (or planar-textured) of the same count; fig12: scale 1 / this. 0: not
  // applicable.
  double frameRatioToPlanar = 0, passRatioToPlanar = 0, passSpeedup = 0, totalSpeedup = 0;
  double frameRatioToTextured = 0, passRatioToTextured = 0;
  double floorPass = 0;  ///< table1: the pass of this method's fill-rate floor; 0: not measured
  double rmse = 0;       ///< against the exact reference; 0: not measured
  bool valid() const { return bench::validAgainstFloor(pass, floorPass); }
};

// What the reference needs besides the case: the renderer's materials, settings and detail video.
struct ReferenceSetup {
  std::vector<media::Material> materials;
  const core::DetailVideo* detail = nullptr;
};

// The exact image of a case's particles over its resolved opaque layer (the last frame drawn),
// clamped to [0, 1]: row 0 at the top.
core::Image referenceImage(const Case& c, const ReferenceSetup& setup) {
  const media::Layers& layers = *c.layers;
  const int w = layers.width(), h = layers.height();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::vector<glm::vec3> color(n);
  std::vector<float> depth(n);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(layers.opaqueColor(), 0, GL_RGB, GL_FLOAT, static_cast<GLsizei>(n * sizeof(glm::vec3)),
                    color.data());
  glGetTextureImage(layers.opaqueDepth(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(n * sizeof(float)), depth.data());
  reference::MediaReferenceInput in;
  in.frame = makeFrame(layers);
  in.frame.viewport.width = w;
  in.frame.viewport.height = h;
  in.particles = *c.particles;
  in.materials = setup.materials;
  in.temperatureDetail = setup.detail;
  in.opacityDetail = setup.detail;
  in.opaqueColor = color;
  in.opaqueDepth = depth;
  auto image = reference::renderMediaReference(in);
  if (!image) {
    std::fprintf(stderr, "puff_bench_media: error: the reference: %s\n", image.error().message.c_str());
    std::exit(1);
  }
  for (float& v : image->pixels) v = std::clamp(v, 0.0f, 1.0f);
  return std::move(*image);
}

// One more frame of the case, shimmer off, against `reference`.
double errorAgainst(media::Renderer& renderer, Case& c, const core::Image& reference) {
  drawFrame(renderer, c, false);
  return reference::imageError(c.output->image(), reference).rmse;
}

Row summarize(const std::string& experiment, const Case& c, const std::string& method, float radius,
              const Overdraw& o) {
  Row r;
  r.experiment = experiment;
  r.method = method;
  r.particles = static_cast<int>(c.particles->size());
  r.outputPx = c.layers->width();
  r.layerPx = c.layers->mediaWidth();
  r.scale = c.layers->scale();
  r.radius = radius;
  r.overdraw = o;
  r.reps = static_cast<int>(c.times.size());
  std::vector<double> ds, so, pa, co, fr, to;
  for (const FrameTime& t : c.times) {
    ds.push_back(t.downsample);
    so.push_back(t.sort);
    pa.push_back(t.pass);
    co.push_back(t.compose);
    fr.push_back(t.pass + t.compose);
    to.push_back(t.downsample + t.pass + t.compose);
  }
  r.downsample = bench::median(ds);
  r.sort = bench::median(so);
  r.pass = bench::median(pa);
  r.compose = bench::median(co);
  r.frame = bench::median(fr);
  r.total = bench::median(to);
  return r;
}

std::string fmt(double v, const char* f = "%.3f") {
  if (v == 0.0) return {};
  char b[32];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  puff::io::useOpenImageIO();
  int reps = 5;
  std::string csvPath, dumpDir;
  bool runTable = true, runFig = true, withError = true;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
      reps = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc)
      csvPath = argv[++i];
    else if (!std::strcmp(argv[i], "--dump") && i + 1 < argc)
      dumpDir = argv[++i];
    else if (!std::strcmp(argv[i], "--no-table1"))
      runTable = false;
    else if (!std::strcmp(argv[i], "--no-error"))
      withError = false;
    else if (!std::strcmp(argv[i], "--no-fig12"))
      runFig = false;
    else {
      std::fprintf(puff::bench::usageStream(argv[i]),
                   "usage: puff_bench_media [--reps N (5)] [--csv FILE] [--dump DIR] [--no-table1] [--no-fig12] "
                   "[--no-error]\n");
      return puff::bench::usageExit(argv[i]);
    }
  }

  auto context = core::createGlContext({});
  if (!context) {
    std::fprintf(stderr, "puff_bench_media: error: %s\n", context.error().message.c_str());
    return 1;
  }
  std::fprintf(stderr, "puff_bench_media: %s\n", (*context)->describe().c_str());

  auto created = media::Renderer::create();
  if (!created) {
    std::fprintf(stderr, "puff_bench_media: error: %s\n", created.error().message.c_str());
    return 1;
  }
  std::unique_ptr<media::Renderer> renderer = std::move(*created);
  media::Material fire = media::fireMaterial();
  fire.becomes = -1;
  if (auto r = renderer->setMaterials({media::smokeMaterial(), media::dustMaterial(), fire}); !r) {
    std::fprintf(stderr, "puff_bench_media: error: %s\n", r.error().message.c_str());
    return 1;
  }
  const core::DetailVideo detail = makeDetail();
  renderer->setDetail(&detail, &detail);
  const ReferenceSetup setup{{media::smokeMaterial(), media::dustMaterial(), fire}, &detail};

  auto makeLayers = [](int size, float scale) {
    auto l = media::Layers::create(size, size, 1, scale);
    if (!l) {
      std::fprintf(stderr, "puff_bench_media: error: %s\n", l.error().message.c_str());
      std::exit(1);
    }
    fillOpaque(**l);
    return std::move(*l);
  };
  auto dump = [&](Case& c, const std::string& name) {
    if (dumpDir.empty()) return;
    drawFrame(*renderer, c);
    std::error_code ec;
    fs::create_directories(dumpDir, ec);
    if (auto r = core::writeImage(fs::path(dumpDir) / (name + ".png"), c.output->image(), core::PixelType::kUInt8); !r)
      std::fprintf(stderr, "puff_bench_media: %s\n", r.error().message.c_str());
  };

  std::vector<Row> rows;
  const auto runStart = Clock::now();

  if (runTable) {
    for (int count : kTableCounts) {
      std::vector<media::Particle> ps = makeParticles(count);
      const float radius = setRadius(ps);
      const Overdraw o = measureOverdraw(ps, kTableSize / 2);  // the layer at half resolution
      if (o.discsCrossingEdge > 0)
        std::fprintf(stderr, "puff_bench_media: note: %d discs cross the screen edge\n", o.discsCrossingEdge);
      auto makeCase = [&](media::Method m, bool floor) {
        return Case{makeLayers(kTableSize, 0.5f), std::make_unique<Output>(kTableSize), &ps, m, {}, floor};
      };
      Case spherical = makeCase(media::Method::kSpherical, false);
      if (count == 0) {  // compose only: draw returns at once without particles
        runRounds(*renderer, {&spherical}, reps);
        checkGl("table1, 0 particles");
        rows.push_back(summarize("table1", spherical, "none", 0.0f, o));
        dump(spherical, "table1_0");
      } else {
        Case planar = makeCase(media::Method::kPlanar, false);
        Case textured = makeCase(media::Method::kPlanarTextured, false);
        Case sphericalFloor = makeCase(media::Method::kSpherical, true);
        Case planarFloor = makeCase(media::Method::kPlanar, true);
        Case texturedFloor = makeCase(media::Method::kPlanarTextured, true);
        runRounds(*renderer, {&spherical, &planar, &textured, &sphericalFloor, &planarFloor, &texturedFloor}, reps);
        checkGl("table1");
        Overdraw ot = o, os = o;
        ot.quad = o.texturedQuad;
        os.quad = o.sphericalQuad;
        Row s = summarize("table1", spherical, "spherical", radius, os);
        Row p = summarize("table1", planar, "planar", radius, o);
        Row t = summarize("table1", textured, "planar-textured", radius, ot);
        s.floorPass = summarize("table1", sphericalFloor, "", radius, o).pass;
        p.floorPass = summarize("table1", planarFloor, "", radius, o).pass;
        t.floorPass = summarize("table1", texturedFloor, "", radius, ot).pass;
        if (withError) {  // one reference for all: the same particles over the same opaque layer
          const core::Image ref = referenceImage(spherical, setup);
          s.rmse = errorAgainst(*renderer, spherical, ref);
          p.rmse = errorAgainst(*renderer, planar, ref);
          t.rmse = errorAgainst(*renderer, textured, ref);
        }
        for (Row* r : {&p, &t, &s}) {
          r->frameRatioToPlanar = r->frame / p.frame;
          r->passRatioToPlanar = r->pass / p.pass;
          r->frameRatioToTextured = r->frame / t.frame;
          r->passRatioToTextured = r->pass / t.pass;
        }
        rows.push_back(p);
        rows.push_back(t);
        rows.push_back(s);
        dump(planar, "table1_" + std::to_string(count) + "_planar");
        dump(textured, "table1_" + std::to_string(count) + "_planar_textured");
        dump(spherical, "table1_" + std::to_string(count) + "_spherical");
      }
      const Row& last = rows.back();
      std::fprintf(stderr,
                   "puff_bench_media: table1 %4d particles r %.3f overdraw %.2f (quads: planar %.2f, spherical %.2f, "
                   "textured %.2f): frame %.2f ms%s (%.0f s so far)\n",
                   count, radius, o.disc, o.quad, o.sphericalQuad, o.texturedQuad, last.frame,
                   count ? (", spherical/planar " + fmt(last.frameRatioToPlanar) + ", spherical/planar-textured " +
                            fmt(last.frameRatioToTextured))
                               .c_str()
                         : "",
                   msBetween(runStart, Clock::now()) / 1000.0);
    }
  }

  if (runFig) {
    std::vector<media::Particle> ps = makeParticles(kFigParticles);
    const float radius = setRadius(ps);
    const Overdraw o = measureOverdraw(ps, kFigSize);  // the margin of the finest layer
    std::vector<Case> cases;
    for (float s : kFigScales)
      cases.push_back(
          Case{makeLayers(kFigSize, s), std::make_unique<Output>(kFigSize), &ps, media::Method::kSpherical, {}});
    std::vector<Case*> all;
    for (Case& c : cases) all.push_back(&c);
    runRounds(*renderer, all, reps);
    checkGl("fig12");
    const std::size_t first = rows.size();
    std::optional<core::Image> ref;
    if (withError) ref = referenceImage(cases.front(), setup);  // the full-size opaque layer: every scale's
    for (Case& c : cases) {
      Row r = summarize("fig12", c, "spherical", radius, o);
      if (ref) r.rmse = errorAgainst(*renderer, c, *ref);
      r.passSpeedup = rows.size() > first ? rows[first].pass / r.pass : 1.0;
      r.totalSpeedup = rows.size() > first ? rows[first].total / r.total : 1.0;
      rows.push_back(r);
      std::fprintf(stderr, "puff_bench_media: fig12 layer %4d^2: pass %.2f ms (x%.2f), total %.2f ms (x%.2f)\n",
                   r.layerPx, r.pass, r.passSpeedup, r.total, r.totalSpeedup);
      dump(c, "fig12_" + std::to_string(r.layerPx));
    }
  }
  // Sorting back to front (it must be fast enough for 50k): media::backToFront alone on the CPU, one
  // thread, for the paper's counts and 50k, from a camera looking at the ball.
  for (int count : {1578, 10000, 50000}) {
    const std::vector<media::Particle> ps = makeParticles(count);
    const glm::mat4 view = glm::lookAt(glm::vec3(3, 2, 0), glm::vec3(0, 0, -8), glm::vec3(0, 1, 0));
    std::vector<double> times;
    for (int i = 0; i < reps + 2; ++i) {
      const auto t0 = Clock::now();
      const std::vector<std::uint32_t> order = media::backToFront(view, ps);
      const double ms = msBetween(t0, Clock::now());
      if (order.size() != ps.size()) return 1;
      if (i >= 2) times.push_back(ms);
    }
    Row r;
    r.experiment = "sort";
    r.method = "radix";
    r.particles = count;
    r.reps = reps;
    r.sort = bench::median(times);
    rows.push_back(r);
    std::fprintf(stderr, "puff_bench_media: sort %d particles back to front: %.3f ms\n", count, r.sort);
  }
  const double runS = msBetween(runStart, Clock::now()) / 1000.0;

  std::string csv =
      "experiment,method,particles,output_px,layer_scale,layer_px,radius,overdraw_disc,overdraw_quad,reps,"
      "downsample_ms,sort_ms,pass_ms,compose_ms,frame_ms,total_ms,frame_ratio_to_planar,pass_ratio_to_planar,"
      "pass_speedup_over_scale1,total_speedup_over_scale1,rmse_vs_reference,frame_ratio_to_planar_textured,"
      "pass_ratio_to_planar_textured,floor_pass_ms,pass_ratio_to_floor,valid\n";
  for (const Row& r : rows) {
    const bool floored = r.floorPass > 0.0;
    bench::appendf(csv,
                   "%s,%s,%d,%d,%g,%d,%.4f,%.2f,%.2f,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s\n",
                   r.experiment.c_str(), r.method.c_str(), r.particles, r.outputPx, r.scale, r.layerPx, r.radius,
                   r.overdraw.disc, r.overdraw.quad, r.reps, r.downsample, r.sort, r.pass, r.compose, r.frame, r.total,
                   fmt(r.frameRatioToPlanar).c_str(), fmt(r.passRatioToPlanar).c_str(), fmt(r.passSpeedup).c_str(),
                   fmt(r.totalSpeedup).c_str(), fmt(r.rmse, "%.5f").c_str(), fmt(r.frameRatioToTextured).c_str(),
                   fmt(r.passRatioToTextured).c_str(), fmt(r.floorPass).c_str(),
                   bench::ratioToFloor(r.pass, r.floorPass).c_str(), floored ? (r.valid() ? "1" : "0") : "");
  }
  if (!bench::writeCsv("puff_bench_media", csvPath, csv)) return 1;

  std::fprintf(stderr, "\nTable 1 (%d^2 output, layer at 1/2; median ms of %d frames; x: spherical / the method)\n",
               kTableSize, reps);
  std::fprintf(stderr, "%9s %7s %8s %-16s %9s %9s %8s %9s %10s %9s %9s\n", "particles", "radius", "overdraw", "method",
               "frame", "pass", "sph. x", "floor", "x floor", "compose", "RMSE");
  for (const Row& r : rows) {
    if (r.experiment != "table1") continue;
    const Row* sph = nullptr;
    for (const Row& q : rows)
      if (q.experiment == "table1" && q.method == "spherical" && q.particles == r.particles) sph = &q;
    std::string xFloor = r.floorPass > 0.0 ? bench::ratioToFloor(r.pass, r.floorPass) : "-";
    if (!r.valid()) xFloor = "INVALID";
    std::fprintf(stderr, "%9d %7.3f %8.2f %-16s %9.2f %9.2f %8s %9s %10s %9.2f %9s\n", r.particles, r.radius,
                 r.overdraw.disc, r.method.c_str(), r.frame, r.pass,
                 sph && &r != sph ? fmt(sph->pass / r.pass).c_str() : "-",
                 r.floorPass > 0.0 ? fmt(r.floorPass, "%.2f").c_str() : "-", xFloor.c_str(), r.compose,
                 fmt(r.rmse, "%.5f").c_str());
  }
  std::fprintf(stderr, "\nFig. 12 (%d^2 output, spherical, %d particles; median ms of %d frames)\n", kFigSize,
               kFigParticles, reps);
  std::fprintf(stderr, "%6s %8s %10s %10s %10s %10s %10s %10s %12s\n", "scale", "layer", "pass", "speedup",
               "downsample", "compose", "total", "speedup", "RMSE");
  for (const Row& r : rows) {
    if (r.experiment != "fig12") continue;
    std::fprintf(stderr, "%6g %8d %10.2f %10.2f %10.2f %10.2f %10.2f %10.2f %12s\n", r.scale, r.layerPx, r.pass,
                 r.passSpeedup, r.downsample, r.compose, r.total, r.totalSpeedup, fmt(r.rmse, "%.5f").c_str());
  }
  std::fprintf(stderr, "\npuff_bench_media: %.0f s in all\n", runS);
  return 0;
}
