// Colliders: planes, spheres and boxes over the particle arrays, and mesh colliders (triangles
// binned in a grid, tested along each particle's step).
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include "simulator_impl.h"

namespace puff::sim {

namespace detail {

MeshGrid::MeshGrid(const Collider& c) {
  const std::size_t tris = c.indices.size() / 3;
  lo = glm::vec3(std::numeric_limits<float>::max());
  hi = -lo;
  for (const glm::vec3& p : c.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  for (std::size_t t = 0; t < tris; ++t) {
    const glm::vec3 p0 = c.positions[c.indices[3 * t]], p1 = c.positions[c.indices[3 * t + 1]],
                    p2 = c.positions[c.indices[3 * t + 2]];
    const glm::vec3 normal = glm::cross(p1 - p0, p2 - p0);
    const float len = glm::length(normal);
    if (!(len > 0.0f)) continue;  // degenerate: nothing to hit
    a.push_back(p0), e1.push_back(p1 - p0), e2.push_back(p2 - p0), n.push_back(normal / len);
  }
  const glm::vec3 extent = glm::max(hi - lo, glm::vec3(1e-4f));
  const int perAxis = std::clamp(static_cast<int>(std::cbrt(static_cast<double>(a.size())) * 1.5), 1, 64);
  const float side = std::max({extent.x, extent.y, extent.z}) / static_cast<float>(perAxis);
  dims = glm::clamp(glm::ivec3(glm::ceil(extent / side)), glm::ivec3(1), glm::ivec3(64));
  cell = extent / glm::vec3(dims);
  std::vector<std::vector<std::uint32_t>> bins(static_cast<std::size_t>(dims.x) * dims.y * dims.z);
  for (std::size_t t = 0; t < a.size(); ++t) {
    const glm::vec3 p1 = a[t] + e1[t], p2 = a[t] + e2[t];
    const glm::ivec3 c0 = cellOf(glm::min(a[t], glm::min(p1, p2))), c1 = cellOf(glm::max(a[t], glm::max(p1, p2)));
    for (int z = c0.z; z <= c1.z; ++z)
      for (int y = c0.y; y <= c1.y; ++y)
        for (int x = c0.x; x <= c1.x; ++x) bins[index(x, y, z)].push_back(static_cast<std::uint32_t>(t));
  }
  start.push_back(0);
  for (const auto& b : bins) {
    items.insert(items.end(), b.begin(), b.end());
    start.push_back(static_cast<std::uint32_t>(items.size()));
  }
}

bool MeshGrid::firstHit(const glm::vec3& p, const glm::vec3& q, float& tHit, std::uint32_t& triHit) const {
  if (!std::isfinite(p.x + p.y + p.z + q.x + q.y + q.z)) return false;
  const glm::vec3 sLo = glm::min(p, q), sHi = glm::max(p, q);
  if (glm::any(glm::lessThan(sHi, lo)) || glm::any(glm::greaterThan(sLo, hi))) return false;
  const glm::ivec3 c0 = cellOf(sLo), c1 = cellOf(sHi);
  const glm::vec3 d = q - p;
  bool hit = false;
  tHit = 2.0f;
  for (int z = c0.z; z <= c1.z; ++z) {
    for (int y = c0.y; y <= c1.y; ++y) {
      for (int x = c0.x; x <= c1.x; ++x) {
        const std::size_t b = index(x, y, z);
        for (std::uint32_t k = start[b]; k < start[b + 1]; ++k) {
          const std::uint32_t t = items[k];
          // Moller-Trumbore, both sides.
          const glm::vec3 pv = glm::cross(d, e2[t]);
          const float det = glm::dot(e1[t], pv);
          if (std::abs(det) < 1e-20f) continue;
          const float inv = 1.0f / det;
          const glm::vec3 tv = p - a[t];
          const float u = glm::dot(tv, pv) * inv;
          if (u < 0.0f || u > 1.0f) continue;
          const glm::vec3 qv = glm::cross(tv, e1[t]);
          const float v = glm::dot(d, qv) * inv;
          if (v < 0.0f || u + v > 1.0f) continue;
          const float s = glm::dot(e2[t], qv) * inv;
          if (s >= 0.0f && s <= 1.0f && s < tHit) tHit = s, triHit = t, hit = true;
        }
      }
    }
  }
  return hit;
}

}  // namespace detail

namespace {

// Plane and sphere contacts over the arrays, branch-free; returns the number of contacts.
std::size_t collidePlane(const glm::mat3& toLocal, const glm::vec3& center, const glm::vec3& halfExtent, float keep,
                         float* __restrict X, float* __restrict Y, float* __restrict Z, float* __restrict VX,
                         float* __restrict VY, float* __restrict VZ, const float* __restrict R, std::size_t n) {
  // toLocal rows: the plane's x, normal, z axes in world space.
  const glm::vec3 ex = glm::row(toLocal, 0), nrm = glm::row(toLocal, 1), ez = glm::row(toLocal, 2);
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = X[i] - center.x, dy = Y[i] - center.y, dz = Z[i] - center.z;
    const float lx = ex.x * dx + ex.y * dy + ex.z * dz, ly = nrm.x * dx + nrm.y * dy + nrm.z * dz,
                lz = ez.x * dx + ez.y * dy + ez.z * dz;
    const bool hit = (ly < R[i]) & (std::abs(lx) <= halfExtent.x) & (std::abs(lz) <= halfExtent.z);
    const float push = hit ? R[i] - ly : 0.0f;
    X[i] += push * nrm.x, Y[i] += push * nrm.y, Z[i] += push * nrm.z;
    const float vn = VX[i] * nrm.x + VY[i] * nrm.y + VZ[i] * nrm.z;
    const bool slide = hit & (vn < 0.0f);  // & not &&: no branch, so the loop vectorizes
    const float into = slide ? vn : 0.0f;
    const float scale = slide ? keep : 1.0f;
    VX[i] = (VX[i] - into * nrm.x) * scale, VY[i] = (VY[i] - into * nrm.y) * scale,
    VZ[i] = (VZ[i] - into * nrm.z) * scale;
    contacts += hit ? 1 : 0;
  }
  return contacts;
}

std::size_t collideSphere(const glm::vec3 center, float radius, const glm::vec3 up, float keep, float* __restrict X,
                          float* __restrict Y, float* __restrict Z, float* __restrict VX, float* __restrict VY,
                          float* __restrict VZ, const float* __restrict R, std::size_t n) {
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = X[i] - center.x, dy = Y[i] - center.y, dz = Z[i] - center.z;
    const float reach = radius + R[i];
    const float l2 = dx * dx + dy * dy + dz * dz;
    const bool hit = l2 < reach * reach;
    const float l = std::sqrt(l2);
    const float centred = static_cast<float>(!(l > 1e-12f));  // at the very centre: out along `up`
    const float inv = (1.0f - centred) / std::max(l, 1e-12f);
    const float nx = dx * inv + centred * up.x, ny = dy * inv + centred * up.y, nz = dz * inv + centred * up.z;
    const float move = static_cast<float>(hit);
    X[i] += move * (center.x + nx * reach - X[i]);
    Y[i] += move * (center.y + ny * reach - Y[i]);
    Z[i] += move * (center.z + nz * reach - Z[i]);
    const float vn = VX[i] * nx + VY[i] * ny + VZ[i] * nz;
    const bool slide = hit & (vn < 0.0f);  // & not &&: no branch, so the loop vectorizes
    const float into = slide ? vn : 0.0f;
    const float scale = slide ? keep : 1.0f;
    VX[i] = (VX[i] - into * nx) * scale, VY[i] = (VY[i] - into * ny) * scale, VZ[i] = (VZ[i] - into * nz) * scale;
    contacts += hit ? 1 : 0;
  }
  return contacts;
}

// Oriented-box contacts over the arrays, branch-free: a particle inside the box grown by its
// radius leaves through the nearest face.
std::size_t collideBox(const glm::mat3& toWorld, const glm::vec3& center, const glm::vec3& halfExtent, float keep,
                       float* __restrict X, float* __restrict Y, float* __restrict Z, float* __restrict VX,
                       float* __restrict VY, float* __restrict VZ, const float* __restrict R, std::size_t n) {
  const glm::vec3 ax = toWorld[0], ay = toWorld[1], az = toWorld[2];  // the box's axes in world space
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = X[i] - center.x, dy = Y[i] - center.y, dz = Z[i] - center.z;
    const float lx = ax.x * dx + ax.y * dy + ax.z * dz, ly = ay.x * dx + ay.y * dy + ay.z * dz,
                lz = az.x * dx + az.y * dy + az.z * dz;
    const float rx = halfExtent.x + R[i], ry = halfExtent.y + R[i], rz = halfExtent.z + R[i];
    const float px = rx - std::abs(lx), py = ry - std::abs(ly), pz = rz - std::abs(lz);
    const bool hit = (px > 0.0f) & (py > 0.0f) & (pz > 0.0f);
    const bool outX = (px < py) & (px < pz), outY = !outX & (py < pz), outZ = !outX & !outY;
    const float sx = lx < 0.0f ? -1.0f : 1.0f, sy = ly < 0.0f ? -1.0f : 1.0f, sz = lz < 0.0f ? -1.0f : 1.0f;
    // How far to move along the chosen face's normal (local), and that normal in world space.
    const float push = hit ? (outX ? px : (outY ? py : pz)) : 0.0f;
    const float nlx = outX ? sx : 0.0f, nly = outY ? sy : 0.0f, nlz = outZ ? sz : 0.0f;
    const float nx = ax.x * nlx + ay.x * nly + az.x * nlz, ny = ax.y * nlx + ay.y * nly + az.y * nlz,
                nz = ax.z * nlx + ay.z * nly + az.z * nlz;
    X[i] += push * nx, Y[i] += push * ny, Z[i] += push * nz;
    const float vn = VX[i] * nx + VY[i] * ny + VZ[i] * nz;
    const bool slide = hit & (vn < 0.0f);
    const float into = slide ? vn : 0.0f;
    const float scale = slide ? keep : 1.0f;
    VX[i] = (VX[i] - into * nx) * scale, VY[i] = (VY[i] - into * ny) * scale, VZ[i] = (VZ[i] - into * nz) * scale;
    contacts += hit ? 1 : 0;
  }
  return contacts;
}

}  // namespace

// Puts particles [begin, end) back outside every collider; returns the number of contacts.
// `prev` (x, y, z arrays indexed from `begin`) is where the particles were before they moved: mesh
// colliders test the segment, so a fast particle cannot tunnel through a thin wall.
std::size_t Simulator::Impl::collide(std::size_t begin, std::size_t end, const float* const* prev, double t0,
                                     double t) {
  std::size_t contacts = 0;
  std::size_t meshIndex = 0;
  // Each particle's collision radius, once for all colliders.
  radii.resize(end - begin);
  for (std::size_t i = begin; i < end; ++i)
    radii[i - begin] = s.collisionRadius * 0.5f * size0[i] * std::max(0.0f, 1.0f - age[i] / life[i]);
  for (const Collider& collider : s.colliders) {
    Collider moved;  // a collider on a path, where it is now (meshes move by the same offset)
    const bool onPath = !collider.path.empty();
    if (onPath) {
      moved.type = collider.type, moved.rotation = collider.rotation, moved.halfExtent = collider.halfExtent;
      moved.friction = collider.friction, moved.center = collider.center + collider.path.at(t);
    }
    const Collider& c = onPath ? moved : collider;
    // A moving mesh: the particle's step is tested in the mesh's frame (start against where the
    // mesh was, end against where it is), so a sweeping mesh pushes smoke it passes through.
    const glm::vec3 meshOffset0 = onPath ? collider.path.at(t0) : glm::vec3(0.0f);
    const glm::vec3 meshOffset = onPath ? collider.path.at(t) : glm::vec3(0.0f);
    const glm::vec3 bodyVelocity = (meshOffset - meshOffset0) / static_cast<float>(t - t0);
    const float keep = 1.0f - c.friction;
    switch (c.type) {
      case Collider::Type::kPlane:
        contacts += collidePlane(glm::transpose(glm::mat3_cast(c.rotation)), c.center, c.halfExtent, keep,
                                 px.data() + begin, py.data() + begin, pz.data() + begin, vx.data() + begin,
                                 vy.data() + begin, vz.data() + begin, radii.data(), end - begin);
        break;
      case Collider::Type::kSphere:
        contacts += collideSphere(c.center, c.halfExtent.x, c.rotation * glm::vec3(0, 1, 0), keep, px.data() + begin,
                                  py.data() + begin, pz.data() + begin, vx.data() + begin, vy.data() + begin,
                                  vz.data() + begin, radii.data(), end - begin);
        break;
      case Collider::Type::kBox:
        contacts += collideBox(glm::mat3_cast(c.rotation), c.center, c.halfExtent, keep, px.data() + begin,
                               py.data() + begin, pz.data() + begin, vx.data() + begin, vy.data() + begin,
                               vz.data() + begin, radii.data(), end - begin);
        break;
      case Collider::Type::kMesh: {
        const detail::MeshGrid& m = meshes[meshIndex++];
        const float* OX = prev[0];
        const float* OY = prev[1];
        const float* OZ = prev[2];
        for (std::size_t i = begin; i < end; ++i) {
          const glm::vec3 p = glm::vec3(OX[i - begin], OY[i - begin], OZ[i - begin]) - meshOffset0,
                          q = glm::vec3(px[i], py[i], pz[i]) - meshOffset;
          float along;
          std::uint32_t tri;
          if (!m.firstHit(p, q, along, tri)) continue;
          glm::vec3 n = m.n[tri];
          if (glm::dot(p - m.a[tri], n) < 0.0f) n = -n;  // the side it came from
          const glm::vec3 hit = p + (q - p) * along;
          const glm::vec3 at = hit + n * 1e-4f * std::max(1.0f, glm::length(m.hi - m.lo)) + meshOffset;
          px[i] = at.x, py[i] = at.y, pz[i] = at.z;
          // Lose the velocity into the surface relative to the moving body.
          glm::vec3 v = glm::vec3(vx[i], vy[i], vz[i]) - bodyVelocity;
          const float vn = glm::dot(v, n);
          if (vn < 0.0f) v = (v - vn * n) * keep;
          v += bodyVelocity;
          vx[i] = v.x, vy[i] = v.y, vz[i] = v.z;
          ++contacts;
        }
        break;
      }
    }
  }
  return contacts;
}

}  // namespace puff::sim
