// A scene's dynamic objects simulated with ODE (bodies.h).
#include <puff/scene/bodies.h>

#include <algorithm>
#include <cmath>
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

struct World {
  dWorldID world = nullptr;
  dSpaceID space = nullptr;
  dJointGroupID contacts = nullptr;
  std::vector<std::unique_ptr<TriangleSoup>> meshes;
  ~World() {
    if (contacts) dJointGroupDestroy(contacts);
    if (space) dSpaceDestroy(space);  // and its geoms, before the triangle data they use
    for (const auto& m : meshes) dGeomTriMeshDataDestroy(m->data);
    if (world) dWorldDestroy(world);  // and its bodies
  }
};

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

// Contacts between a dynamic body and anything (two still or keyframed objects never touch).
void nearCallback(void* data, dGeomID a, dGeomID b) {
  const auto* ia = static_cast<const GeomInfo*>(dGeomGetData(a));
  const auto* ib = static_cast<const GeomInfo*>(dGeomGetData(b));
  if (!ia->dynamic && !ib->dynamic) return;
  World& w = *static_cast<Collision*>(data)->w;
  constexpr int kMax = 8;
  dContact contact[kMax];
  const int n = dCollide(a, b, kMax, &contact[0].geom, sizeof(dContact));
  // A dynamic body's own surface decides; two bodies take the mean friction and the larger bounce.
  float mu = 0.0f, bounce = 0.0f;
  if (ia->dynamic && ib->dynamic) {
    mu = 0.5f * (ia->friction + ib->friction);
    bounce = std::max(ia->restitution, ib->restitution);
  } else {
    const GeomInfo& d = ia->dynamic ? *ia : *ib;
    mu = d.friction;
    bounce = d.restitution;
  }
  for (int i = 0; i < n; ++i) {
    dSurfaceParameters& s = contact[i].surface;
    s.mode = dContactBounce | dContactApprox1 | dContactSoftCFM;
    s.mu = mu;
    s.bounce = bounce;
    s.bounce_vel = 0.05;  // slower impacts do not bounce: bodies come to rest
    s.soft_cfm = 1e-6;
    dJointID j = dJointCreateContact(w.world, w.contacts, &contact[i]);
    dJointAttach(j, dGeomGetBody(a), dGeomGetBody(b));
  }
}

}  // namespace

Result<void> simulateBodies(Scene& scene) {
  std::vector<std::size_t> dynamic;
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    if (scene.objects[i].dynamic) dynamic.push_back(i);
  if (dynamic.empty()) return {};

  const double rate = scene.rigidBodies.stepsPerSecond;
  const double dt = 1.0 / rate;
  const double duration = static_cast<double>(scene.animation.frames) / static_cast<double>(scene.animation.fps);
  // Every key of every body is kept: bounded (counted in doubles, before anything is an integer:
  // a tiny fps makes the duration astronomical), so that a long animation fails clearly instead of
  // taking minutes and gigabytes. So are the bodies, whose contacts every step tests pairwise.
  constexpr double kMaxKeys = 2'000'000;
  constexpr std::size_t kMaxBodies = 256;
  const double stepCount = std::max(1.0, std::ceil(duration * rate - 1e-9));
  if (!(stepCount * static_cast<double>(dynamic.size()) <= kMaxKeys)) {
    return Error{"/rigidBodies: " + std::to_string(dynamic.size()) + " dynamic objects over " +
                 std::to_string(duration) + " s at " + std::to_string(scene.rigidBodies.stepsPerSecond) +
                 " steps per second are more than " + std::to_string(static_cast<long long>(kMaxKeys)) +
                 " keys (steps times objects): fewer frames, or fewer steps per second"};
  }
  if (dynamic.size() > kMaxBodies) {
    return Error{"/objects/" + std::to_string(dynamic[kMaxBodies]) + "/dynamic: at most " + std::to_string(kMaxBodies) +
                 " dynamic objects in a scene, this one has " + std::to_string(dynamic.size())};
  }
  const auto steps = static_cast<long long>(stepCount);
  // ODE's random numbers (QuickStep's constraint order) are one stream for the whole process: one
  // simulation at a time keeps each one's the same, whichever threads parse scenes.
  static std::mutex oneAtATime;
  const std::lock_guard<std::mutex> lock(oneAtATime);

  static std::once_flag initialized;
  std::call_once(initialized, [] { dInitODE2(0); });
  if (!dAllocateODEDataForThread(dAllocateMaskAll)) return Error{"rigid bodies: ODE could not start on this thread"};
  dRandSetSeed(1);  // QuickStep reorders its constraints with ODE's random numbers: the same each run

  World w;
  w.world = dWorldCreate();
  w.space = dSimpleSpaceCreate(nullptr);  // every pair, in an order that depends on the scene alone
  w.contacts = dJointGroupCreate(0);
  const glm::vec3 g = scene.rigidBodies.gravity;
  dWorldSetGravity(w.world, g.x, g.y, g.z);
  dWorldSetERP(w.world, 0.2);
  dWorldSetCFM(w.world, 1e-6);
  dWorldSetQuickStepNumIterations(w.world, 40);
  dWorldSetContactSurfaceLayer(w.world, 1e-3);
  dWorldSetAutoDisableFlag(w.world, 0);

  std::vector<std::unique_ptr<GeomInfo>> infos;
  struct Kinematic {
    dBodyID body;
    const ObjectSpec* object;
  };
  std::vector<Kinematic> kinematic;
  std::vector<dBodyID> bodies(scene.objects.size(), nullptr);
  std::map<std::filesystem::path, std::unique_ptr<mesh::TriMesh>> meshFiles;  // each file read once
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const ObjectSpec& o = scene.objects[i];
    const bool isDynamic = o.dynamic.has_value();
    if (!o.collide && !isDynamic) continue;
    const bool touches = o.collide;  // a dynamic body with collide false flies through everything
    const glm::quat q0 = eulerRotation(o.rotateDegrees);
    dGeomID geom = nullptr;
    glm::vec3 geomOffset(0.0f);  // a plane's slab lies under its square
    switch (touches ? o.type : ObjectSpec::Type::kMesh) {
      case ObjectSpec::Type::kBox:
        geom = dCreateBox(w.space, 2.0 * o.scale.x, 2.0 * o.scale.y, 2.0 * o.scale.z);
        break;
      case ObjectSpec::Type::kSphere:
        geom = dCreateSphere(w.space, std::max({o.scale.x, o.scale.y, o.scale.z}));
        break;
      case ObjectSpec::Type::kPlane: {
        const float h = std::max({o.scale.x, o.scale.z, 0.5f});
        geom = dCreateBox(w.space, 2.0 * o.scale.x, 2.0 * h, 2.0 * o.scale.z);
        geomOffset = q0 * glm::vec3(0.0f, -h, 0.0f);
        break;
      }
      case ObjectSpec::Type::kMesh: {
        if (!touches) break;
        // The mesh's triangles, scaled, in its own frame (its turn and place are the geom's).
        auto& loaded = meshFiles[o.mesh];
        if (!loaded) {
          auto m = mesh::loadMesh(o.mesh);
          if (!m)
            return Error{"/objects/" + std::to_string(i) + "/mesh (a collider of rigid bodies): " + m.error().message};
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
        geom = dCreateTriMesh(w.space, soup->data, nullptr, nullptr, nullptr);
        w.meshes.push_back(std::move(soup));
        break;
      }
    }
    if (geom) {
      auto info = std::make_unique<GeomInfo>();
      info->dynamic = isDynamic;
      if (isDynamic) info->friction = o.dynamic->friction, info->restitution = o.dynamic->restitution;
      dGeomSetData(geom, info.get());
      infos.push_back(std::move(info));
    }
    dQuaternion q;
    toOde(q0, q);
    if (isDynamic || !o.path.empty()) {
      dBodyID body = dBodyCreate(w.world);
      const glm::vec3 start = o.translate + o.path.at(0.0);  // an empty path is at 0
      dBodySetPosition(body, start.x, start.y, start.z);
      dBodySetQuaternion(body, q);
      if (isDynamic) {
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
        bodies[i] = body;
      } else {
        dBodySetKinematic(body);
        kinematic.push_back({body, &o});
      }
      if (geom) {
        dGeomSetBody(geom, body);
        // A keyframed plane's slab lies under its square, in the body's (the plane's) frame.
        if (o.type == ObjectSpec::Type::kPlane) dGeomSetOffsetPosition(geom, 0.0, -glm::length(geomOffset), 0.0);
      }
    } else {
      const glm::vec3 c = o.translate + geomOffset;
      dGeomSetPosition(geom, c.x, c.y, c.z);
      dGeomSetQuaternion(geom, q);
    }
  }

  // The trajectories: a key at t = 0 and after each step.
  std::vector<sim::Path> paths(scene.objects.size());
  const auto record = [&](float t) {
    for (std::size_t i : dynamic) {
      const ObjectSpec& o = scene.objects[i];
      const dReal* p = dBodyGetPosition(bodies[i]);
      const glm::vec3 at(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
      // objectTransform draws T(translate + path) R_path R_euler S: R_path = body R_euler^-1.
      const glm::quat turn =
          glm::normalize(fromOde(dBodyGetQuaternion(bodies[i])) * glm::inverse(eulerRotation(o.rotateDegrees)));
      paths[i].times.push_back(t);
      paths[i].points.push_back(at - o.translate);
      paths[i].rotations.push_back(turn);
    }
  };
  for (std::size_t i : dynamic) {
    paths[i].times.reserve(static_cast<std::size_t>(steps) + 1);
    paths[i].points.reserve(static_cast<std::size_t>(steps) + 1);
    paths[i].rotations.reserve(static_cast<std::size_t>(steps) + 1);
  }
  record(0.0f);
  Collision collision{&w};
  for (long long k = 0; k < steps; ++k) {
    const double t0 = static_cast<double>(k) * dt, t1 = static_cast<double>(k + 1) * dt;
    // Keyframed objects: where their path has them now, moving to where it has them at the step's end.
    for (const Kinematic& kb : kinematic) {
      const glm::vec3 p0 = kb.object->translate + kb.object->path.at(t0);
      const glm::vec3 v = (kb.object->path.at(t1) - kb.object->path.at(t0)) / static_cast<float>(dt);
      dBodySetPosition(kb.body, p0.x, p0.y, p0.z);
      dBodySetLinearVel(kb.body, v.x, v.y, v.z);
    }
    dSpaceCollide(w.space, &collision, &nearCallback);
    dWorldQuickStep(w.world, dt);
    dJointGroupEmpty(w.contacts);
    // A body that has left every number the solver can hold stops the simulation (before ODE's
    // collision tests meet it) with an error naming it.
    for (std::size_t i : dynamic) {
      const dReal* p = dBodyGetPosition(bodies[i]);
      const dReal* v = dBodyGetLinearVel(bodies[i]);
      const dReal* a = dBodyGetAngularVel(bodies[i]);
      bool fine = true;
      // Positions as far as a path may reach (sim::validate's 10^6 units from where it starts).
      const glm::vec3 from = scene.objects[i].translate;
      for (int c = 0; c < 3; ++c) {
        fine = fine && std::abs(p[c] - from[c]) < 1e6 && std::abs(v[c]) < 1e7 && std::abs(a[c]) < 1e7;
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
    record(static_cast<float>(t1));
  }
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
