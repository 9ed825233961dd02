// Opaque scene objects for the cel frame: ground plane, boxes, spheres and triangle meshes, lit
// like the puffs (cel through the ramp q, or smooth Lambert), writing the frame's linear depth and
// receiving billboard shadows (drawn again with ShadePass::kShadowed where the stencil says so).
//
//   lit:      albedo * (K_a(x, y) + K_L * q(max(0, N.L)))     (cel)
//             albedo * (K_a(x, y) + K_L * max(0, N.L))        (smooth)
//   shadowed: albedo * K_a(x, y)
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/cel/shadow_map.h>
#include <puff/cel/volume_clip.h>

namespace puff::cel {

/// Triangles in object space with per-vertex normals; indices are counter-clockwise from outside.
/// (puff::mesh makes the primitives; puff::render turns its meshes into these.)
struct TriangleMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  ///< same count as positions, unit length
  std::vector<std::uint32_t> indices;
};

struct OpaqueObject {
  std::string name;  ///< for messages
  std::shared_ptr<const TriangleMesh> mesh;
  glm::mat4 transform{1.0f};     ///< object -> world, affine and invertible; normals use its inverse
                                 ///< transpose (a mirroring transform is fine)
  glm::vec3 albedo{0.6038273f};  ///< scene-linear, >= 0 (display 0.8 by default; encoded for Eq. 2 inside)
  bool cel = true;               ///< q ramp (true) or smooth Lambert
};

class OpaqueRenderer {
 public:
  /// Builds the programs and points them at `bindings` (validated: cel::validate). Needs a current
  /// GL 4.5 context. Leaves no bound state changed.
  static Result<std::unique_ptr<OpaqueRenderer>> create(const Bindings& bindings = {});
  ~OpaqueRenderer();

  /// Uploads the objects' meshes (shared meshes once). Replaces the previous set. Fails, keeping
  /// the previous set, on a missing or empty mesh, an index out of range, a normal count unlike the
  /// position count, a zero or non-finite normal or position, a non-finite, non-affine or singular
  /// transform, or a negative or non-finite albedo: "opaque object 'NAME': problem" ('#i' when
  /// unnamed).
  Result<void> setObjects(std::vector<OpaqueObject> objects);

  /// Moves object `index` (in the order given to setObjects) to `transform`, for animated objects.
  /// The same checks as setObjects; on failure the object stays where it was.
  Result<void> setTransform(std::size_t index, const glm::mat4& transform);

  /// Draws every object into the current framebuffer and viewport (the host's glViewport must match
  /// the frame's Viewport) with the bound FrameBlock, ramp (unit `ramp`) and gradient (unit `gradient`), writing
  /// depth in the frame's convention. kLit: depth nearer (LESS; GREATER for reversed-z) + write.
  /// kShadowed: depth EQUAL, stencil != 0 (not written), no depth write, ambient colour only.
  /// kDepthOnly: depth nearer + write, no colour. All three passes
  /// compute depth identically, so kShadowed matches what kLit or kDepthOnly wrote. Sets every GL
  /// state it relies on (culling off: back faces are lit with the normal turned to the viewer).
  /// Leaves (nailboards.h's terms): the pass state; no program, no vertex array; write masks on;
  /// front face GL_CCW; and per pass what NailboardRenderer::drawNailboards leaves (depth function,
  /// stencil). Binds no texture or buffer (it reads the frame block, the ramp, the gradient and the
  /// shadow map where the host bound them). Nothing with no objects.
  void draw(ShadePass pass);

  /// Counts every object's shadow volume into the stencil buffer (Style::shadowMethod kVolumes, next
  /// to NailboardRenderer::drawShadowVolumes, after the lit passes and before the kShadowed ones):
  /// depth-fail with caps and depth clamp, each triangle swept style.shadowLength world units along
  /// the light (shaders/cel/opaque_volume.geom). Open meshes cast too: a triangle facing away from the
  /// light casts as if it faced it. Objects shadow each other, the puffs, and themselves where the
  /// light truly cannot reach (a face turned away from the light, or behind another part of the same
  /// object); a face toward the light is never in its own volume (the volume's depth is pushed back a
  /// hair, see opaque_volume.frag). `floorPlane` as NailboardRenderer::drawShadowVolumes: volumes end
  /// just past it and objects wholly on or below it are skipped. Leaves colour and depth untouched;
  /// drawCalls: objects drawn. `clip`: as NailboardRenderer::drawShadowVolumes's.
  /// Leaves: the pass state; no program, no vertex array; write masks on; front face GL_CCW; depth
  /// function GL_LESS; stencil test off with function GL_ALWAYS, reference 0, value mask 0xFF, front
  /// operations (GL_KEEP, GL_DECR_WRAP, GL_KEEP) and back (GL_KEEP, GL_INCR_WRAP, GL_KEEP); the
  /// scissor box and depth bounds as NailboardRenderer::drawShadowVolumes. Nothing with no objects,
  /// a shadow length <= 0 or clip.nothing.
  DrawStats drawShadowVolumes(const Style& style, const glm::vec4& floorPlane = glm::vec4(0.0f),
                              const VolumeClip& clip = VolumeClip{});

  /// Draws every object into a shadow map (after ShadowMap::beginCasters): its near surface's depth
  /// in the light's frame and its id, kObjectIdBase + its index. Depth LESS + write.
  /// Leaves: the pass state; no program, no vertex array; write masks on; depth function GL_LESS;
  /// stencil test off. Nothing with no objects.
  void drawCasters();

  /// Draws every object's triangles with the caller's `program` and nothing else: binds the vertex
  /// array (attribute 0 position, 1 normal, object space) and per object sets uniform location 0 (mat4
  /// model: object -> world) and location 5 (uint caster id, kObjectIdBase + index): the program must
  /// declare and use both (`layout(location = 0) uniform mat4`, `layout(location = 5) uniform uint`). The caller sets
  /// the state and the program's other uniforms (the cel reference's own shadow passes use it).
  /// Leaves: no vertex array bound (and `program`'s two uniforms set).
  void drawGeometry(core::GlId program) const;

  /// How many objects there are, and object `index`'s world-space box (its mesh through its transform).
  std::size_t count() const;
  Bounds worldBounds(std::size_t index) const;

 private:
  OpaqueRenderer();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace puff::cel
