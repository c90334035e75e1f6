// The paper's plausible chainmail model (§3-§4): a mass per ring and no springs. Neighbour rings
// are held by Provot edge constraints (at most a fraction of the inner diameter apart, at least the
// wire thickness), non-neighbours repel through a spatial hash, velocities are recomputed from the
// constrained positions, and ring orientations are derived from the neighbour vectors.
#pragma once

#include <array>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "core/colouring.hpp"
#include "core/damping.hpp"
#include "core/frame.hpp"
#include "core/link_length.hpp"
#include "core/orientation.hpp"
#include "core/pin_attachments.hpp"
#include "core/pin_paths.hpp"
#include "core/plausible_rings.hpp"
#include "core/profile.hpp"
#include "core/projection.hpp"
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
  // long-range attachments (core/pin_attachments): each ring no farther from its nearest pins
  // than its links to them allow, projected first in every sweep, so a hanging sheet's stretch
  // does not need O(rows^2) sweeps; a bound real rings never exceed, so it biases nothing
  bool pin_attachments = true;
  // 4-in-1: how close neighbours, rings that share two neighbours (i +- 1, j +- 1) and rings a row
  // and a half apart (i +- 2, j +- 1), (i +- 1, j +- 2) can come, from the ring geometry
  // (core/weave_limits), enforced in the sweeps; off: the paper's rule, neighbours as close as the
  // wire thickness and the sheet never compressed along both axes
  bool compression_limits = true;
  // 4-in-1: each ring's swivel hinge turns toward the pins it hangs from, the direction propagated
  // from the pins through the weave (core/pin_paths; paper §6), so a sheet hung from its corners
  // leans along the diagonals; off, or without pins: the row normal (weighted by the neighbour
  // distances) everywhere
  bool swivel_from_pins = true;
};

// one Provot edge: a plain record, solved by solve_edge_constraint
struct EdgeConstraint {
  int a, b;
  double min_length;  // m
  double max_length;  // m
};

// four pairs of a stage solved together in SIMD lanes (core/plausible_blocks), or one alone
struct PairBlock {
  enum class Kind : int {
    single,    // pairs[pair] alone (scalar)
    run,       // (a + i, b + i), i = 0..3, the two runs of rings apart
    adjacent,  // (a + 2 i, a + 2 i + 1), i = 0..3: rings a .. a + 7
  };
  int a = 0, b = 0;  // the first pair's rings
  Kind kind = Kind::single;
  int pair = 0;  // the first pair's index in the stage's list
  // run or adjacent with shared bounds: groups of four, each continuing the last (its rings 4,
  // or for adjacent sets 8, further on, its pairs the next four), solved one after the other
  // without reading another block (a regular weave's colours run along whole rows)
  int groups = 1;
  // m, the four pairs' bounds where they share them (else read from the pairs)
  bool shared_bounds = true;
  double min_length = 0.0, max_length = 0.0;
  int pairs() const { return kind == Kind::single ? 1 : 4 * groups; }
};

// a long-range attachment of a sweep's list alone, or groups of four attachments of consecutive
// rings solved together in SIMD lanes (core/plausible_blocks)
struct AttachmentBlock {
  int item = 0;  // the first attachment's index in its list
  // groups of four consecutive rings, each continuing the last (its rings 4 further on, its
  // attachments the next four); 0: the item alone
  int groups = 0;
  // each group's four pins are consecutive rings too, each group's 4 on from the last's (rings
  // along a pinned edge hang from the pins along it)
  bool pin_run = false;
  int items() const { return groups == 0 ? 1 : 4 * groups; }
};

// the sweep's attachments, edges and diagonals as stages (an attachment list, a colour) cut into
// bands of consecutive rings (core/plausible_bands.cpp), each band at least as wide as the
// farthest any pair reaches (|a - b|): a pair joins its lower ring's band to itself or the next.
// Each thread takes a run of bands through the stages in order and waits only where a
// neighbouring band of another thread has not finished the stage before; the result is that of
// the coloured sweep, stage after stage over the whole sheet
struct SweepBands {
  enum class Kind { attachments, edges, diagonals };
  struct Stage {
    Kind kind = Kind::edges;
    int list = 0;                 // attachments: which list
    std::vector<int> band_start;  // (bands + 1) the stage's items of each band, into its list
    // edges and diagonals: the stage's pairs as blocks, band by band
    std::vector<PairBlock> blocks;
    std::vector<int> block_start;  // (bands + 1) each band's blocks, into (attachment_)blocks
    // attachments: the list's items as blocks, band by band, and their max_distance in the
    // list's order (m: four load as one vector)
    std::vector<AttachmentBlock> attachment_blocks;
    std::vector<double> reach;
  };
  std::vector<int> first_ring;  // (bands + 1)
  std::vector<Stage> stages;    // in the sweep's order
  int bands() const { return static_cast<int>(first_ring.size()) - 1; }
};

// fixed model: built once from the scene
struct PlausibleModel {
  RingGeometry ring;
  std::vector<double> mass;             // (n) kg
  std::vector<double> inverse_mass;     // (n) 1/kg, 0 for pinned rings
  std::vector<EdgeConstraint> edges;    // (m) neighbour links, by colour
  Colouring edge_colours;               // edges of one colour share no ring
  double longest_link = 0.0;            // m, the largest max_length: the solver's length scale
  std::vector<EdgeConstraint> outward;  // edges reachable from a pin, a = nearer the pin, by depth
  PinAttachments attachments;           // long-range attachments to the pins (pin_attachments)
  // rings that share two neighbours, and rings of adjacent rows a row and a half apart (4-in-1
  // with compression_limits), kept within their bounds
  std::vector<EdgeConstraint> diagonals;  // by colour
  Colouring diagonal_colours;
  PinPaths pin_paths;  // 4-in-1 with swivel_from_pins: the rings breadth-first from the pins
  // the attachments, edges and diagonals in bands (core/plausible_bands.cpp)
  SweepBands bands;
  std::vector<Collider> colliders;
  Vec3 gravity = Vec3::Zero();  // m/s^2
  RigidFreedom rigid;           // rigid motions the pins leave the sheet (damping spares them)
  bool self_contact = true;
  double repulsion_range = 0.0;  // m
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
  int substeps = 0;        // automatic substeps: what the stretch control gives the next step
  int speed_substeps = 1;  // automatic substeps: what the rings' speed asks of the next step
  // m, the largest violation the step's substeps met in their last scheduled sweep (extra sweeps
  // past iterations not counted): what the stretch control reads
  double scheduled_residual = 0.0;
  double residual = 0.0;  // m
};

class PlausibleSim {
 public:
  // automatic substeps: at least kMinSubsteps, more (up to kMaxSubsteps) while the sweeps leave
  // links stretched toward the inner diameter or the rings move fast
  static constexpr int kMinSubsteps = 4;
  static constexpr int kMaxSubsteps = 64;
  static constexpr double kMovePerSubstep = 0.25;  // inner diameters

  void reset(const Scene& scene, const Weave& weave, const PlausibleSettings& settings);
  void step(double dt);
  void frame(RingFrame& out) const;
  // threads the step's data-parallel loops run on (core/parallel.hpp: any count gives the same
  // result); 1 by default
  void set_threads(int threads) { threads_ = threads < 1 ? 1 : threads; }
  int threads() const { return threads_; }
  // the banded sweeps' pairs and the per-ring passes go four at a time in lanes, AVX2 where the
  // machine has it (on by default); off takes the portable lanes anyway: a hook for tests and
  // benchmarks to compare the two builds of the kernels (the same bits)
  void set_vector_sweeps(bool on) { vector_sweeps_ = on; }
  bool vector_sweeps() const { return vector_sweeps_; }
  // one sweep of the attachments, edges and diagonals, band by band (core/plausible_bands.cpp):
  // what each constraint sweep runs before the contacts and colliders. Its result is that of the
  // colour-by-colour sweep (tests/core keeps that as the oracle); the largest violation met, m
  double sweep_links();

  // whether the contact list's pair walk reads the weave's grid packed (see constrained_pair)
  bool packed_grid() const { return !grid_key_.empty(); }
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
  // automatic substeps: the last sweep's largest violation above the control level (of the
  // longest link) adds substeps for the next step, and up to kExtraSweeps sweeps at once to the
  // substep that met it; the fastest ring's move in the next step sets a floor
  bool controls_substeps() const { return model_.settings.substeps == 0; }
  // the way from the longest link to a link at the inner diameter, of the longest link (at least
  // 1 %); the control acts at three quarters of it
  double headroom() const;
  double stretch_control_level() const { return 0.75 * headroom(); }
  void control_substeps(double dt);
  static constexpr int kExtraSweeps = 8;
  // one predict-solve-update pass of h seconds; damps as for damp_dt seconds (0: not at all).
  // another_follows: a substep of the same h comes next in this step (the velocity update may
  // then wait for its prediction, to go in one pass with it)
  void substep(double h, double damp_dt, bool another_follows);
  // the prediction (after the velocity update the substep before left pending, in the same pass);
  // with `moves` (and a contact list), also the rings' moves from the list's anchor, measured in
  // the same pass
  void integrate(double dt, RingMoves* moves = nullptr);
  void solve_positions();
  bool solves_contacts() const;
  // Newton steps on the edges and colliders until the largest violation is below tolerance, m;
  // none where it is below trigger to begin with
  void solve_together(double tolerance, double trigger);
  double newton_trigger() const;  // m, the violation past which the Newton steps run
  // rows of the constraints violated or within `near` of their bound; the largest violation, m
  double edge_rows(double near, std::vector<ProjectionRow>& rows) const;
  double contact_rows(double near, std::vector<ProjectionRow>& rows) const;
  double collider_rows(double near, std::vector<ProjectionRow>& rows);
  // one sweep over the contact list's pairs; the largest violation met, m
  double solve_contacts();
  // the attachments, edges and diagonals of a sweep in bands (core/plausible_bands.cpp); the
  // lists and colours are reordered by band within each colour (no result changes)
  void build_sweep_bands();
  // the threads' runs of bands, (members + 1) first band of each, moved a band at a time toward
  // the thread that worked less in the last sweep (the top of a hanging sheet has more to
  // correct); scheduling only: any split gives the same bits
  void balance_band_split(const std::vector<double>& busy);
  double solve_stage_band(const SweepBands::Stage& stage, int band);
  // the diagonal records and the neighbours' closest approach (core/plausible_weave.cpp), m
  double build_compression_limits();
  // the weave's grid packed ring by ring, row << 16 | column, where the neighbour lists are
  // exactly each ring's grid-adjacent rings and every coordinate fits 16 bits (else left empty)
  void build_grid_keys();
  // pairs the sweeps hold already: linked neighbours (the edges) and rings that share two
  // neighbours, (i +- 1, j +- 1), where the model bounds them (the diagonals). Inline: the contact
  // list's pair walk asks it of every pair in range, nine in ten of which are one or the other;
  // from the packed grid where there is one (4 bytes a ring: the walk's lookups stay in cache;
  // the neighbour lists and the grid cost a cache miss a pair at 256 x 256)
  bool constrained_pair(int a, int b) const {
    if (!grid_key_.empty()) {
      const std::uint32_t p = grid_key_[a], q = grid_key_[b];
      const int rows = std::abs(static_cast<int>(p >> 16) - static_cast<int>(q >> 16));
      const int cols = std::abs(static_cast<int>(p & 0xffff) - static_cast<int>(q & 0xffff));
      return rows <= 1 && cols <= 1 && (rows + cols == 1 || !model_.diagonals.empty());
    }
    const std::array<int, 4>& nb = weave_.neighbours[a];
    if (nb[0] == b || nb[1] == b || nb[2] == b || nb[3] == b) return true;
    if (model_.diagonals.empty()) return false;
    const std::array<int, 2>& first = weave_.grid[a];
    const std::array<int, 2>& second = weave_.grid[b];
    return std::abs(first[0] - second[0]) == 1 && std::abs(first[1] - second[1]) == 1;
  }
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

  Weave weave_;
  PlausibleModel model_;
  // mutable only for the orientations orient() derives from the positions on demand
  mutable PlausibleState state_;
  mutable bool orientation_stale_ = false;
  // the last substep's velocity update waits for the next prediction (integrate does both)
  bool velocities_pending_ = false;
  SpatialHash hash_;
  std::vector<std::uint32_t> grid_key_;  // (n) row << 16 | column (build_grid_keys), or empty
  // the contact list's pair walk, one list per part (each on cache lines of its own: the parts
  // push at once), kept from rebuild to rebuild with their memory
  struct alignas(64) FoundPairs {
    std::vector<RingPair> pairs;
  };
  std::vector<FoundPairs> contact_found_;
  Projection projection_;  // the Newton steps' factorisation, kept between steps
  StageProfile profile_;
  int threads_ = 1;
  std::vector<int> band_split_;    // sweep_links' runs of bands, (members + 1)
  std::vector<double> band_busy_;  // s, each run's time solving, smoothed over sweeps
  bool vector_sweeps_ = true;
};

}  // namespace chainmail
