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

// The kernels below take every loop invariant as a scalar: read through a reference, the compiler
// must assume the stores to the arrays may change it, and it then runs the loop unvectorized.

// Plane contacts over the arrays, branch-free; returns the number of contacts.
PUFF_SIM_KERNEL std::size_t collidePlane(const glm::mat3& toLocal, const glm::vec3& center, const glm::vec3& halfExtent,
                                         float keep, float* __restrict X, float* __restrict Y, float* __restrict Z,
                                         float* __restrict VX, float* __restrict VY, float* __restrict VZ,
                                         const float* __restrict R, std::size_t n) {
  // toLocal rows: the plane's x, normal, z axes in world space.
  const glm::vec3 ex = glm::row(toLocal, 0), nrm = glm::row(toLocal, 1), ez = glm::row(toLocal, 2);
  const float exx = ex.x, exy = ex.y, exz = ex.z, nx = nrm.x, ny = nrm.y, nz = nrm.z, ezx = ez.x, ezy = ez.y,
              ezz = ez.z;
  const float cx = center.x, cy = center.y, cz = center.z, hx = halfExtent.x, hz = halfExtent.z;
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = X[i] - cx, dy = Y[i] - cy, dz = Z[i] - cz;
    const float lx = exx * dx + exy * dy + exz * dz, ly = nx * dx + ny * dy + nz * dz,
                lz = ezx * dx + ezy * dy + ezz * dz;
    const bool hit = (ly < R[i]) & (std::abs(lx) <= hx) & (std::abs(lz) <= hz);
    const float push = hit ? R[i] - ly : 0.0f;
    X[i] += push * nx, Y[i] += push * ny, Z[i] += push * nz;
    const float vn = VX[i] * nx + VY[i] * ny + VZ[i] * nz;
    const bool slide = hit & (vn < 0.0f);  // & not &&: no branch, so the loop vectorizes
    const float into = slide ? vn : 0.0f;
    const float scale = slide ? keep : 1.0f;
    VX[i] = (VX[i] - into * nx) * scale, VY[i] = (VY[i] - into * ny) * scale, VZ[i] = (VZ[i] - into * nz) * scale;
    contacts += hit ? 1 : 0;
  }
  return contacts;
}

PUFF_SIM_KERNEL std::size_t collideSphere(const glm::vec3& center, float radius, const glm::vec3& up, float keep,
                                          float* __restrict X, float* __restrict Y, float* __restrict Z,
                                          float* __restrict VX, float* __restrict VY, float* __restrict VZ,
                                          const float* __restrict R, std::size_t n) {
  const float cx = center.x, cy = center.y, cz = center.z, upx = up.x, upy = up.y, upz = up.z;
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = X[i] - cx, dy = Y[i] - cy, dz = Z[i] - cz;
    const float reach = radius + R[i];
    const float l2 = dx * dx + dy * dy + dz * dz;
    const bool hit = l2 < reach * reach;
    const float l = std::sqrt(l2);
    // At the very centre: out along `up`. (Ternaries, not bool-to-float casts, which keep GCC 12
    // from vectorizing the loop.)
    const float centred = l > 1e-12f ? 0.0f : 1.0f;
    const float inv = (1.0f - centred) / std::max(l, 1e-12f);
    const float nx = dx * inv + centred * upx, ny = dy * inv + centred * upy, nz = dz * inv + centred * upz;
    const float move = hit ? 1.0f : 0.0f;
    X[i] += move * (cx + nx * reach - X[i]);
    Y[i] += move * (cy + ny * reach - Y[i]);
    Z[i] += move * (cz + nz * reach - Z[i]);
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
PUFF_SIM_KERNEL std::size_t collideBox(const glm::mat3& toWorld, const glm::vec3& center, const glm::vec3& halfExtent,
                                       float keep, float* __restrict X, float* __restrict Y, float* __restrict Z,
                                       float* __restrict VX, float* __restrict VY, float* __restrict VZ,
                                       const float* __restrict R, std::size_t n) {
  const glm::vec3 ax = toWorld[0], ay = toWorld[1], az = toWorld[2];  // the box's axes in world space
  const float axx = ax.x, axy = ax.y, axz = ax.z, ayx = ay.x, ayy = ay.y, ayz = ay.z, azx = az.x, azy = az.y,
              azz = az.z;
  const float cx = center.x, cy = center.y, cz = center.z, hx = halfExtent.x, hy = halfExtent.y, hz = halfExtent.z;
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = X[i] - cx, dy = Y[i] - cy, dz = Z[i] - cz;
    const float lx = axx * dx + axy * dy + axz * dz, ly = ayx * dx + ayy * dy + ayz * dz,
                lz = azx * dx + azy * dy + azz * dz;
    const float rx = hx + R[i], ry = hy + R[i], rz = hz + R[i];
    const float px = rx - std::abs(lx), py = ry - std::abs(ly), pz = rz - std::abs(lz);
    const bool hit = (px > 0.0f) & (py > 0.0f) & (pz > 0.0f);
    const bool outX = (px < py) & (px < pz), outY = !outX & (py < pz), outZ = !outX & !outY;
    const float sx = lx < 0.0f ? -1.0f : 1.0f, sy = ly < 0.0f ? -1.0f : 1.0f, sz = lz < 0.0f ? -1.0f : 1.0f;
    // How far to move along the chosen face's normal (local), and that normal in world space.
    const float push = hit ? (outX ? px : (outY ? py : pz)) : 0.0f;
    const float nlx = outX ? sx : 0.0f, nly = outY ? sy : 0.0f, nlz = outZ ? sz : 0.0f;
    const float nx = axx * nlx + ayx * nly + azx * nlz, ny = axy * nlx + ayy * nly + azy * nlz,
                nz = axz * nlx + ayz * nly + azz * nlz;
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

// Each particle's collision radius: collisionRadius of its current radius.
PUFF_SIM_KERNEL void collisionRadii(float collisionRadius, const float* __restrict S0, const float* __restrict A,
                                    const float* __restrict L, float* __restrict R, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) R[i] = collisionRadius * 0.5f * S0[i] * std::max(0.0f, 1.0f - A[i] / L[i]);
}

}  // namespace

// Where every collider is during the step t0 -> t1 (contacts are resolved against where it is at t1).
void Simulator::Impl::prepareColliders(double t0, double t1) {
  stepColliders.clear();
  std::size_t meshIndex = 0;
  for (const Collider& c : s.colliders) {
    detail::StepCollider sc;
    sc.type = c.type;
    const bool onPath = !c.path.empty();
    sc.center = onPath ? c.center + c.path.at(t1) : c.center;
    sc.halfExtent = c.halfExtent;
    sc.keep = 1.0f - c.friction;
    // A turning body (a dynamic object's trajectory) turns its frame about its centre.
    const glm::quat rotation = onPath ? glm::normalize(c.path.rotationAt(t1) * c.rotation) : c.rotation;
    switch (c.type) {
      case Collider::Type::kPlane:
        sc.frame = glm::transpose(glm::mat3_cast(rotation));
        break;
      case Collider::Type::kSphere:
        sc.up = rotation * glm::vec3(0, 1, 0);
        break;
      case Collider::Type::kBox:
        sc.frame = glm::mat3_cast(rotation);
        break;
      case Collider::Type::kMesh:
        // A moving mesh: the particle's step is tested in the mesh's frame (start against where the
        // mesh was, end against where it is), so a sweeping mesh pushes smoke it passes through.
        sc.mesh = meshIndex++;
        sc.offset0 = onPath ? c.path.at(t0) : glm::vec3(0.0f);
        sc.offset1 = onPath ? c.path.at(t1) : glm::vec3(0.0f);
        sc.velocity = (sc.offset1 - sc.offset0) / static_cast<float>(t1 - t0);
        break;
    }
    stepColliders.push_back(sc);
  }
}

// Puts particles [begin, end) back outside every collider; returns the number of contacts.
// `prev` (x, y, z arrays indexed from `begin`) is where the particles were before they moved: mesh
// colliders test the segment, so a fast particle cannot tunnel through a thin wall.
std::size_t Simulator::Impl::collide(std::size_t begin, std::size_t end, const float* const* prev) {
  std::size_t contacts = 0;
  const std::size_t n = end - begin;
  float* X = px.data() + begin;
  float* Y = py.data() + begin;
  float* Z = pz.data() + begin;
  float* VX = vx.data() + begin;
  float* VY = vy.data() + begin;
  float* VZ = vz.data() + begin;
  float* R = radii.data() + begin;
  // Each particle's collision radius, once for all colliders.
  collisionRadii(s.collisionRadius, size0.data() + begin, age.data() + begin, life.data() + begin, R, n);
  for (const detail::StepCollider& c : stepColliders) {
    switch (c.type) {
      case Collider::Type::kPlane:
        contacts += collidePlane(c.frame, c.center, c.halfExtent, c.keep, X, Y, Z, VX, VY, VZ, R, n);
        break;
      case Collider::Type::kSphere:
        contacts += collideSphere(c.center, c.halfExtent.x, c.up, c.keep, X, Y, Z, VX, VY, VZ, R, n);
        break;
      case Collider::Type::kBox:
        contacts += collideBox(c.frame, c.center, c.halfExtent, c.keep, X, Y, Z, VX, VY, VZ, R, n);
        break;
      case Collider::Type::kMesh: {
        const detail::MeshGrid& m = meshes[c.mesh];
        const float* OX = prev[0];
        const float* OY = prev[1];
        const float* OZ = prev[2];
        const float extent = std::max(1.0f, glm::length(m.hi - m.lo));
        for (std::size_t i = 0; i < n; ++i) {
          const glm::vec3 p = glm::vec3(OX[i], OY[i], OZ[i]) - c.offset0, q = glm::vec3(X[i], Y[i], Z[i]) - c.offset1;
          float along;
          std::uint32_t tri;
          if (!m.firstHit(p, q, along, tri)) continue;
          glm::vec3 nrm = m.n[tri];
          if (glm::dot(p - m.a[tri], nrm) < 0.0f) nrm = -nrm;  // the side it came from
          const glm::vec3 hit = p + (q - p) * along;
          const glm::vec3 at = hit + nrm * 1e-4f * extent + c.offset1;
          X[i] = at.x, Y[i] = at.y, Z[i] = at.z;
          // Lose the velocity into the surface relative to the moving body.
          glm::vec3 v = glm::vec3(VX[i], VY[i], VZ[i]) - c.velocity;
          const float vn = glm::dot(v, nrm);
          if (vn < 0.0f) v = (v - vn * nrm) * c.keep;
          v += c.velocity;
          VX[i] = v.x, VY[i] = v.y, VZ[i] = v.z;
          ++contacts;
        }
        break;
      }
    }
  }
  return contacts;
}

}  // namespace puff::sim
