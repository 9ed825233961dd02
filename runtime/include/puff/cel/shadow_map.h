// Shadows from a light-space map (Style::shadowMethod kMap): the casters (puffs as nailboards,
// opaque objects as meshes) drawn from the light into a depth map with per-caster ids, looked up by
// the receivers' lit passes (shaders/cel/shadow_map.glsl). One pass over the casters at the map's
// resolution replaces the volumes' stencil count and the receivers' second pass.
//
// What a texel holds: the light-space depth where the nearest caster's shadow STARTS, and that
// caster's id. A puff's shadow starts behind its far side (its depth map mirrored through the
// billboard plane, as the shadow volumes take it) plus Style::shadowBias diameters; an object's at
// its near surface. A receiver is shadowed by a caster other than itself whose shadow starts at
// least a texel's depth before it and no more than Style::shadowLength before it. A puff never
// shadows itself; neither does an object.
//
// The light's frame is orthographic along the light, fitted to the casters' bounds. Its size comes
// from the screen: texels per world unit = Style::shadowMapScale x screen pixels per world unit at
// the casters' centre, so a map texel is about a pixel where the shadows fall (chooseShadowMapSize).
//
// A frame with a shadow map, as a host draws it (render::detail::CelPath does this):
//   1. NailboardRenderer::upload(particles); ShadowMap::prepare(eyeFrame, casterBounds, style);
//   2. ShadowMap::beginCasters(); NailboardRenderer::drawShadowCasters(style);
//      OpaqueRenderer::drawCasters(); then rebind the host's framebuffer and viewport;
//   3. eyeFrame.shadow = ShadowMap::lookup(); FrameBlock::upload(eyeFrame); ShadowMap::bind();
//   4. OpaqueRenderer::draw(kLit); NailboardRenderer::drawNailboards(style, kLit).
#pragma once

#include <cstdint>
#include <limits>
#include <span>

#include <glm/vec3.hpp>

#include <puff/cel/frame.h>
#include <puff/cel/types.h>
#include <puff/core/gl.h>

namespace puff::cel {

/// An axis-aligned box in world space; empty until something is added.
struct Bounds {
  glm::vec3 lo{std::numeric_limits<float>::max()};
  glm::vec3 hi{std::numeric_limits<float>::lowest()};
  void add(const glm::vec3& p);
  void add(const Bounds& b);
  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
};

/// The box around every puff drawn (position +- half its size; zero sizes left out).
Bounds particleBounds(std::span<const Particle> particles);

/// Ids the map stores: 0 nothing, a puff its particle index + 1, an opaque object kObjectIdBase + its index.
constexpr std::uint32_t kObjectIdBase = 0x80000000u;

/// The map for one frame: the light's frame the casters are drawn with, its size, and the lookup the
/// receivers' frame carries. A pure function of its inputs (no GL): chooseShadowMap.
struct ShadowMapPlan {
  Frame light;  ///< orthographic along the light; viewport = the map
  int width = 0, height = 0;
  ShadowLookup lookup;         ///< for the eye's Frame::shadow
  float texelsPerUnit = 0.0f;  ///< world resolution of the map
};

/// Plans the map over `casters` for `eye`: texels per world unit = style.shadowMapScale x the eye's
/// pixels per world unit at the casters' centre (at least its near plane away), rounded to a quarter
/// octave (2^(k/4)), each side at most `maxSize` (the resolution drops evenly when the casters would
/// need more) and at least 16. The region starts on a texel lattice fixed to the world, so shadows
/// of still casters keep their texels while other casters or the camera move.
/// Empty casters give a 16 x 16 map that shadows nothing.
/// `reach` (optional): every caster's box, the ones left out of the fit included (planes): the
/// map's depth range covers them too, so they cast wherever the map reaches (depth costs nothing).
ShadowMapPlan chooseShadowMap(const Frame& eye, const Bounds& casters, const Style& style, int maxSize = 4096,
                              const Bounds& reach = {});

class ShadowMap {
 public:
  /// Needs a current GL 4.5 context. `bindings`: the renderers' (frameBlock, shadowMapDepth and
  /// shadowMapIds are used).
  explicit ShadowMap(const Bindings& bindings = {});
  /// Plans this frame's map (chooseShadowMap, at most GL_MAX_TEXTURE_SIZE and 4096 a side) and makes
  /// its textures that size (reallocated only when the size changes). Changes no bound GL state.
  void prepare(const Frame& eye, const Bounds& casters, const Style& style, const Bounds& reach = {});
  /// Binds the map's framebuffer and viewport, clears it (depth 1, id 0) and uploads the light's frame
  /// to uniform binding `frameBlock`: the caster passes draw next. The caller rebinds its own
  /// framebuffer, viewport and frame block afterwards.
  /// Leaves (a begin call: the caster passes need it so): the draw framebuffer = the map's; the
  /// viewport = (0, 0, plan().width, plan().height); scissor test and rasterizer discard off; depth write mask on;
  /// draw buffer 0's colour write mask on; uniform binding `frameBlock` = the light's block; units
  /// `shadowMapDepth` and `shadowMapIds` with no texture on any target (the map must not be read
  /// while it is drawn). The read framebuffer is untouched. (GL_STENCIL_REF then reads back 0, front
  /// and back: the query clamps the stored reference to the bound framebuffer's stencil bits, and
  /// the map has none; the stored value is the host's and reads so again on its framebuffer.)
  void beginCasters();
  /// The receivers' lookup: put it in the eye's Frame::shadow before FrameBlock::upload.
  const ShadowLookup& lookup() const { return plan_.lookup; }
  const ShadowMapPlan& plan() const { return plan_; }
  /// Binds the map's depth and ids to units `shadowMapDepth` and `shadowMapIds` (cel/bindings.h)
  /// for the receivers, with no sampler object there. Leaves: those units' 2D textures = the map's
  /// and their sampler bindings = 0.
  void bind() const;

 private:
  Bindings bindings_;
  ShadowMapPlan plan_;
  FrameBlock lightBlock_;
  core::Framebuffer fbo_;
  core::Texture depth_, ids_;
  int allocatedW_ = 0, allocatedH_ = 0;
};

}  // namespace puff::cel
