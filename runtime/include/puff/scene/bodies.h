// Rigid bodies (McGuire & Fein §3 combine their smoke with "a Newtonian rigid body
// simulator", ODE): a scene's dynamic objects simulated once, their trajectories kept as paths.
#pragma once

#include <puff/core/error.h>
#include <puff/scene/scene.h>

namespace puff::scene {

/// Simulates the scene's dynamic objects (ObjectSpec::dynamic) with ODE and writes each one's
/// trajectory into its `path`: a key at t = 0 and after every step of 1 / stepsPerSecond s up to the
/// animation's end (frames / fps, at least one step), positions relative to `translate` and
/// rotations (applied before the object's own `rotate`). Nothing happens before t = 0 (a body holds
/// its first key, as every path does).
///
/// What it meets: the other dynamic bodies, and the scene's boxes, spheres, planes and meshes whether
/// still or keyframed (a keyframed object moves as a kinematic body along its path and pushes what it
/// hits; a plane is the top of a slab under its square; a mesh is its triangles, turned and scaled
/// as it is drawn, through ODE's triangle-mesh collider; a mesh file that does not load is an error
/// naming the object).
/// Objects with `collide: false` are left out of the rigid-body world as they are of the smoke's.
///
/// Deterministic: one thread, a fixed step, ODE's random seed reset for every call, the bodies in
/// the scene's order; the same scene gives bit-identical paths on one machine (tested), so a frame
/// rendered alone equals the same frame of a sequence (one simulation runs at a time: ODE's random
/// numbers are one stream for the process). Errors, each naming the JSON pointer: more than 256
/// dynamic objects, more than 2 million keys (steps times dynamic objects), a body that goes past
/// 10^6 units from where it started or 10^7 units or radians a second (diverged, or fell for
/// long enough), ODE that cannot start. A scene without dynamic objects is left untouched.
Result<void> simulateBodies(Scene& scene);

/// After an edit in memory (puffview's panels): simulates the dynamic objects again and gives the
/// emitters and vortices that ride on one of them (`attach`, in `simulation` and `media`) its new
/// trajectory, as reading the edited scene from a file would. On an error the scene is unchanged.
Result<void> updateBodies(Scene& scene);

}  // namespace puff::scene
