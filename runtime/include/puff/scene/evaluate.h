// What a frame of a scene draws. A frame is a pure function of (scene, frame number): listed
// particles move by their velocities and spin by their angular velocities from their birth time,
// shrink linearly to nothing over their lifetime (size follows density, so nothing pops), and
// emitters place particles from their seed; a "simulation" is stepped from its start to the frame
// (puff::sim). Any frame evaluated alone equals the same frame of a full run. Particles with a
// lifetime also grow in over its first tenth (celBirthGrowth), so nothing pops at birth either.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include <puff/cel/types.h>
#include <puff/core/error.h>
#include <puff/media/types.h>
#include <puff/scene/geometry.h>
#include <puff/scene/scene.h>
#include <puff/sim/simulator.h>

namespace puff::core {
struct DetailVideo;
}  // namespace puff::core

namespace puff::scene {

/// Whether the scene has cel particles: listed, placed by emitters, or simulated.
bool hasParticles(const Scene& scene);

/// The JSON pointer of the first thing in the scene that asks for oriented puffs (a particle, an
/// emitter or a simulator emitter with `oriented`), e.g. "/emitters/1/oriented"; empty when none does.
std::string orientedPuffs(const Scene& scene);

/// Seconds at frame `frame` (frame / fps).
float frameTime(const Scene& scene, int frame);
/// Object space -> world of an object at scene time `t` (seconds): translate(translate + path(t)) *
/// rotate (X, then Y, then Z) * scale.
glm::mat4 objectTransform(const ObjectSpec& object, double t = 0.0);

/// The simulator's settings for the scene: its "simulation" with the animation's fps and the
/// colliding objects as colliders (their shapes from `geometry`). No simulation: empty.
Result<std::optional<sim::Settings>> simulationSettings(const Scene& scene, const SceneGeometry& geometry);

/// The simulator's settings for the scene's media emitters (colliders as above). No media
/// emitters: empty.
Result<std::optional<sim::Settings>> mediaSimulationSettings(const Scene& scene, const SceneGeometry& geometry);

/// The particles alive at `frame` that the scene lists or places with its (force-free) emitters:
/// moved, spun and shrunk. Pure. Simulated particles are not included (see SceneRenderer).
/// `variations` is the atlas's variation count (>= 1), for emitters that pick any variation.
/// `keys`, when given, receives each particle's identity across frames (particleKey), in the same order.
std::vector<cel::Particle> particlesAt(const Scene& scene, int frame, int variations,
                                       std::vector<std::uint64_t>* keys = nullptr);

/// Where a cel particle comes from, for its key: listed (index in /particles), placed by an emitter
/// (emitter index, particle index), or simulated (the simulator's id).
enum class ParticleSource : std::uint64_t { kListed = 0, kEmitted = 1, kSimulated = 2 };
/// A particle's identity across frames: the same particle has the same key in every frame it lives,
/// and two particles of one frame never share one (a simulated particle's id is a 32-bit hash: two
/// that collide share a key, which a frame's motion takes as one particle).
inline std::uint64_t particleKey(ParticleSource source, std::uint32_t a, std::uint32_t b = 0) {
  return (static_cast<std::uint64_t>(source) << 62) | (static_cast<std::uint64_t>(a & 0x3FFFFFFFu) << 32) | b;
}
/// The scene's media materials as they are drawn: their colours in scene-linear (the scene file's
/// colours are display values, docs/colour.md; the media renderer and its references light in
/// linear), and in a loop their detail speeds rounded (loopDetailSpeed) for the detail videos
/// given (those the scene names, loaded; none: frames of one). Requires scene.media.
std::vector<media::Material> linearMediaMaterials(const Scene& scene, const core::DetailVideo* temperature = nullptr,
                                                  const core::DetailVideo* opacity = nullptr);
/// What the cel and media frames share for `camera` over a width x height viewport at (0, 0):
/// view, projection, planes, the depth convention of Puff's own renderer (kLinear, cel/frame.h
/// says why), and the scene's light and ambient colours DECODED to scene-linear (the scene file
/// holds display values).
core::SharedFrame sharedFrameFor(const Scene& scene, const cel::Camera& camera, int width, int height);
/// The media renderer's frame: sharedFrameFor and the scene time `time`.
media::Frame mediaFrameFor(const Scene& scene, const cel::Camera& camera, float time, int width, int height);
/// The scene's cel style as the renderers take it: its ink DECODED to scene-linear (the scene file
/// holds a display value).
cel::Style celStyleFor(const Scene& scene);
/// A scene object's albedo as the renderers take it, DECODED to scene-linear.
glm::vec3 linearAlbedo(const ObjectSpec& object);
/// Whether the scene draws fire: a media particle or emitter whose material (or the material it
/// becomes) is emissive.
bool hasFire(const Scene& scene);
/// The scene's view transform: scene.view, or when it is empty `filmic` for scenes with fire
/// (hasFire) and `standard` for the rest (docs/colour.md).
core::ViewTransform viewTransformFor(const Scene& scene);
/// The camera at `frame` (orbit applied).
cel::Camera cameraAt(const Scene& scene, int frame);

/// Media particles from emitters fade in: their density is multiplied by mediaBirthFade(life), a
/// smoothstep from 0 at birth to 1 at kMediaBirthFade of their life, so none appears at full
/// density in one frame (a pop). Smooth (C1) at both ends: no kink in the density where the fade
/// meets the linear fade-out, so a particle's second difference from frame to frame shrinks with
/// the square of the frames the fade spans. 10% of the life: at 24 fps it spans 4 frames of the
/// explosion's shortest-lived fire (1.8 s) and 10 of its smoke (4 s), and keeps 90% of the
/// particle's peak density (the density falls linearly from birth).
inline constexpr float kMediaBirthFade = 0.1f;
float mediaBirthFade(float life);

/// Cel particles with a lifetime (listed, placed or simulated) grow in: their size is multiplied by
/// celBirthGrowth(age / lifetime), the same smoothstep over the first kCelBirthGrowth of the life,
/// so a puff does not appear at full size in one frame (a pop); after it they shrink linearly to
/// nothing as before. The simulator's collision radius is not changed.
inline constexpr float kCelBirthGrowth = 0.1f;
float celBirthGrowth(float life);

/// What one frame draws, evaluated from the scene and the frame number alone.
struct FrameInputs {
  int frame = 0;
  float time = 0.0f;   ///< seconds of scene time (frameTime)
  cel::Camera camera;  ///< cameraAt(frame), or the caller's camera
  /// Listed, placed and simulated cel particles, in that order (none when the scene draws no
  /// nailboards: FrameEvaluator::create got 0 variations).
  std::vector<cel::Particle> particles;
  std::size_t simulated = 0;           ///< of `particles`, from the simulator
  std::vector<std::uint64_t> keys;     ///< particleKey of each of `particles`
  std::vector<media::Particle> media;  ///< listed, then simulated fire, smoke and dust
  double simulateMs = 0.0;             ///< CPU time spent stepping the simulators for this frame
};

/// Evaluates a scene frame by frame. Owns the scene's simulators (the smoke's and the media
/// emitters'), steps them from the start to each frame asked (an earlier frame restarts them), so
/// any frame equals the same frame of a full run.
/// Whether a FrameEvaluator evaluates the scene's fire, smoke and dust (a path that does not draw
/// them skips their simulation).
enum class MediaEvaluation { kEvaluate, kSkip };

class FrameEvaluator {
 public:
  /// `variations`: the atlas's variation count (cel particles pick among the first min(n, 256)), or
  /// 0 when the scene draws no cel particles. `media`: whether the fire, smoke and dust are
  /// evaluated too. `threads`: what the simulators step on
  /// (sim::Settings::threads; 0, the default, the hardware's threads): the frames are bit-identical
  /// for every count. Errors name the scene field or the collider mesh.
  static Result<std::unique_ptr<FrameEvaluator>> create(const Scene& scene, const SceneGeometry& geometry,
                                                        int variations,
                                                        MediaEvaluation media = MediaEvaluation::kEvaluate,
                                                        int threads = 0);
  ~FrameEvaluator();

  /// The reload rule: whether `next` needs a new evaluator. It does when anything that places or
  /// simulates particles differs (particles, emitters, objects, fps, simulation and media settings)
  /// other than the forces; camera, style and every other look are read at each frame.
  bool needsRebuild(const Scene& next) const;
  /// Takes an edited scene that does not need a rebuild. New forces restart the simulators, so the
  /// next frame is simulated from the start under them. Errors (forces out of range) change nothing.
  Result<void> update(const Scene& next);

  /// Frame `frame` (>= 0); `camera` replaces the scene's camera when given.
  FrameInputs evaluate(int frame, const cel::Camera* camera = nullptr);

  const Scene& scene() const;

 private:
  FrameEvaluator() = default;
  Scene scene_;
  int variations_ = 0;
  bool media_ = true;
  std::unique_ptr<sim::Simulator> sim_, mediaSim_;
};

/// Refuses a loop (animation.period > 0) that would not repeat: "PATH: /animation/orbit: ..." names
/// the first thing that changes from one period to the next (a camera that moves, an object on a
/// path or falling, a listed or placed particle that moves, is born or dies, a media light whose
/// intensity changes, or what the simulators refuse: sim::Settings::period).
Result<void> checkLoop(const Scene& scene);
/// checkLoop's refusal as "/pointer: what", without the file; none when the loop repeats.
std::optional<std::string> loopRefusal(const Scene& scene);
/// A material's detailSpeed (video frames a second) in a loop of `periodSeconds`: rounded so the
/// detail videos (`videoFrames`: the least common multiple of their lengths) play a whole number of
/// times a period, so the media's detail repeats with the loop (0 plays: the detail holds still).
float loopDetailSpeed(float speed, double periodSeconds, int videoFrames);

/// What `scene` holds that is valid but likely not what its author meant, one line each starting
/// with the JSON pointer: a `preroll` that no emitter fills (every emitter starts at 0 or later; a
/// loop fills its own), and a loop whose emitters may reach the particle budget
/// (sim::loopPeakParticles), where the births dropped would not repeat.
/// puffrender prints them as warnings, puffview shows them.
std::vector<std::string> sceneWarnings(const Scene& scene);

}  // namespace puff::scene
