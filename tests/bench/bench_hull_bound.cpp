// What a multi-view atlas's views can bound at best: the tumbling hull
// (docs/cel-rendering.md, "Tumbling puffs") with exact maps. Each mesh (normalized as puffbake
// normalizes it) is voxelized; every view of the atlas's layout and grid keeps the voxels inside its
// silhouette and behind its front surface (with --layers K, also outside the gaps between the first
// K runs of the puff along each of its rays: what K depth layers per view would add; with --far,
// before the far side of the last run: what the back map adds, puff/core/atlas.h); the hull is
// what every view keeps, inside the unit sphere. It and the mesh are then seen from every direction
// of the sweep (yaw and pitch every 15 degrees), 48 pixels across, and their silhouettes compared:
// coverage IoU, worst and mean, and the share of directions at 0.95. No GL: no texel, bit depth or
// march stands between the views and the hull, so a GPU sweep's (puffbench --part tumble) errors
// beyond these are the renderer's; these are the views'.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <puff/bake/maps.h>
#include <puff/mesh/mesh.h>

namespace {

using namespace puff;

void usage(std::FILE* f) {
  std::fprintf(
      f,
      "usage: puff_bench_hull [--layout oct|hemioct] [--grid N (3)] [--layers K (0)] [--far] [--voxels N (192)] "
      "MESH...\n"
      "The silhouette coverage IoU of the hull of exact views (silhouette and front depth; --layers K:\n"
      "K depth layers; --far: the last run's far side, as the back map) against each mesh, over yaw and\n"
      "pitch every 15 degrees at 48 px.\n");
}

struct Grid {
  int n;
  std::vector<unsigned char> v;
  glm::vec3 centre(int i, int j, int k) const {
    return glm::vec3((static_cast<float>(i) + 0.5f) / static_cast<float>(n) - 0.5f,
                     (static_cast<float>(j) + 0.5f) / static_cast<float>(n) - 0.5f,
                     (static_cast<float>(k) + 0.5f) / static_cast<float>(n) - 0.5f);
  }
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(n) +
           static_cast<std::size_t>(i);
  }
};

// Inside the mesh: the parity of its crossings along z through each column of voxel centres.
Grid voxelize(const mesh::TriMesh& m, int n) {
  Grid g{n, std::vector<unsigned char>(static_cast<std::size_t>(n) * n * n, 0)};
  std::vector<std::vector<float>> crossings(static_cast<std::size_t>(n) * n);
  auto cellOf = [n](float x) { return (x + 0.5f) * static_cast<float>(n) - 0.5f; };
  for (const glm::uvec3& t : m.triangles) {
    // Into the unit-diameter cube: the normalized mesh has radius 1.
    const glm::vec3 p[3] = {0.5f * m.positions[t.x], 0.5f * m.positions[t.y], 0.5f * m.positions[t.z]};
    const float x0 = std::min({p[0].x, p[1].x, p[2].x}), x1 = std::max({p[0].x, p[1].x, p[2].x});
    const float y0 = std::min({p[0].y, p[1].y, p[2].y}), y1 = std::max({p[0].y, p[1].y, p[2].y});
    const int i0 = std::max(0, static_cast<int>(std::floor(cellOf(x0)))),
              i1 = std::min(n - 1, static_cast<int>(std::ceil(cellOf(x1))));
    const int j0 = std::max(0, static_cast<int>(std::floor(cellOf(y0)))),
              j1 = std::min(n - 1, static_cast<int>(std::ceil(cellOf(y1))));
    const double d = static_cast<double>(p[1].x - p[0].x) * (p[2].y - p[0].y) -
                     static_cast<double>(p[2].x - p[0].x) * (p[1].y - p[0].y);
    if (std::abs(d) < 1e-14) continue;
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        // Nudged off the grid so that a column never passes exactly through an edge or a vertex.
        const double px = (i + 0.5) / n - 0.5 + 1e-7, py = (j + 0.5) / n - 0.5 + 1.3e-7;
        const double a = ((p[1].x - px) * (p[2].y - py) - (p[2].x - px) * (p[1].y - py)) / d;
        const double b = ((p[2].x - px) * (p[0].y - py) - (p[0].x - px) * (p[2].y - py)) / d;
        const double c = 1.0 - a - b;
        if (a < 0.0 || b < 0.0 || c < 0.0) continue;
        crossings[static_cast<std::size_t>(j) * n + i].push_back(
            static_cast<float>(a * p[0].z + b * p[1].z + c * p[2].z));
      }
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      std::vector<float>& z = crossings[static_cast<std::size_t>(j) * n + i];
      std::sort(z.begin(), z.end());
      for (std::size_t q = 0; q + 1 < z.size(); q += 2)
        for (int k = 0; k < n; ++k) {
          const float zc = g.centre(i, j, k).z;
          if (zc >= z[q] && zc <= z[q + 1]) g.v[g.index(i, j, k)] = 1;
        }
    }
  }
  return g;
}

// The rows of bake::viewRotation: right, up, toward the viewer.
void axes(const glm::vec3& dir, glm::vec3& right, glm::vec3& up) {
  const glm::mat3 r = bake::viewRotation(dir);
  right = glm::vec3(r[0][0], r[1][0], r[2][0]);
  up = glm::vec3(r[0][1], r[1][1], r[2][1]);
}

Grid hullOf(const Grid& puff, bake::ViewLayout layout, int grid, int layers, bool far) {
  const int n = puff.n, m = n / 2;  // each view's image: two voxels a pixel
  Grid h{n, std::vector<unsigned char>(puff.v.size(), 0)};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) h.v[h.index(i, j, k)] = glm::length(h.centre(i, j, k)) <= 0.5f;
  const float voxel = 1.0f / static_cast<float>(n);
  for (int view = 0; view < grid * grid; ++view) {
    const glm::vec3 dir = bake::viewDirection(layout, grid, view);
    glm::vec3 right, up;
    axes(dir, right, up);
    auto pixel = [&](const glm::vec3& p) {
      const int a = static_cast<int>(std::floor((glm::dot(p, right) + 0.5f) * static_cast<float>(m)));
      const int b = static_cast<int>(std::floor((glm::dot(p, up) + 0.5f) * static_cast<float>(m)));
      return a < 0 || b < 0 || a >= m || b >= m ? -1 : b * m + a;
    };
    // Each pixel's runs of puff along the view's ray, nearest the viewer first (a gap of over two
    // voxels splits a run).
    std::vector<std::vector<float>> depths(static_cast<std::size_t>(m) * m);
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          if (puff.v[puff.index(i, j, k)]) {
            const glm::vec3 p = puff.centre(i, j, k);
            if (const int q = pixel(p); q >= 0) depths[static_cast<std::size_t>(q)].push_back(glm::dot(p, dir));
          }
    std::vector<std::vector<std::pair<float, float>>> runs(depths.size());
    for (std::size_t q = 0; q < depths.size(); ++q) {
      std::vector<float>& d = depths[q];
      if (d.empty()) continue;
      std::sort(d.rbegin(), d.rend());
      float top = d[0], previous = d[0];
      for (std::size_t t = 1; t < d.size(); ++t) {
        if (previous - d[t] > 2.0f * voxel) {
          runs[q].push_back({top, previous});
          top = d[t];
        }
        previous = d[t];
      }
      runs[q].push_back({top, previous});
    }
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
          const std::size_t id = h.index(i, j, k);
          if (!h.v[id]) continue;
          const glm::vec3 p = h.centre(i, j, k);
          const int q = pixel(p);
          if (q < 0 || runs[static_cast<std::size_t>(q)].empty()) {
            h.v[id] = 0;  // outside the silhouette
            continue;
          }
          const auto& r = runs[static_cast<std::size_t>(q)];
          const float depth = glm::dot(p, dir);
          if (depth > r[0].first + voxel) {
            h.v[id] = 0;  // in front of the front surface
            continue;
          }
          if (layers > 0) {
            const int known = std::min<int>(layers, static_cast<int>(r.size()));
            bool inRun = false;
            for (int t = 0; t < known; ++t) inRun |= depth <= r[t].first + voxel && depth >= r[t].second - voxel;
            const bool beyond = depth < r[static_cast<std::size_t>(known - 1)].second - voxel;
            // In a gap the layers show, or behind the last run when they show every run.
            if (!inRun && (!beyond || known == static_cast<int>(r.size()))) h.v[id] = 0;
          }
          if (far && depth < r.back().second - voxel) h.v[id] = 0;  // beyond the last run's far side
        }
      }
    }
  }
  return h;
}

struct Score {
  double worst = 1.0, mean = 0.0, share = 0.0;
};

Score compare(const Grid& puff, const Grid& hull) {
  constexpr int kPixels = 48;
  std::vector<glm::vec3> a, b;
  for (int k = 0; k < puff.n; ++k)
    for (int j = 0; j < puff.n; ++j)
      for (int i = 0; i < puff.n; ++i) {
        if (puff.v[puff.index(i, j, k)]) a.push_back(puff.centre(i, j, k));
        if (hull.v[hull.index(i, j, k)]) b.push_back(hull.centre(i, j, k));
      }
  Score s;
  int count = 0, ok = 0;
  for (int pitch = -90; pitch <= 90; pitch += 15) {
    for (int yaw = 0; yaw < 360; yaw += 15) {
      if (std::abs(pitch) == 90 && yaw != 0) continue;
      const float p = glm::radians(static_cast<float>(pitch)), y = glm::radians(static_cast<float>(yaw));
      glm::vec3 right, up;
      axes(glm::vec3(std::cos(p) * std::sin(y), std::sin(p), std::cos(p) * std::cos(y)), right, up);
      auto splat = [&](const std::vector<glm::vec3>& points) {
        std::vector<unsigned char> image(kPixels * kPixels, 0);
        for (const glm::vec3& q : points) {
          const int x = static_cast<int>(std::floor((glm::dot(q, right) + 0.5f) * kPixels));
          const int z = static_cast<int>(std::floor((glm::dot(q, up) + 0.5f) * kPixels));
          if (x >= 0 && z >= 0 && x < kPixels && z < kPixels) image[static_cast<std::size_t>(z * kPixels + x)] = 1;
        }
        return image;
      };
      const std::vector<unsigned char> sa = splat(a), sb = splat(b);
      int both = 0, either = 0;
      for (std::size_t q = 0; q < sa.size(); ++q) {
        both += sa[q] && sb[q];
        either += sa[q] || sb[q];
      }
      const double iou = either ? static_cast<double>(both) / either : 1.0;
      s.worst = std::min(s.worst, iou);
      s.mean += iou;
      ok += iou >= 0.95;
      ++count;
    }
  }
  s.mean /= count;
  s.share = static_cast<double>(ok) / count;
  return s;
}

bool number(const char* text, int lo, int hi, int& out) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (!*text || *end || v < lo || v > hi) return false;
  out = static_cast<int>(v);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  bake::ViewLayout layout = bake::ViewLayout::kOct;
  int grid = 3, layers = 0, voxels = 192;
  bool far = false;
  std::vector<std::string> meshes;
  for (int i = 1; i < argc; ++i) {
    const bool more = i + 1 < argc;
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      usage(stdout);
      return 0;
    } else if (!std::strcmp(argv[i], "--layout") && more) {
      const std::string v = argv[++i];
      if (v != "oct" && v != "hemioct") {
        std::fprintf(stderr, "puff_bench_hull: --layout takes oct or hemioct, got '%s'\n", v.c_str());
        return 2;
      }
      layout = v == "oct" ? bake::ViewLayout::kOct : bake::ViewLayout::kHemiOct;
    } else if (!std::strcmp(argv[i], "--grid") && more) {
      if (!number(argv[++i], 1, 15, grid)) return std::fprintf(stderr, "puff_bench_hull: --grid takes 1 to 15\n"), 2;
    } else if (!std::strcmp(argv[i], "--layers") && more) {
      if (!number(argv[++i], 0, 16, layers))
        return std::fprintf(stderr, "puff_bench_hull: --layers takes 0 to 16\n"), 2;
    } else if (!std::strcmp(argv[i], "--far")) {
      far = true;
    } else if (!std::strcmp(argv[i], "--voxels") && more) {
      if (!number(argv[++i], 32, 512, voxels))
        return std::fprintf(stderr, "puff_bench_hull: --voxels takes 32 to 512\n"), 2;
    } else if (argv[i][0] == '-') {
      usage(stderr);
      return 2;
    } else {
      meshes.push_back(argv[i]);
    }
  }
  if (meshes.empty()) {
    usage(stderr);
    return 2;
  }
  for (const std::string& path : meshes) {
    auto m = mesh::loadMesh(path);
    if (!m) {
      std::fprintf(stderr, "puff_bench_hull: %s\n", m.error().message.c_str());
      return 1;
    }
    const Grid puff = voxelize(*m, voxels);
    const Score s = compare(puff, hullOf(puff, layout, grid, layers, far));
    std::printf("%s: %s %dx%d, %d layers%s: coverage IoU worst %.3f mean %.3f, %.1f%% of directions >= 0.95\n",
                path.c_str(), layout == bake::ViewLayout::kOct ? "oct" : "hemioct", grid, grid, layers,
                far ? ", far side" : "", s.worst, s.mean, 100.0 * s.share);
  }
  return 0;
}
