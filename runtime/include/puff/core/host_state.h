// An opt-in guard that gives a host its GL state back after Puff's calls (docs/cel-rendering.md,
// "Host state"; docs/media.md, "Host state").
//
// Puff's draw calls do not query the host's state: each sets what it relies on and leaves what its
// header lists (and nothing else). A host that wants its state back wraps the Puff calls of a frame
// in one HostStateGuard:
//
//   {
//     puff::core::HostStateGuard guard;  // saves the state below
//     block.upload(frame); ramp.bind(); nailboards.drawNailboards(style, kLit); ...
//   }                                    // restores it
//
// Why a guard around the whole block rather than a restore in every call: a frame draws several
// Puff passes back to back (lit, volumes, shadowed; draw, compose) which set the same state; a
// restore per call would undo each pass's state only for the next pass to set it again, and would
// need a query per item per call. The guard queries once and restores once. Its cost: the queries
// (glGet*) are answered from the driver's client-side copy of the state on desktop drivers (no GPU
// round trip), about 200 of them for the default extent; but a driver that runs GL on its own thread
// (Mesa's glthread, NVIDIA's threaded optimization) must finish the queued calls before it answers
// one, which is why the guard is opt-in. On destruction it queries again and sets only the items that
// differ: a binding restore costs one GL call each, so it pays for what Puff changed, not for all.
//
// What it saves and restores: the program, vertex array, draw and read framebuffers; the generic
// array, uniform and shader storage buffer bindings and the indexed uniform and storage bindings
// [0, extent) (buffer, offset, size); on texture units [0, extent) the texture of every target (1D,
// 2D, 3D, 1D/2D arrays, rectangle, cube map, cube map array, buffer, 2D multisample and its array)
// and the sampler object; the active texture unit; blending (enable, functions, equations per draw
// buffer [0, extent); the blend colour); depth (test, function, write mask, range, clamp; the
// bounds test and bounds where GL_EXT_depth_bounds_test is there); stencil (test, function,
// reference, value mask, the three operations and the write mask, front and back); culling
// (enable, face, front face); sRGB conversion; scissor (enable, box); the viewport; colour masks per
// draw buffer; polygon offset (fill, line and point enables, factor, units) and polygon mode;
// multisample, sample coverage, alpha to coverage and to one, sample shading, sample mask,
// rasterizer discard, primitive restart (both), dither, logic op enable, program point size,
// seamless cube maps; pixel pack and unpack alignment.
// Not saved (no Puff call changes them): clear values, other pixel store parameters, vertex
// attribute state outside a vertex array, image units, atomic counter and transform feedback
// bindings, queries, the viewport array beyond index 0.
#pragma once

#include <memory>

#include <puff/core/binding_base.h>

namespace puff::core {

/// Which indexed points a HostStateGuard saves: [0, n) of each. The defaults cover every default
/// point of cel::Bindings and media::Bindings; cel::guardExtent / media::guardExtent give the
/// extent of chosen ones (GuardExtent::cover joins two).
struct GuardExtent {
  int textureUnits = static_cast<int>(BindingBase{}.textureUnit + kTextureUnitSpan);        ///< units 0-24
  int uniformBuffers = static_cast<int>(BindingBase{}.uniformBuffer + kUniformBufferSpan);  ///< bindings 0-13
  int storageBuffers = static_cast<int>(BindingBase{}.storageBuffer + kStorageBufferSpan);  ///< bindings 0-6
  int drawBuffers = 4;  ///< per-draw-buffer blend state and colour masks 0-3
  /// The larger of each.
  GuardExtent cover(const GuardExtent& other) const;
};

/// Saves the host's GL state (above) on construction and restores it on destruction (or at
/// restore(), once). Needs the same current GL context on both ends; not copyable. A texture or
/// buffer name saved there whose object the guarded calls deleted (one of Puff's, made again for
/// another size, samples or format) comes back as 0, not as a deleted name.
class HostStateGuard {
 public:
  explicit HostStateGuard(const GuardExtent& extent = {});
  ~HostStateGuard();
  HostStateGuard(const HostStateGuard&) = delete;
  HostStateGuard& operator=(const HostStateGuard&) = delete;

  /// Restores now; the destructor then does nothing.
  void restore();

 private:
  struct Saved;
  std::unique_ptr<Saved> saved_;
};

}  // namespace puff::core
