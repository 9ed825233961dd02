#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <puff/cel/nailboards.h>
#include <puff/cel/pass_state.h>
#include <puff/cel/volume_clip.h>
#include <puff/core/bind_points.h>
#include <puff/core/colour.h>
#include <puff/core/shader.h>
#include <puff/gl_api.h>
#include <puff/shader_contract.h>

#include "atlas_textures.h"
#include "bindings_gl.h"
#include "hull_field.h"
#include "nailboard_programs.h"
#include "shadow_profiles.h"
#include "visibility.h"

namespace puff::cel {

using detail::AtlasUniforms;
using detail::DeferredPrograms;
using detail::kPolar;
using detail::NailboardProgram;
using detail::ShadowProfiles;
using detail::shadowProfiles;
using detail::TumbleShare;

namespace {

// How far apart (in steps of the host's depth buffer) a hull fragment's nearest depth and a disc's
// must be stored for the fragment to be dropped (shaders/cel/nailboard_fs.glsl, hullOccluded).
constexpr float kOccluderSteps = 4.0f;

// The draw framebuffer's samples per pixel: 1 unless it is multisampled.
int framebufferSamples() {
  GLint sampleBuffers = 0, samples = 0;
  glGetIntegerv(GL_SAMPLE_BUFFERS, &sampleBuffers);
  if (sampleBuffers == 0) return 1;
  glGetIntegerv(GL_SAMPLES, &samples);
  return std::max(1, static_cast<int>(samples));
}

}  // namespace

namespace {

// The shade passes in the order PassPrograms holds their programs, and each one's fragment file
// suffix (nailboard<suffix>.frag: the variant compiled with that PUFF_SHADE_PASS).
constexpr std::array<std::pair<ShadePass, const char*>, 3> kPassPrograms = {
    {{ShadePass::kLit, ""}, {ShadePass::kShadowed, "_shadowed"}, {ShadePass::kDepthOnly, "_depth"}}};
using PassPrograms = std::array<NailboardProgram, kPassPrograms.size()>;

std::size_t passProgramIndex(ShadePass pass) {
  for (std::size_t i = 0; i < kPassPrograms.size(); ++i) {
    if (kPassPrograms[i].first == pass) return i;
  }
  return 0;
}

// Every shade pass's program of one variant: vertex stage `vertex`, fragment files fragment + suffix.
Result<PassPrograms> buildPassPrograms(const std::string& vertex, const std::string& fragment) {
  PassPrograms out;
  for (std::size_t i = 0; i < kPassPrograms.size(); ++i) {
    PUFF_TRY_ASSIGN(out[i], NailboardProgram::build("cel/" + vertex + ".vert",
                                                    "cel/" + fragment + kPassPrograms[i].second + ".frag", false));
  }
  return out;
}

}  // namespace

struct NailboardRenderer::Impl {
  Bindings bindings;
  // multi: four views blended (style.tumble "blend"); hull: oriented puffs by the hull of their views.
  // One program per shade pass (kPassPrograms' order), and one caster.
  PassPrograms singleView, multiView, hullView;
  NailboardProgram singleCaster, multiCaster, hullCaster;
  // The lit pass of one view and of four blended, shading each pixel once: the visibility pre-pass
  // into Puff's own target, then the deferred shading of each pixel's particles (drawNailboards);
  // the shadowed pass's deferred shading reads the lit pass's visibility.
  DeferredPrograms singleDeferred, multiDeferred;
  detail::VisibilityTarget visibility;
  // The tumbling hull's occluders: each hull-drawn puff's core, drawn before each pass of the hull
  // into Puff's own target (drawOccluders); its fragments behind another's core skip their march.
  NailboardProgram occluder;
  detail::OccluderTarget occluders;
  HullOcclusion hullOcclusion = HullOcclusion::kAuto;
  // What the visibility target holds: the particles of upload number `upload` (0:
  // none) seen in the frame block bound as number `frame` (cel::boundFrameSerial), drawn for the
  // draw framebuffer `framebuffer` at `samples`.
  struct Visible {
    std::uint64_t upload = 0, frame = 0;
    GLint framebuffer = -1;
    int samples = 0;
    float hullFrom = 0.0f;  // the blend's share of a split frame (> 0), or every particle (0)
    bool operator==(const Visible&) const = default;
  };
  std::uint64_t uploads = 0;
  Visible held;
  int maxIntegerSamples = 1;  // GL_MAX_INTEGER_SAMPLES: the multisampled pre-pass's ids
  // The drawn particles' centres and sizes, their centres' box and largest size (upload).
  std::vector<glm::vec4> drawn;
  glm::vec3 boxMin{0.0f}, boxMax{0.0f};
  float maxSize = 0.0f;
  bool anyDrawn = false;
  LitShading litShading = LitShading::kAuto;
  TumbleShare share = TumbleShare::kAll;  // the particles the draw being set up takes
  core::Program shadow, sprite;
  AtlasUniforms svAtlas, spAtlas;
  GLint shadowBias = -1, shadowLength = -1, shadowFloor = -1, shadowBackFace = -1;
  core::VertexArray vao;
  core::Buffer particles, cells;
  core::Buffer next;          // uploadNext's: made on first use
  std::size_t nextCount = 0;  // particles it holds (0: none, nothing bound)
  core::Texture shadowProfile;
  std::size_t particleCapacity = 0;
  std::size_t count = 0;
  PackBounds bounds;
  std::vector<PackedParticle> packed;
  core::Texture maps, color;  // maps: normal xy, depth, distance (RGBA8); color: C + coverage
  core::Texture hull;         // a multi-view atlas's hull field (R16F, 3D: detail::HullField); none: 0
  core::Texture noHull;       // 1 x 1 x 1, on unit atlasHull when the atlas has no field (one view: no hull)
  core::AtlasDesc desc;
  bool hasAtlas = false;
  // Oriented puffs split between the blend's program and the hull's by their size (hullFromPixels).
  bool splitsTumble(const Style& s) const {
    return desc.views > 1 && s.tumble == TumbleMethod::kHull && s.hullFromPixels > 0.0f;
  }

  void setCommon(GLuint program, const AtlasUniforms& u, const Style& style) const {
    glProgramUniform3fv(program, u.gridOrigin, 1, glm::value_ptr(bounds.min));
    glProgramUniform3fv(program, u.gridStep, 1, glm::value_ptr(bounds.step));
    glProgramUniform1i(program, u.alignment, static_cast<int>(style.alignment));
    glProgramUniform4i(program, u.layout, desc.variations, desc.views, desc.viewGrid, desc.viewLayout == "oct" ? 1 : 0);
    glProgramUniform4f(program, u.geom, static_cast<float>(desc.width), static_cast<float>(desc.height),
                       static_cast<float>(desc.cellSize), static_cast<float>(desc.margin));
    glProgramUniform4f(program, u.scale, static_cast<float>(desc.contentSize), desc.depthScale, desc.distanceRange,
                       0.0f);
    glProgramUniform1f(program, u.hullFrom, style.hullFromPixels);
    glProgramUniform1i(program, u.tumbleShare, static_cast<int>(share));
    glBindVertexArray(vao.get());
    // Multi-bind: the generic GL_SHADER_STORAGE_BUFFER binding stays the host's.
    const GLuint particleBuffer = particles.get(), cellBuffer = cells.get();
    glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, bindings.particles, 1, &particleBuffer);
    glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, bindings.cells, 1, &cellBuffer);
    if (nextCount > 0) {
      const GLuint nextBuffer = next.get();
      glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, bindings.particleNext, 1, &nextBuffer);
    }
    core::bindTextureAndNoSampler(bindings.atlasPacked, maps.get());
    core::bindTextureAndNoSampler(bindings.atlasColor, color.get());
    core::bindTextureAndNoSampler(bindings.atlasHull, hull.get() != 0 ? hull.get() : noHull.get());
    // The silhouette's radius table: the shadow volumes' sides, small nailboards' silhouettes and bands.
    core::bindTextureAndNoSampler(bindings.shadowProfile, shadowProfile.get());
  }
  // What every nailboard program reads besides the atlas: the style's shading and outlines.
  void setUniforms(const NailboardProgram& nb, const Style& style, int samples) const {
    const GLuint p = nb.program.get();
    setCommon(p, nb.atlas, style);
    glProgramUniform1i(p, nb.shading, style.shading ? 1 : 0);
    glProgramUniform1i(p, nb.outlines, style.outlines ? 1 : 0);
    glProgramUniform1f(p, nb.outlineWidth, std::max(0.0f, style.outlineWidth));
    const glm::vec3 ink = core::linearToSrgb(style.outlineColor);  // the shader mixes display values
    glProgramUniform3fv(p, nb.outlineColor, 1, glm::value_ptr(ink));
    glProgramUniform1i(p, nb.multisample, samples > 1 ? 1 : 0);
    glProgramUniform1i(p, nb.samples, samples);
  }
  // The pre-pass of the lit pass shading each pixel once: the particles' ids and depths into the
  // visibility target; then the screen pass of `pass` over it. Each sets every state it relies on.
  // False, drawing nothing, where the target cannot be made (an incomplete framebuffer).
  bool drawVisibility(const NailboardProgram& visible, const Style& style, int samples);
  // The hull's occluder pass, of the particles `share` takes, into the occluder target (the draw
  // framebuffer's binding put back). False, drawing nothing, where the target cannot be made.
  bool drawOccluders(const Style& style, int samples);
  // The screen rectangle the quads reach: their centres' box grown by a grid step (the packed
  // positions' rounding) and the largest quad's half-diagonal (a quad spans at least the whole cell,
  // halfCell diameters from its centre; one larger for its ink is larger by the ink's pixels, in the
  // pad), and the pad: the ink band, its antialiased edge (measured in the billboard's plane: a
  // billboard turned from the view plane stretches it on the screen, up to sqrt 2 across the pad's
  // square) and a pixel (the rasterizer's rounding).
  float halfCell() const {
    return std::max(0.5f, 0.5f * static_cast<float>(desc.cellSize) / static_cast<float>(std::max(1, desc.contentSize)));
  }
  glm::vec3 reachLo() const {
    return boxMin - bounds.step - glm::vec3(maxSize * halfCell() * std::sqrt(2.0f) * 1.0001f);
  }
  glm::vec3 reachHi() const {
    return boxMax + bounds.step + glm::vec3(maxSize * halfCell() * std::sqrt(2.0f) * 1.0001f);
  }
  static float padPixels(const Style& style) {
    return ((style.outlines ? std::max(0.0f, style.outlineWidth) : 0.0f) + 1.5f) * std::sqrt(2.0f) + 1.0f;
  }
  // How deep the quads stack over that rectangle: their summed screen area over its (from at most
  // 4096 of them). 0 where they reach no pixel.
  double stacked(const Style& style) const {
    const glm::mat4 viewProjection = boundViewProjection();
    const core::Viewport viewport = boundViewport();
    const double rect = detail::reachedPixels(viewProjection, reachLo(), reachHi(), padPixels(style), viewport);
    if (rect <= 0.0) return 0.0;
    const std::size_t stride = drawn.size() / 4096 + 1;
    const float band = (style.outlines ? std::max(0.0f, style.outlineWidth) : 0.0f) + 1.5f;
    return detail::quadPixels(drawn, stride, halfCell(), band, viewProjection, boundProjectionScaleY(), viewport) /
           rect;
  }
  // What a pre-pass drawn now would hold.
  Visible current(int samples, const Style& style) const {
    GLint framebuffer = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
    return {uploads, boundFrameSerial(), framebuffer, samples,
            share == TumbleShare::kBlend ? style.hullFromPixels : 0.0f};
  }
  // One pass of `variant` over the particles of `share`: each pixel shaded once from a pre-pass
  // (`deferred`, where the pass allows it; none: every layer).
  DrawStats drawShare(const PassPrograms& variant, const DeferredPrograms* deferred, TumbleShare taken,
                      const Style& style, ShadePass pass);
  void drawScreen(const NailboardProgram& shade, ShadePass pass, const Style& style, int samples);
  // Every draw ends here: no program or vertex array of Puff's stays bound (a host binding an
  // element buffer next would otherwise change Puff's vertex array).
  static void unbind() {
    glBindVertexArray(0);
    glUseProgram(0);
  }
};

NailboardRenderer::NailboardRenderer() : impl_(std::make_unique<Impl>()) {}
NailboardRenderer::~NailboardRenderer() = default;

Result<std::unique_ptr<NailboardRenderer>> NailboardRenderer::create(const Bindings& bindings) {
  if (auto ok = validate(bindings); !ok) return ok.error();
  std::unique_ptr<NailboardRenderer> r(new NailboardRenderer());
  Impl& m = *r->impl_;
  m.bindings = bindings;
  PUFF_TRY_ASSIGN(auto single, buildPassPrograms("nailboard", "nailboard"));
  PUFF_TRY_ASSIGN(auto multi, buildPassPrograms("nailboard_views", "nailboard_views"));
  PUFF_TRY_ASSIGN(m.singleCaster, NailboardProgram::build("cel/nailboard.vert", "cel/nailboard_caster.frag", true));
  PUFF_TRY_ASSIGN(m.multiCaster,
                  NailboardProgram::build("cel/nailboard_views.vert", "cel/nailboard_views_caster.frag", true));
  PUFF_TRY_ASSIGN(auto hull, buildPassPrograms("nailboard_views", "nailboard_hull"));
  PUFF_TRY_ASSIGN(m.hullCaster,
                  NailboardProgram::build("cel/nailboard_views.vert", "cel/nailboard_hull_caster.frag", true));
  PUFF_TRY_ASSIGN(m.occluder, NailboardProgram::build("cel/hull_occluder.vert", "cel/hull_occluder.frag", false));
  PUFF_TRY_ASSIGN(m.singleDeferred, DeferredPrograms::build("nailboard"));
  PUFF_TRY_ASSIGN(m.multiDeferred, DeferredPrograms::build("nailboard_views"));
  PUFF_TRY_ASSIGN(auto sv, core::buildProgram({"cel/shadow.vert", "cel/shadow.frag"}));
  PUFF_TRY_ASSIGN(auto sp, core::buildProgram({"cel/sprite.vert", "cel/sprite.frag"}));
  m.singleView = std::move(single);
  m.multiView = std::move(multi);
  m.hullView = std::move(hull);
  m.shadow = std::move(sv);
  m.sprite = std::move(sp);
  m.svAtlas.find(m.shadow.get());
  m.spAtlas.find(m.sprite.get());
  m.shadowBias = glGetUniformLocation(m.shadow.get(), "uShadowBias");
  m.shadowLength = glGetUniformLocation(m.shadow.get(), "uShadowLength");
  m.shadowFloor = glGetUniformLocation(m.shadow.get(), "uShadowFloor");
  m.shadowBackFace = glGetUniformLocation(m.shadow.get(), "uBackFace");
  for (const PassPrograms* variant : {&m.singleView, &m.multiView, &m.hullView}) {
    for (const NailboardProgram& nb : *variant) detail::assignBindPoints(nb.program.get(), bindings);
  }
  for (const DeferredPrograms* variant : {&m.singleDeferred, &m.multiDeferred}) {
    for (const NailboardProgram* nb : variant->all()) detail::assignBindPoints(nb->program.get(), bindings);
  }
  for (const GLuint p : {m.singleCaster.program.get(), m.multiCaster.program.get(), m.hullCaster.program.get(),
                         m.occluder.program.get(), m.shadow.get(), m.sprite.get()}) {
    detail::assignBindPoints(p, bindings);
  }
  // Binding texture 0 would empty every target of the unit (glBindTextureUnit), the host's too.
  m.noHull = core::makeTexture(GL_TEXTURE_3D, "nailboards: no hull field");
  glTextureStorage3D(m.noHull.get(), 1, GL_R16F, 1, 1, 1);
  glClearTexImage(m.noHull.get(), 0, GL_RED, GL_FLOAT, nullptr);  // 0; no unpack state touched
  glGetIntegerv(GL_MAX_INTEGER_SAMPLES, &m.maxIntegerSamples);
  m.vao = core::makeVertexArray("nailboards: vertex array");
  m.particles = core::makeBuffer("nailboards: particles");
  m.cells = core::makeBuffer("nailboards: atlas cells");
  return r;
}

const core::AtlasDesc& NailboardRenderer::atlas() const { return impl_->desc; }

Result<void> NailboardRenderer::setAtlas(const core::Atlas& atlas) {
  Impl& m = *impl_;
  const core::AtlasDesc& d = atlas.desc;
  if (d.variations < 1 || d.views < 1 || d.cells.size() != static_cast<std::size_t>(d.variations * d.views)) {
    return Error{"atlas has " + std::to_string(d.cells.size()) + " cells for " + std::to_string(d.variations) +
                 " variations x " + std::to_string(d.views) + " views"};
  }
  const std::vector<core::Image>* ndMap = detail::findAtlasMap(atlas, "normalDepth");
  const std::vector<core::Image>* colorMap = detail::findAtlasMap(atlas, "color");
  const std::vector<core::Image>* distMap = detail::findAtlasMap(atlas, "distance");
  if (!ndMap || !colorMap || !distMap) {
    return Error{std::string("atlas has no ") + (!ndMap ? "normalDepth" : !colorMap ? "color" : "distance") + " map"};
  }
  if (ndMap->size() != distMap->size()) return Error{"atlas normalDepth and distance maps have different mip counts"};
  // What the nailboard reads per pixel, in one RGBA8 fetch (the paper's budget is two 32-bit reads:
  // this one and the colour): normal x and y (z >= 0 is rebuilt), depth offset, and the distance
  // to the silhouette at 8 bits (1/255 of its +-range: 0.13 texels at the default range of 16).
  std::vector<core::Image> packed;
  for (std::size_t l = 0; l < ndMap->size(); ++l) {
    const core::Image& n = (*ndMap)[l];
    const core::Image& di = (*distMap)[l];
    if (n.width != di.width || n.height != di.height || n.channels < 4 || di.channels < 1) {
      return Error{"atlas normalDepth and distance level " + std::to_string(l) + " differ in size"};
    }
    core::Image p(n.width, n.height, 4);
    for (int y = 0; y < n.height; ++y) {
      for (int x = 0; x < n.width; ++x) {
        p.at(x, y, 0) = n.at(x, y, 0);
        p.at(x, y, 1) = n.at(x, y, 1);
        p.at(x, y, 2) = n.at(x, y, 3);
        p.at(x, y, 3) = di.at(x, y, 0);
      }
    }
    packed.push_back(std::move(p));
  }
  PUFF_TRY_ASSIGN(auto nd, detail::uploadAtlasLevels(d, packed, "normalDepth", 4, GL_RGBA8));
  // The colour map holds display values (docs/colour.md); the shader reads scene-linear ones, so
  // filtering and mips mix light: an sRGB texture decodes 8-bit maps, EXR maps are decoded here.
  const bool floatMap = d.fileFormat == "exr";
  PUFF_TRY_ASSIGN(
      auto co, detail::uploadAtlasLevels(d, *colorMap, "color", 4, floatMap ? GL_RGBA16F : GL_SRGB8_ALPHA8, floatMap));
  // The tumbling hull's field, built before anything the renderer holds changes: a failure leaves
  // the last atlas whole.
  const ShadowProfiles profiles = shadowProfiles(atlas);
  PUFF_TRY_ASSIGN(detail::HullFieldTexture hull, detail::hullFieldTexture(atlas, profiles.radii));

  // shaders/cel/particle.glsl's AtlasCell: rect, right, up, dir, and the variation's core.
  std::vector<glm::vec4> cellData;
  cellData.reserve(d.cells.size() * 5);
  for (std::size_t i = 0; i < d.cells.size(); ++i) {
    const core::AtlasCell& c = d.cells[i];
    const glm::vec3 dir = glm::normalize(c.viewDir), up = glm::normalize(c.viewUp);
    const glm::vec3 right = glm::cross(up, dir);
    cellData.emplace_back(c.rect[0], c.rect[1], c.rect[2], c.rect[3]);
    cellData.emplace_back(right, 0.0f);
    cellData.emplace_back(up, 0.0f);
    cellData.emplace_back(dir, 0.0f);
    cellData.push_back(hull.cores[i / static_cast<std::size_t>(d.views)]);
  }
  m.cells = core::makeBuffer("nailboards: atlas cells");
  glNamedBufferStorage(m.cells.get(), static_cast<GLsizeiptr>(cellData.size() * sizeof(glm::vec4)), cellData.data(), 0);
  m.shadowProfile = core::makeTexture(GL_TEXTURE_2D, "nailboards: silhouette radius table");
  const GLuint sp = m.shadowProfile.get();
  const auto rows = static_cast<GLsizei>(d.cells.size());
  glTextureStorage2D(sp, 1, GL_R32F, kPolar, rows);
  glTextureSubImage2D(sp, 0, 0, 0, kPolar, rows, GL_RED, GL_FLOAT, profiles.radii.data());
  glTextureParameteri(sp, GL_TEXTURE_WRAP_S, GL_REPEAT);  // directions wrap around
  glTextureParameteri(sp, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(sp, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(sp, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  m.maps = std::move(nd);
  m.color = std::move(co);
  m.hull = std::move(hull.texture);
  m.desc = d;
  m.hasAtlas = true;
  m.held = {};  // drawn with other maps
  return {};
}

DrawStats NailboardRenderer::upload(std::span<const Particle> particles) {
  Impl& m = *impl_;
  m.bounds = packParticles(particles, m.packed);
  m.count = particles.size();
  m.nextCount = 0;
  ++m.uploads;
  // The box the deferred screen pass covers (drawScreen): every drawn particle's centre, and the
  // largest size.
  m.anyDrawn = false;
  m.maxSize = 0.0f;
  m.drawn.clear();
  for (const Particle& p : particles) {
    const glm::vec3 c = p.position;
    if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && std::isfinite(p.size) && p.size > 0.0f))
      continue;
    m.boxMin = m.anyDrawn ? glm::min(m.boxMin, p.position) : p.position;
    m.boxMax = m.anyDrawn ? glm::max(m.boxMax, p.position) : p.position;
    m.maxSize = std::max(m.maxSize, p.size);
    m.anyDrawn = true;
    m.drawn.emplace_back(c, p.size);
  }
  const std::size_t bytes = m.packed.size() * sizeof(PackedParticle);
  // Orphan and refill: the driver hands out fresh storage while the last frame may still read it.
  if (bytes > 0) {
    glNamedBufferData(m.particles.get(), static_cast<GLsizeiptr>(bytes), m.packed.data(), GL_STREAM_DRAW);
  }
  DrawStats s;
  s.particles = m.count;
  s.bytesUploaded = bytes;
  return s;
}

void NailboardRenderer::uploadNext(std::span<const glm::vec4> next) {
  Impl& m = *impl_;
  m.nextCount = next.size();
  if (next.empty()) return;
  if (m.next.get() == 0) m.next = core::makeBuffer("nailboards: next positions");
  glNamedBufferData(m.next.get(), static_cast<GLsizeiptr>(next.size_bytes()), next.data(), GL_STREAM_DRAW);
}

DrawStats NailboardRenderer::drawNailboards(const Style& style, ShadePass pass) {
  const core::DebugGroup group(pass == ShadePass::kLit        ? "nailboards (lit)"
                               : pass == ShadePass::kShadowed ? "nailboards (shadowed)"
                                                              : "nailboards (depth)");
  Impl& m = *impl_;
  DrawStats s;
  s.particles = m.count;
  if (m.count == 0 || !m.hasAtlas) return s;
  // Only the framebuffer's draw buffer 0 is written (a host's other attachments stay as they are).
  const core::DrawBufferZero drawBuffers;
  // A multi-view atlas blends the four nearest views; a one-view atlas needs one lookup per map. The
  // tumbling hull is drawn forward; from a size on (hullFromPixels), only the puffs that large,
  // after the blend has drawn the rest.
  if (m.desc.views == 1) return m.drawShare(m.singleView, &m.singleDeferred, TumbleShare::kAll, style, pass);
  if (style.tumble == TumbleMethod::kBlend) {
    return m.drawShare(m.multiView, &m.multiDeferred, TumbleShare::kAll, style, pass);
  }
  if (!m.splitsTumble(style)) return m.drawShare(m.hullView, nullptr, TumbleShare::kAll, style, pass);
  DrawStats blend = m.drawShare(m.multiView, &m.multiDeferred, TumbleShare::kBlend, style, pass);
  blend.drawCalls += m.drawShare(m.hullView, nullptr, TumbleShare::kHull, style, pass).drawCalls;
  return blend;
}

DrawStats NailboardRenderer::Impl::drawShare(const PassPrograms& variant, const DeferredPrograms* deferred,
                                             TumbleShare taken, const Style& style, ShadePass pass) {
  Impl& m = *this;
  m.share = taken;
  DrawStats s;
  s.particles = m.count;
  const int samples = framebufferSamples();
  const bool msaa = samples > 1;
  // The lit pass shades each pixel once: a pre-pass into Puff's own target finds each pixel's (each
  // sample's) nearest particle, a screen pass shades it (not past the samples the pass reads); the
  // shadowed pass after it too. kAuto's estimate counts every particle: a split's blend share is drawn
  // every layer unless kOncePerPixel is asked for.
  const bool onceLit = pass == ShadePass::kLit && m.litShading != LitShading::kEveryLayer && deferred != nullptr &&
                       samples <= shader::kMaxDeferredSamples && (samples == 1 || samples <= m.maxIntegerSamples) &&
                       (m.litShading == LitShading::kOncePerPixel ||
                        (taken == TumbleShare::kAll && m.stacked(style) >= kOnceMinOverdraw));
  const bool onceShadowed =
      pass == ShadePass::kShadowed && deferred != nullptr && m.held.upload != 0 && m.held == m.current(samples, style);
  if (onceShadowed || (onceLit && m.drawVisibility(deferred->visible, style, samples))) {
    m.drawScreen(deferred->screen(pass, msaa), pass, style, samples);
    s.drawCalls = onceLit ? 2 : 1;
    return s;
  }
  // Every layer: a lit pass drawn so leaves nothing the shadowed pass may read (but the hull's share,
  // drawn after the blend's pre-pass).
  if (pass == ShadePass::kLit && taken != TumbleShare::kHull) m.held = {};
  const bool occluded = &variant == &m.hullView && m.hullOcclusion != HullOcclusion::kNone &&
                        (m.hullOcclusion == HullOcclusion::kCores || m.stacked(style) >= kOccludersMinOverdraw) &&
                        m.drawOccluders(style, samples);
  const NailboardProgram& nb = variant[passProgramIndex(pass)];
  const GLuint p = nb.program.get();
  m.setUniforms(nb, style, samples);
  glProgramUniform1i(p, nb.occluded, occluded ? 1 : 0);
  if (occluded) {
    GLint host = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &host);
    glProgramUniform1f(p, nb.occluderSteps, kOccluderSteps * detail::depthStep(detail::hostDepthFormat(host)));
  }
  if (occluded) core::bindTextureAndNoSampler(bindings.visibility, occluders.texture());

  // Every state this pass relies on is set here.
  glUseProgram(p);
  resetPassState();
  if (msaa) {
    glEnable(GL_MULTISAMPLE);
    glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE);
  }
  applyShadePass(pass);
  // The shader's alpha is the edge's coverage, spent on the sample mask: it must not reach the
  // frame, whose alpha stays 1 (an opaque frame, docs/colour.md). GL_SAMPLE_ALPHA_TO_ONE would say
  // the same, but not every driver honours it (Mesa llvmpipe does not); a write mask does.
  if (pass != ShadePass::kDepthOnly) glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(m.count * 6));
  glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
  restoreWriteMasks();
  Impl::unbind();
  s.drawCalls = occluded ? 2 : 1;
  return s;
}

bool NailboardRenderer::Impl::drawOccluders(const Style& style, int samples) {
  GLint host = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &host);
  setUniforms(occluder, style, samples);
  glUseProgram(occluder.program.get());
  resetPassState();
  applyShadePass(ShadePass::kLit);  // the nearer disc wins; depth and colour written, no stencil
  const bool made = occluders.begin(boundViewport(), boundDepthConvention());
  if (made) glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(count * 6));
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(host));
  return made;
}

bool NailboardRenderer::Impl::drawVisibility(const NailboardProgram& visible, const Style& style, int samples) {
  Impl& m = *this;
  const Visible now = current(samples, style);
  const auto host = static_cast<GLuint>(now.framebuffer);
  // The pre-pass: the nailboards' depth and id into Puff's own target (the host's depth is not
  // needed: where the nearest particle lies behind it, so do all the others).
  m.setUniforms(visible, style, samples);
  glUseProgram(visible.program.get());
  resetPassState();
  if (samples > 1) glEnable(GL_MULTISAMPLE);
  applyShadePass(ShadePass::kLit);
  // (The target stays on unit `visibility` while it is drawn into: no sampler of this program reads
  // it, so that is no feedback loop.)
  m.held = {};
  if (!m.visibility.begin(boundViewport(), samples, detail::hostDepthFormat(host), boundDepthConvention())) {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, host);
    return false;
  }
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(m.count * 6));
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, host);
  m.held = now;
  return true;
}

void NailboardRenderer::Impl::drawScreen(const NailboardProgram& shade, ShadePass pass, const Style& style,
                                         int samples) {
  // The shading, once per pixel the pre-pass covered, at the depth it found (the host's depth test;
  // the shadowed pass's, EQUAL, meets the depth the lit pass wrote).
  setUniforms(shade, style, samples);
  // Over the screen rectangle the quads reach (reachLo, reachHi, padPixels).
  const GLuint p = shade.program.get();
  glProgramUniform3fv(p, shade.boxMin, 1, glm::value_ptr(reachLo()));
  glProgramUniform3fv(p, shade.boxMax, 1, glm::value_ptr(reachHi()));
  glProgramUniform1f(p, shade.padPixels, padPixels(style));
  core::bindTextureAndNoSampler(bindings.visibility, visibility.texture());
  glUseProgram(shade.program.get());
  resetPassState();
  if (samples > 1) glEnable(GL_MULTISAMPLE);
  applyShadePass(pass);
  // The shader's alpha is not the frame's (drawNailboards).
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
  if (anyDrawn) glDrawArrays(GL_TRIANGLES, 0, 6);
  restoreWriteMasks();
  Impl::unbind();
}

void NailboardRenderer::setHullOcclusion(HullOcclusion occlusion) { impl_->hullOcclusion = occlusion; }

void NailboardRenderer::setLitShading(LitShading shading) {
  impl_->litShading = shading;
  impl_->held = {};
}

DrawStats NailboardRenderer::drawShadowCasters(const Style& style, const Frame& eye) {
  const core::DebugGroup group("nailboards (shadow casters)");
  Impl& m = *impl_;
  DrawStats s;
  s.particles = m.count;
  if (m.count == 0 || !m.hasAtlas) return s;
  const bool split = m.splitsTumble(style);  // as the eye's passes draw them, by size in the map's texels
  const std::pair<const NailboardProgram*, TumbleShare> draws[2] = {
      {m.desc.views == 1                               ? &m.singleCaster
       : style.tumble == TumbleMethod::kHull && !split ? &m.hullCaster
                                                       : &m.multiCaster,
       split ? TumbleShare::kBlend : TumbleShare::kAll},
      {&m.hullCaster, TumbleShare::kHull}};
  const glm::mat4 eyeToWorld = glm::inverse(eye.view);
  for (int i = 0; i < (split ? 2 : 1); ++i) {
    const NailboardProgram& nb = *draws[i].first;
    const GLuint p = nb.program.get();
    m.share = draws[i].second;
    m.setCommon(p, nb.atlas, style);
    glProgramUniform1i(p, nb.shading, 0);
    glProgramUniform1i(p, nb.outlines, 0);  // the silhouette casts, not the ink
    glProgramUniform1f(p, nb.outlineWidth, 0.0f);
    glProgramUniform1i(p, nb.multisample, 0);  // hard edge at half coverage: the map is not multisampled
    glProgramUniform1f(p, nb.casterBias, std::clamp(style.shadowBias, 0.0f, 1.0f));
    glProgramUniform3fv(p, nb.eyeRight, 1, glm::value_ptr(glm::normalize(glm::vec3(eyeToWorld[0]))));
    glProgramUniform3fv(p, nb.eyeUp, 1, glm::value_ptr(glm::normalize(glm::vec3(eyeToWorld[1]))));
    glUseProgram(p);
    resetPassState();
    applyShadePass(ShadePass::kLit);  // depth LESS + write: the nearest start wins; ids written
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(m.count * 6));
    restoreWriteMasks();
    ++s.drawCalls;
  }
  Impl::unbind();
  return s;
}

DrawStats NailboardRenderer::drawBaseline(const Style& style) {
  const core::DebugGroup group("nailboards (fill-rate floor)");
  Impl& m = *impl_;
  DrawStats s;
  s.particles = m.count;
  if (m.count == 0 || !m.hasAtlas) return s;
  const core::DrawBufferZero drawBuffers;
  m.setCommon(m.sprite.get(), m.spAtlas, style);
  glUseProgram(m.sprite.get());
  resetPassState();
  applyShadePass(ShadePass::kLit);
  // The same write masks as the nailboards' lit pass: the texel's alpha is coverage, not the frame's.
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(m.count * 6));
  restoreWriteMasks();
  Impl::unbind();
  s.drawCalls = 1;
  return s;
}

DrawStats NailboardRenderer::drawShadowVolumes(const Style& style, const glm::vec4& floorPlane,
                                               const VolumeClip& clip) {
  const core::DebugGroup group("nailboards (shadow volumes)");
  Impl& m = *impl_;
  DrawStats s;
  s.particles = m.count;
  if (m.count == 0 || !m.hasAtlas || clip.nothing) return s;
  const core::DrawBufferZero drawBuffers;  // colour writes off: the host's other attachments keep their masks
  const GLuint p = m.shadow.get();
  m.setCommon(p, m.svAtlas, style);
  glProgramUniform1f(p, m.shadowBias, std::clamp(style.shadowBias, 0.0f, 1.0f));
  glProgramUniform1f(p, m.shadowLength, std::max(0.0f, style.shadowLength));
  glProgramUniform4fv(p, m.shadowFloor, 1, glm::value_ptr(floorPlane));

  glUseProgram(p);
  resetPassState();
  // No near or far clipping of the faces: the fragment shader clamps their depth instead.
  glEnable(GL_DEPTH_CLAMP);
  glDepthFunc(nearerDepthFunc(boundDepthConvention()));  // depth-fail counting: a face behind fails
  glDepthMask(GL_FALSE);
  glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glEnable(GL_STENCIL_TEST);
  glStencilMask(0xFF);
  glStencilFunc(GL_ALWAYS, 0, 0xFF);
  // Depth-fail counting: a face behind the receiver counts, exit faces up and entry faces down, so
  // a receiver inside the volume ends non-zero wherever the eye is. The two faces are the same
  // triangles in the same order, drawn twice; the draw (not the winding) says which face it is, so
  // both rasterize and interpolate alike and the count never depends on facing.
  const auto vertices = static_cast<GLsizei>(m.count * 12);
  beginVolumeClip(clip);
  glProgramUniform1i(p, m.shadowBackFace, 0);
  glStencilOp(GL_KEEP, GL_DECR_WRAP, GL_KEEP);
  glDrawArrays(GL_TRIANGLES, 0, vertices);
  glProgramUniform1i(p, m.shadowBackFace, 1);
  glStencilOp(GL_KEEP, GL_INCR_WRAP, GL_KEEP);
  glDrawArrays(GL_TRIANGLES, 0, vertices);
  endVolumeClip();
  glDisable(GL_DEPTH_CLAMP);
  glDisable(GL_STENCIL_TEST);
  restoreWriteMasks();
  Impl::unbind();
  s.drawCalls = 2;
  return s;
}

std::size_t NailboardRenderer::textureBytes() const {
  const Impl& m = *impl_;
  if (!m.hasAtlas) return 0;
  std::size_t bytes = 0;
  for (const core::Texture* t : {&m.maps, &m.color, &m.hull}) {
    if (t->get() == 0) continue;
    GLint levels = 0;
    glGetTextureParameteriv(t->get(), GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
    for (GLint l = 0; l < levels; ++l) {
      GLint w = 0, h = 0, depth = 0, format = 0;
      glGetTextureLevelParameteriv(t->get(), l, GL_TEXTURE_WIDTH, &w);
      glGetTextureLevelParameteriv(t->get(), l, GL_TEXTURE_HEIGHT, &h);
      glGetTextureLevelParameteriv(t->get(), l, GL_TEXTURE_DEPTH, &depth);
      glGetTextureLevelParameteriv(t->get(), l, GL_TEXTURE_INTERNAL_FORMAT, &format);
      std::size_t texelBytes = 0;
      switch (format) {
        case GL_RGBA8:
        case GL_SRGB8_ALPHA8:
          texelBytes = 4;
          break;
        case GL_RGBA16F:
          texelBytes = 8;
          break;
        case GL_R16F:
          texelBytes = 2;
          break;
        default:
          PUFF_CHECK(!"an atlas texture in a format setAtlas never makes");
      }
      bytes += static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(depth) * texelBytes;
    }
  }
  return bytes;
}

}  // namespace puff::cel
