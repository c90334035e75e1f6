// The plausible model's position solve: the outward pass from the pins, then the edge
// constraints, the minimum distance between non-neighbours and the colliders, solved together
// (Newton steps on all of them, or Gauss-Seidel sweeps) until the largest violation is below the
// tolerance.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/colliders.hpp"
#include "core/parallel.hpp"
#include "core/plausible/constraints.hpp"
#include "core/plausible/neighbour_frame.hpp"
#include "core/plausible/plausible.hpp"
#include "core/plausible/plausible_sweep.hpp"
#include "core/plausible/projection.hpp"

namespace chainmail {
namespace {

// one Gauss-Seidel sweep over coloured pairs, colour by colour; a colour's pairs share no ring,
// so they run on the threads with the result of any order. solve(k) returns pair k's violation
template <class Solve>
double sweep_colours(const Colouring& colours, int threads, Solve&& solve) {
  double worst = 0.0;  // m
  for (int c = 0; c < colours.colours(); ++c) {
    const int begin = colours.start[c], end = colours.start[c + 1];
    const bool serial = colours.serial_tail && c + 1 == colours.colours();
    const int team = serial ? 1 : loop_threads(threads, end - begin);
    worst = parallel_max(begin, end, team, worst, solve);
  }
  return worst;
}

}  // namespace

void PlausibleSim::solve_positions(bool slide) {
  if (model_.settings.shock_propagation && !model_.outward.empty()) propagate_from_pins();
  const double tolerance = model_.settings.tolerance * model_.longest_link;  // m
  // Gauss-Seidel sweeps: each ends with the colliders, so a converged sweep leaves the edges
  // within tolerance with every ring outside (neither has the last word)
  const bool contacts = solves_contacts();
  // a chain's minimum distances read the ring axes: derived once a step, where a pair is near
  if (contacts && model_.shaped_contacts && orientation_stale_ &&
      !state_.contact_candidates.empty()) {
    auto scope = profile_.scope(stage_name(PlausibleStage::orient));
    orient();
  }
  const bool colliders = !model_.colliders.empty();
  state_.sweeps = 0;
  state_.newton_steps = 0;
  state_.residual = 0.0;
  double local = 0.0;  // m, the last sweep's largest violation but the attachments'
  // the step's sweeps are shared among its substeps
  const int iterations = std::max(1, model_.settings.iterations / substep_count());
  // with the substeps under control, up to kExtraSweeps more while a sweep meets a link stretched
  // past the control level (control_substeps): the substep that meets it is not left with it
  const int extra = controls_substeps() ? kExtraSweeps : 0;
  const double control = stretch_control_level() * model_.longest_link;  // m
  while (state_.sweeps < iterations + extra) {
    // the attachments first: the sheet-wide part of a stretch, then the edges fix the local one
    // rows the step's first prediction pushed together slide out of the sheet first; the
    // diagonals then hold every row pair along its centre line (once a step: the look for them
    // reads every row pair, and what breaks the sheet's mirror symmetry is the way, not the amount)
    const double slid =
        slide && state_.sweeps == 0 && !model_.row_pairs.empty() ? slide_rows() : 0.0;
    SweepViolation links = sweep_links();
    links.links = std::max(links.links, slid);
    local = links.links;
    if (contacts) local = std::max(local, solve_contacts());
    if (colliders) local = std::max(local, collide());
    const double residual = std::max(local, links.attachments);  // m
    ++state_.sweeps;
    state_.residual = residual;
    // the edges' stretch the scheduled sweeps met, before any extra ones: the stretch control's
    // signal
    if (state_.sweeps <= iterations) {
      state_.scheduled_stretch = std::max(state_.scheduled_stretch, links.edges);
    }
    if (residual <= tolerance) return;
    if (state_.sweeps >= iterations && links.links <= control) break;
  }
  // what the sweeps leave past the Newton level (a sheet torn by an impact or a huge step: the
  // sweeps move a violation a few rings a sweep), Newton steps on the edges and colliders
  // together remove; the state decides, not the ring count. An attachment's violation is a whole
  // path's: the rows are built only where a link, contact or collider was met past the level
  const double trigger = newton_trigger();  // m
  if (model_.settings.newton_steps > 0 && local > trigger && !state_.newton_stalled) {
    solve_together(tolerance, trigger);
  }
  if (!model_.carried.empty()) hold_carried(tolerance);
}

void PlausibleSim::hold_carried(double tolerance) {
  // a ring much heavier than one it hangs from: a sweep moves each pair by its mass shares, so
  // the light rings on its way to the pins pass its weight on a little a sweep while it sinks
  // and jitters. More sweeps of that way alone, from the heavy ring up, until one meets no edge
  // past the tolerance
  auto scope = profile_.scope("carried");
  double* const x = state_.position.data();            // (3 n) m
  const double* const w = model_.inverse_mass.data();  // (n) 1/kg
  const std::vector<EdgeConstraint>& edges = model_.carried;
  for (int pass = 0; pass < kCarriedPasses; ++pass) {
    double worst = 0.0;  // m
    for (auto e = edges.rbegin(); e != edges.rend(); ++e)
      worst = std::max(worst, sweep_pair(x, w, *e));
    if (worst <= tolerance) return;
  }
}

double PlausibleSim::max_over_extension() const {
  double worst = 0.0;
  for (const EdgeConstraint& e : model_.edges) {
    const double length = (state_.position.col(e.a) - state_.position.col(e.b)).norm();
    worst = std::max(worst, (length - e.max_length) / e.max_length);
  }
  return worst;
}

double PlausibleSim::newton_trigger() const {
  // newton_level of the way from the longest link to a link at the inner diameter: at 1, a link
  // would otherwise end the substep longer than real rings allow (a chain's links have only the
  // tolerance between them and the inner diameter)
  const double tolerance = model_.settings.tolerance * model_.longest_link;  // m
  const double room = std::max(model_.ring.inner_diameter() - model_.longest_link, tolerance);
  return std::max(tolerance, model_.settings.newton_level * room);
}

double PlausibleSim::slide_rows() {
  // rings side by side in a row pushed together past their closest approach slide along their
  // axes, as leaning coins do (PlausibleModel::row_pairs); each axis is its rest lean turned with
  // its neighbour frame as the substep began: read from the positions being corrected, the push
  // would steer itself
  Positions& p = state_.position;
  const std::vector<EdgeConstraint>& pairs = model_.row_pairs;
  // few rows are pushed together at once: the pairs closer than their closest approach are found
  // first, then pushed apart one by one in the list's order (a pair that a push before it brought
  // together waits for the next step)
  std::vector<int> found;
  for (int k = 0; k < static_cast<int>(pairs.size()); ++k) {
    const EdgeConstraint& e = pairs[k];
    if ((p.col(e.b) - p.col(e.a)).squaredNorm() < e.min_length * e.min_length) found.push_back(k);
  }
  if (found.empty()) return 0.0;
  auto scope = profile_.scope(stage_name(PlausibleStage::constraints));
  const std::vector<double>& w = model_.inverse_mass;
  const double slip = model_.settings.row_slip;
  double worst = 0.0;  // m
  for (const int k : found) {
    const EdgeConstraint& e = pairs[k];
    Vec3 normal = p.col(e.b) - p.col(e.a);
    const double length2 = normal.squaredNorm();  // m^2
    const double weight = w[e.a] + w[e.b];
    if (length2 >= e.min_length * e.min_length || weight == 0.0 || length2 < 1e-30) continue;
    const double length = std::sqrt(length2);  // m
    normal /= length;
    const Vec3 way = slide_toward_faces(
        normal, axis_in_frame(model_.weave, model_.rest_axes, state_.previous, e.a),
        axis_in_frame(model_.weave, model_.rest_axes, state_.previous, e.b), slip);
    // as far along `way` as closes the gap along the centre line
    const double gap = length - e.min_length;  // m, < 0
    const Vec3 shift = (gap / (weight * way.dot(normal))) * way;
    p.col(e.a) += w[e.a] * shift;
    p.col(e.b) -= w[e.b] * shift;
    // the slide across the centre line moves the rings, not their velocities: kicked out of the
    // sheet at each step's push, a sheet pinned along an edge swings about it (a motion damping
    // spares) and one carrying a heavy ring does not come to rest
    const Vec3 across = shift - shift.dot(normal) * normal;
    state_.previous.col(e.a) += w[e.a] * across;
    state_.previous.col(e.b) -= w[e.b] * across;
    worst = std::max(worst, -gap);
  }
  return worst;
}

bool PlausibleSim::solves_contacts() const {
  return model_.self_contact && !model_.settings.repulsion_spring && state_.position.cols() > 1;
}

void PlausibleSim::solve_together(double tolerance, double trigger) {
  // the minimum distances between non-neighbours stay with the sweeps: where a sheet is packed
  // tight they contradict the edges, and a system holding both has no solution
  const bool colliders = !model_.colliders.empty();
  std::vector<ProjectionRow> rows;
  double least = std::numeric_limits<double>::infinity();  // m, the least residual reached
  int stalled = 0;  // steps in a row that did not bring the residual below kNewtonProgress * least
  for (;;) {
    rows.clear();
    double residual = 0.0;
    {
      auto scope = profile_.scope("constraints");
      residual = std::max(residual, edge_rows(tolerance, rows));
    }
    const size_t first_collider = rows.size();
    if (colliders) {
      auto scope = profile_.scope("colliders");
      residual = std::max(residual, collider_rows(tolerance, rows));
    }
    state_.residual = residual;
    // the sweeps' residual counts every kind of violation: the edges and colliders alone may
    // stand within the level
    if (state_.newton_steps == 0 && residual <= trigger) break;
    if (residual <= tolerance || state_.newton_steps >= model_.settings.newton_steps) break;
    const bool progress = residual < kNewtonProgress * least;
    if (progress) least = residual;
    if (progress || residual < kNewtonStallFloor * model_.longest_link) {
      stalled = 0;
    } else if (++stalled >= kNewtonPatience) {
      state_.newton_stalled = true;
      break;
    }
    ++state_.newton_steps;
    auto scope = profile_.scope("newton");
    const ProjectionResult result = projection_.project(rows, model_.inverse_mass, state_.position);
    if (!result.solved) break;  // not factorisable (never seen): the sweeps' result stands
    // collider pushes, for friction in the velocity update
    for (size_t k = first_collider; k < rows.size(); ++k) {
      const int ring = rows[k].b;
      state_.contact_push[ring] += result.shift[k] * model_.inverse_mass[ring];
    }
  }
}

double PlausibleSim::edge_rows(double near, std::vector<ProjectionRow>& rows) const {
  const Positions& p = state_.position;
  const std::vector<double>& w = model_.inverse_mass;
  double worst = 0.0;  // m
  for (const EdgeConstraint& e : model_.edges) {
    if (w[e.a] + w[e.b] == 0.0) continue;
    const Vec3 d = p.col(e.b) - p.col(e.a);
    const double length = d.norm();
    if (length < 1e-15) continue;
    const Vec3 n = d / length;
    // at most max_length: C = length - max; at least min_length: C = min - length
    const double over = length - e.max_length, under = e.min_length - length;
    if (over > -near) rows.push_back({e.a, e.b, n, over});
    if (under > -near) rows.push_back({e.a, e.b, -n, under});
    worst = std::max({worst, over, under});
  }
  return worst;
}

double PlausibleSim::contact_rows(double near, std::vector<ProjectionRow>& rows) const {
  const Positions& p = state_.position;
  const Positions& before = state_.previous;
  const double range = model_.repulsion_range;
  double worst = 0.0;  // m
  for (const RingPair& pair : state_.contact_candidates) {
    if (model_.inverse_mass[pair.a] + model_.inverse_mass[pair.b] == 0.0) continue;
    // apart along the direction the pair had at the start of the step (see solve_contacts)
    Vec3 normal = before.col(pair.b) - before.col(pair.a);
    if (normal.squaredNorm() < 1e-24) normal = p.col(pair.b) - p.col(pair.a);
    const double length = normal.norm();
    if (length < 1e-12) continue;
    normal /= length;
    const double violation = range - (p.col(pair.b) - p.col(pair.a)).dot(normal);
    if (violation > -near) rows.push_back({pair.a, pair.b, -normal, violation});
    worst = std::max(worst, violation);
  }
  return worst;
}

double PlausibleSim::collider_rows(double near, std::vector<ProjectionRow>& rows) {
  const int n = static_cast<int>(state_.position.cols());
  double worst = 0.0;  // m
  for (int i = 0; i < n; ++i) {
    if (model_.inverse_mass[i] == 0.0) continue;
    for (const Collider& collider : model_.colliders) {
      Vec3 normal;
      const double distance = collider_distance(collider, state_.position.col(i), normal);
      const double violation = collider_margin(i, normal) - distance;
      if (violation <= -near) continue;
      rows.push_back({-1, i, -normal, violation});
      worst = std::max(worst, violation);
      if (violation > 0.0 || state_.contact_push[i] > 0.0) {
        state_.contact_normal.col(i) = normal;
        state_.contact_friction[i] = collider.friction;
      }
    }
  }
  return worst;
}

void PlausibleSim::propagate_from_pins() {
  auto scope = profile_.scope("propagate");
  Positions& p = state_.position;
  // edges are grouped by their far ring (sorted by depth); a ring with two parents (4-in-1) takes
  // the mean of the projections onto each parent's sphere, so parents that are too far apart to
  // satisfy both pull it to a compromise instead of making it jump from one to the other
  const auto& edges = model_.outward;
  for (size_t first = 0; first < edges.size();) {
    size_t last = first;
    while (last < edges.size() && edges[last].b == edges[first].b) ++last;
    const int ring = edges[first].b;
    if (model_.inverse_mass[ring] != 0.0) {
      for (int pass = 0; pass < 2; ++pass) {
        Vec3 sum = Vec3::Zero();
        int count = 0;
        for (size_t k = first; k < last; ++k) {
          Vec3 corr0, corr1;
          if (solve_edge_constraint(p.col(edges[k].a), 0.0, p.col(ring), 1.0, edges[k].min_length,
                                    edges[k].max_length, corr0, corr1) > 0.0) {
            sum += corr1;
            ++count;
          }
        }
        if (count == 0) break;
        p.col(ring) += sum / static_cast<double>(last - first);
      }
    }
    first = last;
  }
}

double PlausibleSim::collider_margin(int ring, const Vec3& normal) const {
  if (model_.settings.contact_margin > 0.0) return model_.settings.contact_margin;
  // the torus reaches c sqrt(1 - (axis . n)^2) + a from its centre along n: a ring lying flat
  // needs a, one standing on its rim c + a (the orientation is the last step's)
  const Vec3 axis = state_.contact_axis.col(ring);
  const double along = std::min(1.0, std::abs(axis.dot(normal)));
  return model_.ring.wire_radius + model_.ring.centre_radius * std::sqrt(1.0 - along * along);
}

double PlausibleSim::collide() {
  auto scope = profile_.scope("colliders");
  const int n = static_cast<int>(state_.position.cols());
  const double reach = std::max(model_.settings.contact_margin,
                                model_.ring.wire_radius + model_.ring.centre_radius);  // m
  // each ring against every collider: rings are independent; the largest push, m
  return parallel_max(0, n, loop_threads(threads_, n), 0.0, [&](int i) {
    double pushed = 0.0;  // m
    if (model_.inverse_mass[i] == 0.0) return pushed;
    for (const Collider& collider : model_.colliders) {
      Vec3 normal;
      const double distance = collider_distance(collider, state_.position.col(i), normal);
      // no torus reaches farther than its outer radius: most rings end here, before the margin
      if (distance >= reach) continue;
      const double depth = collider_margin(i, normal) - distance;  // m
      if (depth <= 0.0) continue;
      state_.position.col(i) += depth * normal;
      state_.contact_push[i] += depth;
      state_.contact_normal.col(i) = normal;
      state_.contact_friction[i] = collider.friction;
      pushed = std::max(pushed, depth);
    }
    return pushed;
  });
}

double PlausibleSim::shaped_range(const RingPair& pair, const Vec3& normal) const {
  // each torus's convex hull reaches c sqrt(1 - (y . u)^2) + a from its centre along u (y its
  // axis): hulls that far apart along the line between the centres cannot overlap, so rings
  // lying face to face may come to 2a. The bound is conservative (a rim resting in another ring's
  // hole is closer) and reads the orientations the model derives from the centres, a guess where
  // a chain folds: it only lets a pair closer than repulsion_range, never holds one farther (held
  // to 2 (c + a) edge on, a dropped chain stands as a column twice as tall)
  const double c = model_.ring.centre_radius, a = model_.ring.wire_radius;  // m
  const double along_a = state_.ring_axis.col(pair.a).dot(normal);
  const double along_b = state_.ring_axis.col(pair.b).dot(normal);
  const double hull = 2.0 * a + c * (std::sqrt(std::max(0.0, 1.0 - along_a * along_a)) +
                                     std::sqrt(std::max(0.0, 1.0 - along_b * along_b)));
  return std::min(model_.repulsion_range, hull);
}

Vec3 PlausibleSim::slip_direction(const RingPair& pair, const Vec3& normal) const {
  // round rims pressed together slide toward the rings' faces, where the hulls let the pair come
  // closer: the push turns from the centre line toward each ring's axis by kContactSlip of the
  // axis's part across the line (the way the hull distance falls; edge on, where neither way
  // falls, the way the axis points: the tie a dropped chain meets, which real rings and the rigid
  // engines' faceted ones break by their imperfections)
  return slide_toward_faces(normal, state_.ring_axis.col(pair.a), state_.ring_axis.col(pair.b),
                            kContactSlip);
}

double PlausibleSim::solve_contacts() {
  auto scope = profile_.scope("self_contact");
  Positions& p = state_.position;
  const Positions& before = state_.previous;
  const std::vector<double>& w = model_.inverse_mass;
  const double range = model_.repulsion_range;
  const bool shaped = model_.shaped_contacts;
  return sweep_colours(state_.contact_colours, threads_, [&](int k) {
    const RingPair& pair = state_.contact_candidates[k];
    const double weight = w[pair.a] + w[pair.b];
    if (weight == 0.0) return 0.0;
    // apart along the direction the pair had at the start of the step: a ring that passed
    // through another during the step goes back to its own side (no tunnelling), and the
    // distance is at least the separation along that direction
    Vec3 normal = before.col(pair.b) - before.col(pair.a);
    // most candidates are far apart: decided without the square root and division
    if (clear_along(p.col(pair.b) - p.col(pair.a), normal, range)) return 0.0;
    if (normal.squaredNorm() < 1e-24) normal = p.col(pair.b) - p.col(pair.a);
    const double length = normal.norm();
    if (length < 1e-12) return 0.0;
    normal /= length;
    const double reach = shaped ? shaped_range(pair, normal) : range;        // m
    const double gap = (p.col(pair.b) - p.col(pair.a)).dot(normal) - reach;  // m, < 0 too close
    if (gap >= 0.0) return 0.0;
    Vec3 shift = (gap / weight) * normal;
    if (shaped) {
      // along the slip direction, by as much as closes the gap along the normal
      const Vec3 dir = slip_direction(pair, normal);
      shift = (gap / (weight * dir.dot(normal))) * dir;
    }
    p.col(pair.a) += w[pair.a] * shift;
    p.col(pair.b) -= w[pair.b] * shift;
    return -gap;
  });
}

}  // namespace chainmail
