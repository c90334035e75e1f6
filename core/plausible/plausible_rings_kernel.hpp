// The per-ring passes of core/plausible/plausible_rings.hpp over a lane type, four rings at a time:
// four consecutive rings are 12 consecutive doubles in each (3, n) array, and both passes work
// coordinate by coordinate, so the lanes take the array as it is, with each ring's mask spread
// over its coordinates. A range's last rings (fewer than four) go through the same code in a
// group of their own. Included by the kernel builds only (core/plausible/plausible_lanes.hpp), with
// L the lane type, CHAINMAIL_LANES_NAMESPACE the build's namespace and CHAINMAIL_LANES_FN and
// CHAINMAIL_LANES_INLINE its function attributes.
#include <algorithm>
#include <cstddef>

#include "core/plausible/plausible_rings.hpp"

namespace chainmail {
namespace CHAINMAIL_LANES_NAMESPACE {
namespace {

// the moves of the rings so far: per lane of each of the 12 coordinates' parts, and the
// farthest per ring
struct MoveLanes {
  L lo[3], hi[3], farthest2;
};

// rings i .. i + 3, free where `free` (the 12 coordinates' parts)
CHAINMAIL_LANES_INLINE void free_rings(RingArrays r, std::ptrdiff_t i, M free[3]) {
  spread(L::load(r.inverse_mass + i) != L::zero(), free);
}

// predict_rings on rings i .. i + 3; velocities_first: each ring's velocity from its move over
// the substep before (update_ring_velocities) first. fall: gravity's step in the coordinates'
// pattern. min(m, lo) and max(m, hi) keep lo and hi on a NaN move
template <bool velocities_first>
CHAINMAIL_LANES_INLINE void predict_group(RingArrays r, std::ptrdiff_t i, const L fall[3], L step,
                                          const double* anchor, MoveLanes& moves) {
  const std::ptrdiff_t at = 3 * i;
  M free[3];
  free_rings(r, i, free);
  L move[3] = {L::zero(), L::zero(), L::zero()};
  for (int k = 0; k < 3; ++k) {
    const L x = L::load(r.position + at + 4 * k);
    L v;
    if constexpr (velocities_first) {
      v = keep(free[k], (x - L::load(r.previous + at + 4 * k)) / step);  // pinned: +0
    } else {
      v = L::load(r.velocity + at + 4 * k);
    }
    store(r.previous + at + 4 * k, x);
    const L v_next = v + fall[k];
    const L x_next = blend(free[k], x + step * v_next, x);
    store(r.velocity + at + 4 * k, blend(free[k], v_next, v));
    store(r.position + at + 4 * k, x_next);
    if (anchor) move[k] = x_next - L::load(anchor + at + 4 * k);
  }
  store(r.contact_push + i, L::zero());
  if (!anchor) return;
  for (int k = 0; k < 3; ++k) {
    moves.lo[k] = lane_min(move[k], moves.lo[k]);
    moves.hi[k] = lane_max(move[k], moves.hi[k]);
  }
  const Rings<L> m = to_rings(move[0], move[1], move[2]);
  moves.farthest2 =
      lane_max((m.x * m.x + m.y * m.y) + m.z * m.z, moves.farthest2);  // squaredNorm's order
}

// update_ring_velocities on rings i .. i + 3
CHAINMAIL_LANES_INLINE void velocities_group(RingArrays r, std::ptrdiff_t i, L step) {
  const std::ptrdiff_t at = 3 * i;
  M free[3];
  free_rings(r, i, free);
  for (int k = 0; k < 3; ++k) {
    const L v = (L::load(r.position + at + 4 * k) - L::load(r.previous + at + 4 * k)) / step;
    store(r.velocity + at + 4 * k, keep(free[k], v));  // pinned: +0
  }
}

// rings [i, end), fewer than four, copied into a group of four: the last one repeated in the
// lanes beyond (the same values, so the same moves), and only the real ones written back
struct Tail {
  double position[12], velocity[12], previous[12], push[4], inverse_mass[4], anchor[12];
  RingArrays arrays() { return {position, velocity, previous, push, inverse_mass}; }
};

CHAINMAIL_LANES_INLINE void gather_tail(const RingArrays& r, int i, int end, const double* anchor,
                                        Tail& t) {
  for (int l = 0; l < 4; ++l) {
    const std::ptrdiff_t ring = std::min(i + l, end - 1);
    for (int c = 0; c < 3; ++c) {
      t.position[3 * l + c] = r.position[3 * ring + c];
      t.velocity[3 * l + c] = r.velocity[3 * ring + c];
      t.previous[3 * l + c] = r.previous[3 * ring + c];
      t.anchor[3 * l + c] = anchor ? anchor[3 * ring + c] : 0.0;
    }
    t.push[l] = r.contact_push[ring];
    t.inverse_mass[l] = r.inverse_mass[ring];
  }
}

CHAINMAIL_LANES_INLINE void scatter_tail(const Tail& t, const RingArrays& r, int i, int end) {
  for (int l = 0; l < end - i; ++l) {
    const std::ptrdiff_t ring = i + l;
    for (int c = 0; c < 3; ++c) {
      r.position[3 * ring + c] = t.position[3 * l + c];
      r.velocity[3 * ring + c] = t.velocity[3 * l + c];
      r.previous[3 * ring + c] = t.previous[3 * l + c];
    }
    r.contact_push[ring] = t.push[l];
  }
}

// the lanes' moves joined into `moves` (lane l of part k holds coordinate (4 k + l) mod 3)
CHAINMAIL_LANES_INLINE void join_lanes(const MoveLanes& lanes, RingMoves& moves) {
  double lane[4];
  store(lane, lanes.farthest2);
  for (double v : lane) moves.farthest2 = std::max(moves.farthest2, v);
  for (int k = 0; k < 3; ++k) {
    store(lane, lanes.lo[k]);
    for (int l = 0; l < 4; ++l)
      moves.lo[(4 * k + l) % 3] = std::min(moves.lo[(4 * k + l) % 3], lane[l]);
    store(lane, lanes.hi[k]);
    for (int l = 0; l < 4; ++l)
      moves.hi[(4 * k + l) % 3] = std::max(moves.hi[(4 * k + l) % 3], lane[l]);
  }
}

template <bool velocities_first>
CHAINMAIL_LANES_FN RingMoves predict(const RingArrays& rings, const Vec3& fall, double h, int begin,
                                     int end, const double* anchor) {
  // gravity's step in the 12-coordinate pattern
  const L fall_part[3] = {L::set(fall.x(), fall.y(), fall.z(), fall.x()),
                          L::set(fall.y(), fall.z(), fall.x(), fall.y()),
                          L::set(fall.z(), fall.x(), fall.y(), fall.z())};
  const L step = L::splat(h);
  const RingArrays r = rings;  // the pointers in registers: no store can move them
  MoveLanes lanes;
  for (int k = 0; k < 3; ++k) lanes.lo[k] = L::splat(RingMoves::kInf);
  for (int k = 0; k < 3; ++k) lanes.hi[k] = L::splat(-RingMoves::kInf);
  lanes.farthest2 = L::zero();
  int i = begin;
  for (; i + 4 <= end; i += 4)
    predict_group<velocities_first>(r, i, fall_part, step, anchor, lanes);
  if (i < end) {
    Tail t;
    gather_tail(r, i, end, anchor, t);
    predict_group<velocities_first>(t.arrays(), 0, fall_part, step, anchor ? t.anchor : nullptr,
                                    lanes);
    scatter_tail(t, r, i, end);
  }
  RingMoves moves;
  if (anchor) join_lanes(lanes, moves);
  return moves;
}

CHAINMAIL_LANES_FN RingMoves predict_rings(const RingArrays& r, const Vec3& fall, double h,
                                           int begin, int end, const double* anchor) {
  return predict<false>(r, fall, h, begin, end, anchor);
}

CHAINMAIL_LANES_FN RingMoves update_velocities_and_predict(const RingArrays& r, const Vec3& fall,
                                                           double h, int begin, int end,
                                                           const double* anchor) {
  return predict<true>(r, fall, h, begin, end, anchor);
}

CHAINMAIL_LANES_FN void update_ring_velocities(const RingArrays& rings, double h, int begin,
                                               int end) {
  const L step = L::splat(h);
  const RingArrays r = rings;  // as in predict
  int i = begin;
  for (; i + 4 <= end; i += 4) velocities_group(r, i, step);
  if (i < end) {
    Tail t;
    gather_tail(r, i, end, nullptr, t);
    velocities_group(t.arrays(), 0, step);
    scatter_tail(t, r, i, end);
  }
}

}  // namespace
}  // namespace CHAINMAIL_LANES_NAMESPACE
}  // namespace chainmail
