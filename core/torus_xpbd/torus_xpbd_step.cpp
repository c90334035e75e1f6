// The rigid-torus XPBD model's step: its substeps, each phase solving the two halves side by side
// and then the seam between them (torus_xpbd.hpp), and the link passes of the contact phase.
#include <algorithm>
#include <cmath>

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

bool TorusXpbdSim::step(double dt) {
  for (std::size_t part = 0; part < velocity_solves_.size(); ++part) velocity_solves_[part] = 0;
  collect_pairs(dt);
  // enough substeps that two rings close in by at most a wire radius in one: wires cannot pass
  // through each other between two contact solves, however fast the rings fly
  const double travel = 2.0 * fastest_ * dt / model_.ring.wire_radius;
  const int substeps =
      std::max(model_.settings.substeps,
               static_cast<int>(std::min(std::ceil(travel), double{kMaxSubsteps})));
  const double h = dt / substeps;
  const int team = parallel_loops_available() && static_cast<int>(part_.size()) >= kThreadedRings
                       ? std::min(threads_, kParts)
                       : 1;
  // substeps are stamped from 1 (a seed's `pushed` starts at 0)
  const std::uint64_t first_stamp = substep_ + 1;
  substep_ += static_cast<std::uint64_t>(substeps);
#pragma omp parallel num_threads(team) if (team > 1)
  run_substeps(h, substeps, team > 1 ? team_size() : 1, first_stamp);  // OpenMP may give fewer
  if (model_.settings.sleeping) update_sleep(dt);
  state_.t += dt;
  return finite();
}

// the substeps, on each thread of the team: every phase solves the halves (both on one thread, one
// each on two) and then, on the first thread, the contacts between them. Every thread meets every
// barrier: the loops' trip counts come from state the phase before left. Steps that touch only
// one half's rings follow each other within a phase with no barrier between (a half's colliders
// and first link pass see only its own rings, which its own integration moved): the order, and
// the result, are those of one barrier after each.
void TorusXpbdSim::run_substeps(double h, int substeps, int team, std::uint64_t first_stamp) {
  const int thread = team > 1 ? team_thread() : 0;
  const bool lead = thread == 0;  // keeps the profile, solves the seam
  const auto each_half = [&](const auto& solve) {
    for (int part = 0; part < kParts; ++part)
      if (team == 1 || part == thread) solve(part);
    team_barrier(team);
  };
  const auto seam = [&](const auto& solve) {
    if (lead) solve(kSeam);
    team_barrier(team);
  };
  const auto halves_then_seam = [&](const auto& solve) {
    each_half(solve);
    seam(solve);
  };
  const bool colliders = !collider_candidates_.empty();
  for (int k = 0; k < substeps; ++k) {
    const bool scan = k % kScanInterval == 0;
    const std::uint64_t stamp = first_stamp + static_cast<std::uint64_t>(k);
    // each half: integrated, then its colliders (the rings' own contacts then see where the
    // colliders put them), then its links in their order. The links, then again those that pushed
    // deep or hold a ring against a collider: one Gauss-Seidel pass leaves a link carrying much of
    // a sheet's weight (a corner that holds half of it, a ring pressed between a collider and the
    // rings it carries) short by a share of that weight
    each_half([&](int part) {
      {
        auto scope = profile_.scope_if(lead, "integrate");
        if (part == 0) active_[kSeam].clear();  // the lead's: the seam's solve comes after
        active_[part].clear();
        collider_holds_[part].clear();
        integrate(h, part);
      }
      if (colliders) {
        auto scope = profile_.scope_if(lead, "colliders");
        solve_colliders(h, scan, part);
      }
      auto scope = profile_.scope_if(lead, "contacts");
      solve_links(h, scan, part, true, stamp);
    });
    {
      auto scope = profile_.scope_if(lead, "contacts");
      // (whether any link is left is the lead's to say, in the seam's phase: the halves' lists
      // change again once both threads have read it)
      const auto seam_links = [&](bool first) {
        seam([&](int part) {
          solve_links(h, scan, part, first, stamp);
          seam_retrying_ = !retry_[kSeam].empty();
          retrying_ = seam_retrying_ || !(retry_[0].empty() && retry_[1].empty());
        });
      };
      seam_links(true);
      // the retry passes, each half's and then the seam's, while the seam has links to retry; then
      // each half's remaining passes and its other pairs back to back, with no barrier between
      // them, and the seam's other pairs. A half's retries and other pairs move only its own
      // rings, and a part's list only shrinks (the seam's, once empty, stays so): the order, and
      // the result, are those of taking every pass in turn
      int pass = 0;
      for (; pass < kRetryPasses && seam_retrying_; ++pass) {
        each_half([&](int part) { solve_links(h, scan, part, false, stamp); });
        seam_links(false);
      }
      const bool others = !other_pairs_.empty();
      if (others || (pass < kRetryPasses && retrying_)) {
        each_half([&](int part) {
          for (int more = pass; more < kRetryPasses && !retry_[part].empty(); ++more)
            solve_links(h, scan, part, false, stamp);
          if (others) {
            auto scope = profile_.scope_if(lead, "self_contact");
            solve_other_pairs(h, scan, part, stamp);
          }
        });
      }
      if (others) {
        auto scope = profile_.scope_if(lead, "self_contact");
        seam([&](int part) { solve_other_pairs(h, scan, part, stamp); });
      }
    }
    // each half: the colliders' static friction once more, its velocities from the substep's
    // motion, what the velocity pass needs from the poses (which it does not change), and the
    // first velocity pass over its contacts (they join only its own rings, which it has just
    // updated); then the seam's, prepared by the lead first. The later passes over every contact
    // alternate the same way, and then those near colliders (none: no more passes; the lists are
    // read by both threads here and written again only in the next substep's prepare)
    const int passes = model_.settings.velocity_iterations;
    const int everywhere = std::min(passes, kEveryContactPasses);
    each_half([&](int part) {
      if (colliders) {
        auto scope = profile_.scope_if(lead, "colliders");
        hold_collider_friction(h, part);
      }
      {
        auto scope = profile_.scope_if(lead, "velocities");
        update_velocities(h, part);
      }
      auto scope = profile_.scope_if(lead, "velocity_pass");
      prepare_velocity_pass(part);
      if (everywhere > 0) velocity_sweep(h, part, true);
    });
    auto scope = profile_.scope_if(lead, "velocity_pass");
    for (int iteration = 0; iteration < everywhere; ++iteration) {
      if (iteration > 0) each_half([&](int part) { velocity_sweep(h, part, true); });
      seam([&](int part) {
        if (iteration == 0) prepare_velocity_pass(part);
        velocity_sweep(h, part, true);
      });
    }
    bool near_colliders = false;
    for (std::size_t part = 0; part < near_collider_contacts_.size(); ++part)
      near_colliders = near_colliders || !near_collider_contacts_[part].empty();
    for (int iteration = everywhere; near_colliders && iteration < passes; ++iteration)
      halves_then_seam([&](int part) { velocity_sweep(h, part, false); });
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
