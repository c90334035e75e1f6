#include "core/plausible/plausible.hpp"
#include "core/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/colliders.hpp"
#include "core/damping.hpp"
#include "core/plausible/constraints.hpp"

namespace chainmail {
namespace {

// per-ring values as an Eigen vector, without a copy
Eigen::Map<const Eigen::VectorXd> view(const std::vector<double>& values) {
  return {values.data(), static_cast<Eigen::Index>(values.size())};
}

// rings [0, n) in one range per thread, each but the last a multiple of 4 rings long (the vector
// passes' groups); pass(range, begin, end)
template <class Pass>
void for_ring_ranges(int n, int threads, Pass&& pass) {
  const int team = loop_threads(threads, n);
  parallel_for(0, team, team, [&](int t) {
    const int begin = static_cast<int>(static_cast<long long>(n) * t / team) & ~3;
    const int end =
        t + 1 == team ? n : static_cast<int>(static_cast<long long>(n) * (t + 1) / team) & ~3;
    pass(t, begin, end);
  });
}

// the edges reachable from a pin, directed away from it (a = nearer the pin), ordered by the
// breadth-first depth of the far ring, then by far ring: Provot's outward pass
std::vector<EdgeConstraint> outward_edges(const std::vector<EdgeConstraint>& edges,
                                          const Weave& weave,
                                          const std::vector<double>& inverse_mass) {
  const int n = weave.size();
  std::vector<EdgeConstraint> outward;
  std::vector<int> depth(n, -1), queue;
  for (int i = 0; i < n; ++i) {
    if (inverse_mass[i] == 0.0) depth[i] = 0, queue.push_back(i);
  }
  for (size_t head = 0; head < queue.size(); ++head) {
    for (int other : weave.neighbours[queue[head]]) {
      if (other >= 0 && depth[other] < 0)
        depth[other] = depth[queue[head]] + 1, queue.push_back(other);
    }
  }
  for (const EdgeConstraint& e : edges) {
    if (depth[e.a] < 0 || depth[e.b] < 0 || depth[e.a] == depth[e.b]) continue;
    EdgeConstraint directed = e;
    if (depth[e.b] < depth[e.a]) std::swap(directed.a, directed.b);
    outward.push_back(directed);
  }
  // by depth of the far ring, then by far ring, so each ring's parent edges sit together
  std::stable_sort(outward.begin(), outward.end(),
                   [&](const EdgeConstraint& x, const EdgeConstraint& y) {
                     return depth[x.b] != depth[y.b] ? depth[x.b] < depth[y.b] : x.b < y.b;
                   });
  return outward;
}

// the outward edges on the way from the pins to each ring kCarriedMassRatio times heavier than
// a ring it hangs from (outward is ordered by depth: a reverse walk reaches every ancestor)
std::vector<EdgeConstraint> carried_edges(const std::vector<EdgeConstraint>& outward,
                                          const std::vector<double>& inverse_mass) {
  std::vector<char> carried(inverse_mass.size(), 0);
  for (const EdgeConstraint& e : outward) {
    if (inverse_mass[e.b] * PlausibleSim::kCarriedMassRatio <= inverse_mass[e.a]) carried[e.b] = 1;
  }
  for (auto e = outward.rbegin(); e != outward.rend(); ++e) {
    if (carried[e->b]) carried[e->a] = 1;
  }
  std::vector<EdgeConstraint> edges;
  for (const EdgeConstraint& e : outward) {
    if (carried[e.b]) edges.push_back(e);
  }
  return edges;
}

}  // namespace

void PlausibleSim::reset(const Scene& scene, const Weave& weave,
                         const PlausibleSettings& settings) {
  band_split_.clear();  // the threads' split of the bands starts even
  band_busy_.clear();
  const int n = weave.size();
  threads_ = team_threads(n);
  const RingGeometry& ring = scene.ring;

  // fixed model
  model_ = PlausibleModel{};
  model_.weave = weave;
  model_.ring = ring;
  model_.settings = settings;
  model_.mass = ring_masses(scene, weave);
  model_.inverse_mass.resize(n);
  for (int i = 0; i < n; ++i) model_.inverse_mass[i] = 1.0 / model_.mass[i];
  for (int pinned : resolve_pins(scene, weave)) model_.inverse_mass[pinned] = 0.0;
  const double fraction_length = settings.max_link_fraction * ring.inner_diameter();
  model_.extended_swivel = settings.swivel_fit ? fitted_extended_swivel(ring, fraction_length)
                           : settings.swivel_extended > 0 ? settings.swivel_extended
                                                          : paper_extended_swivel(ring);
  // the link length from the ring geometry, aimed a tolerance short of it so that a solve
  // converged within the tolerance never stretches a link beyond it
  const double geometric =
      settings.link_geometry ? weave_max_link_distance(weave, ring, model_.extended_swivel) : 0.0;
  const double max_length =
      geometric > 0.0 ? (1.0 - settings.tolerance) * geometric : fraction_length;
  // neighbours as close as the weave's geometry lets them come (the wire thickness without it)
  const double closest = build_compression_limits();
  model_.grid = grid_keys(weave, !model_.diagonals.empty());
  // the weave's links as edge constraints, grouped by colour (core/plausible/colouring.hpp)
  for (const RingPair& link : weave.links) {
    model_.edges.push_back({link.a, link.b, closest, max_length});
  }
  model_.edge_colours = colour_pairs(model_.edges, n);
  model_.diagonal_colours = colour_pairs(model_.diagonals, n);
  model_.longest_link = max_length;
  model_.outward = outward_edges(model_.edges, weave, model_.inverse_mass);
  model_.carried = carried_edges(model_.outward, model_.inverse_mass);
  const std::vector<int> pinned = resolve_pins(scene, weave);
  if (settings.swivel_from_pins && settings.swivel && weave.type == WeaveType::four_in_one) {
    model_.pin_paths = pin_paths(weave, pinned);
  }
  if (settings.pin_attachments && !pinned.empty()) {
    // the breadth-first paths once: the swivel hinge's when it has them
    const PinPaths paths =
        model_.pin_paths.order.empty() ? pin_paths(weave, pinned) : model_.pin_paths;
    model_.attachments = pin_attachments(weave, paths, pinned, max_length);
  }
  // the threads meet at band edges, not after every colour
  build_sweep_bands();
  model_.rigid = rigid_freedom(weave.rest_position, view(model_.inverse_mass));
  model_.colliders = scene.colliders;
  model_.gravity = scene.gravity;
  model_.self_contact = scene.self_contact;
  model_.repulsion_range = settings.repulsion_fraction * ring.inner_diameter();
  // a chain has no bounds of its own between non-neighbours: their tori decide how close they come
  model_.shaped_contacts = weave.type == WeaveType::chain && !settings.repulsion_spring;

  reset_state(scene.initial_velocity);
  // a layout whose links are longer than the rings allow (a grid spaced at the inner diameter)
  // is pulled in before the first step, as a ring inside a collider is pushed out: the move makes
  // no velocity (a substep's correction would, at 1 / h of it)
  const double tolerance = settings.tolerance * model_.longest_link;  // m
  if (max_over_extension() * model_.longest_link > tolerance) {
    solve_together(tolerance, 0.0);
    state_.previous = state_.position;
    state_.contact_push.setZero();
  }
  profile_.clear();
  orient();
}

void PlausibleSim::reset_state(const Vec3& initial_velocity) {
  const int n = model_.weave.size();
  state_ = PlausibleState{};
  state_.position = model_.weave.rest_position;
  state_.previous = model_.weave.rest_position;
  state_.velocity = Positions::Zero(3, n);
  for (int i = 0; i < n; ++i) {
    if (model_.inverse_mass[i] > 0.0) state_.velocity.col(i) = initial_velocity;
  }
  state_.force = Positions::Zero(3, n);
  state_.orientation = model_.weave.rest_orientation;
  state_.contact_push = Eigen::VectorXd::Zero(n);
  state_.contact_normal = Positions::Zero(3, n);
  state_.contact_friction = Eigen::VectorXd::Zero(n);
  state_.substeps = kMinSubsteps;  // where the control runs (controls_substeps)
  state_.speed_substeps = 1;
}

void PlausibleSim::step(double dt) {
  threads_ = team_threads(static_cast<int>(state_.position.cols()));
  if (controls_substeps()) floor_substeps_by_speed(dt);
  const int substeps = substep_count();
  state_.newton_stalled = false;  // each step tries the Newton correction afresh
  // a substep's velocity update and the next one's prediction share one pass over the rings
  // where nothing comes between them: no collider friction, no forces to sum, no damping (the
  // last substep's)
  const bool fuse = model_.colliders.empty() && !model_.settings.repulsion_spring;
  state_.scheduled_stretch = 0.0;
  for (int k = 0; k < substeps; ++k) {
    const bool last = k + 1 == substeps;
    Substep substep{dt / substeps, last ? dt : 0.0, fuse && k > 0, fuse && !last, k == 0, {}};
    for (const PlausibleStage stage : kSubstepStages) run_stage(stage, substep);
  }
  Substep whole{dt, dt, false, false, false, {}};
  run_stage(PlausibleStage::orient, whole);
  state_.t += dt;
  if (controls_substeps()) control_substeps(dt);
}

void PlausibleSim::run_stage(PlausibleStage stage, Substep& substep) {
  const bool contacts = model_.self_contact && state_.position.cols() > 1;
  const bool spring = model_.settings.repulsion_spring;
  switch (stage) {
    case PlausibleStage::forces:
      // the repulsion spring between non-neighbours and gravity summed per ring (without the
      // spring, integrate adds gravity as an acceleration: one pass over the rings less)
      if (!spring) return;
      accumulate_forces();
      if (contacts) {
        auto scope = profile_.scope(stage_name(PlausibleStage::self_contact));
        refresh_contact_candidates();
        add_repulsion_forces();
      }
      return;
    case PlausibleStage::integrate:
      // symplectic Euler prediction, and the rings' moves since the contact list was built
      return integrate(substep, contacts && !spring ? &substep.moves : nullptr);
    case PlausibleStage::self_contact: {
      // candidate pairs near the predicted positions, for the minimum distance in the sweeps
      if (!contacts || spring) return;
      auto scope = profile_.scope(stage_name(stage));
      return refresh_contact_candidates(&substep.moves);
    }
    case PlausibleStage::constraints:
      // long-range attachments to the pins, Provot edge constraints, minimum distances between
      // non-neighbours and colliders, swept together (then Newton steps where they leave a link
      // past newton_level)
      solve_positions(substep.first);
      profile_.record_residual(state_.residual, model_.settings.tolerance * model_.longest_link);
      return;
    case PlausibleStage::velocity:
      // velocities from the constrained motion (paper §3), collider friction; damping once per
      // step, in the last substep (it removes min(1, damping dt) of the motion it damps)
      if (!substep.velocity_waits) update_velocities(substep.h, substep.damp_dt);
      return;
    case PlausibleStage::orient:
      // ring orientation from the neighbour vectors (paper §4), once a step: the colliders read
      // it every step (a torus reaches into a collider by its orientation); otherwise only frames
      // and a chain's contacts (solve_positions) do, and it waits
      orientation_stale_ = true;
      if (!model_.colliders.empty()) {
        auto scope = profile_.scope(stage_name(stage));
        orient();
      }
      return;
  }
}

int PlausibleSim::substep_count() const {
  if (model_.settings.substeps > 0) return model_.settings.substeps;
  return std::min(kMaxSubsteps, std::max(state_.substeps, state_.speed_substeps));
}

double PlausibleSim::headroom() const {
  return std::max(model_.ring.inner_diameter() / model_.longest_link - 1.0, 0.01);
}

void PlausibleSim::control_substeps(double dt) {
  // one sweep a substep leaves the links a stretch that falls with the square of the substeps
  // (Macklin et al. 2019) and grows with the rows a sheet hangs by. The control reads the edges'
  // largest stretch the scheduled sweeps met (not the attachments': theirs is a whole path's; not
  // the diagonals' or contacts' or colliders': theirs is compression, and the speed floor below
  // bounds how far a substep presses into them; the extra sweeps still read the diagonals).
  // Past the control level, the next step takes at least a quarter more substeps; otherwise, the
  // count that would bring the stretch to the target (kStretchTarget of the headroom), falling
  // by at most an eighth a step
  const double high = stretch_control_level();                            // of the longest link
  const double target = kStretchTarget * headroom();                      // of the longest link
  const double stretch = state_.scheduled_stretch / model_.longest_link;  // of the longest link
  const int now = state_.substeps;
  const int wanted = static_cast<int>(
      std::min<double>(kMaxSubsteps, std::ceil(now * std::sqrt(stretch / target))));
  if (stretch > high) {
    state_.substeps = std::max(wanted, now + std::max(1, now / 4));
  } else if (wanted < now) {
    state_.substeps = std::max(wanted, now - std::max(1, now / 8));
  }
  state_.substeps = std::clamp(state_.substeps, kMinSubsteps, kMaxSubsteps);
}

void PlausibleSim::floor_substeps_by_speed(double dt) {
  // the fastest ring's move over the step, gravity's gain included, in substeps of at most
  // kMovePerSubstep inner diameters: a sweep corrects a substep's move only where the move is
  // small beside the rings (a sheet hitting a ball at 10 m/s tears otherwise). Read as the step
  // begins, so the first step has it too: at rest, at dt = 0.1 s gravity alone moves a ring a
  // dozen inner diameters, and a heavy ring thrown about by four coarse substeps starts a swing
  // the step's damping no longer takes out
  const double speed = std::sqrt(max_speed_squared()) + model_.gravity.norm() * dt;  // m/s
  const double limit = kMovePerSubstep * model_.ring.inner_diameter();               // m
  state_.speed_substeps =
      static_cast<int>(std::min<double>(kMaxSubsteps, std::ceil(speed * dt / limit)));
}

void PlausibleSim::accumulate_forces() {
  auto scope = profile_.scope("forces");
  const int n = static_cast<int>(state_.position.cols());
  parallel_for(0, n, loop_threads(threads_, n),
               [&](int i) { state_.force.col(i) = model_.mass[i] * model_.gravity; });
}

void PlausibleSim::add_repulsion_forces() {
  const double range = model_.repulsion_range;
  const double k = model_.settings.repulsion_stiffness;
  for (const RingPair& pair : state_.contact_candidates) {
    const Vec3 f =
        repulsion_force(state_.position.col(pair.a), state_.position.col(pair.b), range, k);
    state_.force.col(pair.a) += f;
    state_.force.col(pair.b) -= f;
  }
}

void PlausibleSim::refresh_contact_candidates(const RingMoves* measured) {
  // a pair closer than the range now was closer than range + skin when the list was built, as
  // long as no two rings have closed in by more than the skin since: no ring has moved more than
  // half the skin, or all the rings' moves fit in a box whose diagonal is at most the skin (a
  // sheet that falls or swings as a whole closes in on nothing). Only then is a rebuild needed
  const double skin = model_.settings.contact_skin * model_.repulsion_range;
  const int n = static_cast<int>(state_.position.cols());
  if (skin > 0.0 && state_.contact_anchor.cols() == n) {
    const RingMoves moves = measured ? *measured : measure_moves();
    const Vec3 box(moves.hi[0] - moves.lo[0], moves.hi[1] - moves.lo[1],
                   moves.hi[2] - moves.lo[2]);  // m
    if (moves.farthest2 <= 0.25 * skin * skin || box.squaredNorm() <= skin * skin) return;
  }
  const double radius = model_.repulsion_range + skin;
  hash_.build(state_.position, radius, 0, threads_);
  // the pair walk in one part per thread, each into its own list, joined in order: the same list
  // for any thread count
  const int walk = hash_.pair_walk_size(state_.position);
  const int parts = loop_threads(threads_, walk, 4096);
  if (static_cast<int>(contact_found_.size()) < parts) contact_found_.resize(parts);
  parallel_for(0, parts, parts, [&](int part) {
    std::vector<RingPair>& found = contact_found_[part].pairs;
    found.clear();
    const int begin = static_cast<int>(static_cast<long long>(walk) * part / parts);
    const int end = static_cast<int>(static_cast<long long>(walk) * (part + 1) / parts);
    hash_.for_each_pair_in(state_.position, radius, begin, end, [&](int i, int j) {
      if (!model_.grid.constrained(i, j)) found.push_back({i, j});
    });
  });
  state_.contact_candidates.clear();
  for (int part = 0; part < parts; ++part) {
    const std::vector<RingPair>& found = contact_found_[part].pairs;
    state_.contact_candidates.insert(state_.contact_candidates.end(), found.begin(), found.end());
  }
  state_.contact_colours = colour_pairs(state_.contact_candidates, n);
  state_.contact_anchor = state_.position;
  ++state_.contact_rebuilds;
}

RingMoves PlausibleSim::measure_moves() const {
  const int n = static_cast<int>(state_.position.cols());
  std::vector<RingMoves> part(loop_threads(threads_, n));
  for_ring_ranges(n, threads_, [&](int range, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const Vec3 move = state_.position.col(i) - state_.contact_anchor.col(i);
      part[range].add(move.x(), move.y(), move.z());
    }
  });
  RingMoves moves;
  for (const RingMoves& p : part) moves.join(p);
  return moves;
}

double PlausibleSim::max_speed_squared() const {
  const int n = static_cast<int>(state_.velocity.cols());
  std::vector<double> part(loop_threads(threads_, n), 0.0);
  for_ring_ranges(n, threads_, [&](int range, int begin, int end) {
    double fastest = 0.0;
    for (int i = begin; i < end; ++i)
      fastest = std::max(fastest, state_.velocity.col(i).squaredNorm());
    part[range] = fastest;
  });
  return *std::max_element(part.begin(), part.end());
}

void PlausibleSim::integrate(const Substep& substep, RingMoves* moves) {
  auto scope = profile_.scope(stage_name(PlausibleStage::integrate));
  const double dt = substep.h;  // s
  const int n = static_cast<int>(state_.position.cols());
  // a ring that starts the step inside a collider's margin (a scene placed it there, or its torus
  // turned to reach farther) moves out before the step, so the move makes no velocity
  if (!model_.colliders.empty()) collide();
  const bool forces = model_.settings.repulsion_spring;  // else gravity alone (substep)
  const Vec3 fall = dt * model_.gravity;                 // m/s
  if (!forces) {
    // with a contact list, the moves from its anchor, range by range, joined after (min and max
    // do not depend on the order)
    const double* anchor =
        moves && state_.contact_anchor.cols() == n ? state_.contact_anchor.data() : nullptr;
    // (with the last substep's velocities first, where they waited: substeps of one step share h)
    const bool velocities_first = substep.velocity_first;
    std::vector<RingMoves> part(loop_threads(threads_, n));
    for_ring_ranges(n, threads_, [&](int range, int begin, int end) {
      part[range] = velocities_first ? update_velocities_and_predict(ring_arrays(), fall, dt, begin,
                                                                     end, vector_sweeps_, anchor)
                                     : predict_rings(ring_arrays(), fall, dt, begin, end,
                                                     vector_sweeps_, anchor);
    });
    if (anchor) {
      *moves = RingMoves{};
      for (const RingMoves& p : part) moves->join(p);
    }
    return;
  }
  parallel_for(0, n, loop_threads(threads_, n), [&](int i) {
    state_.previous.col(i) = state_.position.col(i);
    state_.contact_push[i] = 0.0;
    const double w = model_.inverse_mass[i];
    if (w == 0.0) return;  // pinned
    state_.velocity.col(i) += forces ? Vec3(dt * w * state_.force.col(i)) : fall;
    state_.position.col(i) += dt * state_.velocity.col(i);
  });
}

void PlausibleSim::update_velocities(double dt, double damp_dt) {
  auto scope = profile_.scope(stage_name(PlausibleStage::velocity));
  const int n = static_cast<int>(state_.position.cols());
  for_ring_ranges(n, threads_, [&](int, int begin, int end) {
    update_ring_velocities(ring_arrays(), dt, begin, end, vector_sweeps_);
  });
  // Coulomb friction on the rings a collider pushed this step (only colliders push): the
  // tangential velocity loses at most mu times the normal velocity change
  if (model_.colliders.empty()) return damp(damp_dt);
  parallel_for(0, n, loop_threads(threads_, n), [&](int i) {
    if (model_.inverse_mass[i] == 0.0 || state_.contact_push[i] <= 0.0) return;
    Vec3 v = state_.velocity.col(i);
    const Vec3 normal = state_.contact_normal.col(i);
    const Vec3 tangential = v - v.dot(normal) * normal;
    const double speed = tangential.norm();
    const double limit = state_.contact_friction[i] * state_.contact_push[i] / dt;
    if (speed > 0.0) v -= tangential * std::min(1.0, limit / speed);
    state_.velocity.col(i) = v;
  });
  damp(damp_dt);
}

void PlausibleSim::damp(double damp_dt) {
  if (damp_dt <= 0.0) return;
  const double fraction = std::min(1.0, model_.settings.damping * damp_dt);
  if (model_.settings.damp_rigid) {
    state_.velocity *= 1.0 - fraction;
  } else {
    damp_toward_rigid(model_.rigid, state_.position, view(model_.mass), view(model_.inverse_mass),
                      fraction, state_.velocity, threads_);
  }
}

void PlausibleSim::orient() const {
  orientation_stale_ = false;
  OrientationSettings settings;
  settings.max_link_distance = model_.settings.max_link_fraction * model_.ring.inner_diameter();
  settings.swivel = model_.settings.swivel;
  settings.extended_angle = model_.extended_swivel;
  if (!model_.pin_paths.order.empty()) {
    pull_toward_pins(model_.pin_paths, state_.position, state_.pull);
    settings.pull = &state_.pull;
  }
  settings.threads = threads_;
  orient_rings(state_.position, model_.weave, model_.ring, settings, state_.orientation);
  // the ring axes the colliders see follow the orientations a fraction per step: a torus's reach
  // into a collider moves its centre, which turns its neighbours; followed at once, rings on a
  // floor lift and turn each other without end
  const Orientations& o = state_.orientation;
  const int n = static_cast<int>(o.cols());
  // a sheet at rest on a floor settles for 0.1 to 0.25; from 0.3 (0.5 with the paper's swivel
  // and rule, which settle only after a burst) the loop grows from round-off into bursts of motion
  constexpr double follow = 0.2;
  const bool first = state_.contact_axis.cols() != n;
  if (first) state_.contact_axis.resize(3, n);
  const bool shaped = model_.shaped_contacts;
  if (shaped) state_.ring_axis.resize(3, n);
  parallel_for(0, n, loop_threads(threads_, n), [&](int i) {
    const Vec3 axis = Quat(o(0, i), o(1, i), o(2, i), o(3, i)) * Vec3::UnitY();
    if (shaped) state_.ring_axis.col(i) = axis;
    const Vec3 old = state_.contact_axis.col(i);
    // the axis's sign is arbitrary: follow it from the side the old one is on
    const Vec3 target = !first && axis.dot(old) < 0.0 ? Vec3(-axis) : axis;
    state_.contact_axis.col(i) =
        first ? target : Vec3((old + follow * (target - old)).normalized());
  });
}

void PlausibleSim::frame(RingFrame& out) const {
  if (orientation_stale_) orient();
  out.t = state_.t;
  out.position = state_.position;
  out.orientation = state_.orientation;
  // a chain's quarter turns from the centres alone leave a folded link apart: turned to link
  const bool chain = model_.weave.type == WeaveType::chain;
  if ((model_.settings.swivel && model_.weave.type == WeaveType::four_in_one) || chain) {
    keep_links(state_.position, model_.weave, model_.ring, out.orientation);
  }
  out.velocity = state_.velocity;
}

}  // namespace chainmail
