// Opaque scene objects: primitives, validation, one packed upload, and the three shade passes.
#include <puff/cel/opaque.h>
#include <puff/cel/pass_state.h>
#include <puff/cel/volume_clip.h>
#include <puff/core/colour.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <numbers>
#include <tuple>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <puff/core/shader.h>
#include <puff/gl_api.h>
#include <puff/shader_contract.h>

#include "bindings_gl.h"

namespace puff::cel {

// ---- renderer ------------------------------------------------------------------------------------

namespace {

struct Vertex {
  glm::vec3 position, normal;
};

// Where one distinct mesh lies in the packed buffers. Its triangles with adjacency (6 indices per
// triangle) start at firstIndex * 2 in the adjacency buffer.
struct MeshRange {
  GLsizei indexCount = 0;
  std::size_t firstIndex = 0;
  GLint baseVertex = 0;
};

// Each triangle with the vertex across each of its edges, in GL_TRIANGLES_ADJACENCY order (vertex 0,
// across edge 0-1, vertex 1, across 1-2, vertex 2, across 2-0). Vertices are welded by position
// first: a box's faces have their own vertices (split normals) but share edges. The neighbour across
// edge a -> b is the one triangle holding b -> a; an edge with none (an open mesh's border), with
// more than one, or used twice the same way (a non-manifold or inconsistently wound mesh) gets the
// triangle's own third vertex, which opaque_volume.geom takes for "no neighbour".
std::vector<std::uint32_t> adjacencyIndices(const TriangleMesh& m) {
  std::map<std::tuple<float, float, float>, std::uint32_t> weldIndex;
  std::vector<std::uint32_t> weld(m.positions.size());
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    const glm::vec3& p = m.positions[v];
    weld[v] = weldIndex.try_emplace({p.x, p.y, p.z}, static_cast<std::uint32_t>(weldIndex.size())).first->second;
  }
  struct Across {
    std::uint32_t vertex = 0;  // original index of the third vertex of the triangle holding the edge
    int uses = 0;
  };
  std::map<std::pair<std::uint32_t, std::uint32_t>, Across> edges;  // welded directed edge
  const std::size_t triangles = m.indices.size() / 3;
  for (std::size_t t = 0; t < triangles; ++t) {
    const std::uint32_t* tri = &m.indices[3 * t];
    for (int e = 0; e < 3; ++e) {
      Across& a = edges[{weld[tri[e]], weld[tri[(e + 1) % 3]]}];
      a.vertex = tri[(e + 2) % 3];
      ++a.uses;
    }
  }
  std::vector<std::uint32_t> out;
  out.reserve(triangles * 6);
  for (std::size_t t = 0; t < triangles; ++t) {
    const std::uint32_t* tri = &m.indices[3 * t];
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = weld[tri[e]], b = weld[tri[(e + 1) % 3]];
      const auto back = edges.find({b, a});
      const bool paired = back != edges.end() && back->second.uses == 1 && edges.at({a, b}).uses == 1;
      out.push_back(tri[e]);
      out.push_back(paired ? back->second.vertex : tri[(e + 2) % 3]);
    }
  }
  return out;
}

struct DrawItem {
  std::size_t mesh = 0;  // index into Impl::ranges
  glm::mat4 model{1.0f};
  glm::mat3 normalMatrix{1.0f};
  glm::vec3 albedo{0.8f};
  bool cel = true;
  bool mirrored = false;  // det < 0: the transform turns counter-clockwise into clockwise
};

// Uniform locations of shaders/cel/opaque.{vert,frag} and opaque_volume.{vert,geom,frag}.
constexpr GLint kModelLoc = shader::loc::kOpaqueModel, kNormalMatrixLoc = shader::loc::kOpaqueNormalMatrix,
                kAlbedoLoc = shader::loc::kOpaqueAlbedo, kCelLoc = shader::loc::kOpaqueCel,
                kPassLoc = shader::loc::kOpaquePass, kIdLoc = shader::loc::kOpaqueId;
constexpr GLint kVolumeLengthLoc = shader::loc::kVolumeLength, kVolumeFloorLoc = shader::loc::kVolumeFloor,
                kVolumeBiasLoc = shader::loc::kVolumeBias;

std::string describe(const OpaqueObject& o, std::size_t i) {
  std::string s = "opaque object ";
  if (o.name.empty()) {
    s += '#';
    s += std::to_string(i);
  } else {
    s += '\'';
    s += o.name;
    s += '\'';
  }
  return s;
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Result<void> validateMesh(const TriangleMesh& m) {
  if (m.positions.empty() || m.indices.empty()) return Error{"mesh has no triangles"};
  if (m.normals.size() != m.positions.size()) {
    return Error{"mesh has " + std::to_string(m.normals.size()) + " normals for " + std::to_string(m.positions.size()) +
                 " positions"};
  }
  if (m.indices.size() % 3 != 0) {
    return Error{"mesh index count " + std::to_string(m.indices.size()) + " is not a multiple of 3"};
  }
  if (m.positions.size() > static_cast<std::size_t>(INT32_MAX)) return Error{"mesh has too many vertices"};
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    if (!finite(m.positions[i])) return Error{"position " + std::to_string(i) + " is not finite"};
    if (!finite(m.normals[i])) return Error{"normal " + std::to_string(i) + " is not finite"};
    // A zero normal would turn into NaN colour in the shader.
    if (glm::dot(m.normals[i], m.normals[i]) < 1e-12f) return Error{"normal " + std::to_string(i) + " is zero"};
  }
  for (std::size_t i = 0; i < m.indices.size(); ++i) {
    if (m.indices[i] >= m.positions.size()) {
      return Error{"indices[" + std::to_string(i) + "] = " + std::to_string(m.indices[i]) + " is out of range for " +
                   std::to_string(m.positions.size()) + " vertices"};
    }
  }
  return {};
}

Result<DrawItem> validateObject(const OpaqueObject& o) {
  DrawItem d;
  for (int c = 0; c < 4; ++c) {
    if (!finite(glm::vec3(o.transform[c])) || !std::isfinite(o.transform[c][3])) {
      return Error{"transform is not finite"};
    }
  }
  if (o.transform[0][3] != 0.0f || o.transform[1][3] != 0.0f || o.transform[2][3] != 0.0f ||
      o.transform[3][3] != 1.0f) {
    return Error{"transform is not affine (its last row must be 0 0 0 1)"};
  }
  const glm::dmat3 a(glm::mat3(o.transform));
  const double det = glm::determinant(a);
  const double scale = glm::length(a[0]) * glm::length(a[1]) * glm::length(a[2]);
  // Relative test: a transform that flattens an axis has no normal matrix.
  if (!(std::abs(det) > 1e-9 * scale)) return Error{"transform is singular (an axis is scaled to zero)"};
  if (!finite(o.albedo)) return Error{"albedo is not finite"};
  if (o.albedo.x < 0.0f || o.albedo.y < 0.0f || o.albedo.z < 0.0f) return Error{"albedo is negative"};
  d.model = o.transform;
  d.normalMatrix = glm::mat3(glm::transpose(glm::inverse(a)));
  d.albedo = core::linearToSrgb(o.albedo);  // Eq. 2 takes display values
  d.cel = o.cel;
  d.mirrored = det < 0.0;
  return d;
}

}  // namespace

struct OpaqueRenderer::Impl {
  core::Program program, caster, volume;
  std::vector<std::pair<glm::vec3, glm::vec3>> meshBounds;  // object space, per entry of `ranges`
  core::VertexArray vao, adjacencyVao;                      // the same vertices; triangles, or triangles with adjacency
  core::Buffer vbo, ibo, adjacency;
  std::vector<MeshRange> ranges;
  std::vector<DrawItem> items;
};

OpaqueRenderer::OpaqueRenderer() : impl_(std::make_unique<Impl>()) {}
OpaqueRenderer::~OpaqueRenderer() = default;

Result<std::unique_ptr<OpaqueRenderer>> OpaqueRenderer::create(const Bindings& bindings) {
  if (auto ok = validate(bindings); !ok) return ok.error();
  PUFF_TRY_ASSIGN(auto program, core::buildProgram({"cel/opaque.vert", "cel/opaque.frag"}));
  PUFF_TRY_ASSIGN(auto caster, core::buildProgram({"cel/opaque.vert", "cel/opaque_caster.frag"}));
  PUFF_TRY_ASSIGN(auto volume,
                  core::buildProgram({"cel/opaque_volume.vert", "cel/opaque_volume.geom", "cel/opaque_volume.frag"}));
  std::unique_ptr<OpaqueRenderer> r(new OpaqueRenderer);
  Impl& im = *r->impl_;
  im.program = std::move(program);
  im.caster = std::move(caster);
  im.volume = std::move(volume);
  for (const GLuint p : {im.program.get(), im.caster.get(), im.volume.get()}) detail::assignBindPoints(p, bindings);
  im.vao = core::makeVertexArray("opaque objects: vertex array");
  im.adjacencyVao = core::makeVertexArray("opaque objects: adjacency vertex array");
  const GLuint offsets[] = {offsetof(Vertex, position), offsetof(Vertex, normal)};
  for (const GLuint vao : {im.vao.get(), im.adjacencyVao.get()}) {
    for (GLuint a = 0; a < 2; ++a) {
      glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE, offsets[a]);
      glVertexArrayAttribBinding(vao, a, 0);
      glEnableVertexArrayAttrib(vao, a);
    }
  }
  if (auto err = core::drainGlErrors(); !err.empty())
    return Error{"GL error while creating the opaque renderer: " + err};
  return r;
}

Result<void> OpaqueRenderer::setTransform(std::size_t index, const glm::mat4& transform) {
  Impl& im = *impl_;
  if (index >= im.items.size()) {
    return Error{"opaque object #" + std::to_string(index) + ": there are only " + std::to_string(im.items.size())};
  }
  OpaqueObject probe;
  probe.transform = transform;
  probe.albedo = im.items[index].albedo;
  auto item = validateObject(probe);
  if (!item) return Error{"opaque object #" + std::to_string(index) + ": " + item.error().message};
  DrawItem& d = im.items[index];
  d.model = item->model;
  d.normalMatrix = item->normalMatrix;
  d.mirrored = item->mirrored;
  return {};
}

Result<void> OpaqueRenderer::setObjects(std::vector<OpaqueObject> objects) {
  // Validate everything before touching GL, so a bad object leaves the previous set in place.
  std::unordered_map<const TriangleMesh*, std::size_t> meshIndex;
  std::vector<const TriangleMesh*> meshes;
  std::vector<DrawItem> items;
  items.reserve(objects.size());
  std::size_t vertexCount = 0, indexCount = 0;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const OpaqueObject& o = objects[i];
    if (!o.mesh) return Error{describe(o, i) + ": has no mesh"};
    auto [it, inserted] = meshIndex.try_emplace(o.mesh.get(), meshes.size());
    if (inserted) {
      if (auto ok = validateMesh(*o.mesh); !ok) return Error{describe(o, i) + ": " + ok.error().message};
      meshes.push_back(o.mesh.get());
      vertexCount += o.mesh->positions.size();
      indexCount += o.mesh->indices.size();
    }
    auto item = validateObject(o);
    if (!item) return Error{describe(o, i) + ": " + item.error().message};
    item->mesh = it->second;
    items.push_back(*item);
  }
  if (vertexCount > static_cast<std::size_t>(INT32_MAX) || indexCount > static_cast<std::size_t>(INT32_MAX)) {
    return Error{"opaque objects: more than 2^31 vertices or indices in all"};
  }

  // Every distinct mesh goes into one vertex and one index buffer; draws pick theirs with a first
  // index and a base vertex, so a shared mesh costs its memory once.
  std::vector<Vertex> vertices;
  std::vector<std::uint32_t> indices, adjacency;
  vertices.reserve(vertexCount);
  indices.reserve(indexCount);
  adjacency.reserve(indexCount * 2);
  std::vector<MeshRange> ranges;
  ranges.reserve(meshes.size());
  std::vector<std::pair<glm::vec3, glm::vec3>> meshBounds;
  for (const TriangleMesh* m : meshes) {
    glm::vec3 lo = m->positions.front(), hi = lo;
    for (const glm::vec3& p : m->positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    meshBounds.emplace_back(lo, hi);
    ranges.push_back({static_cast<GLsizei>(m->indices.size()), indices.size(), static_cast<GLint>(vertices.size())});
    for (std::size_t v = 0; v < m->positions.size(); ++v) vertices.push_back({m->positions[v], m->normals[v]});
    indices.insert(indices.end(), m->indices.begin(), m->indices.end());
    const std::vector<std::uint32_t> adj = adjacencyIndices(*m);
    adjacency.insert(adjacency.end(), adj.begin(), adj.end());
  }
  Impl& im = *impl_;
  // Fresh buffers each time: immutable storage sized to this set.
  im.vbo = core::makeBuffer("opaque objects: vertices");
  im.ibo = core::makeBuffer("opaque objects: indices");
  im.adjacency = core::makeBuffer("opaque objects: adjacency indices");
  if (!vertices.empty()) {
    glNamedBufferStorage(im.vbo.get(), static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(), 0);
    glNamedBufferStorage(im.ibo.get(), static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)), indices.data(),
                         0);
    glNamedBufferStorage(im.adjacency.get(), static_cast<GLsizeiptr>(adjacency.size() * sizeof(std::uint32_t)),
                         adjacency.data(), 0);
  }
  glVertexArrayVertexBuffer(im.vao.get(), 0, im.vbo.get(), 0, sizeof(Vertex));
  glVertexArrayElementBuffer(im.vao.get(), im.ibo.get());
  glVertexArrayVertexBuffer(im.adjacencyVao.get(), 0, im.vbo.get(), 0, sizeof(Vertex));
  glVertexArrayElementBuffer(im.adjacencyVao.get(), im.adjacency.get());
  im.ranges = std::move(ranges);
  im.meshBounds = std::move(meshBounds);
  im.items = std::move(items);
  if (auto err = core::drainGlErrors(); !err.empty()) return Error{"opaque objects: GL error while uploading: " + err};
  return {};
}

void OpaqueRenderer::draw(ShadePass pass) {
  const core::DebugGroup group(pass == ShadePass::kLit        ? "opaque objects (lit)"
                               : pass == ShadePass::kShadowed ? "opaque objects (shadowed)"
                                                              : "opaque objects (depth)");
  Impl& im = *impl_;
  if (im.items.empty()) return;
  const core::DrawBufferZero drawBuffers;  // draw buffer 0 alone: a host's other attachments stay as they are

  // Every state this pass relies on is set here; nothing is inherited from the host or a pass.
  // Culling stays off: planes show both sides; the fragment shader turns back-face normals around.
  resetPassState();
  const int passMode = applyShadePass(pass);

  const GLuint program = im.program.get();
  glUseProgram(program);
  glProgramUniform1i(program, kPassLoc, passMode);
  glBindVertexArray(im.vao.get());
  for (const DrawItem& d : im.items) {
    const MeshRange& r = im.ranges[d.mesh];
    // A mirroring transform turns outside faces clockwise; keep gl_FrontFacing meaning "outside".
    glFrontFace(d.mirrored ? GL_CW : GL_CCW);
    glProgramUniformMatrix4fv(program, kModelLoc, 1, GL_FALSE, glm::value_ptr(d.model));
    glProgramUniformMatrix3fv(program, kNormalMatrixLoc, 1, GL_FALSE, glm::value_ptr(d.normalMatrix));
    glProgramUniform3fv(program, kAlbedoLoc, 1, glm::value_ptr(d.albedo));
    glProgramUniform1i(program, kCelLoc, d.cel ? 1 : 0);
    glProgramUniform1ui(program, kIdLoc, kObjectIdBase + static_cast<GLuint>(&d - im.items.data()));
    glDrawElementsBaseVertex(GL_TRIANGLES, r.indexCount, GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(r.firstIndex * sizeof(std::uint32_t)), r.baseVertex);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glFrontFace(GL_CCW);
  restoreWriteMasks();
}

void OpaqueRenderer::drawCasters() {
  const core::DebugGroup group("opaque objects (shadow casters)");
  Impl& im = *impl_;
  if (im.items.empty()) return;
  resetPassState();
  applyShadePass(ShadePass::kLit);  // depth LESS + write; the id is the colour
  glUseProgram(im.caster.get());
  drawGeometry(im.caster.get());
  glUseProgram(0);
  restoreWriteMasks();
}

void OpaqueRenderer::drawGeometry(GLuint program) const {
  const Impl& im = *impl_;
  if (im.items.empty()) return;
  glBindVertexArray(im.vao.get());
  for (std::size_t i = 0; i < im.items.size(); ++i) {
    const DrawItem& d = im.items[i];
    const MeshRange& r = im.ranges[d.mesh];
    glProgramUniformMatrix4fv(program, kModelLoc, 1, GL_FALSE, glm::value_ptr(d.model));
    glProgramUniform1ui(program, kIdLoc, kObjectIdBase + static_cast<GLuint>(i));
    glDrawElementsBaseVertex(GL_TRIANGLES, r.indexCount, GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(r.firstIndex * sizeof(std::uint32_t)), r.baseVertex);
  }
  glBindVertexArray(0);
}

DrawStats OpaqueRenderer::drawShadowVolumes(const Style& style, const glm::vec4& floorPlane, const VolumeClip& clip) {
  Impl& im = *impl_;
  DrawStats s;
  if (im.items.empty() || style.shadowLength <= 0.0f || clip.nothing) return s;
  const core::DrawBufferZero drawBuffers;
  const GLuint program = im.volume.get();
  glProgramUniform1f(program, kVolumeLengthLoc, style.shadowLength);
  glProgramUniform4fv(program, kVolumeFloorLoc, 1, glm::value_ptr(floorPlane));
  // Half a thousandth of a percent of the depth range: far above the rounding between this program's
  // depth and opaque.frag's for the same surface, far below any gap between surfaces that matters.
  glProgramUniform1f(program, kVolumeBiasLoc, 1e-5f);
  resetPassState();
  glUseProgram(program);
  // No far clipping of the far caps: depth clamp (the fragment shader clamps its depth too).
  glEnable(GL_DEPTH_CLAMP);
  glDepthFunc(nearerDepthFunc(boundDepthConvention()));  // depth-fail counting: a face behind fails
  glDepthMask(GL_FALSE);
  glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glEnable(GL_STENCIL_TEST);
  glStencilMask(0xFF);
  glStencilFunc(GL_ALWAYS, 0, 0xFF);
  // Depth-fail (z-fail) counting over closed volumes: faces behind the receiver count, back faces
  // up and front faces down. The geometry shader emits every face outward, counter-clockwise.
  glFrontFace(GL_CCW);
  glStencilOpSeparate(GL_BACK, GL_KEEP, GL_INCR_WRAP, GL_KEEP);
  glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_DECR_WRAP, GL_KEEP);
  glBindVertexArray(im.adjacencyVao.get());
  beginVolumeClip(clip);
  const bool haveFloor = glm::dot(glm::vec3(floorPlane), glm::vec3(floorPlane)) > 0.0f;
  for (std::size_t i = 0; i < im.items.size(); ++i) {
    const DrawItem& d = im.items[i];
    // Nothing below the floor is seen: an object wholly on or under it casts nothing visible.
    if (haveFloor) {
      const Bounds b = worldBounds(i);
      float highest = std::numeric_limits<float>::lowest();
      for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner((c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z);
        highest = std::max(highest, glm::dot(glm::vec3(floorPlane), corner) + floorPlane.w);
      }
      if (highest <= 0.0f) continue;
    }
    const MeshRange& r = im.ranges[d.mesh];
    glProgramUniformMatrix4fv(program, kModelLoc, 1, GL_FALSE, glm::value_ptr(d.model));
    glDrawElementsBaseVertex(GL_TRIANGLES_ADJACENCY, r.indexCount * 2, GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(r.firstIndex * 2 * sizeof(std::uint32_t)), r.baseVertex);
    ++s.drawCalls;
  }
  endVolumeClip();
  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_DEPTH_CLAMP);
  glDisable(GL_STENCIL_TEST);
  restoreWriteMasks();
  return s;
}

std::size_t OpaqueRenderer::count() const { return impl_->items.size(); }

Bounds OpaqueRenderer::worldBounds(std::size_t index) const {
  const Impl& im = *impl_;
  Bounds b;
  if (index >= im.items.size()) return b;
  const DrawItem& d = im.items[index];
  const auto& [lo, hi] = im.meshBounds[d.mesh];
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    b.add(glm::vec3(d.model * glm::vec4(c, 1.0f)));
  }
  return b;
}

}  // namespace puff::cel
