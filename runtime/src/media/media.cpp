// The media pass: materials, back-to-front sorting, the GPU tables and the draw.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <puff/core/bind_points.h>
#include <puff/core/number_text.h>
#include <puff/core/shader.h>
#include <puff/core/stopwatch.h>
#include <puff/gl_api.h>
#include <puff/media/media.h>
#include <puff/shader_blocks.h>

namespace puff::media {

namespace {

Result<void> inRange(const std::string& field, double v, double lo, double hi) {
  if (!(v >= lo && v <= hi))
    return Error{field + ": expected a number in [" + core::numberText(lo) + ", " + core::numberText(hi) + "], got " +
                 core::numberText(v)};
  return {};
}

using shader::MaterialGpu;
using shader::MediaBlockData;

core::Texture makeDetailTexture(const core::DetailVideo* v) {
  core::Texture t = core::makeTexture(GL_TEXTURE_3D, "media: detail video");
  const bool have = v != nullptr && v->width > 0 && v->height > 0 && v->frames > 0;
  const int w = have ? v->width : 1, h = have ? v->height : 1, f = have ? v->frames : 1;
  glTextureStorage3D(t.get(), 1, GL_R16F, w, h, f);
  std::vector<float> flipped(static_cast<std::size_t>(w) * h * f, 0.5f);
  if (have) {
    // DetailVideo rows run top to bottom; GL's t runs bottom to top. Flip so uv (0,0) is bottom-left.
    for (int k = 0; k < f; ++k)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) flipped[(static_cast<std::size_t>(k) * h + (h - 1 - y)) * w + x] = v->at(x, y, k);
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);  // floats: rows are always 4-byte aligned
  glTextureSubImage3D(t.get(), 0, 0, 0, 0, w, h, f, GL_RED, GL_FLOAT, flipped.data());
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTextureParameteri(t.get(), wrap, GL_REPEAT);  // tileable and looping
  glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  return t;
}

// The frame's uniform block: camera, target, light in view space, black-body range, method.
MediaBlockData blockData(const Frame& frame, const Settings& settings, Method method, bool shimmer) {
  MediaBlockData d{};
  d.view = frame.view;
  d.proj = frame.projection;
  d.invProj = glm::inverse(frame.projection);
  d.target = glm::vec4(frame.viewport.width, frame.viewport.height, 1.0f / static_cast<float>(frame.viewport.width),
                       1.0f / static_cast<float>(frame.viewport.height));
  d.origin = glm::vec4(frame.viewport.x, frame.viewport.y, 0.0f, 0.0f);
  d.depth = glm::vec4(frame.nearPlane, frame.farPlane, frame.farPlane - frame.nearPlane, frame.orthographic() ? 1 : 0);
  glm::vec3 l = frame.light.direction;
  l = glm::length(l) > 0.0f ? glm::normalize(l) : glm::vec3(0, 1, 0);
  d.lightDir = glm::vec4(glm::normalize(glm::vec3(frame.view * glm::vec4(l, 0.0f))), 0.0f);
  d.lightColor = glm::vec4(frame.light.color, 1.0f);
  d.ambient = glm::vec4(frame.ambient, 1.0f);
  d.kelvin = glm::vec4(settings.minKelvin, settings.maxKelvin, 1.0f / (settings.maxKelvin - settings.minKelvin),
                       settings.exposure);
  d.mode = glm::ivec4(static_cast<int>(method), shimmer ? 1 : 0, 0, 0);
  d.time = glm::vec4(frame.time, 0.0f, 0.0f, 0.0f);
  d.cartoon = glm::vec4(settings.cartoon.coolKelvin, 1.0f / (settings.cartoon.hotKelvin - settings.cartoon.coolKelvin),
                        0.0f, 0.0f);
  return d;
}

// State: blending per Ilmonen (premultiplied colour, alpha = transmittance multiplier), no depth
// test (surfaces clip in the shader; planar and planar-textured test the opaque depth texture
// there, as the depth unit would), depth clamp for the spherical method only (its far-point
// quads must not be clipped; planar billboards keep the near-plane clipping that makes them pop).
// The cartoon style over-composites draw buffers 0, 2 and 3 (common/media.glsl, cartoonOutputs);
// the photoreal style's programs have no outputs there, and it leaves their state alone.
// The draw buffers a draw of the style sets and writes: the layer and the shimmer, and the
// cartoon's two more. The masks and blending of the rest stay the host's.
GLuint drawnBuffers(bool cartoon) { return cartoon ? 4u : 2u; }

void applyBlendState(Method method, bool shimmer, bool cartoon) {
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
  glDisable(GL_RASTERIZER_DISCARD);  // GL_FRAMEBUFFER_SRGB stays the host's (the layer is float)
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  if (method == Method::kSpherical)
    glEnable(GL_DEPTH_CLAMP);
  else
    glDisable(GL_DEPTH_CLAMP);
  for (GLuint i = 0; i < drawnBuffers(cartoon); ++i) glEnablei(GL_BLEND, i);
  glBlendEquationi(0, GL_FUNC_ADD);
  glBlendFuncSeparatei(0, GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE_MINUS_SRC_ALPHA);
  glBlendEquationi(1, GL_FUNC_ADD);
  glBlendFunci(1, GL_ONE, GL_ONE);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  // Without shimmer, a second attachment (if the host has one) is left untouched.
  const GLboolean s = shimmer ? GL_TRUE : GL_FALSE;
  glColorMaski(1, s, s, s, s);
  if (!cartoon) return;
  for (GLuint i : {2u, 3u}) {
    glBlendEquationi(i, GL_FUNC_ADD);
    glBlendFunci(i, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glColorMaski(i, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  }
}

}  // namespace

Material smokeMaterial() {
  Material m;
  m.name = "smoke";
  m.albedo = 0.2f;
  m.density = 0.4f;
  return m;
}

Material dustMaterial() {
  Material m;
  m.name = "dust";
  m.albedo = 0.9f;
  m.density = 0.4f;
  m.color = {0.85f, 0.75f, 0.6f};
  return m;
}

Material fireMaterial() {
  Material m;
  m.name = "fire";
  m.albedo = 0.0f;
  m.density = 0.4f;
  m.emissive = true;
  m.temperature = 2500.0f;
  m.temperatureRange = 700.0f;
  m.burn = 1.0f;
  m.shimmer = 1.0f;
  return m;
}

Result<void> validate(const Material& m, int count) {
  const std::string at = m.name.empty() ? std::string() : m.name + ": ";
  const std::pair<const char*, std::array<double, 3>> checks[] = {
      {"albedo", {m.albedo, 0, 1}},
      {"density", {m.density, 0, 1e4}},
      {"color/0", {m.color.r, 0, 1}},
      {"color/1", {m.color.g, 0, 1}},
      {"color/2", {m.color.b, 0, 1}},
      {"g", {m.g, -0.95, 0.95}},
      {"temperature", {m.temperature, 0, 1e5}},
      {"temperatureRange", {m.temperatureRange, -1e5, 1e5}},
      {"emission", {m.emission, 0, 1e4}},
      {"burn", {m.burn, 0, 1}},
      {"detail", {m.detail, 0, 1}},
      {"detailWindow", {m.detailWindow, 1e-3, 1}},
      {"detailSpeed", {m.detailSpeed, 0, kMaxDetailSpeed}},
      {"shimmer", {m.shimmer, 0, 1}},
      {"transitionStart", {m.transitionStart, 0, 1}},
      {"transitionEnd", {m.transitionEnd, 0, 1}},
  };
  for (const auto& [name, v] : checks)
    if (auto ok = inRange(at + name, v[0], v[1], v[2]); !ok) return ok;
  if (m.transitionEnd < m.transitionStart)
    return Error{at + "transitionEnd: expected >= transitionStart (" + core::numberText(m.transitionStart) + "), got " +
                 core::numberText(m.transitionEnd)};
  if (m.becomes < -1 || m.becomes >= count)
    return Error{at + "becomes: expected -1 or a material index below " + std::to_string(count) + ", got " +
                 std::to_string(m.becomes)};
  return {};
}

double sphereOpacity(const glm::dvec3& o, const glm::dvec3& dir, const glm::dvec3& c, double r, double tau,
                     double sceneDepth, double nearPlane) {
  const glm::dvec3 m = o - c;
  const double b = glm::dot(m, dir);
  const glm::dvec3 across = glm::cross(m, dir);
  const double d2 = glm::dot(across, across);
  if (!(d2 < r * r)) return 0.0;
  const double d = std::sqrt(d2), w = std::sqrt(r * r - d2);
  const double cosA = -dir.z, oz = -o.z;
  const double tScene = (sceneDepth - oz) / cosA, tNear = (nearPlane - oz) / cosA;
  const double ds = std::max(0.0, std::min(-b + w, tScene) - std::max(-b - w, tNear));
  return 1.0 - std::exp(-tau * (1.0 - d / r) * ds);
}

std::vector<std::uint32_t> backToFront(const glm::mat4& view, std::span<const Particle> particles, SortKey key,
                                       Projection projection) {
  const std::size_t n = particles.size();
  std::vector<std::uint32_t> keys(n), idx(n), tmpKeys(n), tmpIdx(n);
  const glm::vec4 row(view[0][2], view[1][2], view[2][2], view[3][2]);  // camera-space z
  const glm::dmat4 dview(view);
  // The power order from an eye at infinity (orthographic) is the view-axis order (types.h).
  const bool power = key == SortKey::kPowerDistance && projection == Projection::kPerspective;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3& p = particles[i].position;
    // Ascending k = farthest first.
    float k;
    if (power) {
      // -(|c|^2 - r^2): the eye's power with respect to the sphere, largest (farthest) first.
      const glm::dvec3 c(dview * glm::dvec4(glm::dvec3(p), 1.0));
      const double r = particles[i].radius;
      k = static_cast<float>(-(glm::dot(c, c) - r * r));
    } else {
      k = row.x * p.x + row.y * p.y + row.z * p.z + row.w;  // camera-space z: more negative = farther
    }
    if (!std::isfinite(k)) k = 0.0f;
    std::uint32_t bits;
    std::memcpy(&bits, &k, 4);
    // Order-preserving map of floats to unsigned: ascending key = ascending k = farthest first.
    bits = (bits & 0x80000000u) ? ~bits : bits | 0x80000000u;
    keys[i] = bits;
    idx[i] = static_cast<std::uint32_t>(i);
  }
  // LSD radix sort, 4 passes of 8 bits: stable, O(n).
  for (int shift = 0; shift < 32; shift += 8) {
    std::array<std::size_t, 257> count{};
    for (std::size_t i = 0; i < n; ++i) ++count[((keys[i] >> shift) & 0xFF) + 1];
    for (int b = 0; b < 256; ++b) count[b + 1] += count[b];
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t to = count[(keys[i] >> shift) & 0xFF]++;
      tmpKeys[to] = keys[i];
      tmpIdx[to] = idx[i];
    }
    keys.swap(tmpKeys);
    idx.swap(tmpIdx);
  }
  return idx;
}

double falloffWeight(double rho) {
  if (!(rho >= 0.0 && rho < 1.0)) return 0.0;
  return 2.0 * (1.0 - rho) * std::sqrt(1.0 - rho * rho);
}

namespace {

// planar-textured's falloff texture, made once: falloffWeight at each texel centre's distance
// from the quad's centre (in radii; the quad spans [-1, 1]^2), linear filtering, clamped at the
// edges. The size is odd, so the centre texel lies on the quad's centre and the centre is exact.
core::Texture makeFalloffTexture() {
  constexpr int n = kFalloffTexels;
  std::vector<float> w(static_cast<std::size_t>(n) * n);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const double u = (x + 0.5) / n * 2.0 - 1.0, v = (y + 0.5) / n * 2.0 - 1.0;
      w[static_cast<std::size_t>(y) * n + x] = static_cast<float>(falloffWeight(std::sqrt(u * u + v * v)));
    }
  }
  core::Texture t = core::makeTexture(GL_TEXTURE_2D, "media: planar falloff");
  glTextureStorage2D(t.get(), 1, GL_R32F, n, n);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(t.get(), 0, 0, 0, n, n, GL_RED, GL_FLOAT, w.data());
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  return t;
}

}  // namespace

struct Renderer::Impl {
  Settings settings;
  Bindings bindings;
  // The sphere-profile program (planar, soft and spherical: billboard.vert/.frag), the classic
  // textured billboard (billboard_textured.vert/.frag), and each one's fill-rate floor: its own
  // vertex stage and depth test with a fragment stage that computes nothing else.
  core::Program program, textured;  // the cartoon style's versions when Settings::style is kCartoon
  core::Program floorProgram, planarFloor, texturedFloor;
  bool fillRateFloor = false;
  core::Texture falloff;
  core::VertexArray vao;
  core::Buffer block, materialBlock, particleBuffer;
  std::size_t particleCapacity = 0;
  core::Texture blackbody, phase, temperatureDetail, opacityDetail;
  std::vector<Material> materials;
  std::vector<Particle> sorted;
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;
const std::vector<Material>& Renderer::materials() const { return impl_->materials; }
void Renderer::setFillRateFloor(bool on) { impl_->fillRateFloor = on; }

namespace {

// The checks of Renderer::create's arguments: the bindings, the exposure, the sort key and the style.
Result<void> checkSettings(const Settings& settings, const Bindings& bindings) {
  if (auto ok = validate(bindings); !ok) return ok.error();
  if (auto ok = inRange("exposure", settings.exposure, 0, 1e4); !ok) return ok.error();
  if (settings.sort != SortKey::kViewDepth && settings.sort != SortKey::kPowerDistance)
    return Error{"sort: expected view-depth or power-distance, got " + std::to_string(static_cast<int>(settings.sort))};
  if (settings.style != Style::kPhotoreal && settings.style != Style::kCartoon)
    return Error{"style: expected photoreal or cartoon, got " + std::to_string(static_cast<int>(settings.style))};
  if (settings.style == Style::kCartoon) {
    if (auto ok = validate(settings.cartoon); !ok) return Error{"cartoon/" + ok.error().message};
  }
  return {};
}

// The media pass's programs: the sphere-profile and textured billboards and their fill-rate floors.
struct Programs {
  core::Program program, textured, floorProgram, planarFloor, texturedFloor;
};

// Builds the programs, the billboards' cartoon fragment stages when `cartoon`.
Result<Programs> buildPrograms(bool cartoon) {
  PUFF_TRY_ASSIGN(auto program, core::buildProgram({"media/billboard.vert", cartoon ? "media/billboard_cartoon.frag"
                                                                                    : "media/billboard.frag"}));
  PUFF_TRY_ASSIGN(auto textured,
                  core::buildProgram({"media/billboard_textured.vert", cartoon ? "media/billboard_textured_cartoon.frag"
                                                                               : "media/billboard_textured.frag"}));
  PUFF_TRY_ASSIGN(auto floorProgram, core::buildProgram({"media/billboard.vert", "media/floor.frag"}));
  PUFF_TRY_ASSIGN(auto planarFloor, core::buildProgram({"media/billboard.vert", "media/floor_depth_tested.frag"}));
  PUFF_TRY_ASSIGN(auto texturedFloor,
                  core::buildProgram({"media/billboard_textured.vert", "media/floor_depth_tested.frag"}));
  return Programs{std::move(program), std::move(textured), std::move(floorProgram), std::move(planarFloor),
                  std::move(texturedFloor)};
}

// Points program `p`'s blocks and samplers at the units and binding points of `bindings`.
void assignMediaBindPoints(GLuint p, const Bindings& bindings) {
  using K = core::BindPoint::Kind;
  core::assignBindPoints(p, {{K::kUniformBlock, "MediaBlock", bindings.mediaBlock},
                             {K::kUniformBlock, "MaterialBlock", bindings.materialBlock},
                             {K::kStorageBlock, "MediaParticles", bindings.particles},
                             {K::kSampler, "uDepthTex", bindings.depth},
                             {K::kSampler, "uBlackbody", bindings.blackbody},
                             {K::kSampler, "uPhase", bindings.phase},
                             {K::kSampler, "uTemperatureDetail", bindings.temperatureDetail},
                             {K::kSampler, "uOpacityDetail", bindings.opacityDetail},
                             {K::kSampler, "uFalloff", bindings.falloff}});
}

// A new buffer of `bytes` bytes, uninitialized, that glNamedBufferSubData updates.
core::Buffer makeDynamicBuffer(GLsizeiptr bytes) {
  core::Buffer b = core::makeBuffer("media: block");
  glNamedBufferStorage(b.get(), bytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
  return b;
}

// Black body: linear sRGB radiance, negative (out-of-gamut) components kept; the shader clips.
core::Texture makeBlackbodyTexture(const core::BlackbodyRamp& ramp) {
  core::Texture t = core::makeTexture(GL_TEXTURE_1D, "media: black body");
  const int n = static_cast<int>(ramp.rgb.size());
  glTextureStorage1D(t.get(), 1, GL_RGB32F, n);
  glTextureSubImage1D(t.get(), 0, 0, n, GL_RGB, GL_FLOAT, ramp.rgb.data());
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  return t;
}

// The phase texture: `model`'s 4 pi P(cos, g) over s = sin(theta / 2) and g, linearly filtered.
core::Texture makePhaseTexture(PhaseModel model) {
  // Phase: 4 pi P(cos, g), so an isotropic medium scatters exactly the light's colour. Addressed by
  // s = sin(theta / 2) = sqrt((1 - cos) / 2), not cos: the forward peak of g = 0.95 is about 0.03
  // wide in s and 0.001 in cos, so evenly spaced s samples resolve it. Between g rows the lookup
  // mixes two normalized functions, which stays normalized; 256 rows keep that mix within 1% of the
  // exact value on the g = 0.9 peak.
  constexpr int kCos = 512, kG = 256;
  std::vector<float> table(static_cast<std::size_t>(kCos) * kG);
  for (int j = 0; j < kG; ++j) {
    const double g = -0.95 + 1.9 * j / (kG - 1);
    for (int i = 0; i < kCos; ++i) {
      const double sHalf = static_cast<double>(i) / (kCos - 1);
      const double c = 1.0 - 2.0 * sHalf * sHalf;
      table[static_cast<std::size_t>(j) * kCos + i] = static_cast<float>(4.0 * std::numbers::pi * phase(model, c, g));
    }
  }
  core::Texture t = core::makeTexture(GL_TEXTURE_2D, "media: phase function");
  glTextureStorage2D(t.get(), 1, GL_R32F, kCos, kG);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(t.get(), 0, 0, 0, kCos, kG, GL_RED, GL_FLOAT, table.data());
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  return t;
}

}  // namespace

Result<std::unique_ptr<Renderer>> Renderer::create(const Settings& settings, const Bindings& bindings) {
  PUFF_TRY(checkSettings(settings, bindings));
  PUFF_TRY_ASSIGN(auto ramp,
                  core::makeBlackbodyRamp(settings.minKelvin, settings.maxKelvin, 1024, settings.normalizeKelvin));
  PUFF_TRY_ASSIGN(auto programs, buildPrograms(settings.style == Style::kCartoon));

  std::unique_ptr<Renderer> r(new Renderer());
  Impl& m = *r->impl_;
  m.settings = settings;
  m.bindings = bindings;
  m.program = std::move(programs.program);
  m.textured = std::move(programs.textured);
  m.floorProgram = std::move(programs.floorProgram);
  m.planarFloor = std::move(programs.planarFloor);
  m.texturedFloor = std::move(programs.texturedFloor);
  for (const GLuint p :
       {m.program.get(), m.textured.get(), m.floorProgram.get(), m.planarFloor.get(), m.texturedFloor.get()}) {
    assignMediaBindPoints(p, bindings);
  }
  m.falloff = makeFalloffTexture();
  m.vao = core::makeVertexArray("media: vertex array");
  m.block = makeDynamicBuffer(sizeof(MediaBlockData));
  m.materialBlock = makeDynamicBuffer(sizeof(MaterialGpu) * shader::kMaxMaterials);
  m.blackbody = makeBlackbodyTexture(ramp);
  m.phase = makePhaseTexture(settings.phase);

  r->setDetail(nullptr, nullptr);
  auto mats = r->setMaterials({smokeMaterial(), dustMaterial(), fireMaterial()});
  PUFF_CHECK(mats.ok());
  return r;
}

Result<void> Renderer::setMaterials(std::vector<Material> materials) {
  if (materials.empty() || materials.size() > shader::kMaxMaterials)
    return Error{"materials: expected 1 to " + std::to_string(shader::kMaxMaterials) + ", got " +
                 std::to_string(materials.size())};
  std::array<MaterialGpu, shader::kMaxMaterials> gpu{};
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const Material& mt = materials[i];
    if (auto ok = validate(mt, static_cast<int>(materials.size())); !ok) return ok;
    gpu[i].colorAlbedo = glm::vec4(mt.color, mt.emissive ? 0.0f : mt.albedo);
    gpu[i].densityGEmissiveEmission = glm::vec4(mt.density, mt.g, mt.emissive ? 1.0f : 0.0f, mt.emission);
    // An emitter has no opacity detail (its detail is temperature) and scatters nothing (albedo 0).
    gpu[i].tempRangeBurnDetail =
        glm::vec4(mt.temperature, mt.temperatureRange, mt.burn, mt.emissive ? 0.0f : mt.detail);
    gpu[i].windowSpeedShimmerNext =
        glm::vec4(mt.detailWindow, mt.detailSpeed, mt.shimmer, static_cast<float>(mt.becomes));
    gpu[i].transition = glm::vec4(mt.transitionStart, mt.transitionEnd, 0.0f, 0.0f);
  }
  glNamedBufferSubData(impl_->materialBlock.get(), 0, sizeof(gpu), gpu.data());
  impl_->materials = std::move(materials);
  return {};
}

void Renderer::setDetail(const core::DetailVideo* temperature, const core::DetailVideo* opacity) {
  impl_->temperatureDetail = makeDetailTexture(temperature);
  impl_->opacityDetail = makeDetailTexture(opacity);
}

void Renderer::draw(const Frame& frame, std::span<const Particle> particles, Method method, GLuint depth,
                    Shimmer shimmerOutput, DrawStats* stats) {
  const core::DebugGroup group("media particles");
  const bool shimmer = shimmerOutput == Shimmer::kWritten;
  Impl& m = *impl_;
  const auto t0 = core::Clock::now();
  const std::vector<std::uint32_t> order =
      backToFront(frame.view, particles, m.settings.sort,
                  frame.orthographic() ? Projection::kOrthographic : Projection::kPerspective);
  m.sorted.clear();
  m.sorted.reserve(particles.size());
  for (std::uint32_t i : order)
    if (particles[i].radius > 0.0f) m.sorted.push_back(particles[i]);
  if (stats) {
    stats->sortMs = core::millisecondsSince(t0);
    stats->particles = m.sorted.size();
  }
  if (m.sorted.empty()) return;

  const std::size_t bytes = m.sorted.size() * sizeof(Particle);
  if (bytes > m.particleCapacity) {
    m.particleCapacity = std::max(bytes, m.particleCapacity * 2);
    m.particleBuffer = core::makeBuffer("media: particles");
    glNamedBufferStorage(m.particleBuffer.get(), static_cast<GLsizeiptr>(m.particleCapacity), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
  }
  glNamedBufferSubData(m.particleBuffer.get(), 0, static_cast<GLsizeiptr>(bytes), m.sorted.data());

  const MediaBlockData d = blockData(frame, m.settings, method, shimmer);
  glNamedBufferSubData(m.block.get(), 0, sizeof(d), &d);

  applyBlendState(method, shimmer, m.settings.style == Style::kCartoon);

  // The floor of a method keeps its quads and its depth test (planar and planar-textured test
  // the opaque depth; the soft and spherical methods read it only to compute their opacity).
  const bool textured = method == Method::kPlanarTextured;
  GLuint program = textured ? m.textured.get() : m.program.get();
  if (m.fillRateFloor) {
    program = textured ? m.texturedFloor.get() : method == Method::kPlanar ? m.planarFloor.get() : m.floorProgram.get();
  }
  glUseProgram(program);
  glBindVertexArray(m.vao.get());
  // Multi-bind: the generic GL_UNIFORM_BUFFER and GL_SHADER_STORAGE_BUFFER bindings stay the host's.
  const Bindings& b = m.bindings;
  const GLuint blockBuffer = m.block.get(), materialBuffer = m.materialBlock.get(),
               particleBuffer = m.particleBuffer.get();
  const GLintptr offset = 0;
  const auto size = static_cast<GLsizeiptr>(bytes);
  glBindBuffersBase(GL_UNIFORM_BUFFER, b.mediaBlock, 1, &blockBuffer);
  glBindBuffersBase(GL_UNIFORM_BUFFER, b.materialBlock, 1, &materialBuffer);
  glBindBuffersRange(GL_SHADER_STORAGE_BUFFER, b.particles, 1, &particleBuffer, &offset, &size);
  core::bindTextureAndNoSampler(b.depth, depth);
  core::bindTextureAndNoSampler(b.blackbody, m.blackbody.get());
  core::bindTextureAndNoSampler(b.phase, m.phase.get());
  core::bindTextureAndNoSampler(b.temperatureDetail, m.temperatureDetail.get());
  core::bindTextureAndNoSampler(b.opacityDetail, m.opacityDetail.get());
  core::bindTextureAndNoSampler(b.falloff, m.falloff.get());
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(m.sorted.size() * 6));

  glBindVertexArray(0);
  glUseProgram(0);
  for (GLuint i = 0; i < drawnBuffers(m.settings.style == Style::kCartoon); ++i) {
    glDisablei(GL_BLEND, i);
    glColorMaski(i, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  }
  glDisable(GL_DEPTH_CLAMP);
  glDepthMask(GL_TRUE);
}

}  // namespace puff::media
