// The example game: a small scene a game would draw, with Puff's smoke and fire dropped into its
// own frame (docs/embedding.md, "The example game").
//
// What is the game's and what is Puff's:
//  - The game: a GLFW window with a GL 4.5 core context, its own glad loader, its own shaders, its
//    own camera uniform block (binding 0, bound ONCE at start-up), its own framebuffer with colour
//    and depth TEXTURES (RGBA16F scene-linear colour; DEPTH24_STENCIL8 standard hyperbolic depth
//    from glm::perspective, clip z in [-1, 1]), a world-space marker and a HUD drawn after Puff,
//    and the last pass that display-encodes (sRGB) into an RGBA8 target shown in the window.
//  - Puff: initGl from glfwGetProcAddress; a sim::Simulator (emitter, buoyancy, wind, turbulence,
//    colliders) whose particles become cel nailboards with outlines drawn into the game's
//    framebuffer against its standard depth (DepthConvention::kStandard: a pillar cuts the smoke);
//    and (GAME_MEDIA_FIRE) a second simulator's particles drawn as fire by the media renderer,
//    reading the game's depth texture and composited over the game's colour with an explosion
//    light on the scene.
//
// Colour: the scene pass, Puff's passes and the marker all write SCENE-LINEAR values into the
// RGBA16F target; the display pass encodes them to sRGB (the piecewise sRGB curve, in its shader)
// into an RGBA8 target; the HUD is drawn there in display values. The screenshot is that target.
//
// Deterministic: a fixed time step (1/60 s per frame, whatever the display's rate), fixed seeds.
#include <glad/gl.h>  // the game's loader, first

#include <GLFW/glfw3.h>

#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

#include <puff/cel/frame.h>
#include <puff/cel/nailboards.h>
#include <puff/core/atlas.h>
#include <puff/core/gl.h>
#include <puff/sim/simulator.h>
#if GAME_MEDIA_FIRE
#include <puff/media/layers.h>
#include <puff/media/media.h>
#endif

namespace {

constexpr float kStep = 1.0f / 60.0f;  // seconds per frame: the simulators' fps is 60
constexpr float kNear = 0.1f, kFar = 100.0f;
constexpr GLuint kCameraBlock = 0;  // the game's camera uniform block: binding 0, as most games do
// Puff's binding points, chosen by the game: the cel frame block moves off 0 to 1, so the game's
// camera block on 0 stays bound through every Puff call. Everything else keeps its default
// (cel: storage buffers 0-1, units 0-7; media: uniform buffers 3-5, storage buffer 0, units 0-5).
const puff::cel::Bindings kCelBindings{.frameBlock = 1};

int fail(const std::string& what) {
  std::fprintf(stderr, "puff_game: %s\n", what.c_str());
  return 1;
}

// ---- options --------------------------------------------------------------------------------
struct Options {
  std::filesystem::path atlas;       // the sidecar (DIR/puff.json, or a .json given directly)
  std::filesystem::path screenshot;  // empty: interactive
  int frames = 60, width = 960, height = 540;
};

constexpr const char* kHelp =
    "puff_game: a small GLFW game scene with Puff's cel smoke (from the simulator)"
#if GAME_MEDIA_FIRE
    " and media fire"
#endif
    " drawn into the game's own frame.\n"
    "Usage: puff_game --atlas DIR [--screenshot FILE.png [--frames N]] [--width W] [--height H]\n"
    "  --atlas DIR          a cooked atlas: DIR/puff.json (or the sidecar .json itself), e.g. from\n"
    "                       `puffbake bake -g lumpy -o baked`, then\n"
    "                       `puffbake cook baked/puff.json -o DIR/puff.json`; required. The game\n"
    "                       links no image library, so it reads cooked atlases (.puffimg maps) only\n"
    "  --screenshot FILE    render --frames frames at a fixed 1/60 s step, write the last one as an\n"
    "                       8-bit sRGB PNG and exit; without it the window runs until closed (Esc)\n"
    "  --frames N           frames before the screenshot, >= 1 (default 60)\n"
    "  --width W, --height H  the frame in pixels, 16..8192 (default 960 x 540)\n"
    "  --help               this text\n"
    "Needs a display (X11 or Xvfb: xvfb-run -a puff_game ...) and GL 4.5.\n";

bool parseInt(std::string_view s, int lo, int hi, int& out) {
  int v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc{} || end != s.data() + s.size() || v < lo || v > hi) return false;
  out = v;
  return true;
}

// Returns 0 to run, 1 on bad input (message printed), -1 for --help.
int parseOptions(int argc, char** argv, Options& o) {
  bool framesGiven = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "--help" || a == "-h") {
      std::fputs(kHelp, stdout);
      return -1;
    }
    if (i + 1 >= argc) return fail(std::string(a) + ": unknown option or missing value (see --help)");
    const std::string_view v = argv[++i];
    if (a == "--atlas") {
      o.atlas = v;
    } else if (a == "--screenshot") {
      o.screenshot = v;
    } else if (a == "--frames") {
      if (!parseInt(v, 1, 100000, o.frames))
        return fail("--frames: expected an integer in [1, 100000], got " + std::string(v));
      framesGiven = true;
    } else if (a == "--width") {
      if (!parseInt(v, 16, 8192, o.width))
        return fail("--width: expected an integer in [16, 8192], got " + std::string(v));
    } else if (a == "--height") {
      if (!parseInt(v, 16, 8192, o.height))
        return fail("--height: expected an integer in [16, 8192], got " + std::string(v));
    } else {
      return fail(std::string(a) + ": unknown option (see --help)");
    }
  }
  if (o.atlas.empty()) return fail("--atlas DIR is required (a cooked atlas: see --help)");
  if (framesGiven && o.screenshot.empty()) return fail("--frames needs --screenshot");
  std::error_code ec;
  if (std::filesystem::is_directory(o.atlas, ec)) o.atlas /= "puff.json";
  if (!std::filesystem::is_regular_file(o.atlas, ec))
    return fail("no atlas at " + o.atlas.string() + " (a cooked atlas: see --help)");
  if (!o.screenshot.empty()) {
    // Checked before any frame is drawn, so a bad path costs nothing.
    const std::filesystem::path dir = o.screenshot.has_parent_path() ? o.screenshot.parent_path() : ".";
    if (!std::filesystem::is_directory(dir, ec) || ::access(dir.c_str(), W_OK) != 0)
      return fail("cannot write the screenshot " + o.screenshot.string() + ": " + dir.string() +
                  " is not a writable directory");
    if (std::filesystem::is_directory(o.screenshot, ec))
      return fail("cannot write the screenshot " + o.screenshot.string() + ": it is a directory");
  }
  return 0;
}

// ---- the game's GL helpers ------------------------------------------------------------------
GLuint compile(GLenum type, const char* source, std::string& log) {
  GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char text[2048] = {};
    glGetShaderInfoLog(s, sizeof text, nullptr, text);
    log = text;
  }
  return s;
}

GLuint program(const char* vs, const char* fs) {
  std::string log;
  GLuint v = compile(GL_VERTEX_SHADER, vs, log), f = compile(GL_FRAGMENT_SHADER, fs, log);
  GLuint p = glCreateProgram();
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    std::fprintf(stderr, "puff_game: a game shader failed: %s\n", log.c_str());
    std::exit(1);
  }
  return p;
}

// The scene's shader: the camera block (binding 0), a model matrix, Lambert from the sun plus a
// flat ambient, or an emissive colour (the marker). Writes scene-linear colour.
constexpr const char* kSceneVs = R"(#version 450 core
layout(std140, binding = 0) uniform Camera { mat4 view; mat4 projection; vec4 sunDirection; };
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 albedo;
layout(location = 0) uniform mat4 model;
out vec3 vNormal;
out vec3 vAlbedo;
void main() {
  vNormal = mat3(model) * normal;
  vAlbedo = albedo;
  gl_Position = projection * view * model * vec4(position, 1.0);  // standard depth: nothing else
})";
constexpr const char* kSceneFs = R"(#version 450 core
layout(std140, binding = 0) uniform Camera { mat4 view; mat4 projection; vec4 sunDirection; };
layout(location = 1) uniform vec3 emissive;  // > 0: unlit (the marker)
layout(location = 2) uniform vec3 sunColor;
layout(location = 3) uniform vec3 ambient;
in vec3 vNormal;
in vec3 vAlbedo;
out vec4 colour;  // scene-linear
void main() {
  vec3 lit = vAlbedo * (ambient + sunColor * max(dot(normalize(vNormal), sunDirection.xyz), 0.0));
  colour = vec4(any(greaterThan(emissive, vec3(0.0))) ? emissive : lit, 1.0);
})";

// A full-screen triangle: the display pass (scene-linear -> sRGB) and the HUD's rectangles.
constexpr const char* kScreenVs = R"(#version 450 core
layout(location = 0) uniform vec4 rect;  // x0, y0, x1, y1 in NDC
out vec2 uv;
void main() {
  vec2 corner = vec2((gl_VertexID & 1) != 0 ? 1.0 : 0.0, (gl_VertexID & 2) != 0 ? 1.0 : 0.0);
  uv = corner;
  gl_Position = vec4(mix(rect.xy, rect.zw, corner), 0.0, 1.0);
})";
constexpr const char* kEncodeFs = R"(#version 450 core
layout(binding = 0) uniform sampler2D sceneLinear;
in vec2 uv;
out vec4 colour;  // display-encoded sRGB, written to an RGBA8 (UNORM) target
vec3 encode(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}
void main() { colour = vec4(encode(texture(sceneLinear, uv).rgb), 1.0); })";
constexpr const char* kHudFs = R"(#version 450 core
layout(location = 1) uniform vec4 tint;  // display values (sRGB), alpha blended
out vec4 colour;
void main() { colour = tint; })";

struct Vertex {
  glm::vec3 position, normal, albedo;
};

// An axis-aligned box as 12 triangles with outward normals.
void addBox(std::vector<Vertex>& out, glm::vec3 centre, glm::vec3 half, glm::vec3 albedo) {
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {-1.0f, 1.0f}) {
      glm::vec3 n(0.0f);
      n[axis] = sign;
      const glm::vec3 u = axis == 1 ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
      const glm::vec3 v = glm::cross(n, u);
      const glm::vec3 c = centre + n * half;
      const glm::vec3 du = u * half, dv = v * half;
      const glm::vec3 p[4] = {c - du - dv, c + du - dv, c + du + dv, c - du + dv};
      for (int i : {0, 1, 2, 0, 2, 3}) out.push_back({p[i], n, albedo});
    }
  }
}

struct Mesh {
  GLuint vao = 0, vbo = 0;
  GLsizei count = 0;
};

Mesh upload(const std::vector<Vertex>& vertices) {
  Mesh m;
  m.count = static_cast<GLsizei>(vertices.size());
  glCreateBuffers(1, &m.vbo);
  glNamedBufferStorage(m.vbo, static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(), 0);
  glCreateVertexArrays(1, &m.vao);
  glVertexArrayVertexBuffer(m.vao, 0, m.vbo, 0, sizeof(Vertex));
  for (GLuint a = 0; a < 3; ++a) {
    glEnableVertexArrayAttrib(m.vao, a);
    glVertexArrayAttribFormat(m.vao, a, 3, GL_FLOAT, GL_FALSE, a * sizeof(glm::vec3));
    glVertexArrayAttribBinding(m.vao, a, 0);
  }
  return m;
}

// A colour texture + framebuffer (the display target), or colour + depth textures (the scene).
struct Target {
  GLuint fbo = 0, colour = 0, depth = 0;
};

Target makeTarget(int w, int h, GLenum colourFormat, bool withDepth) {
  Target t;
  glCreateTextures(GL_TEXTURE_2D, 1, &t.colour);
  glTextureStorage2D(t.colour, 1, colourFormat, w, h);
  glTextureParameteri(t.colour, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.colour, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glCreateFramebuffers(1, &t.fbo);
  glNamedFramebufferTexture(t.fbo, GL_COLOR_ATTACHMENT0, t.colour, 0);
  if (withDepth) {
    // Standard depth in a depth TEXTURE: Puff's media path reads it (resolveHostDepth).
    glCreateTextures(GL_TEXTURE_2D, 1, &t.depth);
    glTextureStorage2D(t.depth, 1, GL_DEPTH24_STENCIL8, w, h);
    glNamedFramebufferTexture(t.fbo, GL_DEPTH_STENCIL_ATTACHMENT, t.depth, 0);
  }
  if (glCheckNamedFramebufferStatus(t.fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    std::fprintf(stderr, "puff_game: incomplete framebuffer\n");
    std::exit(1);
  }
  return t;
}

// ---- the world ------------------------------------------------------------------------------
const glm::vec3 kSun = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));            // toward the sun
const glm::vec3 kSunColor(0.9f, 0.85f, 0.75f), kAmbient(0.22f, 0.26f, 0.34f);  // scene-linear
const glm::vec3 kSky(0.20f, 0.36f, 0.62f);                                     // scene-linear
const glm::vec3 kChimneyTop(-2.6f, 1.6f, -1.2f);                               // where the smoke leaves the chimney
const glm::vec3 kFirePit(2.4f, 0.15f, -0.6f);                                  // the fire's base
const glm::vec3 kMarker(0.9f, 1.6f, 2.2f);                                     // above the near crate

struct Box {
  glm::vec3 centre, half, albedo;
};
// Albedos are scene-linear reflectances.
const Box kBoxes[] = {
    {{0.0f, -0.05f, 0.0f}, {20.0f, 0.05f, 20.0f}, {0.30f, 0.27f, 0.20f}},  // ground
    {{0.0f, 1.25f, -4.0f}, {7.0f, 1.25f, 0.3f}, {0.30f, 0.26f, 0.24f}},    // back wall
    {{-2.6f, 0.8f, -1.2f}, {0.45f, 0.8f, 0.45f}, {0.40f, 0.10f, 0.06f}},   // chimney
    {{-1.1f, 1.6f, 1.4f}, {0.3f, 1.6f, 0.3f}, {0.45f, 0.45f, 0.50f}},      // pillar, in front of the smoke
    {{0.9f, 0.5f, 2.2f}, {0.5f, 0.5f, 0.5f}, {0.50f, 0.28f, 0.10f}},       // crate
    {{1.75f, 0.35f, 2.9f}, {0.35f, 0.35f, 0.35f}, {0.50f, 0.28f, 0.10f}},  // small crate
    {{2.4f, 0.1f, -0.6f}, {0.6f, 0.1f, 0.6f}, {0.12f, 0.11f, 0.10f}},      // fire pit's stones
};

puff::sim::Settings smokeSettings() {
  puff::sim::Settings s;
  s.fps = 60.0f;
  s.substeps = 2;
  s.preroll = 4.0f;  // the plume is full at frame 0
  s.forces.buoyancy = 0.5f;
  s.forces.drag = 1.0f;
  s.forces.wind = {1.0f, 0.0f, 0.3f};
  s.forces.turbulence = {.strength = 0.25f, .scale = 0.8f, .speed = 0.4f, .seed = 7};
  puff::sim::Emitter e;
  e.shape = puff::sim::Emitter::Shape::kSphere;
  e.position = kChimneyTop;
  e.radius = 0.25f;
  e.rate = 12.0f;
  e.start = -s.preroll;
  e.seed = 11;
  e.velocity = {0.0f, 1.2f, 0.0f};
  e.spreadDegrees = 15.0f;
  e.sizeMin = 0.7f;
  e.sizeMax = 1.1f;
  e.lifetime = 5.0f;
  e.lifetimeSpread = 0.2f;
  s.emitters = {e};
  // The smoke slides over the ground, the back wall and the pillar.
  auto collider = [](puff::sim::Collider::Type type, const char* name, const Box& box) {
    puff::sim::Collider c;
    c.type = type;
    c.name = name;
    c.center = box.centre + (type == puff::sim::Collider::Type::kPlane ? glm::vec3(0, box.half.y, 0) : glm::vec3(0));
    c.halfExtent = box.half;
    return c;
  };
  s.colliders = {collider(puff::sim::Collider::Type::kPlane, "ground", kBoxes[0]),
                 collider(puff::sim::Collider::Type::kBox, "back wall", kBoxes[1]),
                 collider(puff::sim::Collider::Type::kBox, "pillar", kBoxes[3])};
  return s;
}

// The simulator's particles as nailboards: each grows in over the first tenth of its life (the
// simulator's size only shrinks), as puffrender does.
void celParticles(const puff::sim::Simulator& sim, std::vector<puff::cel::Particle>& out) {
  out.clear();
  for (std::size_t i = 0; i < sim.size(); ++i) {
    const puff::sim::ParticleState p = sim.particle(i);
    const float x = std::clamp(p.age / p.lifetime / 0.1f, 0.0f, 1.0f);
    const float size = p.size * x * x * (3.0f - 2.0f * x);
    if (size > 0.0f) out.push_back({p.position, size, p.variation});
  }
}

#if GAME_MEDIA_FIRE
puff::sim::Settings fireSettings() {
  puff::sim::Settings s;
  s.fps = 60.0f;
  s.substeps = 2;
  s.preroll = 2.0f;
  s.forces.buoyancy = 1.5f;
  s.forces.drag = 3.0f;
  s.forces.wind = {0.15f, 0.0f, 0.0f};
  s.forces.turbulence = {.strength = 0.5f, .scale = 0.3f, .speed = 1.0f, .seed = 3};
  puff::sim::Emitter e;
  e.shape = puff::sim::Emitter::Shape::kDisc;
  e.position = kFirePit + glm::vec3(0.0f, 0.1f, 0.0f);
  e.radius = 0.35f;
  e.rate = 90.0f;
  e.start = -s.preroll;
  e.seed = 5;
  e.velocity = {0.0f, 1.8f, 0.0f};
  e.spreadDegrees = 10.0f;
  e.sizeMin = 0.5f;
  e.sizeMax = 0.8f;
  e.lifetime = 1.1f;
  e.lifetimeSpread = 0.25f;
  s.emitters = {e};
  return s;
}

// The fire simulator's particles for the media renderer: material 0 (fire, turning into 1, smoke),
// fading in over the first tenth of the life, the radius growing by half over it.
void mediaParticles(const puff::sim::Simulator& sim, std::vector<puff::media::Particle>& out) {
  out.clear();
  for (std::size_t i = 0; i < sim.size(); ++i) {
    const puff::sim::ParticleState p = sim.particle(i);
    const float life = std::clamp(p.age / p.lifetime, 0.0f, 1.0f);
    const float fade = std::clamp(life / 0.1f, 0.0f, 1.0f);
    out.push_back({p.position, 0.5f * p.birthSize * (1.0f + 0.5f * life), 0u, life, p.density * fade, p.id});
  }
}
#endif

int run(const Options& opt, const puff::core::Atlas& atlas, GLFWwindow* window) {
  const int W = opt.width, H = opt.height;

  // ---- the game's resources ------------------------------------------------------------------
  const GLuint sceneProgram = program(kSceneVs, kSceneFs);
  const GLuint encodeProgram = program(kScreenVs, kEncodeFs);
  const GLuint hudProgram = program(kScreenVs, kHudFs);
  std::vector<Vertex> world;
  for (const Box& b : kBoxes) addBox(world, b.centre, b.half, b.albedo);
  const Mesh worldMesh = upload(world);
  std::vector<Vertex> marker;  // a diamond: a box turned on its corner by the model matrix
  addBox(marker, glm::vec3(0.0f), glm::vec3(0.18f), glm::vec3(1.0f));
  const Mesh markerMesh = upload(marker);
  GLuint emptyVao = 0;  // the screen passes pull their vertices from gl_VertexID
  glCreateVertexArrays(1, &emptyVao);
  const Target scene = makeTarget(W, H, GL_RGBA16F, true);   // scene-linear colour, standard depth
  const Target display = makeTarget(W, H, GL_RGBA8, false);  // display-encoded (sRGB) values

  // The camera: glm::perspective (GL's [-1, 1] clip z), written to the game's uniform block,
  // which is bound once to binding 0 and never again: Puff is told to use other points.
  const glm::vec3 eye(0.3f, 3.0f, 10.5f), lookAt(0.0f, 1.4f, 0.0f);
  const glm::mat4 view = glm::lookAt(eye, lookAt, glm::vec3(0, 1, 0));
  const glm::mat4 projection = glm::perspective(glm::radians(45.0f), float(W) / float(H), kNear, kFar);
  struct CameraBlock {
    glm::mat4 view, projection;
    glm::vec4 sun;
  } const cameraBlock{view, projection, glm::vec4(kSun, 0.0f)};
  GLuint cameraUbo = 0;
  glCreateBuffers(1, &cameraUbo);
  glNamedBufferStorage(cameraUbo, sizeof cameraBlock, &cameraBlock, 0);
  glBindBufferBase(GL_UNIFORM_BUFFER, kCameraBlock, cameraUbo);

  // ---- Puff: cel smoke from the simulator -----------------------------------------------------
  auto nailboards = puff::cel::NailboardRenderer::create(kCelBindings);
  if (!nailboards) return fail(nailboards.error().message);
  if (auto set = (*nailboards)->setAtlas(atlas); !set) return fail(set.error().message);
  auto smoke = puff::sim::Simulator::create(smokeSettings(), std::max(1, atlas.desc.variations));
  if (!smoke) return fail(smoke.error().message);
  puff::cel::FrameBlock celBlock(kCelBindings);
  // A three-band ramp q (dark, mid, light) instead of the paper's two tones.
  puff::core::Image bands(3, 1, 1);
  bands.pixels = {0.15f, 0.55f, 1.0f};
  auto ramp = puff::cel::Ramp::create(bands, "the game's ramp");
  if (!ramp) return fail(ramp.error().message);
  puff::cel::Frame celFrame;
  celFrame.view = view;
  celFrame.projection = projection;  // the game's own matrix, used as is
  celFrame.nearPlane = kNear;
  celFrame.farPlane = kFar;
  celFrame.depth = puff::cel::DepthConvention::kStandard;  // hyperbolic, as gl_Position wrote it
  celFrame.clipDepth = puff::cel::ClipDepth::kNegativeOneToOne;
  celFrame.viewport = {0, 0, W, H};
  celFrame.light = {kSun, glm::vec3(0.75f)};
  celFrame.ambientColor = glm::vec3(0.32f, 0.33f, 0.36f);
  puff::cel::Style style;  // outlines on (black ink), Eq. 2 shading
  style.outlineWidth = 2.5f;
  std::vector<puff::cel::Particle> puffs;

#if GAME_MEDIA_FIRE
  // ---- Puff: fire from the media renderer, into the game's frame -----------------------------
  auto media = puff::media::Renderer::create();
  if (!media) return fail(media.error().message);
  puff::media::Material fire = puff::media::fireMaterial();
  fire.density = 4.0f;  // denser and brighter than the preset: small flames
  fire.emission = 0.8f;
  fire.becomes = 1;  // fire turns to smoke over its life
  fire.transitionStart = 0.45f;
  fire.transitionEnd = 0.9f;
  if (auto ok = (*media)->setMaterials({fire, puff::media::smokeMaterial()}); !ok) return fail(ok.error().message);
  auto layers = puff::media::Layers::createForHost(W, H, 0.5f);  // the media layer at half size
  if (!layers) return fail(layers.error().message);
  auto flames = puff::sim::Simulator::create(fireSettings());
  if (!flames) return fail(flames.error().message);
  puff::media::Frame mediaFrame;
  mediaFrame.view = view;
  mediaFrame.projection = projection;
  mediaFrame.nearPlane = kNear;
  mediaFrame.farPlane = kFar;
  mediaFrame.lightDirection = kSun;
  mediaFrame.lightColor = kSunColor;
  mediaFrame.ambient = kAmbient;
  mediaFrame.width = W;
  mediaFrame.height = H;
  // The game's depth texture as Puff reads it: standard depth from the same projection.
  const puff::media::HostDepth hostDepth{.texture = scene.depth,
                                         .space = {puff::core::DepthConvention::kStandard,
                                                   puff::core::ClipDepth::kNegativeOneToOne, projection, kNear, kFar}};
  std::vector<puff::media::Particle> fireParticles;
#endif

  const bool interactive = opt.screenshot.empty();
  for (int frame = 0; interactive ? !glfwWindowShouldClose(window) : frame < opt.frames; ++frame) {
    const float time = frame * kStep;
    // ---- the game's opaque pass: its shaders, its depth ---------------------------------------
    glBindFramebuffer(GL_FRAMEBUFFER, scene.fbo);
    glViewport(0, 0, W, H);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glEnable(GL_CULL_FACE);
    glClearColor(kSky.r, kSky.g, kSky.b, 1.0f);
    glClearDepth(1.0);
    glClearStencil(0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glUseProgram(sceneProgram);
    glProgramUniformMatrix4fv(sceneProgram, 0, 1, GL_FALSE, glm::value_ptr(glm::mat4(1.0f)));
    glProgramUniform3f(sceneProgram, 1, 0.0f, 0.0f, 0.0f);
    glProgramUniform3fv(sceneProgram, 2, 1, glm::value_ptr(kSunColor));
    glProgramUniform3fv(sceneProgram, 3, 1, glm::value_ptr(kAmbient));
    glBindVertexArray(worldMesh.vao);
    glDrawArrays(GL_TRIANGLES, 0, worldMesh.count);

    // ---- Puff: the smoke, into the game's framebuffer, tested against its depth -----------------
    (*smoke)->advanceToFrame(frame);
    celParticles(**smoke, puffs);
    celBlock.upload(celFrame);  // uniform binding 1: the game's camera block on 0 is untouched
    ramp->bind(kCelBindings);
    (*nailboards)->upload(puffs);
    (*nailboards)->drawNailboards(style, puff::cel::ShadePass::kLit);

#if GAME_MEDIA_FIRE
    // ---- Puff: the fire, drawn against the game's depth and composited over its colour ----------
    (*flames)->advanceToFrame(frame);
    mediaParticles(**flames, fireParticles);
    mediaFrame.time = time;
    const float flicker = 1.0f + 0.25f * std::sin(time * 11.0f) * std::sin(time * 3.7f);
    const puff::media::ExplosionLight glow{
        kFirePit + glm::vec3(0, 0.6f, 0), 2.2f, {1.0f, 0.45f, 0.12f}, 0.9f * flicker};
    if (auto ok = (*layers)->resolveHostDepth(hostDepth); !ok) return fail(ok.error().message);
    (*layers)->beginMedia();
    (*media)->draw((*layers)->layerFrame(mediaFrame), fireParticles, puff::media::Method::kSpherical,
                   (*layers)->mediaDepth());
    const int viewport[4] = {0, 0, W, H};
    if (auto ok = (*layers)->composeOver(scene.fbo, viewport, mediaFrame, {&glow, 1}, {}); !ok)
      return fail(ok.error().message);
#endif

    // ---- the game again, after Puff: a spinning marker over the crate ---------------------------
    // What Puff's calls left that this pass needs set (their headers list it): no program and no
    // vertex array; depth test off (composeOver), culling off; the draw framebuffer is the game's
    // (composeOver binds its target; the cel passes do not change it) but is bound again here so
    // the pass stands on its own. The camera block on binding 0 is still the game's: not rebound.
    glBindFramebuffer(GL_FRAMEBUFFER, scene.fbo);
    glViewport(0, 0, W, H);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glEnable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glUseProgram(sceneProgram);
    const glm::mat4 spin =
        glm::rotate(glm::translate(glm::mat4(1.0f), kMarker + glm::vec3(0, 0.1f * std::sin(3 * time), 0)), 1.7f * time,
                    glm::vec3(0, 1, 0)) *
        glm::rotate(glm::mat4(1.0f), glm::radians(45.0f), glm::vec3(1, 0, 1));
    glProgramUniformMatrix4fv(sceneProgram, 0, 1, GL_FALSE, glm::value_ptr(spin));
    glProgramUniform3f(sceneProgram, 1, 1.0f, 0.8f, 0.05f);  // emissive yellow, scene-linear
    glBindVertexArray(markerMesh.vao);
    glDrawArrays(GL_TRIANGLES, 0, markerMesh.count);

    // ---- the display pass: scene-linear -> sRGB into the RGBA8 target, then the HUD ------------
    glBindFramebuffer(GL_FRAMEBUFFER, display.fbo);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glUseProgram(encodeProgram);
    glBindVertexArray(emptyVao);
    glBindTextureUnit(0, scene.colour);
    glBindSampler(0, 0);
    glProgramUniform4f(encodeProgram, 0, -1.0f, -1.0f, 1.0f, 1.0f);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    // The HUD, in display values: a health bar (frame, then fill) and a crosshair, alpha blended.
    glUseProgram(hudProgram);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glBlendEquation(GL_FUNC_ADD);
    auto rect = [&](float x0, float y0, float x1, float y1, glm::vec4 tint) {
      // pixels, origin bottom-left
      glProgramUniform4f(hudProgram, 0, 2 * x0 / W - 1, 2 * y0 / H - 1, 2 * x1 / W - 1, 2 * y1 / H - 1);
      glProgramUniform4fv(hudProgram, 1, 1, glm::value_ptr(tint));
      glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    };
    const float health = 0.75f;
    rect(16, 16, 16 + 0.3f * W, 40, {0.0f, 0.0f, 0.0f, 0.6f});
    rect(20, 20, 20 + (0.3f * W - 8) * health, 36, {0.86f, 0.20f, 0.16f, 1.0f});
    rect(W / 2.0f - 10, H / 2.0f - 1, W / 2.0f + 10, H / 2.0f + 1, {1.0f, 1.0f, 1.0f, 0.85f});
    rect(W / 2.0f - 1, H / 2.0f - 10, W / 2.0f + 1, H / 2.0f + 10, {1.0f, 1.0f, 1.0f, 0.85f});
    glDisable(GL_BLEND);

    // ---- show it -------------------------------------------------------------------------------
    glBlitNamedFramebuffer(display.fbo, 0, 0, 0, W, H, 0, 0, W, H, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
      return fail("GL error " + std::to_string(e) + " in frame " + std::to_string(frame));
    glfwSwapBuffers(window);
    glfwPollEvents();
    if (glfwGetKey(window, GLFW_KEY_ESCAPE) == GLFW_PRESS) glfwSetWindowShouldClose(window, GLFW_TRUE);
  }

  int status = 0;
  if (!interactive) {
    // The last frame, from the display target (the window's pixels may be covered or off-screen).
    std::vector<unsigned char> rgb(static_cast<std::size_t>(W) * H * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(display.colour, 0, GL_RGB, GL_UNSIGNED_BYTE, static_cast<GLsizei>(rgb.size()), rgb.data());
    stbi_flip_vertically_on_write(1);  // GL's rows start at the bottom, PNG's at the top
    if (stbi_write_png(opt.screenshot.c_str(), W, H, 3, rgb.data(), W * 3) == 0) {
      status = fail("could not write the screenshot " + opt.screenshot.string());
    } else {
      std::printf("puff_game: %d frames, %zu smoke puffs%s, wrote %s (%d x %d)\n", opt.frames, puffs.size(),
#if GAME_MEDIA_FIRE
                  (", " + std::to_string(fireParticles.size()) + " fire particles").c_str(),
#else
                  " (built without GAME_MEDIA_FIRE: no fire)",
#endif
                  opt.screenshot.c_str(), W, H);
    }
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  if (int parsed = parseOptions(argc, argv, opt); parsed != 0) return parsed < 0 ? 0 : 1;
  const int W = opt.width, H = opt.height;
  // The atlas is read before any window opens: a cooked atlas, with no image library (an uncooked
  // one is refused with the command that cooks it).
  auto atlas = puff::core::loadAtlas(opt.atlas);
  if (!atlas) return fail(atlas.error().message);

  // ---- the game's window, context and loader ------------------------------------------------
  if (!glfwInit()) return fail("GLFW could not start (no display? run under xvfb-run -a)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(W, H, "Puff: the example game", nullptr, nullptr);
  if (window == nullptr) {
    glfwTerminate();
    return fail("could not open a GL 4.5 core window");
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(opt.screenshot.empty() ? 1 : 0);
  if (gladLoadGL(glfwGetProcAddress) == 0) return fail("the game's glad could not load GL");
  // Puff loads its own (private) function pointers through the same getProcAddress.
  if (auto gl = puff::core::initGl(glfwGetProcAddress); !gl) return fail(gl.error().message);
  const int status = run(opt, *atlas, window);  // every GL object, the game's and Puff's, goes in there
  glfwDestroyWindow(window);
  glfwTerminate();
  return status;
}
