// Private to puff::scene: the simulators' settings as the scene gives them, before its objects
// are added as colliders (evaluate.cpp: simulationSettings and mediaSimulationSettings add them).
#pragma once

#include <puff/scene/scene.h>

namespace puff::scene::detail {

/// The smoke simulator's: the scene's "simulation" at the animation's fps and loop. Requires scene.simulation.
sim::Settings smokeSettings(const Scene& scene);
/// The media simulator's: the media emitters, forces and limits at the animation's fps and loop.
/// Requires scene.media.
sim::Settings mediaSettings(const Scene& scene);

}  // namespace puff::scene::detail
