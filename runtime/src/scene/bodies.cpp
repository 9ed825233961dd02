// A scene's dynamic objects simulated with ODE (bodies.h).
#include <puff/scene/bodies.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <ode/ode.h>
#include <glm/gtc/quaternion.hpp>

#include <puff/mesh/mesh.h>

namespace puff::scene {

namespace {

// ODE's world, solver and contact parameters (ODE's manual, "World" and "Contact"). Lengths are
// world units, times seconds.

// ERP, the error reduction parameter: the fraction of a joint's error (a contact's penetration)
// corrected in one step, in [0, 1] (no unit).
constexpr dReal kErrorReduction = 0.2;
// CFM, constraint force mixing: how soft every constraint is (0 is rigid), in ODE's units of
// velocity per force; a little softness keeps the solver stable where contacts pile up.
constexpr dReal kConstraintForceMixing = 1e-6;
// QuickStep's iterations a step (a count): more solve the contacts more exactly, and take longer.
constexpr int kSolverIterations = 40;
// World units two surfaces may sink into each other before a contact pushes back, so that resting
// bodies do not jitter.
constexpr dReal kContactSurfaceLayer = 1e-3;
// The most contact points dCollide gives for one pair of geoms (a count).
constexpr int kMaxContactsPerPair = 8;
// World units a second: slower impacts do not bounce, so bodies come to rest.
constexpr dReal kBounceVelocity = 0.05;
// A contact's own CFM (soft_cfm): how soft a contact is, in the units of kConstraintForceMixing.
constexpr dReal kContactSoftness = 1e-6;
// The seed of ODE's random numbers, reset for every simulation.
constexpr unsigned long kRandomSeed = 1;

// The limits of a simulation. Every key of every body is kept: bounded (counted in doubles, before
// anything is an integer: a tiny fps makes the duration astronomical), so that a long animation
// fails clearly instead of taking minutes and gigabytes. So are the bodies, whose contacts every
// step tests pairwise.
constexpr double kMaxKeys = 2'000'000;  // steps times dynamic objects
constexpr std::size_t kMaxBodies = 256;
// A body past these has diverged (or fallen for long enough) and stops the simulation.
constexpr double kMaxTravel = 1e6;  // world units from where it starts (sim::validate's reach of a path)
constexpr double kMaxSpeed = 1e7;   // world units a second, and radians a second

// ODE's state, which is the process's, not a simulation's: ODE is initialised once per process
// (dInitODE2), and its random numbers (QuickStep's constraint order) are one stream for the whole
// process, which no lock of ODE's guards. Each simulation holds `oneAtATime` from the reseed until
// its world is destroyed, so simulations on several threads run one after another and each one's
// draws are the same whichever threads parse scenes. Constant-initialised: no static
// initialisation order can reach it unmade.
struct OdeProcess {
  std::once_flag initialized;  // dInitODE2 has run
  std::mutex oneAtATime;       // held by the one simulation that uses ODE now
};
constinit OdeProcess odeProcess;

// What a geom stands for, for the contacts' surface.
struct GeomInfo {
  bool dynamic = false;
  float friction = 0.0f, restitution = 0.0f;
};

// A mesh object's triangles as ODE holds them (the arrays must outlive its geom).
struct TriangleSoup {
  std::vector<dReal> vertices;  // x, y, z: the object's scaled vertices, in its own frame
  std::vector<dTriIndex> indices;
  dTriMeshDataID data = nullptr;
};

// The ODE world, its collision space and its contacts, set up for the scene's gravity.
struct World {
  dWorldID world = nullptr;
  dSpaceID space = nullptr;
  dJointGroupID contacts = nullptr;
  std::vector<std::unique_ptr<TriangleSoup>> meshes;
  explicit World(const glm::vec3& gravity) {
    world = dWorldCreate();
    space = dSimpleSpaceCreate(nullptr);  // every pair, in an order that depends on the scene alone
    contacts = dJointGroupCreate(0);
    dWorldSetGravity(world, gravity.x, gravity.y, gravity.z);
    dWorldSetERP(world, kErrorReduction);
    dWorldSetCFM(world, kConstraintForceMixing);
    dWorldSetQuickStepNumIterations(world, kSolverIterations);
    dWorldSetContactSurfaceLayer(world, kContactSurfaceLayer);
    dWorldSetAutoDisableFlag(world, 0);  // no body is put to sleep
  }
  World(const World&) = delete;
  World& operator=(const World&) = delete;
  ~World() {
    if (contacts) dJointGroupDestroy(contacts);
    if (space) dSpaceDestroy(space);  // and its geoms, before the triangle data they use
    for (const auto& m : meshes) dGeomTriMeshDataDestroy(m->data);
    if (world) dWorldDestroy(world);  // and its bodies
  }
};

// A keyframed object: a kinematic body moved along its path.
struct Kinematic {
  dBodyID body;
  const ObjectSpec* object;
};

// The scene's objects in the world: the dynamic bodies by object index (null for the others), the
// keyframed ones, and the geoms' surfaces (which their geoms point to).
struct Bodies {
  std::vector<dBodyID> dynamic;
  std::vector<Kinematic> kinematic;
  std::vector<std::unique_ptr<GeomInfo>> infos;
};

// Each mesh file a collider names, read once.
using MeshFiles = std::map<std::filesystem::path, std::unique_ptr<mesh::TriMesh>>;

// What dSpaceCollide passes nearCallback: the world whose contact group the contacts join.
struct Collision {
  World* w = nullptr;
};

// ODE's quaternions are (w, x, y, z).
glm::quat fromOde(const dReal* q) {
  return glm::normalize(glm::quat(static_cast<float>(q[0]), static_cast<float>(q[1]), static_cast<float>(q[2]),
                                  static_cast<float>(q[3])));
}
void toOde(const glm::quat& q, dQuaternion out) { out[0] = q.w, out[1] = q.x, out[2] = q.y, out[3] = q.z; }

glm::quat eulerRotation(const glm::vec3& degrees) {
  return glm::angleAxis(glm::radians(degrees.z), glm::vec3(0, 0, 1)) *
         glm::angleAxis(glm::radians(degrees.y), glm::vec3(0, 1, 0)) *
         glm::angleAxis(glm::radians(degrees.x), glm::vec3(1, 0, 0));
}

// The surface where two geoms touch, at least one of them dynamic: a dynamic body's own surface
// decides; two bodies take the mean friction and the larger bounce.
void contactSurface(const GeomInfo& a, const GeomInfo& b, float& mu, float& bounce) {
  if (a.dynamic && b.dynamic) {
    mu = 0.5f * (a.friction + b.friction);
    bounce = std::max(a.restitution, b.restitution);
  } else {
    const GeomInfo& d = a.dynamic ? a : b;
    mu = d.friction;
    bounce = d.restitution;
  }
}

// Contacts between a dynamic body and anything (two still or keyframed objects never touch).
void nearCallback(void* data, dGeomID a, dGeomID b) {
  const auto* ia = static_cast<const GeomInfo*>(dGeomGetData(a));
  const auto* ib = static_cast<const GeomInfo*>(dGeomGetData(b));
  if (!ia->dynamic && !ib->dynamic) return;
  World& w = *static_cast<Collision*>(data)->w;
  dContact contact[kMaxContactsPerPair];
  const int n = dCollide(a, b, kMaxContactsPerPair, &contact[0].geom, sizeof(dContact));
  float mu = 0.0f, bounce = 0.0f;
  contactSurface(*ia, *ib, mu, bounce);
  for (int i = 0; i < n; ++i) {
    dSurfaceParameters& s = contact[i].surface;
    // Bouncing, friction proportional to the contact's normal force, and a soft contact.
    s.mode = dContactBounce | dContactApprox1 | dContactSoftCFM;
    s.mu = mu;
    s.bounce = bounce;
    s.bounce_vel = kBounceVelocity;
    s.soft_cfm = kContactSoftness;
    dJointID j = dJointCreateContact(w.world, w.contacts, &contact[i]);
    dJointAttach(j, dGeomGetBody(a), dGeomGetBody(b));
  }
}

// The scene's dynamic objects, by index.
std::vector<std::size_t> dynamicObjects(const Scene& scene) {
  std::vector<std::size_t> dynamic;
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    if (scene.objects[i].dynamic) dynamic.push_back(i);
  return dynamic;
}

// The steps to the animation's end (at least one), or an error when the keys or the bodies are
// more than the limits allow.
Result<long long> stepCount(const Scene& scene, const std::vector<std::size_t>& dynamic) {
  const double rate = scene.rigidBodies.stepsPerSecond;
  const double duration = static_cast<double>(scene.animation.frames) / static_cast<double>(scene.animation.fps);
  const double steps = std::max(1.0, std::ceil(duration * rate - 1e-9));
  if (!(steps * static_cast<double>(dynamic.size()) <= kMaxKeys)) {
    return Error{"/rigidBodies: " + std::to_string(dynamic.size()) + " dynamic objects over " +
                 std::to_string(duration) + " s at " + std::to_string(scene.rigidBodies.stepsPerSecond) +
                 " steps per second are more than " + std::to_string(static_cast<long long>(kMaxKeys)) +
                 " keys (steps times objects): fewer frames, or fewer steps per second"};
  }
  if (dynamic.size() > kMaxBodies) {
    return Error{"/objects/" + std::to_string(dynamic[kMaxBodies]) + "/dynamic: at most " + std::to_string(kMaxBodies) +
                 " dynamic objects in a scene, this one has " + std::to_string(dynamic.size())};
  }
  return static_cast<long long>(steps);
}

// Readies ODE for a simulation on this thread, its random numbers reset: QuickStep reorders its
// constraints with them, the same each run. The caller holds odeProcess.oneAtATime.
Result<void> startOde() {
  std::call_once(odeProcess.initialized, [] { dInitODE2(0); });
  if (!dAllocateODEDataForThread(dAllocateMaskAll)) return Error{"rigid bodies: ODE could not start on this thread"};
  dRandSetSeed(kRandomSeed);
  return {};
}

// A mesh collider's geom: the mesh's triangles, scaled, in its own frame (its turn and place are
// the geom's). The triangles stay in `w` as long as the geom.
Result<dGeomID> createTriMesh(World& w, MeshFiles& meshFiles, const ObjectSpec& o, std::size_t i) {
  auto& loaded = meshFiles[o.mesh];
  if (!loaded) {
    auto m = mesh::loadMesh(o.mesh);
    if (!m) return Error{"/objects/" + std::to_string(i) + "/mesh (a collider of rigid bodies): " + m.error().message};
    loaded = std::make_unique<mesh::TriMesh>(std::move(*m));
  }
  auto soup = std::make_unique<TriangleSoup>();
  soup->vertices.reserve(loaded->positions.size() * 3);
  for (const glm::vec3& v : loaded->positions) {
    const glm::vec3 s = v * o.scale;
    soup->vertices.insert(soup->vertices.end(), {s.x, s.y, s.z});
  }
  soup->indices.reserve(loaded->triangles.size() * 3);
  for (const glm::uvec3& t : loaded->triangles) soup->indices.insert(soup->indices.end(), {t.x, t.y, t.z});
  soup->data = dGeomTriMeshDataCreate();
  dGeomTriMeshDataBuildDouble(soup->data, soup->vertices.data(), 3 * sizeof(dReal),
                              static_cast<int>(loaded->positions.size()), soup->indices.data(),
                              static_cast<int>(soup->indices.size()), 3 * sizeof(dTriIndex));
  const dGeomID geom = dCreateTriMesh(w.space, soup->data, nullptr, nullptr, nullptr);
  w.meshes.push_back(std::move(soup));
  return geom;
}

// An object's collision shape, or null for one that touches nothing (a dynamic body with collide
// false flies through everything). A plane's shape is a slab under its square: `offset` is the
// slab's centre from the object's place, turned by `q0`.
Result<dGeomID> createGeom(World& w, MeshFiles& meshFiles, const ObjectSpec& o, std::size_t i, const glm::quat& q0,
                           glm::vec3& offset) {
  if (!o.collide) return dGeomID{nullptr};
  dGeomID geom = nullptr;
  switch (o.type) {
    case ObjectSpec::Type::kBox:
      geom = dCreateBox(w.space, 2.0 * o.scale.x, 2.0 * o.scale.y, 2.0 * o.scale.z);
      break;
    case ObjectSpec::Type::kSphere:
      geom = dCreateSphere(w.space, std::max({o.scale.x, o.scale.y, o.scale.z}));
      break;
    case ObjectSpec::Type::kPlane: {
      const float h = std::max({o.scale.x, o.scale.z, 0.5f});
      geom = dCreateBox(w.space, 2.0 * o.scale.x, 2.0 * h, 2.0 * o.scale.z);
      offset = q0 * glm::vec3(0.0f, -h, 0.0f);
      break;
    }
    case ObjectSpec::Type::kMesh: {
      PUFF_TRY_ASSIGN(geom, createTriMesh(w, meshFiles, o, i));
      break;
    }
  }
  return geom;
}

// A dynamic object's mass, spread through its box or sphere, and its starting velocities.
void setDynamics(dBodyID body, const ObjectSpec& o) {
  dMass m;
  if (o.type == ObjectSpec::Type::kBox) {
    dMassSetBoxTotal(&m, o.dynamic->mass, 2.0 * o.scale.x, 2.0 * o.scale.y, 2.0 * o.scale.z);
  } else {
    dMassSetSphereTotal(&m, o.dynamic->mass, std::max({o.scale.x, o.scale.y, o.scale.z}));
  }
  dBodySetMass(body, &m);
  const glm::vec3 v = o.dynamic->velocity, wv = o.dynamic->angularVelocity;
  dBodySetLinearVel(body, v.x, v.y, v.z);
  dBodySetAngularVel(body, wv.x, wv.y, wv.z);
}

// Puts object `i` where it starts, turned by `q0`: a dynamic or keyframed object as a body that
// carries its geom (if any), a still one as its geom alone.
void placeObject(World& w, Bodies& b, const ObjectSpec& o, std::size_t i, dGeomID geom, const glm::quat& q0,
                 const glm::vec3& geomOffset) {
  dQuaternion q;
  toOde(q0, q);
  if (!o.dynamic && o.path.empty()) {
    const glm::vec3 c = o.translate + geomOffset;
    dGeomSetPosition(geom, c.x, c.y, c.z);
    dGeomSetQuaternion(geom, q);
    return;
  }
  dBodyID body = dBodyCreate(w.world);
  const glm::vec3 start = o.translate + o.path.at(0.0);  // an empty path is at 0
  dBodySetPosition(body, start.x, start.y, start.z);
  dBodySetQuaternion(body, q);
  if (o.dynamic) {
    setDynamics(body, o);
    b.dynamic[i] = body;
  } else {
    dBodySetKinematic(body);
    b.kinematic.push_back({body, &o});
  }
  if (geom) {
    dGeomSetBody(geom, body);
    // A keyframed plane's slab lies under its square, in the body's (the plane's) frame.
    if (o.type == ObjectSpec::Type::kPlane) dGeomSetOffsetPosition(geom, 0.0, -glm::length(geomOffset), 0.0);
  }
}

// Adds object `i` to the world, if it collides or is dynamic: its geom with its surface, then its
// body or its place.
Result<void> addObject(World& w, Bodies& b, MeshFiles& meshFiles, const ObjectSpec& o, std::size_t i) {
  const bool isDynamic = o.dynamic.has_value();
  if (!o.collide && !isDynamic) return {};
  const glm::quat q0 = eulerRotation(o.rotateDegrees);
  glm::vec3 geomOffset(0.0f);  // a plane's slab lies under its square
  PUFF_TRY_ASSIGN(const dGeomID geom, createGeom(w, meshFiles, o, i, q0, geomOffset));
  if (geom) {
    auto info = std::make_unique<GeomInfo>();
    info->dynamic = isDynamic;
    if (isDynamic) info->friction = o.dynamic->friction, info->restitution = o.dynamic->restitution;
    dGeomSetData(geom, info.get());
    b.infos.push_back(std::move(info));
  }
  placeObject(w, b, o, i, geom, q0, geomOffset);
  return {};
}

// Every object of the scene that collides or is dynamic, in the scene's order.
Result<void> addObjects(World& w, Bodies& b, const Scene& scene) {
  b.dynamic.assign(scene.objects.size(), nullptr);
  MeshFiles meshFiles;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) PUFF_TRY(addObject(w, b, meshFiles, scene.objects[i], i));
  return {};
}

// The dynamic objects' trajectories, with room for a key at t = 0 and after each step.
std::vector<sim::Path> emptyPaths(const Scene& scene, const std::vector<std::size_t>& dynamic, long long steps) {
  std::vector<sim::Path> paths(scene.objects.size());
  for (std::size_t i : dynamic) {
    paths[i].times.reserve(static_cast<std::size_t>(steps) + 1);
    paths[i].points.reserve(static_cast<std::size_t>(steps) + 1);
    paths[i].rotations.reserve(static_cast<std::size_t>(steps) + 1);
  }
  return paths;
}

// Appends each dynamic body's key at time t to its trajectory.
void recordKeys(const Scene& scene, const std::vector<std::size_t>& dynamic, const Bodies& b, float t,
                std::vector<sim::Path>& paths) {
  for (std::size_t i : dynamic) {
    const ObjectSpec& o = scene.objects[i];
    const dReal* p = dBodyGetPosition(b.dynamic[i]);
    const glm::vec3 at(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
    // objectTransform draws T(translate + path) R_path R_euler S: R_path = body R_euler^-1.
    const glm::quat turn =
        glm::normalize(fromOde(dBodyGetQuaternion(b.dynamic[i])) * glm::inverse(eulerRotation(o.rotateDegrees)));
    paths[i].times.push_back(t);
    paths[i].points.push_back(at - o.translate);
    paths[i].rotations.push_back(turn);
  }
}

// Keyframed objects: where their path has them at t0, moving to where it has them at t1 = t0 + dt.
void moveKinematic(const std::vector<Kinematic>& kinematic, double t0, double t1, double dt) {
  for (const Kinematic& kb : kinematic) {
    const glm::vec3 p0 = kb.object->translate + kb.object->path.at(t0);
    const glm::vec3 v = (kb.object->path.at(t1) - kb.object->path.at(t0)) / static_cast<float>(dt);
    dBodySetPosition(kb.body, p0.x, p0.y, p0.z);
    dBodySetLinearVel(kb.body, v.x, v.y, v.z);
  }
}

// A body that has left every number the solver can hold stops the simulation (before ODE's
// collision tests meet it) with an error naming it; t1 is the time the step ended.
Result<void> checkBounded(const Scene& scene, const std::vector<std::size_t>& dynamic, const Bodies& b, double t1) {
  for (std::size_t i : dynamic) {
    const dReal* p = dBodyGetPosition(b.dynamic[i]);
    const dReal* v = dBodyGetLinearVel(b.dynamic[i]);
    const dReal* a = dBodyGetAngularVel(b.dynamic[i]);
    bool fine = true;
    // Positions as far as a path may reach (sim::validate's 10^6 units from where it starts).
    const glm::vec3 from = scene.objects[i].translate;
    for (int c = 0; c < 3; ++c) {
      fine = fine && std::abs(p[c] - from[c]) < kMaxTravel && std::abs(v[c]) < kMaxSpeed && std::abs(a[c]) < kMaxSpeed;
    }
    if (!fine) {
      return Error{"/objects/" + std::to_string(i) + "/dynamic: " + scene.objects[i].name +
                   " went past 10^6 units from where it started, or 10^7 units or radians a second, at t = " +
                   std::to_string(t1) +
                   " s (the rigid-body simulation diverged, or the animation is long enough to fall that far): a "
                   "smaller step (rigidBodies.stepsPerSecond), a larger "
                   "mass, smaller speeds or fewer frames may help"};
    }
  }
  return {};
}

// The simulation's steps of dt seconds: keyframed objects moved, contacts found, the world
// stepped, each dynamic body checked and its key recorded.
Result<void> runSteps(World& w, const Bodies& b, const Scene& scene, const std::vector<std::size_t>& dynamic,
                      long long steps, double dt, std::vector<sim::Path>& paths) {
  Collision collision{&w};
  for (long long k = 0; k < steps; ++k) {
    const double t0 = static_cast<double>(k) * dt, t1 = static_cast<double>(k + 1) * dt;
    moveKinematic(b.kinematic, t0, t1, dt);
    dSpaceCollide(w.space, &collision, &nearCallback);
    dWorldQuickStep(w.world, dt);
    dJointGroupEmpty(w.contacts);
    PUFF_TRY(checkBounded(scene, dynamic, b, t1));
    recordKeys(scene, dynamic, b, static_cast<float>(t1), paths);
  }
  return {};
}

}  // namespace

Result<void> simulateBodies(Scene& scene) {
  const std::vector<std::size_t> dynamic = dynamicObjects(scene);
  if (dynamic.empty()) return {};
  PUFF_TRY_ASSIGN(const long long steps, stepCount(scene, dynamic));
  const double rate = scene.rigidBodies.stepsPerSecond;
  const double dt = 1.0 / rate;

  const std::lock_guard<std::mutex> lock(odeProcess.oneAtATime);  // ODE is one simulation at a time
  PUFF_TRY(startOde());
  World w(scene.rigidBodies.gravity);
  Bodies b;
  PUFF_TRY(addObjects(w, b, scene));

  std::vector<sim::Path> paths = emptyPaths(scene, dynamic, steps);
  recordKeys(scene, dynamic, b, 0.0f, paths);
  PUFF_TRY(runSteps(w, b, scene, dynamic, steps, dt, paths));
  for (std::size_t i : dynamic) scene.objects[i].path = std::move(paths[i]);
  return {};
}

Result<void> updateBodies(Scene& scene) {
  Scene next = scene;
  PUFF_TRY(simulateBodies(next));
  // What rides on a dynamic object follows its path as the reader attaches it (read.cpp): the
  // object's keys, offset by where the object stands.
  const auto follow = [&](const std::string& name, sim::Path& path) {
    if (name.empty()) return;
    for (const ObjectSpec& o : next.objects) {
      if (o.name != name || !o.dynamic) continue;
      path = o.path;
      for (glm::vec3& p : path.points) p += o.translate;
    }
  };
  const auto forAll = [&](sim::Forces& forces, auto& emitters, auto emitterOf) {
    for (sim::Vortex& v : forces.vortices) follow(v.attach, v.path);
    for (auto& e : emitters) {
      sim::Emitter& em = emitterOf(e);
      follow(em.attach, em.path);
    }
  };
  if (next.simulation) {
    forAll(next.simulation->forces, next.simulation->emitters, [](sim::Emitter& e) -> sim::Emitter& { return e; });
  }
  if (next.media) {
    forAll(next.media->forces, next.media->emitters, [](MediaEmitterSpec& e) -> sim::Emitter& { return e.emitter; });
  }
  scene = std::move(next);
  return {};
}

}  // namespace puff::scene
