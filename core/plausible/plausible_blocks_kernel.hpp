// The sweeps' blocks of core/plausible/plausible_blocks.hpp over a lane type: a group of four pairs
// or attachments per lane group, each lane doing solve_edge_constraint's (or
// solve_attachment_constraint's) arithmetic in its order; single pairs go through sweep_pair.
// Included by the kernel builds only, as core/plausible/plausible_rings_kernel.hpp.
#include <algorithm>
#include <cstddef>

#include "core/plausible/plausible_blocks.hpp"
#include "core/plausible/plausible_sweep.hpp"

namespace chainmail {
namespace CHAINMAIL_LANES_NAMESPACE {
namespace {

// solve_edge_constraint in four lanes (no weight is zero: blocks hold no pin), from the squared
// lengths on: whether any lane moves, and if so each lane's share of the difference vector for
// either ring (s0, s1: corr0 = s0 d, corr1 = s1 d) where `active`. worst takes the lanes'
// violations (max(v, worst) keeps worst on a NaN, as std::max(worst, v) does)
struct LaneCorrection {
  M active;
  L s0, s1;
};
CHAINMAIL_LANES_INLINE bool correct_lanes(L length2, L w0, L w1, L min_length, L max_length,
                                          L& worst, LaneCorrection& out) {
  const L max2 = max_length * max_length, min2 = min_length * min_length;
  const M within = (length2 <= max2) & (length2 >= min2);
  if (all(within)) return false;  // the usual case
  // the lanes out of bounds (a NaN too, as in the scalar test), not degenerate
  M active = and_not(within, not_less(length2, L::splat(1e-30)));
  const L length = sqrt(length2);
  const L target = blend(length2 > max2, max_length, min_length);
  const L error = length - target;
  const L scale = error / (length * (w0 + w1));
  const L violation = abs(error);
  active = active & (violation != L::zero());
  if (!any(active)) return false;
  out.active = active;
  out.s0 = w0 * scale;
  out.s1 = -(w1 * scale);
  worst = lane_max(keep(active, violation), worst);
  return true;
}

// the same on rings in lanes
CHAINMAIL_LANES_INLINE bool solve_lanes(Rings<L>& p0, Rings<L>& p1, L w0, L w1, L min_length,
                                        L max_length, L& worst) {
  const L dx = p1.x - p0.x, dy = p1.y - p0.y, dz = p1.z - p0.z;
  const L length2 = (dx * dx + dy * dy) + dz * dz;  // squaredNorm's order
  LaneCorrection c;
  if (!correct_lanes(length2, w0, w1, min_length, max_length, worst, c)) return false;
  p0 = {blend(c.active, p0.x + c.s0 * dx, p0.x), blend(c.active, p0.y + c.s0 * dy, p0.y),
        blend(c.active, p0.z + c.s0 * dz, p0.z)};
  p1 = {blend(c.active, p1.x + c.s1 * dx, p1.x), blend(c.active, p1.y + c.s1 * dy, p1.y),
        blend(c.active, p1.z + c.s1 * dz, p1.z)};
  return true;
}

// the block's bounds in lanes holding its pairs `first`, `second`, ... (shared, or the pairs')
struct LaneBounds {
  L min_length, max_length;  // m
};
CHAINMAIL_LANES_INLINE LaneBounds lane_bounds(const EdgeConstraint* pairs, const PairBlock& block,
                                              int first, int second, int third, int fourth) {
  if (block.shared_bounds) return {L::splat(block.min_length), L::splat(block.max_length)};
  const EdgeConstraint* f = pairs + block.pair;
  return {
      L::set(f[first].min_length, f[second].min_length, f[third].min_length, f[fourth].min_length),
      L::set(f[first].max_length, f[second].max_length, f[third].max_length, f[fourth].max_length)};
}

// the squared lengths, in lanes, of four differences held in the array's order
CHAINMAIL_LANES_INLINE L squared_lengths(const L d[3]) {
  const Rings<L> square = to_rings(d[0] * d[0], d[1] * d[1], d[2] * d[2]);
  return (square.x + square.y) + square.z;  // squaredNorm's order
}

// four rings r (in the array's order, at p) moved by each lane's scale of its difference d where
// `active`, stored back
CHAINMAIL_LANES_INLINE void store_moved(double* p, const L r[3], const L d[3], L scale,
                                        const M active[3]) {
  L spread_scale[3];
  spread(scale, spread_scale);
  for (int k = 0; k < 3; ++k)
    store(p + 4 * k, blend(active[k], r[k] + spread_scale[k] * d[k], r[k]));
}

// pairs (a + i, b + i). Both runs of four rings are 12 consecutive coordinates in the same order,
// so the differences and their squares are taken as the array holds them, and only the squares
// are turned into lanes for the test (the same values as in lanes, so the same bits); a block
// within its bounds, the usual case, ends there. The corrections go back the same way: each
// lane's share spread over its ring's three coordinates
CHAINMAIL_LANES_INLINE void solve_run(double* x, const double* w, int a, int b,
                                      const LaneBounds& bounds, L& worst) {
  double* const p0 = x + 3 * static_cast<std::ptrdiff_t>(a);
  double* const p1 = x + 3 * static_cast<std::ptrdiff_t>(b);
  L r0[3], r1[3], d[3];
  for (int k = 0; k < 3; ++k) {
    r0[k] = L::load(p0 + 4 * k);
    r1[k] = L::load(p1 + 4 * k);
    d[k] = r1[k] - r0[k];
  }
  LaneCorrection c;
  if (!correct_lanes(squared_lengths(d), L::load(w + a), L::load(w + b), bounds.min_length,
                     bounds.max_length, worst, c)) {
    return;
  }
  M active[3];
  spread(c.active, active);
  store_moved(p0, r0, d, c.s0, active);
  store_moved(p1, r1, d, c.s1, active);
}

// pairs (a + 2 i, a + 2 i + 1): rings a .. a + 7, the even ones one side, the odd the other (the
// lanes hold pairs 0, 2, 1, 3: unpacking keeps 128-bit halves apart, and lanes are independent)
CHAINMAIL_LANES_INLINE void solve_adjacent(double* x, const double* w, int a,
                                           const LaneBounds& bounds, L& worst) {
  double* const p = x + 3 * static_cast<std::ptrdiff_t>(a);
  const Rings<L> low = L::load_rings(p), high = L::load_rings(p + 12);
  Rings<L> even{unpack_lo(low.x, high.x), unpack_lo(low.y, high.y), unpack_lo(low.z, high.z)};
  Rings<L> odd{unpack_hi(low.x, high.x), unpack_hi(low.y, high.y), unpack_hi(low.z, high.z)};
  const L w_low = L::load(w + a), w_high = L::load(w + a + 4);
  if (!solve_lanes(even, odd, unpack_lo(w_low, w_high), unpack_hi(w_low, w_high), bounds.min_length,
                   bounds.max_length, worst)) {
    return;
  }
  store_rings(p, {unpack_lo(even.x, odd.x), unpack_lo(even.y, odd.y), unpack_lo(even.z, odd.z)});
  store_rings(p + 12,
              {unpack_hi(even.x, odd.x), unpack_hi(even.y, odd.y), unpack_hi(even.z, odd.z)});
}

// the largest of the lanes' violations and worst
CHAINMAIL_LANES_INLINE double join_worst(L lanes_worst, double worst) {
  double lane[4];
  store(lane, lanes_worst);
  for (double v : lane) worst = std::max(worst, v);
  return worst;
}

CHAINMAIL_LANES_FN double sweep_pair_blocks(double* x, const double* w, const EdgeConstraint* pairs,
                                            const PairBlock* blocks, int count) {
  L lanes_worst = L::zero();  // m
  double worst = 0.0;         // m
  for (int k = 0; k < count; ++k) {
    const PairBlock& block = blocks[k];
    switch (block.kind) {
      case PairBlock::Kind::run: {
        const LaneBounds bounds = lane_bounds(pairs, block, 0, 1, 2, 3);
        for (int g = 0; g < block.groups; ++g) {
          solve_run(x, w, block.a + 4 * g, block.b + 4 * g, bounds, lanes_worst);
        }
        break;
      }
      case PairBlock::Kind::adjacent: {
        const LaneBounds bounds = lane_bounds(pairs, block, 0, 2, 1, 3);
        for (int g = 0; g < block.groups; ++g) {
          solve_adjacent(x, w, block.a + 8 * g, bounds, lanes_worst);
        }
        break;
      }
      case PairBlock::Kind::single:
        worst = std::max(worst, sweep_pair(x, w, pairs[block.pair]));
        break;
    }
  }
  return join_worst(lanes_worst, worst);
}

// the attachments' test from the squared lengths on: whether any lane moves, and if so each
// lane's share of the difference vector (corr = scale d) where `active`
CHAINMAIL_LANES_INLINE bool attachment_scale(L length2, L reach, L& worst, M& active, L& scale) {
  const M within = length2 <= reach * reach;
  if (all(within)) return false;  // the usual case
  const L length = sqrt(length2);
  const L violation = length - reach;
  // moved where the violation is positive (not on a NaN, as in the scalar sweep)
  active = and_not(within, violation > L::zero());
  if (!any(active)) return false;
  scale = (reach - length) / length;
  worst = lane_max(keep(active, violation), worst);
  return true;
}

// a group of four consecutive rings p hanging from four consecutive pins q: rings and pins hold
// their coordinates in the same order, so the differences and their squares are taken as the
// array holds them and only the squares turned into lanes for the test (the same values as in
// lanes); the corrections go back the same way (each lane's scale over its ring's coordinates)
CHAINMAIL_LANES_INLINE void solve_attachment_pin_run(double* p, const double* q, L reach,
                                                     L& worst) {
  L r[3], d[3];
  for (int k = 0; k < 3; ++k) {
    r[k] = L::load(p + 4 * k);
    d[k] = r[k] - L::load(q + 4 * k);
  }
  M active;
  L scale;
  if (!attachment_scale(squared_lengths(d), reach, worst, active, scale)) return;
  M spread_active[3];
  spread(active, spread_active);
  store_moved(p, r, d, scale, spread_active);
}

// a group of four consecutive rings p and the attachments f, their pins anywhere
CHAINMAIL_LANES_INLINE void solve_attachment_group(double* x, double* p, const PinAttachment* f,
                                                   L reach, L& worst) {
  const Rings<L> rings = L::load_rings(p);
  const int pin[4] = {f[0].pin, f[1].pin, f[2].pin, f[3].pin};
  const Rings<L> pins = L::gather_rings(x, pin);
  const L dx = rings.x - pins.x, dy = rings.y - pins.y, dz = rings.z - pins.z;
  const L length2 = (dx * dx + dy * dy) + dz * dz;
  M active;
  L scale;
  if (!attachment_scale(length2, reach, worst, active, scale)) return;
  store_rings(p, {blend(active, rings.x + scale * dx, rings.x),
                  blend(active, rings.y + scale * dy, rings.y),
                  blend(active, rings.z + scale * dz, rings.z)});
}

CHAINMAIL_LANES_FN double sweep_attachment_blocks(double* x, const PinAttachment* list,
                                                  const double* reach,
                                                  const AttachmentBlock* blocks, int count) {
  L lanes_worst = L::zero();  // m
  double worst = 0.0;         // m
  for (int k = 0; k < count; ++k) {
    const AttachmentBlock& block = blocks[k];
    const PinAttachment* const f = list + block.item;
    if (block.groups == 0) {
      worst = std::max(worst, sweep_attachment(x, *f));
      continue;
    }
    double* const p = x + 3 * static_cast<std::ptrdiff_t>(f->ring);
    const double* const r = reach + block.item;
    if (block.pin_run) {
      const double* const q = x + 3 * static_cast<std::ptrdiff_t>(f->pin);
      for (int g = 0; g < block.groups; ++g) {
        solve_attachment_pin_run(p + 12 * g, q + 12 * g, L::load(r + 4 * g), lanes_worst);
      }
    } else {
      for (int g = 0; g < block.groups; ++g) {
        solve_attachment_group(x, p + 12 * g, f + 4 * g, L::load(r + 4 * g), lanes_worst);
      }
    }
  }
  return join_worst(lanes_worst, worst);
}

}  // namespace
}  // namespace CHAINMAIL_LANES_NAMESPACE
}  // namespace chainmail
