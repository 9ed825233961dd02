// Level of detail: quadric-error decimation through OpenMesh's Decimater.
#include <puff/mesh/mesh.h>

#include <cstdint>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#pragma GCC diagnostic pop

namespace puff::mesh {
namespace {

using OmTriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

}  // namespace

TriMesh decimate(const TriMesh& mesh, std::size_t targetFaces, DecimatedNormals normals) {
  if (mesh.triangles.size() <= targetFaces || mesh.triangles.empty()) return mesh;

  OmTriMesh om;
  // Halfedge collapses keep the surviving vertex where it was, so each kept vertex only needs to
  // remember where it came from: its color (and, kept, its normal) is carried over by that index.
  OpenMesh::VPropHandleT<std::uint32_t> source;
  om.add_property(source);
  std::vector<OmTriMesh::VertexHandle> vh;
  vh.reserve(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    vh.push_back(om.add_vertex(OmTriMesh::Point(p.x, p.y, p.z)));
    om.property(source, vh.back()) = std::uint32_t(i);
  }
  for (const glm::uvec3& t : mesh.triangles) {
    PUFF_CHECK(t[0] < vh.size() && t[1] < vh.size() && t[2] < vh.size());
    if (om.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid()) continue;
    // Non-manifold input: give the face its own vertex copies, as OpenMesh's importer does, so
    // it is decimated with the rest rather than dropped.
    OmTriMesh::VertexHandle copy[3];
    for (int k = 0; k < 3; ++k) {
      copy[k] = om.add_vertex(om.point(vh[t[k]]));
      om.property(source, copy[k]) = t[k];
    }
    om.add_face(copy[0], copy[1], copy[2]);
  }

  // ModNormalFlipping compares face normals before and after each collapse.
  om.request_face_normals();
  om.update_face_normals();
  {
    OpenMesh::Decimater::DecimaterT<OmTriMesh> decimater(om);
    OpenMesh::Decimater::ModQuadricT<OmTriMesh>::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<OmTriMesh>::Handle noFlip;
    decimater.add(quadric);  // the priority: least quadric error first, no error bound
    decimater.add(noFlip);   // a veto: refuse collapses that turn a face over
    PUFF_CHECK(decimater.initialize());
    decimater.decimate_to_faces(0, targetFaces);
    // Inside the scope: the decimater owns the status flags that mark what to collect.
    om.garbage_collection();
  }

  const bool keepNormals = normals == DecimatedNormals::kFromSource;
  PUFF_CHECK(!keepNormals || mesh.normals.size() == mesh.positions.size());
  TriMesh out;
  out.positions.reserve(om.n_vertices());
  if (mesh.hasColors()) out.colors.reserve(om.n_vertices());
  if (keepNormals) out.normals.reserve(om.n_vertices());
  for (const auto v : om.vertices()) {
    const OmTriMesh::Point& p = om.point(v);
    out.positions.emplace_back(p[0], p[1], p[2]);
    const std::uint32_t from = om.property(source, v);
    if (mesh.hasColors()) out.colors.push_back(mesh.colors[from]);
    if (keepNormals) out.normals.push_back(mesh.normals[from]);
  }
  out.triangles.reserve(om.n_faces());
  for (const auto f : om.faces()) {
    glm::uvec3 t(0);
    int k = 0;
    for (const auto v : om.fv_range(f)) t[k++] = std::uint32_t(v.idx());
    out.triangles.push_back(t);
  }
  // Not re-normalized: a LOD must keep the scale of the mesh it stands in for.
  if (!keepNormals) computeNormals(out);
  return out;
}

}  // namespace puff::mesh
