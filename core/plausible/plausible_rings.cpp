// The prediction and velocity passes of core/plausible_rings.hpp: scalar, and in AVX2 lanes
// (chosen at run time).
#include "core/plausible/plausible_rings.hpp"

#include <algorithm>
#include <cstddef>

#include "core/plausible/plausible_blocks.hpp"
#include "core/plausible/simd_rings.hpp"

namespace chainmail {

void RingMoves::add(double x, double y, double z) {
  farthest2 = std::max(farthest2, (x * x + y * y) + z * z);  // squaredNorm's order
  const double move[3] = {x, y, z};                          // m
  for (int c = 0; c < 3; ++c) {
    lo[c] = std::min(lo[c], move[c]);
    hi[c] = std::max(hi[c], move[c]);
  }
}

void RingMoves::join(const RingMoves& other) {
  farthest2 = std::max(farthest2, other.farthest2);
  for (int c = 0; c < 3; ++c) {
    lo[c] = std::min(lo[c], other.lo[c]);
    hi[c] = std::max(hi[c], other.hi[c]);
  }
}

namespace {

void predict_scalar(const RingArrays& r, const Vec3& fall, double h, int begin, int end,
                    const double* anchor, RingMoves& moves) {
  for (int i = begin; i < end; ++i) {
    for (int c = 0; c < 3; ++c) r.previous[3 * i + c] = r.position[3 * i + c];
    r.contact_push[i] = 0.0;
    if (r.inverse_mass[i] != 0.0) {  // else pinned
      for (int c = 0; c < 3; ++c) {
        r.velocity[3 * i + c] += fall[c];
        r.position[3 * i + c] += h * r.velocity[3 * i + c];
      }
    }
    if (!anchor) continue;
    moves.add(r.position[3 * i] - anchor[3 * i], r.position[3 * i + 1] - anchor[3 * i + 1],
              r.position[3 * i + 2] - anchor[3 * i + 2]);
  }
}

void velocities_scalar(const RingArrays& r, double h, int begin, int end) {
  for (int i = begin; i < end; ++i) {
    const bool pinned = r.inverse_mass[i] == 0.0;
    for (int c = 0; c < 3; ++c) {
      r.velocity[3 * i + c] = pinned ? 0.0 : (r.position[3 * i + c] - r.previous[3 * i + c]) / h;
    }
  }
}

#if defined(CHAINMAIL_AVX2_SWEEPS)
// rings r .. r + 3 are free, as a mask per coordinate of their 12 (x0 y0 z0 x1 | y1 z1 x2 y2 |
// z2 x3 y3 z3)
struct FreeMask {
  __m256d part[3];
};
__attribute__((target("avx2"), always_inline)) inline FreeMask free_mask(const double* w) {
  const __m256d free = _mm256_cmp_pd(_mm256_loadu_pd(w), _mm256_setzero_pd(), _CMP_NEQ_UQ);
  return {{_mm256_permute4x64_pd(free, 0x40),    // 0 0 0 1
           _mm256_permute4x64_pd(free, 0xA5),    // 1 1 2 2
           _mm256_permute4x64_pd(free, 0xFE)}};  // 2 3 3 3
}

// velocities_first: each ring's velocity from its move over the substep before (the velocity
// pass, velocities_avx2's arithmetic) before it is predicted
template <bool velocities_first>
__attribute__((target("avx2"))) void predict_avx2(const RingArrays& r, const Vec3& fall, double h,
                                                  int begin, int end, const double* anchor,
                                                  RingMoves& moves) {
  // gravity's step in the same 12-coordinate pattern
  const __m256d fall_part[3] = {_mm256_setr_pd(fall.x(), fall.y(), fall.z(), fall.x()),
                                _mm256_setr_pd(fall.y(), fall.z(), fall.x(), fall.y()),
                                _mm256_setr_pd(fall.z(), fall.x(), fall.y(), fall.z())};
  const __m256d step = _mm256_set1_pd(h);
  // the moves: per lane of each part, and the farthest per ring (min(m, lo) and max(m, hi) keep
  // lo and hi on a NaN, as std::min(lo, m) and std::max(hi, m) do)
  __m256d lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = _mm256_set1_pd(RingMoves::kInf);
  for (int k = 0; k < 3; ++k) hi[k] = _mm256_set1_pd(-RingMoves::kInf);
  __m256d farthest2 = _mm256_setzero_pd();
  int i = begin;
  for (; i + 4 <= end; i += 4) {
    const std::ptrdiff_t at = 3 * static_cast<std::ptrdiff_t>(i);
    const FreeMask free = free_mask(r.inverse_mass + i);
    __m256d move[3] = {_mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd()};
    for (int k = 0; k < 3; ++k) {
      const __m256d x = _mm256_loadu_pd(r.position + at + 4 * k);
      __m256d v;
      if constexpr (velocities_first) {
        v = _mm256_and_pd(
            _mm256_div_pd(_mm256_sub_pd(x, _mm256_loadu_pd(r.previous + at + 4 * k)), step),
            free.part[k]);  // pinned: +0
      } else {
        v = _mm256_loadu_pd(r.velocity + at + 4 * k);
      }
      _mm256_storeu_pd(r.previous + at + 4 * k, x);
      const __m256d v_next = _mm256_add_pd(v, fall_part[k]);
      const __m256d x_next =
          _mm256_blendv_pd(x, _mm256_add_pd(x, _mm256_mul_pd(step, v_next)), free.part[k]);
      _mm256_storeu_pd(r.velocity + at + 4 * k, _mm256_blendv_pd(v, v_next, free.part[k]));
      _mm256_storeu_pd(r.position + at + 4 * k, x_next);
      if (anchor) move[k] = _mm256_sub_pd(x_next, _mm256_loadu_pd(anchor + at + 4 * k));
    }
    _mm256_storeu_pd(r.contact_push + i, _mm256_setzero_pd());
    if (!anchor) continue;
    for (int k = 0; k < 3; ++k) {
      lo[k] = _mm256_min_pd(move[k], lo[k]);
      hi[k] = _mm256_max_pd(move[k], hi[k]);
    }
    // x y z of the four rings' moves in lanes, for their lengths
    const Lanes m = to_lanes(move[0], move[1], move[2]);
    const __m256d length2 = _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(m.x, m.x), _mm256_mul_pd(m.y, m.y)), _mm256_mul_pd(m.z, m.z));
    farthest2 = _mm256_max_pd(length2, farthest2);
  }
  if (anchor) {
    // lane l of part k holds coordinate (4 k + l) mod 3
    alignas(32) double lane[4];
    _mm256_store_pd(lane, farthest2);
    for (double v : lane) moves.farthest2 = std::max(moves.farthest2, v);
    for (int k = 0; k < 3; ++k) {
      _mm256_store_pd(lane, lo[k]);
      for (int l = 0; l < 4; ++l)
        moves.lo[(4 * k + l) % 3] = std::min(moves.lo[(4 * k + l) % 3], lane[l]);
      _mm256_store_pd(lane, hi[k]);
      for (int l = 0; l < 4; ++l)
        moves.hi[(4 * k + l) % 3] = std::max(moves.hi[(4 * k + l) % 3], lane[l]);
    }
  }
  // clear the vector registers' upper halves before the scalar code (GCC leaves it out before a
  // tail call, and SSE code after it then runs several times slower)
  _mm256_zeroupper();
  if constexpr (velocities_first) velocities_scalar(r, h, i, end);
  predict_scalar(r, fall, h, i, end, anchor, moves);
}

__attribute__((target("avx2"))) void velocities_avx2(const RingArrays& r, double h, int begin,
                                                     int end) {
  const __m256d step = _mm256_set1_pd(h);
  int i = begin;
  for (; i + 4 <= end; i += 4) {
    const std::ptrdiff_t at = 3 * static_cast<std::ptrdiff_t>(i);
    const FreeMask free = free_mask(r.inverse_mass + i);
    for (int k = 0; k < 3; ++k) {
      const __m256d v = _mm256_div_pd(_mm256_sub_pd(_mm256_loadu_pd(r.position + at + 4 * k),
                                                    _mm256_loadu_pd(r.previous + at + 4 * k)),
                                      step);
      _mm256_storeu_pd(r.velocity + at + 4 * k, _mm256_and_pd(v, free.part[k]));  // pinned: +0
    }
  }
  _mm256_zeroupper();  // as in predict_avx2
  velocities_scalar(r, h, i, end);
}
#endif

// the prediction, after the velocity update where velocities_first: in lanes where the machine
// has them, else ring by ring (each ring's velocity depends on its own position alone, so the
// scalar passes may go one after the other over the range)
template <bool velocities_first>
RingMoves predict(const RingArrays& rings, const Vec3& fall, double h, int begin, int end,
                  bool vector, const double* anchor) {
  RingMoves moves;
#if defined(CHAINMAIL_AVX2_SWEEPS)
  if (vector && vector_sweeps_available()) {
    predict_avx2<velocities_first>(rings, fall, h, begin, end, anchor, moves);
    return moves;
  }
#endif
  (void)vector;
  if constexpr (velocities_first) velocities_scalar(rings, h, begin, end);
  predict_scalar(rings, fall, h, begin, end, anchor, moves);
  return moves;
}

}  // namespace

RingMoves predict_rings(const RingArrays& rings, const Vec3& fall, double h, int begin, int end,
                        bool vector, const double* anchor) {
  return predict<false>(rings, fall, h, begin, end, vector, anchor);
}

RingMoves update_velocities_and_predict(const RingArrays& rings, const Vec3& fall, double h,
                                        int begin, int end, bool vector, const double* anchor) {
  return predict<true>(rings, fall, h, begin, end, vector, anchor);
}

void update_ring_velocities(const RingArrays& rings, double h, int begin, int end, bool vector) {
#if defined(CHAINMAIL_AVX2_SWEEPS)
  if (vector && vector_sweeps_available()) return velocities_avx2(rings, h, begin, end);
#endif
  velocities_scalar(rings, h, begin, end);
}

}  // namespace chainmail
