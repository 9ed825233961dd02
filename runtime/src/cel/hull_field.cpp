#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <puff/gl_api.h>
#include <puff/support/parallel.h>

#include "hull_field.h"
#include "shadow_profiles.h"

namespace puff::cel::detail {

namespace {

// A map level at the 8 bits the GPU's copy of the distance holds (the packed map, RGBA8), and the back
// map's own 8 bits.
float eightBit(float v) { return std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f; }

// The distance and back maps at level 0, 8 bits, read as a GL sampler would read them (texel i's
// centre at i + 0.5, edges clamped): as the shaders read the distance (cel/particle.glsl, cellUv,
// insideCell; the radius table as silhouetteRadius reads it).
struct Maps {
  int width = 0, height = 0;
  std::vector<float> dist;
  std::vector<float> back;  // empty: the atlas has none (no bound)

  glm::ivec2 clampTexel(int x, int y) const { return {std::clamp(x, 0, width - 1), std::clamp(y, 0, height - 1)}; }
  std::size_t at(glm::ivec2 t) const { return static_cast<std::size_t>(t.y) * width + t.x; }
  // The four texels a bilinear read at texel coordinate (x, y) mixes, and its weights (textureGather's
  // footprint).
  void footprint(float x, float y, std::array<std::size_t, 4>& idx, glm::vec2& f) const {
    const float gx = x - 0.5f, gy = y - 0.5f;
    const int x0 = static_cast<int>(std::floor(gx)), y0 = static_cast<int>(std::floor(gy));
    f = {gx - static_cast<float>(x0), gy - static_cast<float>(y0)};
    idx = {at(clampTexel(x0, y0)), at(clampTexel(x0 + 1, y0)), at(clampTexel(x0, y0 + 1)),
           at(clampTexel(x0 + 1, y0 + 1))};
  }
};

Maps gpuMaps(const core::Atlas& atlas) {
  const core::Image& dist = atlas.maps.at("distance").front();
  Maps m;
  m.width = dist.width;
  m.height = dist.height;
  m.dist.resize(static_cast<std::size_t>(m.width) * m.height);
  for (int y = 0; y < m.height; ++y) {
    for (int x = 0; x < m.width; ++x) m.dist[m.at({x, y})] = eightBit(dist.at(x, y, 0));
  }
  if (auto back = atlas.maps.find("back"); back != atlas.maps.end() && !back->second.empty()) {
    const core::Image& b = back->second.front();
    m.back.resize(m.dist.size());
    for (int y = 0; y < m.height; ++y) {
      for (int x = 0; x < m.width; ++x) m.back[m.at({x, y})] = eightBit(b.at(x, y, 0));
    }
  }
  return m;
}

struct View {
  glm::vec3 right, up, dir;
  glm::vec2 origin;  // level-0 texel of the content square's corner (x right, y down)
  int cell;
};

// The silhouette's radius of `cell` toward `p` (diameters), as shaders/cel/particle.glsl's
// silhouetteRadius reads its table (diamond angle, linear between directions, wrapping around).
float silhouetteRadius(const std::vector<float>& radii, int cell, glm::vec2 p) {
  float q;
  if (p.y >= 0.0f) {
    q = p.x >= 0.0f ? p.y / (p.x + p.y + 1e-20f) : 1.0f - p.x / (p.y - p.x);
  } else {
    q = p.x < 0.0f ? 2.0f - p.y / (-p.x - p.y) : 3.0f + p.x / (p.x - p.y);
  }
  const float s = q * static_cast<float>(kPolar) / 4.0f;
  const int i = static_cast<int>(std::floor(s));
  const float f = s - static_cast<float>(i);
  const auto row = static_cast<std::size_t>(cell) * kPolar;
  const float a = radii[row + static_cast<std::size_t>(((i % kPolar) + kPolar) % kPolar)];
  const float b = radii[row + static_cast<std::size_t>((((i + 1) % kPolar) + kPolar) % kPolar)];
  return a + (b - a) * f;
}

struct Bounder {
  const core::AtlasDesc& d;
  const Maps& maps;
  const std::vector<float>& radii;

  // How far `pt` (puff space, diameters) lies outside what view `v` bounds (<= 0: inside): its
  // silhouette swept along its direction and its far side, about the distance to them.
  float bound(const View& v, glm::vec3 pt) const {
    const float content = static_cast<float>(d.contentSize), range = d.distanceRange, scale = d.depthScale;
    const glm::vec2 local{glm::dot(pt, v.right), glm::dot(pt, v.up)};
    const float halfTexels = 0.5f * static_cast<float>(d.cellSize) - 0.5f;
    const bool inside = std::abs(local.x) * content <= halfTexels && std::abs(local.y) * content <= halfTexels;
    const float tx = v.origin.x + (local.x + 0.5f) * content, ty = v.origin.y + (0.5f - local.y) * content;
    std::array<std::size_t, 4> idx{};
    glm::vec2 f;
    maps.footprint(tx, ty, idx, f);
    // Outside the cell: empty (the shader's insideCell), no silhouette.
    float w = 1.0f;
    if (inside) {
      const float top = maps.dist[idx[0]] * (1.0f - f.x) + maps.dist[idx[1]] * f.x;
      const float bottom = maps.dist[idx[2]] * (1.0f - f.x) + maps.dist[idx[3]] * f.x;
      w = top * (1.0f - f.y) + bottom * f.y;
    }
    // The distance map holds the distance to the silhouette up to its range; past it (less the texel
    // its last 8-bit step may be off) the radius table's star-shaped hull holds the silhouette.
    float dist = (w - 0.5f) * 2.0f * range;  // texels, > 0 outside the silhouette
    const float trusted = range - 1.0f;
    if (dist >= trusted) dist = std::max((glm::length(local) - silhouetteRadius(radii, v.cell, local)) * content, dist);
    float exact = dist / content;
    if (dist > 0.0f || !inside || maps.back.empty()) return exact;
    // The far side, where the four texels around the point all hold one (inside the silhouette): the
    // farthest of the four, less a step of its 8 bits. A point beyond it lies outside, about the height
    // under it times the far side's normal z away; no map holds that normal, so a tenth of the height
    // is taken (the front's least slope): short steps, that never pass the far side.
    float least = 1.0f;
    for (std::size_t i : idx) least = std::min(least, maps.back[i]);
    if (least > 0.0f) {
      const float below = (least - 0.5f) * scale - scale / 255.0f - glm::dot(pt, v.dir);
      exact = std::max(exact, below > 0.0f ? 0.1f * below : below);
    }
    return exact;
  }
};

// A grid point's value that R16F keeps below 0 and a march reads as inside (diameters).
constexpr float kCoreInside = -1e-3f;

// The squared distance transform of `f` (0 at the points that count, a large value elsewhere) along
// one line of `n` points `stride` apart (Felzenszwalb and Huttenlocher's lower envelope of parabolas).
void squaredDistanceLine(float* f, int n, std::size_t stride, std::vector<float>& line, std::vector<int>& v,
                         std::vector<float>& z) {
  const auto at = [](auto& vec, int i) -> auto& { return vec[static_cast<std::size_t>(i)]; };
  for (int i = 0; i < n; ++i) at(line, i) = f[static_cast<std::size_t>(i) * stride];
  // The parabolas of the envelope (v) and where each takes over (z); z[0] lies below every crossing
  // (the values are at most a far value, so every crossing is finite), so k never falls below 0.
  int k = 0;
  v[0] = 0;
  z[0] = -1e30f;
  z[1] = 1e30f;
  for (int q = 1; q < n; ++q) {
    const auto crossing = [&](int p) {
      return ((at(line, q) + static_cast<float>(q * q)) - (at(line, p) + static_cast<float>(p * p))) /
             static_cast<float>(2 * (q - p));
    };
    float s = crossing(at(v, k));
    while (s <= at(z, k)) s = crossing(at(v, --k));
    ++k;
    at(v, k) = q;
    at(z, k) = s;
    at(z, k + 1) = 1e30f;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (at(z, k + 1) < static_cast<float>(q)) ++k;
    const int p = at(v, k);
    f[static_cast<std::size_t>(q) * stride] = static_cast<float>((q - p) * (q - p)) + at(line, p);
  }
}

// Variation `variation`'s core (HullField::cores): the largest ball about a grid point whose every
// cell lies inside (all eight corners below 0: so is the filtered read all through them) and that
// stays within the grid's outermost points (a read beyond them is clamped). A ball about point g
// reaching R grid steps touches cells whose corners lie within R + sqrt 3 of g: R is g's distance to
// the nearest point outside (a Euclidean distance transform of the grid) less sqrt 3.
glm::vec4 fieldCore(const HullField& field, std::size_t variation) {
  const core::HullFieldLayout& f = field.layout;
  const int side = f.side;
  const auto column = variation / static_cast<std::size_t>(f.perColumn);
  const auto row = variation % static_cast<std::size_t>(f.perColumn);
  const auto s = static_cast<std::size_t>(side), width = static_cast<std::size_t>(f.width());
  constexpr float kFar = 1e20f;
  std::vector<float> d(s * s * s);
  for (std::size_t z = 0; z < s; ++z) {
    for (std::size_t y = 0; y < s; ++y) {
      const float* in = field.values.data() + ((row * s + z) * s + y) * width + column * s;
      for (std::size_t x = 0; x < s; ++x) d[(z * s + y) * s + x] = in[x] < kCoreInside ? kFar : 0.0f;
    }
  }
  std::vector<float> line(s), z(s + 1);
  std::vector<int> v(s);
  // Along x, then y, then z: each pass over the whole grid before the next.
  for (std::size_t a = 0; a < s * s; ++a) squaredDistanceLine(&d[a * s], side, 1, line, v, z);
  for (std::size_t a = 0; a < s * s; ++a) squaredDistanceLine(&d[(a / s) * s * s + a % s], side, s, line, v, z);
  for (std::size_t a = 0; a < s * s; ++a) squaredDistanceLine(&d[a], side, s * s, line, v, z);
  float best = 0.0f;
  glm::vec3 centre(0.0f);
  for (int gz = 0; gz < side; ++gz) {
    for (int gy = 0; gy < side; ++gy) {
      for (int gx = 0; gx < side; ++gx) {
        const float squared =
            d[(static_cast<std::size_t>(gz) * s + static_cast<std::size_t>(gy)) * s + static_cast<std::size_t>(gx)];
        const float faces = static_cast<float>(std::min({gx, gy, gz, side - 1 - gx, side - 1 - gy, side - 1 - gz}));
        const float r = std::min(std::sqrt(squared) - std::sqrt(3.0f) - 1e-3f, faces);
        if (r > best) {
          best = r;
          centre = {gx, gy, gz};
        }
      }
    }
  }
  if (best <= 0.0f) return glm::vec4(0.0f);
  const float voxel = 1.0f / static_cast<float>(side);
  return {(centre + 0.5f) * voxel - 0.5f, best * voxel};
}

}  // namespace

HullField buildHullField(const core::Atlas& atlas, const std::vector<float>& radii) {
  const core::AtlasDesc& d = atlas.desc;
  const Maps maps = gpuMaps(atlas);
  const Bounder bounder{d, maps, radii};
  HullField field;
  const core::HullFieldLayout& f = field.layout = core::hullFieldLayout(d);
  const auto side = static_cast<std::size_t>(f.side), width = static_cast<std::size_t>(f.width());
  field.values.assign(width * side * static_cast<std::size_t>(f.depth()), kHullFieldReach);
  std::vector<std::vector<View>> views(static_cast<std::size_t>(d.variations));
  for (int variation = 0; variation < d.variations; ++variation) {
    for (int k = 0; k < d.views; ++k) {
      const int c = variation * d.views + k;
      const core::AtlasCell& cell = d.cells[static_cast<std::size_t>(c)];
      const glm::vec3 dir = glm::normalize(cell.viewDir), up = glm::normalize(cell.viewUp);
      const glm::vec2 origin{static_cast<float>(cell.rect[0] + d.margin), static_cast<float>(cell.rect[1] + d.margin)};
      views[static_cast<std::size_t>(variation)].push_back({glm::cross(up, dir), up, dir, origin, c});
    }
  }
  // A grid point farther outside the sphere than this holds the sphere's distance: the march stays
  // inside the sphere, and reads out here only through a neighbour's filtering.
  const float voxel = 1.0f / static_cast<float>(f.side), outside = 1.8f * voxel;
  // One slice (variation, z) an index: the variations' work spread over the cores alike.
  core::parallelFor(
      views.size() * side,
      [&](std::size_t slice) {
        const std::size_t variation = slice / side, z = slice % side;
        const std::vector<View>& vs = views[variation];
        const std::size_t column = variation / static_cast<std::size_t>(f.perColumn);
        const std::size_t row = variation % static_cast<std::size_t>(f.perColumn);
        std::size_t last = 0;  // the view that bounded the previous point most: read first
        for (std::size_t y = 0; y < side; ++y) {
          float* out = field.values.data() + ((row * side + z) * side + y) * width + column * side;
          for (std::size_t x = 0; x < side; ++x) {
            const glm::vec3 pt =
                (glm::vec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)) + 0.5f) * voxel - 0.5f;
            float b = glm::length(pt) - 0.5f;
            if (b <= outside) {
              for (std::size_t i = 0; i < vs.size() && b < kHullFieldReach; ++i) {
                const std::size_t k = (last + i) % vs.size();
                if (const float v = bounder.bound(vs[k], pt); v > b) {
                  b = v;
                  last = k;
                }
              }
            }
            out[x] = std::clamp(b, -0.5f, kHullFieldReach);
          }
        }
      },
      1);
  field.cores.resize(views.size());
  core::parallelFor(
      views.size(), [&](std::size_t v) { field.cores[v] = fieldCore(field, v); }, 1);
  return field;
}

Result<HullFieldTexture> hullFieldTexture(const core::Atlas& atlas, const std::vector<float>& radii) {
  const core::AtlasDesc& d = atlas.desc;
  if (d.views < 2) return HullFieldTexture{{}, std::vector<glm::vec4>(static_cast<std::size_t>(d.variations))};
  const core::Image& dist = atlas.maps.at("distance").front();
  if (auto back = atlas.maps.find("back"); back != atlas.maps.end() && !back->second.empty()) {
    const core::Image& b = back->second.front();
    if (b.channels != 1) return Error{"atlas back map is not one channel"};
    if (b.width != dist.width || b.height != dist.height) {
      return Error{"atlas back level 0 is " + std::to_string(b.width) + "x" + std::to_string(b.height) + ", expected " +
                   std::to_string(dist.width) + "x" + std::to_string(dist.height)};
    }
  }
  const core::HullFieldLayout f = core::hullFieldLayout(d);
  GLint most = 0;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &most);
  if (f.width() > most || f.depth() > most) {
    return Error{"the tumbling hull's field needs a 3D texture of " + std::to_string(f.width()) + "x" +
                 std::to_string(f.side) + "x" + std::to_string(f.depth()) + ", more than this GL's largest (" +
                 std::to_string(most) + " a side)"};
  }
  const HullField field = buildHullField(atlas, radii);
  core::Texture t = core::makeTexture(GL_TEXTURE_3D, "atlas hull field");
  glTextureStorage3D(t.get(), 1, GL_R16F, f.width(), f.side, f.depth());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage3D(t.get(), 0, 0, 0, 0, f.width(), f.side, f.depth(), GL_RED, GL_FLOAT, field.values.data());
  if (const std::string e = core::drainGlErrors(); !e.empty()) {
    return Error{"cannot make the atlas's hull field texture (" + std::to_string(f.width()) + "x" +
                 std::to_string(f.side) + "x" + std::to_string(f.depth()) + "): " + e};
  }
  glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTextureParameteri(t.get(), wrap, GL_CLAMP_TO_EDGE);
  return HullFieldTexture{std::move(t), field.cores};
}

}  // namespace puff::cel::detail
