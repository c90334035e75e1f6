// Rings as rigid tori with exact torus-torus contact, in extended position-based dynamics for
// rigid bodies (Müller et al. 2020, "Detailed Rigid Body Simulation with Extended Position Based
// Dynamics"). Every ring keeps its own position, orientation and linear and angular velocity; two
// rings touch where their centre circles come within two wire radii (circle_contact.hpp), and
// that one contact serves linked neighbours and every other pair alike: the weave's links are
// held by contact alone, like real rings.
//
// One step: candidate pairs are collected once (linked neighbours always, others through the
// spatial hash within the reach of the step's motion; links ordered outward from what holds the
// fabric up), then substeps with one constraint pass each:
//   integrate     - gravity and the gyroscopic term, positions and orientations predicted
//   colliders     - the torus's deepest point and four points of its centre circle
//   contacts      - every pair's seeds (local minima of its centre circles' distance) followed by
//                   Newton from their last angle, new minima found by a sampled scan every few
//                   substeps; a seed closer than 2a gets a positional correction with generalised
//                   inverse masses that include rotation, and static friction at the position
//                   level
//                   (then the colliders' static friction once more, after the rings' pull)
//   velocities    - from the pose change over the substep (and drag)
//   velocity pass - restitution and dynamic friction at the contacts that pushed (twice; again
//                   near colliders)
// A step takes `substeps` substeps, more when rings fly fast: two rings never close in by more
// than a wire radius between two solves. A seed remembers the side its pair lay on, so wires
// pushed into each other beyond their circles' crossing are pushed back the way they came.
//
// Threads: the rings are split once into two halves across the fabric (kParts); every phase of a
// substep solves the contacts within each half side by side, then those between the halves
// (kSeam) on one thread. The halves share no ring, so the order, and the result bit for bit, is
// the same on one thread as on two.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/circle_contact.hpp"
#include "core/frame.hpp"
#include "core/parallel.hpp"
#include "core/profile.hpp"
#include "core/scene.hpp"
#include "core/spatial_hash.hpp"
#include "core/weave.hpp"

namespace chainmail {

// the bound on a contact's friction force: Coulomb's cone (friction times the normal force in
// every direction), or the pyramid Bullet's two friction directions and ODE's dContactApprox1
// solve (that bound on each of two tangent axes: up to sqrt 2 times more on the diagonals)
enum class FrictionLaw { cone, pyramid };

struct TorusXpbdSettings {
  int substeps = 25;         // constraint passes per step
  double friction = 1.0;     // factor on the scene's Coulomb coefficients (0: frictionless)
  double restitution = 0.0;  // normal restitution of every contact
  double compliance = 0.0;   // m/N, contact compliance (0: rigid)
  double damping = 0.0;      // 1/s, linear and angular velocity drag
  bool sleeping = false;     // rings at rest are not integrated until a contact moves them
  // Gauss-Seidel passes of the velocity solve (restitution, dynamic friction) per substep, the
  // first two over every contact and the others over those near colliders: one leaves a 16 x 16
  // sheet on a table creeping off it at 3x the rigid references' rate (drape 2.8 mm from
  // Bullet's after 1 s), 8 settle it to 1.7 mm
  int velocity_iterations = 8;
  FrictionLaw friction_law = FrictionLaw::cone;
};

// the halves of the fabric that a step solves side by side (the class's kParts)
inline constexpr int kTorusXpbdParts = 2;

// fixed model: built once from the scene
struct TorusXpbdModel {
  RingGeometry ring;
  std::vector<double> inverse_mass;              // (n) 1/kg, 0 for pinned rings
  std::vector<double> inertia_diameter;          // (n) kg m^2, about a diameter
  std::vector<double> inertia_axis;              // (n) kg m^2, about the ring axis
  std::vector<double> inverse_inertia_diameter;  // (n) 1/(kg m^2), 0 for pinned rings
  std::vector<double> inverse_inertia_axis;      // (n) 1/(kg m^2), 0 for pinned rings
  std::vector<RingPair> links;                   // (m) linked neighbours, a < b, sorted
  std::vector<std::array<int, 4>> neighbours;    // (n) grid neighbours, -1 none
  std::vector<Collider> colliders;
  std::vector<double> collider_friction;  // (colliders) Coulomb coefficient times the knob
  double ring_friction = 0.0;             // ring-ring Coulomb coefficient times the knob
  Vec3 gravity = Vec3::Zero();            // m/s^2
  bool self_contact = true;
  TorusXpbdSettings settings;
  // the halves: the half of each ring (0 or 1), and the rings of each
  std::vector<char> part;                                    // (n)
  std::array<std::vector<int>, kTorusXpbdParts> part_rings;  // ring indices, ascending
  // m, how much nearer than the nearest of a scan's samples the circles may come between them:
  // the distance changes by at most the radius per radian, and half a spacing is pi / kSamples
  double scan_spacing = 0.0;
};
// mass and inertia of the solid torus scaled by any load, pins immovable, the halves split
TorusXpbdModel make_model(const Scene& scene, const Weave& weave,
                          const TorusXpbdSettings& settings);

// changing state
struct TorusXpbdState {
  double t = 0.0;                              // s
  CacheLineVector<Vec3> position;              // (n) m, ring centre
  CacheLineVector<Quat> orientation;           // (n) local ring frame -> world
  CacheLineVector<Vec3> velocity;              // (n) m/s
  CacheLineVector<Vec3> angular_velocity;      // (n) rad/s, world frame
  CacheLineVector<Vec3> previous_position;     // (n) m, at the substep's start
  CacheLineVector<Quat> previous_orientation;  // (n) at the substep's start
  std::vector<double> still_time;              // (n) s the ring has been at rest (sleeping)
  std::vector<char> asleep;                    // (n) 1: not integrated (sleeping)
};

// one local minimum of two rings' centre-circle distance, followed from substep to substep
struct PairSeed {
  double cos_t = 1.0, sin_t = 0.0;  // the second ring's angle at the last closest point
  Vec3 normal = Vec3::UnitX();      // unit, from the second ring's closest point to the first's
  double bound = 0.0;   // m, a lower bound on the distance there now (exact when just solved)
  bool recent = false;  // solved in the last substep
  // the contact it pushed in substep `pushed` (an index into that substep's active contacts): the
  // retries of the same seed in that substep add to it instead of adding contacts
  int active = -1;
  std::uint64_t pushed = 0;
};

// two rings that may touch during this step, with the minima of their distance it follows
struct alignas(kCacheLine) RingPairContact {
  int a = 0, b = 0;  // rings, a < b
  int seeds = 0;     // seeds in use
  std::array<PairSeed, 3> seed;
  // m, a lower bound on the circles' distance anywhere: the last scan's nearest sample less what
  // a sample spacing may hide, less the pair's motion since (a scan of circles farther apart
  // than its reach would find nothing, and is skipped)
  double clear = 0.0;
};

// a contact that pushed in this substep, for the velocity pass
struct ActiveContact {
  int a = 0, b = -1;            // rings; b = -1: a collider
  Vec3 normal = Vec3::UnitY();  // unit, pushes a (away from b or out of the collider)
  Vec3 arm_a, arm_b;            // m, contact point minus each ring's centre
  double lambda = 0.0;          // kg m, the normal correction's multiplier
  double w = 0.0;               // 1/kg, the generalised inverse masses along the normal
  double approach = 0.0;        // m/s, normal speed before the solve (< 0: approaching)
  double friction = 0.0;        // Coulomb coefficient
  // kg m/s, dynamic friction's impulse so far in the velocity pass (the cone's, or each of the
  // pyramid's axes): together at most friction times lambda / h
  double spent[2] = {0.0, 0.0};
};

// a collider contact that static friction held in this substep
struct ColliderHold {
  int ring = 0;
  Vec3 local_arm;         // m, the contact point in the ring's frame
  Vec3 normal;            // unit, out of the collider
  double lambda = 0.0;    // kg m, the normal multiplier
  double friction = 0.0;  // Coulomb coefficient
};

// a ring within reach of a collider during this step
struct ColliderCandidate {
  int ring = 0, collider = 0;
  double cos_s = 1.0, sin_s = 0.0;  // the last deepest point's angle on the ring's centre circle
  bool followed = false;            // that angle is from the last substep
};

// the stages of a step, as its profile names them (stage_name): collect_pairs once, then the
// others in each substep, in the order of TorusXpbdSim's substep table
enum class TorusXpbdStage : std::uint8_t {
  collect_pairs,  // candidate ring pairs and collider candidates for the whole step
  integrate,      // gravity and the gyroscopic term: positions and orientations predicted
  colliders,      // rings out of the colliders, and their static friction after the rings' pull
  contacts,       // the linked neighbours' contacts, in their order outward from the supports
  self_contact,   // the other pairs' contacts
  velocities,     // from the pose change over the substep (and drag)
  velocity_pass,  // restitution and dynamic friction at the contacts that pushed
};
const char* stage_name(TorusXpbdStage stage);

class TorusXpbdSim {
 public:
  void reset(const Scene& scene, const Weave& weave, const TorusXpbdSettings& settings);
  // threads the step may use (the halves run side by side on two; any count, same result)
  void set_threads(int threads) { threads_ = threads < 1 ? 1 : threads; }
  // one step of dt in `substeps` substeps (the step every model has: void step(double dt))
  void step(double dt);
  bool finite() const;  // whether every position, velocity and orientation is finite
  void frame(RingFrame& out) const;

  const TorusXpbdModel& model() const { return model_; }
  const TorusXpbdState& state() const { return state_; }
  TorusXpbdState& mutable_state() { return state_; }
  const StageProfile& profile() const { return profile_; }
  // the pairs of the current step and their seeds: linked neighbours, other pairs
  const std::vector<RingPairContact>& link_pairs() const { return link_pairs_; }
  const std::vector<RingPairContact>& other_pairs() const { return other_pairs_; }
  // translational + rotational kinetic energy plus gravitational potential energy, J
  double energy() const;
  // contact solves of the velocity passes in the last step (every contact in the first passes,
  // those near colliders in the later ones)
  long long velocity_solves() const {
    long long sum = 0;
    for (std::size_t part = 0; part < velocity_solves_.size(); ++part)
      sum += velocity_solves_[part];
    return sum;
  }
  // the half each ring is solved in (0 or 1)
  const std::vector<char>& ring_part() const { return model_.part; }

  // the halves, and the contacts between them
  static constexpr int kParts = kTorusXpbdParts;
  static constexpr int kSeam = kParts;

 private:
  void reset_scratch();
  int pair_part(int a, int b) const {
    return model_.part[a] == model_.part[b] ? model_.part[a] : kSeam;
  }
  // the step's phases (torus_xpbd.cpp); `part`: a half, or kSeam
  void collect_pairs(double dt);
  // substep k of this step is stamped first_stamp + k
  void run_substeps(double h, int substeps, int team, std::uint64_t first_stamp);
  // one substep on one thread of the team (torus_xpbd_step.cpp)
  struct Substep;
  // a row of the substep table: a stage's work on a half, then (null: none) its work across the
  // seam; `needed` (null: always) says whether it runs in this substep
  struct SubstepStage {
    TorusXpbdStage stage;
    void (TorusXpbdSim::*half)(Substep&, int part);
    void (TorusXpbdSim::*seam)(Substep&);
    bool (TorusXpbdSim::*needed)(const Substep&) const;
  };
  static const SubstepStage kSubstepStages[];
  void run_substep(Substep& sub);
  void run_halves(Substep& sub, std::size_t first, std::size_t last);
  bool runs(const SubstepStage& row, const Substep& sub) const;
  // the substep table's work (torus_xpbd_step.cpp)
  void start_half(Substep& sub, int part);
  void collide_half(Substep& sub, int part);
  void first_link_pass(Substep& sub, int part);
  void seam_link_passes(Substep& sub);
  void last_link_passes(Substep& sub, int part);
  void other_pairs_half(Substep& sub, int part);
  void other_pairs_seam(Substep& sub);
  void friction_half(Substep& sub, int part);
  void velocities_half(Substep& sub, int part);
  void first_velocity_pass(Substep& sub, int part);
  void velocity_passes(Substep& sub);
  bool has_colliders(const Substep& sub) const;
  bool links_left(const Substep& sub) const;
  bool has_other_pairs(const Substep& sub) const;
  void integrate(double h, int part);
  void update_velocities(double h, int part);
  void update_sleep(double dt);
  // contacts (torus_xpbd_contacts.cpp)
  // the links of one part once (over-relaxed), or those still deep once more; `retry` keeps those
  // to be solved again
  void solve_links(double h, bool scan, int part, bool first, std::uint64_t stamp);
  void solve_other_pairs(double h, bool scan, int part, std::uint64_t stamp);
  void order_links();
  void mark_near_colliders();
  // the deepest depth it corrected, m; `stamp`: the substep's (PairSeed::pushed)
  double solve_pair(RingPairContact& pair, double h, bool scan, int part, double relaxation,
                    std::uint64_t stamp);
  void find_new_minima(RingPairContact& pair, const CirclePairDistance& distance, double limit);
  void solve_colliders(double h, bool scan, int part);
  // the index in active_[part] of the contact it added to (`into`, a retry of a seed that pushed
  // in this substep) or made; -1: none (nothing can move)
  int apply_contact(int a, int b, const Vec3& normal, const Vec3& point, double depth,
                    double friction, double h, int part, double relaxation = 1.0, int into = -1);
  void merge_contacts(int part, std::size_t first, double h);
  void hold_collider_friction(double h, int part);
  // the static-friction correction (kg m, on a; b = -1: a collider) that undoes the contact point's
  // tangential `slip` (m) where that takes less than `limit` (friction times the normal
  // multiplier): along the slip (the cone) or on each tangent axis (the pyramid); `held` is set
  // when friction undid any of it
  Vec3 static_friction(int a, const Vec3& arm_a, int b, const Vec3& arm_b, const Vec3& normal,
                       const Vec3& slip, double limit, double stiffness_term, bool& held) const;
  void prepare_velocity_pass(int part);
  void velocity_sweep(double h, int part, bool all);
  // one contact: `resting` (m/s) the normal speed below which it does not bounce, inv_h 1/substep
  void velocity_solve(double resting, double inv_h, int part, int contact);
  // rigid-body helpers
  Vec3 inverse_inertia_times(int ring, const Vec3& v) const;
  // (along a direction of squared length length2: the inverse mass along its unit times length2)
  double generalized_inverse_mass(int ring, const Vec3& arm, const Vec3& direction,
                                  double length2 = 1.0) const;
  void apply_correction(int ring, const Vec3& arm, const Vec3& impulse);
  // the velocity pass's per-ring terms of one contact (the ring's pose is fixed in the pass)
  struct RingTerms {
    Vec3 lever_axis = Vec3::Zero();  // m, axis x arm: (arm x d) . axis = d . lever_axis
    double arm2 = 0.0;               // m^2, |arm|^2
  };
  struct VelocityTerms {
    RingTerms a, b;
    double inverse_w = 0.0;  // kg, 1 / the contact's inverse mass along its normal
  };
  RingTerms ring_terms(int ring, const Vec3& arm) const;
  // generalized_inverse_mass along a direction of squared length length2, times length2, from
  // the terms (a unit direction: the inverse mass itself)
  double inverse_mass_along(int ring, const Vec3& arm, const RingTerms& terms,
                            const Vec3& direction, double length2 = 1.0) const;
  void apply_impulse(int ring, const Vec3& arm, const RingTerms& terms, const Vec3& impulse);
  Vec3 point_velocity(int ring, const Vec3& arm) const;
  CircleFrame circle_of(int ring) const;  // its centre circle, from the cached rotation

  TorusXpbdModel model_;
  TorusXpbdState state_;
  SpatialHash hash_;
  StageProfile profile_;
  // per-step and per-substep scratch, kept between steps so the loops do not allocate
  std::vector<double> reach_;   // (n) m/s, bound on the speed of any point of each ring
  std::vector<double> travel_;  // (n) m, how far any point of each ring moves in this substep
  double fastest_ = 0.0;        // m/s, the largest of them
  Positions centres_;           // (3, n) m, ring centres for the spatial hash
  std::vector<RingPair> hash_pairs_;
  std::vector<RingPairContact> link_pairs_, other_pairs_, previous_pairs_;
  // links in the order they are solved: outward from what holds the fabric up (pins, and rings
  // that touched a collider in the last step), by breadth-first depth; then split by part
  std::vector<int> link_order_;
  std::array<std::vector<int>, kParts + 1> part_links_;   // indices into link_pairs_
  std::array<std::vector<int>, kParts + 1> part_others_;  // indices into other_pairs_
  std::array<std::vector<int>, kParts> part_candidates_;  // indices into collider_candidates_
  int threads_ = 1;
  std::vector<int> support_depth_;   // (n) links from the nearest support, -1 none
  std::vector<int> queue_;           // (n) breadth-first scratch
  std::vector<char> touching_;       // (n) 1: touched a collider in this step
  std::vector<char> near_collider_;  // (n) 1: within kVelocityReach links of one that did before
  PerThread<std::vector<int>, kParts + 1> retry_;  // links solved once more in this substep
  bool retrying_ = false;                          // any of them left
  bool seam_retrying_ = false;                     // any of the seam's left
  // ring-ring corrections of the first pass are over-relaxed: one Gauss-Seidel pass a substep
  // leaves a hanging sheet's contacts short by a share of the weight below them, and 1.3 takes a
  // third of that off (rigid contacts overshoot into a gap, never into each other)
  static constexpr double kOverRelaxation = 1.3;
  std::vector<ColliderCandidate> collider_candidates_, previous_candidates_;
  // contacts that pushed in this substep, by part
  PerThread<std::vector<ActiveContact>, kParts + 1> active_;
  PerThread<std::vector<VelocityTerms>, kParts + 1> velocity_terms_;  // (active contacts)
  // the active contacts near colliders (b = -1, or a ring within kVelocityReach links of one that
  // touches one): the velocity passes after the first solve only these
  PerThread<std::vector<int>, kParts + 1> near_collider_contacts_;
  PerThread<long long, kParts + 1> velocity_solves_;  // by part, in this step
  std::uint64_t substep_ = 0;  // substeps taken: their stamps count from 1 (PairSeed::pushed)
  PerThread<std::vector<ColliderHold>, kParts> collider_holds_;
  CacheLineVector<Mat3> rotation_;  // (n) each ring's orientation as a matrix, kept in step with it
  CacheLineVector<Mat3> previous_rotation_;  // (n) the same at the substep's start
};

// ---- rigid-body helpers, inline for the contact loops. The inertia of a torus is symmetric
// about its axis, so its inverse in world space is I_d^-1 + (I_a^-1 - I_d^-1) axis axis^T: no
// matrix to rotate

inline Vec3 TorusXpbdSim::inverse_inertia_times(int ring, const Vec3& v) const {
  const auto axis = rotation_[ring].col(1);
  const double across = model_.inverse_inertia_diameter[ring];
  return across * v + ((model_.inverse_inertia_axis[ring] - across) * axis.dot(v)) * axis;
}

// 1/m + (r x d) . I^-1 (r x d): the inverse mass a correction along `direction` at `arm` meets
inline double TorusXpbdSim::generalized_inverse_mass(int ring, const Vec3& arm,
                                                     const Vec3& direction, double length2) const {
  if (model_.inverse_mass[ring] == 0.0) return 0.0;
  const Vec3 lever = arm.cross(direction);
  return model_.inverse_mass[ring] * length2 + lever.dot(inverse_inertia_times(ring, lever));
}

// a positional correction (kg m) at `arm`: the centre moves by impulse / m, the orientation turns
// by I^-1 (arm x impulse)
inline void TorusXpbdSim::apply_correction(int ring, const Vec3& arm, const Vec3& impulse) {
  const double w = model_.inverse_mass[ring];
  if (w == 0.0) return;
  state_.position[ring] += w * impulse;
  const Vec3 spin = inverse_inertia_times(ring, arm.cross(impulse));
  Quat& q = state_.orientation[ring];
  const Quat turn = Quat(0.0, spin.x(), spin.y(), spin.z()) * q;
  q.coeffs() += 0.5 * turn.coeffs();
  q.coeffs() *= inverse_norm(q.squaredNorm());
  rotation_[ring] = q.toRotationMatrix();
}

inline TorusXpbdSim::RingTerms TorusXpbdSim::ring_terms(int ring, const Vec3& arm) const {
  return {Vec3(rotation_[ring].col(1)).cross(arm), arm.squaredNorm()};
}

// with lever = arm x d: |lever|^2 = |arm|^2 |d|^2 - (arm . d)^2 and lever . axis = d . (axis x
// arm), so lever . I^-1 lever = I_d^-1 |lever|^2 + (I_a^-1 - I_d^-1) (lever . axis)^2
inline double TorusXpbdSim::inverse_mass_along(int ring, const Vec3& arm, const RingTerms& terms,
                                               const Vec3& direction, double length2) const {
  const double w = model_.inverse_mass[ring];
  if (w == 0.0) return 0.0;
  const double across = model_.inverse_inertia_diameter[ring];
  const double along_arm = arm.dot(direction), along_axis = direction.dot(terms.lever_axis);
  return w * length2 + across * (terms.arm2 * length2 - along_arm * along_arm) +
         (model_.inverse_inertia_axis[ring] - across) * along_axis * along_axis;
}

// an impulse (kg m/s) at `arm`: I^-1 (arm x p) = I_d^-1 (arm x p) + (I_a^-1 - I_d^-1) (p .
// lever_axis) axis
inline void TorusXpbdSim::apply_impulse(int ring, const Vec3& arm, const RingTerms& terms,
                                        const Vec3& impulse) {
  const double w = model_.inverse_mass[ring];
  if (w == 0.0) return;
  const double across = model_.inverse_inertia_diameter[ring];
  state_.velocity[ring] += w * impulse;
  state_.angular_velocity[ring] +=
      across * arm.cross(impulse) +
      ((model_.inverse_inertia_axis[ring] - across) * impulse.dot(terms.lever_axis)) *
          rotation_[ring].col(1);
}

inline Vec3 TorusXpbdSim::point_velocity(int ring, const Vec3& arm) const {
  return state_.velocity[ring] + state_.angular_velocity[ring].cross(arm);
}

inline CircleFrame TorusXpbdSim::circle_of(int ring) const {
  const Mat3& r = rotation_[ring];
  return CircleFrame{state_.position[ring], r.col(0), r.col(2), r.col(1),
                     model_.ring.centre_radius};
}

}  // namespace chainmail
