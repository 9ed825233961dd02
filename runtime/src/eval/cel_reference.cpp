#include "cel_reference_gl.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <numeric>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <puff/cel/bindings.h>
#include <puff/cel/pass_state.h>
#include <puff/core/bind_points.h>
#include <puff/core/colour.h>
#include <puff/core/files.h>
#include <puff/core/shader.h>
#include <puff/gl_api.h>

namespace puff::eval::detail {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A 2D texture of one level, sampled nearest (ids and depths must never be filtered).
core::Texture nearestTexture(GLenum format, int w, int h, std::string_view what) {
  core::Texture t = core::makeTexture(GL_TEXTURE_2D, what);
  glTextureStorage2D(t.get(), 1, format, w, h);
  glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return t;
}

void setInt(GLuint prog, const char* name, int v) { glProgramUniform1i(prog, glGetUniformLocation(prog, name), v); }
void setFloat(GLuint prog, const char* name, float v) { glProgramUniform1f(prog, glGetUniformLocation(prog, name), v); }
void setMat4(GLuint prog, const char* name, const glm::mat4& m) {
  glProgramUniformMatrix4fv(prog, glGetUniformLocation(prog, name), 1, GL_FALSE, glm::value_ptr(m));
}

}  // namespace

Result<std::vector<mesh::TriMesh>> atlasSourceMeshes(const core::AtlasDesc& desc, const fs::path& sidecar) {
  std::vector<mesh::TriMesh> out;
  for (std::size_t i = 0; i < desc.sources.size(); ++i) {
    const core::AtlasSource& s = desc.sources[i];
    const std::string where = sidecar.string() + ": /sources/" + std::to_string(i);
    mesh::TriMesh m;
    if (!s.path.empty()) {
      fs::path file = s.path;
      if (file.is_relative()) file = sidecar.parent_path() / file;
      auto bytes = core::readFileBytes(file);
      if (!bytes) return Error{where + ": the puff mesh it was baked from cannot be read: " + bytes.error().message};
      if (!s.hash.empty() && "fnv1a64:" + core::fnv1a64Hex(*bytes) != s.hash) {
        return Error{where + ": " + file.string() + " has changed since the atlas was baked (re-bake it)"};
      }
      PUFF_TRY_ASSIGN(m, mesh::loadMesh(file));
    } else {
      PUFF_TRY_ASSIGN(auto generator, mesh::generatorFromJson(s.generator, s.params, where));
      PUFF_TRY_ASSIGN(m, mesh::generate(generator));
      if (s.faces != 0 && m.faceCount() != s.faces) {
        return Error{where + ": the " + s.generator + " generator with these parameters gives " +
                     std::to_string(m.faceCount()) + " faces, the baked puff had " + std::to_string(s.faces) +
                     " (an atlas from another puffbake version?)"};
      }
    }
    if (!m.hasColors()) m.colors.assign(m.positions.size(), s.defaultColor);
    out.push_back(std::move(m));
  }
  if (out.empty()) return Error{sidecar.string() + ": the atlas lists no sources"};
  return out;
}

glm::mat4 puffTransform(const cel::Particle& p, cel::Alignment alignment, const glm::mat4& view, bool orthographic) {
  const glm::mat4 inv = glm::inverse(view);
  const glm::vec3 camRight = glm::normalize(glm::vec3(inv[0])), camUp = glm::normalize(glm::vec3(inv[1]));
  const glm::vec3 camBack = glm::normalize(glm::vec3(inv[2])), eye = glm::vec3(inv[3]);
  glm::mat3 frame(camRight, camUp, camBack);
  const glm::vec3 toward = orthographic ? camBack : glm::normalize(eye - p.position);
  if (alignment == cel::Alignment::kViewpoint) {
    const glm::vec3 r = glm::cross(camUp, toward);
    if (glm::dot(r, r) > 1e-8f) {
      const glm::vec3 rn = glm::normalize(r);
      frame = glm::mat3(rn, glm::cross(toward, rn), toward);
    }
  } else if (alignment == cel::Alignment::kAxial) {
    const glm::vec3 u(0.0f, 1.0f, 0.0f);
    glm::vec3 w = toward - glm::dot(toward, u) * u;
    if (glm::dot(w, w) > 1e-8f) {
      w = glm::normalize(w);
      frame = glm::mat3(glm::cross(u, w), u, w);
    }
  }
  if (p.oriented) frame = glm::mat3_cast(glm::normalize(p.orientation));
  glm::mat4 m(frame * (0.5f * p.size));
  m[3] = glm::vec4(p.position, 1.0f);
  return m;
}

struct CelReference::Impl {
  CelReferenceOptions options;
  struct PuffMesh {
    core::VertexArray vao;
    core::Buffer vertices, indices, adjacency;
    GLsizei indexCount = 0;
    core::VertexArray adjacencyVao;  // the same vertices, triangles with their neighbours (outlines)
  };
  std::vector<PuffMesh> meshes;
  core::Program meshProgram, stencilProgram, silhouetteProgram, downsampleProgram;
  core::Program objectLightProgram, objectIdProgram;  // opaque objects into the shadow maps and the id buffer
  core::VertexArray emptyVao;
  core::Buffer instances;
  std::size_t instanceCapacity = 0;
  // The supersampled frame: colour, puff ids, depth + stencil, and a copy of the depth to sample.
  int width = 0, height = 0;
  core::Framebuffer fbo;
  core::Texture color, ids, depthStencil, depthCopy, idsCopy;
  // The shadow map: pass 1 (distance, id) and pass 2 (distance), one depth buffer each.
  int shadowSize = 0;
  core::Framebuffer shadowFbo1, shadowFbo2;
  core::Texture shadowNear, shadowId, shadowOther, shadowDepth1, shadowDepth2;

  void ensureTarget(int w, int h) {
    if (w == width && h == height && fbo) return;
    width = w;
    height = h;
    fbo = core::makeFramebuffer("cel reference: frame");
    idsCopy = nearestTexture(GL_R32UI, w, h, "cel reference: ids copy");
    color = nearestTexture(GL_RGBA16F, w, h, "cel reference: colour");  // scene-linear: the box filter averages light
    ids = nearestTexture(GL_R32UI, w, h, "cel reference: ids");
    depthStencil = nearestTexture(GL_DEPTH24_STENCIL8, w, h, "cel reference: depth and stencil");
    depthCopy = nearestTexture(GL_DEPTH24_STENCIL8, w, h, "cel reference: depth copy");
    glTextureParameteri(depthCopy.get(), GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT1, ids.get(), 0);
    glNamedFramebufferTexture(fbo.get(), GL_DEPTH_STENCIL_ATTACHMENT, depthStencil.get(), 0);
  }

  void ensureShadowMaps() {
    if (shadowSize == options.shadowMapSize) return;
    shadowSize = options.shadowMapSize;
    const int s = shadowSize;
    shadowNear = nearestTexture(GL_R32F, s, s, "cel reference: shadow nearest");
    shadowId = nearestTexture(GL_R32UI, s, s, "cel reference: shadow ids");
    shadowOther = nearestTexture(GL_R32F, s, s, "cel reference: shadow others");
    shadowDepth1 = core::makeTexture(GL_TEXTURE_2D, "cel reference: shadow depth 1");
    shadowDepth2 = core::makeTexture(GL_TEXTURE_2D, "cel reference: shadow depth 2");
    glTextureStorage2D(shadowDepth1.get(), 1, GL_DEPTH_COMPONENT32F, s, s);
    glTextureStorage2D(shadowDepth2.get(), 1, GL_DEPTH_COMPONENT32F, s, s);
    shadowFbo1 = core::makeFramebuffer("cel reference: shadow 1");
    glNamedFramebufferTexture(shadowFbo1.get(), GL_COLOR_ATTACHMENT0, shadowNear.get(), 0);
    glNamedFramebufferTexture(shadowFbo1.get(), GL_COLOR_ATTACHMENT1, shadowId.get(), 0);
    glNamedFramebufferTexture(shadowFbo1.get(), GL_DEPTH_ATTACHMENT, shadowDepth1.get(), 0);
    const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(shadowFbo1.get(), 2, both);
    shadowFbo2 = core::makeFramebuffer("cel reference: shadow 2");
    glNamedFramebufferTexture(shadowFbo2.get(), GL_COLOR_ATTACHMENT0, shadowOther.get(), 0);
    glNamedFramebufferTexture(shadowFbo2.get(), GL_DEPTH_ATTACHMENT, shadowDepth2.get(), 0);
    glNamedFramebufferDrawBuffer(shadowFbo2.get(), GL_COLOR_ATTACHMENT0);
  }

  // Draws every instance, one instanced call per variation (instances are grouped by variation):
  // triangles, or triangles with adjacency for the silhouette program.
  void drawInstances(const std::vector<std::size_t>& firstOfVariation, bool adjacency = false) {
    const GLuint prog = adjacency ? silhouetteProgram.get() : meshProgram.get();
    for (std::size_t v = 0; v + 1 < firstOfVariation.size(); ++v) {
      const std::size_t first = firstOfVariation[v], count = firstOfVariation[v + 1] - first;
      if (count == 0) continue;
      setInt(prog, "uFirst", static_cast<int>(first));
      glBindVertexArray(adjacency ? meshes[v].adjacencyVao.get() : meshes[v].vao.get());
      glDrawElementsInstanced(adjacency ? GL_TRIANGLES_ADJACENCY : GL_TRIANGLES,
                              meshes[v].indexCount * (adjacency ? 2 : 1), GL_UNSIGNED_INT, nullptr,
                              static_cast<GLsizei>(count));
    }
  }
  // The particles drawn this frame, grouped by variation (instance firstOfVariation[v] is the
  // first of variation v), and the box around them.
  struct Instances {
    std::size_t count = 0;
    std::vector<std::size_t> firstOfVariation{0};
    glm::vec3 lo{INFINITY}, hi{-INFINITY};
  };

  // Uploads the instances, grouped by variation: rows of the model matrix, the particle's id and tint.
  Instances uploadInstances(const cel::Frame& frame, std::span<const cel::Particle> particles,
                            const cel::Style& style) {
    struct Instance {
      glm::vec4 rows[3];
      glm::uvec4 id;
    };
    const bool ortho = frame.projection[3][3] == 1.0f;
    const std::size_t variations = meshes.size();
    std::vector<std::vector<std::size_t>> byVariation(variations);
    for (std::size_t i = 0; i < particles.size(); ++i) {
      const cel::Particle& p = particles[i];
      if (!(p.size > 0.0f) || !std::isfinite(p.size) || !std::isfinite(p.position.x) || !std::isfinite(p.position.y) ||
          !std::isfinite(p.position.z))
        continue;
      // As the nailboards pick it: the packed 8 bits, modulo the atlas's variations.
      byVariation[static_cast<std::size_t>(p.variation & 0xFF) % variations].push_back(i);
    }
    std::vector<Instance> packed;
    Instances out;
    for (const auto& list : byVariation) {
      for (std::size_t i : list) {
        const cel::Particle& p = particles[i];
        const glm::mat4 model = glm::transpose(puffTransform(p, style.alignment, frame.view, ortho));
        // The tint as the particle holds it (scene-linear, clamped to [0, 1]) encoded, a display
        // multiplier of C in float bits: the reference does not share the nailboards' 7-bit packing.
        glm::vec3 tint;  // as the packing takes it: clamped to [0, 1], not a number untinted
        for (int c = 0; c < 3; ++c)
          tint[c] = std::isnan(p.tint[c])
                        ? 1.0f
                        : static_cast<float>(core::linearToSrgb(std::clamp(double{p.tint[c]}, 0.0, 1.0)));
        packed.push_back(
            Instance{{model[0], model[1], model[2]},
                     glm::uvec4(static_cast<unsigned>(i + 1), std::bit_cast<std::uint32_t>(tint.r),
                                std::bit_cast<std::uint32_t>(tint.g), std::bit_cast<std::uint32_t>(tint.b))});
        out.lo = glm::min(out.lo, p.position - glm::vec3(0.5f * p.size));
        out.hi = glm::max(out.hi, p.position + glm::vec3(0.5f * p.size));
      }
      out.firstOfVariation.push_back(packed.size());
    }
    out.count = packed.size();
    if (!packed.empty()) {
      const std::size_t bytes = packed.size() * sizeof(Instance);
      if (bytes > instanceCapacity) {
        instances = core::makeBuffer("cel reference: instances");
        instanceCapacity = std::max<std::size_t>(bytes, 2 * instanceCapacity);
        glNamedBufferStorage(instances.get(), static_cast<GLsizeiptr>(instanceCapacity), nullptr,
                             GL_DYNAMIC_STORAGE_BIT);
      }
      glNamedBufferSubData(instances.get(), 0, static_cast<GLsizeiptr>(bytes), packed.data());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, instances.get());
    }
    return out;
  }

  // The shadow map over the puffs' bounding sphere, seen along the light: pass 1 the nearest
  // distance and its puff, pass 2 the nearest of any other puff; then bound for the frame.
  void drawShadowMaps(const cel::Frame& frame, const Instances& inst, const cel::OpaqueRenderer& opaque,
                      const cel::Style& style, const cel::Bounds& objectBounds) {
    const GLuint meshProg = meshProgram.get(), objProg = objectLightProgram.get();
    ensureShadowMaps();
    cel::Bounds fit = objectBounds;
    if (inst.count > 0) {
      fit.add(inst.lo);
      fit.add(inst.hi);
    }
    if (fit.empty()) fit.add(glm::vec3(0.0f));
    const glm::vec3 centre = 0.5f * (fit.lo + fit.hi);
    const float radius = std::max(1e-3f, 0.5f * glm::length(fit.hi - fit.lo));
    const float len = glm::length(frame.light.direction);
    const glm::vec3 l = len > 0.0f && std::isfinite(len) ? frame.light.direction / len : glm::vec3(0, 1, 0);
    const glm::vec3 up = std::abs(l.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::mat4 lightView = glm::lookAt(centre + 2.0f * radius * l, centre, up);
    const glm::mat4 lightProj = glm::ortho(-radius, radius, -radius, radius, 0.0f, 4.0f * radius);
    const float bias = 2.0f * radius / static_cast<float>(shadowSize);  // one texel
    for (GLuint prog : {meshProg, objProg}) {
      setMat4(prog, "uLightView", lightView);
      setMat4(prog, "uLightProj", lightProj);
    }
    glViewport(0, 0, shadowSize, shadowSize);
    cel::applyShadePass(cel::ShadePass::kLit);  // depth LESS + write, colour on, no stencil
    // None of the shadow maps may sit on a texture unit while it is being drawn into.
    for (GLuint unit : {4u, 5u, 6u}) glBindTextureUnit(unit, 0);
    const float far[4] = {1e30f, 0, 0, 0};
    const GLuint none[4] = {0, 0, 0, 0};
    // Both passes draw the puffs and then the opaque objects (which cast shadows too).
    auto drawCasters = [&](int mode) {
      glUseProgram(meshProg);
      setInt(meshProg, "uMode", mode);
      drawInstances(inst.firstOfVariation);
      glUseProgram(objProg);
      setInt(objProg, "uMode", mode);
      opaque.drawGeometry(objProg);
    };
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, shadowFbo1.get());
    glClearNamedFramebufferfv(shadowFbo1.get(), GL_COLOR, 0, far);
    glClearNamedFramebufferuiv(shadowFbo1.get(), GL_COLOR, 1, none);
    glClearNamedFramebufferfi(shadowFbo1.get(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
    drawCasters(1);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, shadowFbo2.get());
    glClearNamedFramebufferfv(shadowFbo2.get(), GL_COLOR, 0, far);
    glClearNamedFramebufferfi(shadowFbo2.get(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
    glBindTextureUnit(5, shadowId.get());
    drawCasters(2);
    glBindTextureUnit(4, shadowNear.get());
    glBindTextureUnit(6, shadowOther.get());
    for (GLuint prog : {meshProg, stencilProgram.get()}) {
      setMat4(prog, "uShadowView", lightView);
      setMat4(prog, "uShadowProj", lightProj);
      setFloat(prog, "uShadowBias", bias);
      setFloat(prog, "uShadowLength", std::max(0.0f, style.shadowLength));
    }
  }

  // The frame: clear, opaque objects lit (colour only: their program writes no id), puffs.
  void drawFrame(const cel::Frame& frame, cel::FrameBlock& block, cel::OpaqueRenderer& opaque, const cel::Style& style,
                 const glm::vec3& background, const Instances& inst, bool shadows, int w, int h) {
    const GLuint meshProg = meshProgram.get();
    const GLuint target = fbo.get();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
    glViewport(0, 0, w, h);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glStencilMask(0xFF);
    const glm::vec3 bgLinear = core::srgbToLinear(background);  // the background is a display value
    const float bg[4] = {bgLinear.r, bgLinear.g, bgLinear.b, 1.0f};
    const GLuint zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(target, GL_COLOR, 0, bg);
    // The ids by their texture: attachment 1 is not a draw buffer at this point.
    glClearTexImage(ids.get(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, zero);
    glClearNamedFramebufferfi(target, GL_DEPTH_STENCIL, 0, 1.0f, 0);
    glNamedFramebufferDrawBuffer(target, GL_COLOR_ATTACHMENT0);
    PUFF_CHECK(block.upload(frame).ok());  // a scene camera's planes, checked when it was read
    opaque.draw(cel::ShadePass::kLit);
    if (shadows && opaque.count() > 0) {
      // Each object's caster id over the pixels it showed, for the shadow pass (shadow_stencil.frag).
      const GLenum idOnly[2] = {GL_NONE, GL_COLOR_ATTACHMENT1};
      glNamedFramebufferDrawBuffers(target, 2, idOnly);
      cel::resetPassState();
      glDepthFunc(GL_LEQUAL);
      glDepthMask(GL_FALSE);
      glUseProgram(objectIdProgram.get());
      opaque.drawGeometry(objectIdProgram.get());
      glDepthMask(GL_TRUE);
      glNamedFramebufferDrawBuffer(target, GL_COLOR_ATTACHMENT0);
    }
    if (inst.count > 0) {
      const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
      glNamedFramebufferDrawBuffers(target, 2, both);
      cel::resetPassState();  // whatever the opaque pass left
      cel::applyShadePass(cel::ShadePass::kLit);
      glUseProgram(meshProg);
      setInt(meshProg, "uMode", 0);
      setInt(meshProg, "uShading", style.shading ? 1 : 0);
      setInt(meshProg, "uShadows", shadows ? 1 : 0);
      drawInstances(inst.firstOfVariation);
      glNamedFramebufferDrawBuffer(target, GL_COLOR_ATTACHMENT0);
    }
  }

  // The opaque pixels some puff shadows, drawn again shadowed; then the puffs' outlines.
  void drawShadowsAndOutlines(cel::OpaqueRenderer& opaque, const cel::Style& style, const Instances& inst, bool shadows,
                              bool outlines, int w, int h) {
    if (shadows || outlines) {
      // Sampled copies: the frame's own attachments are not read while it is bound.
      glCopyImageSubData(depthStencil.get(), GL_TEXTURE_2D, 0, 0, 0, 0, depthCopy.get(), GL_TEXTURE_2D, 0, 0, 0, 0, w,
                         h, 1);
      glCopyImageSubData(ids.get(), GL_TEXTURE_2D, 0, 0, 0, 0, idsCopy.get(), GL_TEXTURE_2D, 0, 0, 0, 0, w, h, 1);
      glBindTextureUnit(2, depthCopy.get());
      glBindTextureUnit(3, idsCopy.get());
      glBindVertexArray(emptyVao.get());
    }
    if (shadows) {
      // Opaque pixels some puff shadows: stencil 1, then the opaque objects' own shadowed pass.
      glUseProgram(stencilProgram.get());
      glDisable(GL_DEPTH_TEST);
      glDepthMask(GL_FALSE);
      glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
      glEnable(GL_STENCIL_TEST);
      glStencilFunc(GL_ALWAYS, 1, 0xFF);
      glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
      glDrawArrays(GL_TRIANGLES, 0, 3);
      glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      opaque.draw(cel::ShadePass::kShadowed);
      glDisable(GL_STENCIL_TEST);
    }
    if (outlines) {
      const GLuint prog = silhouetteProgram.get();
      glUseProgram(prog);
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
      glDepthMask(GL_FALSE);
      glDisable(GL_STENCIL_TEST);
      setFloat(prog, "uWidth", style.outlineWidth * static_cast<float>(options.supersample));
      const glm::vec3 ink = core::linearToSrgb(style.outlineColor);  // display values, as the nailboards'
      glProgramUniform3f(prog, glGetUniformLocation(prog, "uInk"), ink.r, ink.g, ink.b);
      drawInstances(inst.firstOfVariation, true);
    }
  }

  // Box-filter into the caller's framebuffer (its read binding stays the caller's).
  void downsample(GLuint outputFbo, const cel::Viewport& viewport) {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, outputFbo);
    glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_BLEND);
    glDepthMask(GL_FALSE);
    const GLuint down = downsampleProgram.get();
    glUseProgram(down);
    setInt(down, "uFactor", options.supersample);
    glProgramUniform2i(down, glGetUniformLocation(down, "uOrigin"), viewport.x, viewport.y);
    glBindTextureUnit(0, color.get());
    glBindVertexArray(emptyVao.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glBindVertexArray(0);
    glUseProgram(0);
  }
};

std::vector<float> CelReference::outputDepth() const {
  const Impl& m = *impl_;
  if (!m.depthStencil) return {};
  const int ss = m.options.supersample;
  std::vector<float> super(static_cast<std::size_t>(m.width) * m.height);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(m.depthStencil.get(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                    static_cast<GLsizei>(super.size() * sizeof(float)), super.data());
  const int w = m.width / ss, h = m.height / ss;
  std::vector<float> out(static_cast<std::size_t>(w) * h, 1.0f);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float& nearest = out[static_cast<std::size_t>(y) * w + x];
      for (int j = 0; j < ss; ++j) {
        for (int i = 0; i < ss; ++i) {
          nearest = std::min(nearest, super[static_cast<std::size_t>(y * ss + j) * m.width + x * ss + i]);
        }
      }
    }
  }
  return out;
}

CelReference::CelReference() : impl_(std::make_unique<Impl>()) {}
CelReference::~CelReference() = default;
int CelReference::supersample() const { return impl_->options.supersample; }

cel::Viewport CelReference::supersampledViewport(int width, int height) const {
  return cel::Viewport{0, 0, width * impl_->options.supersample, height * impl_->options.supersample};
}

Result<void> validate(const CelReferenceOptions& options) {
  if (options.supersample < 1 || options.supersample > 8)
    return Error{"reference supersampling must be in [1, 8], got " + std::to_string(options.supersample)};
  if (options.shadowMapSize < 256 || options.shadowMapSize > 8192)
    return Error{"reference shadow map size must be in [256, 8192], got " + std::to_string(options.shadowMapSize)};
  return {};
}

namespace {
// The reference's programs read the frame's block, ramp and gradient where the cel scene binds them
// (cel::Bindings{}, CelScene's), not at their shaders' `layout(binding = N)` values.
void pointAtFrame(GLuint program) {
  const cel::Bindings b;
  using K = core::BindPoint::Kind;
  core::assignBindPoints(program, {{K::kUniformBlock, "FrameBlock", b.frameBlock},
                                   {K::kSampler, "uRamp", b.ramp},
                                   {K::kSampler, "uGradient", b.gradient}});
}
}  // namespace

Result<std::unique_ptr<CelReference>> CelReference::create(std::vector<mesh::TriMesh> meshes,
                                                           const CelReferenceOptions& options) {
  PUFF_TRY(validate(options));
  if (meshes.empty()) return Error{"the cel reference needs at least one puff mesh"};
  std::unique_ptr<CelReference> r(new CelReference());
  Impl& m = *r->impl_;
  m.options = options;
  PUFF_TRY_ASSIGN(auto mesh, core::buildProgram({"reference/puff_mesh.vert", "reference/puff_mesh.frag"}));
  PUFF_TRY_ASSIGN(auto stencil, core::buildProgram({"reference/fullscreen.vert", "reference/shadow_stencil.frag"}));
  PUFF_TRY_ASSIGN(auto silhouette, core::buildProgram({"reference/silhouette.vert", "reference/silhouette.geom",
                                                       "reference/silhouette.frag"}));
  PUFF_TRY_ASSIGN(auto down, core::buildProgram({"reference/fullscreen.vert", "reference/downsample.frag"}));
  PUFF_TRY_ASSIGN(auto objectLight, core::buildProgram({"reference/object_light.vert", "reference/object_light.frag"}));
  PUFF_TRY_ASSIGN(auto objectId, core::buildProgram({"cel/opaque.vert", "reference/object_id.frag"}));
  for (const core::Program* p : {&mesh, &stencil, &silhouette, &down, &objectLight, &objectId}) pointAtFrame(p->get());
  m.objectLightProgram = std::move(objectLight);
  m.objectIdProgram = std::move(objectId);
  m.meshProgram = std::move(mesh);
  m.stencilProgram = std::move(stencil);
  m.silhouetteProgram = std::move(silhouette);
  m.downsampleProgram = std::move(down);
  m.emptyVao = core::makeVertexArray("cel reference: empty vertex array");
  m.instances = core::makeBuffer("cel reference: instances");

  struct Vertex {
    glm::vec3 position, normal, color;
  };
  for (const mesh::TriMesh& t : meshes) {
    Impl::PuffMesh pm;
    std::vector<Vertex> vertices(t.positions.size());
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      vertices[i] = {t.positions[i], t.normals[i], t.hasColors() ? t.colors[i] : glm::vec3(1.0f)};
    }
    pm.vertices = core::makeBuffer("cel reference: puff mesh vertices");
    pm.indices = core::makeBuffer("cel reference: puff mesh indices");
    glNamedBufferStorage(pm.vertices.get(), static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(),
                         0);
    glNamedBufferStorage(pm.indices.get(), static_cast<GLsizeiptr>(t.triangles.size() * sizeof(glm::uvec3)),
                         t.triangles.data(), 0);
    pm.indexCount = static_cast<GLsizei>(t.triangles.size() * 3);
    pm.vao = core::makeVertexArray("cel reference: puff mesh");
    const GLuint vao = pm.vao.get();
    glVertexArrayVertexBuffer(vao, 0, pm.vertices.get(), 0, sizeof(Vertex));
    glVertexArrayElementBuffer(vao, pm.indices.get());
    for (GLuint a = 0; a < 3; ++a) {
      glEnableVertexArrayAttrib(vao, a);
      glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE, a * sizeof(glm::vec3));
      glVertexArrayAttribBinding(vao, a, 0);
    }
    // Each triangle with the vertex across each of its edges (GL_TRIANGLES_ADJACENCY order); an edge
    // with no neighbour (an open mesh) gets the triangle's own third vertex, which silhouette.geom
    // takes for "no neighbour" and never inks.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> across;
    for (const glm::uvec3& tri : t.triangles) {
      for (int e = 0; e < 3; ++e) across[{tri[e], tri[(e + 1) % 3]}] = tri[(e + 2) % 3];
    }
    std::vector<std::uint32_t> adjacency;
    adjacency.reserve(t.triangles.size() * 6);
    for (const glm::uvec3& tri : t.triangles) {
      for (int e = 0; e < 3; ++e) {
        const auto it = across.find({tri[(e + 1) % 3], tri[e]});
        adjacency.push_back(tri[e]);
        adjacency.push_back(it != across.end() ? it->second : tri[(e + 2) % 3]);
      }
    }
    pm.adjacency = core::makeBuffer("cel reference: puff mesh adjacency");
    glNamedBufferStorage(pm.adjacency.get(), static_cast<GLsizeiptr>(adjacency.size() * sizeof(std::uint32_t)),
                         adjacency.data(), 0);
    pm.adjacencyVao = core::makeVertexArray("cel reference: puff mesh adjacency");
    glVertexArrayVertexBuffer(pm.adjacencyVao.get(), 0, pm.vertices.get(), 0, sizeof(Vertex));
    glVertexArrayElementBuffer(pm.adjacencyVao.get(), pm.adjacency.get());
    glEnableVertexArrayAttrib(pm.adjacencyVao.get(), 0);
    glVertexArrayAttribFormat(pm.adjacencyVao.get(), 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(pm.adjacencyVao.get(), 0, 0);
    m.meshes.push_back(std::move(pm));
  }
  if (const std::string e = core::drainGlErrors(); !e.empty())
    return Error{"uploading the reference's puff meshes: " + e};
  return r;
}

void CelReference::draw(const cel::Frame& frame, cel::FrameBlock& block, cel::OpaqueRenderer& opaque,
                        std::span<const cel::Particle> particles, const cel::Style& style, const glm::vec3& background,
                        GLuint outputFbo, const cel::Viewport& viewport, const cel::Bounds& objectBounds) {
  Impl& m = *impl_;
  // Its framebuffers draw to two buffers; the cel passes set draw buffer 0's mask alone.
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  const int ss = m.options.supersample;
  const int w = viewport.width * ss, h = viewport.height * ss;
  m.ensureTarget(w, h);
  cel::resetPassState();  // no scissor, blending, culling, clamp, ... whatever the host left

  const Impl::Instances instances = m.uploadInstances(frame, particles, style);
  // The shadow map over the casters' bounding sphere (the puffs and the objects that fit the map),
  // seen along the light.
  const bool shadows = style.shadows && (instances.count > 0 || opaque.count() > 0);
  if (shadows) m.drawShadowMaps(frame, instances, opaque, style, objectBounds);
  m.drawFrame(frame, block, opaque, style, background, instances, shadows, w, h);
  const bool outlines = style.outlines && style.outlineWidth > 0.0f && instances.count > 0;
  m.drawShadowsAndOutlines(opaque, style, instances, shadows, outlines, w, h);
  m.downsample(outputFbo, viewport);
}

}  // namespace puff::eval::detail
