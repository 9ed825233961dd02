// Detail videos: periodic gradient-noise fBm, and image-sequence import with a loop cross-fade.
//
// Determinism: integer hashing (splitmix64's finalizer), arithmetic in double, only floor from
// libm, each texel computed on its own (so threads cannot change results), and the statistics
// summed serially in a fixed order.
#include <puff/bake/detail.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>

#include <puff/core/image.h>
#include <puff/core/number_text.h>
#include <puff/core/random.h>
#include <puff/support/parallel.h>

namespace puff::bake {

namespace fs = std::filesystem;

namespace {

using core::mix64;

// Perlin's improved-noise gradients: the 12 edge midpoints of a cube.
constexpr double kGradients[12][3] = {{1, 1, 0},  {-1, 1, 0},  {1, -1, 0}, {-1, -1, 0}, {1, 0, 1},  {-1, 0, 1},
                                      {1, 0, -1}, {-1, 0, -1}, {0, 1, 1},  {0, -1, 1},  {0, 1, -1}, {0, -1, -1}};

double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
double lerp(double a, double b, double t) { return a + (b - a) * t; }
long long wrap(long long i, long long period) {
  const long long m = i % period;
  return m < 0 ? m + period : m;
}

// Gradient noise on a lattice periodic with (px, py, pt) cells, at lattice coordinates (x, y, t).
double periodicGradientNoise(std::uint64_t key, double x, double y, double t, long long px, long long py,
                             long long pt) {
  const double fx0 = std::floor(x), fy0 = std::floor(y), ft0 = std::floor(t);
  const double dx = x - fx0, dy = y - fy0, dt = t - ft0;
  const long long ix = static_cast<long long>(fx0), iy = static_cast<long long>(fy0), it = static_cast<long long>(ft0);
  double corner[8];
  for (int c = 0; c < 8; ++c) {
    const int ox = c & 1, oy = (c >> 1) & 1, ot = (c >> 2) & 1;
    std::uint64_t h = mix64(key ^ static_cast<std::uint64_t>(wrap(it + ot, pt)));
    h = mix64(h ^ static_cast<std::uint64_t>(wrap(iy + oy, py)));
    h = mix64(h ^ static_cast<std::uint64_t>(wrap(ix + ox, px)));
    const double* g = kGradients[(h >> 32) % 12];
    corner[c] = g[0] * (dx - ox) + g[1] * (dy - oy) + g[2] * (dt - ot);
  }
  const double u = fade(dx), v = fade(dy), w = fade(dt);
  const double a = lerp(lerp(corner[0], corner[1], u), lerp(corner[2], corner[3], u), v);
  const double b = lerp(lerp(corner[4], corner[5], u), lerp(corner[6], corner[7], u), v);
  return lerp(a, b, w);
}

// "[lo, hi]", appended piece by piece: GCC 12 warns falsely (-Wrestrict) on this chain of operator+.
std::string rangeText(int lo, int hi) {
  std::string s = "[";
  s += std::to_string(lo);
  s += ", ";
  s += std::to_string(hi);
  s += "]";
  return s;
}

std::string fileName(const fs::path& p) { return p.filename().string(); }

// Where each output texel of one axis reads: (source index, weight) pairs summing to 1.
using AxisWeights = std::vector<std::vector<std::pair<int, double>>>;

AxisWeights axisWeights(int from, int to) {
  AxisWeights w(static_cast<std::size_t>(to));
  if (from >= to) {
    // Box: output texel j covers [j, j + 1) * from / to source texels; weight = overlap.
    const double scale = static_cast<double>(from) / to;
    for (int j = 0; j < to; ++j) {
      const double lo = j * scale, hi = (j + 1) * scale;
      for (int i = static_cast<int>(std::floor(lo)); i < from && i < hi; ++i) {
        const double overlap = std::min(hi, i + 1.0) - std::max(lo, static_cast<double>(i));
        if (overlap > 0.0) w[static_cast<std::size_t>(j)].emplace_back(i, overlap / scale);
      }
    }
  } else {
    // Bilinear between source texel centres, edges clamped.
    for (int j = 0; j < to; ++j) {
      const double s = (j + 0.5) * from / to - 0.5;
      const double f0 = std::floor(s);
      const double f = s - f0;
      const int i0 = std::clamp(static_cast<int>(f0), 0, from - 1),
                i1 = std::clamp(static_cast<int>(f0) + 1, 0, from - 1);
      if (i0 == i1) {
        w[static_cast<std::size_t>(j)].emplace_back(i0, 1.0);
      } else {
        w[static_cast<std::size_t>(j)].emplace_back(i0, 1.0 - f);
        w[static_cast<std::size_t>(j)].emplace_back(i1, f);
      }
    }
  }
  return w;
}

// One frame's single-channel values in [0, 1], or an error naming the file.
Result<std::vector<double>> luminance(const core::Image& img, const fs::path& path) {
  const std::size_t n = static_cast<std::size_t>(img.width) * img.height;
  const std::size_t ch = static_cast<std::size_t>(img.channels);
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &img.pixels[i * ch];
    const double v = ch >= 3 ? 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] : p[0];
    if (!std::isfinite(v)) {
      const std::size_t w = static_cast<std::size_t>(img.width);
      return Error::at(path,
                       "value at pixel (" + std::to_string(i % w) + ", " + std::to_string(i / w) + ") is not finite");
    }
    out[i] = std::clamp(v, 0.0, 1.0);
  }
  return out;
}

}  // namespace

Result<void> validate(const DetailSpec& s) {
  const std::string sizes = rangeText(core::kMinDetailSize, core::kMaxDetailSize);
  if (s.size < core::kMinDetailSize || s.size > core::kMaxDetailSize)
    return Error{"--size must be in " + sizes + ", got " + std::to_string(s.size)};
  if (s.frames < 1 || s.frames > core::kMaxDetailFrames)
    return Error{"--frames must be in [1, " + std::to_string(core::kMaxDetailFrames) + "], got " +
                 std::to_string(s.frames)};
  if (static_cast<long long>(s.size) * s.size * s.frames > kMaxDetailTexels)
    return Error{"--size " + std::to_string(s.size) + " x --frames " + std::to_string(s.frames) +
                 " is too large: size * size * frames must be at most " + std::to_string(kMaxDetailTexels)};
  if (s.octaves < 1 || s.octaves > 10) return Error{"--octaves must be in [1, 10], got " + std::to_string(s.octaves)};
  if (s.frequency < 1 || s.frequency > 256)
    return Error{"--frequency must be in [1, 256], got " + std::to_string(s.frequency)};
  if (!(s.contrast >= 0.0f && s.contrast <= 16.0f))
    return Error{"--contrast must be in [0, 16], got " + core::numberText(s.contrast)};
  return {};
}

namespace {

// detailNoise without the check (generateDetailVideo validates once, not per texel).
double fbm(const DetailSpec& spec, double x, double y, double t) {
  const std::uint64_t seedKey = mix64(0x5EED0000D37A11ull ^ spec.seed);
  const long long maxTimeCells = std::max(1, spec.frames / 4);
  double sum = 0.0, amplitude = 1.0;
  for (int o = 0; o < spec.octaves; ++o) {
    const long long cells = static_cast<long long>(spec.frequency) << o;
    const long long timeCells = std::min(cells, maxTimeCells);
    const std::uint64_t key = mix64(seedKey ^ (static_cast<std::uint64_t>(o) + 1) * 0x9E3779B97F4A7C15ull);
    const double cx = static_cast<double>(cells) / spec.size, ct = static_cast<double>(timeCells) / spec.frames;
    sum += amplitude * periodicGradientNoise(key, x * cx, y * cx, t * ct, cells, cells, timeCells);
    amplitude *= 0.5;
  }
  return sum;
}

}  // namespace

double detailNoise(const DetailSpec& spec, double x, double y, double t) {
  PUFF_CHECK(validate(spec).ok());
  return fbm(spec, x, y, t);
}

Result<core::DetailVideo> generateDetailVideo(const DetailSpec& spec) {
  PUFF_TRY(validate(spec));
  core::DetailVideo v;
  v.width = v.height = spec.size;
  v.frames = spec.frames;
  const std::size_t n = static_cast<std::size_t>(spec.size) * spec.size * spec.frames;
  std::vector<double> raw(n);
  const std::size_t rows = static_cast<std::size_t>(spec.size) * spec.frames;
  core::parallelFor(
      rows,
      [&](std::size_t row) {
        const int f = static_cast<int>(row / static_cast<std::size_t>(spec.size));
        const int y = static_cast<int>(row % static_cast<std::size_t>(spec.size));
        for (int x = 0; x < spec.size; ++x) {
          raw[row * static_cast<std::size_t>(spec.size) + static_cast<std::size_t>(x)] = fbm(spec, x + 0.5, y + 0.5, f);
        }
      },
      4);
  double mean = 0.0;
  for (double r : raw) mean += r;
  mean /= static_cast<double>(n);
  double variance = 0.0;
  for (double r : raw) variance += (r - mean) * (r - mean);
  const double sigma = std::sqrt(variance / static_cast<double>(n));
  const double gain = sigma > 0.0 ? spec.contrast / (6.0 * sigma) : 0.0;
  v.values.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    v.values[i] = static_cast<float>(std::clamp(0.5 + (raw[i] - mean) * gain, 0.0, 1.0));
  char source[160];
  std::snprintf(source, sizeof source,
                "puffbake detail: size %d, frames %d, seed %u, octaves %d, frequency %d, contrast %g", spec.size,
                spec.frames, spec.seed, spec.octaves, spec.frequency, static_cast<double>(spec.contrast));
  v.source = source;
  return v;
}

namespace {

// The import's limits: the size, the frames cross-faded, and what the video would hold.
Result<void> checkImport(int count, int size, int loopFrames) {
  if (size < core::kMinDetailSize || size > core::kMaxDetailSize) {
    return Error{"--size must be in " + rangeText(core::kMinDetailSize, core::kMaxDetailSize) + ", got " +
                 std::to_string(size)};
  }
  if (loopFrames < 0 || 2 * loopFrames > count) {
    return Error{"--loop-frames must be in [0, " + std::to_string(count / 2) + "] (half of the " +
                 std::to_string(count) + " frames), got " + std::to_string(loopFrames)};
  }
  const int outFrames = count - loopFrames;
  if (outFrames > core::kMaxDetailFrames) {
    return Error{"detail import: " + std::to_string(count) + " frames - " + std::to_string(loopFrames) +
                 " cross-faded = " + std::to_string(outFrames) + " frames, more than " +
                 std::to_string(core::kMaxDetailFrames)};
  }
  if (static_cast<long long>(size) * size * outFrames > kMaxDetailTexels) {
    return Error{"detail import: --size " + std::to_string(size) + " x " + std::to_string(outFrames) +
                 " frames is too large: size * size * frames must be at most " + std::to_string(kMaxDetailTexels)};
  }
  return {};
}

// Resamples one frame's luminance (srcW x srcH) to size x size into `out`, separably: rows first
// (srcH x size), then columns (size x size).
void resample(const std::vector<double>& lum, int srcW, int srcH, const AxisWeights& wx, const AxisWeights& wy,
              int size, std::vector<double>& out) {
  const std::size_t plane = static_cast<std::size_t>(size) * size;
  std::vector<double> rowsOut(static_cast<std::size_t>(srcH) * size);
  for (int y = 0; y < srcH; ++y) {
    for (int x = 0; x < size; ++x) {
      double acc = 0.0;
      for (const auto& [i, w] : wx[static_cast<std::size_t>(x)]) acc += w * lum[static_cast<std::size_t>(y) * srcW + i];
      rowsOut[static_cast<std::size_t>(y) * size + x] = acc;
    }
  }
  out.assign(plane, 0.0);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      double acc = 0.0;
      for (const auto& [j, w] : wy[static_cast<std::size_t>(y)])
        acc += w * rowsOut[static_cast<std::size_t>(j) * size + x];
      out[static_cast<std::size_t>(y) * size + x] = acc;
    }
  }
}

}  // namespace

Result<core::DetailVideo> importDetailVideo(const std::vector<fs::path>& frames, int size, int loopFrames) {
  if (frames.empty()) return Error{"detail import: no frames given"};
  const int count = static_cast<int>(frames.size());
  PUFF_TRY(checkImport(count, size, loopFrames));
  const int outFrames = count - loopFrames;

  // Read and resample every frame first: a bad file fails before any work is kept.
  const std::size_t plane = static_cast<std::size_t>(size) * size;
  std::vector<std::vector<double>> in(static_cast<std::size_t>(count));
  int srcW = 0, srcH = 0;
  AxisWeights wx, wy;
  for (int k = 0; k < count; ++k) {
    const fs::path& path = frames[static_cast<std::size_t>(k)];
    PUFF_TRY_ASSIGN(auto img, core::readImage(path, nullptr, kDetailSourceFrameLimits));
    if (k == 0) {
      srcW = img.width;
      srcH = img.height;
      wx = axisWeights(srcW, size);
      wy = axisWeights(srcH, size);
    } else if (img.width != srcW || img.height != srcH) {
      return Error::at(path, "frame is " + std::to_string(img.width) + "x" + std::to_string(img.height) + ", but " +
                                 fileName(frames[0]) + " (the first frame) is " + std::to_string(srcW) + "x" +
                                 std::to_string(srcH));
    }
    PUFF_TRY_ASSIGN(auto lum, luminance(img, path));
    resample(lum, srcW, srcH, wx, wy, size, in[static_cast<std::size_t>(k)]);
  }

  core::DetailVideo v;
  v.width = v.height = size;
  v.frames = outFrames;
  v.values.resize(plane * static_cast<std::size_t>(outFrames));
  for (int i = 0; i < outFrames; ++i) {
    const std::vector<double>& head = in[static_cast<std::size_t>(i)];
    float* dst = &v.values[plane * static_cast<std::size_t>(i)];
    if (i < loopFrames) {
      const std::vector<double>& tail = in[static_cast<std::size_t>(count - loopFrames + i)];
      const double w = static_cast<double>(i + 1) / (loopFrames + 1);
      for (std::size_t p = 0; p < plane; ++p)
        dst[p] = static_cast<float>(std::clamp((1.0 - w) * tail[p] + w * head[p], 0.0, 1.0));
    } else {
      for (std::size_t p = 0; p < plane; ++p) dst[p] = static_cast<float>(std::clamp(head[p], 0.0, 1.0));
    }
  }
  v.source = "puffbake detail: imported " + std::to_string(count) + " frames (" + fileName(frames.front()) + " .. " +
             fileName(frames.back()) + "), resampled from " + std::to_string(srcW) + "x" + std::to_string(srcH) +
             ", last " + std::to_string(loopFrames) + " cross-faded into the first";
  return v;
}

}  // namespace puff::bake
