// Bullet rigid-torus backend: the reference model. Every ring is one rigid body (analytic torus
// mass and inertia) whose collision shape is a compound of capsules on the chords of a regular
// polygon; pins are static bodies, colliders static shapes. Bullet runs in scaled internal units
// (length_scale per metre) because it is tuned for objects of about a unit; everything in and out
// is SI. step(dt) runs a fixed number of equal internal steps, so runs are deterministic.
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "backends/backend.hpp"
#include "backends/capsule_torus.hpp"

namespace chainmail {

namespace {

// backend settings, SI units (scaled to Bullet's internal units in reset). Defaults: two 0.5 ms
// internal steps of 20 sweeps keep a 60-ring catenary and a hanging 4-in-1 curtain linked with
// tori overlapping no more than the capsule approximation allows; 28 pieces keep the compound's
// surface within 2 % of the wire radius for AR 5 rings; millimetres make rings a few units wide.
struct BulletSettings {
  int substeps = 2;                           // equal internal Bullet steps per step()
  int solver_iterations = 20;                 // sequential-impulse sweeps per internal step
  double restitution = 0.0;                   // ring-ring and ring-collider bounce
  double linear_damping = 0.05;               // fraction of linear velocity removed per second
  double angular_damping = 0.05;              // fraction of angular velocity removed per second
  int pieces = 28;                            // capsules per ring
  double length_scale = 1000.0;               // internal units per metre
  bool split_impulse = true;                  // resolve penetration apart from velocity
  double contact_processing_threshold = 1.0;  // m; points separated by more are kept, not solved
  // friction rows per contact, each clamped to mu times the normal impulse on its own: 2 is a
  // pyramid; 1 (along the sliding velocity) bounds a slide as Coulomb's cone does but holds a
  // contact at rest along that one direction only
  int friction_directions = 2;
};

// every knob once, bound to its BulletSettings field (the field's default is the knob's)
const KnobTable<BulletSettings>& bullet_knobs() {
  using S = BulletSettings;
  static const KnobTable<S> table = [] {
    KnobTable<S> t;
    t.time_step(1e-3, 1e-5, 0.1, "time step of the harness, s")
        .unit("s")
        .doc("time step of the harness");
    t.integer("substeps", &S::substeps, 1, 64, "equal internal Bullet steps per time step");
    t.integer("solver_iterations", &S::solver_iterations, 1, 1000,
              "sequential-impulse sweeps per internal step");
    t.number("restitution", &S::restitution, 0.0, 1.0, "coefficient of restitution");
    t.number("linear_damping", &S::linear_damping, 0.0, 1.0,
             "fraction of linear velocity removed per second");
    t.number("angular_damping", &S::angular_damping, 0.0, 1.0,
             "fraction of angular velocity removed per second");
    t.integer("pieces", &S::pieces, 6, 256,
              "capsules per ring torus (28: surface within 2% of the wire radius for AR 5)")
        .doc("capsules per ring torus (28: surface within 2 % of the wire radius for AR 5)");
    t.number("length_scale", &S::length_scale, 1e-3, 1e6, "Bullet internal units per metre");
    t.boolean("split_impulse", &S::split_impulse, "resolve penetration without adding velocity");
    t.number("contact_processing_threshold", &S::contact_processing_threshold, 0.0, 1e3,
             "contact points separated by more than this are kept but not solved, m")
        .unit("m")
        .doc("contact points separated by more than this are kept but not solved");
    t.integer("friction_directions", &S::friction_directions, 1, 2,
              "friction directions per contact, each up to mu times the normal impulse (2: a "
              "pyramid; 1: along the sliding velocity only)")
        .doc(
            "friction directions per contact, each up to μ times the normal impulse on its own "
            "(2: a pyramid; 1: along the sliding velocity only, see [the rigid "
            "backends](#the-rigid-backends))");
    return t;
  }();
  return table;
}

// user index of a collision object: ring index, or this for static colliders
constexpr int kColliderIndex = -1;

// Bullet multiplies the two materials' coefficients; the scene gives one coefficient per contact
// kind instead: a collider's own friction against rings, the ring friction between rings
btScalar combined_friction(const btCollisionObject* body0, const btCollisionObject* body1) {
  if (body0->getUserIndex() == kColliderIndex) return body0->getFriction();
  if (body1->getUserIndex() == kColliderIndex) return body1->getFriction();
  return std::sqrt(body0->getFriction() * body1->getFriction());
}
// every body carries the same restitution knob
btScalar combined_restitution(const btCollisionObject* body0, const btCollisionObject* body1) {
  return std::max(body0->getRestitution(), body1->getRestitution());
}

// broad-phase filter: without self-contact only linked neighbours (and colliders) touch
class RingPairFilter final : public btOverlapFilterCallback {
 public:
  const std::vector<std::array<int, 4>>* neighbours = nullptr;  // (n) from the weave
  bool self_contact = true;

  bool needBroadphaseCollision(btBroadphaseProxy* proxy0,
                               btBroadphaseProxy* proxy1) const override {
    const bool masks = (proxy0->m_collisionFilterGroup & proxy1->m_collisionFilterMask) != 0 &&
                       (proxy1->m_collisionFilterGroup & proxy0->m_collisionFilterMask) != 0;
    if (!masks || self_contact) return masks;
    const int ring0 = static_cast<const btCollisionObject*>(proxy0->m_clientObject)->getUserIndex();
    const int ring1 = static_cast<const btCollisionObject*>(proxy1->m_clientObject)->getUserIndex();
    if (ring0 < 0 || ring1 < 0) return true;
    const auto& around = (*neighbours)[ring0];
    return std::find(around.begin(), around.end(), ring1) != around.end();
  }
};

// Bullet's narrow phase with each pair's work timed under the stage it belongs to: linked
// neighbours ("links"), a ring against a scene collider ("colliders"), two rings that are not
// neighbours ("self_contact"). A scene without colliders or self-contact has no such pairs (the
// broad-phase filter drops them), so those stages never appear, as in every other backend.
class ProfiledDispatcher final : public btCollisionDispatcher {
 public:
  ProfiledDispatcher(btCollisionConfiguration* configuration, StageProfile& profile,
                     const std::vector<std::array<int, 4>>& neighbours)
      : btCollisionDispatcher(configuration), profile_(profile), neighbours_(neighbours) {
    setNearCallback(&near_callback);
  }

 private:
  static void near_callback(btBroadphasePair& pair, btCollisionDispatcher& dispatcher,
                            const btDispatcherInfo& info) {
    auto& self = static_cast<ProfiledDispatcher&>(dispatcher);
    const int ring0 =
        static_cast<const btCollisionObject*>(pair.m_pProxy0->m_clientObject)->getUserIndex();
    const int ring1 =
        static_cast<const btCollisionObject*>(pair.m_pProxy1->m_clientObject)->getUserIndex();
    const char* stage = "self_contact";
    if (ring0 < 0 || ring1 < 0) {
      stage = "colliders";
    } else {
      const auto& around = self.neighbours_[ring0];
      if (std::find(around.begin(), around.end(), ring1) != around.end()) stage = "links";
    }
    auto scope = self.profile_.scope(stage);
    btCollisionDispatcher::defaultNearCallback(pair, dispatcher, info);
  }

  StageProfile& profile_;
  const std::vector<std::array<int, 4>>& neighbours_;
};

// Bullet's discrete world with its phases timed into the backend's StageProfile
class ProfiledWorld final : public btDiscreteDynamicsWorld {
 public:
  ProfiledWorld(btDispatcher* dispatcher, btBroadphaseInterface* broadphase,
                btConstraintSolver* solver, btCollisionConfiguration* configuration,
                StageProfile& profile)
      : btDiscreteDynamicsWorld(dispatcher, broadphase, solver, configuration), profile_(profile) {}

  void performDiscreteCollisionDetection() override {
    auto scope = profile_.scope("collision_detection");
    btDiscreteDynamicsWorld::performDiscreteCollisionDetection();
  }
  void solveConstraints(btContactSolverInfo& info) override {
    auto scope = profile_.scope("solve");
    btDiscreteDynamicsWorld::solveConstraints(info);
  }

 protected:
  void predictUnconstraintMotion(btScalar h) override {
    auto scope = profile_.scope("predict");
    btDiscreteDynamicsWorld::predictUnconstraintMotion(h);
  }
  void integrateTransforms(btScalar h) override {
    auto scope = profile_.scope("integrate");
    btDiscreteDynamicsWorld::integrateTransforms(h);
  }

 private:
  StageProfile& profile_;
};

btVector3 to_bt(const Vec3& v, double scale) {
  return btVector3(static_cast<btScalar>(v.x() * scale), static_cast<btScalar>(v.y() * scale),
                   static_cast<btScalar>(v.z() * scale));
}

class BulletBackend final : public Backend {
 public:
  ~BulletBackend() override { release(); }

  const char* name() const override { return "bullet"; }
  void reset(const Scene& scene, const Weave& weave, const Knobs& knobs) override;
  StepStatus step(double dt) override;
  void frame(RingFrame& out) const override;
  const StageProfile& profile() const override { return profile_; }

 private:
  void release();
  void build_world();
  void build_ring_shape(const RingGeometry& ring);
  void add_colliders(const Scene& scene);
  void add_rings(const Scene& scene, const Weave& weave);

  // fixed model
  BulletSettings settings_;
  std::vector<std::array<int, 4>> neighbours_;  // (n) weave neighbours, for the pair filter
  RingPairFilter pair_filter_;

  // Bullet's world; members are released in reverse order of construction by release()
  std::unique_ptr<btDefaultCollisionConfiguration> configuration_;
  std::unique_ptr<ProfiledDispatcher> dispatcher_;
  std::unique_ptr<btDbvtBroadphase> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<ProfiledWorld> world_;
  std::unique_ptr<btCapsuleShape> capsule_;  // one capsule shared by every piece of every ring
  std::unique_ptr<btCompoundShape> torus_;   // one compound shared by every ring
  std::vector<std::unique_ptr<btCollisionShape>> collider_shapes_;
  std::vector<std::unique_ptr<btRigidBody>> colliders_;
  std::vector<std::unique_ptr<btRigidBody>> rings_;  // (n) in weave order; pins are static

  // changing state beyond Bullet's bodies
  double time_ = 0.0;  // s
  StageProfile profile_;
};

void BulletBackend::release() {
  // bodies leave the world before it goes, the world before its dispatcher, broadphase and solver
  if (world_) {
    for (auto& body : rings_) world_->removeRigidBody(body.get());
    for (auto& body : colliders_) world_->removeRigidBody(body.get());
  }
  world_.reset();
  rings_.clear();
  colliders_.clear();
  collider_shapes_.clear();
  torus_.reset();
  capsule_.reset();
  solver_.reset();
  broadphase_.reset();
  dispatcher_.reset();
  configuration_.reset();
}

void BulletBackend::reset(const Scene& scene, const Weave& weave, const Knobs& knobs) {
  release();
  settings_ = bullet_knobs().settings(knobs);
  neighbours_ = weave.neighbours;
  pair_filter_.neighbours = &neighbours_;
  pair_filter_.self_contact = scene.self_contact;
  time_ = 0.0;
  profile_.clear();

  build_world();
  world_->setGravity(to_bt(scene.gravity, settings_.length_scale));
  build_ring_shape(scene.ring);
  add_colliders(scene);
  add_rings(scene, weave);
}

void BulletBackend::build_world() {
  configuration_ = std::make_unique<btDefaultCollisionConfiguration>();
  dispatcher_ = std::make_unique<ProfiledDispatcher>(configuration_.get(), profile_, neighbours_);
  broadphase_ = std::make_unique<btDbvtBroadphase>();
  broadphase_->getOverlappingPairCache()->setOverlapFilterCallback(&pair_filter_);
  solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
  world_ = std::make_unique<ProfiledWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(),
                                           configuration_.get(), profile_);

  // solver: fixed sweep count, warm starting, penetration recovered by split impulse when on
  btContactSolverInfo& info = world_->getSolverInfo();
  info.m_numIterations = settings_.solver_iterations;
  info.m_splitImpulse = settings_.split_impulse ? 1 : 0;
  info.m_solverMode = SOLVER_USE_WARMSTARTING | SOLVER_SIMD |
                      (settings_.friction_directions > 1 ? SOLVER_USE_2_FRICTION_DIRECTIONS : 0);

  // the scene's friction and restitution per contact kind (process-wide hooks, stateless)
  gCalculateCombinedFrictionCallback = &combined_friction;
  gCalculateCombinedRestitutionCallback = &combined_restitution;
}

void BulletBackend::build_ring_shape(const RingGeometry& ring) {
  // capsules of the wire radius on the chords of a regular polygon in the local X/Z plane
  const double scale = settings_.length_scale;
  const CapsuleTorus fit = capsule_torus(ring.wire_radius, ring.centre_radius, settings_.pieces);
  capsule_ = std::make_unique<btCapsuleShapeX>(static_cast<btScalar>(ring.wire_radius * scale),
                                               static_cast<btScalar>(fit.capsule_length * scale));
  torus_ = std::make_unique<btCompoundShape>(true, settings_.pieces);
  for (int piece = 0; piece < settings_.pieces; ++piece) {
    // chord midpoint at angle s; rotate the capsule's X axis onto the tangent (-sin s, 0, cos s)
    const double s = (2.0 * piece + 1.0) * std::numbers::pi / settings_.pieces;
    const btVector3 midpoint(static_cast<btScalar>(fit.midpoint_radius * scale * std::cos(s)), 0,
                             static_cast<btScalar>(fit.midpoint_radius * scale * std::sin(s)));
    const btQuaternion along_chord(btVector3(0, 1, 0),
                                   static_cast<btScalar>(-(s + 0.5 * std::numbers::pi)));
    torus_->addChildShape(btTransform(along_chord, midpoint), capsule_.get());
  }
}

void BulletBackend::add_colliders(const Scene& scene) {
  const double scale = settings_.length_scale;
  for (const Collider& collider : scene.colliders) {
    btTransform pose = btTransform::getIdentity();
    pose.setOrigin(to_bt(collider.center, scale));
    std::unique_ptr<btCollisionShape> shape;
    switch (collider.type) {
      case Collider::Type::plane: {
        const Vec3 normal = collider.normal.normalized();
        shape = std::make_unique<btStaticPlaneShape>(
            to_bt(normal, 1.0), static_cast<btScalar>(normal.dot(collider.center) * scale));
        pose.setOrigin(btVector3(0, 0, 0));
        break;
      }
      case Collider::Type::sphere:
        shape = std::make_unique<btSphereShape>(static_cast<btScalar>(collider.radius * scale));
        break;
      case Collider::Type::box:
        shape = std::make_unique<btBoxShape>(to_bt(collider.half_extents, scale));
        break;
      case Collider::Type::cylinder:
        shape = std::make_unique<btCylinderShape>(
            to_bt(Vec3(collider.radius, collider.half_height, collider.radius), scale));
        break;
    }
    btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shape.get());
    info.m_startWorldTransform = pose;
    info.m_friction = static_cast<btScalar>(collider.friction);
    info.m_restitution = static_cast<btScalar>(settings_.restitution);
    auto body = std::make_unique<btRigidBody>(info);
    body->setUserIndex(kColliderIndex);
    world_->addRigidBody(body.get());
    collider_shapes_.push_back(std::move(shape));
    colliders_.push_back(std::move(body));
  }
}

void BulletBackend::add_rings(const Scene& scene, const Weave& weave) {
  // analytic torus mass and principal inertia (local axes: ring in X/Z, axis Y)
  const double scale = settings_.length_scale;
  // a loaded ring (the scene's loads) scales mass and inertia by its mass factor
  const std::vector<double> masses = ring_masses(scene, weave);
  const btVector3 inertia = to_bt(scene.ring.inertia(), scale * scale);
  std::vector<bool> pinned(weave.size(), false);
  for (int ring : resolve_pins(scene, weave)) pinned[ring] = true;

  for (int ring = 0; ring < weave.size(); ++ring) {
    const auto q = weave.rest_orientation.col(ring);
    btTransform pose(btQuaternion(static_cast<btScalar>(q(1)), static_cast<btScalar>(q(2)),
                                  static_cast<btScalar>(q(3)), static_cast<btScalar>(q(0))),
                     to_bt(weave.rest_position.col(ring), scale));
    // a pinned ring is a static body: infinite mass, never moves
    const btScalar factor = static_cast<btScalar>(masses[ring] / scene.ring.mass());
    const btScalar mass = static_cast<btScalar>(masses[ring]);
    btRigidBody::btRigidBodyConstructionInfo info(
        pinned[ring] ? 0 : mass, nullptr, torus_.get(),
        pinned[ring] ? btVector3(0, 0, 0) : inertia * factor);
    info.m_startWorldTransform = pose;
    info.m_friction = static_cast<btScalar>(scene.ring_friction);
    info.m_restitution = static_cast<btScalar>(settings_.restitution);
    info.m_linearDamping = static_cast<btScalar>(settings_.linear_damping);
    info.m_angularDamping = static_cast<btScalar>(settings_.angular_damping);
    auto body = std::make_unique<btRigidBody>(info);
    body->setUserIndex(ring);
    if (!pinned[ring]) body->setLinearVelocity(to_bt(scene.initial_velocity, scale));
    body->setActivationState(DISABLE_DEACTIVATION);  // no sleeping: a resting sheet is still solved
    body->setContactProcessingThreshold(
        static_cast<btScalar>(settings_.contact_processing_threshold * scale));
    world_->addRigidBody(body.get());
    rings_.push_back(std::move(body));
  }
}

StepStatus BulletBackend::step(double dt) {
  // fixed equal internal steps; maxSubSteps = 0 makes Bullet take exactly one step of h
  const btScalar h = static_cast<btScalar>(dt / settings_.substeps);
  for (int k = 0; k < settings_.substeps; ++k) world_->stepSimulation(h, 0, h);
  time_ += dt;
  return StepStatus::ok;
}

void BulletBackend::frame(RingFrame& out) const {
  const double inverse_scale = 1.0 / settings_.length_scale;
  out.t = time_;
  out.resize(static_cast<int>(rings_.size()));
  for (int ring = 0; ring < static_cast<int>(rings_.size()); ++ring) {
    const btTransform& pose = rings_[ring]->getWorldTransform();
    const btVector3& origin = pose.getOrigin();
    const btVector3& velocity = rings_[ring]->getLinearVelocity();
    const btQuaternion rotation = pose.getRotation();
    out.position.col(ring) = Vec3(origin.x(), origin.y(), origin.z()) * inverse_scale;
    out.velocity.col(ring) = Vec3(velocity.x(), velocity.y(), velocity.z()) * inverse_scale;
    out.set_quat(ring, Quat(rotation.w(), rotation.x(), rotation.y(), rotation.z()).normalized());
  }
}

}  // namespace

BackendInfo bullet_backend_info() {
  BackendInfo info;
  info.name = "bullet";
  info.cost_us_per_ring_step = 150;
  info.bytes_per_ring = 8000;
  info.summary = "rigid tori (compound of capsules), Bullet sequential-impulse solver";
  info.knobs = bullet_knobs().specs();
  info.knob_round_trip = bullet_knobs().round_trip();
  info.create = [] { return std::unique_ptr<Backend>(std::make_unique<BulletBackend>()); };
  return info;
}

}  // namespace chainmail
