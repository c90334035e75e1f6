// ODE rigid-torus backend: every ring a rigid body whose collision shape is a torus built from
// capsules along the chords of a regular N-gon, solved by ODE's QuickStep (projected SOR over
// contact constraints). The harness's ground truth for ring-level behaviour.
//
// Internal units: lengths are multiplied by the knob length_scale (internal units per metre) and
// masses are measured in ring masses, so the contact solver sees numbers near 1; time is seconds.
// Everything crossing the Backend interface is SI.
#include <ode/ode.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "backends/backend.hpp"
#include "core/capsule_torus.hpp"

namespace chainmail {

namespace {

// ---------------------------------------------------------------------------------------------
// process-wide ODE set-up

// ODE reports errors through handlers that return into exit()/abort(); ours throw instead, so a
// run that goes numerically bad ends as a failed simulation rather than a dead process
class OdeFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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

// ---------------------------------------------------------------------------------------------
// settings

struct OdeSettings {
  double dt = 1e-3;                      // s, one step()
  int substeps = 2;                      // fixed solver steps per step()
  int iterations = 20;                   // QuickStep SOR iterations per solver step
  double sor = 1.3;                      // QuickStep over-relaxation
  double erp = 0.2;                      // contact error reduction per solver step
  double cfm = 1e-6;                     // contact constraint force mixing, internal units
  double restitution = 0.0;              // contact bounce
  double linear_damping = 0.0;           // 1/s
  double angular_damping = 0.0;          // 1/s
  int pieces = 28;                       // capsules per ring
  double length_scale = 1000.0;          // internal length units per metre
  int max_contacts = 4;                  // contacts per geom pair
  double max_correcting_velocity = 0.1;  // m/s, cap on penetration recovery speed
  double contact_layer = 0.01;           // allowed resting penetration, fraction of wire radius

  static OdeSettings from(const Knobs& knobs) {
    OdeSettings s;
    s.dt = knobs.at("dt");
    s.substeps = static_cast<int>(knobs.at("substeps"));
    s.iterations = static_cast<int>(knobs.at("iterations"));
    s.sor = knobs.at("sor");
    s.erp = knobs.at("erp");
    s.cfm = knobs.at("cfm");
    s.restitution = knobs.at("restitution");
    s.linear_damping = knobs.at("linear_damping");
    s.angular_damping = knobs.at("angular_damping");
    s.pieces = static_cast<int>(knobs.at("pieces"));
    s.length_scale = knobs.at("length_scale");
    s.max_contacts = static_cast<int>(knobs.at("max_contacts"));
    s.max_correcting_velocity = knobs.at("max_correcting_velocity");
    s.contact_layer = knobs.at("contact_layer");
    return s;
  }
};

constexpr int kMaxContactsLimit = 32;  // knob bound and the size of the per-pair contact buffer

// ---------------------------------------------------------------------------------------------
// the backend

class OdeBackend final : public Backend {
 public:
  OdeBackend() = default;
  ~OdeBackend() override { destroy_world(); }
  OdeBackend(const OdeBackend&) = delete;
  OdeBackend& operator=(const OdeBackend&) = delete;

  const char* name() const override { return "ode"; }
  const StageProfile& profile() const override { return profile_; }

  void reset(const Scene& scene, const Weave& weave, const Knobs& knobs) override {
    ensure_ode_ready();
    destroy_world();
    profile_.clear();
    settings_ = OdeSettings::from(knobs);
    ring_ = scene.ring;
    ring_friction_ = scene.ring_friction;
    self_contact_ = scene.self_contact;
    neighbours_ = weave.neighbours;
    time_ = 0.0;
    solver_steps_ = 0;
    failed_ = false;

    build_world(scene, weave);
    build_rings(weave, resolve_pins(scene, weave), ring_masses(scene, weave),
                scene.initial_velocity);
    build_colliders(scene);
  }

  void step(double dt) override {
    time_ += dt;
    if (failed_ || !world_) return;
    const double h = dt / settings_.substeps;
    if (h != damping_step_) set_damping(h);
    try {
      for (int k = 0; k < settings_.substeps && !failed_; ++k) solver_step(h);
    } catch (const OdeFailure&) {
      failed_ = true;  // the frame reports NaN from now on; metrics give the verdict
    }
    if (!failed_) check_finite();
  }

  void frame(RingFrame& out) const override {
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

 private:
  // ---- model building ----

  void build_world(const Scene& scene, const Weave& weave) {
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

    set_damping(settings_.dt / settings_.substeps);
    dWorldSetLinearDampingThreshold(world_, 0.0);
    dWorldSetAngularDampingThreshold(world_, 0.0);

    contacts_ = dJointGroupCreate(0);
    static_space_ = dSimpleSpaceCreate(nullptr);

    // broad phase over one bounding sphere per ring (not over the pieces: 28x fewer boxes),
    // sweep and prune along the longest axis of the rest layout
    ring_space_ = dSweepAndPruneSpaceCreate(nullptr, sweep_axes(weave));
  }

  // dSAP_AXES_* order: the axis along which the rest layout is longest first
  static int sweep_axes(const Weave& weave) {
    Vec3 extent = Vec3::Zero();
    if (weave.size() > 0) {
      extent = weave.rest_position.rowwise().maxCoeff() - weave.rest_position.rowwise().minCoeff();
    }
    std::array<int, 3> order = {0, 1, 2};
    std::stable_sort(order.begin(), order.end(),
                     [&](int i, int j) { return extent[i] > extent[j]; });
    return order[0] | (order[1] << 2) | (order[2] << 4);  // the dSAP_AXES_* encoding
  }

  // masses (n, kg) carry the scene's loads; every free ring starts at `velocity` (m/s)
  void build_rings(const Weave& weave, const std::vector<int>& pinned,
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

  void build_colliders(const Scene& scene) {
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

  void destroy_world() {
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

  // ---- one solver step: contacts, then the constraint solve ----

  void solver_step(double h) {
    {
      auto scope = profile_.scope("ring_contact");
      dSpaceCollide(ring_space_, this, &OdeBackend::near_callback);
    }
    if (has_colliders_) {
      auto scope = profile_.scope("colliders");
      dSpaceCollide2(reinterpret_cast<dGeomID>(ring_space_),
                     reinterpret_cast<dGeomID>(static_space_), this, &OdeBackend::near_callback);
    }
    {
      auto scope = profile_.scope("solve");
      // QuickStep shuffles constraints with ODE's global generator: seed it per step so the
      // result depends on this model alone
      dRandSetSeed(static_cast<unsigned long>(solver_steps_++));
      const int ok = dWorldQuickStep(world_, h);
      dJointGroupEmpty(contacts_);
      if (!ok) throw OdeFailure("ode: QuickStep could not allocate memory");
    }
  }

  // a body that went non-finite ends the run (ODE would assert on it in the next step)
  void check_finite() {
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

  // ODE damps by a factor per solver step; convert the rates (1/s) so dt does not change them
  void set_damping(double h) {
    dWorldSetLinearDamping(world_, -std::expm1(-settings_.linear_damping * h));
    dWorldSetAngularDamping(world_, -std::expm1(-settings_.angular_damping * h));
    damping_step_ = h;
  }

  static void near_callback(void* data, dGeomID first, dGeomID second) {
    static_cast<OdeBackend*>(data)->collide_pair(first, second);
  }

  void collide_pair(dGeomID first, dGeomID second) {
    // a space against a space or a geom: descend into it
    if (dGeomIsSpace(first) || dGeomIsSpace(second)) {
      dSpaceCollide2(first, second, this, &OdeBackend::near_callback);
      return;
    }
    dBodyID body1 = dGeomGetBody(first);
    dBodyID body2 = dGeomGetBody(second);
    if (body1 == body2) return;  // two static geoms
    const bool moves1 = body1 && !dBodyIsKinematic(body1);
    const bool moves2 = body2 && !dBodyIsKinematic(body2);
    if (!moves1 && !moves2) return;  // pinned against pinned or static: nothing to solve

    if (body1 && body2) {
      const int ring1 = ring_of(body1), ring2 = ring_of(body2);
      if (are_neighbours(ring1, ring2)) {
        collide_rings(ring1, ring2);
      } else if (self_contact_) {
        auto scope = profile_.scope("self_contact");
        collide_rings(ring1, ring2);
      }
    } else {
      const int ring = ring_of(body1 ? body1 : body2);
      dGeomID collider = body1 ? second : first;
      collide_ring_with_collider(ring, collider);
    }
  }

  // pieces of both rings near the other ring's wire, then capsule against capsule
  void collide_rings(int first, int second) {
    near_pieces(first, second, near_first_);
    if (near_first_.empty()) return;
    near_pieces(second, first, near_second_);
    const double reach2 = piece_pair_reach_ * piece_pair_reach_;
    pair_contacts_.clear();
    for (dGeomID p : near_first_) {
      const dReal* pc = dGeomGetPosition(p);
      for (dGeomID q : near_second_) {
        const dReal* qc = dGeomGetPosition(q);
        const double d2 = (pc[0] - qc[0]) * (pc[0] - qc[0]) + (pc[1] - qc[1]) * (pc[1] - qc[1]) +
                          (pc[2] - qc[2]) * (pc[2] - qc[2]);
        if (d2 > reach2) continue;
        dContactGeom found[kMaxContactsLimit];
        const int count = dCollide(p, q, settings_.max_contacts, found, sizeof(dContactGeom));
        pair_contacts_.insert(pair_contacts_.end(), found, found + count);
      }
    }
    merge_duplicate_contacts(pair_contacts_);
    for (const dContactGeom& geom : pair_contacts_) {
      add_contact(geom, bodies_[first], bodies_[second], ring_friction_);
    }
  }

  // where two wires touch near a polygon vertex, both capsules of each ring report the same
  // touch: keep the deepest contact of every cluster closer than half a wire radius. Redundant
  // rows only slow QuickStep down and make its forces jitter.
  void merge_duplicate_contacts(std::vector<dContactGeom>& contacts) const {
    std::stable_sort(
        contacts.begin(), contacts.end(),
        [](const dContactGeom& x, const dContactGeom& y) { return x.depth > y.depth; });
    const double radius2 = 0.25 * wire_radius_internal_ * wire_radius_internal_;
    std::size_t kept = 0;
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      bool duplicate = false;
      for (std::size_t j = 0; j < kept && !duplicate; ++j) {
        double d2 = 0.0;
        for (int axis = 0; axis < 3; ++axis) {
          const double d = contacts[k].pos[axis] - contacts[j].pos[axis];
          d2 += d * d;
        }
        duplicate = d2 < radius2;
      }
      if (!duplicate) contacts[kept++] = contacts[k];
    }
    contacts.resize(kept);
  }

  // the pieces of `ring` whose centres lie within piece_reach_ of the centre circle of `other`
  void near_pieces(int ring, int other, std::vector<dGeomID>& out) const {
    out.clear();
    const dReal* centre = dBodyGetPosition(bodies_[other]);
    const dReal* rotation = dBodyGetRotation(bodies_[other]);  // row-major 3x4
    const Vec3 axis(rotation[1], rotation[5], rotation[9]);    // local Y: the ring axis
    const Vec3 c(centre[0], centre[1], centre[2]);
    const double reach2 = piece_reach_ * piece_reach_;
    const std::size_t begin = static_cast<std::size_t>(ring) * settings_.pieces;
    for (std::size_t k = begin; k < begin + settings_.pieces; ++k) {
      const dReal* m = dGeomGetPosition(pieces_[k]);
      const Vec3 d = Vec3(m[0], m[1], m[2]) - c;
      const double height = d.dot(axis);
      const double radial = std::sqrt(std::max(0.0, d.squaredNorm() - height * height));
      const double off = radial - centre_radius_internal_;
      if (height * height + off * off <= reach2) out.push_back(pieces_[k]);
    }
  }

  // every piece of `ring` whose box meets the collider's box
  void collide_ring_with_collider(int ring, dGeomID collider) {
    dReal box[6];  // min x, max x, min y, max y, min z, max z
    dGeomGetAABB(collider, box);
    const double friction = collider_friction_[collider_of(collider)];
    const std::size_t begin = static_cast<std::size_t>(ring) * settings_.pieces;
    const double half = 0.5 * piece_pair_reach_;  // half chord + a
    for (std::size_t k = begin; k < begin + settings_.pieces; ++k) {
      const dReal* m = dGeomGetPosition(pieces_[k]);
      bool overlaps = true;
      for (int axis = 0; axis < 3; ++axis) {
        overlaps &= m[axis] + half >= box[2 * axis] && m[axis] - half <= box[2 * axis + 1];
      }
      if (overlaps) add_contacts(pieces_[k], collider, friction);
    }
  }

  void add_contacts(dGeomID first, dGeomID second, double friction) {
    dContactGeom found[kMaxContactsLimit];
    const int count = dCollide(first, second, settings_.max_contacts, found, sizeof(dContactGeom));
    for (int k = 0; k < count; ++k) {
      add_contact(found[k], dGeomGetBody(first), dGeomGetBody(second), friction);
    }
  }

  // one contact joint; `geom.normal` points from body2 into body1, as dCollide reports it
  void add_contact(const dContactGeom& geom, dBodyID body1, dBodyID body2, double friction) {
    dContact contact{};
    contact.geom = geom;
    dSurfaceParameters& surface = contact.surface;
    surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
    surface.mu = friction;
    surface.soft_erp = settings_.erp;
    surface.soft_cfm = settings_.cfm;
    if (settings_.restitution > 0.0) {
      surface.mode |= dContactBounce;
      surface.bounce = settings_.restitution;
      surface.bounce_vel = 0.0;
    }
    dJointID joint = dJointCreateContact(world_, contacts_, &contact);
    dJointAttach(joint, body1, body2);
  }

  static int ring_of(dBodyID body) {
    return static_cast<int>(reinterpret_cast<std::intptr_t>(dBodyGetData(body)));
  }
  static std::size_t collider_of(dGeomID geom) {
    return static_cast<std::size_t>(reinterpret_cast<std::intptr_t>(dGeomGetData(geom)));
  }
  bool are_neighbours(int a, int b) const {
    const auto& around = neighbours_[a];
    return std::find(around.begin(), around.end(), b) != around.end();
  }

  // fixed model
  OdeSettings settings_;
  RingGeometry ring_;
  double ring_friction_ = 0.3;
  bool self_contact_ = true;
  bool has_colliders_ = false;
  std::vector<std::array<int, 4>> neighbours_;  // (n) grid neighbours, -1 none
  std::vector<double> collider_friction_;       // (colliders) Coulomb coefficient
  double piece_reach_ = 0.0;             // internal: mid-phase reach of a piece to another ring
  double piece_pair_reach_ = 0.0;        // internal: centre distance below which pieces may touch
  double centre_radius_internal_ = 0.0;  // internal: c
  double wire_radius_internal_ = 0.0;    // internal: a

  // ODE objects (the changing state lives in the bodies)
  dWorldID world_ = nullptr;
  dSpaceID ring_space_ = nullptr;    // one bounding sphere per ring
  dSpaceID static_space_ = nullptr;  // scene colliders
  dJointGroupID contacts_ = nullptr;
  std::vector<dBodyID> bodies_;                    // (n) one per ring
  std::vector<dGeomID> pieces_;                    // (n * pieces) capsules, ring-major
  std::vector<dGeomID> near_first_, near_second_;  // mid-phase scratch
  std::vector<dContactGeom> pair_contacts_;        // contacts of one ring pair, scratch

  double damping_step_ = 0.0;   // s, solver step the world's damping factors were set for
  double time_ = 0.0;           // s
  long long solver_steps_ = 0;  // solver steps taken, seeds QuickStep's shuffle
  bool failed_ = false;         // ODE failed or a body went non-finite
  StageProfile profile_;
};

}  // namespace

BackendInfo ode_backend_info() {
  using T = KnobSpec::Type;
  const OdeSettings d;
  BackendInfo info;
  info.name = "ode";
  info.cost_us_per_ring_step = 25;
  info.bytes_per_ring = 6000;
  info.summary = "ODE 0.16 rigid bodies, each ring a torus of capsules, QuickStep contacts";
  info.knobs = {
      {"dt", T::number, d.dt, 1e-7, 1.0, "time step of one step(), s"},
      {"substeps", T::integer, double(d.substeps), 1, 10000, "fixed solver steps per step()"},
      {"iterations", T::integer, double(d.iterations), 1, 100000,
       "QuickStep SOR iterations per solver step"},
      {"sor", T::number, d.sor, 0.05, 1.95, "QuickStep over-relaxation factor"},
      {"erp", T::number, d.erp, 0.0, 1.0, "contact error reduction per solver step"},
      {"cfm", T::number, d.cfm, 0.0, 1.0,
       "contact constraint force mixing, internal units (length_scale, ring mass 1)"},
      {"restitution", T::number, d.restitution, 0.0, 1.0, "contact restitution"},
      {"linear_damping", T::number, d.linear_damping, 0.0, 1e4, "linear velocity damping, 1/s"},
      {"angular_damping", T::number, d.angular_damping, 0.0, 1e4, "angular velocity damping, 1/s"},
      {"pieces", T::integer, double(d.pieces), 6, 256, "capsules per ring"},
      {"length_scale", T::number, d.length_scale, 1e-3, 1e6, "internal length units per metre"},
      {"max_contacts", T::integer, double(d.max_contacts), 1, kMaxContactsLimit,
       "contacts kept per colliding geom pair"},
      {"max_correcting_velocity", T::number, d.max_correcting_velocity, 0.0, 1e3,
       "cap on the speed of penetration recovery, m/s (0: none)"},
      {"contact_layer", T::number, d.contact_layer, 0.0, 1.0,
       "resting penetration allowed before correction, fraction of the wire radius"},
  };
  info.create = []() -> std::unique_ptr<Backend> { return std::make_unique<OdeBackend>(); };
  return info;
}

}  // namespace chainmail
