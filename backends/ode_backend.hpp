// ODE rigid-torus backend, shared by its two sources (ode_backend.cpp: set-up, model building,
// stepping; ode_contacts.cpp: the collision pipeline). Includes ODE's headers: only the ODE
// backend's own sources include it.
//
// Every ring is a rigid body whose collision shape is a torus built from capsules along the
// chords of a regular N-gon, solved by ODE's QuickStep (projected SOR over contact constraints).
// Internal units: lengths are multiplied by the knob length_scale (internal units per metre) and
// masses are measured in ring masses, so the contact solver sees numbers near 1; time is seconds.
// Everything crossing the Backend interface is SI.
#pragma once

#include <ode/ode.h>

#include <array>
#include <stdexcept>
#include <vector>

#include "backends/backend.hpp"

namespace chainmail::ode {

// ODE reports errors through handlers that return into exit()/abort(); ours throw this instead,
// so a run that goes numerically bad ends as a failed simulation rather than a dead process
class OdeFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct OdeSettings {
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
};

constexpr int kMaxContactsLimit = 32;  // knob bound and the size of the per-pair contact buffer

class OdeBackend final : public Backend {
 public:
  OdeBackend() = default;
  ~OdeBackend() override { destroy_world(); }
  OdeBackend(const OdeBackend&) = delete;
  OdeBackend& operator=(const OdeBackend&) = delete;

  const char* name() const override { return "ode"; }
  const StageProfile& profile() const override { return profile_; }
  void reset(const Scene& scene, const Weave& weave, const Knobs& knobs) override;
  StepStatus step(double dt) override;
  void frame(RingFrame& out) const override;

 private:
  // model building (ode_backend.cpp)
  void build_world(const Scene& scene, const Weave& weave);
  static int sweep_axes(const Weave& weave);
  void build_rings(const Weave& weave, const std::vector<int>& pinned,
                   const std::vector<double>& masses, const Vec3& velocity);
  void build_colliders(const Scene& scene);
  void destroy_world();
  void check_finite();
  void set_damping(double h);

  // one solver step: contacts, then the constraint solve (ode_contacts.cpp)
  void solver_step(double h);
  static void near_callback(void* data, dGeomID first, dGeomID second);
  void collide_pair(dGeomID first, dGeomID second);
  void collide_rings(int first, int second);
  void merge_duplicate_contacts(std::vector<dContactGeom>& contacts) const;
  void near_pieces(int ring, int other, std::vector<dGeomID>& out) const;
  void collide_ring_with_collider(int ring, dGeomID collider);
  void add_contacts(dGeomID first, dGeomID second, double friction);
  void add_contact(const dContactGeom& geom, dBodyID body1, dBodyID body2, double friction);
  bool are_neighbours(int a, int b) const;

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

}  // namespace chainmail::ode
