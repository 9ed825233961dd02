// Mesh checks, normalization to the unit sphere, vertex normals, and generator parameter checks.
#include <puff/core/number_text.h>
#include <puff/mesh/mesh.h>

#include "mesh_read.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace puff::mesh {
namespace {

// Relative area below which a triangle counts as degenerate: area < kDegenerateArea * diag^2,
// with diag the bounding-box diagonal, so the test does not depend on the mesh's units.
constexpr double kDegenerateArea = 1e-12;

struct DVec3 {
  double x = 0, y = 0, z = 0;
};
DVec3 toD(const glm::vec3& v) { return {double(v.x), double(v.y), double(v.z)}; }
DVec3 sub(const DVec3& a, const DVec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
DVec3 cross(const DVec3& a, const DVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double dot(const DVec3& a, const DVec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Error paramError(const char* generator, const std::string& what) {
  return Error::at({}, std::string(generator) + ": " + what);
}

// NaN fails every comparison, so ranges are written as !(lo <= v && v <= hi).
Result<void> checkRange(const char* gen, const char* flag, double v, double lo, double hi) {
  if (!(lo <= v && v <= hi))
    return paramError(gen, std::string(flag) + " must be in [" + core::numberText(lo) + ", " + core::numberText(hi) +
                               "], got " + core::numberText(v));
  return {};
}

Result<void> checkInt(const char* gen, const char* flag, int v, int lo, int hi) {
  if (v < lo || v > hi)
    return paramError(gen, std::string(flag) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                               "], got " + std::to_string(v));
  return {};
}

}  // namespace

Result<void> validateMesh(const TriMesh& mesh, const std::string& what, const std::vector<std::uint32_t>& sourceFace) {
  const bool mapped = !sourceFace.empty();
  PUFF_CHECK(!mapped || sourceFace.size() == mesh.triangles.size());
  return detail::validateMeshNamed(mesh, what,
                                   [&](std::size_t t) { return "face " + std::to_string(mapped ? sourceFace[t] : t); });
}

Result<void> detail::validateMeshNamed(const TriMesh& mesh, const std::string& what,
                                       const std::function<std::string(std::size_t)>& faceName) {
  if (mesh.triangles.empty()) return Error::at(what, "no faces");
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
    return Error::at(what, "has " + std::to_string(mesh.normals.size()) + " normals for " +
                               std::to_string(mesh.positions.size()) + " vertices");
  if (!mesh.colors.empty() && mesh.colors.size() != mesh.positions.size())
    return Error::at(what, "has " + std::to_string(mesh.colors.size()) + " colors for " +
                               std::to_string(mesh.positions.size()) + " vertices");

  const std::size_t n = mesh.positions.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles[t][k] >= n)
        return Error::at(what, faceName(t) + " refers to vertex " + std::to_string(mesh.triangles[t][k]) +
                                   ", but there are only " + std::to_string(n) + " vertices");

  DVec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  DVec3 hi{-lo.x, -lo.y, -lo.z};
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3& p = mesh.positions[i];
    if (!finite(p)) return Error::at(what, "vertex " + std::to_string(i) + " has a non-finite coordinate");
    lo = {std::min(lo.x, double(p.x)), std::min(lo.y, double(p.y)), std::min(lo.z, double(p.z))};
    hi = {std::max(hi.x, double(p.x)), std::max(hi.y, double(p.y)), std::max(hi.z, double(p.z))};
  }

  const DVec3 ext = sub(hi, lo);
  const double diag2 = dot(ext, ext);
  const double minArea = kDegenerateArea * diag2;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    const DVec3 a = toD(mesh.positions[tri[0]]);
    const DVec3 c = cross(sub(toD(mesh.positions[tri[1]]), a), sub(toD(mesh.positions[tri[2]]), a));
    const double area = 0.5 * std::sqrt(dot(c, c));
    // `!(area >= ...)` also catches an all-coincident mesh, where diag2 and every area are 0.
    if (!(area >= minArea) || area == 0.0) return Error::at(what, faceName(t) + " is degenerate (zero area)");
  }
  return {};
}

Result<void> validateMesh(const TriMesh& mesh, const std::string& what) { return validateMesh(mesh, what, {}); }

void normalizeToUnitSphere(TriMesh& mesh) {
  if (mesh.positions.empty()) return;
  DVec3 lo = toD(mesh.positions[0]);
  DVec3 hi = lo;
  for (const glm::vec3& p : mesh.positions) {
    lo = {std::min(lo.x, double(p.x)), std::min(lo.y, double(p.y)), std::min(lo.z, double(p.z))};
    hi = {std::max(hi.x, double(p.x)), std::max(hi.y, double(p.y)), std::max(hi.z, double(p.z))};
  }
  const DVec3 center{(lo.x + hi.x) * 0.5, (lo.y + hi.y) * 0.5, (lo.z + hi.z) * 0.5};
  double maxR2 = 0.0;
  for (const glm::vec3& p : mesh.positions) {
    const DVec3 d = sub(toD(p), center);
    maxR2 = std::max(maxR2, dot(d, d));
  }
  // A single point (or an empty extent) can only be centered.
  const double scale = maxR2 > 0.0 ? 1.0 / std::sqrt(maxR2) : 1.0;
  for (glm::vec3& p : mesh.positions) {
    const DVec3 d = sub(toD(p), center);
    p = glm::vec3(float(d.x * scale), float(d.y * scale), float(d.z * scale));
  }
}

void computeNormals(TriMesh& mesh) {
  // Summing unnormalized face cross products weights each face by its area.
  std::vector<DVec3> acc(mesh.positions.size());
  for (const glm::uvec3& tri : mesh.triangles) {
    PUFF_CHECK(tri[0] < acc.size() && tri[1] < acc.size() && tri[2] < acc.size());
    const DVec3 a = toD(mesh.positions[tri[0]]);
    const DVec3 c = cross(sub(toD(mesh.positions[tri[1]]), a), sub(toD(mesh.positions[tri[2]]), a));
    for (int k = 0; k < 3; ++k) {
      DVec3& s = acc[tri[k]];
      s = {s.x + c.x, s.y + c.y, s.z + c.z};
    }
  }
  mesh.normals.resize(mesh.positions.size());
  for (std::size_t i = 0; i < acc.size(); ++i) {
    const double len = std::sqrt(dot(acc[i], acc[i]));
    // A vertex with no faces (or whose faces cancel) still needs a unit normal; +z is arbitrary.
    if (!(len > 0.0) || !std::isfinite(len)) {
      mesh.normals[i] = glm::vec3(0.0f, 0.0f, 1.0f);
      continue;
    }
    mesh.normals[i] = glm::vec3(float(acc[i].x / len), float(acc[i].y / len), float(acc[i].z / len));
  }
}

Result<void> validate(const SphereParams& p) { return checkInt("sphere", "--subdivisions", p.subdivisions, 0, 7); }

Result<void> validate(const LumpyParams& p) {
  PUFF_TRY(checkInt("lumpy", "--subdivisions", p.subdivisions, 0, 7));
  PUFF_TRY(checkRange("lumpy", "--amplitude", p.amplitude, 0.0, 0.9));
  if (!(p.frequency > 0.0f) || !std::isfinite(p.frequency))
    return paramError("lumpy", "--frequency must be > 0, got " + core::numberText(p.frequency));
  PUFF_TRY(checkInt("lumpy", "--octaves", p.octaves, 1, 8));
  return {};
}

Result<void> validate(const ClusterParams& p) {
  PUFF_TRY(checkInt("cluster", "--count", p.count, 1, 64));
  if (!(p.radiusMin > 0.0f) || !std::isfinite(p.radiusMin))
    return paramError("cluster", "--radius-min must be > 0, got " + core::numberText(p.radiusMin));
  if (!(p.radiusMax >= p.radiusMin) || !std::isfinite(p.radiusMax))
    return paramError("cluster", "--radius-max must be >= --radius-min (" + core::numberText(p.radiusMin) + "), got " +
                                     core::numberText(p.radiusMax));
  if (!(p.spread >= 0.0f) || !std::isfinite(p.spread))
    return paramError("cluster", "--spread must be >= 0, got " + core::numberText(p.spread));
  PUFF_TRY(checkInt("cluster", "--subdivisions", p.subdivisions, 0, 6));
  return {};
}

}  // namespace puff::mesh
