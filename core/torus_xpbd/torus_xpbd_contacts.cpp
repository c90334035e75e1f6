// The rigid-torus XPBD model: seeds, the contact solve (ring against ring, ring against
// collider), and the velocity pass.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/circle_contact.hpp"
#include "core/colliders.hpp"
#include "core/torus_xpbd/torus_colliders.hpp"
#include "core/torus_xpbd/torus_xpbd.hpp"

namespace chainmail {
namespace {

// a seed's angle may move this far (cos of 0.5 rad) in a substep and still follow one minimum
constexpr double kSameMinimum = 0.8775825618903728;
// a sampled minimum within a sample spacing (cos of pi / 16) of a seed, and not below the seed's
// own distance, is the seed's; any other is refined, and kept unless it finds a seed's minimum
constexpr double kCovered = 0.9807852804032304;
// two seeds closer than this (cos of 1e-3 rad) have found the same minimum
constexpr double kDuplicate = 0.9999995;
// the motion the contact solve may add to a pair's in a substep, in wire radii
constexpr double kSolveMotion = 0.02;
// a scan (every few substeps) seeds the minima that may touch within this many substeps' motion
constexpr double kScanReach = 4.0;
// Newton steps from a seed's last angle: one when it was solved in the last substep (the pair
// moved little since), more when it rested a few substeps
constexpr int kSubstepNewton = 1;
constexpr int kResumeNewton = 3;
// the four points of a ring's centre circle that rest on colliders beside the deepest one,
// (cos, sin) of k pi / 2: a ring lying flat stands on them
constexpr double kSupport[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};

double angle_cos(const PairSeed& seed, double c, double s) {
  return seed.cos_t * c + seed.sin_t * s;
}

// two unit tangents of the plane normal to unit n, fixed by n alone (as ODE's dPlaneSpace): the
// pyramid's friction axes
void tangent_axes(const Vec3& n, Vec3& t1, Vec3& t2) {
  if (std::abs(n.z()) > std::numbers::sqrt2 / 2.0) {
    const double k = 1.0 / std::sqrt(n.y() * n.y() + n.z() * n.z());
    t1 = Vec3(0.0, -n.z() * k, n.y() * k);
  } else {
    const double k = 1.0 / std::sqrt(n.x() * n.x() + n.y() * n.y());
    t1 = Vec3(-n.y() * k, n.x() * k, 0.0);
  }
  t2 = n.cross(t1);
}

// the seed followed to the minimum it tracks on the pair's pose now (its angle, normal and bound
// updated, the closest points in `p`); returns the signed distance there, m
double follow_seed(PairSeed& seed, const CircleFrame& fa, const CircleFrame& fb,
                   std::uint64_t stamp, double c, ClosestPoints& p) {
  // a retry in the substep that solved the seed keeps its angle: the pair moved by one
  // correction since, and the distance there is an upper bound (never over-corrects)
  const int newton_steps = seed.pushed == stamp ? 0 : seed.recent ? kSubstepNewton : kResumeNewton;
  p = refine_closest_points(fa, fb, seed.cos_t, seed.sin_t, newton_steps, 1e-10);
  // the side is the seed's while it follows one minimum: circles that crossed within the
  // substep (wires pushed through each other) have their gap reversed, a negative distance
  const bool same = seed.recent && angle_cos(seed, p.cos_t, p.sin_t) > kSameMinimum;
  double distance = p.distance;
  if (p.distance > 1e-12 * c) {
    const Vec3 normal = (1.0 / p.distance) * (p.first - p.second);
    if (same && normal.dot(seed.normal) < 0.0) {
      seed.normal = -normal, distance = -distance;
    } else {
      seed.normal = normal;
    }
  }
  seed.cos_t = p.cos_t, seed.sin_t = p.sin_t;
  seed.bound = p.distance, seed.recent = true;
  return distance;
}

}  // namespace

// one pair in one substep: new minima that could touch before the next scan are seeded (when
// `scan`); then each seed that may touch in this substep is followed from its last angle (on the
// pose the pair has then: the seeds before it may have pushed), and one closer than two wire
// radii pushes the rings apart. A seed that cannot touch yet is not solved: its lower bound only
// shrinks by the substep's motion, so it is solved again before it could touch.
double TorusXpbdSim::solve_pair(RingPairContact& pair, double h, bool scan, int part,
                                double relaxation, std::uint64_t stamp) {
  const double a = model_.ring.wire_radius, c = model_.ring.centre_radius;
  // m, how much nearer the pair can come in a substep: its rings' own motion, and a margin for
  // what the contact solve moves them
  const double reach = travel_[pair.a] + travel_[pair.b] + kSolveMotion * a;
  const double touch = 2.0 * a + reach;  // m, a seed whose bound is above cannot touch now
  // the minima that the pair's own motion, or the fastest ring's of the step (a ring hit between
  // two scans may move as fast), could bring into contact before the next scan; none where the
  // circles are farther apart than that everywhere
  const double fast = 2.0 * fastest_ * h + kSolveMotion * a;
  const double limit = 2.0 * a + kScanReach * std::max(reach, fast);  // m
  pair.clear -= reach;  // (twice in a substep for a retried link: it only shrinks)
  scan = scan && pair.clear <= limit + model_.scan_spacing;
  if (!scan) {
    bool near = false;
    for (int k = 0; k < pair.seeds && !near; ++k) near = pair.seed[k].bound <= touch;
    if (!near) {
      for (int k = 0; k < pair.seeds; ++k) pair.seed[k].bound -= reach, pair.seed[k].recent = false;
      return 0.0;
    }
  }
  CircleFrame fa = circle_of(pair.a), fb = circle_of(pair.b);
  if (scan) {
    find_new_minima(pair, CirclePairDistance(fa, fb), limit);
  }
  bool stale = false;
  int kept = 0;
  double deepest = 0.0;  // m
  for (int k = 0; k < pair.seeds; ++k) {
    PairSeed seed = pair.seed[k];
    if (seed.bound > touch) {
      seed.bound -= reach, seed.recent = false;
      pair.seed[kept++] = seed;
      continue;
    }
    if (stale) {
      fa = circle_of(pair.a), fb = circle_of(pair.b);
      stale = false;
    }
    ClosestPoints p;
    const double distance = follow_seed(seed, fa, fb, stamp, c, p);
    // a seed that found an earlier one's minimum is dropped (far ones stay: their bound keeps
    // them unsolved until they come near)
    bool keep = true;
    for (int j = 0; j < kept && keep; ++j)
      keep = angle_cos(pair.seed[j], seed.cos_t, seed.sin_t) < kDuplicate;
    if (!keep) continue;
    const double depth = 2.0 * a - distance;
    if (depth > 0.0) {
      // one contact per seed for the velocity pass: a retry adds its multiplier to the first's
      const int into = seed.pushed == stamp ? seed.active : -1;
      seed.active = apply_contact(pair.a, pair.b, seed.normal, 0.5 * (p.first + p.second), depth,
                                  model_.ring_friction, h, part, relaxation, into);
      seed.pushed = stamp;
      stale = true;
      deepest = std::max(deepest, depth);
    }
    pair.seed[kept++] = seed;
  }
  pair.seeds = kept;
  return deepest;
}

// the sampled local minima of the pair's distance that no seed follows and that may come closer
// than `limit` (m): refined and seeded, up to three seeds a pair (one that turns out farther is
// still kept, so that the next scans know it; a full pair gives up its farthest seed for a
// nearer minimum). A sample is a seed's when the seed is within a sample spacing of it and the
// sample is no nearer than the seed's bound.
void TorusXpbdSim::find_new_minima(RingPairContact& pair, const CirclePairDistance& distance,
                                   double limit) {
  // the distance moves at most r per radian along the circle: half a sample spacing may hide this
  constexpr int kSamples = CirclePairDistance::kSamples;
  const double hidden = model_.scan_spacing;
  const double reach2 = (limit + hidden) * (limit + hidden);
  double f[kSamples];
  distance.sample(f);
  const double nearest2 = *std::min_element(f, f + kSamples);  // m^2
  pair.clear = std::sqrt(nearest2) - hidden;
  if (nearest2 > reach2) return;
  const auto& angle = CirclePairDistance::samples();
  for (int k = 0; k < kSamples; ++k) {
    if (f[k] > reach2 || f[k] > f[(k + kSamples - 1) % kSamples] || f[k] >= f[(k + 1) % kSamples])
      continue;
    bool covered = false;
    for (int j = 0; j < pair.seeds && !covered; ++j) {
      covered = angle_cos(pair.seed[j], angle.c[k], angle.s[k]) > kCovered &&
                f[k] >= pair.seed[j].bound * pair.seed[j].bound;
    }
    if (covered) continue;
    const ClosestPoints p = distance.refine(angle.c[k], angle.s[k], 8, 1e-9);
    for (int j = 0; j < pair.seeds && !covered; ++j)
      covered = angle_cos(pair.seed[j], p.cos_t, p.sin_t) > kDuplicate;
    if (covered) continue;
    int slot = pair.seeds;
    if (slot < static_cast<int>(pair.seed.size())) {
      ++pair.seeds;
    } else {
      // full: the farthest seed, if this minimum is nearer
      slot = 0;
      for (int j = 1; j < pair.seeds; ++j)
        if (pair.seed[j].bound > pair.seed[slot].bound) slot = j;
      if (pair.seed[slot].bound <= p.distance) continue;
    }
    PairSeed& seed = pair.seed[slot];
    seed.cos_t = p.cos_t, seed.sin_t = p.sin_t;
    seed.bound = p.distance, seed.recent = true;
    seed.active = -1, seed.pushed = 0;
    seed.normal = p.distance > 1e-12 * model_.ring.centre_radius
                      ? Vec3((p.first - p.second) / p.distance)
                      : Vec3((state_.position[pair.a] - state_.position[pair.b]).normalized());
  }
}

// each ring near a collider: the torus's deepest point, then four points of its centre circle
// (a ring lying flat rests on all of them)
void TorusXpbdSim::solve_colliders(double h, bool scan, int part) {
  const double a = model_.ring.wire_radius, c = model_.ring.centre_radius;
  std::vector<ActiveContact>& active = active_[part];
  for (int index : part_candidates_[part]) {
    ColliderCandidate& candidate = collider_candidates_[index];
    const int i = candidate.ring;
    const Collider& collider = model_.colliders[candidate.collider];
    const double friction = model_.collider_friction[candidate.collider];
    // nowhere within a wire radius of it: nothing to do
    if (circle_collider_lower_bound(collider, circle_of(i)) >= a) {
      candidate.followed = false;
      continue;
    }
    const std::size_t first = active.size();
    // from the last substep's deepest angle, from scratch at every scan
    const CirclePointContact deepest =
        candidate.followed && !scan
            ? deepest_circle_point_near(collider, circle_of(i), candidate.cos_s, candidate.sin_s)
            : deepest_circle_point(collider, circle_of(i));
    candidate.cos_s = deepest.cos_s, candidate.sin_s = deepest.sin_s, candidate.followed = true;
    if (deepest.distance < a) {
      apply_contact(i, -1, deepest.normal, deepest.point - a * deepest.normal, a - deepest.distance,
                    friction, h, part);
      touching_[i] = 1;
    }
    for (const auto& angle : kSupport) {
      const Vec3 point = state_.position[i] +
                         c * (angle[0] * rotation_[i].col(0) + angle[1] * rotation_[i].col(2));
      Vec3 normal;
      const double distance = collider_distance(collider, point, normal);
      if (distance < a)
        apply_contact(i, -1, normal, point - a * normal, a - distance, friction, h, part);
    }
    merge_contacts(part, first, h);
  }
}

// the contacts of one ring with one collider since `first` become one for the velocity pass, at
// their multiplier-weighted mean point and normal: one ring bounces off one surface once (points
// bounced one after the other would each spin it, and a flat ring would leap)
void TorusXpbdSim::merge_contacts(int part, std::size_t first, double h) {
  std::vector<ActiveContact>& active = active_[part];
  if (active.size() <= first + 1) return;
  ActiveContact merged = active[first];
  Vec3 arm = Vec3::Zero(), normal = Vec3::Zero();
  double lambda = 0.0, friction = 0.0;
  for (std::size_t k = first; k < active.size(); ++k) {
    const ActiveContact& contact = active[k];
    arm += contact.lambda * contact.arm_a;
    normal += contact.lambda * contact.normal;
    lambda += contact.lambda;
    friction = std::max(friction, contact.friction);
  }
  if (lambda <= 0.0 || normal.squaredNorm() == 0.0) return;
  merged.arm_a = arm / lambda;
  merged.normal = normal.normalized();
  merged.lambda = lambda;
  merged.friction = friction;
  merged.w = generalized_inverse_mass(merged.a, merged.arm_a, merged.normal);
  merged.approach = merged.normal.dot(point_velocity(merged.a, merged.arm_a) - h * model_.gravity);
  active.resize(first);
  if (merged.w > 0.0) active.push_back(merged);
}

// one contact's positional correction along `normal` (pushing a; b = -1: a static collider),
// depth m at `point`, with static friction: the contact point's slip over the substep is undone
// with it when that takes less than friction times the normal multiplier. One correction of each
// ring carries both.
int TorusXpbdSim::apply_contact(int a, int b, const Vec3& normal, const Vec3& point, double depth,
                                double friction, double h, int part, double relaxation, int into) {
  const bool ring_b = b >= 0;
  const Vec3 arm_a = point - state_.position[a];
  const Vec3 arm_b = ring_b ? Vec3(point - state_.position[b]) : Vec3::Zero();
  const double w = generalized_inverse_mass(a, arm_a, normal) +
                   (ring_b ? generalized_inverse_mass(b, arm_b, normal) : 0.0);
  if (w <= 0.0) return -1;
  const double stiffness_term = model_.settings.compliance / (h * h);
  const double lambda = relaxation * depth / (w + stiffness_term);
  Vec3 correction = lambda * normal;  // kg m, on a (b takes the opposite)
  bool stuck = false;

  if (friction > 0.0) {
    // where the contact point was at the substep's start, on each ring
    Vec3 slip = point - state_.previous_position[a] -
                previous_rotation_[a] * (rotation_[a].transpose() * arm_a);
    if (ring_b) {
      slip -= point - state_.previous_position[b] -
              previous_rotation_[b] * (rotation_[b].transpose() * arm_b);
    }
    slip -= slip.dot(normal) * normal;
    correction +=
        static_friction(a, arm_a, b, arm_b, normal, slip, friction * lambda, stiffness_term, stuck);
  }
  // every contact that pushed meets dynamic friction in the velocity pass, held or not (it only
  // takes sliding speed away, never more than there is): a held contact's velocity still carries
  // the slip that the contacts solved after it brought
  std::vector<ActiveContact>& active = active_[part];
  if (into >= 0) {
    active[into].lambda += lambda;
  } else {
    // the approach speed at the substep's start, before gravity's pull in it (against a collider;
    // between rings it cancels): a bounce returns no more than the speed the contact met
    Vec3 relative = point_velocity(a, arm_a);
    if (ring_b) relative -= point_velocity(b, arm_b);
    if (!ring_b) relative -= h * model_.gravity;
    active.push_back({a, b, normal, arm_a, arm_b, lambda, w, normal.dot(relative), friction});
    into = static_cast<int>(active.size()) - 1;
  }
  // a ring held by a collider's static friction is held again after the rings' own contacts
  if (stuck && !ring_b) {
    collider_holds_[part].push_back(
        {a, rotation_[a].transpose() * arm_a, normal, lambda, friction});
  }
  apply_correction(a, arm_a, correction);
  if (ring_b) apply_correction(b, arm_b, -correction);
  return into;
}

Vec3 TorusXpbdSim::static_friction(int a, const Vec3& arm_a, int b, const Vec3& arm_b,
                                   const Vec3& normal, const Vec3& slip, double limit,
                                   double stiffness_term, bool& held) const {
  // the multiplier that undoes the slip along one unit tangent, and whether friction can give it
  const auto undo = [&](const Vec3& tangent, double along) -> Vec3 {
    const double wt = generalized_inverse_mass(a, arm_a, tangent) +
                      (b >= 0 ? generalized_inverse_mass(b, arm_b, tangent) : 0.0);
    if (wt <= 0.0) return Vec3::Zero();
    const double lambda_t = std::abs(along) / (wt + stiffness_term);
    if (lambda_t >= limit) return Vec3::Zero();
    held = true;
    return -std::copysign(lambda_t, along) * tangent;
  };
  if (model_.settings.friction_law == FrictionLaw::pyramid) {
    Vec3 t1, t2;
    tangent_axes(normal, t1, t2);
    return undo(t1, slip.dot(t1)) + undo(t2, slip.dot(t2));
  }
  // the cone, along the slip itself: with k = |slip|^2 / (the inverse mass along it times
  // |slip|^2 + the stiffness term's), undoing it takes |slip| k, and no square root
  const double slip2 = slip.squaredNorm();  // m^2
  if (!(slip2 > 0.0) || limit <= 0.0) return Vec3::Zero();
  const double w_slip2 = generalized_inverse_mass(a, arm_a, slip, slip2) +
                         (b >= 0 ? generalized_inverse_mass(b, arm_b, slip, slip2) : 0.0);
  if (w_slip2 <= 0.0) return Vec3::Zero();
  const double k = slip2 / (w_slip2 + stiffness_term * slip2);  // kg / m
  if (slip2 * k * k >= limit * limit) return Vec3::Zero();
  held = true;
  return -k * slip;
}

// static friction against the colliders once more, after the rings' contacts have moved the rings:
// each held contact point's slip over the substep is undone again where friction can (otherwise
// the rings' pull drags a sheet over a table a little every substep)
void TorusXpbdSim::hold_collider_friction(double h, int part) {
  const double stiffness_term = model_.settings.compliance / (h * h);
  for (const ColliderHold& hold : collider_holds_[part]) {
    const int i = hold.ring;
    const Vec3 arm = rotation_[i] * hold.local_arm;
    Vec3 slip = state_.position[i] + arm - state_.previous_position[i] -
                previous_rotation_[i] * hold.local_arm;
    slip -= slip.dot(hold.normal) * hold.normal;
    bool held = false;
    const Vec3 correction = static_friction(i, arm, -1, Vec3::Zero(), hold.normal, slip,
                                            hold.friction * hold.lambda, stiffness_term, held);
    if (held) apply_correction(i, arm, correction);
  }
}

// restitution and dynamic friction on the velocities the substep produced, at every contact that
// pushed in it, in velocity_iterations Gauss-Seidel passes: each contact's impulse leaves its
// normal speed e times the approach speed (0 for resting contact) and takes from its sliding
// speed what friction allows, at most friction times the normal impulse lambda / h over all the
// passes, each part through the inverse mass along its own direction. One pass leaves the speeds
// the later contacts gave the earlier ones: a sheet draped over a table creeps off it. So the
// first two passes solve every contact and the later ones those near colliders (within
// kVelocityReach links of a ring that touches one): in fabric that hangs free, the later passes
// cost a third of the step and changed a 16 x 16 curtain's drape by 0.01 mm.
// (The passes alternate between the halves, side by side, and the seam between them.)
//
// first, what the inverse masses along a direction need from each ring's rotation, once per
// contact: the rings' poses do not change in the pass
void TorusXpbdSim::prepare_velocity_pass(int part) {
  const std::vector<ActiveContact>& active = active_[part];
  std::vector<VelocityTerms>& velocity_terms = velocity_terms_[part];
  velocity_terms.resize(active.size());
  std::vector<int>& near = near_collider_contacts_[part];
  near.clear();
  for (std::size_t k = 0; k < active.size(); ++k) {
    const ActiveContact& contact = active[k];
    VelocityTerms& terms = velocity_terms[k];
    terms.a = ring_terms(contact.a, contact.arm_a);
    if (contact.b >= 0) terms.b = ring_terms(contact.b, contact.arm_b);
    terms.inverse_w = 1.0 / contact.w;
    if (contact.b < 0 || touching_[contact.a] || touching_[contact.b] ||
        near_collider_[contact.a] || near_collider_[contact.b])
      near.push_back(static_cast<int>(k));
  }
}

// one contact's restitution and dynamic friction
void TorusXpbdSim::velocity_solve(double resting, double inv_h, int part, int k) {
  ActiveContact& contact = active_[part][k];
  const VelocityTerms& terms = velocity_terms_[part][k];
  const bool ring_b = contact.b >= 0;
  Vec3 relative = point_velocity(contact.a, contact.arm_a);
  if (ring_b) relative -= point_velocity(contact.b, contact.arm_b);
  const Vec3& n = contact.normal;
  const double normal_speed = n.dot(relative);
  const double e = std::abs(normal_speed) <= resting ? 0.0 : model_.settings.restitution;
  Vec3 impulse = ((std::max(-e * contact.approach, 0.0) - normal_speed) * terms.inverse_w) * n;
  const Vec3 sliding = relative - normal_speed * n;
  // takes from the sliding speed along one unit tangent what is left of friction's budget
  const auto slow = [&](const Vec3& tangent, double speed, double& spent) {
    const double wt =
        inverse_mass_along(contact.a, contact.arm_a, terms.a, tangent) +
        (ring_b ? inverse_mass_along(contact.b, contact.arm_b, terms.b, tangent) : 0.0);
    if (wt <= 0.0) return;
    const double budget = contact.friction * contact.lambda * inv_h - spent;
    const double taken = std::min(budget, std::abs(speed) / wt);
    if (taken <= 0.0) return;
    spent += taken;
    impulse -= std::copysign(taken, speed) * tangent;
  };
  if (contact.friction > 0.0 && model_.settings.friction_law == FrictionLaw::pyramid) {
    Vec3 t1, t2;
    tangent_axes(n, t1, t2);
    slow(t1, sliding.dot(t1), contact.spent[0]);
    slow(t2, sliding.dot(t2), contact.spent[1]);
  } else if (contact.friction > 0.0) {
    // the cone, along the slide itself: the inverse mass along it times slide^2 needs no
    // square root, so that the common case, a slide friction stops, waits on none
    const double slide2 = sliding.squaredNorm();
    const double w_slide2 =
        inverse_mass_along(contact.a, contact.arm_a, terms.a, sliding, slide2) +
        (ring_b ? inverse_mass_along(contact.b, contact.arm_b, terms.b, sliding, slide2) : 0.0);
    const double budget = contact.friction * contact.lambda * inv_h - contact.spent[0];
    if (slide2 > 0.0 && w_slide2 > 0.0 && budget > 0.0) {
      const double stop = slide2 / w_slide2;   // kg: the impulse per m/s of sliding that stops it
      const double slide = std::sqrt(slide2);  // m/s
      const double needed = slide * stop;      // kg m/s
      if (needed <= budget) {
        impulse -= stop * sliding;
        contact.spent[0] += needed;
      } else {
        impulse -= (budget / slide) * sliding;
        contact.spent[0] += budget;
      }
    }
  }
  apply_impulse(contact.a, contact.arm_a, terms.a, impulse);
  if (ring_b) apply_impulse(contact.b, contact.arm_b, terms.b, -impulse);
}

// one Gauss-Seidel pass over one part's contacts: all of them (the first pass), or those at rings
// that touch a collider (the later ones)
void TorusXpbdSim::velocity_sweep(double h, int part, bool all) {
  std::vector<ActiveContact>& active = active_[part];
  const double resting = 2.0 * model_.gravity.norm() * h;  // m/s, slower contacts do not bounce
  const double inv_h = 1.0 / h;                            // 1/s
  if (all) {
    for (std::size_t k = 0; k < active.size(); ++k)
      velocity_solve(resting, inv_h, part, static_cast<int>(k));
    velocity_solves_[part] += static_cast<long long>(active.size());
  } else {
    for (int k : near_collider_contacts_[part]) velocity_solve(resting, inv_h, part, k);
    velocity_solves_[part] += static_cast<long long>(near_collider_contacts_[part].size());
  }
}

}  // namespace chainmail
