// Four doubles side by side, for the plausible model's kernels
// (core/plausible/plausible_lanes.hpp): the kernels are written once over a lane type L and
// compiled twice, over ScalarLanes (a double[4], portable) and over Avx2Lanes (an __m256d, where
// the compiler targets x86). Both give per lane the same IEEE bits: each operation is one correctly
// rounded operation on each lane (no fused multiply-add: the kernels' files build with
// -ffp-contract=off), and the few with corner cases (min and max on a NaN, the masks) copy the AVX2
// instruction's rule.
//
// Per lane type L: L::Mask (per lane true or false); L::load, L::splat, L::set, L::zero; store;
// + - * / and unary -; sqrt, abs, lane_min, lane_max; the compares; all, any, blend, keep,
// and_not; unpack_lo and unpack_hi; spread. Rings<L> holds x, y and z of four rings, and
// to_rings, L::load_rings, store_rings and L::gather_rings move them between lanes and a (3, n)
// array.
#pragma once

#include <cmath>
#include <cstddef>

// x86 with GCC or Clang: the AVX2 lanes (core/plausible/lanes_avx2.hpp) are compiled in, and run
// where the machine has AVX2
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__)
#define CHAINMAIL_AVX2_SWEEPS 1
#endif

namespace chainmail {

// x, y and z of four rings, one per lane
template <class L>
struct Rings {
  L x, y, z;
};

// ---- the portable lanes: every operation lane by lane, as the AVX2 instruction defines it

struct ScalarLanes {
  struct Mask {
    bool on[4];
  };
  double v[4];

  static ScalarLanes load(const double* p) { return {{p[0], p[1], p[2], p[3]}}; }
  static ScalarLanes splat(double a) { return {{a, a, a, a}}; }
  static ScalarLanes set(double a, double b, double c, double d) { return {{a, b, c, d}}; }
  static ScalarLanes zero() { return splat(0.0); }
  // four consecutive rings at p, and four rings anywhere in the (3, n) array x
  static Rings<ScalarLanes> load_rings(const double* p);
  static Rings<ScalarLanes> gather_rings(const double* x, const int ring[4]);
};

inline void store(double* p, const ScalarLanes& a) {
  for (int l = 0; l < 4; ++l) p[l] = a.v[l];
}

// one lane-wise operation: out[l] = op(lane l of each argument)
#define CHAINMAIL_SCALAR_LANES(out, expression) \
  out r;                                        \
  for (int l = 0; l < 4; ++l) r.expression;     \
  return r

inline ScalarLanes operator+(ScalarLanes a, ScalarLanes b) {
  CHAINMAIL_SCALAR_LANES(ScalarLanes, v[l] = a.v[l] + b.v[l]);
}
inline ScalarLanes operator-(ScalarLanes a, ScalarLanes b) {
  CHAINMAIL_SCALAR_LANES(ScalarLanes, v[l] = a.v[l] - b.v[l]);
}
inline ScalarLanes operator*(ScalarLanes a, ScalarLanes b) {
  CHAINMAIL_SCALAR_LANES(ScalarLanes, v[l] = a.v[l] * b.v[l]);
}
inline ScalarLanes operator/(ScalarLanes a, ScalarLanes b) {
  CHAINMAIL_SCALAR_LANES(ScalarLanes, v[l] = a.v[l] / b.v[l]);
}
// the sign bit flipped (a NaN's too), as an xor with -0.0
inline ScalarLanes operator-(ScalarLanes a) {
  CHAINMAIL_SCALAR_LANES(ScalarLanes, v[l] = -a.v[l]);
}
// the sign bit cleared
inline ScalarLanes abs(ScalarLanes a) {
  CHAINMAIL_SCALAR_LANES(ScalarLanes, v[l] = std::fabs(a.v[l]));
}
inline ScalarLanes sqrt(ScalarLanes a) {
  CHAINMAIL_SCALAR_LANES(ScalarLanes, v[l] = std::sqrt(a.v[l]));
}
// _mm256_min_pd and _mm256_max_pd: the second argument where either is a NaN
inline ScalarLanes lane_min(ScalarLanes a, ScalarLanes b) {
  CHAINMAIL_SCALAR_LANES(ScalarLanes, v[l] = a.v[l] < b.v[l] ? a.v[l] : b.v[l]);
}
inline ScalarLanes lane_max(ScalarLanes a, ScalarLanes b) {
  CHAINMAIL_SCALAR_LANES(ScalarLanes, v[l] = a.v[l] > b.v[l] ? a.v[l] : b.v[l]);
}
// the compares: ordered (false on a NaN) but != and not_less (true on a NaN)
using ScalarMask = ScalarLanes::Mask;
inline ScalarMask operator<=(ScalarLanes a, ScalarLanes b) {
  CHAINMAIL_SCALAR_LANES(ScalarMask, on[l] = a.v[l] <= b.v[l]);
}
inline ScalarMask operator>=(ScalarLanes a, ScalarLanes b) {
  CHAINMAIL_SCALAR_LANES(ScalarMask, on[l] = a.v[l] >= b.v[l]);
}
inline ScalarMask operator>(ScalarLanes a, ScalarLanes b) {
  CHAINMAIL_SCALAR_LANES(ScalarMask, on[l] = a.v[l] > b.v[l]);
}
inline ScalarMask operator!=(ScalarLanes a, ScalarLanes b) {
  CHAINMAIL_SCALAR_LANES(ScalarMask, on[l] = a.v[l] != b.v[l]);
}
inline ScalarMask not_less(ScalarLanes a, ScalarLanes b) {
  CHAINMAIL_SCALAR_LANES(ScalarMask, on[l] = !(a.v[l] < b.v[l]));
}
inline ScalarMask operator&(ScalarMask a, ScalarMask b) {
  CHAINMAIL_SCALAR_LANES(ScalarMask, on[l] = a.on[l] && b.on[l]);
}
// (not a) and b
inline ScalarMask and_not(ScalarMask a, ScalarMask b) {
  CHAINMAIL_SCALAR_LANES(ScalarMask, on[l] = !a.on[l] && b.on[l]);
}
inline bool all(ScalarMask m) {
  return m.on[0] && m.on[1] && m.on[2] && m.on[3];
}
inline bool any(ScalarMask m) {
  return m.on[0] || m.on[1] || m.on[2] || m.on[3];
}
// yes where m, else no
inline ScalarLanes blend(ScalarMask m, ScalarLanes yes, ScalarLanes no) {
  CHAINMAIL_SCALAR_LANES(ScalarLanes, v[l] = m.on[l] ? yes.v[l] : no.v[l]);
}
// a where m, else +0 (an and with the mask's bits)
inline ScalarLanes keep(ScalarMask m, ScalarLanes a) {
  CHAINMAIL_SCALAR_LANES(ScalarLanes, v[l] = m.on[l] ? a.v[l] : 0.0);
}
// lanes 0 and 2 of a and b interleaved (a0 b0 a2 b2), and lanes 1 and 3 (a1 b1 a3 b3)
inline ScalarLanes unpack_lo(ScalarLanes a, ScalarLanes b) {
  return {{a.v[0], b.v[0], a.v[2], b.v[2]}};
}
inline ScalarLanes unpack_hi(ScalarLanes a, ScalarLanes b) {
  return {{a.v[1], b.v[1], a.v[3], b.v[3]}};
}
#undef CHAINMAIL_SCALAR_LANES

// four rings' lanes repeated over their 12 coordinates as a (3, n) array holds them: lanes
// 0 0 0 1 | 1 1 2 2 | 2 3 3 3 (coordinate k is ring k / 3's)
inline void spread(ScalarLanes a, ScalarLanes out[3]) {
  for (int k = 0; k < 12; ++k) out[k / 4].v[k % 4] = a.v[k / 3];
}
inline void spread(ScalarMask a, ScalarMask out[3]) {
  for (int k = 0; k < 12; ++k) out[k / 4].on[k % 4] = a.on[k / 3];
}

// the 12 coordinates of four consecutive rings (x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3) as lanes
inline Rings<ScalarLanes> to_rings(ScalarLanes v0, ScalarLanes v1, ScalarLanes v2) {
  double c[12];
  store(c, v0), store(c + 4, v1), store(c + 8, v2);
  return {{{c[0], c[3], c[6], c[9]}}, {{c[1], c[4], c[7], c[10]}}, {{c[2], c[5], c[8], c[11]}}};
}
inline Rings<ScalarLanes> ScalarLanes::load_rings(const double* p) {
  return to_rings(load(p), load(p + 4), load(p + 8));
}
inline void store_rings(double* p, const Rings<ScalarLanes>& r) {
  for (int l = 0; l < 4; ++l) p[3 * l] = r.x.v[l], p[3 * l + 1] = r.y.v[l], p[3 * l + 2] = r.z.v[l];
}
inline Rings<ScalarLanes> ScalarLanes::gather_rings(const double* x, const int ring[4]) {
  Rings<ScalarLanes> r;
  for (int l = 0; l < 4; ++l) {
    const double* const p = x + 3 * static_cast<std::ptrdiff_t>(ring[l]);
    r.x.v[l] = p[0], r.y.v[l] = p[1], r.z.v[l] = p[2];
  }
  return r;
}

}  // namespace chainmail
