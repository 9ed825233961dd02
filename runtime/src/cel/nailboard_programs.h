// Internal: the nailboards' programs, each variant's uniforms found once (NailboardRenderer).
#pragma once

#include <array>
#include <string>
#include <utility>

#include <puff/cel/types.h>
#include <puff/core/error.h>
#include <puff/core/shader.h>
#include <puff/gl_api.h>

namespace puff::cel::detail {

// Which particles a draw of a four-view program takes (uTumbleShare, nailboard_vs.glsl): all, or of
// a frame whose oriented puffs take the hull from a size on (Style::hullFromPixels), the share the
// hull draws or the share the blend draws.
enum class TumbleShare : int { kAll = 0, kHull = 1, kBlend = 2 };

// The atlas's uniforms, and which particles the draw takes.
struct AtlasUniforms {
  GLint gridOrigin = -1, gridStep = -1, alignment = -1, layout = -1, geom = -1, scale = -1;
  GLint hullFrom = -1, tumbleShare = -1;
  void find(GLuint program) {
    hullFrom = glGetUniformLocation(program, "uHullFromPixels");
    tumbleShare = glGetUniformLocation(program, "uTumbleShare");
    gridOrigin = glGetUniformLocation(program, "uGridOrigin");
    gridStep = glGetUniformLocation(program, "uGridStep");
    alignment = glGetUniformLocation(program, "uAlignment");
    layout = glGetUniformLocation(program, "uAtlasLayout");
    geom = glGetUniformLocation(program, "uAtlasGeom");
    scale = glGetUniformLocation(program, "uAtlasScale");
  }
};

// One nailboard program variant (one view per cell, four blended, or the hull; one shade pass, or
// the caster) and its uniforms.
struct NailboardProgram {
  core::Program program;
  AtlasUniforms atlas;
  GLint shading = -1, outlines = -1, outlineWidth = -1, outlineColor = -1, multisample = -1, samples = -1;
  GLint casterBias = -1, eyeRight = -1, eyeUp = -1;  // the caster variants only (-1 elsewhere)
  GLint boxMin = -1, boxMax = -1, padPixels = -1;    // the deferred screen passes only
  GLint occluded = -1, occluderSteps = -1;           // the hull's passes only

  // Shader files `vertex` and `fragment` (paths under shaders/); `caster`: the shadow map's caster
  // pass (drawn from the light).
  static Result<NailboardProgram> build(const std::string& vertex, const std::string& fragment, bool caster) {
    PUFF_TRY_ASSIGN(auto p, core::buildProgram({vertex, fragment}));
    NailboardProgram n;
    n.program = std::move(p);
    const GLuint id = n.program.get();
    n.atlas.find(id);
    n.shading = glGetUniformLocation(id, "uShading");
    n.outlines = glGetUniformLocation(id, "uOutlines");
    n.outlineWidth = glGetUniformLocation(id, "uOutlineWidth");
    n.outlineColor = glGetUniformLocation(id, "uOutlineColor");
    n.multisample = glGetUniformLocation(id, "uMultisample");
    n.samples = glGetUniformLocation(id, "uSamples");
    n.casterBias = glGetUniformLocation(id, "uShadowBias");
    n.eyeRight = glGetUniformLocation(id, "uEyeRight");
    n.eyeUp = glGetUniformLocation(id, "uEyeUp");
    n.boxMin = glGetUniformLocation(id, "uBoxMin");
    n.boxMax = glGetUniformLocation(id, "uBoxMax");
    n.padPixels = glGetUniformLocation(id, "uPadPixels");
    n.occluded = glGetUniformLocation(id, "uOccluded");
    n.occluderSteps = glGetUniformLocation(id, "uOccluderSteps");
    // The caster variants draw from the light in every call: their vertex stage's mode is fixed.
    if (caster) glProgramUniform1i(id, glGetUniformLocation(id, "uCaster"), 1);
    return n;
  }
};

// One variant's programs for the lit and shadowed passes shading each pixel once: the pre-pass, and
// the screen passes single-sampled and multisampled.
struct DeferredPrograms {
  NailboardProgram visible, lit, litMs, shadowed, shadowedMs;

  // `name`: nailboard or nailboard_views.
  static Result<DeferredPrograms> build(const std::string& name) {
    DeferredPrograms d;
    const std::string screen = "cel/screen_rect.vert", cel = "cel/" + name;
    PUFF_TRY_ASSIGN(d.visible, NailboardProgram::build(cel + ".vert", cel + "_visible.frag", false));
    PUFF_TRY_ASSIGN(d.lit, NailboardProgram::build(screen, cel + "_deferred.frag", false));
    PUFF_TRY_ASSIGN(d.litMs, NailboardProgram::build(screen, cel + "_deferred_ms.frag", false));
    PUFF_TRY_ASSIGN(d.shadowed, NailboardProgram::build(screen, cel + "_deferred_shadowed.frag", false));
    PUFF_TRY_ASSIGN(d.shadowedMs, NailboardProgram::build(screen, cel + "_deferred_shadowed_ms.frag", false));
    return d;
  }
  std::array<const NailboardProgram*, 5> all() const { return {&visible, &lit, &litMs, &shadowed, &shadowedMs}; }
  const NailboardProgram& screen(ShadePass pass, bool multisampled) const {
    if (pass == ShadePass::kShadowed) return multisampled ? shadowedMs : shadowed;
    return multisampled ? litMs : lit;
  }
};

}  // namespace puff::cel::detail
