#include <algorithm>
#include <limits>

#include <puff/bake/maps.h>
#include <puff/support/parallel.h>

namespace puff::bake {

namespace {

// 1D squared distance transform of sampled function f (Felzenszwalb & Huttenlocher 2012):
// d[q] = min_p (q - p)^2 + f[p]. v, z are scratch of size n and n + 1.
// Doubles: q^2 + f reaches 1e8 and more, past float's exact integers.
void transform1d(const double* f, double* d, int n, int* v, double* z) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] == kInf) continue;
    if (k < 0) {
      k = 0;
      v[0] = q;
      z[0] = -kInf;
      z[1] = kInf;
      continue;
    }
    auto meet = [&](int p) { return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p)); };
    double s = meet(v[k]);
    while (s <= z[k]) s = meet(v[--k]);  // z[0] is -inf, so this stops at k == 0
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = kInf;
  }
  if (k < 0) {
    std::fill(d, d + n, kInf);
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[j + 1] < q) ++j;
    const double dq = q - v[j];
    d[q] = dq * dq + f[v[j]];
  }
}

}  // namespace

std::vector<float> squaredDistanceTransform(const std::vector<std::uint8_t>& feature, int width, int height) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const std::size_t n = static_cast<std::size_t>(width) * height;
  std::vector<float> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = feature[i] ? 0.0f : kInf;
  // Columns, then rows: the 2D transform separates into two 1D passes, each parallel.
  struct Scratch {
    std::vector<double> f, d, z;
    std::vector<int> v;
    explicit Scratch(int m) : f(m), d(m), z(m + 1), v(m) {}
  };
  const int m = std::max(width, height);
  // Columns in blocks of kBlock: a row's kBlock neighbours share a cache line, where one column
  // at a time would miss the cache on every sample of tall images.
  constexpr int kBlock = 16;
  const int blocks = (width + kBlock - 1) / kBlock;
  core::parallelFor(
      static_cast<std::size_t>(blocks),
      [&](std::size_t bi) {
        thread_local Scratch s(0);
        thread_local std::vector<double> gathered;
        if (static_cast<int>(s.f.size()) < m) s = Scratch(m);
        const int x0 = static_cast<int>(bi) * kBlock, nb = std::min(kBlock, width - x0);
        gathered.resize(static_cast<std::size_t>(kBlock) * height);
        for (int y = 0; y < height; ++y) {
          const float* row = out.data() + static_cast<std::size_t>(y) * width + x0;
          for (int b = 0; b < nb; ++b) gathered[static_cast<std::size_t>(b) * height + y] = row[b];
        }
        for (int b = 0; b < nb; ++b) {
          double* col = gathered.data() + static_cast<std::size_t>(b) * height;
          transform1d(col, s.d.data(), height, s.v.data(), s.z.data());
          std::copy_n(s.d.data(), height, col);
        }
        for (int y = 0; y < height; ++y) {
          float* row = out.data() + static_cast<std::size_t>(y) * width + x0;
          for (int b = 0; b < nb; ++b) row[b] = static_cast<float>(gathered[static_cast<std::size_t>(b) * height + y]);
        }
      },
      1);
  core::parallelFor(static_cast<std::size_t>(height), [&](std::size_t yi) {
    thread_local Scratch s(0);
    if (static_cast<int>(s.f.size()) < m) s = Scratch(m);
    float* row = out.data() + yi * width;
    std::copy_n(row, width, s.f.begin());
    transform1d(s.f.data(), s.d.data(), width, s.v.data(), s.z.data());
    for (int x = 0; x < width; ++x) row[x] = static_cast<float>(s.d[x]);
  });
  return out;
}

}  // namespace puff::bake
