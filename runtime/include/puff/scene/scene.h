// The scene file's contents: everything puffrender and puffview need to draw a frame. Reading
// (read.h) and writing (write.h) are separate; evaluate.h turns a scene and a frame number into
// what that frame draws. docs/scene-format.md is the annotated reference; art/scenes/ holds
// working examples. No GL anywhere in puff::scene.
//
// Every field is optional ("zero means default": a scene lists only what it changes). Relative
// paths resolve against the scene file's directory; "${PUFF_ART}" at the start of a path means
// the baked-art directory given to the loader.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <puff/core/colour.h>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <puff/cel/types.h>
#include <puff/core/error.h>
#include <puff/media/types.h>
#include <puff/sim/simulator.h>

namespace puff::scene {

/// One particle listed in the scene.
struct ParticleSpec {
  glm::vec3 position{0.0f};
  float size = 1.0f;                              ///< diameter at birth, world units, >= 0
  int variation = 0;                              ///< [0, 255]
  bool oriented = false;                          ///< see cel::Particle
  glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};  ///< JSON: axis-angle {"axis": [x,y,z], "degrees": a}
  glm::vec3 velocity{0.0f};                       ///< world units per second
  glm::vec3 angularVelocity{0.0f};                ///< world-space axis * radians per second
  float birth = 0.0f;                             ///< seconds; not drawn before
  float lifetime = 0.0f;                          ///< seconds; 0 = lives forever. Size falls linearly to 0 at the end.
  bool operator==(const ParticleSpec&) const = default;
};

/// A deterministic generator of particles (not the simulator: no forces). Places `count`
/// particles in a shape from `seed`; each gets a size in [sizeMin, sizeMax], a random variation,
/// a velocity `velocity` + a random vector of length <= `speedSpread`, a birth time uniform in
/// [0, birthSpread] seconds, and `lifetime` (0 = forever).
struct EmitterSpec {
  enum class Shape {
    kSphere,  ///< uniform in a ball of `radius` around `center`
    kBox,     ///< uniform in the box `center` +- `halfExtent`
    kCone,    ///< along the segment `center` -> `end`, radius growing from `radius` to `endRadius`
              ///< (a missile trail, a lamp's plume); particles near `end` are born later
  };
  Shape shape = Shape::kSphere;
  int count = 100;  ///< [0, 1'000'000]
  unsigned seed = 1;
  glm::vec3 center{0.0f};
  float radius = 1.0f;                   ///< sphere radius / cone start radius, >= 0
  glm::vec3 halfExtent{1.0f};            ///< box
  glm::vec3 end{0.0f, 1.0f, 0.0f};       ///< cone end point
  float endRadius = 1.0f;                ///< cone end radius
  float sizeMin = 0.5f, sizeMax = 1.0f;  ///< 0 <= sizeMin <= sizeMax
  /// Particles nearer the shape's edge are smaller (size *= 1 - falloff * r/R): [0, 1].
  float sizeFalloff = 0.0f;
  std::vector<int> variations;  ///< allowed variations; empty = all of the atlas's
  bool oriented = false;        ///< give particles random orientations (multi-view atlases)
  float spin = 0.0f;            ///< random angular velocity up to this, radians per second
  glm::vec3 velocity{0.0f};
  float speedSpread = 0.0f;
  float birthSpread = 0.0f;
  float lifetime = 0.0f;
  /// Size over the life (needs a lifetime > 0); density is not drawn by nailboards.
  sim::LifeCurves overLife;
  bool operator==(const EmitterSpec&) const = default;
};

/// A rigid body simulated with ODE (McGuire & Fein §3's "Newtonian rigid body simulator").
/// Its motion is computed once per scene, from where the object stands at t = 0, at a fixed step
/// (RigidBodies): ObjectSpec::path then holds its trajectory (positions and rotations), so every
/// frame reads it as a pure function of time and everything that follows keyframed objects (the
/// renderers, the smoke's colliders, "attach") follows the body.
struct DynamicBody {
  float mass = 1.0f;                ///< kg, [0.001, 1e6]; spread uniformly through the box or sphere
  glm::vec3 velocity{0.0f};         ///< world units / s at t = 0
  glm::vec3 angularVelocity{0.0f};  ///< world-space axis times radians / s at t = 0
  float friction = 0.5f;            ///< Coulomb mu of its contacts, [0, 10] (two bodies: their mean)
  float restitution = 0.3f;         ///< bounce, [0, 1] (two bodies: the larger)
  bool operator==(const DynamicBody&) const = default;
};

/// The rigid-body world: gravity and the fixed step.
struct RigidBodies {
  glm::vec3 gravity{0.0f, -9.81f, 0.0f};  ///< world units / s^2
  int stepsPerSecond = 240;               ///< [24, 10000]
  bool operator==(const RigidBodies&) const = default;
};

struct ObjectSpec {
  enum class Type { kPlane, kBox, kSphere, kMesh };
  Type type = Type::kPlane;
  std::string name;            ///< defaults to "objects/N"
  std::filesystem::path mesh;  ///< kMesh: a mesh file (mesh::kMeshFormatsRead), resolved
  glm::vec3 translate{0.0f};
  glm::vec3 rotateDegrees{0.0f};  ///< XYZ Euler angles, applied X then Y then Z
  glm::vec3 scale{1.0f};          ///< plane: half-size in x and z; box: half extents; sphere: radius
  glm::vec3 albedo{0.8f};         ///< a display value (scene::linearAlbedo decodes it for the renderers)
  bool cel = true;                ///< cel (the ramp) or smooth shading
  /// A moving object: its position is translate + path(t), t in seconds of scene time. Simulated
  /// vortices and emitters can ride on it ("attach": its name).
  sim::Path path;
  bool collide = true;    ///< simulated particles collide with it (scenes with a "simulation")
  float friction = 0.0f;  ///< [0, 1], for simulated particles sliding on it
  /// A box or sphere simulated as a rigid body (not with a keyframed `path`: `path` is then its
  /// computed trajectory, never written back to a scene file).
  std::optional<DynamicBody> dynamic;
  bool operator==(const ObjectSpec&) const = default;
};

struct Animation {
  float fps = 24.0f;  ///< > 0
  int frames = 1;     ///< frames in the sequence, >= 1
  /// Camera turns about the vertical axis through its target, degrees per second.
  float orbitDegreesPerSecond = 0.0f;
  /// A camera flight: the camera's position (and, if given, its target) follow these keys
  /// (seconds of scene time, linear between keys, held outside them); the orbit turns after.
  sim::Path cameraPath, targetPath;
  /// > 0: the scene is a loop of `period` frames (sim::Settings::period for both simulators): frame
  /// f + period draws what frame f does, so a flipbook of one period loops without a seam. What does
  /// not repeat is refused (scene::checkLoop). [0, sim::kMaxPeriod]; 0 = no loop.
  int period = 0;
  bool operator==(const Animation&) const = default;
};

/// A media particle listed in the scene (it does not move).
struct MediaParticleSpec {
  glm::vec3 position{0.0f};
  float radius = 1.0f;             ///< world units, >= 0
  std::string material = "smoke";  ///< a name in MediaSpec::materials
  int materialIndex = 0;           ///< resolved by the parser
  float life = 0.0f;               ///< [0, 1]: where it is in its material's transition
  float density = 1.0f;            ///< multiplies the material's tau, >= 0
  std::uint32_t seed = 0;          ///< its detail window
  bool operator==(const MediaParticleSpec&) const = default;
};

/// Media particles born by the simulator (an explosion's burst, a fire's stream). The emitter's
/// size is the diameter at birth; the radius grows to (1 + growth) times its birth value over the
/// particle's life while its density (which multiplies the material's tau) falls linearly to 0:
/// it fades, never pops.
struct MediaEmitterSpec {
  sim::Emitter emitter;
  std::string material = "smoke";
  int materialIndex = 0;  ///< resolved by the parser
  float growth = 0.0f;    ///< [0, 100]
  bool operator==(const MediaEmitterSpec&) const = default;
};

/// An explosion's light on the scene (media::ExplosionLight), its intensity keyed in time.
struct MediaLightSpec {
  glm::vec3 center{0.0f};
  float radius = 1.0f;
  glm::vec3 color{1.0f, 0.6f, 0.25f};
  std::vector<float> times{0.0f}, intensities{1.0f};  ///< linear between keys, held outside
  bool modulate = false;
  bool fullAtBack = false;
  float intensityAt(double t) const;
  bool operator==(const MediaLightSpec&) const = default;
};

/// The translucent media (puff::media): fire, smoke and dust composited over the opaque scene.
struct MediaSpec {
  media::Method method = media::Method::kSpherical;
  float resolution = 0.5f;  ///< the media layer's share of the output size: 1, 0.5, 0.25 or 0.125
  media::Settings settings;
  std::vector<media::Material> materials{media::smokeMaterial(), media::dustMaterial(), media::fireMaterial()};
  std::filesystem::path temperatureDetail, opacityDetail;  ///< detail videos; empty = none
  media::ComposeSettings compose;
  /// Motion blur: each frame is the weighted sum of itself and the `motionBlurFrames` before it,
  /// weights persistence^age, so earlier frames fade (0 frames: off). A frame alone equals the same
  /// frame of a sequence.
  int motionBlurFrames = 0;
  float motionBlurPersistence = 0.5f;  ///< [0, 1)
  std::vector<MediaParticleSpec> particles;
  std::vector<MediaEmitterSpec> emitters;
  sim::Forces forces;  ///< what moves the simulated media (buoyancy, drag, wind, turbulence...)
  int substeps = 2;
  float preroll = 0.0f;
  std::size_t maxParticles = 100'000;
  float collisionRadius = 0.5f;
  std::vector<MediaLightSpec> lights;
  bool operator==(const MediaSpec&) const = default;
};

/// How the fixed-function path (puff::fixedfunc, McGuire & Fein §4.4) draws this scene.
struct FixedSettings {
  std::filesystem::path puff;  ///< the puff mesh; empty: the atlas's first source mesh
  float outlineScale = 1.1f;   ///< backing billboard size / particle size on screen, [1, 4]
  float outlineOffset = 0.0f;  ///< d, world units, >= 0; 0 = the billboard's width (the paper's)
  int cellSize = 128;          ///< texels per orientation of the puff texture: 32, 64, 128 or 256
                               ///< (halved until 2 cells fit in the frame's smaller side)
  bool operator==(const FixedSettings&) const = default;
};

/// The scene file's light. Its colour is a display value, as every colour in a scene is; the
/// renderers' frames get it decoded to scene-linear (core::Light).
struct LightSpec {
  glm::vec3 direction{0.4f, 1.0f, 0.3f};  ///< world space, toward the light; non-zero
  glm::vec3 color{1.0f};                  ///< K_L, a display value
  bool operator==(const LightSpec&) const = default;
};

struct Scene {
  std::filesystem::path file;     ///< the file it was loaded from (for messages)
  int width = 640, height = 480;  ///< output size, [1, 16384]
  int samples = 4;                ///< MSAA samples for antialiased edges: 1, 2, 4 or 8
  glm::vec3 background{1.0f};     ///< clear colour, a display value (sRGB-encoded)
  /// output.background "transparent": nothing is drawn behind the frame; its alpha is the frame's
  /// coverage (SceneRenderer::renderFrame, docs/scene-format.md). `background` is then unused.
  bool transparent = false;
  /// How a transparent frame's alpha is written (only with `transparent`). Empty: each file's own
  /// convention, straight in PNG, premultiplied in EXR (which refuses straight).
  std::optional<core::AlphaMode> alpha;
  /// output.plate: an image drawn under the frame instead of the background colour (display values,
  /// decoded to scene-linear; stretched to the frame, render::resizePlate). Empty: none. Not with
  /// `transparent`.
  std::filesystem::path plate;
  /// How the scene-linear frame becomes display values for PNG and the screen (docs/colour.md);
  /// EXR output is the scene-linear frame before it. Empty: automatic, viewTransformFor().
  std::optional<core::ViewTransform> view;
  cel::Camera camera;
  LightSpec light;
  glm::vec3 ambientColor{0.25f};          ///< uniform K_a, a display value
  std::filesystem::path ambientGradient;  ///< image-space K_a(x, y); empty = uniform
  std::filesystem::path ramp;             ///< q ramp image; empty = the built-in two-tone ramp
  bool rampSmooth = false;                ///< linear filtering of the ramp
  std::filesystem::path atlas;            ///< atlas sidecar JSON (required if there are particles)
  /// Draw the nailboards with the atlas from this mip level on (0: the atlas as baked; k: its cells
  /// 2^k times smaller, as if baked at that size). [0, 14]; SceneRenderer refuses a level deeper than
  /// the atlas allows (core::deepestAtlasLevel). eval::chooseCelBudget can choose it.
  int atlasLevel = 0;
  /// Draw this share of each placed emitter's particles (`emitters`: its first round(count * f), at
  /// least 1), each (1 / f)^(1/3) times larger so they fill about the same volume: fewer, bigger puffs
  /// (the particle count a budget chooses). (0, 1]; listed particles and the simulator's are not thinned.
  /// eval::chooseCelBudget can choose it.
  float particleFraction = 1.0f;
  std::string stylePreset;  ///< named preset applied before the explicit style fields
  cel::Style style;         ///< as the file gives it: its outlineColor a display value (scene::celStyleFor decodes it)
  std::vector<ParticleSpec> particles;
  std::vector<EmitterSpec> emitters;
  std::vector<ObjectSpec> objects;
  RigidBodies rigidBodies;  ///< for objects with `dynamic`
  Animation animation;
  /// The smoke simulator (forces, emitters; colliders come from `objects` with collide = true).
  /// Its fps is the animation's. Absent: particles and emitters above move without forces.
  std::optional<sim::Settings> simulation;
  FixedSettings fixed;
  /// Fire, smoke and dust (the programmable path only; the fixed-function path draws without them).
  std::optional<MediaSpec> media;
  bool operator==(const Scene&) const = default;
};

/// Named style presets: "outlines" (Fig. 8a), "cel" (Fig. 8b), "cel-shadows" (Fig. 8c),
/// "ink" (Fig. 9: outlines, flat), "solid" (Fig. 13d: flat, outlines). Unknown names are an error
/// listing these.
std::vector<std::string> stylePresetNames();
Result<cel::Style> stylePreset(const std::string& name);

}  // namespace puff::scene
