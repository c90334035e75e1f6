// The paper's plausible chainmail model (§3-§4): a mass per ring and no springs. Neighbour rings
// are held by Provot edge constraints (at most a fraction of the inner diameter apart, at least the
// wire thickness), non-neighbours repel through a spatial hash, velocities are recomputed from the
// constrained positions, and ring orientations are derived from the neighbour vectors.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "core/damping.hpp"
#include "core/frame.hpp"
#include "core/parallel.hpp"
#include "core/plausible/colouring.hpp"
#include "core/plausible/link_distance.hpp"
#include "core/plausible/orientation.hpp"
#include "core/plausible/pin_attachments.hpp"
#include "core/plausible/pin_paths.hpp"
#include "core/plausible/plausible_rings.hpp"
#include "core/plausible/projection.hpp"
#include "core/plausible/sweep_records.hpp"
#include "core/profile.hpp"
#include "core/scene.hpp"
#include "core/spatial_hash.hpp"
#include "core/weave.hpp"

namespace chainmail {

struct PlausibleSettings {
  // constraint sweeps (edges, minimum distances, colliders in one Gauss-Seidel sweep) run until
  // the largest violation a sweep meets is below tolerance * the longest link, at most iterations;
  // where the sweeps leave a violation past newton_level (below), Newton steps on the edges and
  // colliders together (a sparse direct solve each, at most newton_steps) remove it
  int iterations = 4;
  double tolerance = 1e-3;
  int newton_steps = 30;
  // the Newton correction runs on a substep whose sweeps left a violation past this fraction of
  // the way from the longest link to a link at the inner diameter (1: only where a link would
  // pass the inner diameter; a sheet torn by an impact or a huge step); 0: wherever they left
  // more than the tolerance (with substeps = 1, the converged solve of every step)
  double newton_level = 1.0;
  // equal substeps per step, each a full predict-solve-velocity pass with iterations / substeps
  // sweeps (at least one): the same sweeps, but a stretch left by one substep is g (dt/s)^2 small
  // (Macklin et al. 2019, "Small Steps"). 0: automatic, from the sheet's state (PlausibleSim::
  // substep_count): kMinSubsteps while the sweeps converge, more while they leave the links
  // stretched toward the inner diameter, and enough that no ring moves more than
  // kMovePerSubstep inner diameters a substep (up to kMaxSubsteps)
  int substeps = 0;
  // the links' largest length from the ring geometry, for the two rings as the model turns them at
  // full extension (exact circle-circle distance); where the geometry gives none (4-in-1 at the
  // paper's swivel: turned nearly into one plane, the rings cannot link without touching), and
  // without link_geometry, the paper's effective inner diameter max_link_fraction * ID
  bool link_geometry = true;
  double max_link_fraction = 0.95;
  // 1/s: each step pulls velocities a fraction damping * dt toward the rigid motion that fits the
  // free rings best, so falling or turning as a whole is not slowed (0.5 lets a 100-row curtain
  // whip)
  double damping = 5.0;
  bool damp_rigid = false;          // damp all motion instead (a drag that also slows free fall)
  double repulsion_fraction = 0.7;  // repulsion range / inner diameter
  // non-neighbours closer than the range are pushed apart to it in the constraint sweeps (a
  // minimum distance, stable at any dt); repulsion_spring: the paper's spring that all rings emit
  // on each other instead, k (range - d), integrated explicitly with gravity
  bool repulsion_spring = false;
  double repulsion_stiffness = 10.0;  // N/m, the spring's
  // candidate repulsion pairs are gathered within range * (1 + contact_skin) and kept until some
  // ring has moved half the skin (a Verlet list); 0 rebuilds from the spatial hash every step.
  // 0.6: a falling 256 x 256 sheet rebuilds 1.9 times a step instead of 3.8 (0.3), and the
  // candidates beyond the range cost little (each is one dot product a sweep)
  double contact_skin = 0.6;
  // m, distance kept between a ring centre and a collider; 0 = the torus's own extent along the
  // collider normal, a + c sqrt(1 - (axis . n)^2), from the ring's orientation
  double contact_margin = 0.0;
  bool swivel = true;            // paper §4 swivel (4in1)
  double swivel_extended = 0.0;  // rad, swivel at full extension; 0 = the paper's a/c
  // take the swivel at full extension from the ring geometry (fitted_extended_swivel) instead
  bool swivel_fit = true;
  // before the sweeps, one pass outward from the pins that moves only the ring farther from a pin
  // (Provot's fixed-end rule; shock propagation): removes the stretch a hanging sheet accumulates
  // when Gauss-Seidel sweeps alone would need O(rows^2) iterations. Off by default: the Newton
  // steps converge without it, and its one-sided moves bias the shape (a catenary sags 5 % less)
  bool shock_propagation = false;
  // long-range attachments (core/plausible/pin_attachments): each ring no farther from its nearest
  // pins than its links to them allow, projected first in every sweep, so a hanging sheet's stretch
  // does not need O(rows^2) sweeps; a bound real rings never exceed, so it biases nothing
  bool pin_attachments = true;
  // 4-in-1: how close neighbours, rings that share two neighbours (i +- 1, j +- 1) and rings a row
  // and a half apart (i +- 2, j +- 1), (i +- 1, j +- 2) can come, from the ring geometry
  // (core/plausible/weave_limits), enforced in the sweeps; off: the paper's rule, neighbours as
  // close as the wire thickness and the sheet never compressed along both axes
  bool compression_limits = true;
  // 4-in-1 with compression_limits: rings side by side in a row, (i +- 1, j +- 1), that a step's
  // first prediction pushes past their closest approach (stacked like leaning coins) are pushed
  // apart along a way turned from the centre line toward their axes by this fraction of the axes'
  // part across it, so the row slides out of the sheet toward the faces it leans to and a sheet's
  // slack folds to the side rigid rings fold it to (slide_rows, core/plausible/neighbour_frame).
  // 0 (the default): along the centre line, and a fold has no side to take; on, the orientations
  // derived from the centres leave a few links of a fold apart (docs/backends.md)
  double row_slip = 0.0;
  // 4-in-1: each ring's swivel hinge turns toward the pins it hangs from, the direction propagated
  // from the pins through the weave (core/pin_paths; paper §6), so a sheet hung from its corners
  // leans along the diagonals; off, or without pins: the row normal (weighted by the neighbour
  // distances) everywhere
  bool swivel_from_pins = true;
};

// the pairs the sweeps hold already: linked neighbours (the edges) and, where the model bounds
// them (the diagonals), rings that share two neighbours, (i +- 1, j +- 1). The contact list's
// pair walk asks it of every pair in range, nine in ten of which are one or the other: the grid
// packed into 4 bytes a ring keeps the walk's lookups in cache (the neighbour lists and the grid
// cost a cache miss a pair at 256 x 256; tests/core keeps them as the oracle)
struct GridKeys {
  std::vector<std::uint32_t> key;  // (n) row << column_bits | column, from the grid's corner
  int column_bits = 0;
  bool diagonals = false;
  bool constrained(int a, int b) const {
    const std::uint32_t p = key[a], q = key[b], column = (std::uint32_t{1} << column_bits) - 1;
    const int rows =
        std::abs(static_cast<int>(p >> column_bits) - static_cast<int>(q >> column_bits));
    const int cols = std::abs(static_cast<int>(p & column) - static_cast<int>(q & column));
    return rows <= 1 && cols <= 1 && (rows + cols == 1 || diagonals);
  }
};

// the weave's grid packed; std::invalid_argument where a ring's neighbours are not exactly its
// grid-adjacent rings (every weave make_weave builds has them so), two rings share a cell, or the
// grid spans more cells than 32 bits number
GridKeys grid_keys(const Weave& weave, bool diagonals);

// fixed model: built once from the scene
struct PlausibleModel {
  Weave weave;  // the rings' links, neighbours, grid cells and rest layout
  RingGeometry ring;
  std::vector<double> mass;             // (n) kg
  std::vector<double> inverse_mass;     // (n) 1/kg, 0 for pinned rings
  std::vector<EdgeConstraint> edges;    // (m) neighbour links, by colour
  Colouring edge_colours;               // edges of one colour share no ring
  double longest_link = 0.0;            // m, the largest max_length: the solver's length scale
  std::vector<EdgeConstraint> outward;  // edges reachable from a pin, a = nearer the pin, by depth
  // the outward edges on the way from the pins to a ring kCarriedMassRatio times heavier than a
  // ring it hangs from: swept again after every substep's sweeps (hold_carried)
  std::vector<EdgeConstraint> carried;
  PinAttachments attachments;  // long-range attachments to the pins (pin_attachments)
  // rings that share two neighbours, and rings of adjacent rows a row and a half apart (4-in-1
  // with compression_limits), kept within their bounds
  std::vector<EdgeConstraint> diagonals;  // by colour
  Colouring diagonal_colours;
  // with row_slip: rings side by side in a row (also among the diagonals), pushed apart sliding
  // toward their faces where a step's first prediction brings them closer than their closest
  // approach (slide_rows)
  std::vector<EdgeConstraint> row_pairs;  // by first ring
  Positions rest_axes;  // (3, n) with row_slip: each ring's rest axis in its rest neighbour frame
  PinPaths pin_paths;   // 4-in-1 with swivel_from_pins: the rings breadth-first from the pins
  GridKeys grid;        // which pairs the sweeps hold (the contact list leaves them out)
  // the attachments, edges and diagonals in bands (core/plausible/plausible_bands.cpp)
  SweepBands bands;
  std::vector<Collider> colliders;
  Vec3 gravity = Vec3::Zero();  // m/s^2
  RigidFreedom rigid;           // rigid motions the pins leave the sheet (damping spares them)
  bool self_contact = true;
  double repulsion_range = 0.0;  // m
  // chains: each pair of non-neighbours as close as the convex hulls of their tori allow, up to
  // repulsion_range, pushed apart sliding toward their faces (shaped_range, slip_direction);
  // otherwise (4-in-1, whose neighbours' own bounds hold the weave) repulsion_range
  bool shaped_contacts = false;
  double extended_swivel = 0.0;  // rad, swivel at full extension (a/c, the knob, or fitted)
  PlausibleSettings settings;
};

// changing state
struct PlausibleState {
  double t = 0.0;                    // s
  Positions position;                // (3, n) m
  Positions velocity;                // (3, n) m/s
  Positions previous;                // (3, n) m, positions at the start of the step
  Positions force;                   // (3, n) N, accumulated external + repulsion
  Orientations orientation;          // (4, n) w, x, y, z
  Positions pull;                    // (3, n) m, toward the pins each ring hangs from (pin_paths)
  Positions contact_axis;            // (3, n) unit, ring axes as the colliders see them
  Positions ring_axis;               // (3, n) unit, ring axes of the last orientation (chains)
  Eigen::VectorXd contact_push;      // (n) m, collider push-out this step (0: no contact)
  Positions contact_normal;          // (3, n) unit, last collider normal this step
  Eigen::VectorXd contact_friction;  // (n) Coulomb coefficient of that collider
  // self-contact candidates: non-neighbour pairs near each other when the list was built
  std::vector<RingPair> contact_candidates;  // (k) i < j, by colour
  Colouring contact_colours;
  Positions contact_anchor;        // (3, n) m, positions when the list was built
  long long contact_rebuilds = 0;  // lists built so far
  // the last step's constraint solve: sweeps and Newton steps run, and the largest violation
  // left (the last sweep's, or the edges' and colliders' after the Newton steps)
  int sweeps = 0;
  int newton_steps = 0;
  // the step's Newton steps stalled (the constraints cannot all be met: pins farther apart than
  // the links between them reach): its later substeps keep the sweeps' result
  bool newton_stalled = false;
  int substeps = 0;        // automatic substeps: what the stretch control gives the next step
  int speed_substeps = 1;  // automatic substeps: what the rings' speed asks of the step
  // m, the edges' largest stretch the step's substeps met in their scheduled sweeps (extra sweeps
  // past iterations not counted): what the stretch control reads
  double scheduled_stretch = 0.0;
  double residual = 0.0;  // m
};

// the model's stages: a step walks kSubstepStages once a substep, then orient; the profile
// reports each by its name
enum class PlausibleStage {
  forces,        // repulsion_spring: gravity and the springs summed per ring
  integrate,     // symplectic Euler prediction (after the substep before's velocities, if waiting)
  self_contact,  // the contact list near the predicted positions
  constraints,   // the sweeps, then the Newton correction where they leave too much
  velocity,      // from the constrained motion; collider friction; damping in the last substep
  orient,        // ring orientations from the neighbour vectors
};
inline constexpr PlausibleStage kSubstepStages[] = {
    PlausibleStage::forces, PlausibleStage::integrate, PlausibleStage::self_contact,
    PlausibleStage::constraints, PlausibleStage::velocity};
constexpr const char* stage_name(PlausibleStage stage) {
  constexpr const char* kNames[] = {"forces",      "integrate", "self_contact",
                                    "constraints", "velocity",  "orient"};
  return kNames[static_cast<int>(stage)];
}

// the largest violation one sweep met, m: the long-range attachments' (a ring farther from its
// pins than its links allow: the sum of a path's stretch) apart from the links' own (edges and
// diagonals), and of those the edges' alone, which the stretch bound is about
struct SweepViolation {
  double attachments = 0.0;  // m
  double links = 0.0;        // m
  double edges = 0.0;        // m
  double worst() const { return attachments > links ? attachments : links; }
};

class PlausibleSim {
 public:
  // automatic substeps: at least kMinSubsteps, more (up to kMaxSubsteps) while the sweeps leave
  // links stretched toward the inner diameter or the rings move fast
  static constexpr int kMinSubsteps = 4;
  static constexpr int kMaxSubsteps = 64;
  static constexpr double kMovePerSubstep = 0.25;  // inner diameters
  // Newton steps stop where kNewtonPatience steps in a row have not brought the residual below
  // kNewtonProgress of the least it has reached: near a solution each step squares the error, so a
  // run that stalls there has none to find (pins farther apart than their links reach). Below
  // kNewtonStallFloor of the longest link no step counts as stalled: a chain at full extension
  // hovers there while rows are released and taken back, and converges
  static constexpr double kNewtonProgress = 0.5;
  static constexpr int kNewtonPatience = 4;
  static constexpr double kNewtonStallFloor = 0.01;
  // a ring this many times heavier than a ring it hangs from has its way to the pins swept up to
  // kCarriedPasses more times a substep (PlausibleModel::carried)
  static constexpr double kCarriedMassRatio = 4.0;
  static constexpr int kCarriedPasses = 8;
  // the links' stretch the control settles at, of the way from the longest link to a link at the
  // inner diameter
  static constexpr double kStretchTarget = 0.6;
  // rings a thread's share of a step is worth (set_threads)
  static constexpr int kRingsPerThread = 5000;

  void reset(const Scene& scene, const Weave& weave, const PlausibleSettings& settings);
  void step(double dt);
  void frame(RingFrame& out) const;
  // threads the step's data-parallel loops may run on (core/parallel.hpp: any count gives the
  // same result); 1 by default. A step takes one thread per rings_per_thread rings at most: on
  // fewer, its passes are over in microseconds and a team's hand-overs cost more than they save
  void set_threads(int threads) { requested_threads_ = threads < 1 ? 1 : threads; }
  int threads() const { return requested_threads_; }
  // kRingsPerThread by default; tests lower it to run small sheets on several threads
  void set_rings_per_thread(int rings) { rings_per_thread_ = rings < 1 ? 1 : rings; }
  int step_threads() const { return threads_; }  // the threads the last step (or reset) took
  // the banded sweeps' pairs and the per-ring passes go four at a time in lanes, AVX2 where the
  // machine has it (on by default); off takes the portable lanes anyway: a hook for tests and
  // benchmarks to compare the two builds of the kernels (the same bits)
  void set_vector_sweeps(bool on) { vector_sweeps_ = on; }
  bool vector_sweeps() const { return vector_sweeps_; }
  // one sweep of the attachments, edges and diagonals, band by band
  // (core/plausible/plausible_bands.cpp): what each constraint sweep runs before the contacts and
  // colliders. Its result is that of the colour-by-colour sweep (tests/core keeps that as the
  // oracle); the largest violation met, m
  SweepViolation sweep_links();

  const PlausibleModel& model() const { return model_; }
  const PlausibleState& state() const {
    if (orientation_stale_) orient();
    return state_;
  }
  PlausibleState& mutable_state() { return state_; }
  const StageProfile& profile() const { return profile_; }
  // largest relative over-extension of any edge, (length - max) / max, 0 when none
  double max_over_extension() const;

 private:
  // the state at rest in the weave's layout, free rings moving at initial_velocity (m/s)
  void reset_state(const Vec3& initial_velocity);
  void accumulate_forces();
  void add_repulsion_forces();
  // the contact list, rebuilt where the rings' moves since it was built (measured here, or given)
  // could have brought a pair it does not hold within range
  void refresh_contact_candidates(const RingMoves* moves = nullptr);
  RingMoves measure_moves() const;
  double max_speed_squared() const;  // (m/s)^2, of any ring
  // the substeps of the next step: the knob's, or the larger of the stretch control's and the
  // speed's count
  int substep_count() const;
  // automatic substeps: the links' stretch the step's scheduled sweeps met sets the next step's
  // count (more at once past the control level, fewer toward the target, an eighth a step), a
  // link met past the control level takes up to kExtraSweeps sweeps at once in its substep; the
  // fastest ring's move in the step sets a floor (floor_substeps_by_speed, as the step begins)
  bool controls_substeps() const { return model_.settings.substeps == 0; }
  // the way from the longest link to a link at the inner diameter, of the longest link (at least
  // 1 %); the control acts at three quarters of it and settles at kStretchTarget
  double headroom() const;
  double stretch_control_level() const { return 0.75 * headroom(); }
  void control_substeps(double dt);
  void floor_substeps_by_speed(double dt);
  // threads a step on `rings` rings takes (set_threads)
  int team_threads(int rings) const {
    return std::clamp(rings / rings_per_thread_, 1, requested_threads_);
  }
  static constexpr int kExtraSweeps = 8;
  // one substep as its stages see it
  struct Substep {
    double h = 0.0;               // s
    double damp_dt = 0.0;         // s, damping's span: the step's in its last substep, else none
    bool velocity_first = false;  // integrate: the substep before left its velocity update here
    bool velocity_waits = false;  // velocity: left to the next substep's prediction
    bool first = false;           // the step's first substep
    RingMoves moves;  // the rings' moves from the contact list's anchor, as integrate measured
  };
  void run_stage(PlausibleStage stage, Substep& substep);
  // the prediction (after the velocity update the substep before left to it, in the same pass);
  // with `moves` (and a contact list), also the rings' moves from the list's anchor, measured in
  // the same pass
  void integrate(const Substep& substep, RingMoves* moves = nullptr);
  // slide: the step's first substep, where the row pairs slide (slide_rows) before the sweeps
  void solve_positions(bool slide);
  bool solves_contacts() const;
  // Newton steps on the edges and colliders until the largest violation is below tolerance, m;
  // none where it is below trigger to begin with
  void solve_together(double tolerance, double trigger);
  double newton_trigger() const;  // m, the violation past which the Newton steps run
  // the carried edges swept again (kCarriedPasses at most), tolerance in m
  void hold_carried(double tolerance);
  // rows of the constraints violated or within `near` of their bound; the largest violation, m
  double edge_rows(double near, std::vector<ProjectionRow>& rows) const;
  double contact_rows(double near, std::vector<ProjectionRow>& rows) const;
  double collider_rows(double near, std::vector<ProjectionRow>& rows);
  // one sweep over the contact list's pairs; the largest violation met, m
  double solve_contacts();
  // the row pairs closer than their closest approach pushed apart sliding toward their faces
  // (row_slip); the largest violation met, m
  double slide_rows();
  // shaped_contacts: the minimum distance of a pair of non-neighbours apart along unit `normal`,
  // m, and the direction a violation pushes them apart in (unit)
  double shaped_range(const RingPair& pair, const Vec3& normal) const;
  Vec3 slip_direction(const RingPair& pair, const Vec3& normal) const;
  // shaped_contacts: how far a push between non-neighbours turns toward the rings' axes (a chain
  // dropped upright heaps for 0.025 to 0.2: drape 26 to 43 mm against Bullet's; at 0 it stands)
  static constexpr double kContactSlip = 0.1;
  // the attachments, edges and diagonals of a sweep in bands (core/plausible/plausible_bands.cpp);
  // the lists and colours are reordered by band within each colour (no result changes)
  void build_sweep_bands();
  // the threads' runs of bands, (members + 1) first band of each, moved a band at a time toward
  // the thread that worked less in the last sweep (the top of a hanging sheet has more to
  // correct); scheduling only: any split gives the same bits
  void balance_band_split(const std::vector<double>& busy);
  double solve_stage_band(const SweepBands::Stage& stage, int band);
  // the diagonal records and the neighbours' closest approach (core/plausible/plausible_weave.cpp),
  // m
  double build_compression_limits();
  double collide();
  // m, how far ring's centre must stay from a collider with outward normal n
  double collider_margin(int ring, const Vec3& normal) const;
  void propagate_from_pins();
  void update_velocities(double dt, double damp_dt);
  // damping once per step (it removes min(1, damping damp_dt) of the motion it damps)
  void damp(double damp_dt);
  RingArrays ring_arrays() {
    return {state_.position.data(), state_.velocity.data(), state_.previous.data(),
            state_.contact_push.data(), model_.inverse_mass.data()};
  }
  // orientations from the positions (const: they are derived, and computed on demand when no
  // collider needs them every step)
  void orient() const;

  PlausibleModel model_;
  // mutable only for the orientations orient() derives from the positions on demand
  mutable PlausibleState state_;
  mutable bool orientation_stale_ = false;
  SpatialHash hash_;
  // the contact list's pair walk, one list per part (each on cache lines of its own: the parts
  // push at once), kept from rebuild to rebuild with their memory
  struct alignas(kCacheLine) FoundPairs {
    std::vector<RingPair> pairs;
  };
  std::vector<FoundPairs> contact_found_;
  Projection projection_;  // the Newton steps' factorisation, kept between steps
  StageProfile profile_;
  int requested_threads_ = 1;
  int rings_per_thread_ = kRingsPerThread;
  int threads_ = 1;  // the step's: requested_threads_, or fewer on a small sheet (team_threads)
  std::vector<int> band_split_;    // sweep_links' runs of bands, (members + 1)
  std::vector<double> band_busy_;  // s, each run's time solving, smoothed over sweeps
  bool vector_sweeps_ = true;
};

}  // namespace chainmail
