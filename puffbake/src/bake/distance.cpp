#include <algorithm>
#include <limits>

#include <puff/bake/maps.h>

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
  const int m = std::max(width, height);
  std::vector<double> f(m), d(m), z(m + 1);
  std::vector<int> v(m);
  // Columns, then rows: the 2D transform separates into two 1D passes.
  for (int x = 0; x < width; ++x) {
    for (int y = 0; y < height; ++y) f[y] = out[static_cast<std::size_t>(y) * width + x];
    transform1d(f.data(), d.data(), height, v.data(), z.data());
    for (int y = 0; y < height; ++y) out[static_cast<std::size_t>(y) * width + x] = static_cast<float>(d[y]);
  }
  for (int y = 0; y < height; ++y) {
    float* row = out.data() + static_cast<std::size_t>(y) * width;
    std::copy_n(row, width, f.begin());
    transform1d(f.data(), d.data(), width, v.data(), z.data());
    for (int x = 0; x < width; ++x) row[x] = static_cast<float>(d[x]);
  }
  return out;
}

}  // namespace puff::bake
