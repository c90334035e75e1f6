#include "core/plausible/orientation.hpp"
#include "core/parallel.hpp"

#include "core/geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

namespace chainmail {
namespace {

Quat quat_at(const Orientations& o, int i) {
  return Quat(o(0, i), o(1, i), o(2, i), o(3, i));
}
void store(Orientations& o, int i, const Quat& q) {
  o.col(i) << q.w(), q.x(), q.y(), q.z();
}

// direction along one grid axis: opposite neighbour to opposite neighbour for interior rings,
// centre to the one neighbour on edges; false when the ring has no neighbour on that axis
bool axis_vector(const Positions& p, int ring, int minus, int plus, Vec3& out, double& spacing) {
  if (minus >= 0 && plus >= 0) {
    out = p.col(plus) - p.col(minus);
    spacing = 0.5 * out.norm();
  } else if (plus >= 0) {
    out = p.col(plus) - p.col(ring);
    spacing = out.norm();
  } else if (minus >= 0) {
    out = p.col(ring) - p.col(minus);
    spacing = out.norm();
  } else {
    return false;
  }
  return spacing > 1e-15;
}

// one ring's neighbour directions along the two grid axes: unit vectors and spacings, m
struct GridAxes {
  Vec3 x = Vec3::Zero(), z = Vec3::Zero();
  double dx = 0.0, dz = 0.0;
  bool has_x = false, has_z = false;
};

// fills the axis `g` lacks from the first neighbour (on the axis it has) that has it, with that
// spacing taken as its own; false when no neighbour has it
bool borrow_axis(const std::vector<GridAxes>& axes, const std::array<int, 4>& nb, GridAxes& g) {
  if (g.has_x && g.has_z) return true;
  const int first = g.has_x ? 0 : 2;
  for (int k = first; k < first + 2; ++k) {
    if (nb[k] < 0) continue;
    const GridAxes& other = axes[nb[k]];
    if (g.has_x && other.has_z) {
      g.z = other.z, g.dz = g.dx, g.has_z = true;
      return true;
    }
    if (g.has_z && other.has_x) {
      g.x = other.x, g.dx = g.dz, g.has_x = true;
      return true;
    }
  }
  return false;
}

Circle circle_of(const Positions& p, const Orientations& o, int i, double c) {
  return ring_circle(p.col(i), quat_at(o, i), c);
}

// circles_linked, the cheap test first (most candidate turns fail it)
bool linked_fast(const Circle& mine, const Circle& theirs) {
  return circles_may_link(mine, theirs) && circles_linked(mine, theirs);
}

// neighbours of ring i whose centre circle links ring i's when ring i has orientation q
int linked_count(const Positions& p, const Weave& weave, const Orientations& o, int i,
                 const Quat& q, double c) {
  const Circle mine = ring_circle(p.col(i), q, c);
  int count = 0;
  for (int k : weave.neighbours[i]) {
    if (k >= 0) count += linked_fast(mine, circle_of(p, o, k, c));
  }
  return count;
}

int neighbour_count(const Weave& weave, int i) {
  int count = 0;
  for (int k : weave.neighbours[i]) count += k >= 0;
  return count;
}

// neighbours set in a mask of the four neighbour slots (std::popcount compiles to a library call
// where the target has no popcount instruction, and the searches count a mask for every turn)
constexpr int slots_set(unsigned mask) {
  return static_cast<int>((mask & 1u) + (mask >> 1 & 1u) + (mask >> 2 & 1u) + (mask >> 3 & 1u));
}

// one ring's candidate turns about its local X and Z axes, 7.5 degrees apart up to 90 either way,
// in the grid's order (a-major), each with the neighbours it links as bits by neighbour slot.
// With `enough`, the search goes by size of turn and stops at the first turn linking that many
// neighbours: no turn met later is larger in links or smaller in turn, so the choice is the whole
// grid's; the turns not searched have links kUnsearched. With `floor`, a turn that cannot link
// more neighbours than that is not tested exactly and counts none (no search that sets it can
// choose it)
struct TurnCandidates {
  static constexpr std::uint8_t kUnsearched = 0xff;
  std::vector<Quat> q;
  std::vector<std::uint8_t> links;
  // neighbours linked by turn a, the neighbour in `skip` (a slot, or -1) left out; -1 unsearched
  int linked(int a, int skip) const {
    if (links[a] == kUnsearched) return -1;
    return slots_set(skip < 0 ? links[a] : links[a] & ~(1u << skip));
  }
};

constexpr int kTurnSteps = 12;
constexpr int kTurnSide = 2 * kTurnSteps + 1;

// the size of a grid cell's turn, a^2 + b^2 in steps about local X and Z (cells a-major): the
// nearest turn is the smallest
int turn_size(int cell) {
  const int a = cell / kTurnSide - kTurnSteps, b = cell % kTurnSide - kTurnSteps;
  return a * a + b * b;
}

TurnCandidates turn_candidates(const Positions& p, const Weave& weave, const Orientations& o, int i,
                               double c, int enough = 5, int floor = -1) {
  constexpr double kStep = 7.5 * std::numbers::pi / 180;  // rad
  // the turns about local X and Z once, and the grid's cells by size of turn, then grid order
  // (the products below keep their order, so their bits)
  static const std::array<std::array<Quat, kTurnSide>, 2> turns = [] {
    std::array<std::array<Quat, kTurnSide>, 2> t;
    for (int a = -kTurnSteps; a <= kTurnSteps; ++a) {
      t[0][a + kTurnSteps] = Quat(Eigen::AngleAxisd(a * kStep, Vec3::UnitX()));
      t[1][a + kTurnSteps] = Quat(Eigen::AngleAxisd(a * kStep, Vec3::UnitZ()));
    }
    return t;
  }();
  static const std::array<int, kTurnSide* kTurnSide> by_turn = [] {
    std::array<int, kTurnSide * kTurnSide> order;
    for (int k = 0; k < kTurnSide * kTurnSide; ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [](int x, int y) { return turn_size(x) < turn_size(y); });
    return order;
  }();
  TurnCandidates out;
  out.q.resize(kTurnSide * kTurnSide);
  out.links.assign(kTurnSide * kTurnSide, TurnCandidates::kUnsearched);
  const Quat q0 = quat_at(o, i);
  std::array<Circle, 4> theirs;
  std::array<int, 4> slot;
  int count = 0;
  for (int s = 0; s < 4; ++s) {
    const int k = weave.neighbours[i][s];
    if (k >= 0) theirs[count] = circle_of(p, o, k, c), slot[count++] = s;
  }
  for (const int cell : by_turn) {
    const Quat q = q0 * turns[0][cell / kTurnSide] * turns[1][cell % kTurnSide];
    const Circle mine = ring_circle(p.col(i), q, c);
    // the cheap test first; the exact one only where the turn could link more than `floor`
    unsigned maybe = 0, links = 0;
    for (int k = 0; k < count; ++k) maybe |= unsigned{circles_may_link(mine, theirs[k])} << k;
    if (slots_set(maybe) > floor) {
      for (int k = 0; k < count; ++k) {
        if (maybe >> k & 1u) links |= unsigned{circles_linked(mine, theirs[k])} << slot[k];
      }
    }
    out.q[cell] = q, out.links[cell] = static_cast<std::uint8_t>(links);
    if (slots_set(links) >= enough) break;
  }
  return out;
}

int slot_of(const Weave& weave, int i, int k) {
  for (int s = 0; s < 4; ++s) {
    if (weave.neighbours[i][s] == k) return s;
  }
  return -1;
}

// turns a linked pair (i, k) that neither ring can link alone without losing another link: both
// together, to the nearest pair of turns that links the most of their neighbours; true if turned
bool turn_pair(const Positions& p, const Weave& weave, Orientations& o, int i, int k, double c) {
  const TurnCandidates ti = turn_candidates(p, weave, o, i, c);
  const TurnCandidates tk = turn_candidates(p, weave, o, k, c);
  const int skip_i = slot_of(weave, i, k), skip_k = slot_of(weave, k, i);
  const int size = static_cast<int>(ti.q.size());
  std::vector<int> li(size), lk(size);  // neighbours linked, the partner left out
  for (int a = 0; a < size; ++a) li[a] = ti.linked(a, skip_i), lk[a] = tk.linked(a, skip_k);
  const int now = linked_count(p, weave, o, i, quat_at(o, i), c) +
                  linked_count(p, weave, o, k, quat_at(o, k), c);
  // the most links, then the least turn, then the first in the grids' order; the candidates go
  // by links, most first, so that the search stops where even a linked pair cannot reach the best
  const auto by_links = [size](const std::vector<int>& linked) {
    std::vector<int> order(size);
    for (int a = 0; a < size; ++a) order[a] = a;
    std::stable_sort(order.begin(), order.end(),
                     [&](int x, int y) { return linked[x] > linked[y]; });
    return order;
  };
  const std::vector<int> order_i = by_links(li), order_k = by_links(lk);
  const int most_k = lk[order_k.front()];
  // nothing can link more than now: no turn
  if (li[order_i.front()] + most_k + 2 <= now) return false;
  // the parts of circles_may_link that read one ring's turn alone, once a turn: each circle
  // passing near the other ring's centre
  std::vector<Circle> theirs(size);
  std::vector<char> near_i(size);
  for (int b = 0; b < size; ++b) {
    theirs[b] = ring_circle(p.col(k), tk.q[b], c);
    near_i[b] = circle_may_pass_within_radius(theirs[b], p.col(i));
  }
  int best = now, bi = -1, bk = -1;
  int best_turn = 0;
  for (const int a : order_i) {
    if (li[a] + most_k + 2 < best) break;  // neither this nor any later can win
    const Circle mine = ring_circle(p.col(i), ti.q[a], c);
    const bool may = circle_may_pass_within_radius(mine, p.col(k));
    // what linking the pair can add: nothing where no turn of k links this turn of i
    const int bonus = may ? 2 : 0;
    for (const int b : order_k) {
      if (li[a] + lk[b] + bonus < best) break;
      // at most a tie on links, which a larger turn loses
      if (bi >= 0 && li[a] + lk[b] + bonus == best && turn_size(a) + turn_size(b) > best_turn)
        continue;
      const bool linked = may && near_i[b] && linked_fast(mine, theirs[b]);
      const int score = li[a] + lk[b] + 2 * linked;
      const int turn = turn_size(a) + turn_size(b);
      const bool better =
          score > best ||
          (score == best && bi >= 0 &&
           (turn < best_turn || (turn == best_turn && (a < bi || (a == bi && b < bk)))));
      if (better) best = score, bi = a, bk = b, best_turn = turn;
    }
  }
  if (bi < 0) return false;
  store(o, i, ti.q[bi].normalized());
  store(o, k, tk.q[bk].normalized());
  return true;
}

}  // namespace

int keep_links(const Positions& position, const Weave& weave, const RingGeometry& ring,
               Orientations& orientation) {
  const double c = ring.centre_radius;
  const int n = weave.size();
  int turned = 0;
  // a search reads only the orientations of its rings and their neighbours: one that found no turn
  // finds none again until one of those turns, and the second round skips it. turned_at: the
  // count of turns when the ring last turned; the stamps: the count when a search found nothing
  std::vector<int> turned_at(n, 0), ring_stamp(n, -1);
  std::vector<std::array<int, 4>> pair_stamp(n, {-1, -1, -1, -1});  // by neighbour slot
  const auto unchanged = [&](int i, int stamp) {
    if (stamp < 0 || turned_at[i] > stamp) return false;
    for (int k : weave.neighbours[i]) {
      if (k >= 0 && turned_at[k] > stamp) return false;
    }
    return true;
  };
  // two rounds: a ring's best turn depends on its neighbours', turned in the round before
  for (int round = 0; round < 2; ++round) {
    for (int i = 0; i < n; ++i) {
      if (unchanged(i, ring_stamp[i])) continue;
      const int now = linked_count(position, weave, orientation, i, quat_at(orientation, i), c);
      const int all = neighbour_count(weave, i);
      if (now == all) continue;
      const TurnCandidates ci = turn_candidates(position, weave, orientation, i, c, all, now);
      int best = -1;
      for (int a = 0; a < static_cast<int>(ci.q.size()); ++a) {
        const int linked = ci.linked(a, -1);
        if (linked <= now) continue;
        if (best < 0 || linked > ci.linked(best, -1) ||
            (linked == ci.linked(best, -1) && turn_size(a) < turn_size(best))) {
          best = a;
        }
      }
      if (best < 0) {
        ring_stamp[i] = turned;
        continue;
      }
      store(orientation, i, ci.q[best].normalized());
      turned_at[i] = ++turned;
    }
    // pairs still apart: each ring links its other neighbours and would lose one to link this one
    for (int i = 0; i < n; ++i) {
      for (int slot = 0; slot < 4; ++slot) {
        const int k = weave.neighbours[i][slot];
        if (k <= i || linked_fast(circle_of(position, orientation, i, c),
                                  circle_of(position, orientation, k, c))) {
          continue;
        }
        const int stamp = pair_stamp[i][slot];
        if (unchanged(i, stamp) && unchanged(k, stamp)) continue;
        if (!turn_pair(position, weave, orientation, i, k, c)) {
          pair_stamp[i][slot] = turned;
          continue;
        }
        ++turned;
        turned_at[i] = turned_at[k] = turned;
      }
    }
  }
  return turned;
}

Mat3 basis_from_unit_axes(const Vec3& xn, const Vec3& zn, const Vec3& y) {
  // eq. (1): the bisector of x and z and its perpendicular in their plane, rotated back by 45
  // degrees; v45 and v135 are orthonormal, so their sum has length sqrt(2) exactly
  const Vec3 v45 = (xn + zn).normalized();
  const Vec3 v135 = y.cross(v45);
  Mat3 basis;
  basis.col(0) = (v45 + v135) * std::numbers::sqrt2 * 0.5;
  basis.col(1) = y;
  basis.col(2) = basis.col(0).cross(y);
  return basis;
}

Mat3 orthonormal_basis_eq1(const Vec3& x, const Vec3& z) {
  const Vec3 xn = x.normalized(), zn = z.normalized();
  const Vec3 y = zn.cross(xn).normalized();
  return basis_from_unit_axes(xn, zn, y);
}

double swivel_angle(double ratio, double min_ratio, double extended) {
  const double compressed = 0.5 * std::numbers::pi;
  const double t = std::clamp((1.0 - ratio) / (1.0 - min_ratio), 0.0, 1.0);
  return extended + t * (compressed - extended);
}

double fitted_extended_swivel(const RingGeometry& ring, double max_link_distance) {
  // one ring at the origin with the identity basis (neighbours along local X and Z) swivelled by
  // +theta about (1, 0, -1)/sqrt(2); its neighbours swivelled by -theta about the same axis
  const Vec3 axis = Vec3(1.0, 0.0, -1.0).normalized();
  const double d = max_link_distance, c = ring.centre_radius;
  auto clearance = [&](double theta) {
    const Quat mine(Eigen::AngleAxisd(theta, axis)), theirs(Eigen::AngleAxisd(-theta, axis));
    const Circle centre = ring_circle(Vec3::Zero(), mine, c);
    double worst = std::numeric_limits<double>::infinity();
    for (const Vec3& offset : {Vec3(d, 0.0, 0.0), Vec3(0.0, 0.0, d)}) {
      const Circle other = ring_circle(offset, theirs, c);
      if (!circles_linked(centre, other)) return -std::numeric_limits<double>::infinity();
      worst = std::min(worst, circle_circle_distance(centre, other));
    }
    return worst;
  };
  // coarse scan, then golden-section refinement around the best sample
  constexpr int kSamples = 90;
  const double step = 0.5 * std::numbers::pi / kSamples;
  int best = 0;
  double best_clearance = -std::numeric_limits<double>::infinity();
  for (int k = 0; k <= kSamples; ++k) {
    const double value = clearance(k * step);
    if (value > best_clearance) best_clearance = value, best = k;
  }
  double lo = std::max(0.0, (best - 1) * step);
  double hi = std::min(0.5 * std::numbers::pi, (best + 1) * step);
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int k = 0; k < 40; ++k) {
    const double m1 = hi - ratio * (hi - lo), m2 = lo + ratio * (hi - lo);
    if (clearance(m1) < clearance(m2)) {
      lo = m1;
    } else {
      hi = m2;
    }
  }
  return 0.5 * (lo + hi);
}

Vec3 swivel_hinge(const Vec3& pull) {
  const Vec3 normal = Vec3(1.0, 0.0, -1.0).normalized(), along = Vec3(1.0, 0.0, 1.0).normalized();
  double turn = std::atan2(pull.dot(along), pull.dot(normal));  // (-pi, pi]
  // a hinge is a line: the pull's direction or its opposite, whichever is nearer the row normal
  if (turn > 0.5 * std::numbers::pi) turn -= std::numbers::pi;
  if (turn < -0.5 * std::numbers::pi) turn += std::numbers::pi;
  turn = std::clamp(turn, -kMaxHingeTurn, kMaxHingeTurn);
  return std::cos(turn) * normal + std::sin(turn) * along;
}

void orient_rings(const Positions& position, const Weave& weave, const RingGeometry& ring,
                  const OrientationSettings& settings, Orientations& orientation) {
  const int n = weave.size();

  if (weave.type == WeaveType::chain) {
    // chain: x along the chain; each ring's axis perpendicular to the chain and to its
    // predecessor's axis, so links alternate by quarter turns; the first follows its old axis
    Vec3 previous_axis = Vec3::Zero();
    for (int k = 0; k < n; ++k) {
      Vec3 x;
      double spacing;
      if (!axis_vector(position, k, weave.neighbours[k][0], weave.neighbours[k][1], x, spacing)) {
        continue;
      }
      x.normalize();
      Vec3 y = k == 0 ? Vec3(quat_at(orientation, k) * Vec3::UnitY()) : x.cross(previous_axis);
      y -= y.dot(x) * x;
      if (y.norm() < 1e-9) y = x.unitOrthogonal();
      y.normalize();
      Mat3 basis;
      basis.col(0) = x, basis.col(1) = y, basis.col(2) = x.cross(y);
      store(orientation, k, Quat(basis).normalized());
      previous_axis = y;
    }
    return;
  }

  const double min_ratio = ring.min_link_distance() / settings.max_link_distance;
  const double extended =
      settings.extended_angle > 0.0 ? settings.extended_angle : paper_extended_swivel(ring);
  // neighbour vectors along both grid axes (X from (i-1,j)->(i+1,j), Z from (i,j-1)->(i,j+1)),
  // unit, with the neighbour spacing along each
  std::vector<GridAxes> axes(n);
  const int threads = loop_threads(settings.threads, n);
  parallel_for(0, n, threads, [&](int i) {
    const auto& nb = weave.neighbours[i];
    GridAxes& g = axes[i];
    g.has_x = axis_vector(position, i, nb[0], nb[1], g.x, g.dx);
    g.has_z = axis_vector(position, i, nb[2], nb[3], g.z, g.dz);
    if (g.has_x) g.x /= nb[0] >= 0 && nb[1] >= 0 ? 2.0 * g.dx : g.dx;
    if (g.has_z) g.z /= nb[2] >= 0 && nb[3] >= 0 ? 2.0 * g.dz : g.dz;
  });
  parallel_for(0, n, threads, [&](int i) {
    const auto& nb = weave.neighbours[i];
    // a ring with neighbours on one axis only (a sheet's corner) borrows the other axis from a
    // neighbour that has it: taken from positions alone, never from its own last orientation,
    // which would compose last step's swivel again every step
    GridAxes g = axes[i];
    if (!g.has_x && !g.has_z) return;
    if (!borrow_axis(axes, nb, g)) return;
    const Vec3 xn = g.x, zn = g.z;
    const double dx = g.dx, dz = g.dz;
    const Vec3 normal = zn.cross(xn);
    const double sine = normal.norm();
    if (sine < 1e-6) return;  // x and z (anti)parallel: degenerate, keep the old orientation
    const Mat3 basis = basis_from_unit_axes(xn, zn, normal / sine);
    Quat q(basis);

    if (settings.swivel && weave.type == WeaveType::four_in_one) {
      // swivel about the axis weighted by the neighbour distances along each grid direction
      // (equal distances: the row normal, about which European 4-in-1 rows lean); the angle grows
      // from a/c at full extension to pi/2 under compression; its sign alternates by row.
      // In the ring's own frame that axis is (dx, 0, -dz) / |.|: the swivel composes on the right
      const double ratio = 0.5 * (dx + dz) / settings.max_link_distance;
      const double theta = weave.parity[i] * swivel_angle(ratio, min_ratio, extended);
      const Vec3 pull = settings.pull ? Vec3(settings.pull->col(i)) : Vec3::Zero();
      if (pull.squaredNorm() > 0.0) {
        // the hinge from the pins (paper §6): the pull in the ring's own frame
        q = q * Quat(Eigen::AngleAxisd(theta, swivel_hinge(basis.transpose() * pull)));
      } else {
        const double half_sin = std::sin(0.5 * theta) / std::hypot(dx, dz);
        q = q * Quat(std::cos(0.5 * theta), half_sin * dx, 0.0, -half_sin * dz);
      }
    }
    store(orientation, i, q.normalized());
  });
}

}  // namespace chainmail
