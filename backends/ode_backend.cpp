// ODE rigid-torus backend: process-wide set-up, knobs, model building and stepping; the
// collision pipeline is in ode_contacts.cpp. The harness's ground truth for ring-level behaviour.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "backends/capsule_torus.hpp"
#include "backends/ode_backend.hpp"

namespace chainmail {
namespace ode {
namespace {

[[noreturn]] void throw_ode_failure(int errnum, const char* msg, va_list ap) {
  char text[512];
  std::vsnprintf(text, sizeof text, msg, ap);
  throw OdeFailure("ode error " + std::to_string(errnum) + ": " + text);
}

// messages (LCP warnings and the like) are informational; the metrics report what matters
void ignore_ode_message(int, const char*, va_list) {}

// dInitODE2 once per process, dCloseODE at exit; per-thread data for every thread that steps
void ensure_ode_ready() {
  struct Library {
    Library() {
      dInitODE2(0);
      dSetErrorHandler(&throw_ode_failure);
      dSetDebugHandler(&throw_ode_failure);
      dSetMessageHandler(&ignore_ode_message);
    }
    ~Library() { dCloseODE(); }
  };
  static Library library;
  thread_local const bool thread_ready = dAllocateODEDataForThread(dAllocateMaskAll) != 0;
  if (!thread_ready) throw std::runtime_error("ode: cannot allocate per-thread data");
}

// every knob once, bound to its OdeSettings field (the field's default is the knob's)
const KnobTable<OdeSettings>& ode_knobs() {
  using S = OdeSettings;
  static const KnobTable<S> table = [] {
    KnobTable<S> t;
    t.time_step(1e-3, 1e-7, 1.0, "time step of one step(), s")
        .unit("s")
        .doc("time step of one `step()`");
    t.integer("substeps", &S::substeps, 1, 10000, "fixed solver steps per step()")
        .doc("fixed solver steps per `step()`");
    t.integer("iterations", &S::iterations, 1, 100000, "QuickStep SOR iterations per solver step");
    t.number("sor", &S::sor, 0.05, 1.95, "QuickStep over-relaxation factor");
    t.number("erp", &S::erp, 0.0, 1.0, "contact error reduction per solver step");
    t.number("cfm", &S::cfm, 0.0, 1.0,
             "contact constraint force mixing, internal units (length_scale, ring mass 1)")
        .doc("contact constraint force mixing, internal units (`length_scale`, ring mass 1)");
    t.number("restitution", &S::restitution, 0.0, 1.0, "contact restitution");
    t.number("linear_damping", &S::linear_damping, 0.0, 1e4, "linear velocity damping, 1/s")
        .unit("1/s")
        .doc("linear velocity damping rate");
    t.number("angular_damping", &S::angular_damping, 0.0, 1e4, "angular velocity damping, 1/s")
        .unit("1/s")
        .doc("angular velocity damping rate");
    t.integer("pieces", &S::pieces, 6, 256, "capsules per ring");
    t.number("length_scale", &S::length_scale, 1e-3, 1e6, "internal length units per metre");
    t.integer("max_contacts", &S::max_contacts, 1, kMaxContactsLimit,
              "contacts kept per colliding geom pair")
        .doc("contacts kept per colliding geometry pair");
    t.number("max_correcting_velocity", &S::max_correcting_velocity, 0.0, 1e3,
             "cap on the speed of penetration recovery, m/s (0: none)")
        .unit("m/s")
        .doc("cap on the speed of penetration recovery (0: none)");
    t.number("contact_layer", &S::contact_layer, 0.0, 1.0,
             "resting penetration allowed before correction, fraction of the wire radius");
    return t;
  }();
  return table;
}

}  // namespace

void OdeBackend::reset(const Scene& scene, const Weave& weave, const Knobs& knobs) {
  ensure_ode_ready();
  destroy_world();
  profile_.clear();
  settings_ = ode_knobs().settings(knobs);
  ring_ = scene.ring;
  ring_friction_ = scene.ring_friction;
  self_contact_ = scene.self_contact;
  neighbours_ = weave.neighbours;
  time_ = 0.0;
  solver_steps_ = 0;
  damping_step_ = 0.0;  // the first step sets the damping factors for its solver step h
  failed_ = false;

  build_world(scene, weave);
  build_rings(weave, resolve_pins(scene, weave), ring_masses(scene, weave), scene.initial_velocity);
  build_colliders(scene);
}

StepStatus OdeBackend::step(double dt) {
  time_ += dt;
  if (failed_) return StepStatus::non_finite;
  if (!world_) return StepStatus::ok;
  const double h = dt / settings_.substeps;
  if (h != damping_step_) set_damping(h);
  try {
    for (int k = 0; k < settings_.substeps && !failed_; ++k) solver_step(h);
  } catch (const OdeFailure&) {
    failed_ = true;  // the frame reports NaN from now on
  }
  if (!failed_) check_finite();
  return failed_ ? StepStatus::non_finite : StepStatus::ok;
}

void OdeBackend::frame(RingFrame& out) const {
  const int n = static_cast<int>(bodies_.size());
  out.t = time_;
  out.resize(n);
  const double to_metres = 1.0 / settings_.length_scale;
  for (int i = 0; i < n; ++i) {
    const dReal* p = dBodyGetPosition(bodies_[i]);
    const dReal* q = dBodyGetQuaternion(bodies_[i]);  // w, x, y, z
    const dReal* v = dBodyGetLinearVel(bodies_[i]);
    out.position.col(i) = to_metres * Vec3(p[0], p[1], p[2]);
    out.orientation.col(i) << q[0], q[1], q[2], q[3];
    out.velocity.col(i) = to_metres * Vec3(v[0], v[1], v[2]);
  }
  if (failed_) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.position.setConstant(nan);
    out.orientation.setConstant(nan);
    out.velocity.setConstant(nan);
  }
}

// ---- model building ----

void OdeBackend::build_world(const Scene& scene, const Weave& weave) {
  const double scale = settings_.length_scale;
  world_ = dWorldCreate();
  const Vec3 g = scale * scene.gravity;
  dWorldSetGravity(world_, g.x(), g.y(), g.z());
  dWorldSetQuickStepNumIterations(world_, settings_.iterations);
  dWorldSetQuickStepW(world_, settings_.sor);
  dWorldSetERP(world_, settings_.erp);
  dWorldSetCFM(world_, settings_.cfm);
  dWorldSetContactMaxCorrectingVel(world_, settings_.max_correcting_velocity > 0.0
                                               ? settings_.max_correcting_velocity * scale
                                               : dInfinity);
  dWorldSetContactSurfaceLayer(world_, settings_.contact_layer * scene.ring.wire_radius * scale);
  dWorldSetAutoDisableFlag(world_, 0);

  // every body damped whatever its speed; the factors themselves are set by step (set_damping)
  dWorldSetLinearDampingThreshold(world_, 0.0);
  dWorldSetAngularDampingThreshold(world_, 0.0);

  contacts_ = dJointGroupCreate(0);
  static_space_ = dSimpleSpaceCreate(nullptr);

  // broad phase over one bounding sphere per ring (not over the pieces: 28x fewer boxes),
  // sweep and prune along the longest axis of the rest layout
  ring_space_ = dSweepAndPruneSpaceCreate(nullptr, sweep_axes(weave));
}

// dSAP_AXES_* order: the axis along which the rest layout is longest first
int OdeBackend::sweep_axes(const Weave& weave) {
  Vec3 extent = Vec3::Zero();
  if (weave.size() > 0) {
    extent = weave.rest_position.rowwise().maxCoeff() - weave.rest_position.rowwise().minCoeff();
  }
  std::array<int, 3> order = {0, 1, 2};
  std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return extent[i] > extent[j]; });
  return order[0] | (order[1] << 2) | (order[2] << 4);  // the dSAP_AXES_* encoding
}

// masses (n, kg) carry the scene's loads; every free ring starts at `velocity` (m/s)
void OdeBackend::build_rings(const Weave& weave, const std::vector<int>& pinned,
                             const std::vector<double>& masses, const Vec3& velocity) {
  const double scale = settings_.length_scale;
  const int n = weave.size();
  const CapsuleTorus shape =
      capsule_torus(ring_.wire_radius, ring_.centre_radius, settings_.pieces);

  // mass in ring masses: 1 per ring, inertia of the analytic torus (local Y is the ring axis)
  // (a loaded ring scales both by its mass factor)
  const Vec3 inertia = ring_.inertia() / ring_.mass() * (scale * scale);

  // mid phase: a piece (centre m, half length l) can touch another ring's compound only when m
  // is within l + a of that compound, which lies within a + e of its centre circle
  piece_reach_ = (0.5 * shape.capsule_length + 2.0 * ring_.wire_radius + shape.surface_error) *
                 scale * (1.0 + 1e-9);
  piece_pair_reach_ = (shape.capsule_length + 2.0 * ring_.wire_radius) * scale * (1.0 + 1e-9);
  centre_radius_internal_ = ring_.centre_radius * scale;
  wire_radius_internal_ = ring_.wire_radius * scale;

  bodies_.resize(n);
  pieces_.reserve(static_cast<std::size_t>(n) * settings_.pieces);
  for (int i = 0; i < n; ++i) {
    dBodyID body = dBodyCreate(world_);
    bodies_[i] = body;
    dBodySetData(body, reinterpret_cast<void*>(static_cast<std::intptr_t>(i)));
    const double factor = masses[i] / ring_.mass();
    dMass mass;
    dMassSetParameters(&mass, factor, 0.0, 0.0, 0.0, factor * inertia.x(), factor * inertia.y(),
                       factor * inertia.z(), 0.0, 0.0, 0.0);
    dBodySetMass(body, &mass);
    const Vec3 p = scale * weave.rest_position.col(i);
    dBodySetPosition(body, p.x(), p.y(), p.z());
    const dQuaternion q = {weave.rest_orientation(0, i), weave.rest_orientation(1, i),
                           weave.rest_orientation(2, i), weave.rest_orientation(3, i)};
    dBodySetQuaternion(body, q);
    const Vec3 v = scale * velocity;
    dBodySetLinearVel(body, v.x(), v.y(), v.z());
    dBodySetAngularVel(body, 0.0, 0.0, 0.0);

    // the ring's bounding sphere for the broad phase; it is never collided itself
    dGeomID bound = dCreateSphere(
        ring_space_, (ring_.centre_radius + ring_.wire_radius + shape.surface_error) * scale);
    dGeomSetBody(bound, body);

    // capsule k joins polygon vertices k and k+1; ODE capsules run along their local Z.
    // pieces live in no space: the mid phase picks them per ring pair
    for (int k = 0; k < settings_.pieces; ++k) {
      const double phi = (2.0 * k + 1.0) * std::numbers::pi / settings_.pieces;
      const double midpoint = shape.midpoint_radius * scale;  // internal units
      const Vec3 radial(std::cos(phi), 0.0, std::sin(phi));
      const Vec3 tangent(-std::sin(phi), 0.0, std::cos(phi));
      dGeomID capsule =
          dCreateCapsule(nullptr, ring_.wire_radius * scale, shape.capsule_length * scale);
      pieces_.push_back(capsule);
      dGeomSetBody(capsule, body);
      dGeomSetOffsetPosition(capsule, midpoint * radial.x(), 0.0, midpoint * radial.z());
      // columns: geom X = radial, geom Y = ring axis, geom Z = tangent (row-major 3x4)
      dMatrix3 rotation = {radial.x(), 0.0, tangent.x(), 0.0,  //
                           radial.y(), 1.0, tangent.y(), 0.0,  //
                           radial.z(), 0.0, tangent.z(), 0.0};
      dGeomSetOffsetRotation(capsule, rotation);
    }
  }
  // pins: kinematic bodies (infinite mass) held at their rest pose
  for (int i : pinned) {
    dBodySetKinematic(bodies_[i]);
    dBodySetLinearVel(bodies_[i], 0.0, 0.0, 0.0);
  }
}

void OdeBackend::build_colliders(const Scene& scene) {
  const double scale = settings_.length_scale;
  collider_friction_.clear();
  for (const Collider& collider : scene.colliders) {
    const Vec3 c = scale * collider.center;
    dGeomID geom = nullptr;
    switch (collider.type) {
      case Collider::Type::plane:
        geom = dCreatePlane(static_space_, collider.normal.x(), collider.normal.y(),
                            collider.normal.z(), collider.normal.dot(c));
        break;
      case Collider::Type::sphere:
        geom = dCreateSphere(static_space_, collider.radius * scale);
        dGeomSetPosition(geom, c.x(), c.y(), c.z());
        break;
      case Collider::Type::box: {
        const Vec3 size = 2.0 * scale * collider.half_extents;
        geom = dCreateBox(static_space_, size.x(), size.y(), size.z());
        dGeomSetPosition(geom, c.x(), c.y(), c.z());
        break;
      }
      case Collider::Type::cylinder: {
        // ODE cylinders run along their local Z; turn it onto world Y
        geom = dCreateCylinder(static_space_, collider.radius * scale,
                               2.0 * collider.half_height * scale);
        dGeomSetPosition(geom, c.x(), c.y(), c.z());
        dMatrix3 rotation;
        dRFromAxisAndAngle(rotation, 1.0, 0.0, 0.0, -0.5 * std::numbers::pi);
        dGeomSetRotation(geom, rotation);
        break;
      }
    }
    dGeomSetData(geom,
                 reinterpret_cast<void*>(static_cast<std::intptr_t>(collider_friction_.size())));
    collider_friction_.push_back(collider.friction);
  }
  has_colliders_ = !scene.colliders.empty();
}

void OdeBackend::destroy_world() {
  // the joint group, pieces and spaces (with their geoms) go before the world and its bodies
  if (contacts_) dJointGroupDestroy(contacts_);
  for (dGeomID piece : pieces_) dGeomDestroy(piece);
  pieces_.clear();
  if (ring_space_) dSpaceDestroy(ring_space_);
  if (static_space_) dSpaceDestroy(static_space_);
  if (world_) dWorldDestroy(world_);
  contacts_ = nullptr;
  ring_space_ = static_space_ = nullptr;
  world_ = nullptr;
  bodies_.clear();
}

// a body that went non-finite ends the run (ODE would assert on it in the next step)
void OdeBackend::check_finite() {
  for (dBodyID body : bodies_) {
    const dReal* p = dBodyGetPosition(body);
    const dReal* v = dBodyGetLinearVel(body);
    const dReal* w = dBodyGetAngularVel(body);
    const dReal* q = dBodyGetQuaternion(body);
    bool finite = true;
    for (int k = 0; k < 3; ++k) {
      finite &= std::isfinite(p[k]) && std::isfinite(v[k]) && std::isfinite(w[k]);
    }
    for (int k = 0; k < 4; ++k) finite &= std::isfinite(q[k]);
    if (!finite) {
      failed_ = true;
      return;
    }
  }
}

// ODE damps by a factor per solver step; convert the rates (1/s) so dt does not change them. A
// body copies the world's factors only when it is created, so the bodies are set as well
void OdeBackend::set_damping(double h) {
  const dReal linear = -std::expm1(-settings_.linear_damping * h);
  const dReal angular = -std::expm1(-settings_.angular_damping * h);
  dWorldSetLinearDamping(world_, linear);
  dWorldSetAngularDamping(world_, angular);
  for (dBodyID body : bodies_) {
    dBodySetLinearDamping(body, linear);
    dBodySetAngularDamping(body, angular);
  }
  damping_step_ = h;
}

}  // namespace ode

BackendInfo ode_backend_info() {
  BackendInfo info;
  info.name = "ode";
  info.cost_us_per_ring_step = 25;
  info.bytes_per_ring = 6000;
  info.summary = "ODE 0.16 rigid bodies, each ring a torus of capsules, QuickStep contacts";
  info.knobs = ode::ode_knobs().specs();
  info.knob_round_trip = ode::ode_knobs().round_trip();
  info.create = []() -> std::unique_ptr<Backend> { return std::make_unique<ode::OdeBackend>(); };
  return info;
}

}  // namespace chainmail
