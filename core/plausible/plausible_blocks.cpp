// The blocks of four pairs (core/plausible_blocks.hpp): their making, and their sweep in AVX2
// lanes where the machine has it (chosen at run time, so a portable build uses it too).
#include "core/plausible/plausible_blocks.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdlib>

#include "core/plausible/plausible_sweep.hpp"
#include "core/plausible/simd_rings.hpp"

namespace chainmail {
namespace {

bool same_bounds(const EdgeConstraint& x, const EdgeConstraint& y) {
  return x.min_length == y.min_length && x.max_length == y.max_length;
}

PairBlock::Kind block_kind(const EdgeConstraint* f) {
  const int a = f[0].a, b = f[0].b;
  bool run = std::abs(b - a) >= 4;  // the two runs of rings do not overlap
  bool adjacent = b == a + 1;
  for (int i = 1; i < 4; ++i) {
    run = run && f[i].a == a + i && f[i].b == b + i;
    adjacent = adjacent && f[i].a == a + 2 * i && f[i].b == a + 2 * i + 1;
  }
  if (run) return PairBlock::Kind::run;
  if (adjacent) return PairBlock::Kind::adjacent;
  return PairBlock::Kind::single;
}

// `next` is one more group of `last`: the same kind and shared bounds, its rings and pairs where
// last's next group's would be
bool continues(const PairBlock& last, const PairBlock& next) {
  if (last.kind == PairBlock::Kind::single || next.kind != last.kind) return false;
  if (!last.shared_bounds || !next.shared_bounds) return false;
  if (next.min_length != last.min_length || next.max_length != last.max_length) return false;
  const int rings = last.kind == PairBlock::Kind::run ? 4 : 8;  // a group's, on each side
  return next.a == last.a + rings * last.groups && next.b == last.b + rings * last.groups &&
         next.pair == last.pair + 4 * last.groups;
}

}  // namespace

bool vector_sweeps_available() {
#if defined(CHAINMAIL_AVX2_SWEEPS)
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

std::vector<PairBlock> make_pair_blocks(const EdgeConstraint* pairs, int begin, int end,
                                        const std::vector<double>& inverse_mass) {
  std::vector<PairBlock> blocks;
  for (int k = begin; k < end;) {
    const EdgeConstraint* f = pairs + k;
    PairBlock block{f->a, f->b, PairBlock::Kind::single, k, 1, true, f->min_length, f->max_length};
    if (k + 4 <= end) {
      const PairBlock::Kind kind = block_kind(f);
      bool fits = kind != PairBlock::Kind::single;
      for (int i = 0; i < 4 && fits; ++i) {
        fits = inverse_mass[f[i].a] != 0.0 && inverse_mass[f[i].b] != 0.0;
        block.shared_bounds = block.shared_bounds && same_bounds(f[i], f[0]);
      }
      if (fits) block.kind = kind;
    }
    k += block.pairs();
    if (!blocks.empty() && continues(blocks.back(), block)) {
      ++blocks.back().groups;
    } else {
      blocks.push_back(block);
    }
  }
  return blocks;
}

std::vector<AttachmentBlock> make_attachment_blocks(const PinAttachment* list, int begin, int end) {
  std::vector<AttachmentBlock> blocks;
  for (int k = begin; k < end;) {
    const PinAttachment* f = list + k;
    AttachmentBlock block{k, 0, false};
    // one ring at most once, sorted by ring: four items three rings apart are consecutive rings
    if (k + 4 <= end && f[3].ring == f[0].ring + 3) {
      block.groups = 1;
      block.pin_run =
          f[1].pin == f[0].pin + 1 && f[2].pin == f[0].pin + 2 && f[3].pin == f[0].pin + 3;
    }
    k += block.items();
    AttachmentBlock* last = blocks.empty() ? nullptr : &blocks.back();
    if (last && last->groups > 0 && block.groups > 0 && block.pin_run == last->pin_run &&
        f->ring == list[last->item].ring + 4 * last->groups &&
        (!block.pin_run || f->pin == list[last->item].pin + 4 * last->groups)) {
      ++last->groups;
    } else {
      blocks.push_back(block);
    }
  }
  return blocks;
}

#if defined(CHAINMAIL_AVX2_SWEEPS)
namespace {

// solve_edge_constraint in four lanes (no weight is zero: blocks hold no pin), from the squared
// lengths on: whether any lane moves, and if so each lane's share of the difference vector for
// either ring (s0, s1: corr0 = s0 d, corr1 = s1 d) where `active`. worst takes the lanes'
// violations (max(v, worst) keeps worst on a NaN, as std::max(worst, v) does)
struct LaneCorrection {
  __m256d active, s0, s1;
};
__attribute__((target("avx2"), always_inline)) inline bool correct_lanes(
    __m256d length2, __m256d w0, __m256d w1, __m256d min_length, __m256d max_length, __m256d& worst,
    LaneCorrection& out) {
  const __m256d sign = _mm256_set1_pd(-0.0), zero = _mm256_setzero_pd();
  const __m256d max2 = _mm256_mul_pd(max_length, max_length);
  const __m256d min2 = _mm256_mul_pd(min_length, min_length);
  const __m256d within = _mm256_and_pd(_mm256_cmp_pd(length2, max2, _CMP_LE_OQ),
                                       _mm256_cmp_pd(length2, min2, _CMP_GE_OQ));
  if (_mm256_movemask_pd(within) == 0xF) return false;  // the usual case
  // the lanes out of bounds (a NaN too, as in the scalar test), not degenerate
  __m256d active =
      _mm256_andnot_pd(within, _mm256_cmp_pd(length2, _mm256_set1_pd(1e-30), _CMP_NLT_UQ));
  const __m256d length = _mm256_sqrt_pd(length2);
  const __m256d target =
      _mm256_blendv_pd(min_length, max_length, _mm256_cmp_pd(length2, max2, _CMP_GT_OQ));
  const __m256d error = _mm256_sub_pd(length, target);
  const __m256d scale = _mm256_div_pd(error, _mm256_mul_pd(length, _mm256_add_pd(w0, w1)));
  const __m256d violation = _mm256_andnot_pd(sign, error);
  active = _mm256_and_pd(active, _mm256_cmp_pd(violation, zero, _CMP_NEQ_UQ));
  if (_mm256_movemask_pd(active) == 0) return false;
  out.active = active;
  out.s0 = _mm256_mul_pd(w0, scale);
  out.s1 = _mm256_xor_pd(_mm256_mul_pd(w1, scale), sign);  // -(w1 scale)
  worst = _mm256_max_pd(_mm256_and_pd(violation, active), worst);
  return true;
}

// the same on rings in lanes
__attribute__((target("avx2"), always_inline)) inline bool solve_lanes(Lanes& p0, Lanes& p1,
                                                                       __m256d w0, __m256d w1,
                                                                       __m256d min_length,
                                                                       __m256d max_length,
                                                                       __m256d& worst) {
  const __m256d dx = _mm256_sub_pd(p1.x, p0.x), dy = _mm256_sub_pd(p1.y, p0.y),
                dz = _mm256_sub_pd(p1.z, p0.z);
  // (dx dx + dy dy) + dz dz: squaredNorm's order
  const __m256d length2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                                        _mm256_mul_pd(dz, dz));
  LaneCorrection c;
  if (!correct_lanes(length2, w0, w1, min_length, max_length, worst, c)) return false;
  p0.x = _mm256_blendv_pd(p0.x, _mm256_add_pd(p0.x, _mm256_mul_pd(c.s0, dx)), c.active);
  p0.y = _mm256_blendv_pd(p0.y, _mm256_add_pd(p0.y, _mm256_mul_pd(c.s0, dy)), c.active);
  p0.z = _mm256_blendv_pd(p0.z, _mm256_add_pd(p0.z, _mm256_mul_pd(c.s0, dz)), c.active);
  p1.x = _mm256_blendv_pd(p1.x, _mm256_add_pd(p1.x, _mm256_mul_pd(c.s1, dx)), c.active);
  p1.y = _mm256_blendv_pd(p1.y, _mm256_add_pd(p1.y, _mm256_mul_pd(c.s1, dy)), c.active);
  p1.z = _mm256_blendv_pd(p1.z, _mm256_add_pd(p1.z, _mm256_mul_pd(c.s1, dz)), c.active);
  return true;
}

// the block's bounds in lanes holding its pairs `first`, `second`, ... (shared, or the pairs')
struct LaneBounds {
  __m256d min_length, max_length;  // m
};
__attribute__((target("avx2"), always_inline)) inline LaneBounds lane_bounds(
    const EdgeConstraint* pairs, const PairBlock& block, int first, int second, int third,
    int fourth) {
  if (block.shared_bounds) {
    return {_mm256_set1_pd(block.min_length), _mm256_set1_pd(block.max_length)};
  }
  const EdgeConstraint* f = pairs + block.pair;
  return {_mm256_setr_pd(f[first].min_length, f[second].min_length, f[third].min_length,
                         f[fourth].min_length),
          _mm256_setr_pd(f[first].max_length, f[second].max_length, f[third].max_length,
                         f[fourth].max_length)};
}

// pairs (a + i, b + i). Both runs of four rings are 12 consecutive coordinates in the same order
// (x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3), so the differences and their squares are taken as the
// array holds them, and only the squares are turned into lanes for the test (the same values as
// in lanes, so the same bits); a block within its bounds, the usual case, ends there. The
// corrections go back the same way: each lane's share repeated over its ring's three coordinates
__attribute__((target("avx2"), always_inline)) inline void spread_lanes(__m256d lanes,
                                                                        __m256d out[3]) {
  out[0] = _mm256_permute4x64_pd(lanes, 0x40);  // 0 0 0 1
  out[1] = _mm256_permute4x64_pd(lanes, 0xA5);  // 1 1 2 2
  out[2] = _mm256_permute4x64_pd(lanes, 0xFE);  // 2 3 3 3
}

// the squared lengths, in lanes, of four differences held in the array's order
__attribute__((target("avx2"), always_inline)) inline __m256d squared_lengths(const __m256d d[3]) {
  const Lanes square =
      to_lanes(_mm256_mul_pd(d[0], d[0]), _mm256_mul_pd(d[1], d[1]), _mm256_mul_pd(d[2], d[2]));
  // (dx dx + dy dy) + dz dz: squaredNorm's order
  return _mm256_add_pd(_mm256_add_pd(square.x, square.y), square.z);
}

// four rings r (in the array's order, at p) moved by each lane's scale of its difference d where
// `active`, stored back
__attribute__((target("avx2"), always_inline)) inline void store_moved(
    double* p, const __m256d r[3], const __m256d d[3], __m256d scale, const __m256d active[3]) {
  __m256d spread[3];
  spread_lanes(scale, spread);
  for (int k = 0; k < 3; ++k) {
    _mm256_storeu_pd(
        p + 4 * k,
        _mm256_blendv_pd(r[k], _mm256_add_pd(r[k], _mm256_mul_pd(spread[k], d[k])), active[k]));
  }
}

__attribute__((target("avx2"), always_inline)) inline void solve_run(double* x, const double* w,
                                                                     int a, int b,
                                                                     const LaneBounds& bounds,
                                                                     __m256d& worst) {
  double* const p0 = x + 3 * static_cast<std::ptrdiff_t>(a);
  double* const p1 = x + 3 * static_cast<std::ptrdiff_t>(b);
  __m256d r0[3], r1[3], d[3];
  for (int k = 0; k < 3; ++k) {
    r0[k] = _mm256_loadu_pd(p0 + 4 * k);
    r1[k] = _mm256_loadu_pd(p1 + 4 * k);
    d[k] = _mm256_sub_pd(r1[k], r0[k]);
  }
  const __m256d length2 = squared_lengths(d);
  LaneCorrection c;
  if (!correct_lanes(length2, _mm256_loadu_pd(w + a), _mm256_loadu_pd(w + b), bounds.min_length,
                     bounds.max_length, worst, c)) {
    return;
  }
  __m256d active[3];
  spread_lanes(c.active, active);
  store_moved(p0, r0, d, c.s0, active);
  store_moved(p1, r1, d, c.s1, active);
}

// pairs (a + 2 i, a + 2 i + 1): rings a .. a + 7, the even ones one side, the odd the other (the
// lanes hold pairs 0, 2, 1, 3: unpacking keeps 128-bit halves apart, and lanes are independent)
__attribute__((target("avx2"), always_inline)) inline void solve_adjacent(double* x,
                                                                          const double* w, int a,
                                                                          const LaneBounds& bounds,
                                                                          __m256d& worst) {
  double* const p = x + 3 * static_cast<std::ptrdiff_t>(a);
  const Lanes low = load_rings(p), high = load_rings(p + 12);
  Lanes even{_mm256_unpacklo_pd(low.x, high.x), _mm256_unpacklo_pd(low.y, high.y),
             _mm256_unpacklo_pd(low.z, high.z)};
  Lanes odd{_mm256_unpackhi_pd(low.x, high.x), _mm256_unpackhi_pd(low.y, high.y),
            _mm256_unpackhi_pd(low.z, high.z)};
  const __m256d w_low = _mm256_loadu_pd(w + a), w_high = _mm256_loadu_pd(w + a + 4);
  if (!solve_lanes(even, odd, _mm256_unpacklo_pd(w_low, w_high), _mm256_unpackhi_pd(w_low, w_high),
                   bounds.min_length, bounds.max_length, worst)) {
    return;
  }
  store_rings(p, {_mm256_unpacklo_pd(even.x, odd.x), _mm256_unpacklo_pd(even.y, odd.y),
                  _mm256_unpacklo_pd(even.z, odd.z)});
  store_rings(p + 12, {_mm256_unpackhi_pd(even.x, odd.x), _mm256_unpackhi_pd(even.y, odd.y),
                       _mm256_unpackhi_pd(even.z, odd.z)});
}

__attribute__((target("avx2"))) double sweep_blocks_avx2(double* x, const double* w,
                                                         const EdgeConstraint* pairs,
                                                         const PairBlock* blocks, int count) {
  __m256d lanes_worst = _mm256_setzero_pd();  // m
  double worst = 0.0;                         // m
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
  alignas(32) double lane[4];
  _mm256_store_pd(lane, lanes_worst);
  for (double v : lane) worst = std::max(worst, v);
  return worst;
}

// four attachments of consecutive rings: solve_attachment_constraint in lanes, the pins' positions
// loaded one by one (a pin's x y, then z)
__attribute__((target("avx2"), always_inline)) inline __m256d load_ring(const double* x, int ring) {
  const double* const p = x + 3 * static_cast<std::ptrdiff_t>(ring);
  return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p)), _mm_load_sd(p + 2), 1);
}

// the attachments' test from the squared lengths on: whether any lane moves, and if so each
// lane's share of the difference vector (corr = scale d) where `active`
__attribute__((target("avx2"), always_inline)) inline bool attachment_scale(
    __m256d length2, __m256d reach, __m256d& worst, __m256d& active, __m256d& scale) {
  const __m256d within = _mm256_cmp_pd(length2, _mm256_mul_pd(reach, reach), _CMP_LE_OQ);
  if (_mm256_movemask_pd(within) == 0xF) return false;  // the usual case
  const __m256d length = _mm256_sqrt_pd(length2);
  const __m256d violation = _mm256_sub_pd(length, reach);
  // moved where the violation is positive (not on a NaN, as in the scalar sweep)
  active = _mm256_andnot_pd(within, _mm256_cmp_pd(violation, _mm256_setzero_pd(), _CMP_GT_OQ));
  if (_mm256_movemask_pd(active) == 0) return false;
  scale = _mm256_div_pd(_mm256_sub_pd(reach, length), length);
  worst = _mm256_max_pd(_mm256_and_pd(violation, active), worst);
  return true;
}

// a group of four consecutive rings p hanging from four consecutive pins q: rings and pins hold
// their coordinates in the same order, so the differences and their squares are taken as the
// array holds them and only the squares turned into lanes for the test (the same values as in
// lanes); the corrections go back the same way (each lane's scale over its ring's coordinates)
__attribute__((target("avx2"), always_inline)) inline void solve_attachment_pin_run(
    double* p, const double* q, __m256d reach, __m256d& worst) {
  __m256d r[3], d[3];
  for (int k = 0; k < 3; ++k) {
    r[k] = _mm256_loadu_pd(p + 4 * k);
    d[k] = _mm256_sub_pd(r[k], _mm256_loadu_pd(q + 4 * k));
  }
  __m256d active, scale;
  if (!attachment_scale(squared_lengths(d), reach, worst, active, scale)) return;
  __m256d spread_active[3];
  spread_lanes(active, spread_active);
  store_moved(p, r, d, scale, spread_active);
}

// a group of four consecutive rings p and the attachments f, their pins anywhere: the pins'
// positions loaded one by one (x y, then z) and transposed into lanes
__attribute__((target("avx2"), always_inline)) inline void solve_attachment_group(
    double* x, double* p, const PinAttachment* f, __m256d reach, __m256d& worst) {
  const Lanes rings = load_rings(p);
  const __m256d pin0 = load_ring(x, f[0].pin), pin1 = load_ring(x, f[1].pin);
  const __m256d pin2 = load_ring(x, f[2].pin), pin3 = load_ring(x, f[3].pin);
  const __m256d xz01 = _mm256_unpacklo_pd(pin0, pin1), y01 = _mm256_unpackhi_pd(pin0, pin1);
  const __m256d xz23 = _mm256_unpacklo_pd(pin2, pin3), y23 = _mm256_unpackhi_pd(pin2, pin3);
  const __m256d dx = _mm256_sub_pd(rings.x, _mm256_permute2f128_pd(xz01, xz23, 0x20));
  const __m256d dy = _mm256_sub_pd(rings.y, _mm256_permute2f128_pd(y01, y23, 0x20));
  const __m256d dz = _mm256_sub_pd(rings.z, _mm256_permute2f128_pd(xz01, xz23, 0x31));
  const __m256d length2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                                        _mm256_mul_pd(dz, dz));
  __m256d active, scale;
  if (!attachment_scale(length2, reach, worst, active, scale)) return;
  store_rings(
      p, {_mm256_blendv_pd(rings.x, _mm256_add_pd(rings.x, _mm256_mul_pd(scale, dx)), active),
          _mm256_blendv_pd(rings.y, _mm256_add_pd(rings.y, _mm256_mul_pd(scale, dy)), active),
          _mm256_blendv_pd(rings.z, _mm256_add_pd(rings.z, _mm256_mul_pd(scale, dz)), active)});
}

__attribute__((target("avx2"))) double sweep_attachment_blocks_avx2(double* x,
                                                                    const PinAttachment* list,
                                                                    const double* reach,
                                                                    const AttachmentBlock* blocks,
                                                                    int count) {
  __m256d lanes_worst = _mm256_setzero_pd();  // m
  double worst = 0.0;                         // m
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
        solve_attachment_pin_run(p + 12 * g, q + 12 * g, _mm256_loadu_pd(r + 4 * g), lanes_worst);
      }
    } else {
      for (int g = 0; g < block.groups; ++g) {
        solve_attachment_group(x, p + 12 * g, f + 4 * g, _mm256_loadu_pd(r + 4 * g), lanes_worst);
      }
    }
  }
  alignas(32) double lane[4];
  _mm256_store_pd(lane, lanes_worst);
  for (double v : lane) worst = std::max(worst, v);
  return worst;
}

}  // namespace
#endif

double sweep_pair_blocks(double* x, const double* w, const EdgeConstraint* pairs,
                         const PairBlock* blocks, int count) {
#if defined(CHAINMAIL_AVX2_SWEEPS)
  if (vector_sweeps_available()) return sweep_blocks_avx2(x, w, pairs, blocks, count);
#endif
  // without AVX2: each block's pairs one by one (they are consecutive in the stage's list)
  double worst = 0.0;  // m
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < blocks[k].pairs(); ++i) {
      worst = std::max(worst, sweep_pair(x, w, pairs[blocks[k].pair + i]));
    }
  }
  return worst;
}

double sweep_attachment_blocks(double* x, const PinAttachment* list, const double* reach,
                               const AttachmentBlock* blocks, int count) {
#if defined(CHAINMAIL_AVX2_SWEEPS)
  if (vector_sweeps_available()) {
    return sweep_attachment_blocks_avx2(x, list, reach, blocks, count);
  }
#endif
  (void)reach;
  // without AVX2: each block's attachments one by one (consecutive in the list)
  double worst = 0.0;  // m
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < blocks[k].items(); ++i) {
      worst = std::max(worst, sweep_attachment(x, list[blocks[k].item + i]));
    }
  }
  return worst;
}

}  // namespace chainmail
