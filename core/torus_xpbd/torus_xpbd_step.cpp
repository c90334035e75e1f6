// The rigid-torus XPBD model's step: its substeps, each phase solving the two halves side by side
// and then the seam between them (torus_xpbd.hpp), and the link passes of the contact phase.
#include <algorithm>
#include <cmath>
#include <iterator>

#include "core/parallel.hpp"
#include "core/torus_xpbd/torus_xpbd.hpp"

#if defined(CHAINMAIL_HAS_OPENMP)
#include <omp.h>
#endif

namespace chainmail {
namespace {

// substeps between scans of a pair for new minima (the seeds are followed in every substep)
constexpr int kScanInterval = 4;
// the most substeps a fast step may take
constexpr int kMaxSubsteps = 2000;
// fewer rings than this step on one thread: the halves' hand-overs would cost more than they save
constexpr int kThreadedRings = 64;
// a link that pushed deeper than this (in wire radii) in a substep is solved again, up to this many
// more passes
constexpr double kRetryDepth = 0.003;
constexpr int kRetryPasses = 4;
// the velocity passes over every contact (the later ones solve those near colliders): one leaves
// each contact the speed the later ones gave it, which in fabric hanging free lets a swinging
// sheet's links sink deeper (corner_hang, t >= 0.5 s: deepest linked pair 0.018a on average,
// 0.035a at most, against 0.015a and 0.025a with two) and a chain's jerk push them far deeper
// (the catenary's release: 0.081a against 0.021a)
constexpr int kEveryContactPasses = 2;

// this thread's number in its team (0 outside one), and the team's size
int team_thread() {
#if defined(CHAINMAIL_HAS_OPENMP)
  return omp_get_thread_num();
#else
  return 0;
#endif
}
int team_size() {
#if defined(CHAINMAIL_HAS_OPENMP)
  return omp_get_num_threads();
#else
  return 1;
#endif
}

// every thread of the team waits here for the others (nothing on one thread)
void team_barrier(int team) {
  if (team > 1) {
#pragma omp barrier
  }
}

}  // namespace

const char* stage_name(TorusXpbdStage stage) {
  switch (stage) {
    case TorusXpbdStage::collect_pairs:
      return "collect_pairs";
    case TorusXpbdStage::integrate:
      return "integrate";
    case TorusXpbdStage::colliders:
      return "colliders";
    case TorusXpbdStage::contacts:
      return "contacts";
    case TorusXpbdStage::self_contact:
      return "self_contact";
    case TorusXpbdStage::velocities:
      return "velocities";
    case TorusXpbdStage::velocity_pass:
      return "velocity_pass";
  }
  return "?";
}

// collect_pairs, then the substeps (each a walk over kSubstepStages), then sleep
void TorusXpbdSim::step(double dt) {
  for (std::size_t part = 0; part < velocity_solves_.size(); ++part) velocity_solves_[part] = 0;
  collect_pairs(dt);
  // enough substeps that two rings close in by at most a wire radius in one: wires cannot pass
  // through each other between two contact solves, however fast the rings fly
  const double travel = 2.0 * fastest_ * dt / model_.ring.wire_radius;
  const int substeps =
      std::max(model_.settings.substeps,
               static_cast<int>(std::min(std::ceil(travel), double{kMaxSubsteps})));
  const double h = dt / substeps;
  const int team =
      parallel_loops_available() && static_cast<int>(model_.part.size()) >= kThreadedRings
          ? std::min(threads_, kParts)
          : 1;
  // substeps are stamped from 1 (a seed's `pushed` starts at 0)
  const std::uint64_t first_stamp = substep_ + 1;
  substep_ += static_cast<std::uint64_t>(substeps);
#pragma omp parallel num_threads(team) if (team > 1)
  run_substeps(h, substeps, team > 1 ? team_size() : 1, first_stamp);  // OpenMP may give fewer
  if (model_.settings.sleeping) update_sleep(dt);
  state_.t += dt;
}

// one substep as one thread of the team sees it. Every thread meets every barrier: the loops' trip
// counts, and whether a stage runs, come from state the phase before left
struct TorusXpbdSim::Substep {
  double h = 0.0;  // s
  bool scan = false;
  std::uint64_t stamp = 0;
  int team = 1, thread = 0;
  bool lead = true;     // keeps the profile, solves the seam
  int link_passes = 0;  // the retry passes seam_link_passes took

  // `solve` on each half (both on one thread, one each on two), then the barrier
  template <class Solve>
  void each_half(const Solve& solve) const {
    for (int part = 0; part < kParts; ++part)
      if (team == 1 || part == thread) solve(part);
    team_barrier(team);
  }
  // `solve` on the contacts between the halves, on the lead, then the barrier
  template <class Solve>
  void seam(const Solve& solve) const {
    if (lead) solve(kSeam);
    team_barrier(team);
  }
};

// a substep's stages in order. Each half integrated, then its colliders (the rings' own contacts
// then see where the colliders put them), then its links in their order; the seam's links, and
// the retries of those that pushed deep or hold a ring against a collider (one Gauss-Seidel pass
// leaves a link carrying much of a sheet's weight short by a share of it); the other pairs; the
// colliders' static friction once more, after the rings' pull; velocities; the velocity passes
const TorusXpbdSim::SubstepStage TorusXpbdSim::kSubstepStages[] = {
    {TorusXpbdStage::integrate, &TorusXpbdSim::start_half, nullptr, nullptr},
    {TorusXpbdStage::colliders, &TorusXpbdSim::collide_half, nullptr, &TorusXpbdSim::has_colliders},
    {TorusXpbdStage::contacts, &TorusXpbdSim::first_link_pass, &TorusXpbdSim::seam_link_passes,
     nullptr},
    {TorusXpbdStage::contacts, &TorusXpbdSim::last_link_passes, nullptr, &TorusXpbdSim::links_left},
    {TorusXpbdStage::self_contact, &TorusXpbdSim::other_pairs_half, &TorusXpbdSim::other_pairs_seam,
     &TorusXpbdSim::has_other_pairs},
    {TorusXpbdStage::colliders, &TorusXpbdSim::friction_half, nullptr,
     &TorusXpbdSim::has_colliders},
    {TorusXpbdStage::velocities, &TorusXpbdSim::velocities_half, nullptr, nullptr},
    {TorusXpbdStage::velocity_pass, &TorusXpbdSim::first_velocity_pass,
     &TorusXpbdSim::velocity_passes, nullptr},
};

void TorusXpbdSim::run_substeps(double h, int substeps, int team, std::uint64_t first_stamp) {
  Substep sub;
  sub.h = h;
  sub.team = team;
  sub.thread = team > 1 ? team_thread() : 0;
  sub.lead = sub.thread == 0;
  for (int k = 0; k < substeps; ++k) {
    sub.scan = k % kScanInterval == 0;
    sub.stamp = first_stamp + static_cast<std::uint64_t>(k);
    run_substep(sub);
  }
}

// the table walked: stages with no work across the seam run back to back within each half with no
// barrier between (each touches only its half's rings, which the half's stages before moved: the
// order, and the result, are those of one barrier after each), up to one that has such work,
// which follows the halves' barrier
void TorusXpbdSim::run_substep(Substep& sub) {
  constexpr std::size_t count = std::size(kSubstepStages);
  std::size_t first = 0;
  for (std::size_t last = 0; last < count; ++last) {
    const SubstepStage& row = kSubstepStages[last];
    if (!row.seam && last + 1 < count) continue;
    run_halves(sub, first, last + 1);
    if (row.seam && runs(row, sub)) {
      auto scope = profile_.scope_if(sub.lead, stage_name(row.stage));
      (this->*row.seam)(sub);
    }
    first = last + 1;
  }
}

// the half work of stages [first, last), where any of them runs
void TorusXpbdSim::run_halves(Substep& sub, std::size_t first, std::size_t last) {
  bool any = false;
  for (std::size_t k = first; k < last && !any; ++k) any = runs(kSubstepStages[k], sub);
  if (!any) return;
  sub.each_half([&](int part) {
    for (std::size_t k = first; k < last; ++k) {
      const SubstepStage& row = kSubstepStages[k];
      if (!runs(row, sub)) continue;
      auto scope = profile_.scope_if(sub.lead, stage_name(row.stage));
      (this->*row.half)(sub, part);
    }
  });
}

bool TorusXpbdSim::runs(const SubstepStage& row, const Substep& sub) const {
  return !row.needed || (this->*row.needed)(sub);
}

bool TorusXpbdSim::has_colliders(const Substep&) const {
  return !collider_candidates_.empty();
}
bool TorusXpbdSim::links_left(const Substep& sub) const {
  return sub.link_passes < kRetryPasses && retrying_;
}
bool TorusXpbdSim::has_other_pairs(const Substep&) const {
  return !other_pairs_.empty();
}

void TorusXpbdSim::start_half(Substep& sub, int part) {
  if (part == 0) active_[kSeam].clear();  // the lead's: the seam's solve comes after
  active_[part].clear();
  collider_holds_[part].clear();
  integrate(sub.h, part);
}

void TorusXpbdSim::collide_half(Substep& sub, int part) {
  solve_colliders(sub.h, sub.scan, part);
}

void TorusXpbdSim::first_link_pass(Substep& sub, int part) {
  solve_links(sub.h, sub.scan, part, true, sub.stamp);
}

// the seam's links, then the retry passes, each half's and then the seam's, while the seam has
// links to retry (whether any link is left is the lead's to say, in the seam's phase: the halves'
// lists change again once both threads have read it)
void TorusXpbdSim::seam_link_passes(Substep& sub) {
  const auto seam_links = [&](bool first) {
    sub.seam([&](int part) {
      solve_links(sub.h, sub.scan, part, first, sub.stamp);
      seam_retrying_ = !retry_[kSeam].empty();
      retrying_ = seam_retrying_ || !(retry_[0].empty() && retry_[1].empty());
    });
  };
  seam_links(true);
  int pass = 0;
  for (; pass < kRetryPasses && seam_retrying_; ++pass) {
    sub.each_half([&](int part) { solve_links(sub.h, sub.scan, part, false, sub.stamp); });
    seam_links(false);
  }
  sub.link_passes = pass;
}

// each half's remaining retry passes, back to back with its other pairs: a half's retries and
// other pairs move only its own rings, and a part's list only shrinks (the seam's, once empty,
// stays so): the order, and the result, are those of taking every pass in turn
void TorusXpbdSim::last_link_passes(Substep& sub, int part) {
  for (int more = sub.link_passes; more < kRetryPasses && !retry_[part].empty(); ++more)
    solve_links(sub.h, sub.scan, part, false, sub.stamp);
}

void TorusXpbdSim::other_pairs_half(Substep& sub, int part) {
  solve_other_pairs(sub.h, sub.scan, part, sub.stamp);
}

void TorusXpbdSim::other_pairs_seam(Substep& sub) {
  sub.seam([&](int part) { solve_other_pairs(sub.h, sub.scan, part, sub.stamp); });
}

void TorusXpbdSim::friction_half(Substep& sub, int part) {
  hold_collider_friction(sub.h, part);
}

void TorusXpbdSim::velocities_half(Substep& sub, int part) {
  update_velocities(sub.h, part);
}

// what the velocity pass needs from the poses (which it does not change), and the first pass over
// the half's contacts (they join only its own rings, which it has just updated)
void TorusXpbdSim::first_velocity_pass(Substep& sub, int part) {
  prepare_velocity_pass(part);
  if (std::min(model_.settings.velocity_iterations, kEveryContactPasses) > 0)
    velocity_sweep(sub.h, part, true);
}

// the seam's first pass, prepared by the lead first; the later passes over every contact
// alternate the same way, and then those near colliders (none: no more passes; the lists are
// read by both threads here and written again only in the next substep's prepare)
void TorusXpbdSim::velocity_passes(Substep& sub) {
  const int passes = model_.settings.velocity_iterations;
  const int everywhere = std::min(passes, kEveryContactPasses);
  for (int iteration = 0; iteration < everywhere; ++iteration) {
    if (iteration > 0) sub.each_half([&](int part) { velocity_sweep(sub.h, part, true); });
    sub.seam([&](int part) {
      if (iteration == 0) prepare_velocity_pass(part);
      velocity_sweep(sub.h, part, true);
    });
  }
  bool near_colliders = false;
  for (std::size_t part = 0; part < near_collider_contacts_.size(); ++part)
    near_colliders = near_colliders || !near_collider_contacts_[part].empty();
  for (int iteration = everywhere; near_colliders && iteration < passes; ++iteration) {
    sub.each_half([&](int part) { velocity_sweep(sub.h, part, false); });
    sub.seam([&](int part) { velocity_sweep(sub.h, part, false); });
  }
}

// one part's links in their order (first: over-relaxed, every link), or again those that pushed
// deep or hold a ring against a collider (the later passes are not over-relaxed: they correct
// what is left, not a whole load)
void TorusXpbdSim::solve_links(double h, bool scan, int part, bool first, std::uint64_t stamp) {
  const double deep = kRetryDepth * model_.ring.wire_radius;  // m
  const auto again = [&](const RingPairContact& pair, double depth) {
    return depth > deep || touching_[pair.a] || touching_[pair.b];
  };
  std::vector<int>& retry = retry_[part];
  if (first) {
    retry.clear();
    for (int index : part_links_[part]) {
      RingPairContact& pair = link_pairs_[index];
      if (again(pair, solve_pair(pair, h, scan, part, kOverRelaxation, stamp)))
        retry.push_back(index);
    }
    return;
  }
  std::size_t kept = 0;
  for (int index : retry) {
    RingPairContact& pair = link_pairs_[index];
    if (again(pair, solve_pair(pair, h, false, part, 1.0, stamp))) retry[kept++] = index;
  }
  retry.resize(kept);
}

void TorusXpbdSim::solve_other_pairs(double h, bool scan, int part, std::uint64_t stamp) {
  for (int index : part_others_[part])
    solve_pair(other_pairs_[index], h, scan, part, kOverRelaxation, stamp);
}

}  // namespace chainmail
