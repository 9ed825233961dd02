// FrameEvaluator: the scene's simulators and what each frame draws.
#include <algorithm>
#include <chrono>
#include <tuple>

#include <puff/core/stopwatch.h>
#include <puff/scene/evaluate.h>

#include <puff/core/colour.h>

namespace puff::scene {

namespace {

// What the simulators were built from, forces aside (forces change in place) and the curves over
// life (they shape what is drawn, read from the scene each frame, not the simulation).
std::optional<sim::Settings> simulationKey(const Scene& s) {
  std::optional<sim::Settings> key = s.simulation;
  if (key) {
    key->forces = {};
    for (sim::Emitter& e : key->emitters) e.overLife = {};
  }
  return key;
}

auto mediaKey(const Scene& s) {
  using Key = std::tuple<std::vector<MediaEmitterSpec>, int, float, std::size_t, float>;
  if (!s.media) return std::optional<Key>{};
  const MediaSpec& m = *s.media;
  std::vector<MediaEmitterSpec> emitters = m.emitters;
  for (MediaEmitterSpec& e : emitters) e.emitter.overLife = {};
  return std::optional<Key>(Key{emitters, m.substeps, m.preroll, m.maxParticles, m.collisionRadius});
}

}  // namespace

Result<std::unique_ptr<FrameEvaluator>> FrameEvaluator::create(const Scene& scene, const SceneGeometry& geometry,
                                                               int variations, MediaEvaluation media, int threads) {
  std::unique_ptr<FrameEvaluator> e(new FrameEvaluator());
  e->scene_ = scene;
  e->variations_ = variations;
  e->media_ = media == MediaEvaluation::kEvaluate;
  PUFF_TRY_ASSIGN(auto settings, simulationSettings(scene, geometry));
  if (settings) {
    (settings)->threads = threads;
    // Particles carry an 8-bit variation (cel::Particle): emitters pick among the first 256.
    auto sim = sim::Simulator::create(std::move(*settings), std::clamp(variations, 1, 256));
    if (!sim) return Error::at(scene.file, "/simulation" + sim.error().message);
    e->sim_ = std::move(*sim);
  }
  if (e->media_ && scene.media) {
    PUFF_TRY_ASSIGN(auto mediaSettings, mediaSimulationSettings(scene, geometry));
    if (mediaSettings) {
      (mediaSettings)->threads = threads;
      auto sim = sim::Simulator::create(std::move(*mediaSettings), 1);
      if (!sim) return Error::at(scene.file, "/media" + sim.error().message);
      e->mediaSim_ = std::move(*sim);
    }
  }
  return e;
}

FrameEvaluator::~FrameEvaluator() = default;

const Scene& FrameEvaluator::scene() const { return scene_; }

bool FrameEvaluator::needsRebuild(const Scene& next) const {
  const Scene& a = scene_;
  return a.particles != next.particles || a.emitters != next.emitters || a.objects != next.objects ||
         a.animation.fps != next.animation.fps || a.animation.period != next.animation.period ||
         simulationKey(a) != simulationKey(next) || mediaKey(a) != mediaKey(next);
}

Result<void> FrameEvaluator::update(const Scene& next) {
  if (mediaSim_ && next.media) {
    if (auto ok = mediaSim_->setForces(next.media->forces); !ok)
      return Error::at(next.file, "/media" + ok.error().message);
    mediaSim_->reset();
  }
  if (sim_ && next.simulation) {
    if (auto ok = sim_->setForces(next.simulation->forces); !ok) {
      return Error::at(next.file, "/simulation" + ok.error().message);
    }
    // A frame stays a pure function of the scene: the next frame is simulated from the start under
    // the new forces, so what a viewer shows is what puffrender makes of the saved file.
    sim_->reset();
  }
  scene_ = next;
  return {};
}

float mediaBirthFade(float life) {
  const float x = std::clamp(life / kMediaBirthFade, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

float celBirthGrowth(float life) {
  const float x = std::clamp(life / kCelBirthGrowth, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

FrameInputs FrameEvaluator::evaluate(int frame, const cel::Camera* camera) {
  const Scene& s = scene_;
  FrameInputs in;
  in.frame = frame;
  in.time = frameTime(s, frame);
  in.camera = camera ? *camera : cameraAt(s, frame);
  if (variations_ > 0) {
    in.particles = particlesAt(s, frame, variations_, &in.keys);
    if (sim_) {
      const auto t0 = core::Clock::now();
      sim_->advanceToFrame(frame);
      in.simulateMs += core::millisecondsSince(t0);
      in.particles.reserve(in.particles.size() + sim_->size());
      for (std::size_t i = 0; i < sim_->size(); ++i) {
        const sim::ParticleState p = sim_->particle(i);
        const sim::LifeCurves& curves = s.simulation->emitters[static_cast<std::size_t>(p.emitter)].overLife;
        const sim::LifeCurve& curve = curves.size;
        const float life = p.lifetime > 0.0f ? std::clamp(p.age / p.lifetime, 0.0f, 1.0f) : 0.0f;
        const float size =
            curve.empty() ? p.size * (p.lifetime > 0.0f ? celBirthGrowth(life) : 1.0f) : p.birthSize * curve.at(life);
        if (!(size > 0.0f)) continue;
        // The colour curve is a display value, decoded: cel::Particle::tint is scene-linear.
        in.particles.push_back(
            cel::Particle{p.position, size, p.variation, p.oriented, p.orientation,
                          curves.color.empty() ? glm::vec3(1.0f) : core::srgbToLinear(curves.color.at(life))});
        in.keys.push_back(particleKey(ParticleSource::kSimulated, 0, p.id));
        ++in.simulated;
      }
    }
  }
  if (media_ && s.media) {
    const MediaSpec& spec = *s.media;
    for (const MediaParticleSpec& p : spec.particles) {
      in.media.push_back(media::Particle{p.position, p.radius, static_cast<std::uint32_t>(p.materialIndex), p.life,
                                         p.density, p.seed});
    }
    if (mediaSim_) {
      const auto t0 = core::Clock::now();
      mediaSim_->advanceToFrame(frame);
      in.simulateMs += core::millisecondsSince(t0);
      for (std::size_t i = 0; i < mediaSim_->size(); ++i) {
        const sim::ParticleState p = mediaSim_->particle(i);
        const MediaEmitterSpec& e = spec.emitters[static_cast<std::size_t>(p.emitter)];
        const float life = std::clamp(p.age / p.lifetime, 0.0f, 1.0f);
        // The radius grows by `growth` over the particle's life; the emitter's density multiplies
        // the material's tau, fades in over the first kMediaBirthFade of the life and falls
        // linearly to 0 with age. Curves over life replace either.
        const sim::LifeCurves& curves = e.emitter.overLife;
        const float radius = 0.5f * p.birthSize * (curves.size.empty() ? 1.0f + e.growth * life : curves.size.at(life));
        const float density =
            curves.density.empty() ? p.density * mediaBirthFade(life) : e.emitter.density * curves.density.at(life);
        // The colour curve is a display value (a scene colour), decoded: the media light in linear.
        const glm::vec3 tint = curves.color.empty() ? glm::vec3(1.0f) : core::srgbToLinear(curves.color.at(life));
        const float temperature = curves.temperature.empty() ? 0.0f : curves.temperature.at(life);
        in.media.push_back(media::Particle{p.position, radius, static_cast<std::uint32_t>(e.materialIndex), life,
                                           density, p.id, tint, temperature});
      }
    }
  }
  return in;
}

}  // namespace puff::scene
