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

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
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

#include "options.h"

namespace {

constexpr float kStep = 1.0f / 60.0f;  // seconds per frame: the simulators' fps is 60
constexpr float kNear = 0.1f, kFar = 100.0f;
constexpr GLuint kCameraBlock = 0;  // the game's camera uniform block: binding 0, as most games do
// Puff's binding points keep their defaults: each an offset from one base per kind, uniform buffers
// from 8, storage buffers from 4 and texture units from 16, clear of the game's camera block on
// uniform buffer 0 and its textures on the low units, which stay bound through every Puff call. A game
// whose own points reached there would pass cel::Bindings::at(base) and media::Bindings::at(base).

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
const glm::vec3 kSmokeAmbient(0.0835f, 0.0890f, 0.1065f);  // scene-linear: display (0.32, 0.33, 0.36)
const glm::vec3 kSky(0.20f, 0.36f, 0.62f);                 // scene-linear
const glm::vec3 kChimneyTop(-2.6f, 1.6f, -1.2f);           // where the smoke leaves the chimney
const glm::vec3 kFirePit(2.4f, 0.15f, -0.6f);              // the fire's base
const glm::vec3 kMarker(0.9f, 1.6f, 2.2f);                 // above the near crate

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

// ---- the game's GL objects and passes ---------------------------------------------------------
// The camera: glm::perspective, so GL's [-1, 1] clip z and standard hyperbolic depth.
struct Camera {
  glm::mat4 view, projection;
};

Camera makeCamera(int width, int height) {
  const glm::vec3 eye(0.3f, 3.0f, 10.5f), lookAt(0.0f, 1.4f, 0.0f);
  return {glm::lookAt(eye, lookAt, glm::vec3(0, 1, 0)),
          glm::perspective(glm::radians(45.0f), float(width) / float(height), kNear, kFar)};
}

// The game's GL objects: its programs, meshes and render targets.
struct GameResources {
  int width = 0, height = 0;  // the frame, pixels
  GLuint sceneProgram = 0, encodeProgram = 0, hudProgram = 0;
  Mesh world, marker;
  GLuint emptyVao = 0;  // the screen passes pull their vertices from gl_VertexID
  Target scene;         // scene-linear colour, standard depth
  Target display;       // display-encoded (sRGB) values
};

GameResources createGameResources(int width, int height) {
  GameResources g;
  g.width = width;
  g.height = height;
  g.sceneProgram = program(kSceneVs, kSceneFs);
  g.encodeProgram = program(kScreenVs, kEncodeFs);
  g.hudProgram = program(kScreenVs, kHudFs);
  std::vector<Vertex> world;
  for (const Box& b : kBoxes) addBox(world, b.centre, b.half, b.albedo);
  g.world = upload(world);
  std::vector<Vertex> marker;  // a diamond: a box turned on its corner by the model matrix
  addBox(marker, glm::vec3(0.0f), glm::vec3(0.18f), glm::vec3(1.0f));
  g.marker = upload(marker);
  glCreateVertexArrays(1, &g.emptyVao);
  g.scene = makeTarget(width, height, GL_RGBA16F, true);
  g.display = makeTarget(width, height, GL_RGBA8, false);
  return g;
}

// The camera written to the game's uniform block, which is bound once to binding 0 and never
// again: Puff is told to use other points.
void bindCameraBlock(const Camera& camera) {
  struct CameraBlock {
    glm::mat4 view, projection;
    glm::vec4 sun;
  } const cameraBlock{camera.view, camera.projection, glm::vec4(kSun, 0.0f)};
  GLuint cameraUbo = 0;
  glCreateBuffers(1, &cameraUbo);
  glNamedBufferStorage(cameraUbo, sizeof cameraBlock, &cameraBlock, 0);
  glBindBufferBase(GL_UNIFORM_BUFFER, kCameraBlock, cameraUbo);
}

// The game's opaque pass: its shaders, its depth.
void drawScene(const GameResources& game) {
  glBindFramebuffer(GL_FRAMEBUFFER, game.scene.fbo);
  glViewport(0, 0, game.width, game.height);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glEnable(GL_CULL_FACE);
  glClearColor(kSky.r, kSky.g, kSky.b, 1.0f);
  glClearDepth(1.0);
  glClearStencil(0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  glUseProgram(game.sceneProgram);
  glProgramUniformMatrix4fv(game.sceneProgram, 0, 1, GL_FALSE, glm::value_ptr(glm::mat4(1.0f)));
  glProgramUniform3f(game.sceneProgram, 1, 0.0f, 0.0f, 0.0f);
  glProgramUniform3fv(game.sceneProgram, 2, 1, glm::value_ptr(kSunColor));
  glProgramUniform3fv(game.sceneProgram, 3, 1, glm::value_ptr(kAmbient));
  glBindVertexArray(game.world.vao);
  glDrawArrays(GL_TRIANGLES, 0, game.world.count);
}

// The game again, after Puff: a spinning marker over the crate.
// What Puff's calls left that this pass needs set (their headers list it): no program and no
// vertex array; depth test off (composeOver), culling off; the draw framebuffer is the game's
// (composeOver binds its target; the cel passes do not change it) but is bound again here so
// the pass stands on its own. The camera block on binding 0 is still the game's: not rebound.
void drawMarker(const GameResources& game, float time) {
  glBindFramebuffer(GL_FRAMEBUFFER, game.scene.fbo);
  glViewport(0, 0, game.width, game.height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glEnable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glUseProgram(game.sceneProgram);
  const glm::mat4 spin =
      glm::rotate(glm::translate(glm::mat4(1.0f), kMarker + glm::vec3(0, 0.1f * std::sin(3 * time), 0)), 1.7f * time,
                  glm::vec3(0, 1, 0)) *
      glm::rotate(glm::mat4(1.0f), glm::radians(45.0f), glm::vec3(1, 0, 1));
  glProgramUniformMatrix4fv(game.sceneProgram, 0, 1, GL_FALSE, glm::value_ptr(spin));
  glProgramUniform3f(game.sceneProgram, 1, 1.0f, 0.8f, 0.05f);  // emissive yellow, scene-linear
  glBindVertexArray(game.marker.vao);
  glDrawArrays(GL_TRIANGLES, 0, game.marker.count);
}

// The display pass: scene-linear -> sRGB into the RGBA8 target.
void drawDisplay(const GameResources& game) {
  glBindFramebuffer(GL_FRAMEBUFFER, game.display.fbo);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glUseProgram(game.encodeProgram);
  glBindVertexArray(game.emptyVao);
  glBindTextureUnit(0, game.scene.colour);
  glBindSampler(0, 0);
  glProgramUniform4f(game.encodeProgram, 0, -1.0f, -1.0f, 1.0f, 1.0f);
  glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
}

// The HUD over the display pass, in display values: a health bar (frame, then fill) and a
// crosshair, alpha blended.
void drawHud(const GameResources& game) {
  const int W = game.width, H = game.height;
  const GLuint hudProgram = game.hudProgram;
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
}

// ---- Puff: cel smoke from the simulator --------------------------------------------------------
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

// What the smoke keeps from frame to frame.
struct Smoke {
  std::unique_ptr<puff::cel::NailboardRenderer> nailboards;
  std::unique_ptr<puff::sim::Simulator> simulator;
  puff::cel::FrameBlock celBlock;
  puff::cel::Ramp ramp;
  puff::cel::Frame celFrame;
  puff::cel::Style style;
  std::vector<puff::cel::Particle> puffs;
};

// What Puff's cel and media frames share, once for both: the game's camera, depth and sun.
puff::core::SharedFrame sharedFrame(const Camera& camera, int width, int height) {
  puff::core::SharedFrame f;
  f.view = camera.view;
  f.projection = camera.projection;  // the game's own matrix, used as is
  f.nearPlane = kNear;
  f.farPlane = kFar;
  f.depth = puff::core::DepthConvention::kStandard;  // hyperbolic, as gl_Position wrote it
  f.clipDepth = puff::core::ClipDepth::kNegativeOneToOne;
  f.viewport = {0, 0, width, height};
  f.light = {kSun, kSunColor};  // scene-linear, as the game lights its world
  f.ambient = kAmbient;
  return f;
}

puff::Result<Smoke> createSmoke(const puff::core::Atlas& atlas, const Camera& camera, int width, int height) {
  PUFF_TRY_ASSIGN(auto nailboards, puff::cel::NailboardRenderer::create());
  if (auto set = (nailboards)->setAtlas(atlas); !set) return set.error();
  PUFF_TRY_ASSIGN(auto smoke, puff::sim::Simulator::create(smokeSettings(), std::max(1, atlas.desc.variations)));
  puff::cel::FrameBlock celBlock;
  // A three-band ramp q (dark, mid, light) instead of the paper's two tones.
  puff::core::Image bands(3, 1, 1);
  bands.pixels = {0.15f, 0.55f, 1.0f};
  PUFF_TRY_ASSIGN(auto ramp, puff::cel::Ramp::create(bands, "the game's ramp"));
  puff::cel::Frame celFrame{sharedFrame(camera, width, height)};
  celFrame.ambient = kSmokeAmbient;  // the smoke's K_a, a palette choice darker than the sky
  puff::cel::Style style;            // outlines on (black ink), Eq. 2 shading
  style.outlineWidth = 2.5f;
  return Smoke{std::move(nailboards), std::move(smoke), std::move(celBlock), std::move(ramp), celFrame, style, {}};
}

// The smoke simulator to `frame`, its particles as nailboards.
void advanceSmoke(Smoke& smoke, int frame) {
  smoke.simulator->advanceToFrame(frame);
  celParticles(*smoke.simulator, smoke.puffs);
}

// The smoke, into the game's framebuffer, tested against its depth.
puff::Result<void> drawSmoke(Smoke& smoke) {
  if (auto ok = smoke.celBlock.upload(smoke.celFrame); !ok) return ok;  // binding 8: the game's block 0 is untouched
  smoke.ramp.bind();
  smoke.nailboards->upload(smoke.puffs);
  smoke.nailboards->drawNailboards(smoke.style, puff::cel::ShadePass::kLit);
  return {};
}

#if GAME_MEDIA_FIRE
// ---- Puff: fire from the media renderer, into the game's frame ---------------------------------
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

// What the fire keeps from frame to frame.
struct Fire {
  std::unique_ptr<puff::media::Renderer> media;
  std::unique_ptr<puff::media::HostLayers> layers;
  std::unique_ptr<puff::sim::Simulator> flames;
  puff::media::Frame mediaFrame;
  puff::media::HostDepth hostDepth;
  std::vector<puff::media::Particle> fireParticles;
};

puff::Result<Fire> createFire(const Camera& camera, GLuint depthTexture, int width, int height) {
  PUFF_TRY_ASSIGN(auto media, puff::media::Renderer::create());
  puff::media::Material fire = puff::media::fireMaterial();
  fire.density = 4.0f;  // denser and brighter than the preset: small flames
  fire.emission = 0.8f;
  fire.becomes = 1;  // fire turns to smoke over its life
  fire.transitionStart = 0.45f;
  fire.transitionEnd = 0.9f;
  if (auto ok = (media)->setMaterials({fire, puff::media::smokeMaterial()}); !ok) return ok.error();
  PUFF_TRY_ASSIGN(auto layers, puff::media::HostLayers::create(width, height, 0.5f));  // the layer at half size
  PUFF_TRY_ASSIGN(auto flames, puff::sim::Simulator::create(fireSettings()));
  const puff::media::Frame mediaFrame{sharedFrame(camera, width, height)};
  // The game's depth texture: read in the frame's convention (standard, the same projection).
  const puff::media::HostDepth hostDepth{.texture = depthTexture};
  return Fire{std::move(media), std::move(layers), std::move(flames), mediaFrame, hostDepth, {}};
}

// The fire simulator to `frame`, its particles as the media renderer takes them.
void advanceFire(Fire& fire, int frame, float time) {
  fire.flames->advanceToFrame(frame);
  mediaParticles(*fire.flames, fire.fireParticles);
  fire.mediaFrame.time = time;
}

// The fire, drawn against the game's depth and composited over its colour, its light on the
// scene flickering with `time`.
puff::Result<void> drawFire(Fire& fire, const GameResources& game, float time) {
  const float flicker = 1.0f + 0.25f * std::sin(time * 11.0f) * std::sin(time * 3.7f);
  const puff::media::ExplosionLight glow{kFirePit + glm::vec3(0, 0.6f, 0), 2.2f, {1.0f, 0.45f, 0.12f}, 0.9f * flicker};
  if (auto ok = fire.layers->resolveHostDepth(fire.hostDepth, fire.mediaFrame); !ok) return ok;
  fire.layers->beginMedia();
  fire.media->draw(fire.layers->layerFrame(fire.mediaFrame), fire.fireParticles, puff::media::Method::kSpherical,
                   fire.layers->mediaDepth());
  const puff::core::Viewport viewport{0, 0, game.width, game.height};
  return fire.layers->composeOver(game.scene.fbo, viewport, fire.mediaFrame, {&glow, 1}, {});
}
#endif

// ---- the frame loop -----------------------------------------------------------------------------
// Esc closes the window.
void handleInput(GLFWwindow* window) {
  glfwPollEvents();
  if (glfwGetKey(window, GLFW_KEY_ESCAPE) == GLFW_PRESS) glfwSetWindowShouldClose(window, GLFW_TRUE);
}

// The last frame, from the display target (the window's pixels may be covered or off-screen), as
// an 8-bit sRGB PNG. `drawn` says what the frame holds.
int writeScreenshot(const Options& opt, const Target& display, const std::string& drawn) {
  const int W = opt.width, H = opt.height;
  std::vector<unsigned char> rgb(static_cast<std::size_t>(W) * H * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(display.colour, 0, GL_RGB, GL_UNSIGNED_BYTE, static_cast<GLsizei>(rgb.size()), rgb.data());
  stbi_flip_vertically_on_write(1);  // GL's rows start at the bottom, PNG's at the top
  if (stbi_write_png(opt.screenshot.c_str(), W, H, 3, rgb.data(), W * 3) == 0)
    return fail("could not write the screenshot " + opt.screenshot.string());
  std::printf("puff_game: %d frames, %s, wrote %s (%d x %d)\n", opt.frames, drawn.c_str(), opt.screenshot.c_str(), W,
              H);
  return 0;
}

// Every GL object, the game's and Puff's, is made here. Then each frame: the simulators step, the
// game draws its scene, Puff its smoke (and fire) into it, the game its marker, the display pass and
// the HUD, and the window shows the result.
int run(const Options& opt, const puff::core::Atlas& atlas, GLFWwindow* window) {
  const int W = opt.width, H = opt.height;
  const Camera camera = makeCamera(W, H);
  const GameResources game = createGameResources(W, H);
  bindCameraBlock(camera);
  auto smoke = createSmoke(atlas, camera, W, H);
  if (!smoke) return fail(smoke.error().message);
#if GAME_MEDIA_FIRE
  auto fire = createFire(camera, game.scene.depth, W, H);
  if (!fire) return fail(fire.error().message);
#endif

  const bool interactive = opt.screenshot.empty();
  for (int frame = 0; interactive ? !glfwWindowShouldClose(window) : frame < opt.frames; ++frame) {
    const float time = frame * kStep;
    advanceSmoke(*smoke, frame);
#if GAME_MEDIA_FIRE
    advanceFire(*fire, frame, time);
#endif
    drawScene(game);
    if (auto ok = drawSmoke(*smoke); !ok) return fail(ok.error().message);
#if GAME_MEDIA_FIRE
    if (auto ok = drawFire(*fire, game, time); !ok) return fail(ok.error().message);
#endif
    drawMarker(game, time);
    drawDisplay(game);
    drawHud(game);
    // Show it: the display target into the window.
    glBlitNamedFramebuffer(game.display.fbo, 0, 0, 0, W, H, 0, 0, W, H, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
      return fail("GL error " + std::to_string(e) + " in frame " + std::to_string(frame));
    glfwSwapBuffers(window);
    handleInput(window);
  }
  if (interactive) return 0;

  std::string drawn = std::to_string(smoke->puffs.size()) + " smoke puffs";
#if GAME_MEDIA_FIRE
  drawn += ", " + std::to_string(fire->fireParticles.size()) + " fire particles";
#else
  drawn += " (built without GAME_MEDIA_FIRE: no fire)";
#endif
  return writeScreenshot(opt, game.display, drawn);
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
